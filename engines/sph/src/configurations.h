// The closed list of compiled configurations: which material models a run
// combines and which pair terms its pair loop carries. A deck runs the
// configuration whose model set and pair terms match it exactly; anything
// else is rejected with the list (run_loop.h). Each line is one instantiation
// of the solver per dimension, so the list grows by the meaningful
// combinations only, not by the power set of term bits (before: all 16
// subsets of four term bits).
//
// Per-particle options (body force, wall penalty) are runtime switches
// outside the pair loop (they cost nothing measurable there). `several_materials`
// is set by the dispatcher when a run has more than one material and Morris
// viscosity: only then does the pair loop look up the pair viscosity mu_ab
// (material.h); with one material it keeps the constant mu.
#pragma once
#include <tuple>

#include "material_models.h"
#include "physics_terms.h"

namespace sph {

template <class Models, unsigned Terms>
struct Configuration {
  using models = Models;
  static constexpr unsigned terms = Terms;
};

namespace config {
using N = ModelList<Newtonian>;
using P = ModelList<Ptt>;
using J = ModelList<JohnsonCook>;
using NJ = ModelList<Newtonian, JohnsonCook>;  // a Newtonian fluid beside Johnson-Cook solids
using PJ = ModelList<Ptt, JohnsonCook>;        // a PTT medium beside Johnson-Cook solids (eq. FS1 with its stress)
constexpr unsigned morris = term::morris_viscosity, av = term::artificial_viscosity, several = term::several_materials;
constexpr unsigned sheared = term::sheared;  // Lees-Edwards boundaries (the deck's `lees_edwards`)
constexpr unsigned corrected = term::viscosity_correction;  // the deck's `viscosity_correction`
constexpr unsigned eddy = term::eddy_viscosity;  // the deck's `eddy_viscosity` (Smagorinsky, eq. SM1)
constexpr unsigned grains = term::grains;  // the deck's `grains` (rigid grains the fluid drags, eq. G1)
constexpr unsigned diffused = term::stress_diffusion;  // a PTT material's `stress_diffusion` (eq. SD1)
}  // namespace config

using Configurations = std::tuple<                           //
    Configuration<config::N, 0>,                              // inviscid Newtonian fluid
    Configuration<config::N, config::av>,                     // dam breaks, the LAMMPS-like block
    Configuration<config::N, config::morris>,                 // channel flows
    Configuration<config::N, config::morris | config::av>,    //
    Configuration<config::N, config::morris | config::several>,               // layered Newtonian fluids
    Configuration<config::N, config::morris | config::av | config::several>,  //
    Configuration<config::N, config::morris | config::sheared>,               // Newtonian Lees-Edwards cell
    Configuration<config::N, config::morris | config::corrected>,             // renormalised Morris sum (eq. VC1)
    Configuration<config::N, config::morris | config::av | config::corrected>,  //
    Configuration<config::N, config::morris | config::eddy>,                  // Smagorinsky eddy viscosity
    Configuration<config::N, config::morris | config::av | config::eddy>,     //   (the drill's jets and clearances)
    Configuration<config::N, config::morris | config::grains>,                // grains in a viscous fluid
    Configuration<config::N, config::morris | config::corrected | config::grains>,  //   renormalised (eq. VC1)
    Configuration<config::N, config::morris | config::av | config::corrected | config::grains>,  //
    Configuration<config::N, config::morris | config::av | config::grains>,   //
    Configuration<config::N, config::av | config::grains>,                    //   (inviscid: angular momentum)
    Configuration<config::N, config::morris | config::sheared | config::grains>,  //   in a Lees-Edwards cell
    Configuration<config::P, 0>,                                              // PTT viscoelastic fluid (Nutto et al.)
    Configuration<config::P, config::av>,                                     //   with artificial viscosity
    Configuration<config::P, config::sheared>,                                // PTT Lees-Edwards cell (rheometer)
    Configuration<config::P, config::morris | config::sheared>,               //   with a Morris solvent (steady shear)
    Configuration<config::P, config::morris | config::sheared | config::diffused>,  //   and stress diffusion (high Wi)
    Configuration<config::P, config::morris>,   // PTT whose solvent viscosity is the Morris term (walled channels)
    Configuration<config::J, 0>,                // Johnson-Cook solid (artificial stress: a material key)
    Configuration<config::J, config::av>,       //   with artificial viscosity (shocks, impacts)
    Configuration<config::J, config::sheared>,   //   in a Lees-Edwards cell (homogeneous simple shear)
    Configuration<config::NJ, config::morris | config::several>,               // a viscous fluid on a solid
    Configuration<config::NJ, config::morris | config::av | config::several>,   //   (the abrasive-flow workpiece)
    Configuration<config::NJ, config::morris | config::several | config::grains>,  //   with grains (Fig. 5's channel)
    Configuration<config::NJ, config::morris | config::av | config::several | config::grains>,  //
    Configuration<config::PJ, config::morris | config::several>,               // a PTT medium on a solid
    Configuration<config::PJ, config::morris | config::several | config::grains>,  //   with grains (the MF20 channel)
    Configuration<config::PJ, config::morris | config::av | config::several | config::grains>>;  //

}  // namespace sph
