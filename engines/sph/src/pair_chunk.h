// Pass B of the scalar path's pair loop (pair_loop.h): the per-pair coefficients of eqs. 7, 9-12 over a chunk
// of up to 128 pairs gathered into plain arrays, so that the compiler vectorises it.
#pragma once
#include <cmath>

#include "physics_terms.h"

namespace sph {

// Pass B's inputs and outputs for one chunk (f_a, f_b: the terms along
// r_ab of a and of b, m/s^2).
template <int D>
struct PairChunk {
  static constexpr int size = 128;  // pairs
  int b[size], code[size];
  double r[D][size], r2[size], vr[size];
  double m[size], rho[size], vol[size], p_rho2[size], c[size], mu[size], corr[size];
  double drho_a[size], drho_b[size], f_a[D][size], f_b[D][size], visc_a[size], visc_b[size];
  double vg[D][size], F[size];  // eddy: the velocity difference of eq. SM1 (no-slip against a fixed particle), F
};

// Owner a's values for pass B (corr: its factor k_a of eq. VC1 when corrected).
struct PairOwner {
  double m, rho, vol, p_rho2, inv_rho, c, inv_h, grad_factor, corr;
};

// Pass B over pairs [0, n) of a chunk: kernel factor, eq. 7 for both sides,
// eq. 9 (+ eqs. 11-12) along r_ab, eq. 10's factors.
// Loop: the PairLoop (pair_loop.h) whose terms it evaluates.
template <class Loop, bool AMoves, bool BMoves, int D>
inline __attribute__((always_inline)) void pair_coefficients(PairChunk<D>& k, int n, const PairOwner& o,
                                                             const typename Loop::Model& model) {
  for (int j = 0; j < n; ++j) {
    const double u = 1.0 - 0.5 * (std::sqrt(k.r2[j]) * o.inv_h);
    const double t = 0.5 * (u + std::abs(u));      // exactly max(u, 0), without a branch
    const double F = o.grad_factor * (t * t * t);  // grad_a W_ab = F r_ab (eq. 8)
    const double Fvr = F * k.vr[j];                // v_ab . grad_a W_ab (= v_ba . grad_b W_ba)
    // Eq. 7 for fluid (drho_a = rho_a sum m_b/rho_b v_ab . grad W), the summation rate otherwise.
    k.drho_a[j] = (AMoves ? o.rho * k.vol[j] : k.m[j]) * Fvr;
    k.drho_b[j] = (BMoves ? k.rho[j] * o.vol : o.m) * Fvr;
    if constexpr (AMoves && BMoves) {  // eq. DD1 between two fluid particles (physics_terms.h)
      if (model.diffusion.on()) {
        Vec<D> r_ab;
        for (int d = 0; d < D; ++d) r_ab[d] = k.r[d][j];
        const double w = model.diffusion.rate(F, k.r2[j], o.rho, k.rho[j], r_ab);
        k.drho_a[j] += w * k.vol[j], k.drho_b[j] -= w * o.vol;
      }
    }
    if constexpr (AMoves || BMoves) {
      double radial = -(o.p_rho2 + k.p_rho2[j]) * F;  // eq. 9, along r_ab
      if constexpr (Loop::has(term::artificial_viscosity)) {  // eqs. 11-12 (times 0 or 1 against a fixed particle)
        double pi = model.artificial.pi(k.r2[j], k.vr[j], o.rho, k.rho[j], o.c, k.c[j]);
        if constexpr (!(AMoves && BMoves)) pi *= model.artificial.wall;
        radial -= pi * F;
      }
      const double radial_a = k.m[j] * radial, radial_b = o.m * radial;
      for (int d = 0; d < D; ++d) k.f_a[d][j] = radial_a * k.r[d][j], k.f_b[d][j] = radial_b * k.r[d][j];
      if constexpr (Loop::has(term::morris_viscosity)) {
        // Eq. 10: 2 mu_ab (r_ab . grad W)/(r_ab^2 + 0.01 h^2) m/(rho_a rho_b).
        double s;
        if constexpr (Loop::pair_mu) s = model.morris.factor(k.mu[j], F, k.r2[j]);
        else s = model.morris.factor(F, k.r2[j]);
        if constexpr (Loop::eddy) k.F[j] = F;
        if constexpr (Loop::corrected) {  // eq. VC1: each moving side its own factor; against a fixed particle
          // both sides take the moving one's, so a grain's reaction (eq. G1) is the fluid's force, opposite
          const double ka = (AMoves || !BMoves) ? o.corr : k.corr[j], kb = (BMoves || !AMoves) ? k.corr[j] : o.corr;
          k.visc_a[j] = ka * (s * k.vol[j] * o.inv_rho), k.visc_b[j] = kb * (s * o.vol / k.rho[j]);
        } else
          k.visc_a[j] = s * k.vol[j] * o.inv_rho, k.visc_b[j] = s * o.vol / k.rho[j];
      }
    }
  }
}

}  // namespace sph
