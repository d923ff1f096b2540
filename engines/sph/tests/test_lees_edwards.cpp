// Lees-Edwards boundaries (box_policy.h): a Newtonian fluid at rest in a
// sheared cell develops the linear velocity profile of simple shear; a PTT
// scene with particles crossing the sheared faces runs bitwise the same on 1
// and 2 threads.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "check.h"
#include "fixtures.h"
#include "simulation.h"

using namespace sph;

namespace {

constexpr unsigned kNewtonian = term::morris_viscosity | term::sheared;

}  // namespace

TEST(newtonian_lees_edwards_cell_develops_a_linear_profile) {
  // nu = 0.1 m^2/s in a 1 m cell: the slowest mode decays as exp(-4 pi^2 nu t) (t = 6 s: 5e-11).
  const int n = 20;
  const double gamma_dot = 1.0;
  RunParameters d = fixtures::shear_deck(n, 1.0, 1.0, 5.0, gamma_dot);
  d.terms = term::morris_viscosity, d.viscosity = 0.1;
  Simulation<2, kNewtonian> sim(d, fixtures::shear_cell(n, 1.0, 1.0, 0.0));  // at rest
  const double dt = 2.5e-3;
  for (int s = 0; s < 2400; ++s) CHECK(sim.step(dt, NoCrossings{}));
  CHECK(sim.sort_particles());
  const auto& P = sim.particles();
  double worst = 0.0, mean_vy = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double expected = gamma_dot * (P.x[i][1] - 0.5);
    worst = std::max(worst, std::abs(P.v[i][0] - expected));
    mean_vy += std::abs(P.v[i][1]) / P.size();
  }
  const double scale = 0.5 * gamma_dot;  // the wall speed of the profile
  std::fprintf(stderr, "  max |u_x - gamma_dot (y - L/2)| = %.3e of %.3g m/s (%.3f %%), mean |u_y| %.2e m/s\n", worst,
               scale, 100.0 * worst / scale, mean_vy);
  CHECK(worst < 0.01 * scale);
}

TEST(sheared_ptt_steps_do_not_depend_on_the_thread_count) {
  const int n = 48;  // 2304 particles: the rates, predictor and corrector run on the threads
  RunParameters d = fixtures::shear_deck(n, 1.0, 1.0, 5.0, 1.0);
  MaterialSpec m;
  m.name = "melt", m.model = "ptt", m.rho0 = 1.0, m.c0 = 5.0, m.epsilon = 0.2, m.solvent_viscosity = 1e-3;
  m.mode_lambda = {0.5, 0.05}, m.mode_eta = {0.01, 0.005};
  d.materials = {m};
  Particles<2> start = fixtures::shear_cell(n, 1.0, 1.0, 1.0, 0.1);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> kick(-0.3, 0.3);
  for (auto& v : start.v) v[1] += kick(rng);  // particles cross the sheared faces
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    const std::ptrdiff_t light = parallel_min_light;
    parallel_min_light = 64;
    Simulation<2, term::sheared, ModelList<Ptt>> sim(d, start);
    for (int s = 0; s < 60; ++s) CHECK(sim.step(2e-3, NoCrossings{}));
    parallel_min_light = light;
    std::vector<double> state(start.size() * 6 * 4);
    const auto& P = sim.particles();
    for (std::size_t i = 0; i < P.size(); ++i) {
      double* s = &state[P.id[i] * 6 * 4];
      s[0] = P.x[i][0], s[1] = P.x[i][1], s[2] = P.v[i][0], s[3] = P.v[i][1], s[4] = P.rho[i];
      s[5] = P.mode_stress.value[i](2, 0), s[6] = P.mode_stress.value[i](0, 1);
    }
    return std::pair(state, sim.stage_times().builds);
  };
  const int saved = omp_get_max_threads();
  const auto [one, builds] = run(1);
  const auto [two, builds_two] = run(2);
  omp_set_num_threads(saved);
  std::fprintf(stderr, "  %ld list builds in 60 steps\n", builds);
  CHECK(builds > 2 && builds == builds_two);
  CHECK(one == two);
}
