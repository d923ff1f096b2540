// Smagorinsky's sub-particle-scale eddy viscosity (the Reynolds stresses R of
// the drill paper's eq. 4), switched on by the deck key `eddy_viscosity`:
//
//   eq. SM1  nu_t,a = (cs dx)^2 |S_a|,  |S| = sqrt(2 S:S),  S = (L + L^T) / 2,
//            L_a = sum_b V_b (v_b - v_a) (x) grad_a W_ab   (a fixed particle enters with its no-slip velocity)
//   eq. SM2  the Morris term (eq. 10) with mu_ab = rho0 (nu + nu_t,ab): nu_t,ab = (nu_t,a + nu_t,b) / 2
//            between two fluid particles; against a fixed particle (wall or buffer) the fluid's own nu_t, or
//            none with the deck's "walls": false (the wall friction then is the laminar Morris term's: for walls
//            the lattice does not resolve, where an undamped mixing length cs dx overstates it)
//
// L is summed in the same pair loop as the rates and nu_t is taken when the
// rates close (Simulation::close_rates_at), so a step uses the eddy viscosity
// of the previous evaluation (lagged by one step, as DualSPHysics does for its
// SPS stress); a run starts, and a resumed run restarts, with nu_t = 0. The
// wall takes no damping (van Driest): the mixing length is cs dx up to the
// wall, so the scheme's steady plane channel is the mixing-length profile of
// tests/test_eddy_viscosity.cpp. nu_t only ever adds dissipation.
#pragma once
#include <cmath>

#include "vec.h"

namespace sph {

struct Smagorinsky {
  double length2 = 0.0;  // (cs dx)^2, m^2
  // nu_t of eq. SM1 from a velocity gradient L (1/s), m^2/s.
  template <int D>
  double nu_t(const Mat<D>& L) const {
    const Mat<D> S = 0.5 * (L + L.transpose());
    return length2 * std::sqrt(2.0 * S.squaredNorm());
  }
};

}  // namespace sph
