// Every material model a deck may name, and model lists as compile-time sets.
#pragma once
#include <string>
#include <type_traits>

#include "materials/newtonian.h"

namespace sph {

template <class... M>
struct ModelList {
  static constexpr int size = sizeof...(M);
  static constexpr bool any_stress = (M::has_stress || ...);  // then the momentum pass takes the tensor form
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
using MaterialModels = ModelList<Newtonian>;

}  // namespace sph
