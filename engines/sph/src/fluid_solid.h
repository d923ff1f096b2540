// The pair terms between a fluid's particle and a solid's (a Newtonian fluid beside Johnson-Cook solids, pair_loop.h):
// eq. FS1, the force, and eq. FS2, what each side's density rate and velocity gradient take.
// Between a fluid's particle f and a solid's particle s (or a boundary particle of a solid's material) the tensor
// path's eq. T1 is replaced by the fluid's pressure alone, carried to the pair's midpoint:
//   dv_a/dt += -m_b 2 p~ / (rho_a rho_b) grad_a W_ab,   p~ = p_f + rho_f g . (x_s - x_f) / 2            (FS1)
// (g the body force), antisymmetric in a and b, so momentum is kept pair by pair. The fluid sees the solid as a
// wall of its own pressure (as Adami et al. 2012's walls, with the hydrostatic step to the pair's midpoint), and
// the solid takes that pressure as the traction on its surface; the solid's deviatoric stress acts between its own
// particles only. With eq. T1 across the interface a solid's surface stress that differs from the fluid's pressure
// (a free surface's truncated sums, eq. SS1's smoothing there) held the fluid off its hydrostatic pressure (an
// elastic layer under water: 12 % with SS1), and an interface mode in which the solid's top row and the fluid's
// first row slide against each other grew at about 10 /s in 3D (a layer under oil at rest left 1e-13 m/s and
// reached 3e-2 m/s in 3 s). Eq. FS1 with the solid's smoothing (eq. SS1, which the solid then needs: without it
// the layer's own row mode grows) keeps both at rest.
// A PTT medium (configurations with stress modes) carries its whole stress across, not its pressure alone: its
// extra stress tau_f (modes, plateau, a Cross solvent; eq. 3 of materials/ptt.h) joins the pressure,
//   dv_a/dt += m_b 2 (tau_f - p~ I) / (rho_a rho_b) grad_a W_ab                                        (FS1')
// still antisymmetric in a and b; the solid's surface takes the medium's normal stresses (N1 along its
// streamlines) and shear. A Newtonian medium's Morris term already carries its shear (material.h).
#pragma once
#include <utility>

#include "particles.h"
#include "vec.h"

namespace sph {

// Eq. FS1 for the pair a, b (one of them a solid material's): the factor of m_b in dv_a/dt; grad_a W = F r with
// r = x_a - x_b to the listed periodic image (m).
// Eq. FS1' with Polymer (a medium with stress modes), from the fluid's sigma / rho^2 of this evaluation.
template <bool Polymer, int D>
inline __attribute__((always_inline)) Vec<D> interface_force(const Particles<D>& P, const Vec<D>& gravity, int a,
                                                             int b, double F, const Vec<D>& r) {
  const bool a_fluid = !P.solid_material[P.material[a]];
  const int f = a_fluid ? a : b;
  if constexpr (Polymer) {  // 2 (tau_f - p_f I) / (rho_f rho_s) g, and the hydrostatic step to the midpoint
    const double step = 0.5 * P.rho[f] * gravity.dot(a_fluid ? Vec<D>(-r) : r);
    return (2.0 * P.rho[f] / P.rho[a_fluid ? b : a]) * (P.sigma_rho2[f] * Vec<D>(F * r)) -
           (2.0 * step * F / (P.rho[a] * P.rho[b])) * r;
  }
  const double p = P.p[f] + 0.5 * P.rho[f] * gravity.dot(a_fluid ? Vec<D>(-r) : r);  // x_s - x_f = -r or r
  return (-2.0 * p * F / (P.rho[a] * P.rho[b])) * r;
}

// Eq. FS2: across a fluid-solid interface (one particle of a solid's material, the other not) the solid's density
// rate and velocity gradient L (eq. T2) take its own particles only, and a fixed particle sums its own kind of
// material only. Which of a, b is the solid's (both false: no interface, always in a configuration of one kind).
template <class Models, int D>
inline __attribute__((always_inline)) std::pair<bool, bool> interface_sides(const Particles<D>& P, int a, int b) {
  if constexpr (Models::any_solid && !Models::all_solid)
    if (P.across_interface(a, b)) return {P.solid_material[P.material[a]], !P.solid_material[P.material[a]]};
  return (void)P, (void)a, (void)b, std::pair<bool, bool>{false, false};
}

// Eq. 7 of the pair with Fvr = v_ab . grad_a W_ab: a moving particle's rho_a V_b Fvr (rV_a; a solid's across the
// interface none), a fixed one's summation rate m_b Fvr (none across the interface: it sums its own kind).
template <bool AMoves, bool BMoves>
inline __attribute__((always_inline)) void continuity_pair(double& drho_a, double& drho_b, double Fvr, double rV_a,
                                                           double rV_b, double m_b, double m_a, bool solid_a,
                                                           bool solid_b) {
  if constexpr (AMoves) drho_a += solid_a ? 0.0 : rV_a * Fvr;
  else drho_a += solid_a || solid_b ? 0.0 : m_b * Fvr;
  if constexpr (BMoves) drho_b += solid_b ? 0.0 : rV_b * Fvr;
  else drho_b += solid_a || solid_b ? 0.0 : m_a * Fvr;
}

}  // namespace sph
