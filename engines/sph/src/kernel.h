// Wendland C2 kernel (Canini et al., eq. 8) with support radius 2h.
#pragma once
#include <algorithm>
#include <cmath>

#include "vec.h"

namespace sph {

template <int D>
struct WendlandC2 {
  static_assert(D == 2 || D == 3, "2D or 3D");
  double h, inv_h;
  double alpha_d;      // normalisation: 7/(4 pi h^2) in 2D, 21/(16 pi h^3) in 3D
  double grad_factor;  // -5 alpha_d / h^2

  explicit WendlandC2(double smoothing_length) : h(smoothing_length), inv_h(1.0 / smoothing_length) {
    alpha_d = D == 2 ? 7.0 / (4.0 * M_PI * h * h) : 21.0 / (16.0 * M_PI * h * h * h);
    grad_factor = -5.0 * alpha_d / (h * h);
  }

  double support_radius() const { return 2.0 * h; }

  // W(r) = alpha_d (1 - q/2)^4 (2q + 1), q = r/h <= 2.
  double value(double r) const {
    const double q = r * inv_h;
    if (q >= 2.0) return 0.0;
    const double t = 1.0 - 0.5 * q;
    const double t2 = t * t;
    return alpha_d * t2 * t2 * (2.0 * q + 1.0);
  }

  // W(r) without a test: 0 at and beyond the support (t clamped to 0).
  double value_clamped(double r) const {
    const double q = r * inv_h;
    const double t = std::max(1.0 - 0.5 * q, 0.0);
    const double t2 = t * t;
    return alpha_d * t2 * t2 * (2.0 * q + 1.0);
  }

  // dW/dr = -5 alpha_d q (1 - q/2)^3 / h, so grad_a W_ab = F(r) r_ab with
  // F(r) = -5 alpha_d (1 - q/2)^3 / h^2 (finite at r = 0).
  double gradient_factor(double r) const {
    const double q = r * inv_h;
    if (q >= 2.0) return 0.0;
    const double t = 1.0 - 0.5 * q;
    return grad_factor * t * t * t;
  }

  // gradient_factor for r < 2h known (no test at the support's edge).
  double gradient_factor_inside(double r) const {
    const double t = 1.0 - 0.5 * (r * inv_h);
    return grad_factor * (t * t * t);
  }

  // grad_a W(x_a - x_b) for r_ab = x_a - x_b.
  Vec<D> gradient(const Vec<D>& r_ab) const { return gradient_factor(r_ab.norm()) * r_ab; }
};

}  // namespace sph
