// An inlet's buffer (open_boundaries.h): its patch, speed and profile, options and state, and the
// profile's column speeds (eqs. OB1-OB3).
//
// Options (parameters.h InletSpec):
// - profile: each lattice column moves at v(q) = U f(q) / <f>, with f the
//   Poiseuille shape across the patch (eqs. OB1-OB3 below) and <f> its mean
//   over the lattice columns, so the columns carry exactly U times the patch
//   area; a profile that vanishes at the wall does not pile fluid up where
//   the inflow meets a no-slip wall (a plug does);
// - pressure "extrapolated": the buffer takes the mean density of the fluid
//   within `layers` dx inside the patch (zeroth-order extrapolation of the
//   pressure), so the inflow enters at the pressure of the fluid ahead;
// - ramp_time T: the buffer moves at g(t) times its speed,
//   g = (1 - cos(pi t / T)) / 2 for t < T, 1 after (OB4), set after each
//   step at the new time; the inflow starts at rest without a jump in
//   acceleration, so a scene filled at rest is not struck by a water hammer
//   of rho0 c0 U.
// With any option (or an outlet's held pressure) the patch counts each
// particle as m / rho0 of its material (the mass flux over rho0).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "parameters.h"
#include "particles.h"
#include "plane_patch.h"
#include "vec.h"

namespace sph {

enum class InletProfile { plug, parabolic, annular };

// Radius of the in-plane offset q on a patch (disc patches; |q . u| in 2D), m.
template <int D>
double patch_radius(const Patch<D>& patch, const Vec<D>& q) {
  const double a = q.dot(patch.u);
  if constexpr (D == 2) return std::abs(a);
  const double b = q.dot(patch.w);
  return std::sqrt(a * a + b * b);
}

// An inlet: `layers` layers of lattice columns behind its patch, each moving at its speed along the normal.
template <int D>
struct InletBuffer {
  InletBuffer(const Patch<D>& p, double v, int l) : patch(p), velocity(v), layers(l) {}
  Patch<D> patch;
  double velocity;  // plug speed, or mean speed of a profile, m/s
  int layers;
  double volume = 0.0;
  InletProfile profile = InletProfile::plug;
  double inner_radius = 0.0;  // m (annular)
  double scale = 1.0;         // U / <f> over the lattice columns, m/s per unit of f
  bool extrapolated = false;
  bool reference_volumes = false;  // count m / rho_ref (any option set)
  std::uint8_t material = 0;
  double rho_ref = 0.0;    // rho0 of the material, kg/m^3
  double rho_fluid = 0.0;  // mean density of the fluid ahead (extrapolated), kg/m^3
  double floor_rho = 0.0;  // the material's cavitation floor density (eos.h), kg/m^3 (0: none)
  double ramp_time = 0.0;  // s (eq. OB4)
  double factor = 1.0;     // g(t) of eq. OB4 at the last update
  bool ramping = false;    // this update sets the buffer's speed

  // The profile's shape f at in-plane offset q (unscaled):
  //   parabolic disc (pipe, Hagen-Poiseuille):  f = 1 - r^2 / R^2                           (OB1)
  //   parabolic rectangle / 2D segment (plates): f = 1 - a^2 / a_max^2, a = q . u             (OB2)
  //   annular (Ri <= r <= R):  f = R^2 - r^2 + (R^2 - Ri^2) ln(r/R) / ln(R/Ri)              (OB3)
  // (OB3 is the laminar annulus profile u = G f / (4 mu), Bird, Stewart & Lightfoot 2.4.)
  double shape(const Vec<D>& q) const {
    const Patch<D>& p = patch;
    if (profile == InletProfile::plug) return 1.0;
    if (profile == InletProfile::parabolic) {
      if (D == 3 && p.radius > 0.0) {
        const double r = patch_radius(p, q) / p.radius;
        return std::max(1.0 - r * r, 0.0);
      }
      const double a = q.dot(p.u) / p.half_u;
      return std::max(1.0 - a * a, 0.0);
    }
    const double R = p.radius, Ri = inner_radius, r = std::max(patch_radius(p, q), Ri);
    return std::max(R * R - r * r + (R * R - Ri * Ri) * std::log(r / R) / std::log(R / Ri), 0.0);
  }
  // The lattice columns of an inlet (the annulus without its core).
  std::vector<Vec<D>> columns(double dx) const {
    std::vector<Vec<D>> out;
    for (const auto& q : patch.lattice(dx))
      if (profile != InletProfile::annular || patch_radius(patch, q) >= inner_radius) out.push_back(q);
    return out;
  }
  // The speed of the column at in-plane offset q, m/s (a plug's is its velocity).
  double speed(const Vec<D>& q) const {
    return profile == InletProfile::plug ? velocity : scale * shape(q);
  }
  // Append the buffer's particles, `layers` behind the patch on each lattice column, from id next_id on; dx: the
  // lattice spacing, m; rho0: the run's first material's density, kg/m^3. Returns the next free id.
  std::int64_t fill(Particles<D>& P, std::int64_t next_id, double dx, double rho0) const {
    if (profile == InletProfile::plug && material == 0) {
      const double mass = rho0 * std::pow(dx, D);
      for (const auto& q : patch.lattice(dx))
        for (int l = 0; l < layers; ++l)
          P.append(patch.c + q - (l + 0.5) * dx * patch.n, factor * velocity * patch.n, rho0, mass, Kind::inlet,
                   next_id++);
      return next_id;
    }
    const double m = rho_ref * std::pow(dx, D);
    for (const auto& q : columns(dx))
      for (int l = 0; l < layers; ++l)
        P.append(patch.c + q - (l + 0.5) * dx * patch.n, factor * speed(q) * patch.n, rho_ref, m, Kind::inlet,
                 next_id++, material);
    return next_id;
  }
  // Whether the in-plane offset q lies within `reach` (m) of the patch laterally (the patch grown by it).
  bool near(const Vec<D>& q, double reach) const {
    const double a = q.dot(patch.u);
    if constexpr (D == 2) return std::abs(a) <= patch.half_u + reach;
    const double b = q.dot(patch.w);
    if (patch.radius > 0.0) return std::sqrt(a * a + b * b) <= patch.radius + reach;
    return std::abs(a) <= patch.half_u + reach && std::abs(b) <= patch.half_w + reach;
  }
  // Mean density of the fluid within layers dx ahead of the patch, kg/m^3 (rho_ref if none). A cavitating
  // particle counts at the floor's density (its liquid): averaged as it is, its falling density would make
  // the buffer feed fluid that is part vapour (989.6 kg/m^3 in a drill run at 1.19 ms).
  double fluid_density_ahead(const Particles<D>& P, double dx) const {
    double sum = 0.0;
    long count = 0;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      const double s = patch.height(P.x[i]);
      if (s < 0.0 || s > layers * dx || !patch.contains(P.x[i] - patch.c)) continue;
      sum += std::max(P.rho[i], floor_rho), ++count;
    }
    return count > 0 ? sum / count : rho_ref;
  }
  // Whether buffer particle i is in this inlet's buffer (or just past its patch); then, while the inlet
  // ramps, it takes g(t) times its column's speed (eq. OB4).
  bool ramp(Particles<D>& P, std::size_t i, double dx) const {
    const Vec<D> q = P.x[i] - patch.c;
    if (!ramping || !patch.contains(q)) return false;
    const double s = q.dot(patch.n);
    if (s < -(layers + 1.0) * dx || s > 2.0 * dx) return false;
    P.v[i] = factor * speed(q - s * patch.n) * patch.n;
    return true;
  }
  // Whether buffer particle i is in this extrapolating inlet's buffer; then it takes the fluid's density ahead.
  bool hold(Particles<D>& P, std::size_t i, double dx) const {
    if (!extrapolated || !patch.contains(P.x[i] - patch.c)) return false;
    const double s = patch.height(P.x[i]);
    if (s < -(layers + 1.0) * dx || s > 2.0 * dx) return false;
    P.rho[i] = rho_fluid;
    return true;
  }
  // Scale of a profile so that the columns carry U times the patch area: sum_j v_j dx^(D-1) = U A.
  void normalise(double dx) {
    double sum = 0.0;
    for (const auto& q : columns(dx)) sum += shape(q);
    double area = patch.area();
    if (profile == InletProfile::annular) area -= M_PI * inner_radius * inner_radius;
    scale = sum > 0.0 ? velocity * area / (sum * std::pow(dx, D - 1)) : 0.0;
  }
};

// An inlet's buffer from its deck entry `s` and its material; dx: the lattice spacing, m.
template <int D>
InletBuffer<D> make_inlet(const InletSpec& s, const MaterialSpec& material, double dx) {
  InletBuffer<D> in(Patch<D>(s.patch), s.velocity, s.layers);
  in.profile = s.profile == "parabolic" ? InletProfile::parabolic
               : s.profile == "annular" ? InletProfile::annular
                                        : InletProfile::plug;
  in.inner_radius = s.inner_radius;
  in.extrapolated = s.extrapolated;
  in.material = static_cast<std::uint8_t>(s.material);
  in.rho_ref = material.rho0;
  in.floor_rho = material_eos(material).floor_rho;
  in.ramp_time = s.ramp_time;
  in.factor = s.ramp_time > 0.0 ? 0.0 : 1.0;  // eq. OB4 at t = 0
  in.reference_volumes = in.profile != InletProfile::plug || in.extrapolated || s.material != 0;
  if (in.profile != InletProfile::plug) in.normalise(dx);
  return in;
}

}  // namespace sph
