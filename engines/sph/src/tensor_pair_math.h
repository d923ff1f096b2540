// The tensor pair loop's 3 x 3 updates as plain loops the compiler inlines (pair_loop.h). Its rows are compiled
// for AVX2 as well as SSE2, and the fixed-size Eigen expressions there stayed out-of-line calls (a third of the
// solid's pair time). Plain double operations without FMA round alike on both, as the rest of the loop does.
#pragma once
#include "vec.h"

namespace sph {

// Eq. T2's sums of a pair for both particles: G -= (w u) r^T and M -= (w r) r^T with w_a for a, w_b for b. M is
// symmetric: only its upper triangle (i <= j) is summed; symmetric_shape fills the rest before M is used.
template <int D>
inline __attribute__((always_inline)) void subtract_outer_products(const Vec<D>& u, const Vec<D>& r, double w_a,
                                                                    double w_b, Mat<D>& G_a, Mat<D>& M_a, Mat<D>& G_b,
                                                                    Mat<D>& M_b) {
  double wu_a[D], wu_b[D], wr_a[D], wr_b[D];
  for (int i = 0; i < D; ++i) wu_a[i] = w_a * u[i], wu_b[i] = w_b * u[i], wr_a[i] = w_a * r[i], wr_b[i] = w_b * r[i];
  for (int j = 0; j < D; ++j) {
    for (int i = 0; i < D; ++i) G_a(i, j) -= wu_a[i] * r[j], G_b(i, j) -= wu_b[i] * r[j];
    for (int i = 0; i <= j; ++i) M_a(i, j) -= wr_a[i] * r[j], M_b(i, j) -= wr_b[i] * r[j];
  }
}

// The kernel-correction sum M of eq. T2 from its upper triangle (subtract_outer_products sums only that).
template <int D>
inline Mat<D> symmetric_shape(const Mat<D>& upper) {
  Mat<D> M = upper;
  for (int j = 0; j < D; ++j)
    for (int i = j + 1; i < D; ++i) M(i, j) = M(j, i);
  return M;
}

// (S_a + S_b + s (R_a + R_b)) g for the pair's stress S_a + S_b, its artificial stress R_a + R_b with factor s and
// g = grad_a W_ab.
template <int D>
inline __attribute__((always_inline)) Vec<D> sum_times(const Mat<D>& S_a, const Mat<D>& S_b, double s,
                                                       const Mat<D>& R_a, const Mat<D>& R_b, const Vec<D>& g) {
  Vec<D> out;
  for (int i = 0; i < D; ++i) {
    double sum = (S_a(i, 0) + S_b(i, 0) + s * (R_a(i, 0) + R_b(i, 0))) * g[0];
    for (int j = 1; j < D; ++j) sum += (S_a(i, j) + S_b(i, j) + s * (R_a(i, j) + R_b(i, j))) * g[j];
    out[i] = sum;
  }
  return out;
}

// to += s x, component by component (a Vec<D> update the AVX2 rows would otherwise call out of line).
template <int D>
inline __attribute__((always_inline)) void add_scaled(Vec<D>& to, double s, const Vec<D>& x) {
  for (int i = 0; i < D; ++i) to[i] += s * x[i];
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
