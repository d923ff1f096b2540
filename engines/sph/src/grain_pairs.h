// The fluid's pair forces on the particles of rigid grains (grains.h), in the scalar path's pass C and in the tensor
// path's pair terms (pair_loop.h).
// A grain's particle g is a moving boundary particle: the fluid particle f takes eqs. 9-12 against it, and eq. 10
// against its no-slip velocity v~_g (boundary_particles.h, with the grain's rigid velocity as the wall's), as from
// a fixed wall. The grain's particle takes the reaction of the same pair, term by term:
//   dv_g/dt += m_f (p_f/rho_f^2 + p_g/rho_g^2 + Pi_fg) F r_fg + s_fg V_f / rho_g (v~_g - v_f)          (G1)
// (r_fg = x_f - x_g, grad_f W_fg = F r_fg, s_fg eq. 10's factor of the pair: pass B's f_b and visc_b), so
// m_f dv_f/dt + m_g dv_g/dt = 0 pair by pair (to rounding) and the grain's sum of m_g dv_g/dt (eq. G2) is the
// fluid's force on it. Under Lees-Edwards the velocity differences carry the image's jump, as the fluid's do.
// The viscous reactions also sum, per grain particle, the lever
//   q_g = sum_f s_gf (x_g - x_f)                                                                       (G5)
// (s_gf the grain side's factor, visc_b or visc_a) for the torque's correction of grains.h: the part of eq. 10's
// reaction that answers the grain's own rotation, s_gf omega x (x_g - x_f), is the Laplacian's flux of a rigid
// rotation, which carries no stress.
#pragma once
#include "pair_chunk.h"
#include "particles.h"
#include "vec.h"

namespace sph {

// Pair j of chunk k between owner a and neighbour b, exactly one of them fluid (AMoves: a): the reaction of eq. G1
// on the other when it is a grain's particle (into P.acc[b], or acc_a, the owner's sum). va, vns_a: a's velocity
// and no-slip velocity; jumps: the list's Lees-Edwards jumps per image code (Sheared).
template <bool AMoves, bool Morris, bool Sheared, int D>
inline __attribute__((always_inline)) void grain_reaction(Particles<D>& P, const PairChunk<D>& k, int j, int a, int b,
                                                          const Vec<D>& va, const Vec<D>& vns_a, const Vec<D>* jumps,
                                                          Vec<D>& acc_a) {
  if constexpr (AMoves) {  // a fluid, b fixed: b's reaction when it is a grain's
    if (P.kind[b] != Kind::body) return;
    Vec<D> f_b;
    for (int d = 0; d < D; ++d) f_b[d] = k.f_b[d][j];
    Vec<D>& acc_b = P.acc[b];
    acc_b.noalias() -= f_b;
    if constexpr (Morris) {
      Vec<D> dv = P.v_noslip[b] - va;
      if constexpr (Sheared) dv += jumps[k.code[j]];
      acc_b.noalias() += k.visc_b[j] * dv;
      Vec<D> r;  // r_ab = x_a - x_b: the lever of eq. G5 takes s_b (x_b - x_a)
      for (int d = 0; d < D; ++d) r[d] = k.r[d][j];
      P.grain_lever[b].noalias() -= k.visc_b[j] * r;
    }
    (void)vns_a, (void)acc_a;
  } else {  // a fixed, b fluid: a's reaction when it is a grain's
    if (P.kind[a] != Kind::body) return;
    Vec<D> f_a;
    for (int d = 0; d < D; ++d) f_a[d] = k.f_a[d][j];
    acc_a.noalias() += f_a;
    if constexpr (Morris) {
      Vec<D> dv = vns_a - P.v[b];
      if constexpr (Sheared) dv -= jumps[k.code[j]];
      acc_a.noalias() += k.visc_a[j] * dv;
      Vec<D> r;  // r_ab = x_a - x_b, a the grain's particle (a's row: one thread)
      for (int d = 0; d < D; ++d) r[d] = k.r[d][j];
      P.grain_lever[a].noalias() += k.visc_a[j] * r;
    }
    (void)va;
  }
  (void)jumps;
}

// The tensor path's eq. G1 (pair_loop.h's pair_terms) between owner a and neighbour b, exactly one of them moving
// (AMoves: a): the other takes the pair's reaction when it is a grain's particle. f: the pair force of eq. T1 with
// eqs. 11-12 (the factor of m_b in dv_a/dt); eq. 10's factor s from F, r^2 and mu_ab (mu_row: a's row, Several) or
// the one mu; va, vns_a: a's velocity and no-slip velocity; r = x_a - x_b.
template <bool AMoves, bool Morris, bool Several, int D, class Morris_>
inline __attribute__((always_inline)) void tensor_grain_reaction(Particles<D>& P, const Morris_& morris,
                                                                 const double* mu_row, int a, int b, double F,
                                                                 double r2, const Vec<D>& f, const Vec<D>& va,
                                                                 const Vec<D>& vns_a, const Vec<D>& r, Vec<D>& acc_a) {
  const int g = AMoves ? b : a, m = AMoves ? a : b;  // the grain's particle and the moving one
  if (P.kind[g] != Kind::body) return;
  Vec<D>& acc_g = AMoves ? P.acc[b] : acc_a;
  const double m_m = P.mass[m];
  for (int d = 0; d < D; ++d) acc_g[d] += (AMoves ? -m_m : m_m) * f[d];
  if constexpr (Morris) {
    double s;
    if constexpr (Several) s = morris.factor(mu_row[P.material[b]], F, r2);
    else s = morris.factor(F, r2);
    const double factor = s * P.vol[m] / P.rho[g];  // eq. 10 on the grain's side: s V_m / rho_g
    const Vec<D> dv = AMoves ? Vec<D>(va - P.v_noslip[b]) : Vec<D>(P.v[b] - vns_a);  // the moving one's against v~_g
    for (int d = 0; d < D; ++d) acc_g[d] -= factor * dv[d];
    for (int d = 0; d < D; ++d) P.grain_lever[g][d] += (AMoves ? -factor : factor) * r[d];  // eq. G5: s (x_g - x_m)
  }
  (void)mu_row, (void)F, (void)r2, (void)va, (void)vns_a, (void)r;
}

}  // namespace sph
