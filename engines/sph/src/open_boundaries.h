// Velocity inlets and outlets (open boundaries) made of buffer particles.
//
// Inlet: `layers` layers of inlet particles on a lattice of spacing dx sit
// behind the patch (opposite its normal) and move at the inlet velocity
// along the normal. They carry density and pressure like boundary particles.
// One that crosses the patch becomes fluid, and a new inlet particle takes
// its lateral place `layers` dx upstream, so the buffer stays full.
// Outlet: a fluid particle crossing the patch becomes an outlet particle that
// keeps its density and the normal part of its velocity (so the fluid
// upstream still sees full neighbourhoods) and is removed `layers` dx downstream.
// An outlet with `backflow` (a pressure opening; it needs a held pressure)
// lets its buffer move inward too, at the fluid's normal speed before the
// patch: a buffer particle that crosses the patch inward becomes fluid at the
// held pressure, and a new buffer particle takes its lateral place `layers` dx
// downstream, so fluid enters wherever the fluid inside draws it (a jet's
// entrainment, a suction) instead of leaving voids.
// The volume converted at each patch gives the inflow and outflow rates (an
// opening's backflow counts as negative outflow).
//
// Options (parameters.h InletSpec, OutletSpec), after the buffer inlets and
// outlets of Lastiwka et al. 2009 and Tafuni et al. 2018 (velocity imposed at
// the inlet, pressure at the outlet): the inlet's profile, extrapolated
// pressure and ramp (inlet_buffer.h, eqs. OB1-OB4), the outlet's held
// pressure and backflow (outlet_buffer.h).
//
// List-keeping updates (deck open_boundary_list = "kept", the default): a
// conversion changes a particle's kind only, and Simulation::kinds_changed
// re-sorts its entries in the Verlet list, which then holds; the particles an
// inlet adds and those leaving an outlet's buffer wait for the next build (at
// an output, or when the list is about to be rebuilt anyway: flush). That is
// exact, the fluid sees the same particles, where nothing reads a buffer
// particle's neighbours: every inlet extrapolated (its buffer's density is
// set from the fluid ahead, its velocity prescribed), every outlet holding a
// pressure, and boundary particles with wall points (their pressure and
// density are the fluid's Shepard averages) or none. A waiting inlet particle
// lies (layers - 2) dx or more behind the patch, and is added at once when it
// comes within the list's range 2h (1 + skin) of the patch or of fluid behind
// it; a leaving one is layers dx >= 2h past its patch and moves on. Otherwise
// (and with "rebuilt") every change rebuilds the list, as each one did before.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "parameters.h"
#include "particles.h"
#include "inlet_buffer.h"
#include "outlet_buffer.h"
#include "plane_patch.h"

namespace sph {

template <int D>
class OpenBoundaries {
 public:
  explicit OpenBoundaries(const RunParameters& deck)
      : dx_(deck.dx), rho0_(deck.rho0), reach_(2.0 * deck.h * (1.0 + deck.neighbour_skin)),
        t_last_(deck.t_start), keep_list_(deck.open_boundary_list == "kept") {
    const auto materials = deck.material_list();
    for (const auto& s : deck.inlets) inlets_.push_back(make_inlet<D>(s, materials[s.material], dx_));
    for (const auto& s : deck.outlets) outlets_.push_back(make_outlet<D>(s, materials));
    new_options_only_ = !empty();
    for (const auto& in : inlets_) new_options_only_ = new_options_only_ && in.reference_volumes;
    for (const auto& out : outlets_) new_options_only_ = new_options_only_ && out.holds;
  }

  bool empty() const { return inlets_.empty() && outlets_.empty(); }
  std::size_t count() const { return inlets_.size() + outlets_.size(); }
  const std::string& name(std::size_t k) const {
    return k < inlets_.size() ? inlets_[k].patch.name : outlets_[k - inlets_.size()].patch.name;
  }
  bool is_inlet(std::size_t k) const { return k < inlets_.size(); }

  // Particles the inlets add over a run of t_end seconds (with a margin), for reserving.
  std::size_t extra_capacity(double t_end) const {
    double extra = 0.0;
    for (const auto& in : inlets_)
      extra += 1.2 * in.patch.area() * in.velocity * t_end / std::pow(dx_, D) +
               (in.layers + 1.0) * in.patch.lattice(dx_).size();
    return static_cast<std::size_t>(extra) + 16;
  }

  // Append the inlet buffers; returns the next free particle id.
  std::int64_t fill(Particles<D>& P, std::int64_t next_id) const {
    for (const auto& in : inlets_) next_id = in.fill(P, next_id, dx_, rho0_);
    return next_id;
  }

  // A resumed run's inlets at its start time t (s): the ramp factor of eq. OB4 there (the buffers come from
  // the particle file, as they were).
  void start_at(double t) {
    for (auto& in : inlets_)
      in.factor = in.ramp_time > 0.0 && t < in.ramp_time ? 0.5 * (1.0 - std::cos(M_PI * t / in.ramp_time)) : 1.0;
  }

  // Whether conversions keep the Verlet list and additions and removals wait (see the top), given the
  // particles: with boundary particles only if they have wall points.
  void decide_list_keeping(const Particles<D>& P) {
    bool exact = keep_list_ && new_options_only_;
    for (const auto& in : inlets_) exact = exact && in.extrapolated;
    const bool walls = std::any_of(P.kind.begin(), P.kind.end(), [](Kind k) { return k == Kind::boundary; });
    defer_ = exact && (P.has_wall_points || !walls);
  }
  bool keeps_list() const { return defer_; }

  // Fluid that starts inside an outlet buffer is outlet fluid from the start
  // (not counted as outflow).
  void classify_initial(Particles<D>& P) const {
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      for (const auto& out : outlets_) {
        const double s = out.patch.height(P.x[i]);
        if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
        P.kind[i] = Kind::outlet;
        const double vn = P.v[i].dot(out.patch.n);
        P.v[i] = (out.backflow ? vn : std::max(vn, 0.0)) * out.patch.n;
        if (out.holds) P.rho[i] = out.rho_ref[P.material[i]];
        break;
      }
    }
  }

  // After a step, at time t (s): convert and remove buffer particles, ramp the
  // inlets' speed (eq. OB4). event(x, m, +1 / -1) is called for each particle
  // created / removed. Returns the next free id.
  template <class Event>
  std::int64_t update(Particles<D>& P, std::int64_t next_id, double t, Event&& event) {
    const std::size_t n = P.size();
    bool removals = false;
    const Pending pending = prepare_update(P, t);
    for (std::size_t i = 0; i < n; ++i) {
      if (defer_ && P.kind[i] == Kind::fluid) note_fluid_behind(P.x[i]);
      if (P.kind[i] == Kind::inlet) {
        if (pending.extrapolate) hold_inlet_density(P, i);
        if (pending.ramping) ramp_inlet_velocity(P, i);
        next_id = inlet_to_fluid(P, i, next_id, event);
      } else if (P.kind[i] == Kind::fluid) {
        fluid_to_outlet(P, i);
      } else if (P.kind[i] == Kind::outlet) {
        next_id = move_outlet_particle(P, i, next_id, event, removals);
      }
    }
    for (auto& out : outlets_)
      if (out.column()) out.advance_column(pending.dt);
    if (removals) P.compact([&](std::size_t i) { return P.mass[i] > 0.0; }), kept_ = false;
    if (defer_ && waiting_too_close()) flush(P, event);
    return next_id;
  }

  // Add the waiting inlet particles and remove those that left the outlets' buffers (each with its
  // event); kept_ false if anything changed (the list must be rebuilt). Call before the particles are
  // sorted for an output or when the list is about to be rebuilt anyway.
  template <class Event>
  bool flush(Particles<D>& P, Event&& event) {
    if (waiting_.empty() && !leaving_) return false;
    if (leaving_) {
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.kind[i] == Kind::outlet && past_buffer(P.x[i])) event(P.x[i], P.mass[i], -1.0), P.mass[i] = 0.0;
      P.compact([&](std::size_t i) { return P.mass[i] > 0.0; });
      leaving_ = false;
    }
    for (const auto& w : waiting_) {
      event(w.x, w.mass, 1.0);
      if (w.outlet) {
        P.append(w.x, w.v, outlets_[w.inlet].buffer_density(w.material), w.mass, Kind::outlet, w.id, w.material);
        continue;
      }
      const Inlet& in = inlets_[w.inlet];
      P.append(w.x, w.v, in.rho_fluid > 0.0 ? in.rho_fluid : in.rho_ref, w.mass, Kind::inlet, w.id, in.material);
    }
    waiting_.clear();
    kept_ = false;
    return true;
  }
  bool has_waiting() const { return !waiting_.empty() || leaving_; }
  // The particles whose kind the last update changed (kept list only; indices into the particles).
  const std::vector<std::size_t>& changed() const { return changed_; }

  // Whether the last update left every particle in place with its kind
  // (only the buffers' density and velocity changed), so the Verlet list
  // still holds. Always false when an inlet or outlet runs without options,
  // so those runs rebuild the list after every step as before.
  bool particles_kept() const { return kept_; }

  // The column outlets (eq. OB5): their names, and the chamber's pressure (Pa) and the column's speed (m/s).
  std::vector<std::size_t> columns() const {
    std::vector<std::size_t> out;
    for (std::size_t j = 0; j < outlets_.size(); ++j)
      if (outlets_[j].column()) out.push_back(j);
    return out;
  }
  const std::string& outlet_name(std::size_t j) const { return outlets_[j].patch.name; }
  double column_pressure(std::size_t j) const { return outlets_[j].eos.pressure(outlets_[j].buffer_density(0)); }
  double column_speed(std::size_t j) const { return outlets_[j].column_speed; }

  // Mean inflow (k an inlet) or outflow (k an outlet) since the last reading, m^3/s (m^2/s in 2D).
  double flow_rate(std::size_t k, double elapsed) {
    double& v = k < inlets_.size() ? inlets_[k].volume : outlets_[k - inlets_.size()].volume;
    const double q = elapsed > 0.0 ? v / elapsed : 0.0;
    v = 0.0;
    return q;
  }

 private:
  using Inlet = InletBuffer<D>;
  using Outlet = OutletBuffer<D>;
  bool new_options_only_ = false, kept_ = false;
  struct Waiting {  // an inlet particle (or an opening's buffer particle) still to be added
    Vec<D> x, v;
    double mass;
    std::int64_t id;
    std::size_t inlet;  // the inlet's index, or the outlet's
    bool outlet = false;
    std::uint8_t material = 0;
  };
  std::vector<Waiting> waiting_;
  std::vector<std::size_t> changed_;
  std::vector<Vec<D>> candidates_;  // fluid behind an inlet's patch, near it (this update)
  bool leaving_ = false;            // outlet particles past their buffer wait for the flush

  // An update's state besides the particles: inlets ramping or extrapolating; the time since the last one, s.
  struct Pending { bool ramping, extrapolate; double dt; };
  // Before the particles: the inlets' ramp factors (eq. OB4) and densities ahead, the outlets' fluid behind
  // and columns, and the waiting particles moved on to time t (s).
  Pending prepare_update(const Particles<D>& P, double t) {
    bool extrapolate = false, ramping = false;
    for (auto& in : inlets_) {
      in.ramping = in.factor < 1.0;  // some buffer particles still move below full speed
      if (in.ramping) in.factor = t < in.ramp_time ? 0.5 * (1.0 - std::cos(M_PI * t / in.ramp_time)) : 1.0;
      ramping = ramping || in.ramping;
    }
    for (auto& in : inlets_)
      if (in.extrapolated) in.rho_fluid = in.fluid_density_ahead(P, dx_), extrapolate = true;
    for (auto& out : outlets_) {
      if (out.holds) out.gather_fluid_behind(P, dx_);
      if (out.column() && !out.column_started) out.start_column(P, dx_);
    }
    const double dt = t - t_last_;
    kept_ = new_options_only_;
    changed_.clear();
    candidates_.clear();
    for (auto& w : waiting_) {  // they move as the buffer does (their velocity: the ramp's at the last update)
      w.x += (t - t_last_) * w.v;
      if (w.outlet) continue;
      const Inlet& in = inlets_[w.inlet];
      if (in.ramping) {
        const Vec<D> q = w.x - in.patch.c;
        w.v = in.factor * in.speed(q - q.dot(in.patch.n) * in.patch.n) * in.patch.n;
      }
    }
    t_last_ = t;
    return {ramping, extrapolate, dt};
  }
  // Inlet buffer particle i that reached 2 dx past its patch becomes fluid, and a new buffer particle takes
  // its place layers dx upstream (now, or at the flush). Returns the next free id.
  template <class Event>
  std::int64_t inlet_to_fluid(Particles<D>& P, std::size_t i, std::int64_t next_id, Event&& event) {
    for (auto& in : inlets_) {
      const double s = in.patch.height(P.x[i]);
      if (s < 0.0 || s > 2.0 * dx_ || !in.patch.contains(P.x[i] - in.patch.c)) continue;
      P.kind[i] = Kind::fluid;
      in.volume += P.mass[i] / (in.reference_volumes ? in.rho_ref : P.rho[i]);
      const Vec<D> spawn = P.x[i] - in.layers * dx_ * in.patch.n;
      if (defer_) {
        changed_.push_back(i);
        waiting_.push_back({spawn, P.v[i], P.mass[i], next_id++, static_cast<std::size_t>(&in - inlets_.data())});
        break;
      }
      kept_ = false;
      event(spawn, P.mass[i], 1.0);
      if (in.reference_volumes)
        P.append(spawn, P.v[i], in.extrapolated ? in.rho_fluid : in.rho_ref, P.mass[i], Kind::inlet, next_id++,
                 in.material);
      else
        P.append(spawn, in.factor * in.velocity * in.patch.n, rho0_, P.mass[i], Kind::inlet, next_id++);
      break;
    }
    return next_id;
  }
  // Fluid particle i inside an outlet's buffer becomes outlet fluid (its outflow counted).
  void fluid_to_outlet(Particles<D>& P, std::size_t i) {
    for (auto& out : outlets_) {
      const double s = out.patch.height(P.x[i]);
      if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
      P.kind[i] = Kind::outlet;
      if (defer_) changed_.push_back(i);
      else kept_ = false;
      P.v[i] = std::max(P.v[i].dot(out.patch.n), 0.0) * out.patch.n;  // straight out, not into walls
      if (out.holds) {
        out.volume += P.mass[i] / out.rho0[P.material[i]];
        P.rho[i] = out.buffer_density(P.material[i]);
      } else {
        out.volume += P.mass[i] / P.rho[i];
      }
      break;
    }
  }
  // Outlet particle i: removed past its buffer (marked by mass 0, `removals` set; or left for the flush), back
  // in through a pressure opening, or held at the buffer's density and velocity. Returns the next free id.
  template <class Event>
  std::int64_t move_outlet_particle(Particles<D>& P, std::size_t i, std::int64_t next_id, Event&& event,
                                    bool& removals) {
    for (auto& out : outlets_) {
      if (!out.patch.contains(P.x[i] - out.patch.c)) continue;
      const double s = out.patch.height(P.x[i]);
      if (s >= out.layers * dx_) {
        if (defer_) {  // it moves on until the next flush, beyond the reach of the fluid
          leaving_ = true;
          break;
        }
        event(P.x[i], P.mass[i], -1.0);
        P.mass[i] = 0.0;  // marks it for removal (real particles have mass > 0)
        removals = true;
        break;
      }
      if (out.backflow && s < 0.0 && s > -dx_) {  // back in through a pressure opening
        next_id = enter_through(P, i, out, next_id, event);
        break;
      }
      if (out.holds && s >= 0.0) {
        P.rho[i] = out.buffer_density(P.material[i]);  // the reference pressure, held (a column's: carried on)
        P.v[i] = out.velocity_behind(P.x[i] - out.patch.c, dx_) * out.patch.n;
        break;
      }
    }
    return next_id;
  }
  // Whether an outlet particle lies past the whole buffer of the outlet it is in.
  bool past_buffer(const Vec<D>& x) const {
    for (const auto& out : outlets_)
      if (out.patch.contains(x - out.patch.c) && out.patch.height(x) >= out.layers * dx_) return true;
    return false;
  }
  // A fluid particle at x behind an inlet's patch and near it (within its buffer's depth and the reach):
  // a waiting inlet particle must not come within reach of it.
  void note_fluid_behind(const Vec<D>& x) {
    for (const auto& in : inlets_) {
      const double s = in.patch.height(x);
      if (s < 0.0 && s > -(in.layers + 1.0) * dx_ - reach_ && in.near(x - in.patch.c, reach_)) {
        candidates_.push_back(x);
        return;
      }
    }
  }
  // Whether a waiting inlet particle is within reach of its patch or of fluid behind it: it must be
  // added now, or the fluid would miss it before the next build.
  bool waiting_too_close() const {
    for (const auto& w : waiting_) {
      if (w.outlet) {  // an opening's: the fluid lies before the patch
        if (outlets_[w.inlet].patch.height(w.x) < reach_) return true;
        continue;
      }
      if (inlets_[w.inlet].patch.height(w.x) > -reach_) return true;
      for (const auto& x : candidates_)
        if ((x - w.x).squaredNorm() < reach_ * reach_) return true;
    }
    return false;
  }

  // Outlet particle i crossed its opening's patch inward: it becomes fluid at the held pressure (its outflow
  // counted back), and a buffer particle takes its lateral place layers dx downstream (now, or at the flush).
  template <class Event>
  std::int64_t enter_through(Particles<D>& P, std::size_t i, Outlet& out, std::int64_t next_id, Event&& event) {
    const std::uint8_t mat = P.material[i];
    P.kind[i] = Kind::fluid;
    out.volume -= P.mass[i] / out.rho0[mat];
    const Vec<D> spawn = P.x[i] + out.layers * dx_ * out.patch.n;
    const Vec<D> v = P.v[i];
    if (defer_) {
      changed_.push_back(i);
      waiting_.push_back({spawn, v, P.mass[i], next_id++, static_cast<std::size_t>(&out - outlets_.data()), true, mat});
      return next_id;
    }
    kept_ = false;
    event(spawn, P.mass[i], 1.0);
    P.append(spawn, v, out.buffer_density(mat), P.mass[i], Kind::outlet, next_id++, mat);
    return next_id;
  }
  // An inlet buffer particle of a ramping inlet takes g(t) times its column's speed (eq. OB4).
  void ramp_inlet_velocity(Particles<D>& P, std::size_t i) const {
    for (const auto& in : inlets_)
      if (in.ramp(P, i, dx_)) return;
  }
  // An inlet buffer particle of an extrapolating inlet takes the fluid's density ahead.
  void hold_inlet_density(Particles<D>& P, std::size_t i) const {
    for (const auto& in : inlets_)
      if (in.hold(P, i, dx_)) return;
  }
  double dx_, rho0_;
  double reach_;   // the Verlet list's range 2h (1 + skin), m
  double t_last_;  // s, of the last update
  bool keep_list_ = true, defer_ = false;
  std::vector<Inlet> inlets_;
  std::vector<Outlet> outlets_;
};

}  // namespace sph
