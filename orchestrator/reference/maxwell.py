"""Linear viscoelastic moduli of a multi-mode Maxwell fluid and their least-squares calibration.

Nutto et al., eqs. 18-19, with G_i = eta_i / lambda_i (Pa):

    G'(omega)  = G_p + sum_i G_i (omega lambda_i)^2 / (1 + (omega lambda_i)^2)      storage modulus, Pa
    G''(omega) =       sum_i G_i  omega lambda_i    / (1 + (omega lambda_i)^2)      loss modulus, Pa

omega is the angular frequency in rad/s (gamma(t) = gamma_A sin(omega t), eq. 17); a frequency f in Hz is
omega = 2 pi f. lambda_i is a relaxation time (s), eta_i a mode's viscosity (Pa s), G_p a constant storage
plateau (Pa) that the PTT constitutive law itself does not produce (it is an elastic-solid term).

The Cross option (the paper's 'Cross viscosity law' for G''): G'' = omega eta'(omega), and for Maxwell modes the
dynamic viscosity is eta'(omega) = sum_i eta_i / (1 + (omega lambda_i)^2) -- each mode is itself a Cross law with
eta_inf = 0, K = lambda_i, m = 2. With the option, G'' is omega eta_C(gamma_dot) with
eta_C = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m) and gamma_dot = omega (the Cox-Merz rule); the
modes then follow from G' alone and G'' no longer follows from them (the two moduli stop being one Maxwell
spectrum). Taking gamma_dot = omega gamma_A instead changes only K, to K / gamma_A.

The fit (Baumgaertel & Winter 1989 style): relaxation times start log-spaced over the data's 1/omega range, the
moduli G_i (and G_p) start from a non-negative linear least-squares fit at those times, then
scipy.optimize.least_squares adjusts the logarithms of all parameters to minimise the relative residuals
(model - data) / data. Standard errors come from the Jacobian at the optimum, s^2 (J^T J)^-1 with
s^2 = sum r^2 / (m - n) (each fitted modulus with its own s^2); in log-parameters they are relative standard
errors of the parameters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from orchestrator.errors import OrchestratorError


@dataclass(frozen=True)
class Mode:
    """One Maxwell mode: relaxation_time lambda_i (s) and viscosity eta_i (Pa s)."""

    relaxation_time: float
    viscosity: float

    @property
    def modulus(self) -> float:
        """G_i = eta_i / lambda_i, Pa."""
        return self.viscosity / self.relaxation_time


#: Nutto et al., Table III: the MF20 abrasive medium's five modes (lambda_i s, eta_i Pa s).
TABLE_III = tuple(Mode(lam, eta) for lam, eta in ((0.002, 15.0), (0.02, 40.0), (0.5, 738.0), (2.0, 756.0),
                                                  (5.0, 17315.0)))


@dataclass(frozen=True)
class CrossLaw:
    """eta(gamma_dot) = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m): zero_shear_viscosity eta_0 (Pa s),
    infinite_shear_viscosity eta_inf (Pa s), time_constant K (s), exponent m (-)."""

    zero_shear_viscosity: float
    infinite_shear_viscosity: float
    time_constant: float
    exponent: float

    def viscosity(self, shear_rate) -> np.ndarray:
        """eta at shear rates gamma_dot (1/s), Pa s."""
        rate = np.asarray(shear_rate, dtype=float)
        eta0, etainf = self.zero_shear_viscosity, self.infinite_shear_viscosity
        return etainf + (eta0 - etainf) / (1.0 + (self.time_constant * rate) ** self.exponent)

    def loss_modulus(self, omega) -> np.ndarray:
        """G'' = omega eta(gamma_dot = omega) (Cox-Merz), Pa, at angular frequencies omega (rad/s)."""
        omega = np.asarray(omega, dtype=float)
        return omega * self.viscosity(omega)


def storage_modulus(omega, modes, plateau: float = 0.0) -> np.ndarray:
    """G'(omega) of eq. 18, Pa: omega angular frequencies (rad/s), modes (lambda_i s, eta_i Pa s), plateau G_p Pa."""
    x = np.multiply.outer(np.asarray(omega, dtype=float), [m.relaxation_time for m in modes])
    moduli = np.array([m.modulus for m in modes])
    return plateau + (moduli * x**2 / (1.0 + x**2)).sum(axis=-1)


def loss_modulus(omega, modes) -> np.ndarray:
    """G''(omega) of eq. 19, Pa: omega angular frequencies (rad/s), modes (lambda_i s, eta_i Pa s)."""
    x = np.multiply.outer(np.asarray(omega, dtype=float), [m.relaxation_time for m in modes])
    moduli = np.array([m.modulus for m in modes])
    return (moduli * x / (1.0 + x**2)).sum(axis=-1)


def initial_relaxation_times(omega, n_modes: int, inset: float = 0.0) -> np.ndarray:
    """n_modes relaxation times (s) log-spaced over [1/omega_max, 1/omega_min] of the data (omega in rad/s),
    that range narrowed by inset decades at each end."""
    omega = np.asarray(omega, dtype=float)
    low, high = math.log10(1.0 / omega.max()) + inset, math.log10(1.0 / omega.min()) - inset
    if n_modes == 1 or high <= low:
        return np.full(n_modes, 10 ** (0.5 * (low + high)))
    return np.logspace(low, high, n_modes)


#: Starts of the fit: the relaxation times log-spaced over the data's 1/omega range narrowed by these decades
#: at each end; the fit keeps the lowest cost (noisy data have local minima that merge neighbouring modes).
INSETS = (0.0, 0.5, 1.0)


@dataclass
class MaxwellFit:
    """The fitted modes (sorted by lambda_i; s, Pa s), plateau G_p (Pa; 0 when not fitted), the Cross law for G''
    (or None), which moduli were fitted ('storage', 'loss' or 'both'), the RMS relative residual of each fitted
    modulus (-), relative standard errors (-) of each parameter by name (None where the Jacobian does not
    identify it), the number of data points and parameters, and the optimiser's success and message."""

    modes: tuple[Mode, ...]
    plateau: float
    cross: CrossLaw | None
    fitted: str
    residual_rms: dict[str, float]
    standard_errors: dict[str, float | None] = field(default_factory=dict)
    n_points: int = 0
    n_parameters: int = 0
    success: bool = True
    message: str = ""


def _names(n_modes: int, plateau: bool, cross: bool) -> list[str]:
    names = [f"{kind}_{i + 1}" for i in range(n_modes) for kind in ("lambda", "eta")]
    names += ["G_p"] * plateau
    names += ["cross_eta_0", "cross_eta_inf", "cross_K", "cross_m"] * cross
    return names


def _unpack(p, n_modes: int, plateau: bool, cross: bool):
    p = np.exp(p)
    modes = [Mode(p[2 * i], p[2 * i + 1]) for i in range(n_modes)]
    k = 2 * n_modes
    g_p = p[k] if plateau else 0.0
    law = CrossLaw(*p[k + plateau:k + plateau + 4]) if cross else None
    return modes, g_p, law


def _start(omega, storage, loss, n_modes, plateau, cross, inset):
    """Log-parameters to start from: log-spaced lambda_i, then G_i (and G_p) by non-negative least squares."""
    from scipy.optimize import nnls

    lam = initial_relaxation_times(omega, n_modes, inset)
    x = np.multiply.outer(omega, lam)
    rows, rhs = [], []
    if storage is not None:
        rows.append(np.column_stack([x**2 / (1 + x**2) / storage[:, None]] + [1.0 / storage] * plateau))
        rhs.append(np.ones_like(storage))
    if loss is not None and not cross:
        rows.append(np.column_stack([x / (1 + x**2) / loss[:, None]] + [np.zeros_like(loss)] * plateau))
        rhs.append(np.ones_like(loss))
    coef, _ = nnls(np.vstack(rows), np.concatenate(rhs))
    scale = np.concatenate([d for d in (storage, loss) if d is not None]).mean()
    coef = np.maximum(coef, 1e-3 * scale)
    p = []
    for i in range(n_modes):
        p += [math.log(lam[i]), math.log(coef[i] * lam[i])]
    if plateau:
        p.append(math.log(coef[n_modes]))
    if cross:
        eta = loss / omega
        eta0, etainf = eta.max(), max(eta.min() * 0.5, eta.max() * 1e-6)
        half = omega[np.argmin(np.abs(eta - 0.5 * (eta0 + etainf)))]
        p += [math.log(eta0), math.log(etainf), math.log(1.0 / half), 0.0]
    return np.array(p)


def fit_maxwell(omega, storage=None, loss=None, n_modes: int = 1, plateau: bool = False,
                cross: bool = False) -> MaxwellFit:
    """Fit n_modes Maxwell modes (and G_p with plateau; a Cross law for G'' with cross) to the storage G' and/or
    loss G'' moduli (Pa; None for one not measured) at angular frequencies omega (rad/s), minimising relative
    residuals over the logarithms of lambda_i (s), eta_i (Pa s), G_p (Pa) and the Cross parameters."""
    from scipy.optimize import least_squares

    omega = np.asarray(omega, dtype=float)
    storage = None if storage is None else np.asarray(storage, dtype=float)
    loss = None if loss is None else np.asarray(loss, dtype=float)
    fitted = "both" if storage is not None and loss is not None else "storage" if storage is not None else "loss"
    if storage is None and loss is None:
        raise OrchestratorError("the fit needs G' (storage) or G'' (loss) data, Pa")
    if plateau and storage is None:
        raise OrchestratorError("the plateau G_p enters G' only; fit the storage modulus to fit G_p")
    if cross and fitted != "both":
        raise OrchestratorError("the Cross law replaces the modes' G''; the modes then come from G', so the Cross "
                                "option needs both G' and G''")
    if n_modes < 1:
        raise OrchestratorError(f"{n_modes} modes: allowed: 1 or more")
    for name, data in (("omega", omega), ("G'", storage), ("G''", loss)):
        if data is not None and not (np.all(np.isfinite(data)) and np.all(data > 0)):
            raise OrchestratorError(f"{name}: every value must be a finite number above 0")
    names = _names(n_modes, plateau, cross)
    n_points = sum(len(d) for d in (storage, loss) if d is not None)
    if n_points <= len(names):
        raise OrchestratorError(f"{n_points} data points for {len(names)} parameters ({n_modes} modes"
                                f"{' and G_p' if plateau else ''}{' and a Cross law' if cross else ''}); the fit "
                                "needs more points than parameters: fewer modes or more frequencies")

    def residuals(p):
        modes, g_p, law = _unpack(p, n_modes, plateau, cross)
        parts = []
        if storage is not None:
            parts.append(storage_modulus(omega, modes, g_p) / storage - 1.0)
        if loss is not None:
            model = law.loss_modulus(omega) if cross else loss_modulus(omega, modes)
            parts.append(model / loss - 1.0)
        return np.concatenate(parts)

    p0 = _start(omega, storage, loss, n_modes, plateau, cross, 0.0)
    span = math.log(1e4)
    lower = np.full(len(p0), -np.inf)
    upper = np.full(len(p0), np.inf)
    for i in range(n_modes):  # relaxation times within four decades beyond the data's 1/omega range
        lower[2 * i], upper[2 * i] = math.log(1 / omega.max()) - span, math.log(1 / omega.min()) + span
    if plateau:  # G_p from a millionth of the smallest G' to the largest G'
        lower[2 * n_modes], upper[2 * n_modes] = math.log(1e-6 * storage.min()), math.log(storage.max())
    if cross:
        lower[-1], upper[-1] = math.log(0.05), math.log(20.0)
    result = None
    for inset in INSETS:
        p0 = np.clip(_start(omega, storage, loss, n_modes, plateau, cross, inset), lower + 1e-9, upper - 1e-9)
        trial = least_squares(residuals, p0, bounds=(lower, upper), method="trf", x_scale=1.0,
                              xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=2000 * len(p0))
        if result is None or trial.cost < result.cost:
            result = trial
    p = result.x
    order = np.argsort(p[0:2 * n_modes:2])
    mode_index = np.concatenate([[2 * i, 2 * i + 1] for i in order]).astype(int)
    permutation = np.concatenate([mode_index, np.arange(2 * n_modes, len(p))]).astype(int)
    modes, g_p, law = _unpack(p[permutation], n_modes, plateau, cross)
    errors = _standard_errors(result.jac[:, permutation], result.fun, names, p[permutation], lower[permutation],
                              upper[permutation], [len(d) for d in (storage, loss) if d is not None])
    r, k, rms = result.fun, 0, {}
    for name, data in (("storage", storage), ("loss", loss)):
        if data is not None:
            rms[name] = float(np.sqrt(np.mean(r[k:k + len(data)] ** 2)))
            k += len(data)
    return MaxwellFit(tuple(modes), float(g_p), law, fitted, rms, errors, n_points, len(names),
                      bool(result.success), str(result.message))


def _standard_errors(jac, fun, names, p, lower, upper, blocks) -> dict[str, float | None]:
    """Standard errors of the log-parameters (relative errors of the parameters): the covariance
    (J^T J)^-1 J^T S J (J^T J)^-1, S the variance of each fitted modulus' residuals (its own s^2 = sum r^2 /
    (m_k - n m_k / m), so that a poorly fitted Cross G'' does not inflate the modes' errors; one modulus: s^2
    (J^T J)^-1). None for all when J^T J is numerically singular, and for a parameter at its bound."""
    m, n = jac.shape
    variance = np.empty(m)
    k = 0
    for size in blocks:
        variance[k:k + size] = float(fun[k:k + size] @ fun[k:k + size]) / (size - n * size / m)
        k += size
    u, sing, vt = np.linalg.svd(jac, full_matrices=False)
    if sing.min() <= sing.max() * 1e-10:
        return {name: None for name in names}
    inverse = (vt.T / sing**2) @ vt
    cov = inverse @ (jac.T * variance) @ jac @ inverse
    at_bound = (p - lower < 1e-3) | (upper - p < 1e-3)
    return {name: (None if at_bound[i] else float(math.sqrt(cov[i, i]))) for i, name in enumerate(names)}
