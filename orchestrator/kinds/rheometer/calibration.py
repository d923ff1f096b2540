"""`orchestrator calibrate maxwell`: fit multi-mode Maxwell modes (lambda_i s, eta_i Pa s; G_p Pa) to measured
storage and loss moduli G'(omega), G''(omega) (Pa), as Nutto et al. did for the MF20 medium (Table III).

Input CSV: '#' comment lines, then a header naming the frequency column -- omega_rad_s (angular frequency, rad/s)
or f_Hz (frequency, Hz; omega = 2 pi f) -- and G_storage_Pa and/or G_loss_Pa; then one row of numbers per
frequency. Output: a table, an optional case-file fragment (TOML, [[material.modes]]) and an optional figure.
"""

from __future__ import annotations

import csv
import math
from dataclasses import asdict
from pathlib import Path

import numpy as np

from orchestrator.errors import OrchestratorError
from orchestrator.outputs import check_target, write_text
from orchestrator.plots import save_pyplot_figure
from orchestrator.reference.maxwell import MaxwellFit, Mode, fit_maxwell, loss_modulus, storage_modulus

FREQUENCY_COLUMNS = {"omega_rad_s": 1.0, "f_Hz": 2.0 * math.pi}  # factor to rad/s
MODULUS_COLUMNS = ("G_storage_Pa", "G_loss_Pa")
FORMAT = "a header naming omega_rad_s or f_Hz and G_storage_Pa and/or G_loss_Pa, then rows of numbers"


#: Bounds of a moduli CSV, checked before the fit: its size in bytes, its data rows (the fit's time grows with
#: them), each value's magnitude (frequencies rad/s or Hz, moduli Pa: the fitted relaxation times must stay
#: within the limits of case files), and the number of modes.
MAX_CSV_BYTES = 4 * 2**20
MAX_ROWS = 2000
VALUE_RANGE = (1e-20, 1e20)
MAX_MODES = 20


def read_moduli(path):
    """(omega rad/s, G' Pa or None, G'' Pa or None) from a moduli CSV; OrchestratorError (exit 2) naming the
    file, line and column of the first bad value, or the bound (MAX_CSV_BYTES, MAX_ROWS, VALUE_RANGE) passed."""
    path = Path(path)
    if not path.is_file():
        raise OrchestratorError(f"no CSV file at {path}" if not path.exists() else f"{path} is not a regular file"
                                + f"; give a CSV with {FORMAT}")
    if path.stat().st_size > MAX_CSV_BYTES:
        raise OrchestratorError(f"{path}: {path.stat().st_size} bytes; allowed: at most {MAX_CSV_BYTES} bytes "
                                f"(and {MAX_ROWS} data rows)")
    try:
        with open(path, newline="") as fh:
            lines = [(k + 1, row) for k, row in enumerate(csv.reader(fh))]
    except (UnicodeDecodeError, csv.Error):
        raise OrchestratorError(f"{path}: not a text CSV; expected {FORMAT}") from None
    lines = [(k, [c.strip() for c in row]) for k, row in lines if row and not row[0].lstrip().startswith("#")
             and any(c.strip() for c in row)]
    if not lines:
        raise OrchestratorError(f"{path}: no header line; expected {FORMAT}")
    header_line, header = lines[0]
    frequency = [c for c in header if c in FREQUENCY_COLUMNS]
    if len(frequency) != 1:
        raise OrchestratorError(f"{path}: line {header_line}: the header {','.join(header)!r} must name exactly one "
                                "frequency column: omega_rad_s (rad/s) or f_Hz (Hz)")
    moduli = [c for c in MODULUS_COLUMNS if c in header]
    if not moduli:
        raise OrchestratorError(f"{path}: line {header_line}: the header {','.join(header)!r} names no modulus "
                                "column; expected G_storage_Pa and/or G_loss_Pa")
    wanted = frequency + moduli
    if len(lines) - 1 > MAX_ROWS:
        raise OrchestratorError(f"{path}: {len(lines) - 1} data rows; allowed: at most {MAX_ROWS} (average or "
                                "thin the measurements)")
    columns = {name: [] for name in wanted}
    for line, row in lines[1:]:
        if len(row) != len(header):
            raise OrchestratorError(f"{path}: line {line}: {len(row)} values for the {len(header)} columns of the "
                                    "header")
        for name in wanted:
            text = row[header.index(name)]
            try:
                value = float(text)
            except ValueError:
                raise OrchestratorError(f"{path}: line {line}, column {name}: {text!r} is not a number") from None
            if not (math.isfinite(value) and VALUE_RANGE[0] <= value <= VALUE_RANGE[1]):
                raise OrchestratorError(f"{path}: line {line}, column {name}: {text}; allowed: a number from "
                                        f"{VALUE_RANGE[0]:g} to {VALUE_RANGE[1]:g}")
            columns[name].append(value)
    if len(columns[frequency[0]]) < 3:
        raise OrchestratorError(f"{path}: {len(columns[frequency[0]])} data rows; the fit needs at least 3")
    omega = np.array(columns[frequency[0]]) * FREQUENCY_COLUMNS[frequency[0]]
    if len(np.unique(omega)) != len(omega):
        raise OrchestratorError(f"{path}: column {frequency[0]}: a frequency appears twice")
    order = np.argsort(omega)
    get = (lambda name: np.array(columns[name])[order] if name in columns else None)
    return omega[order], get("G_storage_Pa"), get("G_loss_Pa")


def calibrate(path, n_modes: int, fit: str = "both", plateau: bool = False, cross: bool = False):
    """Read the CSV at path and fit n_modes modes to G' ('storage'), G'' ('loss') or both; returns
    (omega rad/s, G' Pa, G'' Pa, MaxwellFit), the moduli not fitted set to None."""
    if not 1 <= n_modes <= MAX_MODES:
        raise OrchestratorError(f"--modes {n_modes}: allowed: 1 to {MAX_MODES}")
    omega, storage, loss = read_moduli(path)
    for name, data, column in (("storage", storage, "G_storage_Pa"), ("loss", loss, "G_loss_Pa")):
        if fit in (name, "both") and data is None:
            raise OrchestratorError(f"{path}: --fit {fit} needs the column {column}")
    storage = storage if fit in ("storage", "both") else None
    loss = loss if fit in ("loss", "both") else None
    try:
        result = fit_maxwell(omega, storage, loss, n_modes, plateau, cross)
    except OrchestratorError as exc:
        raise OrchestratorError(f"{path}: {exc}") from None
    return omega, storage, loss, result


def format_fit(result: MaxwellFit) -> str:
    """The table: mode, lambda_i (s), eta_i (Pa s), G_i (Pa) with relative standard errors, then G_p, the Cross law
    and the RMS relative residuals."""
    se = result.standard_errors

    def pm(name):
        return "n/a" if se.get(name) is None else f"{100 * se[name]:.3g} %"

    rows = [("mode", "lambda_i [s]", "+-", "eta_i [Pa s]", "+-", "G_i [Pa]")]
    for i, m in enumerate(result.modes, 1):
        rows.append((str(i), f"{m.relaxation_time:.6g}", pm(f"lambda_{i}"), f"{m.viscosity:.6g}", pm(f"eta_{i}"),
                     f"{m.modulus:.6g}"))
    widths = [max(len(r[k]) for r in rows) for k in range(len(rows[0]))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows]
    if "G_p" in se:
        lines.append(f"G_p [Pa]        {result.plateau:.6g}  (+- {pm('G_p')})")
    if result.cross is not None:
        c = result.cross
        lines.append(f"Cross law for G'': eta_0 {c.zero_shear_viscosity:.6g} Pa s, eta_inf "
                     f"{c.infinite_shear_viscosity:.6g} Pa s, K {c.time_constant:.6g} s, m {c.exponent:.4g} "
                     "(shear rate = omega)")
    for name, value in result.residual_rms.items():
        lines.append(f"RMS relative residual of G{chr(39) if name == 'storage' else chr(39) * 2}: {value:.4g}")
    lines.append(f"fitted {result.fitted}: {result.n_points} points, {result.n_parameters} parameters; "
                 "+- are relative standard errors from the Jacobian (n/a: not identified by the data)")
    return "\n".join(lines)


def fit_as_dict(result: MaxwellFit) -> dict:
    """The fit as plain JSON-able values (s, Pa s, Pa)."""
    out = asdict(result)
    out["modes"] = [{"relaxation_time": float(m.relaxation_time), "viscosity": float(m.viscosity),
                     "modulus": float(m.modulus)} for m in result.modes]
    if result.cross is not None:
        out["cross"] = {k: float(v) for k, v in asdict(result.cross).items()}
    return out


def write_fragment(result: MaxwellFit, out, source: str, force: bool = False) -> Path:
    """Write the modes as a case-file fragment (TOML) at out through the output policy (never over the data file
    `source`, a FIFO or a folder); refuse an existing file unless force."""
    out = check_target(out, "--out", inputs=(source,))
    if out.exists() and not force:
        raise OrchestratorError(f"{out} exists; give --force to overwrite it")
    lines = [f"# Multi-mode Maxwell fit of {source} by `orchestrator calibrate maxwell` ({result.fitted} moduli).",
             "# relaxation_time in s, viscosity in Pa s, storage_plateau (G_p) in Pa.", "", "[material]",
             f"storage_plateau = {float(result.plateau)!r}"]
    for m in result.modes:
        lines += ["", "[[material.modes]]", f"relaxation_time = {float(m.relaxation_time)!r}",
                  f"viscosity = {float(m.viscosity)!r}"]
    if result.cross is not None:  # eta_0, eta_inf Pa s; K s; m -
        lines += ["", "[material.cross_loss]"] + [f"{k} = {float(v)!r}" for k, v in asdict(result.cross).items()]
    return write_text(out, "\n".join(lines) + "\n", "--out", inputs=(source,))


def plot_fit(omega, storage, loss, result: MaxwellFit, png, title: str = "") -> Path:
    """G'(omega) and G''(omega) of the data (markers) and the fit (lines), log-log, as a PNG at png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w = np.logspace(math.log10(omega.min()) - 0.3, math.log10(omega.max()) + 0.3, 300)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    if storage is not None:
        ax.loglog(omega, storage, "o", color="C0", mfc="none", label="G' data")
    if loss is not None:
        ax.loglog(omega, loss, "s", color="C3", mfc="none", label="G'' data")
    ax.loglog(w, storage_modulus(w, result.modes, result.plateau), "-", color="C0", label="G' fit")
    fit_loss = result.cross.loss_modulus(w) if result.cross is not None else loss_modulus(w, result.modes)
    ax.loglog(w, fit_loss, "-", color="C3", label="G'' fit" + (" (Cross)" if result.cross else ""))
    ax.set_xlabel("angular frequency omega [rad/s]")
    ax.set_ylabel("modulus [Pa]")
    ax.set_title(title or f"{len(result.modes)}-mode Maxwell fit", fontsize=10)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(loc="lower right", fontsize=9)
    return save_pyplot_figure(fig, png)


def synthetic_moduli(modes, omega, noise: float = 0.03, seed: int = 2, plateau: float = 0.0):
    """(G' Pa, G'' Pa) of Maxwell modes (lambda_i s, eta_i Pa s; plateau G_p Pa) at angular frequencies omega
    (rad/s), each value multiplied by 1 + noise * N(0, 1) drawn from numpy's default_rng(seed), G' first."""
    omega = np.asarray(omega, dtype=float)
    rng = np.random.default_rng(seed)
    storage = storage_modulus(omega, modes, plateau) * (1.0 + noise * rng.standard_normal(len(omega)))
    loss = loss_modulus(omega, modes) * (1.0 + noise * rng.standard_normal(len(omega)))
    return storage, loss


def write_moduli_csv(path, omega, storage, loss, comment: str = "") -> Path:
    """A moduli CSV (omega_rad_s, G_storage_Pa, G_loss_Pa; 6 significant digits) with '#' comment lines."""
    lines = [f"# {line}" for line in comment.splitlines()] + ["omega_rad_s,G_storage_Pa,G_loss_Pa"]
    lines += [f"{w:.6g},{s:.6g},{g:.6g}" for w, s, g in zip(omega, storage, loss)]
    return write_text(path, "\n".join(lines) + "\n", "moduli CSV")


__all__ = ["Mode", "calibrate", "format_fit", "plot_fit", "read_moduli", "synthetic_moduli", "write_fragment"]
