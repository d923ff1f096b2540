"""Parametric geometry of the ejector deep-hole drill of Canini et al.: watertight trimesh solids of the
workpiece with its bore, the outer and inner tubes with the annular gap d_Diff between them, the drill head with its
chip mouth and the groove that carries the gap to the radial adduction holes, and the passages (adduction holes,
ejector nozzles) as separate solids. SI units (m); the drill axis is z, z = 0 the head's front face, the tubes run
towards +z (to the feed and the chuck).

Every diameter, count and length the 1D network has comes from reference.drill_network.DrillNetwork (the single
source; its comments say which the paper gives and which are reconstructions); the few lengths only the geometry
needs are DrillGeometry's own fields, each with its reasoning. Solids of revolution are revolved (r, z) polygons of
`sections` sides, so each volume is the polygon's Pappus volume times N sin(2 pi / N) / (2 pi) (tests compare with
the closed forms). A part can be replaced by a user's mesh file (STL, OBJ, PLY), scaled to metres.

The passages are solids of their own: a scene cuts them from the walls' meshes (manifold3d's booleans) or leaves
their lattice sites out of the boundary particles in closed form. Neighbouring passages round the axis must not
overlap (passage_spacing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from orchestrator.reference.drill_network import DrillNetwork


@dataclass(frozen=True)
class DrillGeometry:
    """The drill's geometry, m. `network` gives the diameters, counts and lengths of the 1D model."""

    network: DrillNetwork = field(default_factory=DrillNetwork)
    # reconstruction: the head reaches over the tube joint; 8 mm of it is the groove that carries the annular gap
    # to the holes (twice the hole diameter, so a hole fits in the groove with 2 mm to spare)
    groove_length: float = 8.0e-3
    # the groove's radial depth beyond the gap's outer radius: a collector chamber cut into the head around the
    # holes' entrances, from the groove's floor up to the holes' upper edge (the head's material above it keeps
    # the chamber off the tube/bore clearance behind the head's rear face: a chamber up to that face, as deep as
    # the outer tube's wall, met the clearance in a corner of no thickness). 0 keeps the groove the gap's own
    # 0.5 mm, from which the Ø4 mm holes must be fed through a 0.5 mm sheet round their rims
    groove_depth: float = 0.0
    # reconstruction: the chip space ahead of the face as one uniform gap to the bore bottom; 2 mm gives the chip
    # mouth's edge (r = 6 mm) the network's front_area, ~80 mm^2 (the cutting edges' 0.5 mm gave 19 mm^2: 81 m/s)
    front_clearance: float = 2.0e-3
    # reconstruction: the ejector nozzles point rearward, 30 degrees off the tube's cross-section (Fig. 1C)
    nozzle_angle_deg: float = 30.0
    # workpiece around the bore: 10 mm of wall and 10 mm of floor ahead of the bore bottom (enough for boundary
    # particles: several kernel supports at the paper's dx = 0.3-0.4 mm)
    workpiece_wall: float = 10.0e-3
    sections: int = 96  # sides of the revolved polygons: 0.07 % volume deficit, 30 mm circle within 8 um

    def __post_init__(self):
        n = self.network
        radii = [n.d_chip_mouth / 2, n.d_inner_tube_id / 2, n.d_inner_tube_od / 2, n.d_outer_tube_id / 2,
                 n.d_outer_tube_od / 2, n.d_head_body / 2, n.d_bore / 2]
        names = ["d_chip_mouth", "d_inner_tube_id", "d_inner_tube_od", "d_outer_tube_id", "d_outer_tube_od",
                 "d_head_body", "d_bore"]
        for k in range(1, len(radii)):
            if not radii[k] > radii[k - 1] and names[k] != "d_outer_tube_od":
                raise ValueError(f"{names[k]} = {2 * radii[k] * 1e3:g} mm must exceed {names[k - 1]} = "
                                 f"{2 * radii[k - 1] * 1e3:g} mm (the parts nest from the axis outwards)")
        if n.d_hole >= self.groove_length:
            raise ValueError(f"d_hole = {n.d_hole * 1e3:g} mm does not fit in groove_length = "
                             f"{self.groove_length * 1e3:g} mm")
        if not 0.0 <= self.groove_depth <= (n.d_outer_tube_od - n.d_outer_tube_id) / 2:
            raise ValueError(f"groove_depth = {self.groove_depth * 1e3:g} mm must lie between 0 and the outer tube's "
                             f"wall, {(n.d_outer_tube_od - n.d_outer_tube_id) / 2 * 1e3:g} mm (the chamber stays "
                             "inside the head, below the tube's end)")
        if n.head_rear_length <= self.groove_length:
            raise ValueError("head_rear_length must exceed groove_length (the head's solid front)")
        if self.sections < 8:
            raise ValueError(f"sections = {self.sections} is too coarse; allowed: >= 8")
        self._check_passage_spacing()

    def _check_passage_spacing(self) -> None:
        """ValueError naming the count when neighbouring adduction holes (from the groove's outer wall out) or
        ejector nozzles (from the inner tube's bore out) overlap where they leave the wall nearest the axis."""
        n = self.network
        for count, d, key, r, tilt, what in (
                ("n_holes", n.d_hole, "d_hole", self.groove_outer_radius, 0.0,
                 "adduction holes overlap where they leave the groove's outer wall"),
                ("n_ejector_nozzles", n.d_ejector_nozzle, "d_ejector_nozzle", n.d_inner_tube_id / 2,
                 math.radians(self.nozzle_angle_deg),
                 "ejector nozzles overlap where they leave the inner tube's bore")):
            number = getattr(n, count)
            if number < 2 or d <= widest_passage(number, r, tilt) * (1 + 1e-12):
                continue
            raise ValueError(f"{count} = {number}: {key} = {d * 1e3:g} mm {what} (r = {r * 1e3:g} mm); allowed: "
                             f"{count} <= {most_passages(d, r, tilt)} for this {key}, or {key} <= "
                             f"{widest_passage(number, r, tilt) * 1e3:.4g} mm for {number}")

    # ------------------------------------------------------------------------------------------- profiles
    @property
    def head_length(self) -> float:
        """Head length from the front face to the tube joint, m (DrillNetwork.head_rear_length)."""
        return self.network.head_rear_length

    @property
    def groove_start(self) -> float:
        """z where the groove (the annular gap inside the head) begins, m."""
        return self.head_length - self.groove_length

    @property
    def groove_outer_radius(self) -> float:
        """The groove's outer radius, m: the outer tube's ID plus groove_depth."""
        return self.network.d_outer_tube_id / 2 + self.groove_depth

    @property
    def collector_top(self) -> float:
        """z of the collector chamber's top (groove_depth > 0): the holes' upper edge, m."""
        return self.hole_z + 0.5 * self.network.d_hole

    @property
    def hole_z(self) -> float:
        """z of the adduction holes' axes: the middle of the groove, m."""
        return self.groove_start + 0.5 * self.groove_length

    def profiles(self) -> dict[str, list[tuple[float, float]]]:
        """The (r, z) polygons of the solids of revolution, m, each closed (last point = first)."""
        n, L = self.network, self.head_length
        r_m, r_ii, r_io = n.d_chip_mouth / 2, n.d_inner_tube_id / 2, n.d_inner_tube_od / 2
        r_oi, r_oo, r_h, r_b = n.d_outer_tube_id / 2, n.d_outer_tube_od / 2, n.d_head_body / 2, n.d_bore / 2
        z_g, z_feed = self.groove_start, L + n.tube_length
        inner_end = z_feed + n.mixing_length + n.discharge_length  # the inner tube runs on to the chip outlet
        c, w = self.front_clearance, self.workpiece_wall
        r_g, z_c = self.groove_outer_radius, self.collector_top
        chamber = [(r_oi, z_c), (r_g, z_c)] if self.groove_depth > 0 else []
        head = [(r_m, 0.0), (r_h, 0.0), (r_h, L), (r_oi, L), *chamber, (r_g, z_g), (r_io, z_g), (r_io, L), (r_m, L)]
        return {
            "workpiece": [(0.0, -c - w), (r_b + w, -c - w), (r_b + w, n.bore_depth), (r_b, n.bore_depth),
                          (r_b, -c), (0.0, -c)],
            "head": head,
            "outer_tube": [(r_oi, L), (r_oo, L), (r_oo, z_feed), (r_oi, z_feed)],
            "inner_tube": [(r_ii, L), (r_io, L), (r_io, inner_end), (r_ii, inner_end)],
        }

    # ------------------------------------------------------------------------------------------- meshes
    def meshes(self, user_files: dict[str, tuple[Path, float]] | None = None) -> dict:
        """name -> trimesh.Trimesh of every part: the solids of revolution, 'adduction_holes' and
        'ejector_nozzles'; user_files: name -> (mesh file, scale to metres) replaces a part."""
        import trimesh

        out = {}
        for name, polygon in self.profiles().items():
            ring = np.asarray(polygon + [polygon[0]], dtype=float)
            mesh = trimesh.creation.revolve(ring, sections=self.sections)
            if mesh.volume < 0:
                mesh.invert()
            out[name] = mesh
        out["adduction_holes"] = trimesh.util.concatenate(self._passages(*self._hole_layout()))
        out["ejector_nozzles"] = trimesh.util.concatenate(self._passages(*self._nozzle_layout()))
        for name, (path, scale) in (user_files or {}).items():
            if name not in out:
                raise ValueError(f"user mesh for {name!r}: no such part; parts: {', '.join(sorted(out))}")
            mesh = trimesh.load(path, force="mesh")
            mesh.apply_scale(scale)
            if not mesh.is_watertight:
                raise ValueError(f"user mesh {path} for {name!r} is not watertight (a closed solid is needed)")
            out[name] = mesh
        return out

    def _hole_layout(self):
        n = self.network
        starts, ends = [], []
        for k in range(n.n_holes):
            a = 2 * math.pi * k / n.n_holes
            e = np.array([math.cos(a), math.sin(a), 0.0])
            # from the groove's inner wall (inner tube OD) out through the head body
            starts.append(e * n.d_inner_tube_od / 2 + [0, 0, self.hole_z])
            ends.append(e * n.d_head_body / 2 + [0, 0, self.hole_z])
        return starts, ends, n.d_hole

    def _nozzle_layout(self):
        n = self.network
        z = self.head_length + n.tube_length
        tilt = math.radians(self.nozzle_angle_deg)
        starts, ends = [], []
        for k in range(n.n_ejector_nozzles):
            a = 2 * math.pi * k / n.n_ejector_nozzles
            e = np.array([math.cos(a), math.sin(a), 0.0])
            # through the inner tube's wall, inwards and rearwards (+z)
            outer = e * n.d_inner_tube_od / 2 + [0, 0, z]
            inner = e * n.d_inner_tube_id / 2 + [0, 0, z + (n.d_inner_tube_od - n.d_inner_tube_id) / 2 *
                                                  math.tan(tilt)]
            starts.append(outer), ends.append(inner)
        return starts, ends, n.d_ejector_nozzle

    def _passages(self, starts, ends, diameter):
        import trimesh

        return [trimesh.creation.cylinder(radius=diameter / 2, segment=[s, e], sections=max(16, self.sections // 4))
                for s, e in zip(starts, ends)]

    def summary(self) -> dict[str, float]:
        """The drill's dimensions, m (and counts), for tables: every field of the network the geometry uses."""
        n = self.network
        keys = ["d_bore", "d_outer_tube_od", "d_outer_tube_id", "d_diff", "d_inner_tube_id", "d_chip_mouth",
                "d_head_body", "d_hole", "n_holes", "d_ejector_nozzle", "n_ejector_nozzles", "tube_length",
                "head_rear_length", "bore_depth", "mixing_length", "discharge_length"]
        out = {k: float(getattr(n, k)) for k in keys}
        out["d_inner_tube_od"] = float(n.d_inner_tube_od)
        out.update({f.name: float(getattr(self, f.name)) for f in fields(self) if f.name != "network"})
        return out


def _axes_angle(count: int, tilt: float) -> float:
    """Angle (rad) between the axes of two neighbouring passages of `count` round the axis, each tilted `tilt` (rad)
    out of the cross-section: both axes meet on the drill axis, cos = cos^2(tilt) cos(2 pi / count) + sin^2(tilt)."""
    cos = math.cos(tilt) ** 2 * math.cos(2 * math.pi / count) + math.sin(tilt) ** 2
    return math.acos(min(1.0, max(-1.0, cos)))


def widest_passage(count: int, r: float, tilt: float = 0.0) -> float:
    """Largest diameter (m) of `count` cylindrical passages round the axis, starting at radius r (m) and tilted `tilt`
    (rad) out of the cross-section, for which neighbours do not overlap: their axes meet at the angle phi
    (_axes_angle) a distance r / cos(tilt) before the wall, so the cylinders stay apart while d / 2 <= r / cos(tilt)
    tan(phi / 2)."""
    return 2.0 * r / math.cos(tilt) * math.tan(0.5 * _axes_angle(count, tilt))


def most_passages(d: float, r: float, tilt: float = 0.0) -> int:
    """Largest count of passages of diameter d (m) round the axis from radius r (m), tilted `tilt` (rad), that do not
    overlap (widest_passage inverted; at least 1)."""
    phi = 2.0 * math.atan(0.5 * d * math.cos(tilt) / r)
    cos = (math.cos(phi) - math.sin(tilt) ** 2) / math.cos(tilt) ** 2
    if cos <= -1.0:
        return 1
    count = max(1, math.floor(2 * math.pi / math.acos(min(1.0, cos)) + 1e-9)) if cos < 1.0 else 1
    while count > 1 and widest_passage(count, r, tilt) < d:
        count -= 1
    return count
