// Rigid grains that the fluid drags: each grain is a set of particles (Kind::body: a sphere's lattice sites, or any
// particle set) that move as one rigid body (rigid_body.h). To the fluid they are moving boundary particles (its
// no-slip against their rigid velocity, their pressure from their own summation density, not floored); the fluid's
// pair forces on them (grain_pairs.h, eq. G1) sum to the grain's force and torque
//   F = sum_i m_i a_i,   T = sum_i (R r_i) x m_i a_i                                                   (G2)
// (a_i the pair loop's reaction per unit mass on particle i, R r_i its arm from the centre of mass X), summed over
// the particles in index order by one thread, so the result does not depend on the thread count and the momentum
// of fluid and grains balances to rounding. The grain's mass and inertia are those of its particles at the grain's
// density rho_g (R1-R2 of rigid_body.h with masses m_i rho_g / rho0_i: its particles keep the fluid's mass and
// density in the pair terms). In the engine's predictor-corrector the grain steps as the impactors (impactors.h, I3),
// with the fluid's own half-step velocity:
//   predict:  X* = X + V dt/2, q* = rotor(q, L, dt/2);  the fluid sees V* = V + dt/2 (F/M + g_g), L* = L + dt/2 T
//             (F, T of the previous evaluation; g_g the grain's body force per unit mass)
//   correct:  V += dt (F*/M + g_g),  L += dt T*,  then the second half drift                          (G3)
// so X' = X + dt (V + V')/2, the fluid's eq. P4. A particle is placed by its grain's displacement from the start
// of the step, x_i = x_i^n + (X' - X) + (R' - R) r_i (positions stay in the periodic image they were wrapped to),
// and moves at v_i = V + omega x R r_i. 3D only.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "cell_list.h"
#include "material.h"
#include "parameters.h"
#include "particles.h"
#include "rigid_body.h"
#include "vec.h"

namespace sph {

template <int D>
class Grains {
 public:
  struct Grain {
    std::string name;
    rigid::RigidBody body;       // mass kg, principal moments kg m^2
    rigid::RigidState state;     // current (mid-step pose during an evaluation)
    rigid::RigidState start;     // at the start of the step
    Vec<3> seen_velocity = Vec<3>::Zero(), seen_omega = Vec<3>::Zero();  // what the fluid sees, m/s, rad/s
    Mat<3> rotation = Mat<3>::Identity(), start_rotation = Mat<3>::Identity();  // R of state and start
    Vec<3> body_force = Vec<3>::Zero();  // g_g, m/s^2
    rigid::Wrench wrench{Vec<3>::Zero(), Vec<3>::Zero()};  // the fluid's force and torque of the last evaluation (G2)
    Vec<3> contact = Vec<3>::Zero();  // the other grains' contact force of the last evaluation (G6), N
    double contact_radius = 0.0;      // m (0: no contact)
    std::size_t particles = 0;
    // Since the last series record (the recorder closes them): the contact's impulse (the kicks' sum of contact dt,
    // N s), its largest magnitude over the steps (N) and the time it acted (s). A record of the contact force is one
    // step's; these see every step.
    mutable Vec<3> contact_impulse = Vec<3>::Zero();
    mutable double contact_peak = 0.0, contact_time = 0.0;
    void close_interval() const { contact_impulse.setZero(), contact_peak = contact_time = 0.0; }
  };

  bool empty() const { return grains_.empty(); }
  const std::vector<Grain>& grains() const { return grains_; }

  // The deck's grains from the body particles of P (unwrapped, as given): mass properties at the grain densities
  // (rho0 of each particle's material), body-frame offsets into P.grain_offset, then every particle placed at its
  // grain's pose and velocity. InputError when a grain has no particle.
  void start(const std::vector<GrainSpec>& specs, Particles<D>& P, const MaterialTable& materials, double dx) {
    if constexpr (D == 3) {
      for (std::size_t g = 0; g < specs.size(); ++g) {
        std::vector<Vec<3>> x, offsets;
        std::vector<double> m;
        std::vector<std::size_t> rows;
        for (std::size_t i = 0; i < P.size(); ++i)
          if (P.kind[i] == Kind::body && P.grain[i] == static_cast<std::int32_t>(g))
            rows.push_back(i), x.push_back(P.x[i]),
                m.push_back(P.mass[i] * specs[g].density / materials.eos(P.material[i]).rho0);
        if (rows.empty()) throw InputError("grains[" + std::to_string(g) + "] ('" + specs[g].name +
                                           "') has no particle (kind 4 with grain = " + std::to_string(g) + ")");
        offsets.resize(rows.size());
        Grain b;
        b.name = specs[g].name, b.particles = rows.size();
        b.body = rigid::body_from_particles(x.data(), m.data(), rows.size(), dx, b.state, offsets.data());
        rigid::set_velocities(b.body, b.state, Eigen::Map<const Vec<3>>(specs[g].velocity.data()),
                              Eigen::Map<const Vec<3>>(specs[g].angular_velocity.data()));
        b.body_force = Eigen::Map<const Vec<3>>(specs[g].body_force.data());
        b.contact_radius = specs[g].contact_radius;
        b.start = b.state, b.seen_velocity = b.state.velocity, b.seen_omega = b.state.angular_velocity;
        b.rotation = b.start_rotation = b.state.orientation.toRotationMatrix();
        for (std::size_t k = 0; k < rows.size(); ++k) {
          const std::size_t i = rows[k];
          P.grain_offset[i] = offsets[k];
          const Vec<3> arm = b.rotation * offsets[k];
          P.x[i] = b.state.position + arm, P.v[i] = b.seen_velocity + b.seen_omega.cross(arm);
          P.grain_spin[i] = b.seen_omega;
        }
        grains_.push_back(std::move(b));
      }
    } else {
      if (!specs.empty()) throw InputError("'grains' act in 3D only");
      (void)P, (void)materials, (void)dx;
    }
  }

  // Start of a step of dt (s): the start pose kept, the half drift, the velocities the fluid sees (G3).
  void predict(double dt) {
    for (auto& b : grains_) {
      b.start = b.state, b.start_rotation = b.rotation;
      rigid::drift(b.body, b.state, 0.5 * dt);
      b.rotation = b.state.orientation.toRotationMatrix();
      b.seen_velocity = b.start.velocity + (0.5 * dt) * ((b.wrench.force + b.contact) / b.body.mass + b.body_force);
      const Vec<3> L = b.start.angular_momentum + (0.5 * dt) * b.wrench.torque;
      b.seen_omega = rigid::angular_velocity(b.body, b.state.orientation, L);
    }
  }

  // Particle i, when it is a grain's: placed by the grain's displacement since the start of the step (P.x0) and
  // given its rigid velocity (after the predictor or the corrector wrote it).
  void place(Particles<D>& P, std::ptrdiff_t i) const {
    if constexpr (D == 3) {
      if (P.kind[i] != Kind::body) return;
      const Grain& b = grains_[P.grain[i]];
      const Vec<3>& offset = P.grain_offset[i];
      const Vec<3> arm = b.rotation * offset;
      P.x[i] = P.x0[i] + (b.state.position - b.start.position) + (arm - b.start_rotation * offset);
      P.v[i] = b.seen_velocity + b.seen_omega.cross(arm), P.grain_spin[i] = b.seen_omega;
    } else {
      (void)P, (void)i;
    }
  }

  // The fluid's force and torque on every grain from the pair loop's reactions (G2), in index order; with dt > 0
  // (s) the corrector of G3. The torque leaves out the viscous reactions' answer to the grain's own rotation,
  // m_i omega x q_i (eq. G5's lever q_i, then zeroed): eq. 10 is the Laplacian form of the viscous force, whose
  // flux through a surface is mu (n . grad) v, not the traction of the stress; the two differ by mu grad(v . n) -
  // v_j grad n_j, which on a rigid body's no-slip surface is mu (n x omega) alone, a torque of 2 mu V omega on a
  // body of volume V that a free sphere in shear would turn 1.5 times too fast with. Serial: call between the pair
  // loop and the particles' corrector.
  void gather(Particles<D>& P, double dt) {
    if constexpr (D == 3) {
      for (auto& b : grains_) b.wrench = {Vec<3>::Zero(), Vec<3>::Zero()};
      for (std::size_t i = 0; i < P.size(); ++i) {
        if (P.kind[i] != Kind::body) continue;
        Grain& b = grains_[P.grain[i]];
        const Vec<3> f = P.mass[i] * P.acc[i];
        const Vec<3> rigid = P.mass[i] * P.grain_spin[i].cross(P.grain_lever[i]);  // eq. G5
        P.grain_lever[i].setZero();
        const Vec<3> arm = b.rotation * P.grain_offset[i];
        b.wrench.force += f;
        b.wrench.torque += arm.cross(f) - arm.cross(rigid);
      }
      contacts();
      solid_contacts(P);
      if (!(dt > 0.0)) return;
      for (auto& b : grains_) {
        b.contact_impulse += dt * b.contact, b.contact_peak = std::max(b.contact_peak, b.contact.norm());
        if (b.contact.squaredNorm() > 0.0) b.contact_time += dt;
        rigid::kick(b.body, b.state, b.wrench.force + b.contact + b.body.mass * b.body_force, b.wrench.torque, dt);
        rigid::drift(b.body, b.state, 0.5 * dt);
        b.rotation = b.state.orientation.toRotationMatrix();
        b.seen_velocity = b.state.velocity, b.seen_omega = b.state.angular_velocity;
      }
    } else {
      (void)P, (void)dt;
    }
  }

  // After start: the contact law (eq. G6) and the box its centres are compared in. In a Lees-Edwards cell
  // (`lees_edwards`, sheared across `axis`): InputError with a contact law, or unless every grain particle lies at least `margin`
  // (m: the kernel's support and the Verlet skin) inside the faces across `axis`, so that no pair of a grain's
  // particle crosses the sheared faces (its no-slip velocity, boundary_particles.h, takes no image velocity jump).
  void configure(const RunParameters& deck, const PeriodicBox<D>& box, int axis, double margin, const Particles<D>& P) {
    box_ = box, stiffness_ = deck.grain_contact.stiffness, walls_ = deck.grain_contact.walls;
    solid_stiffness_ = deck.grain_contact.solid_stiffness, particle_radius_ = 0.5 * deck.dx;
    check_solid_contact(P, deck.t_start > 0.0 || deck.step_start > 0);
    const bool sheared = deck.lees_edwards.on;
    const double log_e = std::log(deck.grain_contact.restitution);
    zeta_ = -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
    if (!sheared || grains_.empty()) return;
    if (stiffness_ > 0.0) throw InputError("'grain_contact' cannot act in a 'lees_edwards' cell");
    const double lo = box.lo[axis], hi = box.hi[axis];
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::body) continue;
      const double y = P.x[i][axis];
      if (y - lo < margin || hi - y < margin)
        throw InputError("grains[" + std::to_string(P.grain[i]) + "] ('" + grains_[P.grain[i]].name +
                         "'): a particle lies " + std::to_string(std::min(y - lo, hi - y)) +
                         " m from a sheared face of the Lees-Edwards cell (axis " + std::to_string(axis) +
                         "); a grain must stay " + std::to_string(margin) + " m (support and skin) inside");
    }
  }

  // Eq. G6: grains whose contact spheres overlap by delta = R_g + R_h - |X_h - X_g| > 0 (the nearest periodic
  // image) push apart along n = (X_h - X_g) / |X_h - X_g| with
  //   F = max(0, k delta - c v_n),  c = 2 zeta sqrt(k m),  zeta = -ln e / sqrt(pi^2 + ln^2 e)               (G6)
  // (m = M_g M_h / (M_g + M_h), v_n = (V_h - V_g) . n at the mid-step pose and velocities the fluid sees): a linear
  // spring-dashpot, which restores the relative normal speed times e in a head-on collision (exactly without the
  // compression-only clamp, which ends the contact a little early). Equal and opposite along the line of centres:
  // momentum and angular momentum kept. A grain on a wall plane (point p, unit normal n into the fluid) the same way
  // with the grain's mass and delta = R_g - (X_g - p) . n, v_n = V_g . n, the force along n on the grain:       (G7)
  // F = max(0, k delta - c v_n), c = 2 zeta sqrt(k M_g). Serial, in grain order.
  void contacts() {
    for (auto& b : grains_) b.contact.setZero();
    if (!(stiffness_ > 0.0)) return;
    for (std::size_t g = 0; g < grains_.size(); ++g)
      for (std::size_t h = g + 1; h < grains_.size(); ++h) {
        Grain &A = grains_[g], &B = grains_[h];
        if (!(A.contact_radius > 0.0 && B.contact_radius > 0.0)) continue;
        const Vec<3> d = nearest(B.state.position - A.state.position);
        const double distance = d.norm(), overlap = A.contact_radius + B.contact_radius - distance;
        if (!(overlap > 0.0) || !(distance > 0.0)) continue;
        const Vec<3> n = d / distance;
        const double m = A.body.mass * B.body.mass / (A.body.mass + B.body.mass);
        const double v_n = (B.seen_velocity - A.seen_velocity).dot(n);
        const double F = std::max(0.0, stiffness_ * overlap - 2.0 * zeta_ * std::sqrt(stiffness_ * m) * v_n);
        A.contact -= F * n, B.contact += F * n;
      }
    for (auto& b : grains_) {  // eq. G7: each grain on each wall plane
      if (!(b.contact_radius > 0.0)) continue;
      for (const auto& w : walls_) {
        const Vec<3> point(w[0], w[1], w[2]), n(w[3], w[4], w[5]);
        const double overlap = b.contact_radius - (b.state.position - point).dot(n);
        if (!(overlap > 0.0)) continue;
        const double v_n = b.seen_velocity.dot(n);
        b.contact += std::max(0.0, stiffness_ * overlap - 2.0 * zeta_ * std::sqrt(stiffness_ * b.body.mass) * v_n) * n;
      }
    }
  }

  // Eq. G8: a grain's contact sphere (centre X_g, radius R_g) on each moving particle s of a solid material (its
  // extent r_p = dx/2 as the impactors' particles), the impactors' eq. I1 with the grain's sphere:
  //   delta = R_g + r_p - |x_s - X_g|,   f_s = k_s delta (x_s - X_g) / |x_s - X_g|   for delta > 0, else 0   (G8)
  // (the nearest periodic image; at the mid-step poses), repulsive only and frictionless. The grain takes -f_s,
  // along its line of centres (no torque), so momentum balances to rounding. The pair terms between a grain's
  // particles and a solid's are left out (pair_loop.h, wall_sums.h): the solid feels the grain through G8 alone,
  // and a grain's particles, moving boundary particles of the fluid, take neither density nor no-slip velocity
  // from the solid's (whose heavier particles would raise their summation density as the grain nears). Serial, in
  // index order; after contacts(), which zeroes the grains' contact forces.
  void solid_contacts(Particles<D>& P) {
    if constexpr (D == 3) {
      if (!(solid_stiffness_ > 0.0)) return;
      for (std::size_t i = 0; i < P.size(); ++i) {
        if (!P.moves(i) || !P.solid_material[P.material[i]]) continue;
        for (auto& b : grains_) {
          const Vec<3> r = nearest(P.x[i] - b.state.position);
          const double reach = b.contact_radius + particle_radius_, d2 = r.squaredNorm();
          if (!(d2 < reach * reach) || !(d2 > 0.0)) continue;
          const double d = std::sqrt(d2);
          const Vec<3> f = (solid_stiffness_ * (reach - d) / d) * r;
          P.acc[i] += f / P.mass[i];
          b.contact -= f;
        }
      }
    } else {
      (void)P;
    }
  }

  // Momentum (kg m/s) and angular momentum about the origin (kg m^2/s) of the grains.
  Vec<3> momentum() const {
    Vec<3> p = Vec<3>::Zero();
    for (const auto& b : grains_) p += b.body.mass * b.state.velocity;
    return p;
  }
  Vec<3> angular_momentum() const {
    Vec<3> l = Vec<3>::Zero();
    for (const auto& b : grains_) l += b.state.angular_momentum + b.body.mass * b.state.position.cross(b.state.velocity);
    return l;
  }

 private:
  // The nearest periodic image of a separation d (m).
  Vec<3> nearest(Vec<3> d) const {
    for (int a = 0; a < D; ++a)
      if (box_.periodic[a]) {
        const double L = box_.hi[a] - box_.lo[a];
        d[a] -= L * std::round(d[a] / L);
      }
    return d;
  }
  // InputError when a solid's moving particle lies beside grains without eq. G8 (no solid_stiffness, or a grain
  // without contact radius), or inside a grain's contact sphere at the start of a new run (a resumed one may
  // start in the contact it was stopped in).
  void check_solid_contact(const Particles<D>& P, bool resumed) const {
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (grains_.empty() || !P.moves(i) || !P.solid_material[P.material[i]]) continue;
      if (!(solid_stiffness_ > 0.0)) throw InputError("grains beside a solid need 'grain_contact.solid_stiffness'");
      for (const auto& b : grains_) {
        if (!(b.contact_radius > 0.0))
          throw InputError("grain '" + b.name + "' beside a solid needs a 'contact_radius' (eq. G8)");
        if constexpr (D == 3)
          if (!resumed && nearest(P.x[i] - b.state.position).norm() < b.contact_radius + particle_radius_)
            throw InputError("grain '" + b.name + "' starts touching solid particle " + std::to_string(P.id[i]) +
                             ": it must start clear of the solid (the particles' extent dx/2 included)");
      }
    }
  }
  std::vector<Grain> grains_;
  PeriodicBox<D> box_{};
  double stiffness_ = 0.0, zeta_ = 0.0;  // eq. G6: k N/m, the damping ratio
  double solid_stiffness_ = 0.0, particle_radius_ = 0.0;  // eq. G8: k_s N/m, r_p m
  std::vector<std::array<double, 6>> walls_;  // eq. G7: point (m) and unit normal of each plane
};

}  // namespace sph
