// Stress diffusion of the PTT mode stresses (eq. SD1 of materials/ptt.h; the deck's `stress_diffusion`, kappa m^2/s):
//   d tau_i,a/dt += kappa sum_b V_b 2 F_ab r_ab^2 / (r_ab^2 + 0.01 h^2) (tau_i,a - tau_i,b)
// the Laplacian of each mode stress in the form of the Morris term (eq. 10), gathered in the tensor pair loop
// (Particles::mode_laplacian, zeroed with the other sums) and added to the rates after eq. R1. A uniform stress
// gives zero, so homogeneous shear keeps its closed form. Configuration PTT + Morris in a Lees-Edwards cell.
#pragma once
#include <cstddef>

#include "material.h"
#include "particles.h"
#include "vec.h"

namespace sph {

// The fluid pair a, b (grad_a W_ab = F r_ab, r2 = r_ab^2 m^2, h m): with w = 2 F r^2 / (r^2 + 0.01 h^2),
// w V_b (tau_a - tau_b) into a's sum and w V_a (tau_b - tau_a) into b's, per mode stress column.
template <int D>
inline __attribute__((always_inline)) void stress_diffusion_pair(Particles<D>& P, int a, int b, double F, double r2,
                                                                 double h) {
  const double w = 2.0 * F * r2 / (r2 + 0.01 * h * h);
  const double* const ta = P.mode_stress.value[a].data();
  const double* const tb = P.mode_stress.value[b].data();
  double* const la = P.mode_laplacian[a].data();
  double* const lb = P.mode_laplacian[b].data();
  const double wa = w * P.vol[b], wb = w * P.vol[a];
  const Eigen::Index n = P.mode_stress.value[a].size();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double d = ta[k] - tb[k];
    la[k] += wa * d, lb[k] -= wb * d;
  }
}

// The gather's zero of particle i's Laplacian sums (On: the configuration diffuses).
template <bool On, int D>
void clear_laplacian(Particles<D>& P, std::ptrdiff_t i) {
  if constexpr (On) P.mode_laplacian[i].setZero();
  else (void)P, (void)i;
}

// After eq. R1 of fluid particle a: kappa of its material times its Laplacian sums.
template <int D>
void add_stress_diffusion(Particles<D>& P, const MaterialTable& materials, std::ptrdiff_t a) {
  P.mode_stress.rate[a] += materials[P.material[a]].modes.diffusion * P.mode_laplacian[a];
}

}  // namespace sph
