// Eq. SC1: contact between two deformable bodies. Each solid material of a run is a body of its own; two particles
// of two different solid materials take no pair term of eqs. 7, T1, T2, SS1 or the viscosities (each body sums its
// own particles only, as at a free surface) but a spring that acts in compression only,
//     dv_a/dt += k (d0 - r_ab) / (m_a r_ab) r_ab,  dv_b/dt -= k (d0 - r_ab) / (m_b r_ab) r_ab   for r_ab < d0,
// with d0 the particle spacing dx (two touching bodies' lattices start d0 apart: no force) and k = rho0 c_L^2 dx^(D-2)
// of the stiffer body (c_L its longitudinal wave speed; per unit depth in 2D): a particle's own stiffness, so the
// contact is as compliant as one spacing of the material and its stable step is the solid's (sqrt(m / k) = dx / c_L). The pair's forces are
// equal and opposite (momentum is conserved); the spring's energy is not in the solid's internal energy. A run with
// one solid material (a workpiece, a bar, a target) has no such pair and the test costs one branch per pair.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "particles.h"
#include "vec.h"

namespace sph {

struct SolidContact {
  std::array<std::uint8_t, 256> solid{};  // per material (uint8 index): 1 for a solid
  double stiffness = 0.0;                 // k, N/m
  double range2 = 0.0;                    // d0^2, m^2
  bool on = false;                        // two solid materials or more

  // From the run's materials: their solids, each one's spacing dx and wave speed.
  template <int D, class Table>
  static SolidContact of(const Table& materials) {
    SolidContact s;
    int solids = 0;
    for (int k = 0; k < materials.size(); ++k) {
      if (!materials[k].is_solid) continue;
      const auto& p = materials[k].solid;
      s.solid[k] = 1, ++solids;
      s.stiffness = std::max(s.stiffness, p.rho0() * p.wave_speed() * p.wave_speed() * (D == 3 ? p.spacing : 1.0));
      s.range2 = std::max(s.range2, p.spacing * p.spacing);
    }
    s.on = solids >= 2;
    return s;
  }
  // Whether a and b belong to two bodies: then eq. SC1 is the pair's only term (added to acc_a and acc[b] of
  // the moving ones) and the caller skips the rest.
  template <bool AMoves, bool BMoves, int D>
  inline __attribute__((always_inline)) bool pair(const Particles<D>& P, int a, int b, const Vec<D>& r, double r2,
                                                  Vec<D>& acc_a, Vec<D>* acc) const {
    const std::uint8_t ka = P.material[a], kb = P.material[b];
    if (!on || ka == kb || !(solid[ka] & solid[kb])) return false;
    if (r2 < range2) {
      const double dist = std::sqrt(r2), f = stiffness * (std::sqrt(range2) - dist) / dist;
      if constexpr (AMoves) acc_a += (f / P.mass[a]) * r;
      if constexpr (BMoves) acc[b] -= (f / P.mass[b]) * r;
    }
    return (void)acc_a, (void)acc, true;
  }
};

}  // namespace sph
