"""The ejector drill's parametric geometry: every part a closed solid whose volume is its closed form, dimensions
from the 1D network (the single source), nesting checked, user meshes accepted or refused by name."""

import math

import numpy as np
import pytest

from orchestrator.drill.geometry import DrillGeometry
from orchestrator.reference.drill_network import DrillNetwork


def _ngon(n):
    """Volume factor of a solid of revolution made of an n-gon: n sin(2 pi / n) / (2 pi)."""
    return n * math.sin(2 * math.pi / n) / (2 * math.pi)


def _ring(r_in, r_out, length):
    return math.pi * (r_out**2 - r_in**2) * length


def test_parts_are_watertight_with_closed_form_volumes():
    g = DrillGeometry()
    n = g.network
    meshes = g.meshes()
    assert set(meshes) == {"workpiece", "head", "outer_tube", "inner_tube", "adduction_holes", "ejector_nozzles"}
    for name, mesh in meshes.items():
        assert mesh.is_watertight and mesh.volume > 0, name
    L, z_feed = n.head_rear_length, n.head_rear_length + n.tube_length
    inner_end = z_feed + n.mixing_length + n.discharge_length
    exact = {
        "outer_tube": _ring(n.d_outer_tube_id / 2, n.d_outer_tube_od / 2, n.tube_length),
        "inner_tube": _ring(n.d_inner_tube_id / 2, n.d_inner_tube_od / 2, inner_end - L),
        # the head: the body from the chip mouth out, minus the groove (the annular gap inside it)
        "head": _ring(n.d_chip_mouth / 2, n.d_head_body / 2, L)
        - _ring(n.d_inner_tube_od / 2, n.d_outer_tube_id / 2, g.groove_length),
        # the workpiece: a cylinder of radius r_b + w from the floor to the bore's mouth, minus the bore
        "workpiece": _ring(0.0, n.d_bore / 2 + g.workpiece_wall, n.bore_depth + g.front_clearance + g.workpiece_wall)
        - _ring(0.0, n.d_bore / 2, n.bore_depth + g.front_clearance),
    }
    for name, volume in exact.items():
        assert meshes[name].volume == pytest.approx(volume * _ngon(g.sections), rel=1e-9), name
        assert meshes[name].volume == pytest.approx(volume, rel=1e-3), name  # 96 sides: within 0.07 %
    # passages: n cylinders of the hole (nozzle) diameter through the wall they cross
    k = max(16, g.sections // 4)
    hole_len = (n.d_head_body - n.d_inner_tube_od) / 2
    assert meshes["adduction_holes"].volume == pytest.approx(
        n.n_holes * math.pi * (n.d_hole / 2) ** 2 * hole_len * _ngon(k), rel=1e-9)
    wall = (n.d_inner_tube_od - n.d_inner_tube_id) / 2
    nozzle_len = wall / math.cos(math.radians(g.nozzle_angle_deg))
    assert meshes["ejector_nozzles"].volume == pytest.approx(
        n.n_ejector_nozzles * math.pi * (n.d_ejector_nozzle / 2) ** 2 * nozzle_len * _ngon(k), rel=1e-9)


def test_a_deep_groove_is_a_collector_chamber():
    """groove_depth cuts a chamber round the holes' entrances: the head loses the ring r_oi..r_oi + depth from the
    groove's floor to the holes' upper edge (closed form), and at least 2 mm of head stays between the chamber and
    the head's rear face (behind which lies the tube/bore clearance); deeper than the tube's wall is refused."""
    from orchestrator.drill.geometry import DrillGeometry as G

    flat, deep = G(), G(groove_depth=2.0e-3)
    n = flat.network
    r_oi = n.d_outer_tube_id / 2
    height = deep.hole_z + 0.5 * n.d_hole - deep.groove_start
    assert flat.meshes()["head"].volume - deep.meshes()["head"].volume == pytest.approx(
        _ring(r_oi, r_oi + 2.0e-3, height) * _ngon(flat.sections), rel=1e-9)
    assert deep.collector_top == pytest.approx(deep.head_length - 2.0e-3)
    assert deep.groove_outer_radius == pytest.approx(r_oi + 2.0e-3)
    with pytest.raises(ValueError, match="groove_depth"):
        G(groove_depth=2.5e-3)


def test_the_gaps_are_the_networks():
    g = DrillGeometry()
    n = g.network
    meshes = g.meshes()
    r = lambda m: np.hypot(m.vertices[:, 0], m.vertices[:, 1])
    # annular gap between the tubes: d_Diff / 2 = 0.5 mm radial (the paper's d_Diff = 1 mm, diametral)
    gap = r(meshes["outer_tube"]).min() - r(meshes["inner_tube"]).max()
    assert gap == pytest.approx(n.d_diff / 2, rel=1e-9)
    # the bore: 30 mm; clearance of the head to the bore wall (d_bore - d_head_body) / 2 = 0.4 mm
    assert 2 * r(meshes["workpiece"])[meshes["workpiece"].vertices[:, 2] > 0].min() == pytest.approx(30e-3, abs=1e-9)
    assert (n.d_bore - 2 * r(meshes["head"]).max()) / 2 == pytest.approx(0.4e-3, rel=1e-9)


def test_bad_dimensions_and_user_meshes_are_named(tmp_path):
    with pytest.raises(ValueError, match="d_inner_tube_id = 21 mm must exceed d_chip_mouth"):
        DrillGeometry(network=DrillNetwork(d_inner_tube_id=21e-3, d_chip_mouth=22e-3))
    with pytest.raises(ValueError, match="d_hole = 9 mm does not fit"):
        DrillGeometry(network=DrillNetwork(d_hole=9e-3))
    import trimesh

    box = trimesh.creation.box(extents=(10.0, 10.0, 10.0))  # mm
    box.export(tmp_path / "head.stl")
    meshes = DrillGeometry().meshes({"head": (tmp_path / "head.stl", 1e-3)})
    assert meshes["head"].volume == pytest.approx(1e-6, rel=1e-9)
    with pytest.raises(ValueError, match="no such part"):
        DrillGeometry().meshes({"chuck": (tmp_path / "head.stl", 1e-3)})
    open_mesh = trimesh.Trimesh(box.vertices, box.faces[:-2])
    open_mesh.export(tmp_path / "open.stl")
    with pytest.raises(ValueError, match="not watertight"):
        DrillGeometry().meshes({"inner_tube": (tmp_path / "open.stl", 1e-3)})
