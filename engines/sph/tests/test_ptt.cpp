// The multi-mode PTT model (materials/ptt.h) in a Lees-Edwards shear cell
// (box_policy.h): steady simple shear against the closed form, the Newtonian
// limit of a short relaxation time, the Cross-law solvent's viscosity and the
// plateau's upper-convected elastic stress G_p (B - I).
#include <cmath>

#include "check.h"
#include "fixtures.h"
#include "simulation.h"

using namespace sph;

namespace {

constexpr unsigned kSheared = term::sheared;
using PttCell = Simulation<2, kSheared, ModelList<Ptt>>;

// A shear cell of PTT fluid (one mode lambda s, eta Pa s): L = 1 m, rho0 = 1, gamma_dot = 1/s, c0 = 5 m/s.
RunParameters ptt_deck(int n, double lambda, double eta, double epsilon) {
  RunParameters d = fixtures::shear_deck(n, 1.0, 1.0, 5.0, 1.0);
  MaterialSpec m;
  m.name = "melt", m.model = "ptt", m.rho0 = 1.0, m.c0 = 5.0;
  m.mode_lambda = {lambda}, m.mode_eta = {eta}, m.epsilon = epsilon;
  d.materials = {m};
  return d;
}

// Steady single-mode linear PTT in simple shear: f^3 - f^2 - 2 eps Wi^2 = 0 (Newton's method).
double steady_f(double epsilon, double wi) {
  double f = 1.0;
  for (int k = 0; k < 50; ++k) f -= (f * f * f - f * f - 2.0 * epsilon * wi * wi) / (3.0 * f * f - 2.0 * f);
  return f;
}

}  // namespace

TEST(ptt_steady_shear_matches_closed_form) {
  const double lambda = 1.0, eta = 0.01, epsilon = 0.1, gamma_dot = 1.0;  // Wi = 1
  PttCell sim(ptt_deck(10, lambda, eta, epsilon), fixtures::shear_cell(10, 1.0, 1.0, gamma_dot));
  const double dt = 5e-3;
  for (int s = 0; s < 3000; ++s) CHECK(sim.step(dt, NoCrossings{}));  // 15 relaxation times
  CHECK(sim.check_stability().ok);
  const Mat<2> tau = sim.mean_extra_stress();
  const double f = steady_f(epsilon, lambda * gamma_dot);
  const double viscosity = tau(0, 1) / gamma_dot, n1 = tau(0, 0) - tau(1, 1);
  const double n1_expected = 2.0 * eta * lambda * gamma_dot * gamma_dot / (f * f);
  const double f_measured = eta * gamma_dot / tau(0, 1);
  std::fprintf(stderr, "  f = %.6f (closed form %.6f), eta/eta_p = %.6f (%.6f), N1 = %.6g Pa (%.6g, error %.2e), "
               "|tau_yy|/tau_xx = %.2e\n", f_measured, f, viscosity / eta, 1.0 / f, n1, n1_expected,
               n1 / n1_expected - 1.0, std::abs(tau(1, 1)) / tau(0, 0));
  CHECK_CLOSE(f, 1.150973, 1e-6);
  CHECK_CLOSE(viscosity / eta, 0.868830, 0.02);
  CHECK_CLOSE(n1, n1_expected, 0.02);
  CHECK(std::abs(tau(1, 1)) < 0.01 * tau(0, 0));
}

TEST(ptt_with_short_relaxation_time_is_newtonian) {
  // Wi = lambda gamma_dot = 0.01: tau = 2 eta D up to O(Wi): tau_xy = eta gamma_dot / f
  // (f - 1 = 2e-5) and tau_xx = 2 Wi tau_xy.
  const double lambda = 0.01, eta = 0.01, epsilon = 0.1, gamma_dot = 1.0;
  PttCell sim(ptt_deck(10, lambda, eta, epsilon), fixtures::shear_cell(10, 1.0, 1.0, gamma_dot));
  for (int s = 0; s < 200; ++s) CHECK(sim.step(1e-3, NoCrossings{}));  // 20 relaxation times
  const Mat<2> tau = sim.mean_extra_stress();
  std::fprintf(stderr, "  tau_xy = %.8g Pa (Newtonian %.8g), tau_xx / tau_xy = %.5f (2 Wi = %.5f)\n", tau(0, 1),
               eta * gamma_dot, tau(0, 0) / tau(0, 1), 2.0 * lambda * gamma_dot);
  CHECK_CLOSE(tau(0, 1), eta * gamma_dot, 1e-3);
  CHECK_CLOSE(tau(0, 0) / tau(0, 1), 2.0 * lambda * gamma_dot, 0.02);
  CHECK(std::abs(tau(1, 1)) < 1e-6 * tau(0, 1));
}

TEST(ptt_steady_shear_in_a_3d_cell) {
  // The same closed form in a 3D Lees-Edwards cell (z plainly periodic), 6^3 particles, 10 relaxation times.
  const int n = 6;
  const double L = 1.0, dx = L / n, lambda = 1.0, eta = 0.01, epsilon = 0.1, gamma_dot = 1.0;
  RunParameters d = ptt_deck(n, lambda, eta, epsilon);
  d.dimension = 3, d.h = 1.3 * dx, d.dx = dx;
  d.periodic_axes = {0, 1, 2}, d.periodic_lo = {0.0, 0.0, 0.0}, d.periodic_hi = {L, L, L};
  Particles<3> P;
  P.resize(n * n * n);
  int k = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      for (int c = 0; c < n; ++c, ++k) {
        P.x[k] = Vec<3>(a + 0.5, b + 0.5, c + 0.5) * dx;
        P.v[k] = Vec<3>(gamma_dot * (P.x[k][1] - 0.5 * L), 0.0, 0.0);
        P.rho[k] = 1.0, P.mass[k] = dx * dx * dx, P.id[k] = k, P.kind[k] = Kind::fluid;
      }
  Simulation<3, kSheared, ModelList<Ptt>> sim(d, P);
  for (int s = 0; s < 1000; ++s) CHECK(sim.step(1e-2, NoCrossings{}));
  const Mat<3> tau = sim.mean_extra_stress();
  const double f = steady_f(epsilon, lambda * gamma_dot);
  std::fprintf(stderr, "  3D: eta/eta_p = %.6f (%.6f), N1 = %.6g Pa (%.6g), |tau_yy|/tau_xx = %.2e, |tau_zz|/tau_xx = %.2e\n",
               tau(0, 1) / (eta * gamma_dot), 1.0 / f, tau(0, 0) - tau(1, 1), 2.0 * eta * lambda / (f * f),
               std::abs(tau(1, 1)) / tau(0, 0), std::abs(tau(2, 2)) / tau(0, 0));
  CHECK_CLOSE(tau(0, 1) / (eta * gamma_dot), 1.0 / f, 0.02);
  CHECK_CLOSE(tau(0, 0) - tau(1, 1), 2.0 * eta * lambda * gamma_dot * gamma_dot / (f * f), 0.02);
  CHECK(std::abs(tau(1, 1)) < 0.01 * tau(0, 0) && std::abs(tau(2, 2)) < 0.01 * tau(0, 0));
}

TEST(oscillatory_shear_of_ucm_gives_the_maxwell_moduli) {
  // Lees-Edwards strain gamma_A sin(omega t), one mode with epsilon = 0 (UCM): after the start-up,
  // sigma_xy = gamma_A (G' sin + G'' cos), G' = eta lambda omega^2 / (1 + (lambda omega)^2),
  // G'' = eta omega / (1 + (lambda omega)^2). Least squares over the last two periods.
  const double lambda = 1.0, eta = 0.01, amplitude = 0.1, omega = M_PI;
  RunParameters d = ptt_deck(10, lambda, eta, 0.0);
  d.lees_edwards.shear_rate = 0.0, d.lees_edwards.amplitude = amplitude, d.lees_edwards.omega = omega;
  PttCell sim(d, fixtures::shear_cell(10, 1.0, 1.0, amplitude * omega));
  const double dt = 1e-3;
  double ss = 0, sc = 0, cc = 0, ys = 0, yc = 0;
  for (int step = 1; step <= 10000; ++step) {
    CHECK(sim.step(dt, NoCrossings{}));
    const double t = step * dt;
    if (t < 6.0 || step % 10) continue;
    const double s = std::sin(omega * t), c = std::cos(omega * t), y = sim.mean_extra_stress()(0, 1);
    ss += s * s, sc += s * c, cc += c * c, ys += y * s, yc += y * c;
  }
  const double det = ss * cc - sc * sc;
  const double g1 = (ys * cc - yc * sc) / det / amplitude, g2 = (yc * ss - ys * sc) / det / amplitude;
  const double w2 = 1.0 + lambda * lambda * omega * omega;
  std::fprintf(stderr, "  G' = %.6g Pa (Maxwell %.6g), G'' = %.6g Pa (Maxwell %.6g)\n", g1, eta * lambda * omega * omega / w2,
               g2, eta * omega / w2);
  CHECK_CLOSE(g1, eta * lambda * omega * omega / w2, 0.03);
  CHECK_CLOSE(g2, eta * omega / w2, 0.03);
}

TEST(ptt_cross_solvent_gives_the_cross_viscosity_in_steady_shear) {
  // A fast mode (Wi = 0.01: eta_p / f) and a Cross solvent eta_C(gamma_dot) at gamma_dot = 1/s, K gamma_dot = 1:
  // tau_xy / gamma_dot = eta_p / f + eta_C with eta_C = eta_inf + (eta_0 - eta_inf) / 2.
  const double lambda = 0.01, eta = 0.01, epsilon = 0.1, gamma_dot = 1.0;
  RunParameters d = ptt_deck(10, lambda, eta, epsilon);
  MaterialSpec& m = d.materials[0];
  m.cross_eta_0 = 0.02, m.cross_eta_inf = 0.002, m.cross_time = 1.0, m.cross_exponent = 0.7;
  PttCell sim(d, fixtures::shear_cell(10, 1.0, 1.0, gamma_dot));
  for (int s = 0; s < 200; ++s) CHECK(sim.step(1e-3, NoCrossings{}));
  const double expected = eta / steady_f(epsilon, lambda * gamma_dot) + 0.002 + 0.018 / 2.0;
  const double viscosity = sim.mean_extra_stress()(0, 1) / gamma_dot;
  std::fprintf(stderr, "  eta = %.8g Pa s (eta_p / f + eta_C = %.8g, error %.2e)\n", viscosity, expected,
               viscosity / expected - 1.0);
  CHECK_CLOSE(viscosity, expected, 1e-6);
}

TEST(ptt_plateau_is_an_upper_convected_elastic_stress) {
  // G_p alone beside a fast mode, sheared at gamma_dot for t: the plateau column holds G_p (B - I),
  // tau_xy = G_p gamma and N1 = G_p gamma^2 at the strain gamma = gamma_dot t.
  const double lambda = 0.01, eta = 1e-4, gamma_dot = 1.0, plateau = 0.01, dt = 1e-3;
  RunParameters d = ptt_deck(10, lambda, eta, 0.0);
  d.materials[0].storage_plateau = plateau;
  PttCell sim(d, fixtures::shear_cell(10, 1.0, 1.0, gamma_dot));
  const int steps = 500;
  for (int s = 0; s < steps; ++s) CHECK(sim.step(dt, NoCrossings{}));
  const Particles<2>& P = sim.particles();
  CHECK(P.modes == 2);
  Mat<2> tau = Mat<2>::Zero();
  for (std::size_t i = 0; i < P.size(); ++i) tau += Eigen::Map<const Mat<2>>(P.mode_stress.value[i].col(1).data());
  tau /= static_cast<double>(P.size());
  const double gamma = gamma_dot * steps * dt;
  std::fprintf(stderr, "  plateau: tau_xy = %.10g Pa (G_p gamma %.10g), N1 = %.10g Pa (G_p gamma^2 %.10g)\n", tau(0, 1),
               plateau * gamma, tau(0, 0) - tau(1, 1), plateau * gamma * gamma);
  CHECK_CLOSE(tau(0, 1), plateau * gamma, 1e-6);
  CHECK_CLOSE(tau(0, 0) - tau(1, 1), plateau * gamma * gamma, 1e-6);
  CHECK(std::abs(tau(1, 1)) < 1e-6 * tau(0, 0));
}
