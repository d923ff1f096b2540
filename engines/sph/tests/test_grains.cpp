// Rigid grains that the fluid drags (grains.h, grain_pairs.h): a sphere of particles in a fluid. Checked: the
// momentum of fluid and grain together in a periodic box (viscous fluid, every pair term of eq. G1), their angular
// momentum in a free blob (inviscid: central pair forces), the grain's particles kept rigid, a grain in a fluid at
// rest left at rest, a grain turning with the fluid free of viscous torque (eqs. G4-G5), two grains colliding
// (eq. G6) and a grain bouncing off a wall plane (eq. G7) at the set restitution, 1 and 2 threads bitwise equal, and
// the deck's refusals.
#include <omp.h>

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "simulation.h"

using namespace sph;

namespace {

using Viscous = Simulation<3, term::morris_viscosity | term::grains>;
using Inviscid = Simulation<3, term::artificial_viscosity | term::grains>;

constexpr double dx = 1e-3, rho0 = 1000.0, c0 = 2.0;
constexpr int n = 10;              // the box: n^3 lattice sites
constexpr double radius = 2.6 * dx;  // the grain: the sites within this radius of the box's centre

// A Newtonian fluid (nu 1e-4 m^2/s) with one grain of density `density` moving at V, turning at omega;
// periodic on every axis when `periodic`.
RunParameters grain_deck(unsigned terms, bool periodic, double density) {
  RunParameters d;
  d.dimension = 3, d.terms = terms, d.rho0 = rho0, d.c0 = c0, d.v_max = 0.2, d.viscosity = 1e-4;
  d.alpha = 0.1, d.dx = dx, d.h = 1.3 * dx;
  if (periodic) d.periodic_axes = {0, 1, 2}, d.periodic_lo = {0, 0, 0}, d.periodic_hi = {n * dx, n * dx, n * dx};
  GrainSpec g;
  g.name = "ball", g.density = density, g.velocity = {0.05, -0.02, 0.01}, g.angular_velocity = {3.0, -5.0, 20.0};
  g.body_force = {0, 0, 0};
  d.grains = {g};
  return d;
}

// The lattice of the box, its sites within `radius` of the centre (shifted off the lattice's symmetry) the grain's,
// the fluid moving in a shear wave of amplitude u (m/s).
Particles<3> grain_in_fluid(double u) {
  Particles<3> P;
  P.grains = true;
  P.resize(n * n * n);
  const Vec<3> centre = dx * Vec<3>(0.5 * n + 0.1, 0.5 * n - 0.2, 0.5 * n + 0.05);
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < n; ++l, ++k) {
        P.x[k] = dx * Vec<3>(i + 0.5, j + 0.5, l + 0.5);
        P.v[k] = u * Vec<3>(std::sin(2 * M_PI * (j + 0.5) / n), 0.3 * std::cos(2 * M_PI * (l + 0.5) / n), 0.0);
        P.rho[k] = rho0, P.mass[k] = rho0 * dx * dx * dx, P.id[k] = k;
        const bool inside = (P.x[k] - centre).norm() < radius;
        P.kind[k] = inside ? Kind::body : Kind::fluid, P.grain[k] = inside ? 0 : -1;
      }
  return P;
}

struct Totals {
  Vec<3> momentum, angular;  // kg m/s, kg m^2/s (about the origin)
  double scale_p, scale_l;   // sums of |m v| and |m x x v|: what rounding is relative to
};
template <class Sim>
Totals totals(const Sim& sim) {
  const auto& P = sim.particles();
  const auto& g = sim.grains().grains()[0];
  Totals t{sim.grains().momentum(), sim.grains().angular_momentum(), 0.0, 0.0};
  t.scale_p = g.body.mass * g.state.velocity.norm(), t.scale_l = t.angular.norm();
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (!P.moves(i)) continue;
    t.momentum += P.mass[i] * P.v[i], t.angular += P.mass[i] * P.x[i].cross(P.v[i]);
    t.scale_p += P.mass[i] * P.v[i].norm(), t.scale_l += P.mass[i] * P.x[i].cross(P.v[i]).norm();
  }
  return t;
}

// Largest deviation (m) of the grain's particle distances from their start, over the particles of grain 0.
double rigidity(const Particles<3>& P, const Particles<3>& start) {
  double worst = 0.0;
  for (std::size_t a = 0; a < P.size(); ++a)
    for (std::size_t b = a + 1; b < P.size(); ++b) {
      if (P.kind[a] != Kind::body || P.kind[b] != Kind::body) continue;
      std::size_t a0 = 0, b0 = 0;  // the same particles (by id) at the start
      for (std::size_t i = 0; i < start.size(); ++i) a0 = start.id[i] == P.id[a] ? i : a0, b0 = start.id[i] == P.id[b] ? i : b0;
      worst = std::max(worst, std::abs((P.x[a] - P.x[b]).norm() - (start.x[a0] - start.x[b0]).norm()));
    }
  return worst;
}

// The contact tests' fluid: inviscid (artificial viscosity only) and light, rho_f kg/m^3.
constexpr double rho_f = 1.0, rho_g = 1000.0;  // the fluid's and the grains' densities, kg/m^3
RunParameters light_fluid_deck() {
  RunParameters d;
  d.dimension = 3, d.terms = term::artificial_viscosity | term::grains, d.rho0 = rho_f, d.c0 = c0, d.v_max = 0.2;
  d.alpha = 0.1, d.dx = dx, d.h = 1.3 * dx;
  return d;
}

// An nx x ny x ny lattice of that fluid at rest whose sites within 2.1 dx of centres[g] are grain g's; count[g]
// their numbers.
Particles<3> light_blob(int nx, int ny, const std::vector<Vec<3>>& centres, std::vector<int>& count) {
  Particles<3> P;
  P.grains = true;
  P.resize(nx * ny * ny);
  count.assign(centres.size(), 0);
  int k = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int l = 0; l < ny; ++l, ++k) {
        P.x[k] = dx * Vec<3>(i + 0.5, j + 0.5, l + 0.5), P.v[k].setZero();
        P.rho[k] = rho_f, P.mass[k] = rho_f * dx * dx * dx, P.id[k] = k;
        int grain = -1;
        for (std::size_t g = 0; g < centres.size(); ++g) grain = (P.x[k] - centres[g]).norm() < 2.1 * dx ? int(g) : grain;
        P.kind[k] = grain >= 0 ? Kind::body : Kind::fluid, P.grain[k] = grain;
        if (grain >= 0) ++count[grain];
      }
  return P;
}

}  // namespace

TEST(grain_and_viscous_fluid_keep_their_momentum_in_a_periodic_box) {
  Viscous sim(grain_deck(term::morris_viscosity | term::grains, true, 3000.0), grain_in_fluid(0.05));
  const Particles<3> start = sim.particles();
  const Totals t0 = totals(sim);
  const double dt = 0.2 * 1.3 * dx / c0;
  double worst = 0.0;
  for (int s = 0; s < 200; ++s) {
    const Totals before = totals(sim);
    CHECK(sim.step(dt, NoCrossings{}));
    const Totals now = totals(sim);
    worst = std::max(worst, (now.momentum - before.momentum).norm() / before.scale_p);
  }
  const auto& g = sim.grains().grains()[0];
  const double rigid = rigidity(sim.particles(), start);
  std::fprintf(stderr, "  %zu grain particles; momentum change per step %.2e of sum |m v|; grain V = (%.4f %.4f %.4f) "
               "m/s from (0.05 -0.02 0.01), |F| %.3g N; distances kept to %.2e m\n", g.particles, worst,
               g.state.velocity.x(), g.state.velocity.y(), g.state.velocity.z(), g.wrench.force.norm(), rigid);
  CHECK(g.particles == 72);  // the sites within 2.6 dx of the centre
  CHECK(worst < 1e-13);                                          // action and reaction pair by pair (eq. G1)
  CHECK((totals(sim).momentum - t0.momentum).norm() < 1e-12 * t0.scale_p);
  CHECK(g.wrench.force.norm() > 0.0 && (g.state.velocity - Vec<3>(0.05, -0.02, 0.01)).norm() > 1e-4);  // dragged
  CHECK(rigid < 1e-15);                                          // placed rigidly (eq. G3)
}

TEST(grain_and_inviscid_blob_keep_their_angular_momentum) {
  Inviscid sim(grain_deck(term::artificial_viscosity | term::grains, false, 1500.0), grain_in_fluid(0.05));
  const double dt = 0.2 * 1.3 * dx / c0;
  double worst_l = 0.0, worst_p = 0.0;
  for (int s = 0; s < 200; ++s) {
    const Totals before = totals(sim);
    CHECK(sim.step(dt, NoCrossings{}));
    const Totals now = totals(sim);
    worst_l = std::max(worst_l, (now.angular - before.angular).norm() / before.scale_l);
    worst_p = std::max(worst_p, (now.momentum - before.momentum).norm() / before.scale_p);
  }
  const auto& g = sim.grains().grains()[0];
  std::fprintf(stderr, "  angular momentum change per step %.2e of sum |m x x v|, momentum %.2e; grain omega "
               "(%.3f %.3f %.3f) rad/s from (3 -5 20)\n", worst_l, worst_p, g.state.angular_velocity.x(),
               g.state.angular_velocity.y(), g.state.angular_velocity.z());
  CHECK(worst_l < 1e-12);  // central pair forces at the mid-step positions, summed about the grain's mid-step centre
  CHECK(worst_p < 1e-13);
}

TEST(grain_in_fluid_at_rest_stays_at_rest) {
  RunParameters d = grain_deck(term::morris_viscosity | term::grains, true, 1000.0);
  d.grains[0].velocity = {0, 0, 0}, d.grains[0].angular_velocity = {0, 0, 0};
  Viscous sim(d, grain_in_fluid(0.0));
  for (int s = 0; s < 100; ++s) CHECK(sim.step(0.2 * 1.3 * dx / c0, NoCrossings{}));
  const auto& g = sim.grains().grains()[0];
  std::fprintf(stderr, "  at rest: |V| %.2e m/s, |omega| %.2e rad/s\n", g.state.velocity.norm(),
               g.state.angular_velocity.norm());
  CHECK(g.state.velocity.norm() < 1e-6 && g.state.angular_velocity.norm() < 1e-3);
}

TEST(grain_turning_with_the_fluid_feels_no_viscous_torque) {
  // Fluid and grain in one rigid rotation (a free blob, omega = (3, -5, 20) rad/s about the grain's centre): the
  // strain rate vanishes, so does the viscous stress. Eq. G4 hands the fluid the rigid rotation at the grain's
  // particles and eq. G5 leaves the Laplacian's flux of the rotation out of the torque, so the viscous pairs add
  // nothing to it: the torque of the viscous run equals the inviscid run's (pressure only; artificial viscosity
  // vanishes on a rigid rotation).
  Vec<3> torque[2];
  double flux = 0.0;  // the torque eq. G5 removes, 2 mu V |omega| (the rotation's Laplacian flux), N m
  for (int viscous = 0; viscous <= 1; ++viscous) {
    const unsigned terms = (viscous ? term::morris_viscosity : term::artificial_viscosity) | term::grains;
    RunParameters d = grain_deck(terms, false, 1000.0);
    d.grains[0].velocity = {0, 0, 0};
    Particles<3> P = grain_in_fluid(0.0);
    const Vec<3> omega(3.0, -5.0, 20.0);
    Vec<3> centre = Vec<3>::Zero();
    int count = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.kind[i] == Kind::body) centre += P.x[i], ++count;
    centre /= count;
    for (std::size_t i = 0; i < P.size(); ++i) P.v[i] = omega.cross(P.x[i] - centre);
    flux = 2.0 * rho0 * d.viscosity * count * dx * dx * dx * omega.norm();
    if (viscous) {
      Viscous sim(d, P);
      CHECK(sim.step(1e-9, NoCrossings{}));
      torque[1] = sim.grains().grains()[0].wrench.torque;
    } else {
      Inviscid sim(d, P);
      CHECK(sim.step(1e-9, NoCrossings{}));
      torque[0] = sim.grains().grains()[0].wrench.torque;
    }
  }
  std::fprintf(stderr, "  viscous torque on the co-rotating grain %.2e N m (2 mu V |omega| = %.2e N m)\n",
               (torque[1] - torque[0]).norm(), flux);
  CHECK((torque[1] - torque[0]).norm() < 1e-6 * flux);
}

TEST(two_grains_collide_at_the_set_restitution_keeping_momentum) {
  // Two grains of 1000 kg/m^3 (the sites within 2.1 dx of two centres 6 dx apart on a line off the lattice's
  // axes) close at 0.2 m/s in a free blob of fluid a thousand times lighter (inviscid: central pair forces);
  // contact spheres of 2.9 dx, eq. G6 with e = 0.8 and a contact lasting about 60 steps. Checked: the relative
  // normal speed after against e times the speed before (the fluid's drag on the way in and out brings about 1e-3),
  // momentum and angular momentum of grains and fluid (a free blob) together per step.
  constexpr int nx = 16, ny = 8;
  const double e = 0.8;
  RunParameters d = light_fluid_deck();
  const Vec<3> line = Vec<3>(1.0, 0.15, 0.1).normalized();
  const Vec<3> mid = dx * Vec<3>(0.5 * nx + 0.05, 0.5 * ny + 0.1, 0.5 * ny - 0.05);
  const std::vector<Vec<3>> centres = {mid - 3.0 * dx * line, mid + 3.0 * dx * line};
  for (int g = 0; g < 2; ++g) {
    GrainSpec s;
    s.name = g ? "right" : "left", s.density = rho_g, s.contact_radius = 2.9 * dx, s.body_force = {0, 0, 0};
    const Vec<3> v = (g ? -0.1 : 0.1) * line;
    s.velocity = {v.x(), v.y(), v.z()}, s.angular_velocity = {0, 0, 0};
    d.grains.push_back(s);
  }
  d.grain_contact.restitution = e;
  std::vector<int> counts;
  const Particles<3> P = light_blob(nx, ny, centres, counts);
  const int count = counts[0];
  const double m_eff = 0.5 * rho_g * count * dx * dx * dx;
  const double dt = 0.2 * 1.3 * dx / c0, contact_time = 60 * dt;  // t_c = pi sqrt(m / k) undamped
  d.grain_contact.stiffness = M_PI * M_PI * m_eff / (contact_time * contact_time);
  Inviscid sim(d, P);
  auto relative_speed = [&]() {
    const auto& G = sim.grains().grains();
    return (G[1].state.velocity - G[0].state.velocity).dot(line);
  };
  auto totals_of = [&](Vec<3>& p, Vec<3>& l, double& scale) {
    p = sim.grains().momentum(), l = sim.grains().angular_momentum(), scale = 0.0;
    for (const auto& g : sim.grains().grains()) scale += g.body.mass * g.state.velocity.norm();
    const auto& Q = sim.particles();
    for (std::size_t i = 0; i < Q.size(); ++i)
      if (Q.moves(i)) p += Q.mass[i] * Q.v[i], l += Q.mass[i] * Q.x[i].cross(Q.v[i]), scale += Q.mass[i] * Q.v[i].norm();
  };
  const double before = relative_speed();
  const Vec<3> v_start = sim.grains().grains()[1].state.velocity;
  Vec<3> fluid_impulse = Vec<3>::Zero();  // the fluid's on the right grain, as its kicks apply it
  double worst_p = 0.0, worst_l = 0.0, closest = 1.0;
  for (int s = 0; s < 200; ++s) {
    Vec<3> p0, l0, p1, l1;
    double scale;
    totals_of(p0, l0, scale);
    CHECK(sim.step(dt, NoCrossings{}));
    fluid_impulse += dt * sim.grains().grains()[1].wrench.force;
    totals_of(p1, l1, scale);
    worst_p = std::max(worst_p, (p1 - p0).norm() / scale);
    worst_l = std::max(worst_l, (l1 - l0).norm() / (scale * nx * dx));
    const auto& G = sim.grains().grains();
    closest = std::min(closest, (G[1].state.position - G[0].state.position).norm());
  }
  const double after = relative_speed();
  std::fprintf(stderr, "  %d particles a grain; relative normal speed %.4f -> %.4f m/s: restitution %.4f (set %.2f); "
               "closest centres %.2f dx; momentum change per step %.1e, angular %.1e\n", count, before, after,
               -after / before, e, closest / dx, worst_p, worst_l);
  CHECK(std::abs(-after / before - e) < 0.02 * e);
  CHECK(closest < 5.8 * dx && closest > 4.0 * dx);  // they touched and did not pass through
  CHECK(worst_p < 1e-13 && worst_l < 1e-12);
  // The contact's record over every step (no recorder closed it here): equal and opposite impulses that, with the
  // fluid's, are the grain's momentum change; about (1 + e) m V along the line (the fluid's drag on the way in and
  // out apart); acting for less than the undamped contact time, its peak above the mean force and below twice it.
  const auto& G = sim.grains().grains();
  const double mass = G[1].body.mass, impulse = G[1].contact_impulse.dot(line);
  const Vec<3> change = mass * (G[1].state.velocity - v_start);
  std::fprintf(stderr, "  contact impulse %.5e N s against (1 + e) m V = %.5e; with the fluid's, the momentum change to "
               "%.1e; peak %.4e N; acted %.1f steps\n", impulse, (1.0 + e) * mass * 0.1,
               (G[1].contact_impulse + fluid_impulse - change).norm() / change.norm(), G[1].contact_peak,
               G[1].contact_time / dt);
  CHECK((G[0].contact_impulse + G[1].contact_impulse).norm() < 1e-14 * std::abs(impulse));
  CHECK((G[1].contact_impulse + fluid_impulse - change).norm() < 1e-12 * change.norm());
  CHECK(std::abs(impulse / ((1.0 + e) * mass * 0.1) - 1.0) < 0.03);
  CHECK(G[1].contact_time > 30 * dt && G[1].contact_time <= contact_time);
  CHECK(G[1].contact_peak > impulse / G[1].contact_time && G[1].contact_peak < 2.0 * impulse / G[1].contact_time);
}

TEST(grain_bounces_off_a_wall_plane_at_the_set_restitution) {
  // One grain of 1000 kg/m^3 (the sites within 2.1 dx of a centre) moves at 0.1 m/s against a wall plane whose
  // normal is off the lattice's axes, through a free blob of fluid a thousand times lighter; eq. G7 with e = 0.7,
  // a contact of about 60 steps. Checked: the normal speed after against -e times the speed before, the tangential
  // velocity kept (the contact is frictionless), and the grain stopped by the plane short of its contact radius.
  constexpr int nx = 12, ny = 8;
  const double e = 0.7;
  RunParameters d = light_fluid_deck();
  const Vec<3> n = Vec<3>(1.0, 0.15, 0.1).normalized();
  const Vec<3> tangent = Vec<3>(0.0, 0.02, -0.01) - Vec<3>(0.0, 0.02, -0.01).dot(n) * n;  // along the plane
  const Vec<3> centre = dx * Vec<3>(0.5 * nx + 0.05, 0.5 * ny + 0.1, 0.5 * ny - 0.05);
  const Vec<3> plane = centre - 4.0 * dx * n;  // the contact sphere (2.9 dx) touches after 1.1 dx
  GrainSpec s;
  s.name = "ball", s.density = rho_g, s.contact_radius = 2.9 * dx, s.body_force = {0, 0, 0};
  const Vec<3> v = -0.1 * n + tangent;
  s.velocity = {v.x(), v.y(), v.z()}, s.angular_velocity = {0, 0, 0};
  d.grains = {s};
  d.grain_contact.restitution = e;
  d.grain_contact.walls = {{plane.x(), plane.y(), plane.z(), n.x(), n.y(), n.z()}};
  std::vector<int> counts;
  const Particles<3> P = light_blob(nx, ny, {centre}, counts);
  const int count = counts[0];
  const double dt = 0.2 * 1.3 * dx / c0, contact_time = 60 * dt;  // t_c = pi sqrt(M / k) undamped
  d.grain_contact.stiffness = M_PI * M_PI * rho_g * count * dx * dx * dx / (contact_time * contact_time);
  Inviscid sim(d, P);
  double nearest = 1.0;
  for (int step = 0; step < 160; ++step) {
    CHECK(sim.step(dt, NoCrossings{}));
    nearest = std::min(nearest, (sim.grains().grains()[0].state.position - plane).dot(n));
  }
  const Vec<3> after = sim.grains().grains()[0].state.velocity;
  const Vec<3> slide = after - after.dot(n) * n;
  std::fprintf(stderr, "  normal speed -0.1 -> %.5f m/s: restitution %.4f (set %.2f); tangential change %.1e m/s; "
               "nearest centre %.2f dx from the plane\n", after.dot(n), after.dot(n) / 0.1, e, (slide - tangent).norm(),
               nearest / dx);
  CHECK(std::abs(after.dot(n) / 0.1 - e) < 0.02 * e);
  CHECK((slide - tangent).norm() < 1e-3 * tangent.norm());
  CHECK(nearest < 2.9 * dx && nearest > 2.0 * dx);
}

TEST(grain_steps_do_not_depend_on_the_thread_count) {
  Particles<3> result[2];
  Vec<3> omega[2];
  for (int threads = 1; threads <= 2; ++threads) {
    omp_set_num_threads(threads);
    Viscous sim(grain_deck(term::morris_viscosity | term::grains, true, 3000.0), grain_in_fluid(0.05));
    for (int s = 0; s < 40; ++s) CHECK(sim.step(0.2 * 1.3 * dx / c0, NoCrossings{}));
    result[threads - 1] = sim.particles(), omega[threads - 1] = sim.grains().grains()[0].state.angular_velocity;
  }
  omp_set_num_threads(1);
  CHECK(omega[0] == omega[1]);
  for (std::size_t i = 0; i < result[0].size(); ++i) CHECK(result[0].x[i] == result[1].x[i] && result[0].v[i] == result[1].v[i]);
}

TEST(grain_deck_refusals_name_the_key) {
  auto refused = [](const std::string& text, const std::string& expected, int dimension = 3) {
    std::string message;
    RunParameters d;
    d.dimension = dimension, d.dx = dx;
    try {
      parse_grains(nlohmann::json::parse(text), d);
    } catch (const InputError& e) {
      message = e.what();
    }
    if (message.find(expected) == std::string::npos)
      std::fprintf(stderr, "  expected '%s' in '%s'\n", expected.c_str(), message.c_str());
    return message.find(expected) != std::string::npos;
  };
  CHECK(refused(R"([{"name": "g", "density": 0}])", "grains[0].density' must be > 0"));
  CHECK(refused(R"([{"name": "g", "density": -2}])", "grains[0].density' must be > 0"));
  CHECK(refused(R"([{"name": "g", "density": 2, "spin": 1}])", "unknown key 'grains[0].spin'"));
  CHECK(refused(R"([{"name": "g", "density": 2, "velocity": [1, 2]}])", "grains[0].velocity"));
  CHECK(refused(R"([{"name": "g", "density": 2}])", "3D only", 2));
  auto contact_refused = [](const std::string& text, const std::string& expected) {
    RunParameters d;
    d.dimension = 3, d.grains = {GrainSpec{}};
    try {
      parse_grain_contact(nlohmann::json::parse(text), d);
    } catch (const InputError& e) {
      return std::string(e.what()).find(expected) != std::string::npos;
    }
    return false;
  };
  CHECK(contact_refused(R"({"stiffness": 1, "walls": [{"point": [0, 0, 0], "normal": [0, 0, 0]}]})",
                        "grain_contact.walls[0].normal' must not be zero"));
  CHECK(contact_refused(R"({"stiffness": 1, "walls": [{"point": [0, 0, 0]}]})", "needs 'point' and 'normal'"));
  // A grain without particles.
  RunParameters d = grain_deck(term::morris_viscosity | term::grains, true, 2000.0);
  d.grains.push_back(d.grains[0]), d.grains[1].name = "empty";
  bool empty = false;
  try {
    Viscous sim(d, grain_in_fluid(0.0));
  } catch (const InputError& e) {
    empty = std::string(e.what()).find("grains[1] ('empty') has no particle") != std::string::npos;
  }
  CHECK(empty);
}
