// When the Verlet list (neighbour_list.h) is still valid: it holds the pairs
// closer than the list range R = 2h + skin at its build, and stays valid
// while no particle has moved skin/2 since (LAMMPS's criterion).
//
// Under Lees-Edwards (box_policy.h, eq. LE3): with s the strain since the
// build and u_i = x_i - x_i^b - s (y_i^b - y_mid) e_x the displacement of
// particle i beside the affine shear, a pair vector (images included) is
// r = A r^b + u_a - u_b, A = I + s e_x e_y^T; an unlisted pair (|r^b| >= R)
// stays beyond the support 2h while 2 max |u| <= R / (1 + |s|) - 2h (y_mid,
// any constant, cancels in u_a - u_b; the mid-plane keeps |u| small in a cell
// sheared about its middle). The plain criterion would rebuild every step in
// a fast shear: the particles near the faces move with the images.
#pragma once
#include <algorithm>
#include <cmath>

#include "vec.h"

namespace sph {

// Displacement of a particle at x since the build (at x_build), m: plain, or
// beside the affine shear of strain s about the plane y = y_mid (Sheared, eq. LE3).
template <int D, bool Sheared>
Vec<D> displacement_since_build(const Vec<D>& x, const Vec<D>& x_build, double strain, double y_mid) {
  Vec<D> moved = x - x_build;
  if constexpr (Sheared) moved[0] -= strain * (x_build[1] - y_mid);
  return moved;
}

// The largest displacement since the build that keeps the list valid, m:
// skin/2; under Lees-Edwards (Sheared) R / (1 + |s|) - 2h halved, at least 0.
template <bool Sheared>
double allowed_displacement(double support, double skin, double strain) {
  if constexpr (Sheared) return std::max(0.0, 0.5 * ((support + skin) / (1.0 + std::abs(strain)) - support));
  return 0.5 * skin;
}

}  // namespace sph
