"""The impact kind on LAMMPS's GRANULAR package (orchestrator/kinds/impact/lammps.py, lammps_output.py, the mapping in
orchestrator/dem/lammps_law.py): the mapping against LAMMPS's own formulas, the rendered deck against its golden files,
the data file read back, the per-contact forces rebuilt from per-sphere forces, what is refused; and, with LAMMPS
installed, Chung & Ooi's test 1 against its closed forms and the oblique impact at 10 degrees with the measured
effect of LAMMPS's Coulomb bookkeeping."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from golden import assert_matches_golden

from orchestrator.case import load_case
from orchestrator.dem.lammps_law import (
    MAX_ALPHA,
    coefficient_of_restitution,
    granular_law,
    hertz_material_young,
    lammps_alpha,
    tangential_damping_scale,
)
from orchestrator.kinds import build_scene
from orchestrator.kinds.impact.analysis import evaluate_checks, expected_values
from orchestrator.kinds.impact.lammps import (
    DATA,
    TEMPLATE,
    contact_law,
    impact_context,
    refusal,
    write_spheres,
)
from orchestrator.kinds.impact.lammps_output import split_pair_forces, step_contacts
from orchestrator.reference import closed_form, contact
from orchestrator.runh5 import read_run
from orchestrator.templating import render
from paths import VERIFICATION
from paths import GOLDEN as GOLDEN_DIR

GOLDEN = {"lammps_impact_sphere_drop.in": "uhlmann2015_sphere_drop",
          "lammps_impact_sphere_sphere.in": "chung_ooi_test1_sphere_sphere"}


def scene_of(name: str):
    return build_scene(load_case(VERIFICATION / f"{name}.toml").model)


# ---- the mapping (LAMMPS's formulas as written in its GRANULAR sources, no engine needed) ----
def lammps_damp(restitution: float) -> float:
    """gran_sub_mod_damping.cpp, coeff_restitution with a Hertz normal model: sqrt(3/2) 2 sqrt(5/6) beta."""
    log_e = math.log(restitution)
    return -math.sqrt(1.5) * 2.0 * math.sqrt(5.0 / 6.0) * log_e / math.sqrt(math.pi**2 + log_e**2)


def lammps_effective_young(young: float, poisson: float) -> float:
    """gran_sub_mod_normal.cpp, hertz/material of a pair set explicitly (and of a wall): E / (2 (1 - nu^2))."""
    return 1.0 / (2.0 * (1.0 - poisson**2) / young)


@pytest.mark.parametrize("alpha", [0.05, 0.5, 1.0, 1.6351178367289902, 2.2])
def test_coefficient_of_restitution_makes_lammps_run_the_asked_alpha(alpha):
    e_star = coefficient_of_restitution(alpha)
    assert 0.0 < e_star < 1.0
    assert lammps_damp(e_star) == pytest.approx(alpha, rel=1e-12)
    assert lammps_alpha(e_star) == pytest.approx(alpha, rel=1e-12)


@pytest.mark.parametrize("restitution", [0.2, 0.68, 0.95])
def test_lammps_own_reading_of_restitution_is_eq10(restitution):
    assert lammps_alpha(restitution) == pytest.approx(float(contact.damping_alpha(restitution)), rel=1e-12)


def test_undamped_and_beyond_reach():
    assert coefficient_of_restitution(0.0) == 1.0 and lammps_alpha(1.0) == 0.0
    with pytest.raises(ValueError, match="coeff_restitution"):
        coefficient_of_restitution(MAX_ALPHA * 1.001)
    assert MAX_ALPHA == pytest.approx(0.999 * math.sqrt(5.0))


@pytest.mark.parametrize("young, poisson", [(380e9, 0.23), (77e9, 0.19), (4.6e11, 0.0)])
def test_hertz_material_young_gives_the_effective_modulus(young, poisson):
    target = 0.5 * young / (1.0 - poisson**2)
    assert lammps_effective_young(hertz_material_young(target, poisson), poisson) == pytest.approx(target, rel=1e-14)


def test_like_spheres_get_their_own_material_and_the_rigid_wall_twice_the_sphere():
    scene = scene_of("chung_ooi_test1_sphere_sphere")
    law = contact_law(scene, "glass", "glass")
    assert law.young == pytest.approx(48e9, rel=1e-14) and law.poisson == 0.2
    assert law.restitution == 1.0 and law.friction == 0.0
    # Mindlin's k_t0 / sqrt(R*) of like spheres, 8 G*: 2 E / ((2 - nu)(1 + nu))
    assert law.shear_stiffness == pytest.approx(2 * 48e9 / (1.8 * 1.2), rel=1e-14)
    wall = contact_law(scene_of("chung_ooi_test4_oblique_10deg"), "alumina", "rigid")
    assert wall.young == pytest.approx(2 * 380e9, rel=1e-14) and wall.poisson == 0.23
    assert wall.shear_stiffness == pytest.approx(8 * 380e9 / 2.46 / 1.77, rel=1e-14)  # 8 G / (2 - nu)
    assert wall.friction == 0.092 and wall.tangential_damping == 1.0


def test_ceramic_on_steel_runs_eq5_and_the_exact_alpha():
    scene = scene_of("uhlmann2015_sphere_drop")
    pair = scene.pair("ceramic", "steel")
    law = contact_law(scene, "ceramic", "steel")
    assert lammps_effective_young(law.young, law.poisson) == pytest.approx(pair.effective_young, rel=1e-14)
    g_ceramic, g_steel = 77e9 / 2.38, 210e9 / 2.6
    eq5 = 4 * (g_ceramic + g_steel) / 2 / (2 - (0.19 + 0.30) / 2)
    assert law.shear_stiffness == pytest.approx(eq5, rel=1e-14)
    assert lammps_damp(law.restitution) == pytest.approx(pair.alpha, rel=1e-12)
    assert pair.alpha == pytest.approx(closed_form.alpha_from_restitution(0.68, True), rel=1e-12)
    lone = contact_law(scene, "ceramic", "ceramic")  # one ball: its pair with itself never touches, undamped
    assert lone.restitution == 1.0 and lone.friction == 0.0 and lone.young == pytest.approx(77e9, rel=1e-14)


def test_engine_damping_passes_the_restitutions_through():
    law = granular_law(1e9, 0.3, 1e9, 0.5, None, 0.6, 0.8)
    assert law.restitution == 0.6
    assert law.tangential_damping == pytest.approx(lammps_damp(0.8) / lammps_damp(0.6), rel=1e-12)
    assert tangential_damping_scale(0.0, 1.0) == 1.0


@pytest.fixture
def low_restitution(tmp_path) -> Path:
    """Chung & Ooi's test 3 at e_n = 0.1: the exact alpha, 2.78, lies beyond coeff_restitution's sqrt(5)."""
    text = (VERIFICATION / "chung_ooi_test3_restitution_020.toml").read_text()
    case = tmp_path / "low.toml"
    case.write_text(text.replace("restitution = 0.2", "restitution = 0.1"))
    return case


def test_a_damping_beyond_reach_is_refused_and_the_suite_is_not(low_restitution):
    assert "alpha = 2.78" in refusal(build_scene(load_case(low_restitution).model))
    for case in sorted(VERIFICATION.glob("chung_ooi_*.toml")) + [VERIFICATION / "uhlmann2015_sphere_drop.toml"]:
        assert refusal(build_scene(load_case(case).model)) == ""


def test_a_refused_scene_is_one_error_line_and_exit_2(low_restitution, tmp_path):
    case = low_restitution
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(case), "--engine", "lammps",
                           "--out", str(tmp_path / "run"), "--no-progress"],
                          check=False, capture_output=True, text=True, timeout=300,
                          env={"ORCHESTRATOR_LAMMPS": sys.executable, "PATH": "/usr/bin:/bin"})
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and "coeff_restitution" in lines[0]


# ---- the deck and the data file ----
@pytest.mark.parametrize("golden", sorted(GOLDEN))
def test_rendered_deck_matches_golden(golden):
    assert_matches_golden(render(TEMPLATE, impact_context(scene_of(GOLDEN[golden]))), GOLDEN_DIR / golden)


def test_deck_sets_every_type_pair_and_one_wall_per_sphere_type():
    case = load_case(VERIFICATION / "uhlmann2015_sphere_drop.toml").model
    spheres = [case.spheres[0].model_copy(update={"material": name, "position": (0.02 * k, 0.0, 0.01327)})
               for k, name in enumerate(("ceramic", "steel", "ceramic"))]
    contacts = list(case.contacts) + [case.contacts[0].model_copy(update={"pair": ("ceramic", "ceramic")}),
                                      case.contacts[0].model_copy(update={"pair": ("steel", "steel")})]
    scene = build_scene(case.model_copy(update={"spheres": tuple(spheres), "contacts": tuple(contacts)}))
    deck = render(TEMPLATE, impact_context(scene))
    assert [line.split()[1:3] for line in deck.splitlines() if line.startswith("pair_coeff")] == \
        [["1", "1"], ["1", "2"], ["2", "2"]]
    walls = [line.split() for line in deck.splitlines() if "wall/gran/region" in line]
    assert [(w[1], w[2]) for w in walls] == [("wall_1", "type_1"), ("wall_2", "type_2")]
    assert "f_wall_2[4]" in deck and "cutoff" in deck


def test_data_file_round_trip(tmp_path):
    scene = scene_of("chung_ooi_test1_sphere_sphere")
    write_spheres(scene, tmp_path / DATA)
    lines = (tmp_path / DATA).read_text().splitlines()
    atoms = lines.index("Atoms # sphere") + 2
    rows = np.array([line.split() for line in lines[atoms:atoms + 2]], dtype=float)
    np.testing.assert_array_equal(rows[:, 2], 2 * scene.radii)
    np.testing.assert_array_equal(rows[:, 3], 2800.0)
    np.testing.assert_array_equal(rows[:, 4:7], scene.positions)
    velocities = lines.index("Velocities") + 2
    rows = np.array([line.split() for line in lines[velocities:velocities + 2]], dtype=float)
    np.testing.assert_array_equal(rows[:, 1:4], scene.velocities)
    np.testing.assert_array_equal(rows[:, 4:7], scene.angular_velocities)


# ---- the reader ----
def test_pair_forces_of_a_chain_are_split_exactly():
    rng = np.random.default_rng(5)
    pairs = np.array([[0, 1], [1, 2], [3, 4]])
    truth = rng.normal(size=(3, 3))
    residual = np.zeros((6, 3))
    for (i, j), f in zip(pairs, truth):
        residual[i] += f
        residual[j] -= f
    np.testing.assert_allclose(split_pair_forces(pairs, residual), truth, rtol=1e-12, atol=1e-12)


def test_step_contacts_of_a_wall_and_a_pair():
    g = np.array([0.0, 0.0, -9.81])
    record = {"radius": np.array([1e-3, 1e-3]), "mass": np.array([2e-5, 2e-5]),
              "x": np.array([[0.0, 0.0, 0.9e-3], [0.0, 0.0, 2.8e-3]]),
              "v": np.array([[0.0, 0.0, -1.0], [0.0, 0.0, -3.0]]), "spin": np.zeros((2, 3)),
              "wall_force": np.array([[0.0, 0.0, 5.0], [0.0, 0.0, 0.0]]), "on_wall": np.array([True, False])}
    pair_on_lower = np.array([0.0, 0.0, -2.0])  # the upper ball pushes the lower one down with 2 N
    record["force"] = record["wall_force"] + record["mass"][:, None] * g + np.array([pair_on_lower, -pair_on_lower])
    dt = 1e-6
    c = step_contacts(record, (np.zeros(3), np.array([0.0, 0.0, 1.0])), g, dt)
    assert c["keys"] == [(0, 1, 0), (0, 0, 1)]
    np.testing.assert_allclose(c["overlap"], [0.1e-3, 0.1e-3], rtol=1e-9)
    np.testing.assert_allclose(c["normal_force"], [5.0, 2.0], rtol=1e-12)
    half_step = record["v"] - 0.5 * dt * record["force"] / record["mass"][:, None]
    assert c["rate"][0] == pytest.approx(-half_step[0, 2], rel=1e-12)
    assert c["rate"][1] == pytest.approx(half_step[0, 2] - half_step[1, 2], rel=1e-12)  # the upper ball closes in


# ---- the oblique impact at 10 degrees replayed with the law alone ----
def replay_oblique_impact(lammps_slip: bool, lever_arm_radius: bool, dt: float) -> tuple[float, float]:
    """Chung & Ooi's alumina sphere at 10 degrees on the rigid wall, integrated as LAMMPS does (velocity Verlet, forces
    from half-step velocities; Hertz, Tsuji's exact alpha clipped at zero, F_t += -k_t a v_t dt, |F_t| <= mu F_n on
    the total): (rebound tangential velocity m/s, rebound spin rad/s). lammps_slip: a sliding contact keeps
    mu F_n minus the dash-pot as spring force (else all of mu F_n, the reference's rule); lever_arm_radius: the
    contact point at R (else R - delta / 2, the reference's)."""
    scene = scene_of("chung_ooi_test4_oblique_10deg")
    material = scene.case.materials["alumina"]
    young, nu, radius = material.young_modulus, material.poisson_ratio, float(scene.radii[0])
    mass = material.density * 4.0 / 3.0 * math.pi * radius**3
    inertia = 0.4 * mass * radius**2
    pair = scene.pair("alumina", "rigid")
    kn0 = 4.0 / 3.0 * pair.effective_young * math.sqrt(radius)
    kt0 = float(contact.mindlin_stiffness_coefficient(radius, young, nu, math.inf, 0.0))
    z, (vx, _, vz), spin = radius, scene.velocities[0], 0.0
    spring = fx = fz = torque = 0.0
    while True:
        vx_half, vz_half = vx + 0.5 * dt * fx / mass, vz + 0.5 * dt * fz / mass
        spin_half = spin + 0.5 * dt * torque / inertia
        z += dt * vz_half
        overlap = radius - z
        if overlap <= 0.0:
            return float(vx_half), float(spin_half)
        damping = pair.alpha * math.sqrt(mass * kn0) * overlap**0.25
        fz = max(0.0, kn0 * overlap**1.5 - damping * vz_half)
        arm = radius if lever_arm_radius else radius - 0.5 * overlap
        slip = vx_half - arm * spin_half
        spring -= kt0 * math.sqrt(overlap) * slip * dt
        fx = spring - damping * slip
        if abs(fx) > pair.friction * fz:
            fx = math.copysign(pair.friction * fz, fx)
            spring = fx + damping * slip if lammps_slip else fx
        torque = -arm * fx
        vx, vz = vx_half + 0.5 * dt * fx / mass, vz_half + 0.5 * dt * fz / mass
        spin = spin_half + 0.5 * dt * torque / inertia


def test_the_10deg_spin_gap_is_lammps_slip_rule_and_lever_arm():
    """Converged in the step (1.4 ns): the reference's rules land within 0.4 % of the closed form (197.86 rad/s);
    LAMMPS's slip rule takes 2.8 % of the spin away, its lever arm R a further 0.44 %."""
    expected = expected_values(load_case(VERIFICATION / "chung_ooi_test4_oblique_10deg.toml").model)["rebound_spin"]
    dt = 1.4e-9
    reference = replay_oblique_impact(False, False, dt)[1]
    slip_rule = replay_oblique_impact(True, False, dt)[1]
    lammps = replay_oblique_impact(True, True, dt)[1]
    assert reference == pytest.approx(expected, rel=4e-3)
    assert slip_rule / reference == pytest.approx(0.9721, abs=1e-3)
    assert lammps / slip_rule == pytest.approx(0.9956, abs=5e-4)


# ---- real runs ----
def _run(tmp_path, name: str) -> tuple[dict, object]:
    out = tmp_path / name
    proc = subprocess.run([sys.executable, "-m", "orchestrator", "run", str(VERIFICATION / f"{name}.toml"), "--engine",
                           "lammps", "--out", str(out), "--no-progress"], check=False, capture_output=True, text=True,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr
    return read_run(out), load_case(VERIFICATION / f"{name}.toml").model


@pytest.mark.lammps
def test_chung_ooi_test1_within_its_tolerances(tmp_path):
    """Two glass spheres at +-10 m/s: Hertz's peak force, overlap and duration and the elastic rebound within
    0.02 % (tolerance 1 %), as the reference DEM and Yade (docs/verify_dem.md)."""
    run, case = _run(tmp_path, "chung_ooi_test1_sphere_sphere")
    assert run["attrs"]["status"] == "ok" and run["attrs"]["engine"] == "lammps"
    rows = evaluate_checks(case, run["measured"]["attrs"])
    assert len(rows) == 4 and all(row.passed for row in rows)
    assert max(row.rel_error for row in rows) < 2e-4


@pytest.mark.lammps
def test_oblique_10deg_runs_lammps_slip_rule(tmp_path):
    """Alumina at 10 degrees (stick, then slip): LAMMPS's rebound spin lies 3.4 % below the paper's law (tolerance
    5 %) and its tangential velocity 1.5 % above, within 0.1 % of the replay with LAMMPS's slip rule and lever arm
    at the same step (test_the_10deg_spin_gap_is_lammps_slip_rule_and_lever_arm; docs/verify_dem.md)."""
    run, case = _run(tmp_path, "chung_ooi_test4_oblique_10deg")
    measured = run["measured"]["attrs"]
    velocity, spin = replay_oblique_impact(True, True, run["attrs"]["dt"])
    assert measured["rebound_spin"] == pytest.approx(spin, rel=1e-3)
    assert measured["rebound_tangential_velocity"] == pytest.approx(velocity, rel=1e-3)
    rows = {row.quantity: row for row in evaluate_checks(case, measured)}
    assert all(row.passed for row in rows.values())
    assert rows["rebound_spin"].rel_error == pytest.approx(0.0343, abs=2e-3)
