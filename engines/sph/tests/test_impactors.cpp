// Rigid impactors (impactors.h) on a soft elastic block: a free sphere dropped onto it and a kinematic sphere
// pressed into it. Checked: the particles' and the body's momentum together (the contact's action and reaction),
// kinetic plus internal plus contact energy, the contact acting in compression only, a prescribed motion kept,
// the deck's refusals, and 1 and 2 threads bitwise equal.
#include <omp.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "simulation.h"

using namespace sph;

namespace {

using Block = Simulation<3, term::artificial_viscosity, ModelList<JohnsonCook>>;

constexpr double dx = 1e-3, rho0 = 1000.0;
constexpr int nx = 10, nz = 6;  // the block: nx x nx x nz particles, top at z = nz dx

// An elastic solid (G 1 MPa, K 2 MPa: wave speed 57.7 m/s) and a sphere of radius 3 dx, 7 x the density, above
// the block's centre, 0.2 dx clear of the top particles' extent, moving down at `speed` m/s.
RunParameters impact_deck(double speed, bool kinematic) {
  MaterialSpec m;
  m.name = "soft", m.model = "johnson_cook", m.rho0 = rho0;
  m.solid.shear_modulus = 1e6, m.solid.linear = {rho0, 2e6};
  m.solid.heat = {rho0, 0.0, 0.0};
  m.c0 = m.solid.wave_speed();
  RunParameters d;
  d.dimension = 3, d.terms = term::artificial_viscosity, d.alpha = 0.5, d.beta = 1.0, d.v_max = speed;
  d.dx = dx, d.h = 1.5 * dx, d.materials = {m};
  ImpactorSpec s;
  const double R = 3 * dx, mass = 7.0 * rho0 * 4.0 / 3.0 * M_PI * R * R * R, I = 0.4 * mass * R * R;
  const double centre[3] = {0.5 * nx * dx, 0.5 * nx * dx, (nz - 0.5) * dx + 0.5 * dx + R + 0.2 * dx};
  s.name = "ball", s.mass = mass, s.inertia = {I, 0, 0, 0, I, 0, 0, 0, I};
  s.centre = {centre[0], centre[1], centre[2]}, s.velocity = {0.0, 0.0, -speed}, s.angular_velocity = {0, 0, 0};
  s.spheres = {{centre[0], centre[1], centre[2], R}};
  s.stiffness = rho0 * m.c0 * m.c0 * dx, s.kinematic = kinematic;
  d.impactors = {s};
  return d;
}

Particles<3> block() {
  Particles<3> P;
  P.resize(nx * nx * nz);
  int k = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nx; ++j)
      for (int l = 0; l < nz; ++l, ++k) {
        P.x[k] = dx * Vec<3>(i + 0.5, j + 0.5, l + 0.5);
        P.v[k].setZero();
        P.rho[k] = rho0, P.mass[k] = rho0 * dx * dx * dx, P.id[k] = k, P.kind[k] = Kind::fluid;
      }
  return P;
}

struct Totals {
  Vec<3> momentum;  // particles + body, kg m/s
  double energy;    // kinetic + internal + body + contact, J
};
Totals totals(const Block& sim) {
  const auto& P = sim.particles();
  const auto& body = sim.impactors().bodies()[0];
  Totals t{body.body.mass * body.state.velocity, sim.impactors().kinetic_energy() + sim.impactors().contact_energy_at(P)};
  for (std::size_t i = 0; i < P.size(); ++i) {
    t.momentum += P.mass[i] * P.v[i];
    t.energy += 0.5 * P.mass[i] * P.v[i].squaredNorm() + P.mass[i] * P.solid_state.value[i][slot::energy];
  }
  return t;
}

}  // namespace

namespace {

struct Drop {
  double momentum, energy, peak_push, speed_after;  // worst drifts (relative), N, m/s
  bool pulled;
  double spin;  // rad/s
};
// The ball dropped at 5 m/s, 250 steps of 0.2 dx / c0 (or as many of `factor` dx / c0 as take the same time).
Drop drop(double factor) {
  Block sim(impact_deck(5.0, false), block());
  const Totals start = totals(sim);
  const double dt = factor * dx / sim.materials()[0].eos.c0;
  Drop r{0.0, 0.0, 0.0, 0.0, false, 0.0};
  for (int s = 0; s < static_cast<int>(std::lround(50.0 / factor)); ++s) {
    CHECK(sim.step(dt, NoCrossings{}));
    const Totals now = totals(sim);
    const auto& body = sim.impactors().bodies()[0];
    r.momentum = std::max(r.momentum, (now.momentum - start.momentum).norm() / start.momentum.norm());
    r.energy = std::max(r.energy, std::abs(now.energy / start.energy - 1.0));
    r.pulled = r.pulled || body.wrench.force.z() < 0.0;
    r.peak_push = std::max(r.peak_push, body.wrench.force.z());
  }
  r.speed_after = sim.impactors().bodies()[0].state.velocity.z();
  r.spin = sim.impactors().bodies()[0].state.angular_velocity.norm();
  return r;
}

}  // namespace

TEST(impactor_free_sphere_balances_momentum_and_energy_with_the_block) {
  const Drop a = drop(0.2), b = drop(0.1);
  std::fprintf(stderr, "  momentum drift %.2e, energy drift %.2e (at dt/2 %.2e, ratio %.2f), peak push %.3g N, "
               "ball now %.3f m/s\n", a.momentum, a.energy, b.energy, a.energy / b.energy, a.peak_push, a.speed_after);
  CHECK(a.momentum < 1e-12 && b.momentum < 1e-12);  // action and reaction, summed in the same order
  CHECK(a.energy < 1.5e-3);                          // kinetic + internal + body + contact
  CHECK(a.energy / b.energy > 3.5);                  // the step's second-order error, no drift of its own
  CHECK(!a.pulled && a.peak_push > 0.0);             // compression only, and it did touch
  CHECK(a.speed_after > -4.0);                       // the block slowed it
  CHECK(a.spin < 1e-9);                              // a central impact does not spin it
}

TEST(impactor_kinematic_sphere_keeps_its_prescribed_motion) {
  Block sim(impact_deck(1.0, true), block());
  const Vec<3> x0 = sim.impactors().bodies()[0].state.position;
  const double dt = 0.2 * dx / sim.materials()[0].eos.c0;
  for (int s = 0; s < 300; ++s) CHECK(sim.step(dt, NoCrossings{}));
  const auto& body = sim.impactors().bodies()[0];
  const double travelled = x0.z() - body.state.position.z();
  std::fprintf(stderr, "  travelled %.6e m (V t = %.6e m), push %.4g N\n", travelled, 300 * dt, body.wrench.force.z());
  CHECK_CLOSE(travelled, 300 * dt * 1.0, 1e-12);
  CHECK(body.state.velocity == Vec<3>(0.0, 0.0, -1.0));
  CHECK(body.wrench.force.z() > 0.0);  // the block resists the indenter
}

TEST(impactor_steps_do_not_depend_on_the_thread_count) {
  const int saved = omp_get_max_threads();
  Particles<3> result[2];
  Vec<3> ball[2];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Block sim(impact_deck(5.0, false), block());
    for (int s = 0; s < 150; ++s) CHECK(sim.step(5e-6, NoCrossings{}));
    result[threads - 1] = sim.particles(), ball[threads - 1] = sim.impactors().bodies()[0].state.velocity;
  }
  omp_set_num_threads(saved);
  bool same = result[0].size() == result[1].size() && ball[0] == ball[1];
  for (std::size_t i = 0; same && i < result[0].size(); ++i)
    same = result[0].x[i] == result[1].x[i] && result[0].v[i] == result[1].v[i] && result[0].tau[i] == result[1].tau[i];
  CHECK(same);
  CHECK(ball[0].z() > -5.0);  // it touched
}

TEST(impactor_deck_refusals_name_the_key) {
  auto refused = [](const std::string& text, const std::string& expected) {
    std::string message;
    RunParameters d;
    d.dimension = 3, d.dx = dx;
    try {
      parse_impactors(nlohmann::json::parse(text), d);
    } catch (const InputError& e) {
      message = e.what();
    }
    if (message.find(expected) == std::string::npos)
      std::fprintf(stderr, "  expected '%s' in '%s'\n", expected.c_str(), message.c_str());
    return message.find(expected) != std::string::npos;
  };
  const std::string ok = R"("name": "b", "mass": 1, "centre": [0, 0, 0], "stiffness": 1, "spheres": [[0, 0, 0, 1]])";
  CHECK(refused(R"([{)" + ok + R"(, "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 3]]}])", "not the inertia of a body"));
  CHECK(refused(R"([{)" + ok + R"(, "inertia": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]}])", "must be symmetric"));
  CHECK(refused(R"([{)" + ok + R"(, "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "kinematic": 1}])", "impactors[0].kinematic"));
  CHECK(refused(R"([{"name": "b", "mass": -1}])", "impactors[0].mass' must be > 0"));
  CHECK(refused(R"([{)" + ok + R"(, "inertia": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "spin": 1}])", "unknown key 'impactors[0].spin'"));
  RunParameters flat;
  flat.dimension = 2;
  bool two_d = false;
  try {
    parse_impactors(nlohmann::json::parse(R"([{"name": "b"}])"), flat);
  } catch (const InputError& e) {
    two_d = std::string(e.what()).find("3D only") != std::string::npos;
  }
  CHECK(two_d);
  // A sphere that overlaps a particle at the start.
  RunParameters d = impact_deck(1.0, false);
  d.impactors[0].centre[2] -= 0.5 * dx, d.impactors[0].spheres[0][2] -= 0.5 * dx;
  bool inside = false;
  try {
    Block sim(d, block());
  } catch (const InputError& e) {
    inside = std::string(e.what()).find("impactor 'ball' starts inside particle") != std::string::npos;
  }
  CHECK(inside);
}
