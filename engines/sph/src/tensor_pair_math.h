// The tensor pair loop's 3 x 3 updates as plain loops the compiler inlines (pair_loop.h). Its rows are compiled
// for AVX2 as well as SSE2, and the fixed-size Eigen expressions there stayed out-of-line calls (a third of the
// solid's pair time). Plain double operations without FMA round alike on both, as the rest of the loop does.
#pragma once
#include "vec.h"

namespace sph {

// Eq. T2's sums of a pair for both particles: X -= w u r^T and M -= w r r^T with w_a for a, w_b for b.
template <int D>
inline __attribute__((always_inline)) void subtract_outer_products(const Vec<D>& u, const Vec<D>& r, double w_a,
                                                                    double w_b, Mat<D>& G_a, Mat<D>& M_a, Mat<D>& G_b,
                                                                    Mat<D>& M_b) {
  for (int j = 0; j < D; ++j)
    for (int i = 0; i < D; ++i) {
      const double ur = u[i] * r[j], rr = r[i] * r[j];
      G_a(i, j) -= w_a * ur, M_a(i, j) -= w_a * rr, G_b(i, j) -= w_b * ur, M_b(i, j) -= w_b * rr;
    }
}

// (S_a + S_b) g for the pair's stress S_a + S_b and g = grad_a W_ab.
template <int D>
inline __attribute__((always_inline)) Vec<D> sum_times(const Mat<D>& S_a, const Mat<D>& S_b, const Vec<D>& g) {
  Vec<D> out;
  for (int i = 0; i < D; ++i) {
    double sum = (S_a(i, 0) + S_b(i, 0)) * g[0];
    for (int j = 1; j < D; ++j) sum += (S_a(i, j) + S_b(i, j)) * g[j];
    out[i] = sum;
  }
  return out;
}

}  // namespace sph
