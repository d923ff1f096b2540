// The extra stress of a particle (tensor configurations: models with a
// deviatoric stress), sigma / rho^2 for the momentum equation in the tensor
// form (eq. T1), and the volume average over the fluid (the rheometer's
// reading, recorder.h).
#pragma once
#include <cstddef>

#include "particles.h"
#include "vec.h"

namespace sph {

// The extra stress of particle i, Pa: its tau (single-stress models), the sum
// of its mode stresses and the solvent stress 2 eta_s D (PTT, materials/ptt.h eq. 3).
template <class Models, int D>
Mat<D> extra_stress(const Particles<D>& P, std::size_t i) {
  Mat<D> tau = Mat<D>::Zero();
  if constexpr (Models::any_single_stress) tau += P.tau[i];
  if constexpr (Models::any_modes) {
    tau += P.tau_solvent[i];
    const ModeStress<D>& s = P.mode_stress.value[i];
    for (int k = 0; k < s.cols(); ++k) tau += Eigen::Map<const Mat<D>>(s.col(k).data());
  }
  return tau;
}

// sigma / rho^2 = (-p I + tau - tau_B) / rho^2 of particle i, Pa m^6/kg^2 (eq. T1), with its pressure p of this
// evaluation; tau_B Pa is a uniform background extra stress (zero unless the cell subtracts its mean, simulation.h).
template <class Models, int D>
Mat<D> stress_over_rho2(const Particles<D>& P, std::size_t i, const Mat<D>& background) {
  if constexpr (Models::any_modes)
    return (extra_stress<Models>(P, i) - background - P.p[i] * Mat<D>::Identity()) / (P.rho[i] * P.rho[i]);
  else
    return (P.tau[i] - background - P.p[i] * Mat<D>::Identity()) / (P.rho[i] * P.rho[i]);
}

// Volume average of the fluid's extra stress, Pa (sigma_xy of a Lees-Edwards cell is its (0, 1) entry).
template <class Models, int D>
Mat<D> mean_extra_stress(const Particles<D>& P) {
  Mat<D> sum = Mat<D>::Zero();
  double volume = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.moves(i)) {
      const double vol = P.mass[i] / P.rho[i];
      sum += vol * extra_stress<Models>(P, i), volume += vol;
    }
  return volume > 0.0 ? Mat<D>(sum / volume) : sum;
}

// tau_B, Pa, of a Lees-Edwards cell that subtracts its mean stress (`on`): the volume mean of the fluid's extra
// stress at the start of the step (one serial sum in particle order: the same for any thread count); else zero.
// A uniform stress exerts no force in a periodic cell, but eq. T1 turns one into forces wherever the kernel
// gradient sums do not vanish (the sliding images), and a first normal stress difference above the rest pressure
// puts the sample in tension (the tensile instability): the momentum equation then carries only the stress's
// departures from the mean; the stress itself (its rates, the records) is unchanged.
template <class Models, int D>
Mat<D> background_stress(const Particles<D>& P, bool on) {
  return on ? mean_extra_stress<Models>(P) : Mat<D>::Zero();
}

}  // namespace sph
