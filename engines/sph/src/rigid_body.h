// A rigid body made of SPH particles, free (Newton-Euler with a quaternion) or
// kinematic (prescribed motion): the per-body stage, on plain structs and Eigen
// fixed-size types, no allocation, no deck types. SI units; world frame unless
// named body frame; a quaternion q turns body-frame vectors into world ones.
//   M = sum m_i,  X = sum m_i x_i / M,  r_i = x_i - X                      (R1)
//   I = sum m_i (|r_i|^2 1 - r_i r_i^T) + sum m_i dx^2 / 6 1               (R2)
// The second sum of R2 is each particle's own inertia as a cube of side dx, so a
// lattice that fills a cube has exactly the solid cube's inertia. The body frame
// is the principal frame (moments ascending). The state integrates the world
// angular momentum L: a torque changes it directly (dL/dt = T) and a free
// rotation leaves it untouched, so a torque-free body keeps L bitwise; omega =
// R diag(1/I_k) R^T L is kept beside it for the particles' velocities. One step:
//   V += F dt / 2M,  L += T dt / 2;  X += V dt,  q <- rotor(dt);  the kick again  (R3)
// the engine's kick-drift-kick leapfrog (velocity Verlet), exact for a constant F.
// rotor(dt) is the free-rotor splitting of Dullweber, Leimkuhler & McLachlan
// (1997): H = sum_k pi_k^2 / 2 I_k (pi = R^T L) split into exact rotations about
// one body axis, q <- q (cos(theta/2), sin(theta/2) e_k), theta = pi_k h / I_k,
// axes 1 2 3 2 1 with h = dt/2 dt/2 dt dt/2 dt/2: symplectic, time-reversible,
// second order; L exact, the energy to O(dt^2) without drift. Each factor is a
// unit quaternion, so |q| leaves 1 by rounding alone; renormalising after a step
// moves q by about 1e-16 and changes no result above rounding.
// A kinematic body moves with its prescribed V and omega and ignores forces:
//   X += V dt,  q <- (cos(|omega| dt/2), sin(|omega| dt/2) omega/|omega|) q         (R4)
// Particles: x_i = X + R r_i^body, v_i = V + omega x (x_i - X); the body's
// wrench from per-particle forces: F = sum f_i, T = sum (x_i - X) x f_i.
// The numpy reference orchestrator/reference/rigid_body.py computes the same.
#pragma once
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstddef>

#include "vec.h"

namespace sph::rigid {

using Quat = Eigen::Quaterniond;

struct MassProperties {
  double mass;     // M, kg
  Vec<3> centre;   // X, m
  Mat<3> inertia;  // about X, world axes, kg m^2 (R2)
};

struct PrincipalFrame {
  Vec<3> moments;    // ascending, kg m^2
  Quat orientation;  // body (principal) axes -> world, w >= 0
};

struct RigidBody {
  double mass;     // kg
  Vec<3> moments;  // principal moments about the centre of mass, kg m^2
};

struct RigidState {
  Vec<3> position = Vec<3>::Zero();          // X, centre of mass, m
  Quat orientation = Quat::Identity();       // q, body -> world
  Vec<3> velocity = Vec<3>::Zero();          // V, m/s
  Vec<3> angular_momentum = Vec<3>::Zero();  // L about X, world, kg m^2/s
  Vec<3> angular_velocity = Vec<3>::Zero();  // omega, world, rad/s (prescribed when kinematic)
  bool kinematic = false;                    // prescribed V and omega; forces and torques ignored
};

struct Wrench {
  Vec<3> force;   // N
  Vec<3> torque;  // about X, N m
};

// R1 and R2 for n particles at x (m) with masses m (kg), each a cube of side dx (m).
inline MassProperties mass_properties(const Vec<3>* x, const double* m, std::size_t n, double dx) {
  double mass = 0.0;
  Vec<3> moment = Vec<3>::Zero();
  for (std::size_t i = 0; i < n; ++i) mass += m[i], moment += m[i] * x[i];
  const Vec<3> centre = moment / mass;
  double trace_part = mass * dx * dx / 6.0;
  Mat<3> outer = Mat<3>::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec<3> r = x[i] - centre;
    trace_part += m[i] * r.squaredNorm();
    outer += m[i] * r * r.transpose();
  }
  return {mass, centre, trace_part * Mat<3>::Identity() - outer};
}

// Eigenvectors as body axes: each with its largest-magnitude component positive, the third flipped when
// needed for a right-handed frame, so the frame does not depend on the eigensolver's signs.
inline PrincipalFrame principal_frame(const Mat<3>& inertia) {
  const Eigen::SelfAdjointEigenSolver<Mat<3>> solver(inertia);
  Mat<3> axes = solver.eigenvectors();
  for (int k = 0; k < 3; ++k) {
    Eigen::Index largest;
    axes.col(k).cwiseAbs().maxCoeff(&largest);
    if (axes(largest, k) < 0.0) axes.col(k) = -axes.col(k);
  }
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  Quat q(axes);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return {solver.eigenvalues(), q};
}

// omega = R diag(1/I_k) R^T L, rad/s, for the world angular momentum L (kg m^2/s).
inline Vec<3> angular_velocity(const RigidBody& body, const Quat& q, const Vec<3>& angular_momentum) {
  return q * (q.conjugate() * angular_momentum).cwiseQuotient(body.moments);
}

// L = R diag(I_k) R^T omega, kg m^2/s, for the world angular velocity omega (rad/s).
inline Vec<3> angular_momentum(const RigidBody& body, const Quat& q, const Vec<3>& omega) {
  return q * (q.conjugate() * omega).cwiseProduct(body.moments);
}

// Sets V (m/s) and omega (rad/s, world) with the matching L: initial conditions, or a kinematic body's motion.
inline void set_velocities(const RigidBody& body, RigidState& state, const Vec<3>& velocity, const Vec<3>& omega) {
  state.velocity = velocity;
  state.angular_velocity = omega;
  state.angular_momentum = angular_momentum(body, state.orientation, omega);
}

// The body (mass, principal moments) and its state at rest at the particles' centre of mass, in their principal
// frame; `offsets` (n entries) receives the body-frame offsets r_i^body = R^T (x_i - X), m.
inline RigidBody body_from_particles(const Vec<3>* x, const double* m, std::size_t n, double dx, RigidState& state,
                                     Vec<3>* offsets) {
  const MassProperties props = mass_properties(x, m, n, dx);
  const PrincipalFrame frame = principal_frame(props.inertia);
  state = RigidState{};
  state.position = props.centre;
  state.orientation = frame.orientation;
  const Mat<3> to_body = frame.orientation.toRotationMatrix().transpose();
  for (std::size_t i = 0; i < n; ++i) offsets[i] = to_body * (x[i] - props.centre);
  return {props.mass, frame.moments};
}

// The torque-free rotor's flow over dt (s) at the world angular momentum L, by the symmetric splitting (R3).
inline Quat free_rotor(const RigidBody& body, Quat q, const Vec<3>& angular_momentum, double dt) {
  constexpr int axes[5] = {0, 1, 2, 1, 0};
  constexpr double fractions[5] = {0.5, 0.5, 1.0, 0.5, 0.5};
  for (int s = 0; s < 5; ++s) {
    const int k = axes[s];
    const double component = (q.conjugate() * angular_momentum)(k);
    const double half_angle = 0.5 * component * fractions[s] * dt / body.moments(k);
    Vec<3> axis = Vec<3>::Zero();
    axis(k) = std::sin(half_angle);
    q = q * Quat(std::cos(half_angle), axis.x(), axis.y(), axis.z());
  }
  q.normalize();
  return q;
}

// Half of R3's kick: V += F h / M, L += T h for a force F (N) and torque T (N m, about X) over h (s); nothing for a
// kinematic body.
inline void kick(const RigidBody& body, RigidState& state, const Vec<3>& force, const Vec<3>& torque, double h) {
  if (state.kinematic) return;
  state.velocity += (h / body.mass) * force;
  state.angular_momentum += h * torque;
  state.angular_velocity = angular_velocity(body, state.orientation, state.angular_momentum);
}

// R3's drift over dt (s) for a free body; R4 for a kinematic one.
inline void drift(const RigidBody& body, RigidState& state, double dt) {
  state.position += dt * state.velocity;
  if (!state.kinematic) {
    state.orientation = free_rotor(body, state.orientation, state.angular_momentum, dt);
    state.angular_velocity = angular_velocity(body, state.orientation, state.angular_momentum);
    return;
  }
  const double angle = state.angular_velocity.norm() * dt;
  if (angle > 0.0) {
    const Vec<3> axis = std::sin(0.5 * angle) * (dt / angle) * state.angular_velocity;
    state.orientation = Quat(std::cos(0.5 * angle), axis.x(), axis.y(), axis.z()) * state.orientation;
    state.orientation.normalize();
  }
  state.angular_momentum = angular_momentum(body, state.orientation, state.angular_velocity);
}

// One step of dt (s) under a force (N) and a torque about X (N m), world frame, constant over the step (R3, R4).
inline void step(const RigidBody& body, RigidState& state, const Vec<3>& force, const Vec<3>& torque, double dt) {
  kick(body, state, force, torque, 0.5 * dt);
  drift(body, state, dt);
  kick(body, state, force, torque, 0.5 * dt);
}

// M |V|^2 / 2 + sum_k pi_k^2 / 2 I_k, J, with pi = R^T L.
inline double kinetic_energy(const RigidBody& body, const RigidState& state) {
  const Vec<3> pi = state.orientation.conjugate() * state.angular_momentum;
  return 0.5 * body.mass * state.velocity.squaredNorm() + 0.5 * pi.cwiseAbs2().cwiseQuotient(body.moments).sum();
}

// V + omega x (x - X), m/s, at a point x (m).
inline Vec<3> rigid_velocity(const RigidState& state, const Vec<3>& x) {
  return state.velocity + state.angular_velocity.cross(x - state.position);
}

// x_i = X + R r_i^body (m) and v_i = V + omega x (x_i - X) (m/s) of n particles with body-frame offsets (m).
inline void place_particles(const RigidState& state, const Vec<3>* offsets, std::size_t n, Vec<3>* x, Vec<3>* v) {
  const Mat<3> rotation = state.orientation.toRotationMatrix();
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = state.position + rotation * offsets[i];
    v[i] = rigid_velocity(state, x[i]);
  }
}

// F = sum f_i (N) and T = sum (x_i - X) x f_i (N m) of n per-particle forces f (N) at x (m).
inline Wrench wrench(const RigidState& state, const Vec<3>* x, const Vec<3>* f, std::size_t n) {
  Wrench w{Vec<3>::Zero(), Vec<3>::Zero()};
  for (std::size_t i = 0; i < n; ++i) {
    w.force += f[i];
    w.torque += (x[i] - state.position).cross(f[i]);
  }
  return w;
}

}  // namespace sph::rigid
