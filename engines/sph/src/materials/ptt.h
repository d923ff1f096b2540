// The multi-mode Phan-Thien-Tanner (PTT) viscoelastic fluid of Nutto et al.
// (eqs. 1-9): weakly compressible (Tait, Canini et al. eq. 6, or the
// quadratic EOS p = c0^2 rho^2 / (2 rho0), Nutto et al. eq. 9: the material key
// `eos`), with the extra stress
//   sigma = -p I + sum_i tau_i + 2 eta_s D                                  (eq. 3)
// and per mode i the linear PTT law
//   f_i tau_i + lambda_i tau_i^nabla = 2 eta_i D                            (eqs. 4-5)
//   tau^nabla = d tau/dt - L tau - tau L^T   (upper-convected derivative, L_jk = d v_j / d x_k)
//   D = (L + L^T) / 2
//   f_i = 1 + (lambda_i epsilon / eta_i) tr tau_i                           (eq. 6, linear PTT)
// Conventions: the paper's eq. 5 writes D = L + L^T; we keep the 1/2 so that
// eta_i is a true viscosity (lambda -> 0 gives tau = 2 eta D, a Newtonian
// fluid of viscosity eta). Each mode has its own f_i from its own trace (the
// usual multi-mode PTT). epsilon = 0 gives Oldroyd-B (with eta_s) or UCM.
// So the rate integrated by the predictor-corrector (integrator.h) is
//   d tau_i/dt = L tau_i + tau_i L^T + (2 eta_i D - f_i tau_i) / lambda_i.   (eq. R1)
// The solvent stress 2 eta_s D uses the velocity gradient of the last rate
// evaluation (explicit, a half step behind). With the deck's `morris_viscosity`
// term the solvent viscosity is the Morris pair term instead (eq. 10 with
// mu = eta_s, boundary particles at their no-slip velocity) and 2 eta_s D is
// not added: the Laplacian form is built on pair velocity differences, so it
// damps the row zig-zag mode that the (kernel-corrected) velocity gradient of
// eq. T2 does not see (the treatment of the Newtonian solvent in SPH
// viscoelastic channel flows, e.g. Ellero & Tanner 2005, Fang et al. 2006).
//
// Two terms of the calibrated moduli (`calibrate maxwell --plateau --cross`):
// - a Cross-law solvent (key `cross_viscosity`): the solvent stress adds
//   2 eta_C(gamma_dot) D, eta_C = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m),
//   gamma_dot = sqrt(2 D:D), from the same velocity gradient as 2 eta_s D.
//   0 < m <= 1 keeps the shear stress eta_C gamma_dot non-decreasing in
//   gamma_dot at any eta_inf >= 0 (m > 1 gives a flow curve with a falling
//   branch: an ill-posed, shear-banding solvent);
// - stress diffusion (key `stress_diffusion`, kappa m^2/s; pair loop, configuration PTT + Morris + Lees-Edwards):
//     d tau_i,a/dt += kappa sum_b V_b 2 F_ab r_ab^2 / (r_ab^2 + 0.01 h^2) (tau_i,a - tau_i,b)      (eq. SD1)
//   the Laplacian of each mode stress in the form of the Morris term (eq. 10); zero for a uniform stress;
// - a plateau modulus G_p (key `storage_plateau`): the stress column after the
//   modes integrates the upper-convected elastic law
//     d tau_p/dt = L tau_p + tau_p L^T + 2 G_p D                             (eq. R2)
//   which is eq. R1 in the limit lambda -> infinity at fixed G = eta / lambda
//   (f tau / lambda -> 0): a mode that never relaxes, objective with the same
//   derivative as the modes, integrating to tau_p = G_p (B - I) (B the left
//   Cauchy-Green tensor: a neo-Hookean solid, elastic over closed strain
//   cycles). In small-amplitude oscillation it adds G_p to G' and nothing to
//   G''; in steady shear its stress grows with the strain (a solid).
#pragma once
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "material_keys.h"
#include "parameters.h"
#include "material.h"
#include "physics_terms.h"
#include "vec.h"

namespace sph {

struct Ptt {
  static constexpr const char* name = "ptt";
  static constexpr bool has_stress = true;              // tensor momentum path (eq. T1)
  static constexpr int stress_modes = max_stress_modes;  // its stress lives in the per-mode field

  static std::vector<std::string> keys() {
    return {"epsilon", "solvent_viscosity", "modes", "storage_plateau", "cross_viscosity", "stress_diffusion"};
  }
  static void parse(const MaterialKeys& k, MaterialSpec& m) {
    m.epsilon = k.non_negative_or("epsilon", 0.0);
    m.solvent_viscosity = k.non_negative_or("solvent_viscosity", 0.0);
    if (k.term_on(term::morris_viscosity)) {  // the solvent viscosity is the Morris term (kinematic, m^2/s)
      if (!(m.solvent_viscosity > 0.0))
        throw InputError("physics term 'morris_viscosity' is on but '" + k.path() +
                         ".solvent_viscosity' is not > 0 (with a ptt material the Morris term is its solvent)");
      m.viscosity = m.solvent_viscosity / m.rho0;
    }
    m.storage_plateau = k.non_negative_or("storage_plateau", 0.0);
    m.stress_diffusion = k.non_negative_or("stress_diffusion", 0.0);
    const std::size_t most = max_stress_modes - (m.storage_plateau > 0.0 ? 1 : 0);  // the plateau takes a column
    const std::vector<MaterialKeys> modes = k.objects("modes", 1, max_stress_modes, {"lambda", "eta"});
    if (modes.size() > most)
      k.fail("modes", "has " + std::to_string(modes.size()) + " modes beside 'storage_plateau'; allowed: 1 to " +
                          std::to_string(most) + " (the plateau takes one of the stress columns)");
    for (const MaterialKeys& mode : modes) {
      m.mode_lambda.push_back(mode.positive("lambda"));
      m.mode_eta.push_back(mode.positive("eta"));
    }
    if (const auto cross = k.object("cross_viscosity", {"eta_0", "eta_inf", "time_constant", "exponent"})) {
      m.cross_eta_0 = cross->positive("eta_0");
      m.cross_eta_inf = cross->non_negative("eta_inf");
      m.cross_time = cross->positive("time_constant");
      m.cross_exponent = cross->number("exponent");
      if (m.cross_eta_inf > m.cross_eta_0)
        cross->fail("eta_inf", "= " + std::to_string(m.cross_eta_inf) + " Pa s is above eta_0 = " +
                                   std::to_string(m.cross_eta_0) + " Pa s; a Cross law thins (eta_inf <= eta_0)");
      if (!(m.cross_exponent > 0.0 && m.cross_exponent <= 1.0))
        cross->fail("exponent", "= " + std::to_string(m.cross_exponent) + " is outside (0, 1]; above 1 the shear "
                                "stress falls with the shear rate (an ill-posed solvent)");
    }
  }
  static void configure(const MaterialSpec& spec, Material& mat) {
    ModeParameters& p = mat.modes;
    p.count = static_cast<int>(spec.mode_lambda.size());
    for (int i = 0; i < p.count; ++i) p.lambda[i] = spec.mode_lambda[i], p.eta[i] = spec.mode_eta[i];
    p.epsilon = spec.epsilon;
    p.eta_s = spec.viscosity > 0.0 ? 0.0 : spec.solvent_viscosity;  // 0: the solvent is the Morris term
    p.plateau = spec.storage_plateau;
    p.cross = spec.cross_eta_0 > 0.0;
    p.diffusion = spec.stress_diffusion;
    p.cross_law = {spec.cross_eta_0, spec.cross_eta_inf, spec.cross_time, p.cross ? spec.cross_exponent : 1.0};
  }

  // Eq. R1 for every mode of the material and eq. R2 for its plateau column (columns beyond keep a zero rate).
  template <int D>
  static void mode_rates(const Material& mat, const Mat<D>& L, const ModeStress<D>& tau, ModeStress<D>& dtau) {
    const ModeParameters& p = mat.modes;
    const Mat<D> two_D = L + L.transpose();
    dtau.setZero();
    for (int i = 0; i < p.count; ++i) {
      const Eigen::Map<const Mat<D>> t(tau.col(i).data());
      const double f = 1.0 + p.lambda[i] * p.epsilon / p.eta[i] * t.trace();
      Eigen::Map<Mat<D>>(dtau.col(i).data()) = L * t + t * L.transpose() + (p.eta[i] * two_D - f * t) / p.lambda[i];
    }
    if (p.plateau > 0.0) {
      const Eigen::Map<const Mat<D>> t(tau.col(p.count).data());
      Eigen::Map<Mat<D>>(dtau.col(p.count).data()) = L * t + t * L.transpose() + p.plateau * two_D;
    }
  }
  // The solvent part of the extra stress, 2 (eta_s + eta_C(gamma_dot)) D, gamma_dot = sqrt(2 D:D).
  template <int D>
  static Mat<D> solvent_stress(const Material& mat, const Mat<D>& L) {
    const ModeParameters& p = mat.modes;
    if (!p.cross) return p.eta_s * (L + L.transpose());
    const Mat<D> two_D = L + L.transpose();
    const double shear_rate = std::sqrt(0.5 * two_D.squaredNorm());  // 2 D:D = (2D):(2D) / 2
    return (p.eta_s + p.cross_law(shear_rate)) * two_D;
  }

  // The single-tensor hooks of the model interface (its stress is in the modes).
  template <int D>
  static void stress_rate(const Material&, const Mat<D>&, const Mat<D>&, Mat<D>& dtau) {
    dtau.setZero();
  }
  template <int D>
  static void post_correct(const Material&, Mat<D>&) {}
};

}  // namespace sph
