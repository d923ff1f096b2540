// Tait equation of state with background pressure (Canini et al., eq. 6), or
// the quadratic EOS of Nutto et al. (eq. 9), p = c0^2 rho^2 / (2 rho0),
// when `quadratic` (a material's `eos = "quadratic"`). With a `min_pressure`
// p_min (a cavitation floor: the vapour pressure, gauge) the pressure is
// max(p(rho), p_min): the fluid holds no tension beyond it, as water boils
// there; below floor_rho, the density of p_min, a particle counts as at
// floor_rho in the density checks (step_maxima.h).
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace sph {

struct TaitEos {
  double rho0;                 // reference density, kg/m^3
  double c0;                   // reference speed of sound, m/s
  double gamma;                // exponent (7 for water)
  double background_pressure;  // p_B, Pa
  bool quadratic = false;      // Nutto et al. eq. 9 instead of eq. 6
  double min_pressure = -std::numeric_limits<double>::infinity();  // p_min, Pa (none: -inf)
  double floor_rho = 0.0;      // the density of p_min, kg/m^3 (0: none)

  // p = rho0 c0^2 / gamma ((rho/rho0)^gamma - 1) + p_B, Pa
  // or p = c0^2 rho^2 / (2 rho0) + p_B (Nutto et al. eq. 9; p_B is 0 unless the deck gives it)
  double pressure(double rho) const {
    const double p = quadratic ? c0 * c0 * rho * rho / (2.0 * rho0) + background_pressure
                               : rho0 * c0 * c0 / gamma * (power(rho / rho0) - 1.0) + background_pressure;
    return p < min_pressure ? min_pressure : p;
  }

  // The density of pressure p (Pa), eq. 6 or 9 inverted, kg/m^3 (0 below the lowest pressure the EOS gives).
  double density(double p) const {
    const double excess = p - background_pressure;
    if (quadratic) return excess > 0.0 ? std::sqrt(2.0 * rho0 * excess) / c0 : 0.0;
    return rho0 * std::pow(std::max(0.0, 1.0 + gamma * excess / (rho0 * c0 * c0)), 1.0 / gamma);
  }

  // Set the floor p_min (Pa, below the rest pressure p_B) and its density.
  void set_min_pressure(double p_min) {
    min_pressure = p_min;
    floor_rho = density(p_min);
  }

  // c = sqrt(dp/drho) = c0 (rho/rho0)^((gamma-1)/2), m/s (quadratic: c0 sqrt(rho/rho0))
  double sound_speed(double rho) const {
    if (quadratic) return c0 * std::sqrt(rho / rho0);
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
