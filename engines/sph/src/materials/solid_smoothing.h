// The diffusion of a solid's density and deviatoric stress between its own particles (optional: the material key
// `smoothing`, delta):
//   d A_a/dt += kappa sum_b 2 V_b (A_a - A_b) F r_ab^2 / (r_ab^2 + 0.01 h^2),  kappa = delta h c0,   (SS1)
// for A = rho, s (and s_zz in 2D), over the pairs of two intact particles of one solid material (grad_a W = F r_ab,
// F < 0: the Morris form of the Laplacian, Morris, Fox & Zhu 1997). The plain pair sum of eq. T1 exerts no force on
// a stress that alternates from one particle row to the next (each particle's neighbours at +-dx share one value, at
// +-2dx another), and the velocity gradient of eq. T2 does not see a velocity that alternates so: such a stress, once
// set (at a boundary, under a sudden load), stays. The Laplacian is largest on exactly that mode (it decays at a rate
// of about 8 kappa / dx^2) and of second order on a smooth field (kappa h^2 grad^2 A / dx^2).
#pragma once
#include <array>

#include "material.h"
#include "materials/solid_state.h"
#include "particles.h"

namespace sph {

struct SolidSmoothing {
  std::array<double, 256> kappa{};  // per material (uint8 index): delta h c0, m^2/s (0: off); no heap in a step
  double eta2 = 0.0;          // 0.01 h^2, m^2
  bool on = false;
  // From the run's materials (h m): each solid's delta times h and its wave speed c0.
  template <class Table>
  static SolidSmoothing of(const Table& materials, double h) {
    SolidSmoothing s;
    s.eta2 = 0.01 * h * h;
    for (int k = 0; k < materials.size(); ++k) {
      const double delta = materials[k].is_solid ? materials[k].solid.smoothing : 0.0;
      s.kappa[k] = delta * h * materials[k].eos.c0;
      s.on = s.on || delta > 0.0;
    }
    return s;
  }
  // Eq. SS1 for the pair a, b (both moving) with F and r^2 of the pair: into drho, dtau (and the s_zz rate) of both.
  template <int D>
  void pair(Particles<D>& P, int a, int b, double F, double r2) const {
    if (!on) return;
    const int k = P.material[a];
    if (k != P.material[b] || !(kappa[k] > 0.0)) return;
    if (P.solid_state.value[a][slot::damage] >= 1.0 || P.solid_state.value[b][slot::damage] >= 1.0) return;
    const double w = 2.0 * kappa[k] * F * r2 / (r2 + eta2), wa = w * P.vol[b], wb = w * P.vol[a];
    const double drho = P.rho[a] - P.rho[b];
    P.drho[a] += wa * drho, P.drho[b] -= wb * drho;
    const Mat<D> ds = P.tau[a] - P.tau[b];
    P.dtau[a].noalias() += wa * ds, P.dtau[b].noalias() -= wb * ds;
    if constexpr (D == 2) {
      const double dz = P.solid_state.value[a][slot::szz] - P.solid_state.value[b][slot::szz];
      P.solid_state.rate[a][slot::szz] += wa * dz, P.solid_state.rate[b][slot::szz] -= wb * dz;
    }
  }
};

}  // namespace sph
