// The Johnson-Cook solid as a material of the engine (materials/johnson_cook_material.h): homogeneous simple
// shear in a Lees-Edwards cell (elastic against Dienes' closed form of the Jaumann rate, perfectly plastic on
// the yield surface), the artificial stress of a particle in tension, and a violent jittered block (plastic
// flow, failure, Mie-Grueneisen pressure, artificial stress and viscosity) stepping bitwise the same on 1 and 2
// threads.
#include <omp.h>

#include <cmath>
#include <random>

#include "check.h"
#include "fixtures.h"
#include "simulation.h"

using namespace sph;

namespace {

using SolidCell = Simulation<2, term::sheared, ModelList<JohnsonCook>>;
using SolidBlock = Simulation<2, term::artificial_viscosity, ModelList<JohnsonCook>>;

// An elastic solid (rho0 1000 kg/m^3, G 1 MPa, K 2 MPa: wave speed 57.7 m/s) in a shear cell of n x n particles.
MaterialSpec soft_solid() {
  MaterialSpec m;
  m.name = "solid", m.model = "johnson_cook", m.rho0 = 1000.0;
  m.solid.shear_modulus = 1e6, m.solid.linear = {1000.0, 2e6};
  m.solid.heat = {1000.0, 0.0, 0.0};
  m.c0 = m.solid.wave_speed();
  return m;
}

RunParameters cell_deck(int n, const MaterialSpec& m) {
  RunParameters d = fixtures::shear_deck(n, 1.0, m.rho0, m.c0, 1.0);
  d.materials = {m};
  return d;
}

// Step the cell to the shear strain gamma (shear rate 1/s); the largest relative spread of s_xy over the particles.
double shear_to(SolidCell& sim, double gamma) {
  const double dt = 0.25 * sim.kernel().h / sim.materials()[0].eos.c0;
  const int steps = static_cast<int>(std::ceil(gamma / dt));
  for (int s = 0; s < steps; ++s) CHECK(sim.step(gamma / steps, NoCrossings{}));
  const auto& P = sim.particles();
  double lo = P.tau[0](0, 1), hi = lo;
  for (std::size_t i = 0; i < P.size(); ++i) lo = std::min(lo, P.tau[i](0, 1)), hi = std::max(hi, P.tau[i](0, 1));
  return (hi - lo) / std::abs(hi);
}

}  // namespace

TEST(solid_elastic_simple_shear_follows_the_jaumann_closed_form) {
  // Hypoelastic with the Jaumann rate in simple shear (Dienes 1979): s_xy = G sin gamma, s_xx = -s_yy = G (1 - cos gamma).
  // The principal tension of s (up to G) would clump the lattice (the tensile instability) without the artificial
  // stress; a uniform R exerts no force on the sheared lattice, so the closed form stands.
  MaterialSpec m = soft_solid();
  m.solid.artificial_stress = 0.3;
  const double G = m.solid.shear_modulus, gamma = 0.5;
  SolidCell sim(cell_deck(10, m), fixtures::shear_cell(10, 1.0, m.rho0, 1.0));
  const double spread = shear_to(sim, gamma);
  const Mat<2> s = sim.mean_extra_stress();
  std::fprintf(stderr, "  s_xy / G = %.8f (sin gamma %.8f), s_xx / G = %.8f (1 - cos gamma %.8f), spread %.1e\n",
               s(0, 1) / G, std::sin(gamma), s(0, 0) / G, 1.0 - std::cos(gamma), spread);
  CHECK_CLOSE(s(0, 1), G * std::sin(gamma), 1e-5);
  CHECK_CLOSE(s(0, 0), G * (1.0 - std::cos(gamma)), 1e-4);
  CHECK_CLOSE(s(1, 1), -s(0, 0), 1e-9);
  CHECK(spread < 1e-9);  // the affinely sheared lattice stays homogeneous
  m.solid.artificial_stress = 0.0;  // without it the round-off grows into clumps
  SolidCell plain(cell_deck(10, m), fixtures::shear_cell(10, 1.0, m.rho0, 1.0));
  const double clumped = shear_to(plain, gamma);
  std::fprintf(stderr, "  without the artificial stress: spread %.2g, s_xy / G = %.4f\n", clumped,
               plain.mean_extra_stress()(0, 1) / G);
  CHECK(clumped > 0.1);
}

TEST(solid_perfectly_plastic_shear_stays_on_the_yield_surface) {
  // A = 10 kPa, no hardening, no rate or heat: sigma_eq = A once yielded, eps_p grows at gamma_dot / sqrt(3).
  MaterialSpec m = soft_solid();
  m.solid.plastic = true;
  m.solid.strength = {1e4, 0.0, 1.0, 0.0, 1.0};
  m.solid.strength.melting_temperature = 1000.0;
  SolidCell sim(cell_deck(10, m), fixtures::shear_cell(10, 1.0, m.rho0, 1.0));
  const double gamma = 0.1, yield_gamma = 1e4 / (std::sqrt(3.0) * m.solid.shear_modulus);
  CHECK(shear_to(sim, gamma) < 1e-9);
  const auto& P = sim.particles();
  const Mat<2> s = sim.mean_extra_stress();
  const double q = std::sqrt(1.5 * (s.squaredNorm() + P.solid_state.value[0][slot::szz] * P.solid_state.value[0][slot::szz]));
  const double eps_p = P.solid_state.value[0][slot::plastic_strain];
  std::fprintf(stderr, "  sigma_eq = %.10g Pa (A = 1e4), eps_p = %.6f ((gamma - gamma_y) / sqrt 3 = %.6f), rate %.4f 1/s\n",
               q, eps_p, (gamma - yield_gamma) / std::sqrt(3.0), P.solid_state.value[0][slot::plastic_rate]);
  CHECK_CLOSE(q, 1e4, 1e-9);
  CHECK_CLOSE(eps_p, (gamma - yield_gamma) / std::sqrt(3.0), 0.01);
  CHECK_CLOSE(P.solid_state.value[0][slot::plastic_rate], 1.0 / std::sqrt(3.0), 0.01);
  CHECK(P.solid_state.value[0][slot::temperature] == 293.0);  // isothermal: heat fraction 0
}

TEST(solid_artificial_stress_acts_on_tension_only) {
  MaterialSpec spec = soft_solid();
  spec.solid.artificial_stress = 0.3;
  Material mat;
  mat.solid = spec.solid;
  Mat<2> sigma;  // principal 3 (tension) along (1, 1)/sqrt 2 and -1 (compression) along (1, -1)/sqrt 2
  sigma << 1.0, 2.0, 2.0, 1.0;
  const Mat<2> R = JohnsonCook::artificial_stress(mat, sigma);
  Mat<2> expected;
  expected << -0.45, -0.45, -0.45, -0.45;  // -0.3 x 3 x e e^T
  CHECK((R - expected).cwiseAbs().maxCoeff() < 1e-14);
  Mat<2> compressed;  // principal -1 and -3
  compressed << -2.0, 1.0, 1.0, -2.0;
  CHECK(JohnsonCook::artificial_stress(mat, compressed).norm() == 0.0);
}

namespace {

// A jittered periodic block of 32 x 24 particles of Al6061-T6 (Nutto et al. Tables I, II; Steinberg's
// Mie-Grueneisen constants) at random velocities of +-150 m/s: it yields, heats and fails within 40 steps.
RunParameters block_deck() {
  MaterialSpec m;
  m.name = "al", m.model = "johnson_cook", m.rho0 = 2703.0;
  SolidParameters& s = m.solid;
  s.shear_modulus = 26e9, s.eos = SolidEos::mie_gruneisen, s.shock = {2703.0, 5240.0, 1.4, 1.97};
  s.plastic = true, s.strength = {324e6, 114e6, 0.42, 0.002, 1.34};
  s.fails = true, s.failure = {0.001, 0.005, -0.47, 0.0, 1.6};
  s.heat = {2703.0, 896.0, 0.95};
  s.artificial_stress = 0.3;
  m.c0 = s.wave_speed();
  RunParameters d;
  d.dimension = 2, d.terms = term::artificial_viscosity, d.alpha = 1.0, d.beta = 1.0, d.v_max = 150.0;
  d.dx = 1e-3, d.h = 1.3e-3, d.materials = {m};
  d.periodic_axes = {0, 1}, d.periodic_lo = {0.0, 0.0}, d.periodic_hi = {0.032, 0.024};
  return d;
}

Particles<2> block_particles() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), speed(-150.0, 150.0);
  Particles<2> P;
  P.resize(32 * 24);
  int k = 0;
  for (int i = 0; i < 32; ++i)
    for (int j = 0; j < 24; ++j, ++k) {
      P.x[k] = 1e-3 * Vec<2>(i + 0.5 + jitter(rng), j + 0.5 + jitter(rng));
      P.v[k] = Vec<2>(speed(rng), speed(rng));
      P.rho[k] = 2703.0, P.mass[k] = 2703.0e-6, P.id[k] = k, P.kind[k] = Kind::fluid;
    }
  return P;
}

}  // namespace

TEST(solid_block_steps_do_not_depend_on_the_thread_count) {
  const int saved = omp_get_max_threads();
  Particles<2> result[2];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    SolidBlock sim(block_deck(), block_particles());
    for (int s = 0; s < 40; ++s) CHECK(sim.step(2e-8, NoCrossings{}));
    result[threads - 1] = sim.particles();
  }
  omp_set_num_threads(saved);
  const Particles<2>& a = result[0];
  const Particles<2>& b = result[1];
  bool same = a.size() == b.size();
  int failed = 0, plastic = 0;
  for (std::size_t i = 0; same && i < a.size(); ++i) {
    same = a.x[i] == b.x[i] && a.v[i] == b.v[i] && a.rho[i] == b.rho[i] && a.tau[i] == b.tau[i] &&
           a.solid_state.value[i] == b.solid_state.value[i];
    failed += a.solid_state.value[i][slot::damage] >= 1.0, plastic += a.solid_state.value[i][slot::plastic_strain] > 0.0;
  }
  std::fprintf(stderr, "  %zu particles: %d plastic, %d failed; 1 and 2 threads bitwise equal: %s\n", a.size(), plastic,
               failed, same ? "yes" : "no");
  CHECK(same);
  CHECK(plastic > 100 && failed > 0 && failed < static_cast<int>(a.size()));
}
