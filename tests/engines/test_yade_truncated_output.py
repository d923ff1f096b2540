"""A Yade run stopped by a timeout or a signal may leave the .npz it was writing truncated: the reader skips that
newest file (the data before it is kept) and still refuses any other unreadable file."""

import os

import numpy as np
import pytest

from orchestrator.errors import ReadError
from orchestrator.kinds.drag_finishing.yade import _load_npz_written


def _truncated(path, source):
    path.write_bytes(source.read_bytes()[:40])  # a zip cut short: no central directory


def test_the_newest_truncated_npz_is_skipped_an_older_one_is_an_error(tmp_path):
    good = tmp_path / "frame_0.npz"
    np.savez(good, time=np.float64(0.5), x=np.arange(3.0))
    newest = tmp_path / "frame_1.npz"
    _truncated(newest, good)
    os.utime(good, ns=(1_000_000_000, 1_000_000_000))
    os.utime(newest, ns=(2_000_000_000, 2_000_000_000))
    assert _load_npz_written(newest) is None
    assert np.array_equal(_load_npz_written(good)["x"], np.arange(3.0))
    older = tmp_path / "network_0.npz"
    _truncated(older, good)
    os.utime(older, ns=(1_500_000_000, 1_500_000_000))
    with pytest.raises(ReadError, match="network_0.npz"):
        _load_npz_written(older)
