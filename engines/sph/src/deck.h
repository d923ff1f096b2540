// The run deck (JSON): every setting of a run in SI units, validated on load into the plain parameter structs of
// parameters.h.
#pragma once
#include <set>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "material_keys.h"
#include "parameters.h"

namespace sph {

// Parse and validate a deck; throws InputError.
RunParameters parse_deck(const nlohmann::json& j, const std::string& deck_dir);
RunParameters load_deck(const std::string& path);
// The `materials` list into d.materials (deck_materials.cpp; d.terms and d.v_max must be parsed).
void parse_materials(const nlohmann::json& j, RunParameters& d);
// The `lees_edwards` object into d.lees_edwards (deck_lees_edwards.cpp; d.periodic_* must be parsed).
void parse_lees_edwards(const nlohmann::json& j, RunParameters& d);
// The `inlets` and `outlets` lists into d.inlets, d.outlets (deck_open_boundaries.cpp; d.dx, d.h and the materials
// must be parsed), and one plane patch of them or of the flow planes (its name must be new in `seen`).
void parse_open_boundaries(const nlohmann::json& j, RunParameters& d);
// The `impactors` list into d.impactors (deck_impactors.cpp; d.dimension and d.dx must be parsed).
void parse_impactors(const nlohmann::json& j, RunParameters& d);
// The `grains` list into d.grains (deck_grains.cpp; d.dimension, d.terms, d.body_force, the time and the Lees-Edwards
// cell must be parsed).
void parse_grains(const nlohmann::json& j, RunParameters& d);
void parse_grain_contact(const nlohmann::json& j, RunParameters& d);  // after parse_grains
PlanePatch parse_patch(const nlohmann::json& e, const std::string& path, int dim, std::set<std::string>& seen);

}  // namespace sph
