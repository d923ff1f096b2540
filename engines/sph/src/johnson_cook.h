// The Johnson-Cook solid of Nutto et al. (eqs. 10-14), the solid equations of
// state and Hutchings' crater (eq. 20): plain parameter structs and free
// functions on doubles and 3 x 3 tensors, no allocation, no deck types. SI
// units; tension positive; pressure p positive in compression, sigma = -p I + s.
//   sigma_y = [A + B eps_p^n] R(epsdot*; C) [1 - T*^m]                 (eq. 10)
//   T*      = (T - T0) / (Tm - T0), clipped to [0, 1]                   (eq. 11)
//   dT      = chi dW_p / (rho0 C_p),  dW_p = sigma_y d eps_p            (eq. 12)
//   D       = sum d eps_p / eps_f                                       (eq. 13)
//   eps_f   = [D1 + D2 exp(D3 sigma*)] R(epsdot*; D4) [1 + D5 T*]       (eq. 14)
// epsdot* = epsdot_p / epsdot_0; R = (1 + epsdot*)^C (power, the paper's form)
// or 1 + C ln(max(epsdot*, 1)) (log, Johnson & Cook's own). sigma* = mean
// stress / von Mises stress (tension positive).
// Mie-Grueneisen on the Hugoniot U_s = C0 + S u_p, mu = rho / rho0 - 1:
//   mu >= 0: p = rho0 C0^2 mu [1 + (1 - Gamma0/2) mu] / [1 - (S-1) mu]^2 + Gamma0 rho0 e
//   mu <  0: p = rho0 C0^2 mu + Gamma0 rho0 e
// The numpy reference orchestrator/reference/johnson_cook.py and solid_eos.py
// computes the same quantities; docs/solids.md states the conventions.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

#include "vec.h"

namespace sph::solid {

enum class RateForm { power, log };

struct JohnsonCookStrength {
  double A;                             // initial yield stress, Pa
  double B;                             // hardening modulus, Pa
  double n;                             // hardening exponent, -
  double C;                             // rate sensitivity, -
  double m;                             // thermal softening exponent, -
  double reference_rate = 1.0;          // epsdot_0, 1/s
  double room_temperature = 293.0;      // T0, K
  double melting_temperature = 925.0;   // Tm, K
  RateForm rate_form = RateForm::power;
};

struct JohnsonCookFailure {
  double D1, D2, D3, D4, D5;            // -
  double reference_rate = 1.0;          // epsdot_0 of the D4 term, 1/s
  RateForm rate_form = RateForm::power;
};

struct SolidHeat {
  double rho0;           // reference density, kg/m^3
  double heat_capacity;  // C_p, J/(kg K)
  double heat_fraction;  // chi, the share of plastic work turned into heat, -
};

struct MieGruneisenEos {
  double rho0;    // kg/m^3
  double c0;      // bulk sound speed, m/s
  double s;       // Hugoniot slope, -
  double gamma0;  // Grueneisen parameter, -
};

struct LinearSolidEos {
  double rho0;          // kg/m^3
  double bulk_modulus;  // K, Pa
};

// x^e for x >= 0 without calling pow where the result is exact (x = 0, e > 0: an elastic particle at room
// temperature, most of a solid, skips its two pow calls).
inline double power_of_nonnegative(double x, double e) { return x > 0.0 || !(e > 0.0) ? std::pow(x, e) : 0.0; }

// R(epsdot*) of eqs. 10 and 14 for a dimensionless rate >= 0, -.
inline double jc_rate_factor(double rate_ratio, double exponent, RateForm form) {
  if (form == RateForm::power) return rate_ratio > 0.0 ? std::pow(1.0 + rate_ratio, exponent) : 1.0;  // 1^C = 1
  return 1.0 + exponent * std::log(std::max(rate_ratio, 1.0));
}

// T* of eq. 11 (-), clipped to [0, 1]; temperatures in K.
inline double homologous_temperature(double temperature, double room_temperature, double melting_temperature) {
  const double t_star = (temperature - room_temperature) / (melting_temperature - room_temperature);
  return std::min(std::max(t_star, 0.0), 1.0);
}

// sigma_y of eq. 10, Pa: plastic strain (-), plastic rate (1/s), temperature (K).
inline double jc_yield_stress(const JohnsonCookStrength& p, double plastic_strain, double plastic_rate,
                              double temperature) {
  const double t_star = homologous_temperature(temperature, p.room_temperature, p.melting_temperature);
  const double hardening = p.A + p.B * power_of_nonnegative(std::max(plastic_strain, 0.0), p.n);
  return hardening * jc_rate_factor(plastic_rate / p.reference_rate, p.C, p.rate_form) *
         (1.0 - power_of_nonnegative(t_star, p.m));
}

// eps_f of eq. 14, -: triaxiality (-, tension positive), plastic rate (1/s), T* (-).
inline double jc_failure_strain(const JohnsonCookFailure& f, double stress_triaxiality, double plastic_rate,
                                double homologous) {
  const double rate = jc_rate_factor(plastic_rate / f.reference_rate, f.D4, f.rate_form);
  return (f.D1 + f.D2 * std::exp(f.D3 * stress_triaxiality)) * rate * (1.0 + f.D5 * homologous);
}

// dD = d eps_p / eps_f of eq. 13; a failure strain <= 0 fails at the first plastic increment (inf).
inline double damage_increment(double plastic_strain_increment, double failure_strain) {
  if (plastic_strain_increment <= 0.0) return 0.0;
  return failure_strain > 0.0 ? plastic_strain_increment / failure_strain : std::numeric_limits<double>::infinity();
}

// T - T0 = chi W_p / (rho0 C_p) of eq. 12, K, for a plastic work W_p per unit volume (J/m^3).
inline double adiabatic_temperature_rise(const SolidHeat& heat, double plastic_work_density) {
  return heat.heat_fraction * plastic_work_density / (heat.rho0 * heat.heat_capacity);
}

inline Mat<3> deviator(const Mat<3>& t) { return t - (t.trace() / 3.0) * Mat<3>::Identity(); }

// sqrt(3/2 s : s), Pa, of a deviatoric stress s (Pa).
inline double von_mises(const Mat<3>& s) { return std::sqrt(1.5 * s.squaredNorm()); }

// sigma* = mean stress / von Mises stress, -; 0 without a deviatoric stress.
inline double triaxiality(double mean_stress, double equivalent_stress) {
  return equivalent_stress > 0.0 ? mean_stress / equivalent_stress : 0.0;
}

// R t R^T with R = exp(W dt): the exact Jaumann rotation over dt (s) for a constant spin W = (L - L^T) / 2 (1/s).
inline Mat<3> corotate(const Mat<3>& t, const Mat<3>& spin, double dt) {
  const Vec<3> axis = Vec<3>(spin(2, 1), spin(0, 2), spin(1, 0)) * dt;
  const double angle = axis.norm();
  if (angle == 0.0) return t;
  const Mat<3> k = spin * (dt / angle);
  const Mat<3> rotation = Mat<3>::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * (k * k);
  return rotation * t * rotation.transpose();
}

struct RadialReturn {
  Mat<3> deviatoric_stress;         // Pa
  double plastic_strain_increment;  // -
  double yield_stress;              // at the end of the step, Pa
  double plastic_work;              // per unit volume, J/m^3
  double temperature_rise;          // eq. 12, K
};

namespace detail {

// f(x) = trial - 3 G x - sigma_y(eps_p + x, x / dt, T) and df/dx (f falls with x).
inline void return_residual(const JohnsonCookStrength& p, double trial, double G, double eps_p, double temperature,
                            double dt, double x, double& f, double& df) {
  const double eps = eps_p + x;
  const double thermal =
      1.0 - std::pow(homologous_temperature(temperature, p.room_temperature, p.melting_temperature), p.m);
  const double ratio = x / (dt * p.reference_rate);
  const double rate = jc_rate_factor(ratio, p.C, p.rate_form);
  const double d_rate = p.rate_form == RateForm::power
                            ? p.C * std::pow(1.0 + ratio, p.C - 1.0) / (dt * p.reference_rate)
                            : (ratio > 1.0 ? p.C / x : 0.0);
  const double hardening = p.A + p.B * std::pow(eps, p.n);
  const double d_hardening = eps > 0.0 ? p.B * p.n * std::pow(eps, p.n - 1.0) : std::numeric_limits<double>::infinity();
  f = trial - 3.0 * G * x - hardening * rate * thermal;
  df = -3.0 * G - thermal * (d_hardening * rate + hardening * d_rate);
}

// The plastic increment: Newton steps inside a shrinking bracket [0, trial / 3G], bisection where Newton leaves it.
inline double plastic_increment(const JohnsonCookStrength& p, double trial, double G, double eps_p, double temperature,
                                double dt) {
  double lo = 0.0, hi = trial / (3.0 * G);
  double x = std::min(hi, (trial - jc_yield_stress(p, eps_p, 0.0, temperature)) / (3.0 * G));
  for (int it = 0; it < 200; ++it) {
    double f, df;
    return_residual(p, trial, G, eps_p, temperature, dt, x, f, df);
    if (f == 0.0) return x;
    (f > 0.0 ? lo : hi) = x;
    double guess = std::isfinite(df) && df < 0.0 ? x - f / df : std::numeric_limits<double>::quiet_NaN();
    if (!(lo < guess && guess < hi)) guess = 0.5 * (lo + hi);
    if (std::abs(guess - x) <= 1e-15 * hi || hi - lo <= 1e-15 * hi) return guess;
    x = guess;
  }
  return x;
}

}  // namespace detail

// One J2 step: the trial s + 2 G dev(d eps) (strain increment D dt, -) returned radially to sigma_y at
// eps_p + d eps_p, rate d eps_p / dt (s) and the step's starting temperature (K); the identity inside the surface.
inline RadialReturn radial_return(const JohnsonCookStrength& p, const SolidHeat& heat, double shear_modulus,
                                  const Mat<3>& deviatoric_stress, const Mat<3>& strain_increment,
                                  double plastic_strain, double temperature, double dt) {
  const Mat<3> trial = deviatoric_stress + 2.0 * shear_modulus * deviator(strain_increment);
  const double q_trial = von_mises(trial);
  const double static_yield = jc_yield_stress(p, plastic_strain, 0.0, temperature);
  if (q_trial <= static_yield) return {trial, 0.0, static_yield, 0.0, 0.0};
  if (static_yield <= 0.0) return {Mat<3>::Zero(), q_trial / (3.0 * shear_modulus), 0.0, 0.0, 0.0};  // molten
  const double dep = detail::plastic_increment(p, q_trial, shear_modulus, plastic_strain, temperature, dt);
  const double q_new = q_trial - 3.0 * shear_modulus * dep;
  const double work = q_new * dep;
  return {trial * (q_new / q_trial), dep, q_new, work, adiabatic_temperature_rise(heat, work)};
}

// Mie-Grueneisen pressure, Pa, at density rho (kg/m^3) and specific internal energy e (J/kg); +inf at or beyond
// the Hugoniot's limiting compression 1 / (S - 1).
inline double mie_gruneisen_pressure(const MieGruneisenEos& eos, double rho, double specific_energy) {
  const double mu = rho / eos.rho0 - 1.0;
  const double bulk = eos.rho0 * eos.c0 * eos.c0;
  const double thermal = eos.gamma0 * eos.rho0 * specific_energy;
  if (mu < 0.0) return bulk * mu + thermal;
  const double denominator = 1.0 - (eos.s - 1.0) * mu;
  if (!(denominator > 0.0)) return std::numeric_limits<double>::infinity();
  return bulk * mu * (1.0 + (1.0 - 0.5 * eos.gamma0) * mu) / (denominator * denominator) + thermal;
}

// p = K (rho / rho0 - 1), Pa.
inline double linear_solid_pressure(const LinearSolidEos& eos, double rho) {
  return eos.bulk_modulus * (rho / eos.rho0 - 1.0);
}

// Eq. 20, d = 2 r sqrt(2 v) (2 rho / (3 H))^(1/4), m: sphere radius (m), speed (m/s), the sphere's density
// (kg/m^3), target hardness (Pa).
inline double hutchings_crater_diameter(double radius, double speed, double sphere_density, double hardness) {
  return 2.0 * radius * std::sqrt(2.0 * speed) * std::pow(2.0 * sphere_density / (3.0 * hardness), 0.25);
}

// Eq. 20 solved for the hardness H, Pa.
inline double hutchings_hardness(double diameter, double radius, double speed, double sphere_density) {
  const double ratio = 2.0 * radius * std::sqrt(2.0 * speed) / diameter;
  return 2.0 * sphere_density / 3.0 * ratio * ratio * ratio * ratio;
}

}  // namespace sph::solid
