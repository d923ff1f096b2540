"""The crater kind: its case checks, the scene (target, held support, sphere clear of it), Hutchings' eq. 20 and
its inverse, the rim and the rows, the impactors' mass properties, and (engine) the quick preset against eq. 20
and energy conservation."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from orchestrator.case import load_case
from orchestrator.cli import main
from orchestrator.errors import CaseError
from orchestrator.kinds import build_scene
from orchestrator.kinds.crater.analysis import (contact_modulus, crater_volume, crest_radius, hertz_fit,
                                                hutchings_diameter, hutchings_pressure, rim_radius)
from orchestrator.kinds.crater.checks import check_run, speed_slope, sweep_runs
from orchestrator.kinds.sph_flow.case_impactors import check_clear, mass_properties
from orchestrator.kinds.sph_flow.sph import deck_context
from orchestrator.reference.contact import bonded_layer_factor
from paths import VERIFICATION

CRATER = VERIFICATION / "crater_hutchings_100cr6.toml"
HERTZ = VERIFICATION / "hertz_sphere_elastic.toml"


def test_the_scene_is_the_target_on_its_support_below_the_sphere():
    case = load_case(CRATER, preset="quick").model
    scene = build_scene(case)
    x, dx = scene.positions, case.numerics.dx
    moving, held = scene.kind == 0, scene.kind == 1
    assert moving.sum() == 30 * 30 * 15 and held.sum() == 30 * 30 * 3
    assert x[moving, 2].max() == pytest.approx(-0.5 * dx) and x[held, 2].max() < x[moving, 2].min()
    np.testing.assert_allclose(x[:, :2].mean(axis=0), 0.0, atol=1e-18)
    deck = json.loads(deck_context(scene)["impactors"][0])
    r = 300e-6
    assert deck["centre"] == pytest.approx([0.0, 0.0, r + 0.25 * dx]) and deck["velocity"] == [0.0, 0.0, -100.0]
    mass = 2500.0 * 4.0 / 3.0 * math.pi * r**3
    assert deck["mass"] == pytest.approx(mass) and deck["inertia"][0][0] == pytest.approx(0.4 * mass * r * r)
    # the contact spring: rho0 c_L^2 dx of the target, c_L^2 = (rho0 C0^2 + 4G/3) / rho0
    assert deck["stiffness"] == pytest.approx((7810.0 * 4578.0**2 + 4.0 / 3.0 * 80.769e9) * dx)


@pytest.mark.parametrize("override, words", [
    ("target.size=[811e-6, 810e-6, 405e-6]", "target.size along x = 0.000811 m is not a whole number"),
    ("sphere.diameter=60e-6", "sphere.diameter = 6e-05 m spans fewer than 8 particles"),
    ("sphere.diameter=900e-6", "sphere.diameter = 0.0009 m is wider than the target"),
    ("material.solid.yield_stress=-1", "yield_stress"),
    ("material.solid.melting_temperature=200", "material.solid.melting_temperature = 200 K is not above"),
    ("sphere.speed=0", "sphere.speed"),
])
def test_bad_craters_are_named(override, words):
    with pytest.raises(CaseError, match=words.replace(".", r"\.").replace("[", r"\[")):
        load_case(CRATER, overrides=[override])


def test_an_impactor_inside_the_particles_is_refused():
    x = np.array([[0.0, 0.0, -0.5e-6]])
    case = load_case(CRATER, preset="quick").model
    from orchestrator.kinds.crater.scene import flow_case

    imp = flow_case(case).impactors[0]
    check_clear([imp], x, np.array([True]), 1e-6)  # far below the sphere: clear
    with pytest.raises(ValueError, match=r"impactors\[0\].spheres\[0\] of 'sphere' overlaps the particles"):
        check_clear([imp], np.array([[0.0, 0.0, imp.spheres[0][2] - imp.spheres[0][3]]]), np.array([True]), 1e-6)


def test_hutchings_eq_20_and_the_papers_reading():
    """The paper's 400 um at 100 m/s with the 600 um glass sphere: H = 0.3375 GPa with the sphere's density
    (2500 kg/m^3), 1.054 GPa with the target's (7810 kg/m^3); eq. 20 and its inverse agree; d grows as sqrt(v)."""
    r = 300e-6
    assert hutchings_pressure(r, 100.0, 2500.0, 400e-6) == pytest.approx(0.3375e9, rel=1e-4)
    assert hutchings_pressure(r, 100.0, 7810.0, 400e-6) == pytest.approx(1.0544e9, rel=1e-3)
    assert hutchings_diameter(r, 100.0, 2500.0, 0.3375e9) == pytest.approx(400e-6, rel=1e-4)
    v = np.array([40.0, 60.0, 80.0, 100.0])
    assert speed_slope(v, [hutchings_diameter(r, s, 2500.0, 2e9) for s in v]) == pytest.approx(0.5, abs=1e-12)
    assert math.isnan(speed_slope([40.0], [1e-4]))


def test_the_rim_is_where_the_ring_means_cross_the_level():
    r = np.linspace(0.0, 10.0, 401)
    value = 1.0 - r / 4.0  # crosses 0 at r = 4
    assert rim_radius(r, value, 0.5, 0.0) == pytest.approx(4.0, abs=0.02)
    assert math.isnan(rim_radius(r, value - 2.0, 0.5, 0.0))  # below the level everywhere
    # a pile-up ring: a parabola peaking at r = 5.3 is found between the ring centres
    assert crest_radius(r, -(r - 5.3) ** 2, 0.5) == pytest.approx(5.3, abs=0.02)
    assert math.isnan(crest_radius(r, -r, 0.5))  # highest on the axis: no crest


def test_the_crater_volume_of_a_spherical_cap():
    """A cap of radius 300 and depth 20 on a disordered cloud of surface points, with a pile-up ring beyond it: the
    ring sums give the cap's pi d^2 (R - d/3) within 1 % and stop where the surface rises back."""
    rng = np.random.default_rng(3)
    xy = rng.uniform(-250.0, 250.0, size=(40000, 2))
    r = np.hypot(xy[:, 0], xy[:, 1])
    radius, depth = 300.0, 20.0
    a = math.sqrt(2.0 * radius * depth - depth**2)
    sink = np.where(r < a, np.sqrt(np.clip(radius**2 - r**2, 0.0, None)) - (radius - depth), 0.0)
    sink -= 3.0 * np.exp(-(((r - a - 15.0) / 10.0) ** 2))  # the rim stands above the start
    expected = math.pi * depth**2 * (radius - depth / 3.0)
    assert crater_volume(r, sink, 2.5) == pytest.approx(expected, rel=0.01)
    assert crater_volume(r, -np.abs(sink), 2.5) == 0.0  # nothing below the start


def test_the_sweep_runs_one_speed_each_and_the_rows():
    case = load_case(CRATER).model
    assert sweep_runs(case, "c") == [(f"c/v_{v:g}", (f"sphere.speed={v!r}",)) for v in (40.0, 60.0, 80.0, 100.0)]
    run = {"attrs": {}, "measured": {"attrs": {"crater_diameter": 2.1e-4, "hutchings_diameter": 2.0e-4,
                                               "mean_pressure": 3e9, "energy_balance": -0.03}}}
    rows, picture = check_run(case, "sph", run)
    assert rows[0]["rel_error"] == pytest.approx(0.05) and rows[0]["passed"]
    assert rows[1]["rel_error"] == pytest.approx(0.03) and not rows[1]["passed"]
    assert picture["speed"] == 100.0
    rows, _ = check_run(case, "sph", {"attrs": {}})
    assert [row["passed"] for row in rows] == [False, False]


def test_mass_properties_of_a_clump():
    """Two spheres of radius 1 whose centres are 1 apart: the union's volume 4 pi - 5 pi / 12 (two caps of height
    1/2 overlap), its centre midway, its inertia about the line of centres against the integral of the slices."""
    spheres = np.array([[-0.5, 0.0, 0.0, 1.0], [0.5, 0.0, 0.0, 1.0]])
    mass, centre, inertia = mass_properties(spheres, 1.0, cells=96)
    volume = 8.0 / 3.0 * math.pi - 5.0 / 12.0 * math.pi
    assert mass == pytest.approx(volume, rel=2e-3)
    np.testing.assert_allclose(centre, 0.0, atol=1e-12)
    # about x: sum of discs, (pi/2) int rho(x)^4 dx, rho^2 = 1 - (|x| - 1/2)^2 for |x| <= 3/2 outside the overlap
    x = np.linspace(-1.5, 1.5, 200001)
    rho2 = np.clip(1.0 - (np.abs(x) - 0.5) ** 2, 0.0, None)
    assert inertia[0, 0] == pytest.approx(np.trapezoid(0.5 * math.pi * rho2**2, x), rel=3e-3)
    assert inertia[0, 1] == pytest.approx(0.0, abs=1e-9) and inertia[1, 1] == pytest.approx(inertia[2, 2], rel=1e-9)
    one = mass_properties(spheres[:1], 2.0)
    assert one[0] == pytest.approx(2.0 * 4.0 / 3.0 * math.pi) and one[2][0, 0] == pytest.approx(0.4 * one[0])


@pytest.mark.sph
def test_the_quick_crater_follows_hutchings(tmp_path, capsys):
    """27 um spacing at 100 m/s against eq. 20 at the run's own mean contact pressure (227 um at 3.2 GPa): the
    contact chord within 5 % (measured 223 um), the rim crest within 15 % (256 um: the pile-up is smeared over a
    kernel at this spacing; +6.8 % at the case's 15 um), energy within 2 %, a rebound."""
    code = main(["run", str(CRATER), "--preset", "quick", "--out", str(tmp_path / "c")])
    assert code == 0
    from orchestrator.runh5 import read_run

    m = read_run(tmp_path / "c")["measured"]["attrs"]
    assert m["contact_diameter"] == pytest.approx(m["hutchings_diameter"], rel=0.05)
    assert m["crater_diameter"] == pytest.approx(m["hutchings_diameter"], rel=0.15)
    assert abs(m["energy_balance"]) < 0.02
    assert 2e9 < m["mean_pressure"] < 5e9 and 0.0 < m["restitution"] < 0.6
    assert m["plastic_zone_diameter"] > m["crater_diameter"] > m["indentation_diameter"] > 0.0
    # eq. 20 at Hutchings' dynamic hardness (kinetic energy over the crater's volume) is the volume's cap
    assert m["volume_diameter"] == pytest.approx(hutchings_diameter(3e-4, 100.0, 2500.0, m["dynamic_hardness"]),
                                                 rel=1e-9)
    assert 0.6 < m["volume_diameter"] / m["contact_diameter"] < 1.0
    assert main(["analyze", str(tmp_path / "c")]) == 0
    out = capsys.readouterr().out
    assert "H = 0.3375 GPa with the sphere's density" in out and (tmp_path / "c" / "crater.png").is_file()


def test_the_bonded_layer_factor_of_dimitriadis_et_al():
    # nu = 1/2: their 1 + 1.133 chi + 1.283 chi^2 + 0.769 chi^3 + 0.0975 chi^4; 1 for a half-space
    chi = np.linspace(0.0, 1.0, 11)
    published = 1 + 1.133 * chi + 1.283 * chi**2 + 0.769 * chi**3 + 0.0975 * chi**4
    np.testing.assert_allclose(bonded_layer_factor(chi, 0.5), published, rtol=2e-4)
    assert bonded_layer_factor(0.0, 0.3) == 1.0 and 1.08 < bonded_layer_factor(0.0884, 0.3) < 1.09
    # a force of Hertz's times the factor fits E* exactly; without the factor the fit is stiffer
    r, e_star, depth = 4e-3, 2.857e6, 8e-3
    delta = np.linspace(0.0, 1.5e-4, 60)
    force = 4.0 / 3.0 * e_star * np.sqrt(r) * delta**1.5 * bonded_layer_factor(np.sqrt(r * delta) / depth, 0.3)
    fit = hertz_fit(r, delta, force, (depth, 0.3))
    assert fit["hertz_modulus"] == pytest.approx(e_star, rel=1e-9) and fit["hertz_modulus_half_space"] > 1.08 * e_star


def test_hertz_fit_recovers_the_contact_modulus():
    """Hertz's F = 4/3 E* sqrt(r) (delta - delta0)^(3/2) with the surface 0.3 dx off: the fit gives E* back; the
    target's E / (1 - nu^2) from G and K (G 1 MPa, K 2.16667 MPa: E 2.6 MPa, nu 0.3)."""
    r, e_star, offset = 4e-3, 2.857e6, 3e-5
    delta = np.linspace(-2e-5, 1.5e-4, 300)
    force = 4.0 / 3.0 * e_star * math.sqrt(r) * np.clip(delta - offset, 0.0, None) ** 1.5
    fit = hertz_fit(r, delta, force)
    assert fit["hertz_modulus"] == pytest.approx(e_star, rel=1e-9) and fit["hertz_fit_residual"] < 1e-9
    assert hertz_fit(r, delta, np.zeros_like(delta)) == {}
    case = load_case(HERTZ).model
    assert contact_modulus(case) == pytest.approx(2.6e6 / (1 - 0.09), rel=1e-5)


def test_a_hertz_row_needs_an_elastic_indenter():
    with pytest.raises(CaseError, match="hertz_modulus needs sphere.kinematic = true"):
        load_case(HERTZ, overrides=["sphere.kinematic=false", "target.size=[9e-3, 9e-3, 4e-3]"])


@pytest.mark.sph
def test_the_quick_indenter_follows_hertz(tmp_path):
    """A 10 x 10 x 8 mm block at 0.25 mm (the contact radius reaches 2.8 dx) with the corrected momentum sum: E*
    fitted to F(delta) over Hertz's bonded-layer factor within 8 % of E / (1 - nu^2) (measured -5.5 %; -1.9 % in the
    case's 15 x 15 x 8 mm block at 0.2 mm; the plain sum: -12.7 % here); the half-space fit above it, within 5 %
    (+2.9 %: the glued support's stiffening)."""
    assert main(["run", str(HERTZ), "--preset", "quick", "--out", str(tmp_path / "h")]) == 0
    from orchestrator.runh5 import read_run

    m = read_run(tmp_path / "h")["measured"]["attrs"]
    assert m["hertz_modulus"] == pytest.approx(m["elastic_modulus"], rel=0.08)
    assert m["hertz_modulus"] < m["hertz_modulus_half_space"] < 1.05 * m["elastic_modulus"]
    assert m["max_penetration"] == pytest.approx(1.125e-4, rel=0.02) and m["hertz_fit_residual"] < 0.04
