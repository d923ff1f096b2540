// The renormalised Morris sum (viscosity_correction.h, eq. VC1) on a regular
// lattice: a quadratic velocity field gets its exact Laplacian nu tr(A) with
// the correction, and nu tr(A) tr(S) / D without it, tr(S) the weighted
// second moment of the lattice summed here by hand.
#include <cmath>

#include "check.h"
#include "simulation.h"

using namespace sph;

namespace {

constexpr double dx = 1e-3, h_over_dx = 1.3, rho0 = 1000.0, nu = 1e-4;

RunParameters lattice_deck(int D, bool corrected) {
  RunParameters d;
  d.dimension = D;
  d.terms = term::morris_viscosity;
  d.rho0 = rho0, d.c0 = 1.0, d.v_max = 0.1, d.viscosity = nu;
  d.h = h_over_dx * dx, d.dx = dx;
  d.viscosity_correction = corrected;
  return d;
}

// tr(S) / D over the offsets of a lattice of spacing dx within 2h, by hand: sum V (-F) r^4 / (r^2 + 0.01 h^2) / D.
template <int D>
double lattice_moment() {
  const double h = h_over_dx * dx, eta2 = 0.01 * h * h;
  const double alpha_d = D == 2 ? 7.0 / (4.0 * M_PI * h * h) : 21.0 / (16.0 * M_PI * h * h * h);
  double sum = 0.0;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = (D == 3 ? -3 : 0); k <= (D == 3 ? 3 : 0); ++k) {
        const double r2 = dx * dx * (i * i + j * j + k * k), q = std::sqrt(r2) / h;
        if (r2 == 0.0 || q >= 2.0) continue;
        const double F = -5.0 * alpha_d * std::pow(1.0 - 0.5 * q, 3) / (h * h);  // grad W = F r (eq. 8)
        sum += std::pow(dx, D) * (-F) * r2 * r2 / (r2 + eta2);
      }
  return sum / D;
}

// A block of n^D fluid particles on the lattice at rest density (p = 0), moving at
// v = (1/2 y^T A y, 1/2 y^T B y, c . y), y = x - centre; the acceleration of every
// particle whose support lies inside the block, against nu tr(A), nu tr(B), 0 times `scale`.
template <int D, unsigned Terms>
void check_quadratic_field(bool corrected, double scale, double tol) {
  constexpr int n = 9;
  Mat<D> A = Mat<D>::Zero(), B = Mat<D>::Zero();
  A(0, 0) = 3.0, A(1, 1) = -1.0, A(0, 1) = A(1, 0) = 2.0;  // 1/(m s)
  B(1, 1) = 5.0, B(0, 1) = B(1, 0) = -0.5;
  if constexpr (D == 3) A(2, 2) = 4.0, A(0, 2) = A(2, 0) = 1.5, B(2, 2) = -2.0, B(1, 2) = B(2, 1) = 0.7;
  Vec<D> c = Vec<D>::Constant(0.3);
  const Vec<D> centre = Vec<D>::Constant(0.5 * (n - 1) * dx);
  Particles<D> P;
  int count = 1;
  for (int d = 0; d < D; ++d) count *= n;
  P.resize(count);
  for (int i = 0; i < count; ++i) {
    Vec<D> x;
    for (int d = 0, rest = i; d < D; ++d, rest /= n) x[d] = (rest % n) * dx;
    const Vec<D> y = x - centre;
    P.x[i] = x, P.rho[i] = rho0, P.mass[i] = rho0 * std::pow(dx, D), P.id[i] = i, P.kind[i] = Kind::fluid;
    P.v[i].setZero();
    P.v[i][0] = 0.5 * y.dot(A * y), P.v[i][1] = 0.5 * y.dot(B * y);
    if constexpr (D == 3) P.v[i][2] = c.dot(y);
  }
  Simulation<D, Terms> sim(lattice_deck(D, corrected), std::move(P));
  sim.compute_rates();
  const auto& Q = sim.particles();
  const double exact_x = nu * A.trace() * scale, exact_y = nu * B.trace() * scale, reach = 2.0 * h_over_dx * dx;
  int inside = 0;
  for (std::size_t i = 0; i < Q.size(); ++i) {
    if (((Q.x[i].array() - reach) < -1e-9).any() || ((Q.x[i].array() + reach) > (n - 1) * dx + 1e-9).any()) continue;
    ++inside;
    CHECK_CLOSE(Q.acc[i][0], exact_x, tol);
    CHECK_CLOSE(Q.acc[i][1], exact_y, tol);
    if constexpr (D == 3) CHECK(std::abs(Q.acc[i][2]) <= tol * std::abs(exact_x));
  }
  CHECK(inside == (D == 2 ? 9 : 27));
}

}  // namespace

TEST(corrected_morris_sum_is_the_exact_laplacian_of_a_quadratic_field) {
  constexpr unsigned corrected = term::morris_viscosity | term::viscosity_correction;
  check_quadratic_field<2, corrected>(true, 1.0, 1e-12);
  check_quadratic_field<3, corrected>(true, 1.0, 1e-12);
}

TEST(plain_morris_sum_is_the_laplacian_times_the_lattice_moment) {
  // tr(S) / D at h = 1.3 dx: 0.9627 (2D), 0.9696 (3D): the plain sum gives 0.97 of the Laplacian, so a
  // channel at a given body force flows about 3 % fast; the lattice sums by hand against their values.
  const double m2 = lattice_moment<2>(), m3 = lattice_moment<3>();
  CHECK_CLOSE(m2, 0.96268, 1e-5);
  CHECK_CLOSE(m3, 0.96957, 1e-5);
  check_quadratic_field<2, term::morris_viscosity>(false, m2, 1e-12);
  check_quadratic_field<3, term::morris_viscosity>(false, m3, 1e-12);
}
