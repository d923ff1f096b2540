// The rigid body (rigid_body.h) against closed forms: the inertia of particle
// lattices against the solid cube and sphere, a torque-free asymmetric top
// (angular momentum over 10 000 steps, energy at dt and dt/2, the intermediate
// axis's flip time from Jacobi's elliptic functions), a symmetric top's
// precession, constant torque and force, a kinematic body, the wrench of particle
// forces; and the numpy reference (orchestrator/reference/rigid_body.py) to 1e-12
// after 200 steps. tests/reference/test_rigid_body_reference.py recomputes the
// constants below from the reference and compares them with this file's text.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>
#include <vector>

#include "check.h"
#include "rigid_body.h"

using namespace sph;
using namespace sph::rigid;

// No allocation in a step: every type the stage holds is fixed-size (trivially destructible, so it owns no heap
// memory) and the per-particle functions write into the caller's arrays. The engine's counting operator new
// (test_alloc.cpp) is private to that file, so the step is not run under it here.
static_assert(std::is_trivially_destructible<RigidState>::value && std::is_trivially_destructible<RigidBody>::value &&
                  std::is_trivially_destructible<Wrench>::value && std::is_trivially_destructible<Quat>::value,
              "the rigid-body stage holds fixed-size types only");

namespace {

constexpr double kGlass = 2500.0;  // kg/m^3
const Vec<3> kZero = Vec<3>::Zero();

// Python-computed expected values: tests/reference/test_rigid_body_reference.py, _cross_check_values() (the
// fixed scene under gravity, a spring to the origin and a drag, 200 steps of 1e-5 s).
constexpr double kMass = 1.511879495852163e-07;
constexpr double kMoment1 = 3.1976786058951893e-15;
constexpr double kMoment2 = 4.3240921622345124e-15;
constexpr double kMoment3 = 5.241713139427373e-15;
constexpr double kEnergy = 1.5090839256072492e-07;
constexpr double kPositionX = 0.004013075021431689;
constexpr double kPositionY = 0.0011636620720977305;
constexpr double kPositionZ = 6.145446289631203e-05;
constexpr double kVelocityX = 1.307066343094736;
constexpr double kVelocityY = -0.4835421891965661;
constexpr double kVelocityZ = 0.21054687715044762;
constexpr double kMomentumX = 8.85077917437414e-13;
constexpr double kMomentumY = -7.989012986452478e-13;
constexpr double kMomentumZ = 2.386532233695176e-12;
constexpr double kOmegaX = 237.09776078937193;
constexpr double kOmegaY = -70.96347566399511;
constexpr double kOmegaZ = 505.1192956831927;
constexpr double kFirstParticleX = 0.004016851779082811;
constexpr double kFirstParticleY = 0.0010154254991784478;
constexpr double kFirstParticleZ = -0.000153084473348748;
constexpr double kLastParticleX = 0.004004328328318123;
constexpr double kLastParticleY = 0.0013115778289490136;
constexpr double kLastParticleZ = 0.00029704493440833006;
constexpr double kQuatW = 0.8254230229867212;
constexpr double kQuatX = 0.27943422245709365;
constexpr double kQuatY = -0.1124720573373331;
constexpr double kQuatZ = 0.4774341679871373;

struct Scene {
  std::vector<Vec<3>> x;
  std::vector<double> m;
  double dx;
};

// A jittered 5 x 4 x 3 glass lattice of spacing 100 um with uneven masses (the reference's _fixed_scene).
Scene fixed_scene() {
  Scene s{{}, {}, 1e-4};
  int i = 0;
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 4; ++b)
      for (int c = 0; c < 3; ++c, ++i) {
        const Vec<3> jitter(std::sin(i), std::cos(2.0 * i), std::sin(3.0 * i + 1.0));
        s.x.push_back(s.dx * (Vec<3>(a, b, c) + 0.1 * jitter) + Vec<3>(1e-3, 2e-3, -5e-4));
        s.m.push_back(kGlass * s.dx * s.dx * s.dx * (1.0 + 0.2 * std::sin(0.7 * i)));
      }
  return s;
}

// Cell centres of cells^3 cubes of side dx (m) centred on the origin, those with |x| < radius (m) when given.
std::vector<Vec<3>> lattice(int cells, double dx, double radius = INFINITY) {
  std::vector<Vec<3>> x;
  for (int a = 0; a < cells; ++a)
    for (int b = 0; b < cells; ++b)
      for (int c = 0; c < cells; ++c) {
        const Vec<3> p = dx * (Vec<3>(a, b, c) - Vec<3>::Constant(0.5 * (cells - 1)));
        if (p.norm() < radius) x.push_back(p);
      }
  return x;
}

double max_off_diagonal(const Mat<3>& t) { return std::max({std::abs(t(0, 1)), std::abs(t(0, 2)), std::abs(t(1, 2))}); }

// The time (s) between sign changes of the intermediate axis's omega (I1 < I2 < I3, kg m^2; energy J; |L|^2):
// 2 K(k) / lambda (Landau and Lifshitz, section 37), I1 and I3 swapped when L^2 < 2 E I2.
double flip_half_period(Vec<3> moments, double energy, double l2) {
  double i1 = moments(0), i2 = moments(1), i3 = moments(2);
  if (l2 < 2.0 * energy * i2) std::swap(i1, i3);
  const double rate = std::sqrt((i3 - i2) * (l2 - 2.0 * energy * i1) / (i1 * i2 * i3));
  const double k2 = (i2 - i1) * (2.0 * energy * i3 - l2) / ((i3 - i2) * (l2 - 2.0 * energy * i1));
  return 2.0 * std::comp_ellint_1(std::sqrt(k2)) / rate;
}

struct TopRun {
  double energy_error = 0.0, momentum_error = 0.0;  // worst relative
  std::vector<double> crossings;                    // s, sign changes of the body-frame omega_2
  double energy, l2;
};

// A torque-free glass grain (moments 1, 2, 3 x 1e-16 kg m^2) spun near its intermediate axis.
TopRun spin_top(double dt, int steps) {
  const RigidBody body{1.5e-8, Vec<3>(1e-16, 2e-16, 3e-16)};
  RigidState s;
  set_velocities(body, s, kZero, Vec<3>(500.0, 1e4, 500.0));
  TopRun run;
  run.energy = kinetic_energy(body, s), run.l2 = s.angular_momentum.squaredNorm();
  const Vec<3> l0 = s.angular_momentum;
  double previous = 1e4;
  for (int k = 1; k <= steps; ++k) {
    step(body, s, kZero, kZero, dt);
    const Vec<3> pi = s.orientation.conjugate() * s.angular_momentum;
    run.energy_error = std::max(run.energy_error, std::abs(kinetic_energy(body, s) / run.energy - 1.0));
    run.momentum_error = std::max(run.momentum_error, std::abs(pi.norm() / l0.norm() - 1.0));
    run.momentum_error = std::max(run.momentum_error, (s.angular_momentum - l0).norm() / l0.norm());
    const double omega2 = pi(1) / body.moments(1);
    if (omega2 * previous < 0.0) run.crossings.push_back(dt * (k - omega2 / (omega2 - previous)));
    previous = omega2;
  }
  return run;
}

}  // namespace

TEST(rigid_cube_lattice_is_the_solid_cube) {
  const double dx = 1e-5;
  std::vector<Vec<3>> x = lattice(6, dx);
  for (auto& p : x) p += Vec<3>(3e-4, -1e-4, 2e-4);
  const std::vector<double> m(x.size(), kGlass * dx * dx * dx);
  const MassProperties props = mass_properties(x.data(), m.data(), x.size(), dx);
  const double solid = props.mass * (6 * dx) * (6 * dx) / 6.0;
  for (int k = 0; k < 3; ++k) CHECK_CLOSE(props.inertia(k, k), solid, 1e-13);
  CHECK(max_off_diagonal(props.inertia) < 1e-13 * solid);
  CHECK_CLOSE(props.centre.x(), 3e-4, 1e-13);
}

TEST(rigid_sphere_lattice_is_the_solid_sphere_to_the_lattice_error) {
  const double dx = 1e-5;
  for (int per_radius : {5, 10, 20}) {
    const std::vector<Vec<3>> x = lattice(2 * per_radius, dx, per_radius * dx);
    const std::vector<double> m(x.size(), kGlass * dx * dx * dx);
    const MassProperties props = mass_properties(x.data(), m.data(), x.size(), dx);
    const double radius = std::cbrt(x.size() * dx * dx * dx * 3.0 / (4.0 * M_PI));  // volume-equivalent
    const double error = props.inertia(0, 0) / (0.4 * props.mass * radius * radius) - 1.0;
    std::fprintf(stderr, "  R/dx %d: I / (2/5 M R^2) - 1 = %.3e (x (R/dx)^2: %.3f)\n", per_radius, error,
                 error * per_radius * per_radius);
    CHECK(error > 0.0 && error < 0.5 / (per_radius * per_radius));
    CHECK_CLOSE(props.inertia(1, 1), props.inertia(0, 0), 1e-13);
    CHECK(max_off_diagonal(props.inertia) < 1e-13 * props.inertia(0, 0));
  }
}

TEST(rigid_inertia_is_the_sum_and_the_principal_frame_carries_the_particles) {
  const Scene s = fixed_scene();
  const std::size_t n = s.x.size();
  const MassProperties props = mass_properties(s.x.data(), s.m.data(), n, s.dx);
  Mat<3> direct = Mat<3>::Zero();  // about the origin, then the parallel-axis theorem
  for (std::size_t i = 0; i < n; ++i)
    direct += s.m[i] * (s.x[i].squaredNorm() * Mat<3>::Identity() - s.x[i] * s.x[i].transpose());
  const Vec<3> c = props.centre;
  direct += props.mass * (s.dx * s.dx / 6.0 * Mat<3>::Identity() - c.squaredNorm() * Mat<3>::Identity() +
                          c * c.transpose());
  CHECK((props.inertia - direct).cwiseAbs().maxCoeff() < 1e-10 * props.inertia.cwiseAbs().maxCoeff());
  RigidState state;
  std::vector<Vec<3>> offsets(n), x(n), v(n);
  const RigidBody body = body_from_particles(s.x.data(), s.m.data(), n, s.dx, state, offsets.data());
  const Mat<3> r = state.orientation.toRotationMatrix();
  const Mat<3> diagonal = r.transpose() * props.inertia * r - Mat<3>(body.moments.asDiagonal());
  CHECK(diagonal.cwiseAbs().maxCoeff() < 1e-13 * body.moments(2));
  CHECK(body.moments(0) < body.moments(1) && body.moments(1) < body.moments(2));
  place_particles(state, offsets.data(), n, x.data(), v.data());
  for (std::size_t i = 0; i < n; ++i) CHECK((x[i] - s.x[i]).norm() < 1e-15 && v[i].norm() == 0.0);
}

TEST(rigid_asymmetric_top_keeps_momentum_energy_to_second_order_and_flips_on_time) {
  const double dt = 2e-6;  // 0.02 rad per step
  const TopRun coarse = spin_top(dt, 10000), fine = spin_top(0.5 * dt, 20000);
  const RigidBody body{1.5e-8, Vec<3>(1e-16, 2e-16, 3e-16)};
  const double half_period = flip_half_period(body.moments, coarse.energy, coarse.l2);
  double worst_flip = 0.0;
  for (std::size_t k = 1; k < coarse.crossings.size(); ++k)
    worst_flip = std::max(worst_flip, std::abs((coarse.crossings[k] - coarse.crossings[k - 1]) / half_period - 1.0));
  std::fprintf(stderr,
               "  10 000 steps: |L| error %.2e; energy error %.3e at dt, %.3e at dt/2 (ratio %.4f); %zu flips, "
               "worst against 2 K(k) / lambda = %.6e s: %.2e\n",
               coarse.momentum_error, coarse.energy_error, fine.energy_error, coarse.energy_error / fine.energy_error,
               coarse.crossings.size(), half_period, worst_flip);
  CHECK(coarse.momentum_error < 1e-12 && fine.momentum_error < 1e-12);
  CHECK_CLOSE(coarse.energy_error / fine.energy_error, 4.0, 0.02);
  CHECK(coarse.crossings.size() >= 10 && worst_flip < 0.01);
}

TEST(rigid_symmetric_top_precesses_at_l_over_the_transverse_moment) {
  const RigidBody body{1.0, Vec<3>(2.0, 2.0, 3.0)};
  RigidState s;
  set_velocities(body, s, kZero, Vec<3>(0.3, 0.0, 1.0));
  const Vec<3> d = s.angular_momentum.normalized();
  const Vec<3> first = (Vec<3>::UnitX() - d.x() * d).normalized(), second = d.cross(first);
  const double dt = 1e-3;
  const int steps = 4000;
  double angle = 0.0, previous = std::atan2(Vec<3>::UnitZ().dot(second), Vec<3>::UnitZ().dot(first));
  for (int k = 0; k < steps; ++k) {
    step(body, s, kZero, kZero, dt);
    const Vec<3> axis = s.orientation * Vec<3>::UnitZ();
    const double now = std::atan2(axis.dot(second), axis.dot(first));
    angle += std::remainder(now - previous, 2.0 * M_PI);
    previous = now;
  }
  const double rate = std::abs(angle) / (steps * dt), expected = s.angular_momentum.norm() / body.moments(0);
  std::fprintf(stderr, "  precession %.8f rad/s, L / I_1 = %.8f rad/s\n", rate, expected);
  CHECK_CLOSE(rate, expected, 1e-4);
}

TEST(rigid_constant_torque_and_force_are_exact) {
  const RigidBody body{2.0, Vec<3>(1.0, 2.0, 3.0)};
  RigidState s;
  s.orientation = Quat(0.8, 0.2, 0.4, -0.4);
  s.position = Vec<3>(1.0, 2.0, 3.0);
  set_velocities(body, s, Vec<3>(0.1, 0.0, -0.2), kZero);
  const Vec<3> torque = 3.0 * (s.orientation * Vec<3>::UnitY()), force(0.5, -1.0, 2.0);
  const double dt = 1e-3;
  for (int k = 0; k < 1000; ++k) step(body, s, force, torque, dt);
  const double t = 1.0;
  const Vec<3> omega = torque * t / body.moments(1);
  const Vec<3> x = Vec<3>(1.0, 2.0, 3.0) + Vec<3>(0.1, 0.0, -0.2) * t + force * t * t / (2.0 * body.mass);
  std::fprintf(stderr, "  omega error %.2e rad/s of %.3f; X error %.2e m\n", (s.angular_velocity - omega).norm(),
               omega.norm(), (s.position - x).norm());
  CHECK((s.angular_velocity - omega).norm() < 1e-12 * omega.norm());
  for (int k = 0; k < 3; ++k) CHECK_CLOSE(s.position(k), x(k), 1e-12);
}

TEST(rigid_kinematic_body_follows_its_prescription_and_ignores_forces) {
  const Scene sc = fixed_scene();
  const std::size_t n = sc.x.size();
  std::vector<Vec<3>> offsets(n), x(n), v(n);
  RigidState s;
  const RigidBody body = body_from_particles(sc.x.data(), sc.m.data(), n, sc.dx, s, offsets.data());
  const Vec<3> velocity(2.0, -1.0, 0.5), omega(300.0, -100.0, 700.0), start = s.position;
  const Quat q0 = s.orientation;
  s.kinematic = true;
  set_velocities(body, s, velocity, omega);
  const double dt = 1e-5;
  for (int k = 0; k < 1000; ++k) step(body, s, Vec<3>(1.0, 2.0, 3.0), Vec<3>(4.0, 5.0, 6.0), dt);
  const double t = 1000 * dt;
  const Quat expected = Quat(Eigen::AngleAxisd(omega.norm() * t, omega.normalized())) * q0;
  for (int k = 0; k < 3; ++k) CHECK_CLOSE(s.position(k), start(k) + velocity(k) * t, 1e-12);
  CHECK((s.orientation.coeffs() - expected.coeffs()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(s.velocity == velocity && s.angular_velocity == omega);
  place_particles(s, offsets.data(), n, x.data(), v.data());
  double worst_gap = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    CHECK((v[i] - velocity - omega.cross(x[i] - s.position)).norm() <= 1e-15 * v[i].norm());
    for (std::size_t j = 0; j < i; ++j)
      worst_gap = std::max(worst_gap, std::abs((x[i] - x[j]).norm() - (sc.x[i] - sc.x[j]).norm()));
  }
  CHECK(worst_gap < 1e-15);
}

TEST(rigid_wrench_of_gravity_and_of_a_couple) {
  const Scene sc = fixed_scene();
  const std::size_t n = sc.x.size();
  RigidState s;
  s.position = mass_properties(sc.x.data(), sc.m.data(), n, sc.dx).centre;
  std::vector<Vec<3>> f(n);
  double mass = 0.0;
  for (std::size_t i = 0; i < n; ++i) f[i] = sc.m[i] * Vec<3>(0.0, 0.0, -9.81), mass += sc.m[i];
  Wrench w = wrench(s, sc.x.data(), f.data(), n);
  CHECK_CLOSE(w.force.z(), -9.81 * mass, 1e-14);
  CHECK(w.torque.norm() < 1e-14 * 9.81 * mass * 1e-3);  // gravity has no torque about the centre of mass
  std::fill(f.begin(), f.end(), kZero);
  f.front() = Vec<3>::UnitY(), f.back() = -Vec<3>::UnitY();
  w = wrench(s, sc.x.data(), f.data(), n);
  const Vec<3> couple = (sc.x.front() - sc.x.back()).cross(Vec<3>::UnitY());
  CHECK(w.force == kZero && (w.torque - couple).norm() < 1e-12 * couple.norm());
}

TEST(rigid_body_agrees_with_the_numpy_reference) {
  const Scene sc = fixed_scene();
  const std::size_t n = sc.x.size();
  std::vector<Vec<3>> offsets(n), x(n), v(n), f(n);
  RigidState s;
  const RigidBody body = body_from_particles(sc.x.data(), sc.m.data(), n, sc.dx, s, offsets.data());
  set_velocities(body, s, Vec<3>(1.5, -0.5, 0.25), Vec<3>(300.0, -200.0, 500.0));
  for (int k = 0; k < 200; ++k) {
    place_particles(s, offsets.data(), n, x.data(), v.data());
    for (std::size_t i = 0; i < n; ++i) f[i] = sc.m[i] * (Vec<3>(0.0, 0.0, -9.81) - 50.0 * v[i]) - 2.5e-5 * x[i];
    const Wrench w = wrench(s, x.data(), f.data(), n);
    step(body, s, w.force, w.torque, 1e-5);
  }
  place_particles(s, offsets.data(), n, x.data(), v.data());
  const double tol = 1e-12;
  CHECK_CLOSE(body.mass, kMass, tol);
  CHECK_CLOSE(kinetic_energy(body, s), kEnergy, tol);
  const struct {
    Vec<3> got, expected;
  } vectors[7] = {{body.moments, {kMoment1, kMoment2, kMoment3}},
                  {s.position, {kPositionX, kPositionY, kPositionZ}},
                  {s.velocity, {kVelocityX, kVelocityY, kVelocityZ}},
                  {s.angular_momentum, {kMomentumX, kMomentumY, kMomentumZ}},
                  {s.angular_velocity, {kOmegaX, kOmegaY, kOmegaZ}},
                  {x.front(), {kFirstParticleX, kFirstParticleY, kFirstParticleZ}},
                  {x.back(), {kLastParticleX, kLastParticleY, kLastParticleZ}}};
  double worst = 0.0;
  for (const auto& e : vectors)
    for (int k = 0; k < 3; ++k) {
      CHECK_CLOSE(e.got(k), e.expected(k), tol);
      worst = std::max(worst, std::abs(e.got(k) / e.expected(k) - 1.0));
    }
  std::fprintf(stderr, "  worst relative difference from the reference after 200 steps: %.1e\n", worst);
  CHECK_CLOSE(s.orientation.w(), kQuatW, tol);
  CHECK_CLOSE(s.orientation.x(), kQuatX, tol);
  CHECK_CLOSE(s.orientation.y(), kQuatY, tol);
  CHECK_CLOSE(s.orientation.z(), kQuatZ, tol);
}
