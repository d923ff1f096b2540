// Fixed boundary particles: their no-slip velocity for the viscous term (and
// the velocity gradient, eq. T2), their extra stress (tensor configurations)
// and their density when an open boundary adds or removes a particle nearby.
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

// Extra stress of fixed boundary particles (tensor configurations: models
// with a deviatoric stress): a boundary particle b takes the Shepard average
// of the extra stress of the fluid around it,
//   tau_b = sum_f tau_f W_bf / sum_f W_bf                                  (eq. W1)
// per mode (and the solvent stress, or the single tau), as Adami et al. 2012
// extrapolate the pressure into the wall, so the fluid next to a wall feels
// the wall shear stress in eq. T1 instead of its own stress alone. A boundary
// particle with no fluid in its support keeps zero extra stress. Its pressure
// is unchanged (eq. 6 of its own density). The sums are taken with the
// no-slip sums (PairLoop::no_slip_sums_of_block), over the same weights.
// Set the sums of boundary particle b to zero (start of the gather stage).
template <class Models, int D>
void clear_wall_stress(Particles<D>& P, std::ptrdiff_t b) {
  if (P.kind[b] != Kind::boundary) return;
  if constexpr (Models::any_single_stress) P.tau[b].setZero();
  if constexpr (Models::any_modes) P.mode_stress.value[b].setZero(), P.tau_solvent[b].setZero();
}
// Add fluid particle f's stress with weight w to the sums of boundary particle b.
template <class Models, int D>
inline void add_wall_stress(Particles<D>& P, int b, int f, double w) {
  if constexpr (Models::any_single_stress) P.tau[b].noalias() += w * P.tau[f];
  if constexpr (Models::any_modes) {
    P.mode_stress.value[b].noalias() += w * P.mode_stress.value[f];
    P.tau_solvent[b].noalias() += w * P.tau_solvent[f];
  }
}
// Divide the sums of boundary particle b by its Shepard weight (eq. W1).
template <class Models, int D>
void wall_stress(Particles<D>& P, const std::vector<double>& shepard, std::ptrdiff_t b) {
  if (P.kind[b] != Kind::boundary || !(shepard[b] > 0.0)) return;
  const double inv = 1.0 / shepard[b];
  if constexpr (Models::any_single_stress) P.tau[b] *= inv;
  if constexpr (Models::any_modes) P.mode_stress.value[b] *= inv, P.tau_solvent[b] *= inv;
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
