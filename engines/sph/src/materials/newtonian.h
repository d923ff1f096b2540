// The weakly compressible Newtonian fluid (Canini et al.): Tait EOS
// (eq. 6) and, with the `morris_viscosity` term, the Morris viscous force
// (eq. 10) as a pair term. It carries no deviatoric stress, so scenes made of
// it alone take the scalar pressure path of the pair loop (pair_loop.h).
//
// This header is the worked example of a material model: a name for the
// deck, its own keys (read into MaterialSpec), whether it carries a
// deviatoric stress tau (then the momentum equation takes the tensor form and
// the model gives d tau/dt in close_rates), and what it does after the
// corrector (return mapping, failure). Add the model to the list in
// material_models.h and a configuration that uses it in configurations.h.
#pragma once
#include <string>
#include <vector>

#include "material_keys.h"
#include "parameters.h"
#include "material.h"
#include "physics_terms.h"
#include "vec.h"

namespace sph {

struct Newtonian {
  static constexpr const char* name = "newtonian";
  static constexpr bool has_stress = false;  // no tau: the scalar (fast) momentum path

  // Keys of a `materials` entry besides name, model and the EOS keys.
  static std::vector<std::string> keys() { return {"viscosity"}; }
  static void parse(const MaterialKeys& k, MaterialSpec& m) {
    m.viscosity = k.positive_with_term("viscosity", term::morris_viscosity, "morris_viscosity");
  }

  // close_rates: d tau/dt from the velocity gradient and tau (models with stress only).
  template <int D>
  static void stress_rate(const Material&, const Mat<D>&, const Mat<D>&, Mat<D>& dtau) {
    dtau.setZero();
  }
  // post_correct: return mapping, failure (models with stress only).
  template <int D>
  static void post_correct(const Material&, Mat<D>&) {}
};

}  // namespace sph
