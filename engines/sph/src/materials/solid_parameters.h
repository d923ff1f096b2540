// The parameters of a Johnson-Cook solid (materials/johnson_cook_material.h), SI units: the deck parser fills
// them (MaterialSpec::solid) and the run's material keeps them (Material::solid). Plain structs of
// johnson_cook.h, whose free functions take them.
#pragma once
#include <cmath>

#include "johnson_cook.h"

namespace sph {

enum class SolidEos { linear, mie_gruneisen };

struct SolidParameters {
  double shear_modulus = 0.0;       // G, Pa
  SolidEos eos = SolidEos::linear;  // p = K mu, or Mie-Grueneisen on the Hugoniot (johnson_cook.h)
  solid::LinearSolidEos linear{};   // rho0 kg/m^3, K Pa
  solid::MieGruneisenEos shock{};   // rho0 kg/m^3, C0 m/s, S -, Gamma0 -
  bool plastic = false;             // a yield stress is given (else elastic without limit)
  solid::JohnsonCookStrength strength{};  // eqs. 10-11
  bool fails = false;                     // Johnson-Cook damage (eqs. 13-14)
  solid::JohnsonCookFailure failure{};
  solid::SolidHeat heat{};                // rho0, C_p J/(kg K), heat fraction chi (0: isothermal)
  double artificial_stress = 0.0;         // epsilon of Monaghan's artificial stress (0: off)
  int artificial_stress_exponent = 4;     // n of f_ab^n
  bool corrected_momentum = false;         // eq. T1 with the kernel-corrected gradient M^-T grad W (eq. KC1)
  double smoothing = 0.0;                  // delta of eq. SS1, the diffusion of rho and s (solid_smoothing.h; 0: off)
  double spacing = 0.0;                   // the particle spacing dx of f_ab = W(r) / W(dx), m

  double rho0() const { return eos == SolidEos::linear ? linear.rho0 : shock.rho0; }
  // Bulk modulus of the reference state, Pa (rho0 C0^2 for Mie-Grueneisen).
  double bulk_modulus() const { return eos == SolidEos::linear ? linear.bulk_modulus : shock.rho0 * shock.c0 * shock.c0; }
  // Longitudinal wave speed in uniaxial strain, sqrt((K + 4G/3) / rho0), m/s.
  double wave_speed() const { return std::sqrt((bulk_modulus() + 4.0 / 3.0 * shear_modulus) / rho0()); }
};

}  // namespace sph
