// An outlet's buffer (open_boundaries.h): its patch and options, and the zero-gradient velocity its
// particles take from the fluid before the patch.
//
// Options (deck.h OutletSpec):
// - pressure p_ref: the buffer holds rho_ref = rho0 (1 + gamma (p_ref - p_B)
//   / (rho0 c0^2))^(1/gamma) (eq. 6 inverted), the domain's reference
//   pressure, so the mean density cannot drift; its particles move at the
//   fluid's normal speed before the patch (velocity_behind);
// - backflow (with a pressure): a pressure opening, whose buffer may move
//   inward at that speed; a buffer particle crossing the patch inward becomes
//   fluid at the held pressure and a new one takes its place layers dx
//   downstream (OpenBoundaries::enter_through).
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

#include "particles.h"
#include "plane_patch.h"
#include "vec.h"

namespace sph {

// An outlet: fluid crossing its patch becomes buffer, removed `layers` dx downstream.
template <int D>
struct OutletBuffer {
  OutletBuffer(const Patch<D>& p, int l) : patch(p), layers(l) {}
  Patch<D> patch;
  int layers;
  double volume = 0.0;
  bool holds = false;                 // holds a reference pressure
  bool backflow = false;              // a pressure opening: its buffer may move inward and feed the fluid
  std::vector<double> rho0, rho_ref;  // per material, kg/m^3
  std::vector<Vec<D>> behind_q;       // in-plane offsets of the fluid within layers dx before the patch
  std::vector<double> behind_v;       // and their speeds along the normal, m/s

  // The fluid within layers dx before an outlet's patch: in-plane offsets and normal speeds.
  void gather_fluid_behind(const Particles<D>& P, double dx) {
    behind_q.clear(), behind_v.clear();
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      const Vec<D> q = P.x[i] - patch.c;
      const double s = q.dot(patch.n);
      if (s >= 0.0 || s < -layers * dx || !patch.contains(q)) continue;
      behind_q.push_back(q - s * patch.n);
      behind_v.push_back(P.v[i].dot(patch.n));
    }
  }
  // Normal speed of an outlet buffer particle at in-plane offset q (normal part
  // ignored): the fluid's normal speed before the patch averaged over the
  // in-plane distance d < R with weight (1 - d / R)^2 (zero-gradient
  // velocity, as the outlets of Tafuni et al. 2018), not below 0 unless the
  // outlet lets fluid back in (backflow), m/s. R = 2 dx; an opening's R = dx
  // (2 dx where no fluid lies that close): its columns beside a wall feed the
  // fluid, and at the core's speed they pushed it into the wall (test_open_boundaries.cpp).
  double velocity_behind(const Vec<D>& x_rel, double dx) const {
    const Vec<D> q = x_rel - x_rel.dot(patch.n) * patch.n;
    for (double reach = backflow ? dx : 2.0 * dx; reach <= 2.0 * dx; reach *= 2.0) {
      double sum = 0.0, weight = 0.0;
      for (std::size_t j = 0; j < behind_q.size(); ++j) {
        const double d = (behind_q[j] - q).norm();
        if (d >= reach) continue;
        const double w = (1.0 - d / reach) * (1.0 - d / reach);
        sum += w * behind_v[j], weight += w;
      }
      if (weight <= 0.0) continue;
      return backflow ? sum / weight : std::max(sum / weight, 0.0);
    }
    return 0.0;
  }
};

}  // namespace sph
