"""A Dask `distributed` cluster as a concurrent.futures.Executor for studies."""

from __future__ import annotations

import contextlib
import os

from orchestrator.errors import OrchestratorError


@contextlib.contextmanager
def dask_executor(address: str, workers: int | None = None):
    """Yield an Executor on the Dask scheduler at address, or on a LocalCluster when address == 'local'.

    A local cluster gets `workers` single-threaded worker processes (default:
    the number of cores), so runs never oversubscribe the machine.
    """
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise OrchestratorError(
            "--dask needs Dask's distributed package: pip install 'orchestrator[dask]'"
        ) from None
    cluster = None
    try:
        if address == "local":
            cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            client = Client(cluster)
        else:
            client = Client(address, timeout=30)
    except OSError as exc:
        raise OrchestratorError(f"cannot reach the Dask scheduler at {address}: {exc}") from None
    try:
        yield client.get_executor(pure=False)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
