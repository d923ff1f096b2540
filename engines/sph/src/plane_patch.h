// A patch of a plane (disc, rectangle, or in 2D a segment) in simulation vectors.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "parameters.h"
#include "vec.h"

namespace sph {

template <int D>
struct Patch {
  std::string name;
  Vec<D> c = Vec<D>::Zero(), n = Vec<D>::Zero();  // centre m, unit normal
  Vec<D> u = Vec<D>::Zero(), w = Vec<D>::Zero();  // in-plane unit axes (w unused in 2D)
  double radius = 0.0;                            // disc; 0 for a rectangle
  double half_u = 0.0, half_w = 0.0;              // rectangle half extents, m

  explicit Patch(const PlanePatch& spec) : name(spec.name) {
    for (int d = 0; d < D; ++d) c[d] = spec.center[d], n[d] = spec.normal[d];
    n.normalize();
    radius = spec.radius;
    if (!spec.half_extents.empty()) half_u = spec.half_extents[0];
    if (spec.half_extents.size() > 1) half_w = spec.half_extents[1];
    if constexpr (D == 2) {
      u = Vec<2>(-n[1], n[0]);
      if (radius > 0.0) half_u = radius;
    } else {
      Vec<3> guess = std::abs(n[0]) < 0.9 ? Vec<3>::UnitX() : Vec<3>::UnitY();
      if (!spec.u.empty()) guess = Vec<3>(spec.u[0], spec.u[1], spec.u[2]);
      u = (guess - guess.dot(n) * n).normalized();
      w = n.cross(u);
    }
  }

  double height(const Vec<D>& x) const { return (x - c).dot(n); }  // signed distance along n

  // Whether the in-plane offset q (relative to c, normal part ignored) lies on the patch.
  bool contains(const Vec<D>& q) const {
    const double a = q.dot(u);
    if constexpr (D == 2) return std::abs(a) <= half_u;
    const double b = q.dot(w);
    if (radius > 0.0) return a * a + b * b <= radius * radius;
    return std::abs(a) <= half_u && std::abs(b) <= half_w;
  }

  // In-plane lattice of spacing dx covering the patch (offsets from c).
  std::vector<Vec<D>> lattice(double dx) const {
    std::vector<Vec<D>> out;
    const double ext_u = radius > 0.0 ? radius : half_u, ext_w = radius > 0.0 ? radius : half_w;
    const int nu = std::max(1, static_cast<int>(std::lround(2.0 * ext_u / dx)));
    const int nw = D == 3 ? std::max(1, static_cast<int>(std::lround(2.0 * ext_w / dx))) : 1;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nw; ++j) {
        Vec<D> q = ((i + 0.5) * dx - 0.5 * nu * dx) * u;
        if constexpr (D == 3) q += ((j + 0.5) * dx - 0.5 * nw * dx) * w;
        if (contains(q)) out.push_back(q);
      }
    return out;
  }

  double area() const {  // m^2 in 3D, m (length) in 2D
    if constexpr (D == 2) return 2.0 * half_u;
    return radius > 0.0 ? M_PI * radius * radius : 4.0 * half_u * half_w;
  }
};

}  // namespace sph
