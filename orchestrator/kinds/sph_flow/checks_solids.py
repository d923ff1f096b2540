"""The SPH verification checks of a fluid beside a solid in one run (cases/verification/sph_solid_under_water.toml):
an elastic layer on the tank's floor under a water column, at rest, against the weight above it."""

from __future__ import annotations

import math

import numpy as np

from orchestrator.kinds.sph_flow.checks_base import body_force_of, check_row, frames_of, tolerance_of
from orchestrator.reference.sph_flows import hydrostatic_pressure, layer_under_water_stress

#: The central part of the tank that the checks look at (fractions of its width): the side walls carry part of the
#: layer's load through its shear stress near them.
CENTRAL = (0.25, 0.75)


def _layer_and_water(case):
    """(layer block, its material, water block, its material) of the scene: the fluid blocks of a solid and of a
    fluid material; None when it lacks one of them."""
    materials = {m.name: m for m in case.materials}
    blocks = [(b, materials.get(b.material)) for b in case.blocks if b.kind == "fluid"]
    layer = next(((b, m) for b, m in blocks if m is not None and m.model == "johnson_cook"), None)
    water = next(((b, m) for b, m in blocks if m is not None and m.model != "johnson_cook"), None)
    return None if layer is None or water is None else (*layer, *water)


def check_solid_under_water(case, run) -> tuple[list[dict], dict]:
    """An elastic layer under water at rest: the layer's mean vertical stress and the water's pressures against the
    weight above them, in the central half of the tank, and the largest speed left."""
    name = case.case.name
    quantities = ("layer_stress", "layer_rows", "water_pressure", "spurious_speed")
    found = _layer_and_water(case)
    if found is None:
        return [check_row(name, quantity, None, None, None, tolerance_of(case, quantity), passed=False,
                          note="the scene needs a fluid block of a johnson_cook material (the layer) and one of a "
                               "fluid material (the water) in [[blocks]]") for quantity in quantities], {}
    layer, solid, water, fluid = found
    g = float(np.linalg.norm(body_force_of(case)))
    floor, top = layer.lo[1], layer.hi[1]
    surface = water.hydrostatic_surface if water.hydrostatic_surface is not None else water.hi[1]
    depth = surface - top
    scale = fluid.density * g * depth
    rows, lines = [], []
    frames = frames_of(run)
    if not frames:
        for quantity in quantities:
            rows.append(check_row(name, quantity, None, None, None, tolerance_of(case, quantity), passed=False,
                                  note="no frames recorded"))
        return rows, {}
    t, frame = frames[-1]
    x = np.asarray(frame["positions"])
    moving = np.asarray(frame["kind"]) == 0
    material = np.asarray(frame["material"])
    names = [m.name for m in case.materials]
    width = layer.hi[0] - layer.lo[0]
    central = (x[:, 0] > layer.lo[0] + CENTRAL[0] * width) & (x[:, 0] < layer.lo[0] + CENTRAL[1] * width)
    in_layer = moving & central & (material == names.index(solid.name))
    in_water = moving & central & (material == names.index(fluid.name))
    p = np.asarray(frame["pressures"])
    y_s = x[in_layer, 1] - floor
    sigma_yy = np.asarray(frame["stress"])[in_layer, 1, 1] - p[in_layer]  # deviatoric s_yy - p
    exact = layer_under_water_stress(y_s, top - floor, depth, solid.density, fluid.density, g)
    measured, expected = float(np.mean(sigma_yy)), float(np.mean(exact))
    rows.append(check_row(name, "layer_stress", measured, expected, abs(measured - expected) / abs(expected),
                          tolerance_of(case, "layer_stress"), source="the weight above, -(rho_w g H_w + rho_s g (H_s - y))",
                          note=f"layer_stress: the mean sigma_yy (Pa) of the layer's {int(in_layer.sum())} particles in "
                               f"the central half of the tank at t = {t:.3g} s, against the mean of the weight above "
                               "each"))
    heights = np.round(y_s / case.numerics.dx - 0.5).astype(int)  # the layer's particle rows
    rows_mean = np.array([np.mean(sigma_yy[heights == k] - exact[heights == k]) for k in np.unique(heights)])
    worst = int(np.argmax(np.abs(rows_mean)))
    rows.append(check_row(name, "layer_rows", rows_mean[worst] + expected, expected,
                          abs(rows_mean[worst]) / abs(expected), tolerance_of(case, "layer_rows"),
                          source="the weight above, row by row",
                          note=f"layer_rows: the mean sigma_yy of each particle row of the layer against the weight "
                               f"above it; value: the row furthest off ({len(rows_mean)} rows), shifted to the layer's "
                               "mean weight; rel_error = its deviation / the layer's mean weight"))
    y_w = x[in_water, 1]
    exact_w = hydrostatic_pressure(y_w - floor, surface - floor, fluid.density, g)
    l1 = float(np.mean(np.abs(p[in_water] - exact_w))) / scale
    lowest = y_w <= y_w.min() + 0.5 * case.numerics.dx
    rows.append(check_row(name, "water_pressure", np.mean(p[in_water][lowest]), np.mean(exact_w[lowest]), l1,
                          tolerance_of(case, "water_pressure"), source="hydrostatic rho_w g (H - y)",
                          note=f"water_pressure: every water particle's pressure in the central half at t = {t:.3g} s; "
                               "value, expected: mean of the row on the layer; rel_error = mean |p - rho_w g (H - y)| "
                               f"/ (rho_w g H_w = {scale:.4g} Pa)"))
    speed = float(np.max(np.linalg.norm(np.asarray(frame["velocities"])[moving], axis=1)))
    reference = math.sqrt(g * (surface - floor))
    rows.append(check_row(name, "spurious_speed", speed, 0.0, speed / reference, tolerance_of(case, "spurious_speed"),
                          source="at rest", note=f"spurious_speed: the fastest particle (water or layer) at t = {t:.3g} s; "
                                                 f"rel_error = value / sqrt(g H) = {reference:.3g} m/s"))
    if run["attrs"].get("status") != "ok":
        for row in rows:
            row["passed"] = False
    lines = [(sigma_yy / scale, (y_s + floor) / (surface - floor), ".", "C1", "layer: sigma_yy"),
             (-p[in_water] / scale, y_w / (surface - floor), ".", "C0", "water: -p"),
             (np.concatenate([exact, -exact_w]) / scale, np.concatenate([y_s + floor, y_w]) / (surface - floor),
              "x", "k", "weight above")]
    plot = {"title": f"{name}: vertical stress at t = {t:.3g} s", "xlabel": "sigma_yy / (rho_w g H_w)",
            "ylabel": "y / H", "lines": lines}
    return rows, plot
