// Maxima over the particles after a corrector, for the stability check and
// the next adaptive step: largest |rho/rho0 - 1| and |v|^2 of the fluid (rho0
// of each particle's material), largest |dv/dt|^2 of the fluid (last
// evaluation), and whether every position, velocity and density is finite.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "parameters.h"
#include "material.h"
#include "parallel.h"
#include "particles.h"
#include "stages.h"

namespace sph {

struct StepMaxima {
  double worst_rho = 0.0, v2 = 0.0, a2 = 0.0;
  bool finite = true;
  bool valid = false;
};

template <int D>
inline void take_maxima(const Particles<D>& P, const MaterialTable& mats, std::ptrdiff_t i, double& worst_rho,
                        double& v2, double& a2, bool& finite) {
  // One test for all: a sum is finite only when every term is (inf - inf is NaN).
  finite = finite && std::isfinite(P.rho[i] + P.x[i].sum() + P.v[i].sum());
  if (!P.moves(i)) return;
  const TaitEos& eos = mats.eos(P.material[i]);  // a cavitating particle counts at its floor's density (eos.h)
  worst_rho = std::max(worst_rho, std::abs(std::max(P.rho[i], eos.floor_rho) / eos.rho0 - 1.0));
  v2 = std::max(v2, P.v[i].squaredNorm());
  a2 = std::max(a2, P.acc[i].squaredNorm());
}

// The maxima of two sets of particles (exact in any order).
inline void combine_maxima(StepMaxima& total, const StepMaxima& part) {
  total.worst_rho = std::max(total.worst_rho, part.worst_rho);
  total.v2 = std::max(total.v2, part.v2), total.a2 = std::max(total.a2, part.a2);
  total.finite = total.finite && part.finite;
}

// update(i) for every particle, then its part of the maxima (one pass, on the threads).
template <int D, class Update>
StepMaxima sweep_maxima(const Particles<D>& P, const MaterialTable& mats, Update&& update) {
  const std::ptrdiff_t n = P.size();
  double worst_rho = 0.0, v2 = 0.0, a2 = 0.0;
  bool finite = true;
  auto body = [&](std::ptrdiff_t i, double& w, double& v, double& a, bool& f) {
    update(i);
    take_maxima(P, mats, i, w, v, a, f);
  };
  if (go_parallel(n, parallel_min_light)) {
#pragma omp parallel for reduction(max : worst_rho, v2, a2) reduction(&& : finite) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i, worst_rho, v2, a2, finite);
  } else {
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i, worst_rho, v2, a2, finite);
  }
  return {worst_rho, v2, a2, finite, true};
}

// Time step of eq. 13 extended by the viscous (with Morris viscosity) and
// force criteria, s: min(cfl h/(c0 + v_max), viscous h^2/nu, force sqrt(h/a_max))
// from the maxima m (largest c0 and nu over the materials).
inline double adaptive_time_step(const StepMaxima& m, const RunParameters& deck, const MaterialTable& mats, bool viscous) {
  const double h = deck.h;
  double dt = deck.cfl * h / (mats.c0_max() + std::sqrt(m.v2));
  if (viscous) dt = std::min(dt, deck.viscous_factor * h * h / mats.nu_max());
  if (m.a2 > 0.0) dt = std::min(dt, deck.force_factor * std::sqrt(h / std::sqrt(m.a2)));
  return dt;
}

// With the eddy viscosity: dt also within the viscous criterion of nu + nu_t_max, the largest nu_t (m^2/s) of
// the last evaluation (eddy_viscosity.h).
inline double eddy_time_step(double dt, const RunParameters& deck, const MaterialTable& mats, double nu_t_max) {
  return std::min(dt, deck.viscous_factor * deck.h * deck.h / (mats.nu_max() + nu_t_max));
}

// max |rho/rho0 - 1| over the fluid particles (rho0 of each particle's material).
template <int D>
double max_density_deviation(const Particles<D>& P, const MaterialTable& mats) {
  double worst = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.moves(i)) {
      const TaitEos& eos = mats.eos(P.material[i]);
      worst = std::max(worst, std::abs(std::max(P.rho[i], eos.floor_rho) / eos.rho0 - 1.0));
    }
  return worst;
}

// NaN anywhere, or a fluid particle whose density deviates from its rho0 by
// more than the threshold or that is faster than c0. (Boundary and buffer
// densities are devices of the wall and open-boundary models.)
inline StabilityReport stability_report(const StepMaxima& m, double max_deviation, double c0) {
  if (!m.finite) return {false, "a particle's position, velocity or density is not finite"};
  if (m.worst_rho > max_deviation)
    return {false, "density deviates from rho0 by " + std::to_string(100.0 * m.worst_rho) + " % (limit " +
                       std::to_string(100.0 * max_deviation) + " %)"};
  if (m.v2 > c0 * c0)
    return {false, "a particle moves at " + std::to_string(std::sqrt(m.v2)) + " m/s, faster than c0 = " +
                       std::to_string(c0) + " m/s"};
  return {};
}

}  // namespace sph
