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
// The volume converted at each patch gives the inflow and outflow rates.
//
// Options (deck.h InletSpec, OutletSpec), after the buffer inlets and
// outlets of Lastiwka et al. 2009 and Tafuni et al. 2018 (velocity imposed at
// the inlet, pressure at the outlet):
// - inlet profile: each lattice column moves at v(q) = U f(q) / <f>, with f
//   the Poiseuille shape across the patch (eqs. OB1-OB3 below) and <f> its
//   mean over the lattice columns, so the columns carry exactly U times the
//   patch area; a profile that vanishes at the wall does not pile fluid up
//   where the inflow meets a no-slip wall (a plug does);
// - inlet pressure "extrapolated": the buffer takes the mean density of the
//   fluid within `layers` dx inside the patch (zeroth-order extrapolation of
//   the pressure), so the inflow enters at the pressure of the fluid ahead;
// - outlet pressure p_ref: the buffer holds rho_ref = rho0 (1 + gamma
//   (p_ref - p_B) / (rho0 c0^2))^(1/gamma) (eq. 6 inverted), the domain's
//   reference pressure, so the mean density cannot drift.
// With any of these options the patch counts each particle as m / rho0 of its
// material (the volume at the reference density: the mass flux over rho0).
// - inlet ramp_time T: the buffer moves at g(t) times its speed,
//   g = (1 - cos(pi t / T)) / 2 for t < T, 1 after (OB4), set after each
//   step at the new time; the inflow starts at rest without a jump in
//   acceleration, so a scene filled at rest is not struck by a water hammer
//   of rho0 c0 U.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deck.h"
#include "particles.h"
#include "plane_patch.h"

namespace sph {

template <int D>
class OpenBoundaries {
 public:
  explicit OpenBoundaries(const Deck& deck) : dx_(deck.dx), rho0_(deck.rho0) {
    const auto materials = deck.material_list();
    for (const auto& s : deck.inlets) {
      Inlet in(Patch<D>(s.patch), s.velocity, s.layers);
      in.profile = s.profile == "parabolic" ? Profile::parabolic : s.profile == "annular" ? Profile::annular : Profile::plug;
      in.inner_radius = s.inner_radius;
      in.extrapolated = s.extrapolated;
      in.material = static_cast<std::uint8_t>(s.material);
      in.rho_ref = materials[s.material].rho0;
      in.ramp_time = s.ramp_time;
      in.factor = s.ramp_time > 0.0 ? 0.0 : 1.0;  // eq. OB4 at t = 0
      in.reference_volumes = in.profile != Profile::plug || in.extrapolated || s.material != 0;
      if (in.profile != Profile::plug) normalise(in);
      inlets_.push_back(in);
    }
    for (const auto& s : deck.outlets) {
      Outlet out(Patch<D>(s.patch), s.layers);
      out.holds = s.pressure.has_value();
      for (const auto& m : materials) {
        out.rho0.push_back(m.rho0);
        if (out.holds)  // eq. 6 inverted
          out.rho_ref.push_back(
              m.rho0 * std::pow(1.0 + m.gamma * (*s.pressure - m.background_pressure) / (m.rho0 * m.c0 * m.c0),
                                1.0 / m.gamma));
      }
      outlets_.push_back(out);
    }
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
    const double mass = rho0_ * std::pow(dx_, D);
    for (const auto& in : inlets_) {
      if (in.profile == Profile::plug && in.material == 0) {
        for (const auto& q : in.patch.lattice(dx_))
          for (int l = 0; l < in.layers; ++l)
            P.append(in.patch.c + q - (l + 0.5) * dx_ * in.patch.n, in.factor * in.velocity * in.patch.n, rho0_, mass,
                     Kind::inlet, next_id++);
        continue;
      }
      const double m = in.rho_ref * std::pow(dx_, D);
      for (const auto& q : columns(in))
        for (int l = 0; l < in.layers; ++l)
          P.append(in.patch.c + q - (l + 0.5) * dx_ * in.patch.n, in.factor * speed(in, q) * in.patch.n, in.rho_ref, m,
                   Kind::inlet, next_id++, in.material);
    }
    return next_id;
  }

  // A resumed run's inlets at its start time t (s): the ramp factor of eq. OB4 there (the buffers come from
  // the particle file, as they were).
  void start_at(double t) {
    for (auto& in : inlets_)
      in.factor = in.ramp_time > 0.0 && t < in.ramp_time ? 0.5 * (1.0 - std::cos(M_PI * t / in.ramp_time)) : 1.0;
  }

  // Fluid that starts inside an outlet buffer is outlet fluid from the start
  // (not counted as outflow).
  void classify_initial(Particles<D>& P) const {
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      for (const auto& out : outlets_) {
        const double s = out.patch.height(P.x[i]);
        if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
        P.kind[i] = Kind::outlet;
        P.v[i] = std::max(P.v[i].dot(out.patch.n), 0.0) * out.patch.n;
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
    bool extrapolate = false;
    bool ramping = false;
    for (auto& in : inlets_) {
      in.ramping = in.factor < 1.0;  // some buffer particles still move below full speed
      if (in.ramping) in.factor = t < in.ramp_time ? 0.5 * (1.0 - std::cos(M_PI * t / in.ramp_time)) : 1.0;
      ramping = ramping || in.ramping;
    }
    for (auto& in : inlets_)
      if (in.extrapolated) in.rho_fluid = fluid_density_ahead(P, in), extrapolate = true;
    for (auto& out : outlets_)
      if (out.holds) gather_fluid_behind(P, out);
    kept_ = new_options_only_;
    for (std::size_t i = 0; i < n; ++i) {
      if (P.kind[i] == Kind::inlet) {
        if (extrapolate) hold_inlet_density(P, i);
        if (ramping) ramp_inlet_velocity(P, i);
        for (auto& in : inlets_) {
          const double s = in.patch.height(P.x[i]);
          if (s < 0.0 || s > 2.0 * dx_ || !in.patch.contains(P.x[i] - in.patch.c)) continue;
          P.kind[i] = Kind::fluid;
          kept_ = false;
          in.volume += P.mass[i] / (in.reference_volumes ? in.rho_ref : P.rho[i]);
          const Vec<D> spawn = P.x[i] - in.layers * dx_ * in.patch.n;
          event(spawn, P.mass[i], 1.0);
          if (in.reference_volumes)
            P.append(spawn, P.v[i], in.extrapolated ? in.rho_fluid : in.rho_ref, P.mass[i], Kind::inlet, next_id++,
                     in.material);
          else
            P.append(spawn, in.factor * in.velocity * in.patch.n, rho0_, P.mass[i], Kind::inlet, next_id++);
          break;
        }
      } else if (P.kind[i] == Kind::fluid) {
        for (auto& out : outlets_) {
          const double s = out.patch.height(P.x[i]);
          if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
          P.kind[i] = Kind::outlet;
          kept_ = false;
          P.v[i] = std::max(P.v[i].dot(out.patch.n), 0.0) * out.patch.n;  // straight out, not into walls
          if (out.holds) {
            out.volume += P.mass[i] / out.rho0[P.material[i]];
            P.rho[i] = out.rho_ref[P.material[i]];
          } else {
            out.volume += P.mass[i] / P.rho[i];
          }
          break;
        }
      } else if (P.kind[i] == Kind::outlet) {
        for (auto& out : outlets_) {
          if (!out.patch.contains(P.x[i] - out.patch.c)) continue;
          const double s = out.patch.height(P.x[i]);
          if (s >= out.layers * dx_) {
            event(P.x[i], P.mass[i], -1.0);
            P.mass[i] = 0.0;  // marks it for removal (real particles have mass > 0)
            removals = true;
            break;
          }
          if (out.holds && s >= 0.0) {
            P.rho[i] = out.rho_ref[P.material[i]];  // the reference pressure, held
            P.v[i] = velocity_behind(out, P.x[i] - out.patch.c) * out.patch.n;
            break;
          }
        }
      }
    }
    if (removals) P.compact([&](std::size_t i) { return P.mass[i] > 0.0; }), kept_ = false;
    return next_id;
  }

  // Whether the last update left every particle in place with its kind
  // (only the buffers' density and velocity changed), so the Verlet list
  // still holds. Always false when an inlet or outlet runs without options,
  // so those runs rebuild the list after every step as before.
  bool particles_kept() const { return kept_; }

  // Mean inflow (k an inlet) or outflow (k an outlet) since the last reading, m^3/s (m^2/s in 2D).
  double flow_rate(std::size_t k, double elapsed) {
    double& v = k < inlets_.size() ? inlets_[k].volume : outlets_[k - inlets_.size()].volume;
    const double q = elapsed > 0.0 ? v / elapsed : 0.0;
    v = 0.0;
    return q;
  }

 private:
  enum class Profile { plug, parabolic, annular };
  struct Inlet {
    Inlet(const Patch<D>& p, double v, int l) : patch(p), velocity(v), layers(l) {}
    Patch<D> patch;
    double velocity;  // plug speed, or mean speed of a profile, m/s
    int layers;
    double volume = 0.0;
    Profile profile = Profile::plug;
    double inner_radius = 0.0;  // m (annular)
    double scale = 1.0;         // U / <f> over the lattice columns, m/s per unit of f
    bool extrapolated = false;
    bool reference_volumes = false;  // count m / rho_ref (any option set)
    std::uint8_t material = 0;
    double rho_ref = 0.0;    // rho0 of the material, kg/m^3
    double rho_fluid = 0.0;  // mean density of the fluid ahead (extrapolated), kg/m^3
    double ramp_time = 0.0;  // s (eq. OB4)
    double factor = 1.0;     // g(t) of eq. OB4 at the last update
    bool ramping = false;    // this update sets the buffer's speed
  };
  struct Outlet {
    Outlet(const Patch<D>& p, int l) : patch(p), layers(l) {}
    Patch<D> patch;
    int layers;
    double volume = 0.0;
    bool holds = false;                 // holds a reference pressure
    std::vector<double> rho0, rho_ref;  // per material, kg/m^3
    std::vector<Vec<D>> behind_q;       // in-plane offsets of the fluid within layers dx before the patch
    std::vector<double> behind_v;       // and their speeds along the normal, m/s
  };
  bool new_options_only_ = false, kept_ = false;

  // The fluid within layers dx before an outlet's patch: in-plane offsets and normal speeds.
  void gather_fluid_behind(const Particles<D>& P, Outlet& out) const {
    out.behind_q.clear(), out.behind_v.clear();
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      const Vec<D> q = P.x[i] - out.patch.c;
      const double s = q.dot(out.patch.n);
      if (s >= 0.0 || s < -out.layers * dx_ || !out.patch.contains(q)) continue;
      out.behind_q.push_back(q - s * out.patch.n);
      out.behind_v.push_back(P.v[i].dot(out.patch.n));
    }
  }
  // Normal speed of an outlet buffer particle at in-plane offset q (normal part
  // ignored): the fluid's normal speed before the patch averaged over the
  // in-plane distance d < 2 dx with weight (1 - d / 2dx)^2 (zero-gradient
  // velocity, as the outlets of Tafuni et al. 2018), not below 0, m/s.
  double velocity_behind(const Outlet& out, const Vec<D>& x_rel) const {
    const Vec<D> q = x_rel - x_rel.dot(out.patch.n) * out.patch.n;
    const double reach = 2.0 * dx_;
    double sum = 0.0, weight = 0.0;
    for (std::size_t j = 0; j < out.behind_q.size(); ++j) {
      const double d = (out.behind_q[j] - q).norm();
      if (d >= reach) continue;
      const double w = (1.0 - d / reach) * (1.0 - d / reach);
      sum += w * out.behind_v[j], weight += w;
    }
    return weight > 0.0 ? std::max(sum / weight, 0.0) : 0.0;
  }

  // Radius of the in-plane offset q (disc patches), m.
  static double radial(const Patch<D>& patch, const Vec<D>& q) {
    const double a = q.dot(patch.u);
    if constexpr (D == 2) return std::abs(a);
    const double b = q.dot(patch.w);
    return std::sqrt(a * a + b * b);
  }
  // The profile's shape f at in-plane offset q (unscaled):
  //   parabolic disc (pipe, Hagen-Poiseuille):  f = 1 - r^2 / R^2                           (OB1)
  //   parabolic rectangle / 2D segment (plates): f = 1 - a^2 / a_max^2, a = q . u             (OB2)
  //   annular (Ri <= r <= R):  f = R^2 - r^2 + (R^2 - Ri^2) ln(r/R) / ln(R/Ri)              (OB3)
  // (OB3 is the laminar annulus profile u = G f / (4 mu), Bird, Stewart & Lightfoot 2.4.)
  static double shape(const Inlet& in, const Vec<D>& q) {
    const Patch<D>& p = in.patch;
    if (in.profile == Profile::plug) return 1.0;
    if (in.profile == Profile::parabolic) {
      if (D == 3 && p.radius > 0.0) {
        const double r = radial(p, q) / p.radius;
        return std::max(1.0 - r * r, 0.0);
      }
      const double a = q.dot(p.u) / p.half_u;
      return std::max(1.0 - a * a, 0.0);
    }
    const double R = p.radius, Ri = in.inner_radius, r = std::max(radial(p, q), Ri);
    return std::max(R * R - r * r + (R * R - Ri * Ri) * std::log(r / R) / std::log(R / Ri), 0.0);
  }
  // The lattice columns of an inlet (the annulus without its core).
  std::vector<Vec<D>> columns(const Inlet& in) const {
    std::vector<Vec<D>> out;
    for (const auto& q : in.patch.lattice(dx_))
      if (in.profile != Profile::annular || radial(in.patch, q) >= in.inner_radius) out.push_back(q);
    return out;
  }
  // The speed of the column at in-plane offset q, m/s (a plug's is its velocity).
  double speed(const Inlet& in, const Vec<D>& q) const {
    return in.profile == Profile::plug ? in.velocity : in.scale * shape(in, q);
  }
  // Scale of a profile so that the columns carry U times the patch area: sum_j v_j dx^(D-1) = U A.
  void normalise(Inlet& in) const {
    double sum = 0.0;
    for (const auto& q : columns(in)) sum += shape(in, q);
    double area = in.patch.area();
    if (in.profile == Profile::annular) area -= M_PI * in.inner_radius * in.inner_radius;
    in.scale = sum > 0.0 ? in.velocity * area / (sum * std::pow(dx_, D - 1)) : 0.0;
  }
  // Mean density of the fluid within layers dx ahead of the inlet's patch, kg/m^3 (rho_ref if none).
  double fluid_density_ahead(const Particles<D>& P, const Inlet& in) const {
    double sum = 0.0;
    long count = 0;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      const double s = in.patch.height(P.x[i]);
      if (s < 0.0 || s > in.layers * dx_ || !in.patch.contains(P.x[i] - in.patch.c)) continue;
      sum += P.rho[i], ++count;
    }
    return count > 0 ? sum / count : in.rho_ref;
  }
  // An inlet buffer particle of a ramping inlet takes g(t) times its column's speed (eq. OB4).
  void ramp_inlet_velocity(Particles<D>& P, std::size_t i) const {
    for (const auto& in : inlets_) {
      const Vec<D> q = P.x[i] - in.patch.c;
      if (!in.ramping || !in.patch.contains(q)) continue;
      const double s = q.dot(in.patch.n);
      if (s < -(in.layers + 1.0) * dx_ || s > 2.0 * dx_) continue;
      P.v[i] = in.factor * speed(in, q - s * in.patch.n) * in.patch.n;
      return;
    }
  }
  // An inlet buffer particle of an extrapolating inlet takes the fluid's density ahead.
  void hold_inlet_density(Particles<D>& P, std::size_t i) const {
    for (const auto& in : inlets_) {
      if (!in.extrapolated || !in.patch.contains(P.x[i] - in.patch.c)) continue;
      const double s = in.patch.height(P.x[i]);
      if (s < -(in.layers + 1.0) * dx_ || s > 2.0 * dx_) continue;
      P.rho[i] = in.rho_fluid;
      return;
    }
  }
  double dx_, rho0_;
  std::vector<Inlet> inlets_;
  std::vector<Outlet> outlets_;
};

}  // namespace sph
