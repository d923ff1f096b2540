// The fluid's pair forces on the particles of rigid grains (grains.h), in the scalar path's pass C (pair_loop.h).
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

}  // namespace sph
