// Tait equation of state with background pressure (Canini et al., eq. 6).
#pragma once
#include <cmath>

namespace sph {

struct TaitEos {
  double rho0;                 // reference density, kg/m^3
  double c0;                   // reference speed of sound, m/s
  double gamma;                // exponent (7 for water)
  double background_pressure;  // p_B, Pa

  // p = rho0 c0^2 / gamma ((rho/rho0)^gamma - 1) + p_B, Pa
  double pressure(double rho) const {
    return rho0 * c0 * c0 / gamma * (power(rho / rho0) - 1.0) + background_pressure;
  }

  // c = sqrt(dp/drho) = c0 (rho/rho0)^((gamma-1)/2), m/s
  double sound_speed(double rho) const {
    const double ratio = rho / rho0;
    if (gamma == 7.0) return c0 * ratio * ratio * ratio;
    return c0 * std::pow(ratio, 0.5 * (gamma - 1.0));
  }

 private:
  // (rho/rho0)^gamma with a fast path for the usual gamma = 7.
  double power(double ratio) const {
    if (gamma == 7.0) {
      const double r2 = ratio * ratio;
      return r2 * r2 * r2 * ratio;
    }
    return std::pow(ratio, gamma);
  }
};

}  // namespace sph
