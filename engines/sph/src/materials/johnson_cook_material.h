// The elastic-plastic Johnson-Cook solid of Nutto et al. (section II-B) as a material of the engine: the
// Cauchy stress sigma = -p I + s, with
//   ds/dt   = 2 G (D - tr D / 3 I) + W s - s W          (hypoelastic, Jaumann rate; D, W of L = G M^-1, eq. T2)
//   de/dt   = -1/2 sum_b m_b v_ab . f_ab                (specific internal energy, J/kg: the work of the pair
//                                                         forces of the momentum equation, f_ab its stress,
//                                                         artificial stress and viscosity terms, so that kinetic
//                                                         plus internal energy is conserved; sigma : D / rho in
//                                                         the continuum)
//   p       = K mu, or Mie-Grueneisen p(rho, e)         (johnson_cook.h; no Tait: the deck's c0 is not a key)
// and after the corrector the radial return of johnson_cook.h onto sigma_y of eq. 10 (the trial is the
// corrected s), the plastic strain and its rate, the heat of eq. 12 and the damage of eqs. 13-14. At D >= 1 the
// particle carries no deviatoric stress and no tension (p >= 0). In 2D (plane strain) s_zz is carried as a
// scalar (ds_zz/dt = -2 G tr D / 3, D_zz = 0) so that the von Mises stress and the return see all of s.
// Its scalars live in the integrated field solid_state (materials/solid_state.h): the energy and s_zz have a
// rate, the others a zero rate (the corrector leaves them at their step's start and post_correct updates them).
// The tensile instability: Monaghan's (2000) artificial stress (Gray, Monaghan & Swift 2001), per particle
// R = -epsilon sum_i max(sigma_i, 0) / rho^2 e_i e_i^T over the principal stresses, in the pair loop as
// f_ab^n (R_a + R_b) beside sigma_a / rho_a^2 + sigma_b / rho_b^2, f_ab = W(r_ab) / W(dx).
#pragma once
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "johnson_cook.h"
#include "material.h"
#include "material_keys.h"
#include "materials/johnson_cook_keys.h"
#include "materials/solid_state.h"
#include "parameters.h"
#include "particles.h"
#include "vec.h"

namespace sph {

struct JohnsonCook {
  static constexpr const char* name = "johnson_cook";
  static constexpr bool has_stress = true;  // tensor momentum path (eq. T1), s in the field `stress`
  static constexpr bool solid = true;       // its own EOS, rates and return mapping over the particle's state

  static std::vector<std::string> keys() {
    return {"shear_modulus", "eos", "bulk_modulus", "bulk_sound_speed", "hugoniot_slope", "gruneisen",
            "yield_stress", "hardening_modulus", "hardening_exponent", "rate_sensitivity", "thermal_exponent",
            "reference_rate", "rate_form", "room_temperature", "melting_temperature", "heat_capacity",
            "heat_fraction", "failure", "artificial_stress", "momentum", "smoothing"};
  }
  static void parse(const MaterialKeys& k, MaterialSpec& m) { parse_johnson_cook(k, m); }  // johnson_cook_keys.h
  // The parsed parameters into the run's material, with the deck's particle spacing dx (m) of W(dx).
  static void configure(const MaterialSpec& spec, Material& mat, double dx) {
    mat.solid = spec.solid;
    mat.solid.spacing = dx;
  }

  // The pressure (Pa) of a particle of density rho (kg/m^3), specific energy e (J/kg), failed or not.
  static double pressure(const SolidParameters& s, double rho, double energy, bool failed) {
    const double p = s.eos == SolidEos::linear ? solid::linear_solid_pressure(s.linear, rho)
                                               : solid::mie_gruneisen_pressure(s.shock, rho, energy);
    return failed ? std::max(p, 0.0) : p;
  }

  // Gather, per particle: pressure and sound speed (a fixed boundary particle at max(rho, rho0), as the fluids').
  template <int D>
  static void equation_of_state(const Material& mat, Particles<D>& P, std::ptrdiff_t i) {
    const SolidParameters& s = mat.solid;
    const SolidState& st = P.solid_state.value[i];
    const double rho = P.kind[i] == Kind::boundary ? std::max(P.rho[i], s.rho0()) : P.rho[i];
    P.p[i] = pressure(s, rho, st[slot::energy], st[slot::damage] >= 1.0);
    P.c[i] = mat.eos.c0;  // the wave speed (artificial viscosity)
  }

  // R / rho^2 of Monaghan's artificial stress (Pa m^6/kg^2) from sigma / rho^2 (eq. T1) of a particle.
  template <int D>
  static Mat<D> artificial_stress(const Material& mat, const Mat<D>& sigma_rho2) {
    if (!(mat.solid.artificial_stress > 0.0)) return Mat<D>::Zero();
    Eigen::SelfAdjointEigenSolver<Mat<D>> eig;
    eig.computeDirect(sigma_rho2);
    Vec<D> r = -mat.solid.artificial_stress * eig.eigenvalues().cwiseMax(0.0);
    return eig.eigenvectors() * r.asDiagonal() * eig.eigenvectors().transpose();
  }

  // close_rates of particle a: the Jaumann rate of s (and of s_zz in 2D) and de/dt from L (1/s).
  template <int D>
  static void rates(const Material& mat, const Mat<D>& L, Particles<D>& P, std::ptrdiff_t a) {
    const double G = mat.solid.shear_modulus;
    const Mat<D> stretching = 0.5 * (L + L.transpose()), spin = 0.5 * (L - L.transpose());
    const Mat<D>& s = P.tau[a];
    SolidState& rate = P.solid_state.rate[a];  // its energy rate: the pair loop's sum, kept
    const double third = stretching.trace() / 3.0;
    if (P.solid_state.value[a][slot::damage] >= 1.0) {
      P.dtau[a].setZero();
    } else {
      P.dtau[a] += 2.0 * G * (stretching - third * Mat<D>::Identity()) + spin * s - s * spin;  // (+ eq. SS1's sum)
      if constexpr (D == 2) rate[slot::szz] += -2.0 * G * third;
    }
  }

  // post_correct of particle i after a step of dt (s): failure, return mapping, plastic strain and its rate,
  // heating, damage.
  template <int D>
  static void post_correct(const Material& mat, Particles<D>& P, std::ptrdiff_t i, double dt) {
    const SolidParameters& s = mat.solid;
    SolidState& st = P.solid_state.value[i];
    Mat<D>& dev = P.tau[i];
    st[slot::plastic_rate] = 0.0;
    if (st[slot::damage] >= 1.0) {
      dev.setZero(), st[slot::szz] = 0.0;
      return;
    }
    if (!s.plastic) return;
    const solid::RadialReturn r = solid::radial_return(s.strength, s.heat, s.shear_modulus, embed(dev, st[slot::szz]),
                                                       Mat<3>::Zero(), st[slot::plastic_strain],
                                                       st[slot::temperature], dt);
    const double increment = r.plastic_strain_increment;
    if (increment <= 0.0) return;
    dev = r.deviatoric_stress.template topLeftCorner<D, D>();
    if constexpr (D == 2) st[slot::szz] = r.deviatoric_stress(2, 2);
    st[slot::plastic_strain] += increment, st[slot::plastic_rate] = increment / dt;
    if (s.heat.heat_fraction > 0.0) st[slot::temperature] += r.temperature_rise;  // else isothermal (C_p unset)
    if (!s.fails) return;
    const double p = pressure(s, P.rho[i], st[slot::energy], false);
    const double t_star = solid::homologous_temperature(st[slot::temperature], s.strength.room_temperature,
                                                        s.strength.melting_temperature);
    const double triaxiality = solid::triaxiality(-p, solid::von_mises(r.deviatoric_stress));
    const double strain = solid::jc_failure_strain(s.failure, triaxiality, increment / dt, t_star);
    st[slot::damage] = std::min(1.0, st[slot::damage] + solid::damage_increment(increment, strain));
    if (st[slot::damage] >= 1.0) dev.setZero(), st[slot::szz] = 0.0;
  }

  // The start state of a particle: at the room temperature, unstrained, undamaged.
  template <int D>
  static void start(const Material& mat, Particles<D>& P, std::ptrdiff_t i) {
    P.solid_state.value[i].setZero();
    P.solid_state.value[i][slot::temperature] = mat.solid.strength.room_temperature;
  }

  // The single-tensor hooks of the model interface (its rates and return use the particle's whole state).
  template <int D>
  static void stress_rate(const Material&, const Mat<D>&, const Mat<D>&, Mat<D>& dtau) {
    dtau.setZero();
  }
  template <int D>
  static void post_correct(const Material&, Mat<D>&) {}

 private:
  // s as a 3 x 3 deviator: in 2D the plane-strain s_zz completes it.
  template <int D>
  static Mat<3> embed(const Mat<D>& s, double szz) {
    if constexpr (D == 3) {
      (void)szz;
      return s;
    } else {
      Mat<3> t = Mat<3>::Zero();
      t.topLeftCorner<2, 2>() = s, t(2, 2) = szz;
      return t;
    }
  }
};

// Gather, per solid particle: its model's pressure, V = m / rho, sigma / rho^2 (eq. T1)
// and the artificial stress R / rho^2.
template <class Models, int D>
void solid_equation_of_state(Particles<D>& P, const MaterialTable& materials, std::ptrdiff_t i) {
  const Material& mat = materials[P.material[i]];
  Models::visit(mat.model, [&](auto model) {
    using Model = decltype(model);
    if constexpr (solid_v<Model>) {  // (the fluid beside solids takes the Tait branch: Simulation::equation_of_state_at)
      Model::equation_of_state(mat, P, i);
      const double rho2 = P.rho[i] * P.rho[i];
      P.vol[i] = P.mass[i] / P.rho[i];
      P.p_rho2[i] = P.p[i] / rho2;
      P.sigma_rho2[i] = (P.tau[i] - P.p[i] * Mat<D>::Identity()) / rho2;
      P.art_stress[i] = Model::artificial_stress(mat, P.sigma_rho2[i]);
      if (mat.solid.corrected_momentum) P.sigma_rho2[i] = P.sigma_rho2[i] * P.grad_correction[i];  // eq. KC1
    }
  });
}

// The start state of every particle of a configuration of solids (nothing for fluids).
template <class Models, int D>
void start_solids(Particles<D>& P, const MaterialTable& materials) {
  if constexpr (Models::any_solid) {
    for (int k = 0; k < materials.size(); ++k) P.solid_material[k] = materials[k].is_solid;  // eqs. FS1, G8
    for (std::size_t i = 0; i < P.size(); ++i) {
      const Material& mat = materials[P.material[i]];
      Models::visit(mat.model, [&](auto model) {
        if constexpr (solid_v<decltype(model)>) decltype(model)::start(mat, P, static_cast<std::ptrdiff_t>(i));
      });
    }
  }
}

// Monaghan's artificial stress in the pair loop: f_ab^n of f_ab = W(r_ab) / W(dx) (dx the particle spacing).
struct ArtificialStressFactor {
  double inv_w_dx = 0.0;  // 1 / (t^4 (2 q + 1)) at r = dx: the kernel's shape there (its constant cancels)
  int exponent = 4;
  bool on = false;
  // From the run's first solid material with an artificial stress (h m): every material shares dx and n.
  template <class Table>
  static ArtificialStressFactor of(const Table& materials, double h) {
    ArtificialStressFactor f;
    for (int k = 0; k < materials.size() && !f.on; ++k) {
      const SolidParameters& s = materials[k].solid;
      if (!(s.artificial_stress > 0.0)) continue;
      const double q = s.spacing / h, t = 1.0 - 0.5 * q;
      f.inv_w_dx = 1.0 / (t * t * t * t * (2.0 * q + 1.0)), f.exponent = s.artificial_stress_exponent, f.on = true;
    }
    return f;
  }
  // f_ab^n from t = max(1 - q/2, 0) and q = r / h of the pair.
  double operator()(double t, double q) const {
    const double f = t * t * t * t * (2.0 * q + 1.0) * inv_w_dx;
    double fn = 1.0;
    for (int k = 0; k < exponent; ++k) fn *= f;
    return fn;
  }
};

}  // namespace sph
