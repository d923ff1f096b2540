// Every material model a deck may name, and model lists as compile-time sets.
#pragma once
#include <algorithm>
#include <string>
#include <type_traits>

#include "parameters.h"
#include "material.h"

#include "materials/johnson_cook_material.h"
#include "materials/newtonian.h"
#include "materials/ptt.h"

namespace sph {

// A model's number of stress modes (its static `stress_modes`, else 0: a single tau or none).
template <class M, class = void>
struct stress_modes_of : std::integral_constant<int, 0> {};
template <class M>
struct stress_modes_of<M, std::void_t<decltype(M::stress_modes)>> : std::integral_constant<int, M::stress_modes> {};
template <class M>
constexpr int stress_modes_v = stress_modes_of<M>::value;

template <class... M>
struct ModelList {
  static constexpr int size = sizeof...(M);
  static constexpr bool any_stress = (M::has_stress || ...);  // then the momentum pass takes the tensor form
  static constexpr bool any_modes = ((stress_modes_v<M> > 0) || ...);  // per-mode stresses (PTT)
  static constexpr bool any_single_stress = ((M::has_stress && stress_modes_v<M> == 0) || ...);  // one tau
  static constexpr bool any_solid = (solid_v<M> || ...);  // solids (alone, or beside a Newtonian fluid)
  static constexpr bool all_solid = (solid_v<M> && ...);
  static constexpr bool any_fluid = (!solid_v<M> || ...);  // fluids
  // Whether model `name` is in the list, and its index (-1 if not).
  static int index(const std::string& name) {
    int k = 0, found = -1;
    ((found = found < 0 && name == M::name ? k : found, ++k), ...);
    return found;
  }
  // f(model) for every model of the list, in order.
  template <class F>
  static void visit_all(F&& f) {
    (f(M{}), ...);
  }
  // f(model) with a value of the model type at index k.
  template <class F>
  static void visit(int k, F&& f) {
    int i = 0;
    ((i++ == k ? f(M{}) : void()), ...);
  }
};

// The models a deck may name in `materials[].model` (one line per model).
using MaterialModels = ModelList<Newtonian, Ptt, JohnsonCook>;

// The deck's materials, in order, into `table` (each with its index in the
// configuration's model list and its model's own parameters); returns the
// largest number of stress columns among them (modes and a plateau; 0: none).
template <class Models>
int add_materials(const RunParameters& deck, MaterialTable& table) {
  int modes = 0;
  for (const MaterialSpec& m : deck.material_list()) {
    Material mat{material_eos(m), m.viscosity, m.rho0 * m.viscosity, std::max(0, Models::index(m.model)), {}, {}};
    Models::visit(mat.model, [&](auto model) {
      if constexpr (stress_modes_v<decltype(model)> > 0) decltype(model)::configure(m, mat);
      if constexpr (solid_v<decltype(model)>) decltype(model)::configure(m, mat, deck.dx), mat.is_solid = true;
    });
    modes = std::max(modes, mat.modes.columns());
    table.add(mat);
  }
  return modes;
}

}  // namespace sph
