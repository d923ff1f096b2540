// Eq. 10 (Morris viscosity) on the tensor path (pair_loop.h's pair_terms).
#pragma once
#include "particles.h"
#include "vec.h"

namespace sph {

// Eq. 10 for owner a and neighbour b: 2 mu_ab (r_ab . grad W)/(r_ab^2 + 0.01 h^2) m/(rho_a rho_b) times the
// velocity difference, each side against the other's no-slip velocity (va, vns_a: a's velocity and no-slip
// velocity, m/s; jump: b's image's Lees-Edwards jump (Sheared); mu_row: a's row of mu_ab (Several); F, r2: the
// pair's grad_a W = F r_ab and r_ab^2; vol_a, inv_rho_a: a's volume and 1/rho_a). AMoves, BMoves: which side moves.
template <bool AMoves, bool BMoves, bool Sheared, bool Several, int D, class Morris>
inline __attribute__((always_inline)) void tensor_morris_pair(Particles<D>& P, const Morris& morris, int b, double F,
                                                              double r2, const Vec<D>& jump, const Vec<D>& va,
                                                              const Vec<D>& vns_a, double vol_a, double inv_rho_a,
                                                              const double* mu_row, Vec<D>& acc_a) {
  const Vec<D>* const v = P.v.data();
  const Vec<D>* const v_noslip = P.v_noslip.data();
  const double* const vol = P.vol.data();
  const double rho_b = P.rho[b];
  Vec<D>* const acc = P.acc.data();
  double s;
  if constexpr (Several) s = morris.factor(mu_row[P.material[b]], F, r2);
  else s = morris.factor(F, r2);
  if constexpr (Sheared) {
    if constexpr (AMoves) acc_a.noalias() += (s * vol[b] * inv_rho_a) * (va - v_noslip[b] - jump);
    if constexpr (BMoves) acc[b].noalias() += (s * vol_a / rho_b) * (v[b] + jump - vns_a);
  } else {
    if constexpr (AMoves) acc_a.noalias() += (s * vol[b] * inv_rho_a) * (va - v_noslip[b]);
    if constexpr (BMoves) acc[b].noalias() += (s * vol_a / rho_b) * (v[b] - vns_a);
  }
  (void)jump, (void)mu_row, (void)v, (void)v_noslip, (void)vol, (void)rho_b, (void)acc;
}

}  // namespace sph
