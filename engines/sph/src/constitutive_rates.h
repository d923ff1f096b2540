// The material models' part of the stages (stages.h) for configurations with
// a deviatoric stress: in close_rates the velocity gradient L = G M^-1
// (eq. T2's kernel correction) and each model's d tau/dt; after the
// corrector, each model's post_correct (return mapping, failure).
#pragma once
#include <cmath>
#include <cstddef>

#include "material.h"
#include "material_models.h"
#include "particles.h"
#include "tensor_pair_math.h"
#include "vec.h"

namespace sph {

// close_rates of fluid particle a, constitutive part: L = G M^-1 (M from its summed upper triangle) when
// `correct_gradient` and M is not singular (else L = G), then the rates of
// its material's stresses (per mode and the solvent stress, or a single tau).
template <class Models, int D>
void close_constitutive_rates(Particles<D>& P, const MaterialTable& materials, std::ptrdiff_t a,
                              bool correct_gradient) {
  Mat<D>& L = P.grad_v[a];
  const Mat<D> M = symmetric_shape(P.shape[a]);
  const double scale = M.cwiseAbs().maxCoeff();
  const bool regular = std::abs(M.determinant()) > 1e-6 * std::pow(scale, D);
  const Material& mat = materials[P.material[a]];
  const Mat<D> M_inv = regular ? Mat<D>(M.inverse()) : Mat<D>::Identity();
  if constexpr (Models::any_solid) {  // eq. KC1's M^-T for the next evaluation (I where M is singular or a is failed)
    if (mat.solid.corrected_momentum) {
      const bool failed = P.solid_state.value[a][slot::damage] >= 1.0;
      P.grad_correction[a] = failed ? Mat<D>::Identity() : Mat<D>(M_inv.transpose());
    }
  }
  if (correct_gradient && regular) L = L * M_inv;
  Models::visit(mat.model, [&](auto model) {
    using Model = decltype(model);
    if constexpr (stress_modes_v<Model> > 0) {
      Model::mode_rates(mat, L, P.mode_stress.value[a], P.mode_stress.rate[a]);
      P.tau_solvent[a] = Model::solvent_stress(mat, L);
    } else if constexpr (solid_v<Model>) {
      Model::rates(mat, L, P, a);  // s, s_zz and the energy (materials/johnson_cook_material.h)
    } else if constexpr (Models::any_single_stress) {
      model.stress_rate(mat, L, P.tau[a], P.dtau[a]);
    }
  });
}

// post_correct of particle i after a step of dt (s): its material's return mapping and failure (single-stress models).
template <class Models, int D>
void post_correct_material(Particles<D>& P, const MaterialTable& materials, std::ptrdiff_t i, double dt) {
  if constexpr (!Models::any_single_stress) return;
  if (!P.advects(i)) return;
  const Material& mat = materials[P.material[i]];
  Models::visit(mat.model, [&](auto model) {
    if constexpr (solid_v<decltype(model)>) decltype(model)::post_correct(mat, P, i, dt);
    else model.post_correct(mat, P.tau[i]);
  });
}

}  // namespace sph
