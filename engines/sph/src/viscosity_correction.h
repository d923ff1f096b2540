// The renormalised Morris viscous term (deck key `viscosity_correction`,
// term::viscosity_correction; off by default).
//
// Eq. 10 sums, over the neighbours b of a fluid particle a,
//   dv_a/dt = sum_b 2 mu V_b / rho_a  g_ab (v_a - v_b),  g_ab = F_ab r_ab^2 / (r_ab^2 + eta^2)
// (F_ab: grad_a W_ab = F_ab r_ab, eta^2 = 0.01 h^2; MorrisViscosity in physics_terms.h).
// For a quadratic field v = v_a + (x - x_a) . grad v + 1/2 (x - x_a)^T A (x - x_a) the
// sum is nu sum_ij A_ij S_ij with the weighted second moment
//   S_a = sum_b V_b (-g_ab) r_ab r_ab^T,
// when the first moment vanishes (a particle inside a full, symmetric support).
// The exact Laplacian nu tr(A) needs S_a = I. The continuous integral gives
// tr(S) = D (1 - O(eta^2 / h^2)); the lattice sum falls short: at h = 1.3 dx
// tr(S_a) / D = 0.9696 on a cubic 3D lattice, 0.9627 on a square 2D one (the
// Morris sum gives 0.97 of the Laplacian; tests/test_viscosity_correction.cpp).
// With the correction each particle's viscous sum is scaled by
//   k_a = D / tr(S_a) = D / sum_b V_b (-F_ab) r_ab^4 / (r_ab^2 + eta^2)         (eq. VC1)
// (Schwaiger 2008 and Fatehi & Manzari 2011 correct with the full matrix; where
// S_a is isotropic, as on a cubic lattice by symmetry, the trace is all of it):
//   dv_a/dt = k_a sum_b 2 mu V_b / rho_a g_ab (v_a - v_b).
// The sum runs over every neighbour the viscous term sees (fluid, boundary
// particles with their no-slip velocity, inlet and outlet buffers), with the
// V_b = m_b / rho_b the pair loop uses (a boundary particle's from eq. WP3).
// A pair's two sides then take k_a and k_b: the viscous forces of a pair are
// equal and opposite only where k_a = k_b (a uniform lattice), so the term
// no longer conserves momentum exactly (the fluid's total momentum changes by
// sum_ab (k_a - k_b) ..., zero on a regular lattice).
// The sums are taken in a pass over the half list before the pair loop
// (PairLoop::rates), both particles of a pair at once, in the block colours of
// the list (bitwise independent of the thread count).
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernel.h"
#include "neighbour_list.h"
#include "particles.h"

namespace sph {

template <int D>
class ViscosityCorrection {
 public:
  // After a list build (particles reordered, added or removed): one zero sum per particle.
  void resize(std::size_t n) { sum_.assign(n, 0.0), factor_.resize(n); }

  // The sums tr(S) of eq. VC1 over the pairs owned by the particles of block k (to both particles). As the
  // pair loop: compiled for SSE2 and for AVX2 without FMA, chosen at run time (the same roundings); each row in
  // chunks: gather r^2, the per-pair weights in a loop the compiler vectorises, then the sums in list order.
  void sums_of_block(const NeighbourList<D>& list, const Particles<D>& P, const WendlandC2<D>& kernel, double eta2,
                     int k) {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) sums_of_block_avx2(list, P, kernel, eta2, k);
    else sums_of_block_default(list, P, kernel, eta2, k);
  }
  __attribute__((target("avx2"), noinline)) void sums_of_block_avx2(const NeighbourList<D>& list,
                                                                    const Particles<D>& P,
                                                                    const WendlandC2<D>& kernel, double eta2, int k) {
    sums(list, P, kernel, eta2, k);
  }
  __attribute__((noinline)) void sums_of_block_default(const NeighbourList<D>& list, const Particles<D>& P,
                                                       const WendlandC2<D>& kernel, double eta2, int k) {
    sums(list, P, kernel, eta2, k);
  }
  // k_i of eq. VC1 from its sum (1 without neighbours); the sum is set to zero for the next evaluation.
  void finish_at(std::ptrdiff_t i) {
    factor_[i] = sum_[i] > 0.0 ? D / sum_[i] : 1.0;
    sum_[i] = 0.0;
  }
  const double* factors() const { return factor_.data(); }

 private:
  static constexpr int chunk = 128;
  inline __attribute__((always_inline)) void sums(const NeighbourList<D>& list, const Particles<D>& P,
                                                  const WendlandC2<D>& kernel, double eta2, int k) {
    using List = NeighbourList<D>;
    const std::uint32_t* const e = list.entries(k);
    const Vec<D>* const shifts = list.shifts();
    const Vec<D>* const x = P.x.data();
    const double* const vol = P.vol.data();
    const double inv_h = kernel.inv_h, minus_grad_factor = -kernel.grad_factor;
    int b[chunk];
    double g[chunk];
    for (int a = list.block_begin(k); a < list.block_end(k); ++a) {
      const auto& row = list.row(a);
      double sum_a = 0.0;
      for (int j0 = row.begin; j0 < row.end; j0 += chunk) {
        const int n = row.end - j0 < chunk ? row.end - j0 : chunk;
        for (int i = 0; i < n; ++i) {
          const std::uint32_t entry = e[j0 + i];
          b[i] = static_cast<int>(entry >> List::shift_bits);
          g[i] = (x[a] - x[b[i]] - shifts[entry & List::shift_mask]).squaredNorm();  // r^2
        }
        for (int i = 0; i < n; ++i) {
          const double r2 = g[i];
          const double u = 1.0 - 0.5 * (std::sqrt(r2) * inv_h);
          const double t = 0.5 * (u + std::abs(u));  // max(u, 0): pairs of the skin add zeros
          g[i] = minus_grad_factor * (t * t * t) * r2 * r2 / (r2 + eta2);  // -F r^4 / (r^2 + eta^2)
        }
        for (int i = 0; i < n; ++i) sum_a += vol[b[i]] * g[i], sum_[b[i]] += vol[a] * g[i];
      }
      sum_[a] += sum_a;
    }
  }

  std::vector<double> sum_, factor_;
};

}  // namespace sph
