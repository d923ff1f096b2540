// Wendland C2 kernel (eq. 8) and Tait EOS (eq. 6).
#include "check.h"
#include "eos.h"
#include "kernel.h"

using namespace sph;

// Midpoint-lattice sum of W over its support approximates the integral.
template <int D>
static double lattice_integral(double h, int per_h) {
  const WendlandC2<D> W(h);
  const double s = h / per_h;
  const int m = 2 * per_h;
  double sum = 0.0;
  if constexpr (D == 2) {
    for (int i = -m; i < m; ++i)
      for (int j = -m; j < m; ++j) sum += W.value(Vec<2>((i + 0.5) * s, (j + 0.5) * s).norm());
    return sum * s * s;
  } else {
    for (int i = -m; i < m; ++i)
      for (int j = -m; j < m; ++j)
        for (int k = -m; k < m; ++k) sum += W.value(Vec<3>((i + 0.5) * s, (j + 0.5) * s, (k + 0.5) * s).norm());
    return sum * s * s * s;
  }
}

TEST(kernel_normalisation_2d) {
  CHECK_CLOSE(lattice_integral<2>(1.3e-3, 40), 1.0, 1e-3);
  CHECK_CLOSE(lattice_integral<2>(2.0, 40), 1.0, 1e-3);
}

TEST(kernel_normalisation_3d) {
  CHECK_CLOSE(lattice_integral<3>(4.5e-4, 20), 1.0, 1e-3);
  CHECK_CLOSE(lattice_integral<3>(1.0, 20), 1.0, 1e-3);
}

TEST(kernel_values) {
  const double h = 0.5;
  const WendlandC2<3> W3(h);
  CHECK_CLOSE(W3.value(0.0), 21.0 / (16.0 * M_PI * h * h * h), 1e-14);
  // q = 1: (1 - 1/2)^4 (2 + 1) = 3/16
  CHECK_CLOSE(W3.value(h), 21.0 / (16.0 * M_PI * h * h * h) * 3.0 / 16.0, 1e-14);
  CHECK(W3.value(2.0 * h) == 0.0);
  CHECK(W3.value(3.0 * h) == 0.0);
  const WendlandC2<2> W2(h);
  CHECK_CLOSE(W2.value(0.0), 7.0 / (4.0 * M_PI * h * h), 1e-14);
  CHECK(W2.support_radius() == 2.0 * h);
}

template <int D>
static void check_gradient(const Vec<D>& r, double h) {
  const WendlandC2<D> W(h);
  const Vec<D> g = W.gradient(r);
  CHECK(((g + W.gradient(Vec<D>(-r))).norm()) <= 1e-14 * g.norm());  // antisymmetric
  const double e = 1e-6 * h;
  for (int d = 0; d < D; ++d) {
    Vec<D> step = Vec<D>::Zero();
    step[d] = e;
    const double fd = (W.value((r + step).norm()) - W.value((r - step).norm())) / (2.0 * e);
    CHECK_CLOSE(g[d], fd, 1e-6, 1e-9 * g.norm());
  }
  CHECK(g.dot(r) < 0.0);  // W decreases outwards
}

TEST(kernel_gradient_matches_finite_difference) {
  check_gradient<2>(Vec<2>(0.3e-3, -0.7e-3), 1e-3);
  check_gradient<2>(Vec<2>(1.5, 0.2), 1.0);
  check_gradient<3>(Vec<3>(0.2, -0.5, 0.9), 0.8);
  check_gradient<3>(Vec<3>(1e-4, 2e-4, -3e-4), 4.5e-4);
  const WendlandC2<3> W(1.0);
  CHECK(W.gradient(Vec<3>(2.5, 0.0, 0.0)).norm() == 0.0);
}

// The cavitation floor (eos.h): the pressure stops at p_min, whose density floor_rho inverts eq. 6 (and eq. 9).
TEST(eos_min_pressure_is_a_floor) {
  TaitEos eos{1000.0, 1000.0, 7.0, 0.0};
  eos.set_min_pressure(-0.99e5);
  CHECK_CLOSE(eos.pressure(eos.floor_rho), -0.99e5, 1e-9);  // its own density
  CHECK(eos.pressure(900.0) == -0.99e5);                   // -746 bar without the floor
  CHECK_CLOSE(eos.pressure(1001.0), 1000.0 * 1e6 / 7.0 * (std::pow(1.001, 7.0) - 1.0), 1e-9);  // untouched above
  CHECK_CLOSE(eos.floor_rho, 1000.0 * std::pow(1.0 - 7.0 * 0.99e5 / 1e9, 1.0 / 7.0), 1e-12);  // 999.901 kg/m^3
  TaitEos quad{1000.0, 10.0, 7.0, -5e4, true};
  quad.set_min_pressure(-4e4);  // c0^2 rho^2 / (2 rho0) = 1e4 at rho = sqrt(2e4 rho0) / c0 = 447.2 kg/m^3
  CHECK_CLOSE(quad.floor_rho, std::sqrt(2.0e4 * 1000.0) / 10.0, 1e-12);
  CHECK(quad.pressure(100.0) == -4e4);
}

TEST(tait_eos_values) {
  const TaitEos eos{1000.0, 20.0, 7.0, 1e3};
  CHECK_CLOSE(eos.pressure(1000.0), 1e3, 1e-14);
  // 1000 * 400 / 7 * (1.01^7 - 1) + 1000, with 1.01^7 = 1.0721353521...
  CHECK_CLOSE(eos.pressure(1010.0), 1000.0 * 400.0 / 7.0 * (1.0721353521 - 1.0) + 1e3, 1e-9);
  CHECK(eos.pressure(990.0) < 1e3);
  CHECK_CLOSE(eos.sound_speed(1000.0), 20.0, 1e-14);
  CHECK_CLOSE(eos.sound_speed(1010.0), 20.0 * std::pow(1.01, 3.0), 1e-12);
  const TaitEos other{998.0, 15.0, 1.5, 0.0};  // general exponent path
  CHECK_CLOSE(other.pressure(1008.0), 998.0 * 225.0 / 1.5 * (std::pow(1008.0 / 998.0, 1.5) - 1.0), 1e-12);
}
