// An Oldroyd-B fluid (PTT, epsilon = 0) between fixed boundary particles:
// the start-up of plane Poiseuille flow against the Waters & King (1970)
// series, the row zig-zag mode damped by the Morris solvent term, and steps
// that do not depend on the thread count, on the configuration PTT + Morris
// (the solvent viscosity as the Morris term) with the wall extra stress
// (boundary_particles.h, eq. W1) and the no-slip velocity in eq. T2.
#include <omp.h>

#include <cmath>
#include <vector>

#include "check.h"
#include "simulation.h"

using namespace sph;

namespace {

// The scene of cases/verification/sph_oldroyd_b_poiseuille.toml at `across`
// particles across: gap L = 1 mm, rho = 1000 kg/m^3, eta_p = 8/9 mPa s,
// eta_s = 1/9 mPa s, lambda = 0.1 s, body force g along x (El = 0.1).
constexpr double kGap = 1e-3, kRho = 1000.0, kLambda = 0.1, kEtaP = 8e-4 / 0.9, kEtaS = 1e-4 / 0.9, kG = 2e-4;
constexpr unsigned kMorris = term::morris_viscosity | term::body_force;
constexpr unsigned kTensorOnly = term::body_force;

RunParameters channel_deck(int across, int columns, unsigned terms, double g) {
  const double dx = kGap / across;
  RunParameters d;
  d.dimension = 2, d.terms = terms;
  d.rho0 = kRho, d.c0 = 0.03, d.gamma = 7.0, d.v_max = 1e-3;
  d.dx = dx, d.h = 1.5 * dx, d.body_force = {g, 0.0};
  d.periodic_axes = {0}, d.periodic_lo = {0.0}, d.periodic_hi = {columns * dx};
  MaterialSpec m;
  m.name = "oldroyd_b", m.model = "ptt", m.rho0 = kRho, m.c0 = 0.03, m.epsilon = 0.0, m.solvent_viscosity = kEtaS;
  if (terms & term::morris_viscosity) m.viscosity = kEtaS / kRho;  // as Ptt::parse: the Morris term is the solvent
  m.mode_lambda = {kLambda}, m.mode_eta = {kEtaP};
  d.materials = {m};
  return d;
}

// `across` rows of fluid (row j at y = (j + 1/2) dx) between three rows of
// boundary particles on each side, `columns` wide; fluid row j moves at
// u_x = zigzag (-1)^j.
Particles<2> channel(int across, int columns, double zigzag = 0.0) {
  const double dx = kGap / across;
  Particles<2> P;
  P.resize(columns * (across + 6));
  int k = 0;
  for (int i = 0; i < columns; ++i)
    for (int j = -3; j < across + 3; ++j, ++k) {
      const bool wall = j < 0 || j >= across;
      P.x[k] = Vec<2>((i + 0.5) * dx, (j + 0.5) * dx);
      P.v[k] = Vec<2>(wall ? 0.0 : zigzag * (j % 2 == 0 ? 1.0 : -1.0), 0.0);
      P.rho[k] = kRho, P.mass[k] = kRho * dx * dx, P.id[k] = k;
      P.kind[k] = wall ? Kind::boundary : Kind::fluid;
    }
  return P;
}

// Mean u_x of the two fluid rows next to the centre line (y = L/2 +- dx/2).
double centre_speed(const Particles<2>& P, int across) {
  const double dx = kGap / across;
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.moves(i) && std::abs(P.x[i][1] - 0.5 * kGap) < dx) sum += P.v[i][0], ++n;
  return sum / n;
}

// Amplitude of the row zig-zag: mean of u_x (-1)^j over the fluid (row j by its initial id).
double zigzag_amplitude(const Particles<2>& P, int across) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.moves(i)) {
      const int j = static_cast<int>(P.id[i] % (across + 6)) - 3;
      sum += P.v[i][0] * (j % 2 == 0 ? 1.0 : -1.0), ++n;
    }
  return sum / n;
}

}  // namespace

TEST(oldroyd_b_channel_start_up_follows_waters_and_king) {
  // The Waters & King series (orchestrator/reference/viscoelastic_flows.py,
  // waters_king_startup_velocity) at y = L/2 +- dx/2 for 40 across, mean of the two, m/s;
  // steady centre-line speed g L^2 / (8 nu_0) = 2.5e-5 m/s. (At 20 across the Morris
  // term's 0.01 h^2 regularisation puts the late speeds 3 % high.)
  const double times[] = {0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5};
  const double series[] = {9.99993972e-06, 1.98303425e-05, 2.73049171e-05, 3.04225950e-05,
                           3.08918049e-05, 3.02627877e-05, 2.75789524e-05, 2.51640071e-05};
  const int across = 40, columns = 10;
  const double dt = 1e-4, steady = 2.5e-5;
  Simulation<2, kMorris, ModelList<Ptt>> sim(channel_deck(across, columns, kMorris, kG), channel(across, columns));
  double worst = 0.0;
  int step = 0;
  for (int k = 0; k < 8; ++k) {
    for (; step * dt < times[k] - 1e-9; ++step) CHECK(sim.step(dt, NoCrossings{}));
    const double u = centre_speed(sim.particles(), across), err = std::abs(u - series[k]) / steady;
    std::fprintf(stderr, "  t = %.2f s: u_c = %.4e m/s, Waters & King %.4e (%+.2f %% of the steady speed)\n",
                 times[k], u, series[k], 100.0 * (u - series[k]) / steady);
    worst = std::max(worst, err);
  }
  CHECK(worst < 0.03);
  // The walls carry the Shepard average of the fluid's mode stress (eq. W1): the lower wall's
  // first row sees tau_xy of the sheared fluid above it, with the sign of the fluid's.
  const auto& P = sim.particles();
  double wall_xy = 0.0, fluid_xy = 0.0;
  const double dx = kGap / across;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double tau_xy = P.mode_stress.value[i](2, 0);  // column-major (0, 1) of mode 0
    if (std::abs(P.x[i][1] + 0.5 * dx) < 1e-3 * dx) wall_xy += tau_xy;
    if (std::abs(P.x[i][1] - 0.5 * dx) < 0.5 * dx && P.moves(i)) fluid_xy += tau_xy;
  }
  std::fprintf(stderr, "  lower wall row tau_xy %.3e Pa, first fluid row %.3e Pa (sums over %d columns)\n", wall_xy,
               fluid_xy, columns);
  CHECK(fluid_xy > 0.0 && wall_xy > 0.5 * fluid_xy && wall_xy < 1.5 * fluid_xy);
}

TEST(row_zigzag_is_damped_by_the_morris_solvent) {
  // Rows moving at +-A along x: the kernel-corrected gradient of eq. T2 sees no shear in them, so
  // on the tensor path alone (solvent 2 eta_s D) nothing resists them; the Morris solvent term
  // (pair velocity differences) damps them at about nu_s / dx^2.
  const int across = 20, columns = 10;
  const double A = 1e-5, dt = 2e-4;
  Simulation<2, kMorris, ModelList<Ptt>> morris(channel_deck(across, columns, kMorris, 0.0), channel(across, columns, A));
  Simulation<2, kTensorOnly, ModelList<Ptt>> tensor_only(channel_deck(across, columns, kTensorOnly, 0.0),
                                                          channel(across, columns, A));
  for (int s = 0; s < 250; ++s) CHECK(morris.step(dt, NoCrossings{}) && tensor_only.step(dt, NoCrossings{}));
  const double a_morris = zigzag_amplitude(morris.particles(), across) / A;
  const double a_tensor = zigzag_amplitude(tensor_only.particles(), across) / A;
  std::fprintf(stderr, "  zig-zag after 0.05 s, / initial: Morris solvent %.3e, tensor path only %.3f\n", a_morris,
               a_tensor);
  CHECK(std::abs(a_morris) < 1e-2);
  CHECK(a_tensor > 0.5);  // the mode the tensor path does not see (why the Morris term carries the solvent)
}

TEST(walled_ptt_morris_steps_do_not_depend_on_the_thread_count) {
  const int across = 20, columns = 30;  // 780 particles: the pair loop runs on the threads
  const RunParameters d = channel_deck(across, columns, kMorris, 50 * kG);
  Particles<2> start = channel(across, columns, 2e-5);
  for (std::size_t i = 0; i < start.size(); ++i)
    if (start.moves(i)) start.v[i][1] = 1e-5 * std::sin(0.7 * static_cast<double>(i));
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    const std::ptrdiff_t light = parallel_min_light;
    parallel_min_light = 64;
    Simulation<2, kMorris, ModelList<Ptt>> sim(d, start);
    for (int s = 0; s < 60; ++s) CHECK(sim.step(2e-4, NoCrossings{}));
    parallel_min_light = light;
    std::vector<double> state(start.size() * 8);
    const auto& P = sim.particles();
    for (std::size_t i = 0; i < P.size(); ++i) {
      double* s = &state[P.id[i] * 8];
      s[0] = P.x[i][0], s[1] = P.x[i][1], s[2] = P.v[i][0], s[3] = P.v[i][1], s[4] = P.rho[i];
      s[5] = P.mode_stress.value[i](0, 0), s[6] = P.mode_stress.value[i](2, 0), s[7] = P.sigma_rho2[i](0, 1);
    }
    return state;
  };
  const int saved = omp_get_max_threads();
  const std::vector<double> one = run(1), two = run(2);
  omp_set_num_threads(saved);
  CHECK(one == two);
}
