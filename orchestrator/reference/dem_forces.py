"""Contact forces of the reference DEM: the law of orchestrator.reference.contact
applied to every contact of a step at once, with the tangential history
carried from step to step and a record of each contact's life (start, end,
peak force). SI units.

Conventions per contact: the normal n points from the sphere (body 1) to the
other body; the branch from the sphere's centre to the contact point is
(R - delta/2) n, as in Yade (the middle of the overlap). A wall (plane or
triangle) is immovable or translates at a set velocity, has infinite mass
and infinite radius (faces, edges and vertices alike), so R_eq = R_sphere
and m_eq = m_sphere; its Young's modulus and Poisson ratio enter E_eq
(eq. 3) and k_t (eq. 5) like a sphere's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from orchestrator.reference import contact

#: Columns of the contact-event table (one row per contact from first touch to separation) and their units:
#: the reference DEM's life record, and Result.events / run.h5 /events of every engine's impact runs
#: (definitions: orchestrator.kinds.impact.analysis).
EVENT_FIELDS: dict[str, str] = {
    "sphere": "-", "other_kind": "-", "other": "-", "start_time": "s", "end_time": "s", "impact_speed": "m/s",
    "rebound_speed": "m/s", "peak_normal_force": "N", "peak_time": "s", "max_overlap": "m",
}
KIND_SPHERE, KIND_PLANE, KIND_TRIANGLE = 0, 1, 2


@dataclass(frozen=True)
class PairLaw:
    """Per material pair (M, M) tables: E_eq (Pa), k_t0 / sqrt(R_eq) (Pa), alpha (-), mu (-)."""

    effective_young: np.ndarray
    tangential_factor: np.ndarray
    alpha: np.ndarray
    friction: np.ndarray


@dataclass
class StepContacts:
    """All contacts of one step, sorted by key (sphere * n_targets + target)."""

    key: np.ndarray
    sphere: np.ndarray
    partner: np.ndarray  # other sphere, or -1
    wall: np.ndarray  # wall index, or -1
    kind: np.ndarray
    other: np.ndarray  # index within its kind
    other_material: np.ndarray
    normal: np.ndarray
    overlap: np.ndarray


def _cross(a, b):
    """Row-wise cross product of (n,3) arrays (np.cross is slow on small arrays)."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    out[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    out[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return out


def _scatter(index, values, length):
    """Sum rows of values (n,3) into (length,3) at index."""
    out = np.zeros((length, 3))
    for axis in range(3):
        out[:, axis] = np.bincount(index, weights=values[:, axis], minlength=length)
    return out


class ContactLaw:
    """Forces from contacts, with the tangential elastic force and the life record of each contact."""

    def __init__(self, law: PairLaw, radii, masses, sphere_material, n_walls, no_tension=True,
                 coulomb_limit="total"):
        self.law, self.radii, self.masses = law, radii, masses
        self.sphere_material, self.n_walls = sphere_material, n_walls
        self.no_tension, self.coulomb_limit = no_tension, coulomb_limit
        self.keys = np.zeros(0, np.int64)
        self.elastic = np.zeros((0, 3))
        self.life = {name: np.zeros(0) for name in EVENT_FIELDS}
        self.last = {"time": np.zeros(0), "overlap": np.zeros(0), "rate": np.zeros(0)}
        self.closed: list[dict] = []
        self._new = np.zeros(0, bool)  # which contacts of the current step are new

    @property
    def active_count(self) -> int:
        return len(self.keys)

    def forces(self, batch: StepContacts, velocities, spins, wall_velocities, time, dt):
        """Force (N,3) and torque (N,3) on each sphere, N and N m, and force (W,3) on each wall, N.

        velocities, spins: (N,3), m/s and rad/s, at the middle of the step
        (they give the tangential increment and the dash-pot); wall_velocities:
        (W,3), m/s; time: end of the step, s; dt: step, s.
        """
        n_spheres = len(self.radii)
        i, j, n, delta = batch.sphere, batch.partner, batch.normal, batch.overlap
        has_partner = j >= 0
        jj = np.where(has_partner, j, 0)
        mat_i = self.sphere_material[i]
        radius_other = np.where(has_partner, self.radii[jj], np.inf)
        mass_other = np.where(has_partner, self.masses[jj], np.inf)
        r_eq = contact.effective_radius(self.radii[i], radius_other)
        m_eq = contact.effective_mass(self.masses[i], mass_other)
        k_n = contact.hertz_stiffness(self.law.effective_young[mat_i, batch.other_material], r_eq)
        k_t0 = self.law.tangential_factor[mat_i, batch.other_material] * np.sqrt(r_eq)
        alpha = self.law.alpha[mat_i, batch.other_material]
        friction = self.law.friction[mat_i, batch.other_material]

        arm_i = (self.radii[i] - delta / 2.0)[:, None] * n
        arm_other = -(np.where(has_partner, self.radii[jj], 0.0) - delta / 2.0)[:, None] * n
        point_velocity_other = np.zeros((len(i), 3))
        point_velocity_other[has_partner] = velocities[j[has_partner]] + _cross(spins[j[has_partner]],
                                                                                arm_other[has_partner])
        point_velocity_other[~has_partner] = wall_velocities[batch.wall[~has_partner]]
        relative = point_velocity_other - (velocities[i] + _cross(spins[i], arm_i))
        normal_speed = np.einsum("ij,ij->i", relative, n)
        approach_rate = -normal_speed
        tangential_velocity = relative - normal_speed[:, None] * n

        f_n = contact.normal_force(delta, approach_rate, k_n, m_eq, alpha, self.no_tension)
        previous = self._carry_history(batch, time)
        elastic, f_t, _ = contact.tangential_force_update(
            previous, tangential_velocity, dt, contact.mindlin_tangential_stiffness(k_t0, delta),
            contact.damping_coefficient(alpha, m_eq, k_n, delta), f_n, friction, self.coulomb_limit)
        self.elastic = elastic
        self._update_life(time, f_n, delta, approach_rate)

        on_sphere = -f_n[:, None] * n + f_t
        force = _scatter(i, on_sphere, n_spheres) - _scatter(j[has_partner], on_sphere[has_partner], n_spheres)
        torque = _scatter(i, _cross(arm_i, on_sphere), n_spheres) + _scatter(
            j[has_partner], _cross(arm_other[has_partner], -on_sphere[has_partner]), n_spheres)
        on_wall = ~has_partner
        wall_force = _scatter(batch.wall[on_wall], -on_sphere[on_wall], self.n_walls)
        return force, torque, wall_force

    def _carry_history(self, batch: StepContacts, time):
        """Elastic tangential force of the contacts that existed last step, turned into
        the current tangent plane (projected, magnitude kept); zero for new ones.
        Contacts that ended are closed in the life record."""
        found = np.zeros(len(batch.key), bool)
        position = np.zeros(len(batch.key), int)
        if len(self.keys):
            position = np.minimum(np.searchsorted(self.keys, batch.key), len(self.keys) - 1)
            found = self.keys[position] == batch.key
        previous = np.zeros((len(batch.key), 3))
        if found.any():
            old = self.elastic[position[found]]
            n = batch.normal[found]
            turned = old - np.einsum("ij,ij->i", old, n)[:, None] * n
            size_old, size_new = np.linalg.norm(old, axis=1), np.linalg.norm(turned, axis=1)
            stretch = np.where(size_new > 0, size_old / np.where(size_new > 0, size_new, 1.0), 0.0)
            previous[found] = turned * stretch[:, None]
        ended = ~np.isin(self.keys, batch.key, assume_unique=True)
        self._close(ended)
        kept = {name: values[position[found]] for name, values in self.life.items()}
        kept_last = {name: values[position[found]] for name, values in self.last.items()}
        count = len(batch.key)
        self.life = {name: np.full(count, np.nan) for name in EVENT_FIELDS}
        self.last = {name: np.full(count, np.nan) for name in self.last}
        for name in EVENT_FIELDS:
            self.life[name][found] = kept[name]
        for name in self.last:
            self.last[name][found] = kept_last[name]
        new = ~found
        for name, values in (("sphere", batch.sphere), ("other_kind", batch.kind), ("other", batch.other)):
            self.life[name][new] = values[new]
        self.life["peak_normal_force"][new] = -np.inf
        self.life["max_overlap"][new] = 0.0
        self._new = new
        self.keys = batch.key
        return previous

    def _update_life(self, time, f_n, overlap, approach_rate):
        new = self._new
        rate = np.where(approach_rate[new] > 0.0, approach_rate[new], np.inf)
        self.life["start_time"][new] = time - overlap[new] / rate
        self.life["impact_speed"][new] = approach_rate[new]
        higher = f_n > self.life["peak_normal_force"]
        self.life["peak_normal_force"] = np.where(higher, f_n, self.life["peak_normal_force"])
        self.life["peak_time"] = np.where(higher, time, self.life["peak_time"])
        self.life["max_overlap"] = np.maximum(self.life["max_overlap"], overlap)
        self.last = {"time": np.full(len(f_n), time), "overlap": overlap, "rate": approach_rate}

    def _close(self, ended):
        if not ended.any():
            return
        record = {name: values[ended] for name, values in self.life.items()}
        separating = -self.last["rate"][ended]
        record["end_time"] = self.last["time"][ended] + np.where(
            separating > 0, self.last["overlap"][ended] / np.where(separating > 0, separating, 1.0), 0.0)
        record["rebound_speed"] = separating
        self.closed.append(record)

    def events(self) -> dict:
        """The life record of every contact, closed ones first, then those still open (end_time nan)."""
        open_now = {name: values.copy() for name, values in self.life.items()}
        open_now["end_time"] = np.full(len(self.keys), np.nan)
        open_now["rebound_speed"] = np.full(len(self.keys), np.nan)
        parts = self.closed + [open_now]
        out = {name: np.concatenate([p[name] for p in parts]) for name in EVENT_FIELDS}
        for name in ("sphere", "other_kind", "other"):
            out[name] = out[name].astype(np.int64)
        order = np.argsort(out["start_time"], kind="stable")
        return {name: values[order] for name, values in out.items()}
