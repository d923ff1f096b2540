// Rigid impactors: ideally hard bodies whose surface is a union of spheres (one sphere: the glass ball of
// Hutchings' crater; several: a grain's clump), free (Newton-Euler, rigid_body.h) or kinematic, pressing on the
// moving particles in compression only. A particle at x, whose own extent reaches r_p = dx/2 from its centre,
// overlaps sphere k (centre c_k, radius R_k) by
//   delta = R_k + r_p - |x - c_k|,   f = k_c delta (x - c_k) / |x - c_k|   for delta > 0, else 0     (I1)
// a linear spring of stiffness k_c (N/m) on the overlap, repulsive only, so a body pushes and never pulls. Its
// potential k_c delta^2 / 2 is the contact energy of the series. The body takes the reaction
//   F = -sum_a f_a,   T = -sum_a (x_a - X) x f_a                                                      (I2)
// summed over the particles in index order by one thread, so the result does not depend on the thread count. In the engine's predictor-corrector (integrator.h) the body
// steps as drift-kick-drift, the particles' own rule (eq. P4 is x + dt v + dt^2 a / 2):
//   predict:  X* = X + V dt/2,  q* = rotor(q, L, dt/2)          (the particles' rates see X*, q*)
//   correct:  V += F* dt / M,  L += T* dt,  then the second half drift                                (I3)
// A kinematic body drifts with its prescribed V and omega (rigid_body.h R4) and ignores F and T, which are still
// recorded (the force a prescribed indenter needs). The contact acts in 3D only.
#pragma once
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "parameters.h"
#include "rigid_body.h"
#include "vec.h"

namespace sph {

template <int D>
class Impactors {
 public:
  struct Body {
    std::string name;
    rigid::RigidBody body;
    rigid::RigidState state;
    std::vector<Vec<3>> offsets;     // sphere centres, body frame, m
    std::vector<Vec<3>> centres;     // sphere centres, world, at the pose of the last placement, m
    std::vector<double> radii;       // m
    double stiffness = 0.0;          // k_c, N/m
    double reach = 0.0;              // largest |c_k - X| + R_k, m (a cheap bound before the spheres)
    rigid::Wrench wrench{Vec<3>::Zero(), Vec<3>::Zero()};  // the reaction of the last evaluation (I2)
  };

  Impactors() = default;
  // The deck's impactors, particles of half-extent r_p = dx/2 (m).
  Impactors(const std::vector<ImpactorSpec>& specs, double dx) : particle_radius_(0.5 * dx) {
    for (const auto& s : specs) {
      Body b;
      b.name = s.name, b.stiffness = s.stiffness;
      Mat<3> inertia;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) inertia(r, c) = s.inertia[3 * r + c];
      const rigid::PrincipalFrame frame = rigid::principal_frame(inertia);
      b.body = {s.mass, frame.moments};
      b.state.position = Vec<3>(s.centre[0], s.centre[1], s.centre[2]);
      b.state.orientation = frame.orientation;
      b.state.kinematic = s.kinematic;
      rigid::set_velocities(b.body, b.state, Vec<3>(s.velocity[0], s.velocity[1], s.velocity[2]),
                            Vec<3>(s.angular_velocity[0], s.angular_velocity[1], s.angular_velocity[2]));
      const Mat<3> to_body = frame.orientation.toRotationMatrix().transpose();
      for (const auto& sphere : s.spheres) {
        const Vec<3> c(sphere[0], sphere[1], sphere[2]);
        b.offsets.push_back(to_body * (c - b.state.position));
        b.radii.push_back(sphere[3]);
        b.reach = std::max(b.reach, (c - b.state.position).norm() + sphere[3]);
      }
      b.centres.resize(b.offsets.size());
      bodies_.push_back(std::move(b));
    }
    place();
  }

  bool empty() const { return bodies_.empty(); }
  const std::vector<Body>& bodies() const { return bodies_; }

  // Start of a step of dt (s): drift every body by dt/2 (I3).
  void predict(double dt) {
    for (auto& b : bodies_) rigid::drift(b.body, b.state, 0.5 * dt);
    place();
  }

  // The contact force (N) of every body on a particle at x (m), eq. I1.
  Vec<D> force(const Vec<D>& x) const {
    Vec<D> total = Vec<D>::Zero();
    if constexpr (D == 3) {
      for (const auto& b : bodies_) {
        const double far = b.reach + particle_radius_;
        if ((x - b.state.position).squaredNorm() >= far * far) continue;
        for (std::size_t k = 0; k < b.radii.size(); ++k) {
          const Vec<3> r = x - b.centres[k];
          const double reach = b.radii[k] + particle_radius_, d2 = r.squaredNorm();
          if (d2 >= reach * reach || !(d2 > 0.0)) continue;
          const double d = std::sqrt(d2);
          total += b.stiffness * (reach - d) / d * r;
        }
      }
    }
    return total;
  }

  // The first body (its index) whose spheres overlap a particle at x (m), or -1.
  int touching(const Vec<D>& x) const {
    if constexpr (D == 3)
      for (std::size_t i = 0; i < bodies_.size(); ++i)
        for (std::size_t k = 0; k < bodies_[i].radii.size(); ++k)
          if ((x - bodies_[i].centres[k]).norm() < bodies_[i].radii[k] + particle_radius_) return static_cast<int>(i);
    return -1;
  }

  // InputError unless every moving particle of P starts clear of the bodies.
  template <class Particles>
  void check_clear(const Particles& P) const {
    for (std::size_t i = 0; i < P.size(); ++i)
      if (const int b = touching(P.x[i]); b >= 0 && P.moves(i))
        throw InputError("impactor '" + bodies_[b].name + "' starts inside particle " + std::to_string(P.id[i]) +
                         ": it must start clear of the particles (their extent dx/2 included)");
  }

  // The reactions (I2) on the bodies from the particles P that move, at their current
  // positions (the mid-step ones during a step), in index order: the same overlaps force() gives the particles,
  // so momentum balances to rounding. Serial; call between the predictor and the particles' close_rates.
  template <class Particles>
  void gather(const Particles& P) {
    for (auto& b : bodies_) b.wrench = {Vec<3>::Zero(), Vec<3>::Zero()};
    each_overlap(bodies_, particle_radius_, P, [](Body& b, const Vec<3>& x, const Vec<3>& r, double d, double delta) {
      const Vec<3> f = b.stiffness * delta / d * r;
      b.wrench.force -= f;
      b.wrench.torque -= (x - b.state.position).cross(f);
    });
  }

  // The contact energy (J) of the particles P at their current positions and the bodies at their current poses
  // (after a step: the state the kinetic energies describe); of body `only` alone when it is >= 0.
  template <class Particles>
  double contact_energy_at(const Particles& P, int only = -1) const {
    double e = 0.0;
    each_overlap(bodies_, particle_radius_, P, [&](const Body& b, const Vec<3>&, const Vec<3>&, double, double delta) {
      if (only < 0 || &b == &bodies_[only]) e += 0.5 * b.stiffness * delta * delta;
    });
    return e;
  }

  // End of the step: the kick with the reactions of the mid-step evaluation and the second half drift (I3).
  void correct(double dt) {
    for (auto& b : bodies_) {
      rigid::kick(b.body, b.state, b.wrench.force, b.wrench.torque, dt);
      rigid::drift(b.body, b.state, 0.5 * dt);
    }
    place();
  }

  // The sum of the bodies' kinetic energies, J.
  double kinetic_energy() const {
    double e = 0.0;
    for (const auto& b : bodies_) e += rigid::kinetic_energy(b.body, b.state);
    return e;
  }

 private:
  // The spheres' world centres at the bodies' current poses.
  void place() {
    for (auto& b : bodies_) {
      const Mat<3> rotation = b.state.orientation.toRotationMatrix();
      for (std::size_t k = 0; k < b.offsets.size(); ++k) b.centres[k] = b.state.position + rotation * b.offsets[k];
    }
  }

  // visit(body, x, r = x - c_k, d = |r|, delta) for every overlap (I1) of a moving particle of P, in index order.
  template <class Bodies, class Particles, class Visit>
  static void each_overlap(Bodies& bodies, double particle_radius, const Particles& P, Visit&& visit) {
    if constexpr (D == 3) {
      for (std::size_t a = 0; a < P.size(); ++a) {
        if (!P.moves(a)) continue;
        const Vec<3>& x = P.x[a];
        for (auto& b : bodies) {
          const double far = b.reach + particle_radius;
          if ((x - b.state.position).squaredNorm() >= far * far) continue;
          for (std::size_t k = 0; k < b.radii.size(); ++k) {
            const Vec<3> r = x - b.centres[k];
            const double reach = b.radii[k] + particle_radius, d2 = r.squaredNorm();
            if (d2 >= reach * reach || !(d2 > 0.0)) continue;
            const double d = std::sqrt(d2);
            visit(b, x, r, d, reach - d);
          }
        }
      }
    }
  }

  std::vector<Body> bodies_;
  double particle_radius_ = 0.0;  // r_p, m
};

}  // namespace sph
