// The fluid-fluid rows of the plain scalar path (pair_loop.h: one material, no Lees-Edwards, eddy viscosity,
// eq. VC1 or grains) four pairs at a time. Each particle's values that a pair reads are packed once per
// evaluation into three 4-wide records, [x y z rho], [v_x v_y v_z p/rho^2], [m/rho c m 1/rho] (2D: z = 0), so that
// a neighbour costs three aligned loads; four neighbours' records are transposed in registers into lanes (one
// pair per lane), the terms of eqs. 7, 9, 10 (fluid-fluid: v~ = v) and 11-12 are evaluated on the lanes, and
// b's share [dv/dt, drho/dt] is transposed back and added to b's packed sum with one 4-wide add. a's share is
// summed per lane and the lanes added as (l0 + l1) + (l2 + l3) at the row's end; the packed sums are added to
// acc and drho after the pair loop (unpack).
// Lanes are GCC vector types: 4-wide AVX instructions in the AVX2 copy of the pair loop, pairs of SSE2
// instructions in the other; both make the same IEEE operations in the same order (no FMA), so results do
// not depend on the CPU, and every particle receives its sums in the order of the blocks (not of the
// threads). Skin pairs (beyond 2h) and the padding of a row's last four (a far-away record) give F = 0:
// exact zeros.
#pragma once
#include <cstdint>
#include <vector>

#include "box_policy.h"
#include "neighbour_list.h"
#include "particles.h"

// Every function that takes or returns Lanes is inlined: no call passes them, so the ABI note of GCC (32-byte
// vectors passed differently with and without AVX) concerns no call of this program.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace sph {

// Set by the tests: the SSE2 copies of the pair loop also where the CPU has AVX2.
inline bool sse2_only = false;

typedef double Lanes __attribute__((vector_size(32)));           // 4 doubles
typedef std::int64_t LaneIndex __attribute__((vector_size(32)));  // shuffle indices of 4 lanes

// Records r0..r3 of 4 values each become the 4 values' lanes: r_j[i] -> r_i[j].
inline __attribute__((always_inline)) void transpose4(Lanes& r0, Lanes& r1, Lanes& r2, Lanes& r3) {
  const Lanes t0 = __builtin_shuffle(r0, r1, LaneIndex{0, 4, 2, 6}), t1 = __builtin_shuffle(r0, r1, LaneIndex{1, 5, 3, 7});
  const Lanes t2 = __builtin_shuffle(r2, r3, LaneIndex{0, 4, 2, 6}), t3 = __builtin_shuffle(r2, r3, LaneIndex{1, 5, 3, 7});
  r0 = __builtin_shuffle(t0, t2, LaneIndex{0, 1, 4, 5}), r1 = __builtin_shuffle(t1, t3, LaneIndex{0, 1, 4, 5});
  r2 = __builtin_shuffle(t0, t2, LaneIndex{2, 3, 6, 7}), r3 = __builtin_shuffle(t1, t3, LaneIndex{2, 3, 6, 7});
}
inline __attribute__((always_inline)) double lane_sum(Lanes s) { return (s[0] + s[1]) + (s[2] + s[3]); }

template <int D>
class PairLanes {
 public:
  struct alignas(32) Record {
    Lanes xr, vp, vm;  // [x y z rho], [v_x v_y v_z p/rho^2], [m/rho c m 1/rho]
  };
  struct alignas(32) Sum {
    Lanes s;  // [dv_x dv_y dv_z drho]/dt
  };

  // The periodic images' shifts (at each list build; they change only under Lees-Edwards, which runs without).
  void set_shifts(const Vec<D>* shifts) {
    for (int code = 0; code < PeriodicImages<D>::codes; ++code) shifts_[code] = lanes_of(shifts[code], 0.0);
  }
  // Room for n particles and the far-away record n that pads a row's last lanes. Before each evaluation, on one
  // thread: open boundaries add and remove particles between list builds.
  void fit(std::size_t n) {
    if (sums_.size() == n) return;
    if (records_.capacity() < n + 1) records_.reserve(n + n / 4 + 1), sums_.reserve(n + n / 4 + 1);
    records_.resize(n + 1), sums_.resize(n);
    records_[n] = Record{Lanes{far, far, far, 1.0}, Lanes{}, Lanes{0.0, 0.0, 0.0, 1.0}};
  }
  // Particle i's record from its current state (after the equation of state), its sum zeroed.
  inline __attribute__((always_inline)) void pack(const Particles<D>& P, std::ptrdiff_t i, bool sound_speed) {
    records_[i] = Record{lanes_of(P.x[i], P.rho[i]), lanes_of(P.v[i], P.p_rho2[i]),
                         Lanes{P.vol[i], sound_speed ? P.c[i] : 0.0, P.mass[i], 1.0 / P.rho[i]}};
    sums_[i].s = Lanes{};
  }
  // Adds particle i's packed sum to its acc and drho.
  inline __attribute__((always_inline)) void unpack(Particles<D>& P, std::ptrdiff_t i) const {
    for (int d = 0; d < D; ++d) P.acc[i][d] += sums_[i].s[d];
    P.drho[i] += sums_[i].s[3];
  }

  // Owner a (fluid) with its fluid neighbours, entries [e, end): eqs. 7, 9, with AV eqs. 11-12, with Morris
  // eq. 10. Model: the loop's FluidModel; grad_factor, inv_h: the kernel's (eq. 8). The terms are those of
  // pair_chunk.h, with the constants gathered: Pi_ab = -alpha h (c_a + c_b) min(v_ab . r_ab, 0) / ((r^2 + eta^2)
  // (rho_a + rho_b)) (+ the beta term), dv_a/dt -= m_b (p_a/rho_a^2 + p_b/rho_b^2 + Pi_ab) F r_ab.
  // With the model's density diffusion on, eq. DD1 (physics_terms.h) as well.
  template <bool AV, bool Morris, class Model>
  inline __attribute__((always_inline)) void row(int a, const std::uint32_t* e, const std::uint32_t* end,
                                                 const Model& model, double inv_h, double grad_factor) {
    if (model.diffusion.on()) row<AV, Morris, true>(a, e, end, model, inv_h, grad_factor);
    else row<AV, Morris, false>(a, e, end, model, inv_h, grad_factor);
  }
  template <bool AV, bool Morris, bool Diffusion, class Model>
  inline __attribute__((always_inline)) void row(int a, const std::uint32_t* e, const std::uint32_t* end,
                                                 const Model& model, double inv_h, double grad_factor) {
    const Record& A = records_[a];
    const Owner o{A.xr * Lanes{1, 1, 1, 0}, A.vp * Lanes{1, 1, 1, 0}, lanes_of(model.diffusion.g_rho, 0.0),
                  A.xr[3], A.vp[3], A.vm[0], A.vm[1], A.vm[2],
                  A.vm[3], 0.5 * inv_h, 4.0 / (inv_h * inv_h) * (1.0 + 1e-9), grad_factor};
    Sums acc{};
    for (; end - e >= 4; e += 4) group<AV, Morris, Diffusion, false>(o, e, 4, model, acc);
    if (e < end) group<AV, Morris, Diffusion, true>(o, e, end - e, model, acc);
    sums_[a].s += Lanes{lane_sum(acc.x), lane_sum(acc.y), lane_sum(acc.z), lane_sum(acc.rho)};
  }

 private:
  // Owner a's values (x, v with 0 in the fourth lane) and the kernel's constants; beyond2: (2h)^2 (1 + 1e-9),
  // beyond which q > 2 whatever the rounding.
  struct Owner {
    Lanes x, v, g_rho;  // g_rho: eq. DD1's rho0/c0^2 g, [g_x g_y g_z 0]
    double rho, p_rho2, vol, c, m, inv_rho, half_inv_h, beyond2, grad_factor;
  };
  struct Sums {
    Lanes x, y, z, rho;  // a's sums per lane
  };
  // Four entries of a's row, [e, e + 4) (Tail: the row's last `left` < 4, the rest padded with the far record).
  template <bool AV, bool Morris, bool Diffusion, bool Tail, class Model>
  inline __attribute__((always_inline)) void group(const Owner& o, const std::uint32_t* e, std::ptrdiff_t left,
                                                   const Model& model, Sums& acc) {
    using List = NeighbourList<D>;
    const std::uint32_t pad = static_cast<std::uint32_t>(records_.size() - 1) << List::shift_bits | List::centre_code;
    int b[4];
    Lanes R[4], V[4], M[4];
    for (int l = 0; l < 4; ++l) {
      const std::uint32_t entry = !Tail || l < left ? e[l] : pad;
      b[l] = static_cast<int>(entry >> List::shift_bits);
      R[l] = (o.x - records_[b[l]].xr) - shifts_[entry & List::shift_mask];  // [r_ab, -rho_b]
    }
    transpose4(R[0], R[1], R[2], R[3]);
    const Lanes rx = R[0], ry = R[1], rz = R[2];
    const Lanes r2 = (rx * rx + ry * ry) + rz * rz;
    // Four pairs beyond the support (the skin, listed after the pairs within it at the build: neighbour_list.h)
    // add exact zeros: skipped.
    const LaneIndex within = r2 < o.beyond2;
    if (((within[0] | within[1]) | (within[2] | within[3])) == 0) return;
    for (int l = 0; l < 4; ++l) {
      const Record& B = records_[b[l]];
      V[l] = o.v - B.vp, M[l] = B.vm;  // [v_ab, -p_b/rho_b^2], [V_b c_b m_b 1/rho_b]
    }
    transpose4(V[0], V[1], V[2], V[3]), transpose4(M[0], M[1], M[2], M[3]);
    const Lanes vx = V[0], vy = V[1], vz = V[2];
    const Lanes vr = (vx * rx + vy * ry) + vz * rz;
    Lanes q;
    for (int l = 0; l < 4; ++l) q[l] = __builtin_sqrt(r2[l]);
    const Lanes u = 1.0 - q * o.half_inv_h;
    const Lanes t = u > 0.0 ? u : Lanes{};
    const Lanes F = (t * t) * (t * o.grad_factor), Fvr = F * vr;  // eq. 8; v_ab . grad_a W_ab
    acc.rho += (o.rho * M[0]) * Fvr;                               // eq. 7 for a and for b
    Lanes drho_b = (R[3] * o.vol) * -Fvr;
    if constexpr (Diffusion) {  // eq. DD1: w (rho_a - rho_b - rho0/c0^2 g . r_ab), times V_b for a, -V_a for b
      const Lanes g_r = (o.g_rho[0] * rx + o.g_rho[1] * ry) + o.g_rho[2] * rz;
      const Lanes w = model.diffusion.kappa2 * (F * r2) / (r2 + model.diffusion.eta2) * ((o.rho + R[3]) - g_r);
      acc.rho += w * M[0];
      drho_b -= w * o.vol;
    }
    Lanes P = o.p_rho2 - V[3];  // p_a/rho_a^2 + p_b/rho_b^2
    if constexpr (AV) P += artificial_pi(model.artificial, r2, vr, o.rho - R[3], o.c + M[1]);
    const Lanes PF = P * F, ga = M[2] * PF, gb = o.m * PF;
    acc.x -= ga * rx, acc.y -= ga * ry, acc.z -= ga * rz;
    Lanes bx = gb * rx, by = gb * ry, bz = gb * rz;
    if constexpr (Morris) {  // eq. 10: 2 mu F r^2 / (r^2 + 0.01 h^2) m_b / (rho_a rho_b) v_ab, the opposite for b
      const Lanes s = (2.0 * model.morris.mu) * (F * r2) / (r2 + model.morris.eta2);
      const Lanes visc_a = (s * M[0]) * o.inv_rho, visc_b = (s * o.vol) * M[3];
      acc.x += visc_a * vx, acc.y += visc_a * vy, acc.z += visc_a * vz;
      bx -= visc_b * vx, by -= visc_b * vy, bz -= visc_b * vz;
    }
    Lanes dr = drho_b;
    transpose4(bx, by, bz, dr);
    const Lanes out[4] = {bx, by, bz, dr};
    for (int l = 0; l < (Tail ? left : 4); ++l) sums_[b[l]].s += out[l];
  }

  static constexpr double far = 1e20;  // m: the padding record, beyond any support
  static inline __attribute__((always_inline)) Lanes lanes_of(const Vec<D>& x, double w) { return Lanes{x[0], x[1], D == 3 ? x[D - 1] : 0.0, w}; }
  // Eq. 11 on lanes from rho_a + rho_b and c_a + c_b: Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab with
  // mu_ab = h min(v_ab . r_ab, 0) / (r^2 + eta^2) and the pair means c_ab, rho_ab.
  template <class Artificial>
  static inline __attribute__((always_inline)) Lanes artificial_pi(const Artificial& av, Lanes r2, Lanes vr,
                                                                   Lanes rho_sum, Lanes c_sum) {
    const Lanes d = r2 + av.eta2, hv = (vr < 0.0 ? vr : Lanes{}) * av.h;  // h min(v_ab . r_ab, 0)
    const Lanes inv = 1.0 / (d * rho_sum);
    const Lanes pi = ((-av.alpha) * c_sum) * hv * inv;
    if (av.beta == 0.0) return pi;
    return pi + ((2.0 * av.beta) * hv) * (hv * inv) / d;
  }

  std::vector<Record> records_;
  std::vector<Sum> sums_;  // of the fluid-fluid rows
  Lanes shifts_[PeriodicImages<D>::codes] = {};  // m: the shift of each image code, [s_x s_y s_z 0]
};

}  // namespace sph
