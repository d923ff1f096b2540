// One pair of particles: continuity (eq. 7), pressure gradient (eq. 9), Morris
// viscosity (eq. 10) and artificial viscosity (eqs. 11-12) against a hand computation.
#include <omp.h>

#include <cmath>
#include <random>

#include "check.h"
#include "simulation.h"

using namespace sph;

namespace {

constexpr unsigned kTerms = term::morris_viscosity | term::artificial_viscosity;

RunParameters pair_deck() {
  RunParameters d;
  d.dimension = 2;
  d.terms = kTerms;
  d.rho0 = 1000.0, d.c0 = 20.0, d.gamma = 7.0, d.background_pressure = 500.0, d.v_max = 2.0;
  d.viscosity = 1e-3, d.alpha = 0.8, d.beta = 1.5;
  d.h = 1e-3, d.dx = 0.8e-3;
  return d;
}

Particles<2> two_particles() {
  Particles<2> P;
  P.resize(2);
  P.x[0] = {0.0, 0.0}, P.v[0] = {0.5, 0.1}, P.rho[0] = 1005.0, P.mass[0] = 1.0e-3;
  P.x[1] = {1.2e-3, 0.4e-3}, P.v[1] = {-0.3, 0.2}, P.rho[1] = 998.0, P.mass[1] = 1.1e-3;
  P.id = {0, 1};
  return P;
}

int index_of(const Particles<2>& P, int id) { return P.id[0] == id ? 0 : 1; }

}  // namespace

TEST(pair_interaction_matches_hand_computation) {
  const RunParameters deck = pair_deck();
  Simulation<2, kTerms> sim(deck, two_particles());
  sim.compute_rates();
  const auto& P = sim.particles();
  const int a = index_of(P, 0), b = index_of(P, 1);

  // By hand, for particle a (id 0) with neighbour b (id 1).
  const double h = 1e-3, rho0 = 1000.0, c0 = 20.0, pB = 500.0;
  const double xab = 0.0 - 1.2e-3, yab = 0.0 - 0.4e-3;  // r_ab = x_a - x_b
  const double vxab = 0.5 - (-0.3), vyab = 0.1 - 0.2;  // v_ab
  const double ra = 1005.0, rb = 998.0, mb = 1.1e-3;
  const double r2 = xab * xab + yab * yab, r = std::sqrt(r2), q = r / h;
  const double alpha_d = 7.0 / (4.0 * M_PI * h * h);
  const double dWdr = -5.0 * alpha_d * q / h * std::pow(1.0 - q / 2.0, 3);  // d/dr of eq. 8
  const double gx = dWdr * xab / r, gy = dWdr * yab / r;                    // grad_a W_ab
  const double B = rho0 * c0 * c0 / 7.0;
  const double pa = B * (std::pow(ra / rho0, 7) - 1.0) + pB, pb = B * (std::pow(rb / rho0, 7) - 1.0) + pB;
  // eq. 7 (sign of -rho div v)
  const double drho = ra * mb / rb * (vxab * gx + vyab * gy);
  // eq. 9 / rho_a
  const double sp = mb * (pa / (ra * ra) + pb / (rb * rb));
  // eq. 10 / rho_a with mu = rho0 nu
  const double mu = rho0 * 1e-3, eta2 = 0.01 * h * h;
  const double sv = mb * (mu + mu) * (xab * gx + yab * gy) / (ra * rb * (r2 + eta2));
  // eqs. 11-12
  const double vr = vxab * xab + vyab * yab;
  CHECK(vr < 0.0);
  const double mu_ab = h * vr / (r2 + eta2);
  const double ca = c0 * std::pow(ra / rho0, 3), cb = c0 * std::pow(rb / rho0, 3);
  const double Pi = (-0.8 * 0.5 * (ca + cb) * mu_ab + 1.5 * mu_ab * mu_ab) / (0.5 * (ra + rb));
  const double ax = -sp * gx + sv * vxab - mb * Pi * gx;
  const double ay = -sp * gy + sv * vyab - mb * Pi * gy;

  CHECK_CLOSE(P.p[a], pa, 1e-12);
  CHECK_CLOSE(P.drho[a], drho, 1e-12);
  CHECK_CLOSE(P.acc[a][0], ax, 1e-12);
  CHECK_CLOSE(P.acc[a][1], ay, 1e-12);
  CHECK(P.drho[a] > 0.0);  // approaching particles get denser
  // Every pair term is antisymmetric: momentum is conserved.
  const Vec<2> momentum = P.mass[a] * P.acc[a] + P.mass[b] * P.acc[b];
  CHECK(momentum.norm() <= 1e-12 * (P.mass[a] * P.acc[a]).norm());
}

TEST(pair_terms_switched_off_cost_nothing_and_change_nothing) {
  RunParameters deck = pair_deck();
  deck.terms = 0;
  Simulation<2, 0> plain(deck, two_particles());
  plain.compute_rates();
  Simulation<2, kTerms> full(pair_deck(), two_particles());
  full.compute_rates();
  const auto &P = plain.particles(), &F = full.particles();
  CHECK_CLOSE(P.drho[0], F.drho[0], 1e-14);  // continuity is always on
  CHECK((P.acc[0] - F.acc[0]).norm() > 0.0);  // viscosity terms only in `full`
  static_assert(!Simulation<2, 0>::has(term::morris_viscosity));
}

TEST(boundary_particle_gets_density_but_no_motion) {
  RunParameters deck = pair_deck();
  Particles<2> P = two_particles();
  P.kind[1] = Kind::boundary;
  Simulation<2, kTerms> sim(deck, P);
  const int b = index_of(sim.particles(), 1);
  const Vec<2> xb = sim.particles().x[b], vb = sim.particles().v[b];
  sim.step(1e-6, NoCrossings{});
  CHECK(sim.particles().x[b] == xb);
  CHECK(sim.particles().v[b] == vb);
  CHECK(sim.particles().rho[b] != 998.0);
}

TEST(artificial_viscosity_off_the_walls) {
  // A fluid particle moving at 1 m/s parallel to a row of boundary particles
  // (spacing 0.8 mm, 0.5 mm below it): with walls = true eqs. 11-12 drag it
  // back; with walls = false the wall pairs give it exactly what alpha = beta
  // = 0 gives (pressure and Morris viscosity only). Between two fluid
  // particles the switch changes nothing.
  auto scene = [](bool second_fluid) {
    Particles<2> P;
    const int walls = 11, n = walls + 1 + (second_fluid ? 1 : 0);
    P.resize(n);
    for (int i = 0; i < walls; ++i) {
      P.x[i] = {(i - 5) * 0.8e-3 + 0.13e-3, 0.0}, P.v[i] = {0.0, 0.0};
      P.kind[i] = Kind::boundary;
    }
    P.x[walls] = {0.0, 0.5e-3}, P.v[walls] = {1.0, 0.0}, P.kind[walls] = Kind::fluid;
    if (second_fluid) P.x[walls + 1] = {0.9e-3, 0.7e-3}, P.v[walls + 1] = {-0.2, 0.1}, P.kind[walls + 1] = Kind::fluid;
    for (int i = 0; i < n; ++i) P.rho[i] = 1000.0 + 0.5 * i, P.mass[i] = 0.64e-3, P.id[i] = i;
    return P;
  };
  auto acc_of = [&](double alpha, double beta, bool walls, bool second_fluid) {
    RunParameters deck = pair_deck();
    deck.alpha = alpha, deck.beta = beta, deck.av_walls = walls;
    Simulation<2, kTerms> sim(deck, scene(second_fluid));
    sim.compute_rates();
    const auto& P = sim.particles();
    for (std::size_t i = 0; i < P.id.size(); ++i)
      if (P.id[i] == 11) return Vec<2>(P.acc[i]);
    return Vec<2>(Vec<2>::Constant(NAN));
  };
  const Vec<2> none = acc_of(0.0, 0.0, true, false), on = acc_of(0.8, 1.5, true, false);
  const Vec<2> off = acc_of(0.8, 1.5, false, false);
  CHECK(off == none);                    // no artificial viscosity from the wall, exactly
  CHECK(on[0] < none[0] - 1.0);          // with walls = true: a drag against the motion (> 1 m/s^2)
  CHECK(acc_of(0.0, 0.0, false, false) == none);
  // A fluid neighbour: the fluid-fluid pair keeps its artificial viscosity.
  const Vec<2> pair_none = acc_of(0.0, 0.0, false, true), pair_off = acc_of(0.8, 1.5, false, true);
  CHECK((pair_off - pair_none).norm() > 1.0);
  // With walls = true both add up: (fluid pair's part) + (wall's part).
  const Vec<2> both = acc_of(0.8, 1.5, true, true) - pair_none, parts = (pair_off - pair_none) + (on - none);
  CHECK((both - parts).norm() <= 1e-9 * both.norm());
}

TEST(periodic_pair_across_the_box_edge) {
  // The same pair, moved so that it straddles the periodic edge x = 0 / x = L:
  // the rates must equal those of the unwrapped pair.
  RunParameters deck = pair_deck();
  deck.periodic_axes = {0};
  deck.periodic_lo = {0.0};
  deck.periodic_hi = {5e-3};
  Particles<2> P = two_particles();
  P.x[0][0] = 4.6e-3, P.x[1][0] = 0.8e-3;  // separation 1.2e-3 through the edge
  Simulation<2, kTerms> wrapped(deck, P);
  wrapped.compute_rates();
  Simulation<2, kTerms> plain(pair_deck(), two_particles());
  plain.compute_rates();
  const auto &W = wrapped.particles(), &U = plain.particles();
  const int wa = index_of(W, 0), ua = index_of(U, 0);
  CHECK_CLOSE(W.drho[wa], U.drho[ua], 1e-10);
  CHECK_CLOSE(W.acc[wa][0], U.acc[ua][0], 1e-10);
  CHECK_CLOSE(W.acc[wa][1], U.acc[ua][1], 1e-10);
}

TEST(rates_do_not_depend_on_the_thread_count) {
  // A jittered 3D lattice with fluid and boundary particles, every term on:
  // gathering per particle gives bitwise the same rates on 1 and 2 threads.
  constexpr unsigned all = term::all & ~term::wall_penalty;
  RunParameters deck;
  deck.dimension = 3, deck.terms = all;
  deck.rho0 = 1000.0, deck.c0 = 20.0, deck.v_max = 2.0, deck.viscosity = 1e-4, deck.alpha = 0.1, deck.beta = 0.2;
  deck.h = 1.3e-3, deck.dx = 1e-3, deck.body_force = {0.0, 0.0, -9.81};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), speed(-1.0, 1.0);
  Particles<3> P;
  P.resize(16 * 16 * 16);
  for (int i = 0, k = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j)
      for (int l = 0; l < 16; ++l, ++k) {
        P.x[k] = 1e-3 * Vec<3>(i + jitter(rng), j + jitter(rng), l + jitter(rng));
        P.v[k] = Vec<3>(speed(rng), speed(rng), speed(rng));
        P.rho[k] = 1000.0 * (1.0 + 0.01 * jitter(rng)), P.mass[k] = 1e-6, P.id[k] = k;
        P.kind[k] = l < 3 ? Kind::boundary : Kind::fluid;
      }
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  Simulation<3, all> one(deck, P);
  one.compute_rates();
  omp_set_num_threads(2);
  Simulation<3, all> two(deck, P);
  two.compute_rates();
  omp_set_num_threads(before);
  bool same = true;
  for (std::size_t i = 0; i < P.size(); ++i)
    same = same && one.particles().acc[i] == two.particles().acc[i] && one.particles().drho[i] == two.particles().drho[i];
  CHECK(same);
}

TEST(four_wide_rows_match_a_brute_force_sum_on_every_cpu_path) {
  // The plain scalar path's fluid-fluid rows run 4 pairs at a time (pair_lanes.h). On a jittered periodic 3D
  // block with unequal masses, eqs. 7, 9, 10 and 11-12 summed pair by pair over all particles (minimum image)
  // give the same rates to 1e-12 of their scale, and the SSE2 copy of the loop gives the AVX2 copy's bits.
  constexpr unsigned terms = term::morris_viscosity | term::artificial_viscosity;
  constexpr int n = 8;
  const double h = 1.3e-3, dx = 1e-3, L = n * dx, rho0 = 1000.0, c0 = 20.0, nu = 1e-4, alpha = 0.1, beta = 0.2;
  RunParameters deck;
  deck.dimension = 3, deck.terms = terms;
  deck.rho0 = rho0, deck.c0 = c0, deck.gamma = 7.0, deck.v_max = 2.0, deck.viscosity = nu;
  deck.alpha = alpha, deck.beta = beta, deck.h = h, deck.dx = dx;
  deck.periodic_axes = {0, 1, 2}, deck.periodic_lo = {0.0, 0.0, 0.0}, deck.periodic_hi = {L, L, L};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15), speed(-1.0, 1.0);
  Particles<3> P;
  P.resize(n * n * n);
  for (int k = 0; k < n * n * n; ++k) {
    P.x[k] = dx * Vec<3>(k % n + 0.5 + jitter(rng), (k / n) % n + 0.5 + jitter(rng), k / (n * n) + 0.5 + jitter(rng));
    P.v[k] = Vec<3>(speed(rng), speed(rng), speed(rng));
    P.rho[k] = rho0 * (1.0 + 0.05 * jitter(rng)), P.mass[k] = 1e-6 * (1.0 + jitter(rng)), P.id[k] = k;
  }
  Simulation<3, terms> sim(deck, P);
  sim.compute_rates();
  const auto& S = sim.particles();
  const double alpha_d = 21.0 / (16.0 * M_PI * h * h * h), B = rho0 * c0 * c0 / 7.0, mu = rho0 * nu, eta2 = 0.01 * h * h;
  auto p = [&](double rho) { return B * (std::pow(rho / rho0, 7) - 1.0); };
  auto c = [&](double rho) { return c0 * std::pow(rho / rho0, 3); };
  double worst = 0.0, scale = 0.0;
  for (std::size_t a = 0; a < S.size(); ++a) {
    Vec<3> acc = Vec<3>::Zero();
    double drho = 0.0;
    for (std::size_t b = 0; b < S.size(); ++b) {
      Vec<3> r = S.x[a] - S.x[b];
      for (int d = 0; d < 3; ++d) r[d] -= L * std::round(r[d] / L);
      const double r2 = r.squaredNorm(), q = std::sqrt(r2) / h;
      if (b == a || q >= 2.0) continue;
      const Vec<3> g = -5.0 * alpha_d * std::pow(1.0 - q / 2.0, 3) / (h * h) * r;  // grad_a W_ab
      const Vec<3> v = S.v[a] - S.v[b];
      const double ra = S.rho[a], rb = S.rho[b], mb = S.mass[b], vr = v.dot(r);
      const double mu_ab = h * std::min(vr, 0.0) / (r2 + eta2);
      const double Pi = (-alpha * 0.5 * (c(ra) + c(rb)) * mu_ab + beta * mu_ab * mu_ab) / (0.5 * (ra + rb));
      drho += ra * mb / rb * v.dot(g);
      acc += -mb * (p(ra) / (ra * ra) + p(rb) / (rb * rb) + Pi) * g + mb * 2.0 * mu * r.dot(g) / (ra * rb * (r2 + eta2)) * v;
    }
    worst = std::max({worst, (acc - S.acc[a]).norm(), std::abs(drho - S.drho[a]) * 1e3});
    scale = std::max({scale, acc.norm(), std::abs(drho) * 1e3});
  }
  CHECK(scale > 1.0);
  CHECK(worst <= 1e-12 * scale);
  sse2_only = true;
  Simulation<3, terms> sse2(deck, P);
  sse2.compute_rates();
  sse2_only = false;
  bool same = true;
  for (std::size_t i = 0; i < P.size(); ++i)
    same = same && sse2.particles().acc[i] == S.acc[i] && sse2.particles().drho[i] == S.drho[i];
  CHECK(same);
}
