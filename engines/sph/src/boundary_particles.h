// Fixed boundary particles: their no-slip velocity for the viscous term and
// their density when an open boundary adds or removes a particle nearby.
#pragma once
#include <cmath>
#include <cstddef>
#include <vector>

#include "cell_list.h"
#include "kernel.h"
#include "particles.h"

namespace sph {

// No-slip at fixed boundary particles for the viscous term: a boundary
// particle b takes 2 v_b - v~_b, with v~_b the Shepard average of the fluid
// velocity around it, so the fluid sees the velocity mirrored through the
// wall (as Adami et al. 2012). Its own v_b (the wall's velocity) is unchanged.
// (v_noslip holds the Shepard sum of PairLoop::no_slip_sums_of_block before,
// shepard the weight sums.)
template <int D>
void no_slip_velocity(Particles<D>& P, const std::vector<double>& shepard, std::ptrdiff_t b) {
  if (P.kind[b] != Kind::boundary) {
    P.v_noslip[b] = P.v[b];
    return;
  }
  const double weight = shepard[b];
  P.v_noslip[b] = weight > 0.0 ? Vec<D>(2.0 * P.v[b] - P.v_noslip[b] / weight) : P.v[b];
}

// A particle of mass m appears (sign +1) or disappears (-1) at x (wrapped):
// change the density of the fixed boundary particles around it by its kernel
// share m W, as a summation density would, so continuity does not keep a
// memory of particles that an inlet created or an outlet removed. Boundary
// particles never move, so the cells of the last binning still hold them.
template <int D>
void book_boundary_density(Particles<D>& P, const CellList<D>& cells, const WendlandC2<D>& kernel, const Vec<D>& x,
                           double m, double sign) {
  const double support2 = kernel.support_radius() * kernel.support_radius();
  cells.for_each_neighbour(x, [&](int b, const Vec<D>& shift) {
    if (static_cast<std::size_t>(b) >= P.size() || P.kind[b] != Kind::boundary) return;
    const double r2 = (P.x[b] + shift - x).squaredNorm();
    if (r2 < support2) P.rho[b] += sign * m * kernel.value(std::sqrt(r2));
  });
}

}  // namespace sph
