"""The rheometer's scene: the sample as an SPH flow case (kind sph_flow: one PTT material, every axis periodic,
Lees-Edwards shear along x with the gradient along y) with the density, sound speed and step of physics.py, and
the particles starting on the homogeneous shear u_x = gamma_dot(0) (y - L/2). SI units."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from orchestrator.kinds.rheometer.case import RheometerCase
from orchestrator.kinds.rheometer.physics import sample_numerics
from orchestrator.kinds.sph_flow.case import SphFlowCase
from orchestrator.kinds.sph_flow.scene import SphScene, build_sph_flow

MATERIAL = "sample"


def flow_case(case: RheometerCase) -> SphFlowCase:
    """The sph_flow case of the sheared sample (density, c0 and dt from physics.sample_numerics)."""
    sample, material, shear, numerics = case.sample, case.material, case.shear, case.numerics
    d, size = sample.dimension, sample.size
    sn = sample_numerics(case)
    le = {"amplitude": shear.amplitude, "omega": shear.omega} if shear.oscillatory else \
        {"shear_rate": shear.shear_rate, "subtract_mean_stress": sn.subtract_mean_stress}
    per = shear.time_scale
    duration = shear.duration_s
    series = per / numerics.samples_per_cycle if shear.oscillatory else duration / 200.0
    frames = per / numerics.frames_per_cycle if shear.oscillatory else duration / 8.0
    data = {
        "case": {"kind": "sph_flow", "name": case.case.name, "engine": "sph",
                 "description": case.case.description or "rheometer sample"},
        "domain": {"dimension": d, "lo": [0.0] * d, "hi": [size] * d, "periodic": list(range(d))},
        "fluid": {"max_speed": sn.sound_speed / 10.0},
        "materials": [{"name": MATERIAL, "model": "ptt", "density": sn.density, "sound_speed": sn.sound_speed,
                       "eos": material.eos, "background_pressure": _zero_pressure_shift(material.eos, sn) + sn.rest_pressure,
                       "epsilon": material.epsilon,
                       "solvent_viscosity": sn.morris_viscosity or material.solvent_viscosity,
                       "modes": [m.model_dump() for m in material.modes],
                       "storage_plateau": material.storage_plateau,
                       "stress_diffusion": sn.stress_diffusion or None,
                       "cross_loss": None if material.cross_loss is None else material.cross_loss.model_dump()}],
        "physics": {"terms": ["morris_viscosity"] if sn.morris_viscosity > 0.0 else []},
        "blocks": [{"name": "sample", "kind": "fluid", "material": MATERIAL, "lo": [0.0] * d, "hi": [size] * d}],
        "lees_edwards": le,
        "numerics": {"dx": sample.dx, "h_over_dx": sample.h_over_dx, "dt": sn.dt, "threads": numerics.threads},
        "simulation": {"duration": duration},
        "output": {"frame_interval": frames, "series_interval": series},
    }
    return SphFlowCase.model_validate(data)


def _zero_pressure_shift(eos: str, sn) -> float:
    """p_B (Pa) that makes the pressure vanish at the reference density: -rho0 c0^2 / 2 for the quadratic EOS
    (Nutto et al.'s eq. 9 gives rho0 c0^2 / 2 at rest), 0 for Tait. A uniform pressure moves nothing in the continuum,
    but across the Lees-Edwards faces, whose images are shifted by a fraction of dx, its discrete gradient
    (eq. 9) does not cancel and would stir the sample: at the paper's EOS it is 10^5 times the stress amplitude."""
    return -0.5 * sn.density * sn.sound_speed**2 if eos == "quadratic" else 0.0


def hexagonal_lattice(size: float, columns: int, dimension: int) -> tuple[np.ndarray, float]:
    """A hexagonal lattice filling the periodic square (2D) of side `size` (m): `columns` particles per row
    spaced dx = size / columns, an even number of rows (nearest to size / (dx sqrt(3)/2)) spaced size / rows,
    odd rows shifted by dx/2; returns positions (n, 2) m and the area per particle m^2. 2D only."""
    if dimension != 2:
        raise ValueError("sample.lattice = 'hexagonal' is 2D only; use 'square' in 3D")
    dx = size / columns
    rows = max(2, 2 * round(size / (dx * np.sqrt(3.0) / 2.0) / 2))
    dy = size / rows
    i, j = np.meshgrid(np.arange(columns), np.arange(rows), indexing="ij")
    x = (i + 0.5 + 0.5 * (j % 2)) * dx
    y = (j + 0.5) * dy
    return np.column_stack([x.ravel(), y.ravel()]), dx * dy


def build_rheometer(case: RheometerCase) -> SphScene:
    """The sample's particles (a lattice of particles^D, moving with the initial homogeneous shear) and deck."""
    scene = build_sph_flow(flow_case(case))
    if case.sample.arrangement == "hexagonal":
        positions, area = hexagonal_lattice(case.sample.size, case.sample.particles, case.sample.dimension)
        n, rho = len(positions), scene.densities[0]
        scene = replace(scene, positions=positions, velocities=np.zeros_like(positions),
                        masses=np.full(n, rho * area), densities=np.full(n, rho), kind=np.zeros(n, np.int8),
                        block=np.zeros(n, np.int32), material=np.zeros(n, np.int32))
    rate0 = case.shear.amplitude * case.shear.omega if case.shear.oscillatory else case.shear.shear_rate
    velocities = np.zeros_like(scene.velocities)
    velocities[:, 0] = rate0 * (scene.positions[:, 1] - 0.5 * case.sample.size)
    return replace(scene, velocities=velocities)
