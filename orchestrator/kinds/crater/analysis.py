"""What a crater run measured (run.h5 /measured) from the sphere's series and the target's frames, and Hutchings'
eq. 20 beside it. Lengths in m, pressures in Pa.

Definitions (the top face is z = 0; r the sphere's radius):
- penetration delta(t) = -(z_centre - r), the sphere's lowest point below the top face;
- contact_diameter = 2 sqrt(2 r delta_max - delta_max^2), the chord at the deepest penetration;
- crater_diameter: the rim crest of the permanent crater, the ring (of dx/2 about the axis) where the top layer's
  pile-up stands highest at the end, placed between rings by a parabola through the highest and its neighbours;
- indentation_diameter: where the top layer (its ring means) rises back through its starting height, inside the
  pile-up;
- plastic_zone_diameter: the rim of the plastically deformed zone at the surface, where the top layer's equivalent
  plastic strain (its mean in rings of dx/2) falls below PLASTIC_RIM;
- permanent_depth: how far the top layer's centre (particles within dx of the axis) ended below its start;
- crater_volume: the permanent crater's volume below the starting surface, from the top layer's final heights (their
  ring means about the axis, by final radius, in rings of dx/2) out to where the surface rises back through its
  starting height;
- volume_diameter: the diameter of the spherical cap of the sphere's radius that holds crater_volume,
  (64 r V / pi)^(1/4): the crater of eq. 20's energy balance, which takes the indentation work as H V;
- dynamic_hardness: the sphere's kinetic energy over crater_volume, Hutchings' (1977) dynamic hardness; eq. 20 at
  this H gives volume_diameter;
- mean_pressure: the time average of F / (pi a^2), a^2 = 2 r delta - delta^2, while the sphere goes in (from the
  first contact force to delta_max): the mean contact pressure H of Hutchings' model;
- hutchings_diameter: eq. 20, d = 2 r sqrt(2 v) (2 rho_s / 3 H)^(1/4) with H = mean_pressure and rho_s the sphere's
  density (the derivation: docs/solids.md, "Hutchings' crater");
- hertz_modulus (an indenter, sphere.kinematic): Hertz's F = 4/3 E* sqrt(r) delta^(3/2) for a rigid sphere on an
  elastic half-space, so F^(2/3) is linear in delta; the least-squares line through (delta, F^(2/3)) of the
  records with F above HERTZ_FROM of the last force gives E* = 3/4 slope^(3/2) / sqrt(r) (its intercept takes up
  where the surface is, within a particle's extent). The block is a layer glued to its held support, which
  stiffens it by a factor that grows with the contact radius over its depth: F is divided by the bonded-layer
  factor of Dimitriadis et al. (2002) before the fit (hertz_modulus_half_space: without it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from orchestrator.kinds.crater.pictures import plot_crater
from orchestrator.kinds.base import print_run_measures
from orchestrator.reference.contact import bonded_layer_factor

#: The equivalent plastic strain that marks the plastic zone's rim at the surface, -.
PLASTIC_RIM = 0.01

#: Hertz's fit starts where the force exceeds this fraction of the last one (the first touches are single particles).
HERTZ_FROM = 0.05

#: The measured quantities: name -> (SI unit, meaning).
QUANTITIES: dict[str, tuple[str, str]] = {
    "crater_diameter": ("m", "the rim crest: where the top layer's pile-up stands highest at the end"),
    "indentation_diameter": ("m", "where the top layer rises back through its starting height"),
    "plastic_zone_diameter": ("m", f"the rim of the plastic zone at the surface (top layer eps_p = {PLASTIC_RIM})"),
    "contact_diameter": ("m", "the sphere's chord at the deepest penetration, 2 sqrt(2 r d - d^2)"),
    "max_penetration": ("m", "the sphere's deepest point below the top face"),
    "permanent_depth": ("m", "the top layer's centre below its start at the end"),
    "crater_volume": ("m^3", "the permanent crater's volume below the starting surface"),
    "volume_diameter": ("m", "the chord of the cap of the sphere's radius holding crater_volume, (64 r V / pi)^(1/4)"),
    "dynamic_hardness": ("Pa", "the sphere's kinetic energy over crater_volume (Hutchings 1977)"),
    "mean_pressure": ("Pa", "time average of F / (pi a^2) while the sphere goes in"),
    "peak_force": ("N", "largest contact force"),
    "hutchings_diameter": ("m", "eq. 20 with the measured mean_pressure and the sphere's density"),
    "rebound_speed": ("m/s", "the sphere's speed along +z at the end"),
    "hertz_modulus": ("Pa", "an indenter's contact modulus E* fitted to Hertz's F = 4/3 E* sqrt(r) delta^(3/2) "
                      "times the bonded-layer factor of the block's depth (Dimitriadis et al. 2002)"),
    "hertz_modulus_half_space": ("Pa", "the same fit without the layer factor (Hertz's half-space)"),
    "hertz_fit_residual": ("-", "largest |F - Hertz's fit| over the last force in the fitted records"),
    "elastic_modulus": ("Pa", "E / (1 - nu^2) of the target from its G and K (Hertz's E* for a rigid sphere)"),
    "restitution": ("-", "rebound speed over impact speed"),
    "plastic_work_fraction": ("-", "the target's internal energy at the end over the sphere's initial kinetic energy"),
    "max_plastic_strain": ("-", "largest equivalent plastic strain in the target"),
    "max_temperature": ("K", "highest temperature in the target"),
    "energy_balance": ("-", ("(sphere + target kinetic, target internal, contact energy) at the end over the "
                             "initial kinetic energy, minus 1")),
}


def hutchings_diameter(radius: float, speed: float, density: float, pressure: float) -> float:
    """Eq. 20: the crater diameter d = 2 r sqrt(2 v) (2 rho / 3 H)^(1/4), m, of a sphere of radius r (m), speed v
    (m/s) and density rho (kg/m^3) on a target of mean contact pressure H (Pa)."""
    return 2.0 * radius * math.sqrt(2.0 * speed) * (2.0 * density / (3.0 * pressure)) ** 0.25


def hutchings_pressure(radius: float, speed: float, density: float, diameter: float) -> float:
    """Eq. 20 solved for H, Pa: the mean contact pressure that gives a crater of `diameter` (m)."""
    return 2.0 * density / 3.0 * (2.0 * radius * math.sqrt(2.0 * speed) / diameter) ** 4


def sphere_history(case, result) -> dict[str, np.ndarray]:
    """The sphere's series: t (s), penetration delta (m), velocity v_z (m/s), contact force F_z (N), kinetic and
    contact energy (J)."""
    radius = 0.5 * case.sphere.diameter
    s = result.series
    z = np.asarray(s["impactor_sphere_position"].values, dtype=float)[:, 2]
    return {"t": np.asarray(result.time, dtype=float), "delta": radius - z,
            "v": np.asarray(s["impactor_sphere_velocity"].values, dtype=float)[:, 2],
            "force": np.asarray(s["impactor_sphere_force"].values, dtype=float)[:, 2],
            "kinetic": np.asarray(s["impactor_sphere_kinetic_energy"].values, dtype=float),
            "contact": np.asarray(s["impactor_sphere_contact_energy"].values, dtype=float)}


def loading(case, h: dict) -> dict[str, float]:
    """Deepest penetration, contact diameter, mean contact pressure and peak force of the sphere's history."""
    radius = 0.5 * case.sphere.diameter
    deepest = int(np.argmax(h["delta"]))
    delta_max = float(h["delta"][deepest])
    touching = np.flatnonzero(h["force"] > 0.0)
    out = {"max_penetration": delta_max, "peak_force": float(h["force"].max())}
    if delta_max > 0.0:
        out["contact_diameter"] = 2.0 * math.sqrt(max(2.0 * radius * delta_max - delta_max**2, 0.0))
    if touching.size and deepest > touching[0]:
        span = slice(int(touching[0]), deepest + 1)
        d = np.clip(h["delta"][span], 0.0, None)
        area = math.pi * np.clip(2.0 * radius * d - d * d, 0.0, None)
        t = h["t"][span]
        ok = area > 0.0
        if ok.sum() >= 2:
            pressure = h["force"][span][ok] / area[ok]
            out["mean_pressure"] = float(np.trapezoid(pressure, t[ok]) / (t[ok][-1] - t[ok][0]))
    return out


def surface(case, first: dict, last: dict) -> dict[str, float]:
    """The plastic zone's rim at the surface and the permanent depth at the centre, from the first and last frame."""
    dx = case.numerics.dx
    x0 = np.asarray(first["positions"], dtype=float)
    top = (np.asarray(first["kind"]) == 0) & (x0[:, 2] > -dx)
    x = np.asarray(last["positions"], dtype=float)
    r = np.hypot(x0[top, 0], x0[top, 1])
    sink = x0[top, 2] - x[top, 2]  # how far each top particle ended below its start, m
    out = {"crater_diameter": 2.0 * crest_radius(r, -sink, 0.5 * dx),
           "indentation_diameter": 2.0 * rim_radius(r, sink, 0.5 * dx, 0.0)}
    centre = r < dx
    if centre.any():
        out["permanent_depth"] = float(np.mean(sink[centre]))
    volume = crater_volume(np.hypot(x[top, 0], x[top, 1]), sink, 0.5 * dx)
    if volume > 0.0:
        radius = 0.5 * case.sphere.diameter
        out["crater_volume"] = volume
        out["volume_diameter"] = (64.0 * radius * volume / math.pi) ** 0.25
    if "plastic_strain" in last:
        eps = np.asarray(last["plastic_strain"], dtype=float)[top]
        out["plastic_zone_diameter"] = 2.0 * rim_radius(r, eps, 0.5 * dx, PLASTIC_RIM)
        out["max_plastic_strain"] = float(np.max(last["plastic_strain"]))
    if "temperature" in last:
        out["max_temperature"] = float(np.max(last["temperature"]))
    return out


def ring_means(r: np.ndarray, value: np.ndarray, ring: float) -> tuple[np.ndarray, np.ndarray]:
    """(ring centres m, mean of `value` in each ring of width `ring` m about the axis), empty rings left out."""
    edges = np.arange(0.0, r.max() + ring, ring)
    index = np.digitize(r, edges) - 1
    means = np.array([value[index == k].mean() if np.any(index == k) else np.nan for k in range(len(edges) - 1)])
    centres = 0.5 * (edges[:-1] + edges[1:])
    keep = np.isfinite(means)
    return centres[keep], means[keep]


def crater_volume(r: np.ndarray, sink: np.ndarray, ring: float) -> float:
    """The volume (m^3) below the starting surface of a crater whose surface points at radius `r` (m, about the
    axis) ended `sink` (m) below their start: the ring means of `sink` (rings of width `ring`, m) times the ring
    areas, summed outwards up to the first ring whose mean is not below the start."""
    centres, means = ring_means(r, sink, ring)
    below = np.flatnonzero(means <= 0.0)
    inside = slice(0, below[0] if below.size else len(means))
    return float(np.sum(means[inside] * 2.0 * math.pi * centres[inside] * ring))


def crest_radius(r: np.ndarray, height: np.ndarray, ring: float) -> float:
    """The radius (m) where the ring means of `height` are highest, off the axis, refined by the parabola through
    that ring and its two neighbours; nan when the highest ring is the first or the last."""
    centres, means = ring_means(r, height, ring)
    k = int(np.argmax(means))
    if k == 0 or k == len(means) - 1:
        return math.nan
    a, b, c = means[k - 1], means[k], means[k + 1]
    curvature = a - 2.0 * b + c
    shift = 0.5 * (a - c) / curvature if curvature < 0.0 else 0.0
    return float(centres[k] + shift * (centres[k + 1] - centres[k]))


def rim_radius(r: np.ndarray, value: np.ndarray, ring: float, level: float) -> float:
    """The radius (m) where the mean of `value` in rings of width `ring` (m) first falls below `level` going out
    from the axis (from the highest ring where the axis is below it: a plastic zone that begins under the surface),
    interpolated linearly between the ring centres; nan when every ring is below it."""
    centres, means = ring_means(r, value, ring)
    if not means.size or means.max() < level:
        return math.nan
    start = 0 if means[0] >= level else int(np.argmax(means))
    below = np.flatnonzero(means[start:] < level) + start
    if not below.size:
        return float(centres[-1])
    above = below[0] - 1
    if above == len(means) - 1:
        return float(centres[-1])
    m0, m1 = means[above], means[above + 1]
    return float(centres[above] + (m0 - level) / (m0 - m1) * (centres[above + 1] - centres[above]))


def hertz_fit(radius: float, delta: np.ndarray, force: np.ndarray, layer=None) -> dict[str, float]:
    """Hertz's contact modulus E* (Pa) from the force F (N) against the penetration delta (m) of a rigid sphere of
    `radius` (m): the line through (delta, F^(2/3)) where F > HERTZ_FROM max F, and its largest residual in F.
    `layer` = (thickness h m, Poisson's ratio): the block is a layer bonded to its support, so F is first divided
    by its factor over Hertz's half-space (reference.contact.bonded_layer_factor at sqrt(r delta) / h); then also
    the half-space's fit as hertz_modulus_half_space."""
    use = force > HERTZ_FROM * force.max()
    if use.sum() < 3:
        return {}
    d = delta[use]
    factor = np.ones_like(d) if layer is None else bonded_layer_factor(np.sqrt(radius * np.clip(d, 0.0, None))
                                                                       / layer[0], layer[1])
    slope, intercept = np.polyfit(d, (force[use] / factor) ** (2.0 / 3.0), 1)
    if not slope > 0.0:
        return {}
    fitted = factor * np.clip(slope * d + intercept, 0.0, None) ** 1.5
    out = {"hertz_modulus": 0.75 * slope**1.5 / math.sqrt(radius),
           "hertz_fit_residual": float(np.max(np.abs(force[use] - fitted)) / force.max())}
    if layer is not None:
        out["hertz_modulus_half_space"] = hertz_fit(radius, delta, force)["hertz_modulus"]
    return out


def poisson_ratio(case) -> float:
    """nu of the target, from its shear modulus G and bulk modulus K, -."""
    solid, density = case.material.solid, case.material.density
    g, k = solid.shear_modulus, solid.bulk(density)
    return (3.0 * k - 2.0 * g) / (2.0 * (3.0 * k + g))


def contact_modulus(case) -> float:
    """E / (1 - nu^2) of the target, Pa, from its shear modulus G and bulk modulus K (E = 2 G (1 + nu))."""
    nu = poisson_ratio(case)
    return 2.0 * case.material.solid.shear_modulus * (1.0 + nu) / (1.0 - nu * nu)


def measure_crater(case, result) -> dict[str, float]:
    """Measured quantities of a crater run (QUANTITIES); empty without its series."""
    if "impactor_sphere_position" not in result.series or len(result.time) < 2:
        return {}
    h = sphere_history(case, result)
    radius, speed = 0.5 * case.sphere.diameter, case.sphere.speed
    measured = loading(case, h)
    if case.sphere.kinematic:  # the block is a layer on its held support
        measured.update(hertz_fit(radius, h["delta"], h["force"], (case.target.size[2], poisson_ratio(case))))
        measured["elastic_modulus"] = contact_modulus(case)
    measured["rebound_speed"] = float(h["v"][-1])
    measured["restitution"] = float(h["v"][-1] / speed)
    if "mean_pressure" in measured and not case.sphere.kinematic:
        measured["hutchings_diameter"] = hutchings_diameter(radius, speed, case.sphere.density,
                                                            measured["mean_pressure"])
    if len(result.frames) >= 2:
        first, last = result.frames[0][1], result.frames[-1][1]
        measured.update(surface(case, first, last))
        kinetic0 = float(h["kinetic"][0])
        if "internal_energy" in last and kinetic0 > 0.0 and not case.sphere.kinematic:
            moving = np.asarray(last["kind"]) == 0
            mass = case.material.inertial_density() * case.numerics.dx**3  # the run's particle mass
            v = np.asarray(last["velocities"], dtype=float)[moving]
            internal = mass * float(np.sum(np.asarray(last["internal_energy"])[moving]))
            final = 0.5 * mass * float(np.sum(v * v)) + internal + float(h["kinetic"][-1] + h["contact"][-1])
            measured["energy_balance"] = final / kinetic0 - 1.0
            measured["plastic_work_fraction"] = internal / kinetic0
        if measured.get("crater_volume", 0.0) > 0.0 and kinetic0 > 0.0 and not case.sphere.kinematic:
            measured["dynamic_hardness"] = kinetic0 / measured["crater_volume"]
    return {k: v for k, v in measured.items() if math.isfinite(v)}


def analyze_crater_run(run_dir: Path, run: dict, case, render: bool = True) -> dict:
    """Print the measured quantities (QUANTITIES) and, for the paper's speed, the mean contact pressure its crater
    implies; write crater.png. Returns {name: path}."""
    print_run_measures(run_dir, run, QUANTITIES)
    reference = case.reference
    if reference is not None and reference.diameter_at_100 is not None:
        r = 0.5 * case.sphere.diameter
        implied = hutchings_pressure(r, 100.0, case.sphere.density, reference.diameter_at_100)
        print(f"{'paper at 100 m/s':<24} {reference.diameter_at_100:.6g} m ({reference.source}); eq. 20 then needs "
              f"H = {implied / 1e9:.4g} GPa with the sphere's density, "
              f"{hutchings_pressure(r, 100.0, case.material.density, reference.diameter_at_100) / 1e9:.4g} GPa "
              f"with the target's")
    if not render:
        return {}
    path = plot_crater(run, case, Path(run_dir) / "crater.png")
    print(f"{'picture':<24} {path}")
    return {"picture": path}
