// The deck's `materials` list (parameters.h: MaterialSpec) and the keys a material model reads.
#include <set>
#include <string>
#include <vector>

#include "deck.h"
#include "deck_json.h"
#include "material_models.h"

namespace sph {

using namespace deck_json;

void parse_tait(const json& e, const std::string& path, MaterialSpec& m);

// The `materials` list: each {name, model, rho0, c0, gamma (7), background_pressure (0), <model keys>}.
void parse_materials(const json& j, RunParameters& d) {
  if (!j.is_array() || j.empty() || j.size() > 255) fail("'materials' must be a list of 1 to 255 materials");
  std::vector<std::string> models;
  MaterialModels::visit_all([&](auto model) { models.push_back(decltype(model)::name); });
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = "materials[" + std::to_string(i) + "]";
    const json& e = j[i];
    if (!e.is_object()) fail("'" + path + "' must be a JSON object");
    MaterialSpec m;
    m.name = unique_name(e, path, seen);
    m.model = text(need(e, path, "model"), where(path, "model"));
    const int index = MaterialModels::index(m.model);
    if (index < 0) fail("'" + where(path, "model") + "' = '" + m.model + "' is not a material model; known: " + join(models));
    std::vector<std::string> allowed = {"name", "model", "rho0", "c0", "gamma", "background_pressure", "eos",
                                        "min_pressure"};
    bool solid = false;
    MaterialModels::visit(index, [&](auto model) { solid = solid_v<decltype(model)>; });
    if (solid) allowed.resize(3);  // a solid's pressure and wave speed are its model's: no Tait keys
    MaterialModels::visit(index, [&](auto model) {
      for (const auto& k : decltype(model)::keys()) allowed.push_back(k);
    });
    check_keys(e, path, allowed);
    m.rho0 = positive(e, path, "rho0");
    if (!solid) parse_tait(e, path, m);
    const MaterialKeys keys(e, path, d.terms);
    MaterialModels::visit(index, [&](auto model) { decltype(model)::parse(keys, m); });
    if (m.c0 < 10.0 * d.v_max)
      fail((solid ? "the wave speed sqrt((K + 4G/3) / rho0) of '" + path + "' = " : "'" + where(path, "c0") + "' = ") +
           std::to_string(m.c0) + " m/s is too small for v_max = " + std::to_string(d.v_max) +
           " m/s; weakly compressible SPH needs c0 >= 10 v_max (density error < 1 %)");
    d.materials.push_back(m);
  }
  const MaterialSpec& first = d.materials.front();
  d.rho0 = first.rho0, d.c0 = first.c0, d.gamma = first.gamma, d.background_pressure = first.background_pressure;
  d.viscosity = first.viscosity;
}

// A fluid's Tait (or quadratic) equation of state: c0, gamma, eos, background_pressure, min_pressure.
void parse_tait(const json& e, const std::string& path, MaterialSpec& m) {
  m.c0 = positive(e, path, "c0");
  if (e.contains("gamma")) {
    m.gamma = number(e["gamma"], where(path, "gamma"));
    if (!(m.gamma >= 1)) fail("'" + where(path, "gamma") + "' must be >= 1, got " + std::to_string(m.gamma));
  }
  if (e.contains("eos")) {
    const std::string eos = text(e["eos"], where(path, "eos"));
    if (eos != "tait" && eos != "quadratic")
      fail("'" + where(path, "eos") + "' = '" + eos + "' is not an equation of state; known: tait, quadratic");
    m.quadratic_eos = eos == "quadratic";
    if (m.quadratic_eos && e.contains("gamma")) fail("'" + where(path, "gamma") + "' is a Tait key; 'eos' is 'quadratic'");
  }
  if (e.contains("background_pressure")) m.background_pressure = number(e["background_pressure"], where(path, "background_pressure"));
  if (e.contains("min_pressure")) m.min_pressure = min_pressure(e["min_pressure"], where(path, "min_pressure"), m.background_pressure);
}


bool MaterialKeys::has(const std::string& key) const { return j_.contains(key); }
double MaterialKeys::positive(const std::string& key) const { return deck_json::positive(j_, path_, key); }
double MaterialKeys::non_negative_or(const std::string& key, double fallback) const {
  return deck_json::non_negative(j_, path_, key, fallback);
}
double MaterialKeys::non_negative(const std::string& key) const {
  need(j_, path_, key);
  return deck_json::non_negative(j_, path_, key, 0.0);
}
double MaterialKeys::positive_or(const std::string& key, double fallback) const {
  return j_.contains(key) ? positive(key) : fallback;
}
double MaterialKeys::number(const std::string& key) const { return deck_json::number(need(j_, path_, key), where(path_, key)); }
double MaterialKeys::number_or(const std::string& key, double fallback) const {
  return j_.contains(key) ? number(key) : fallback;
}
std::string MaterialKeys::text_or(const std::string& key, const std::string& fallback,
                                  const std::vector<std::string>& allowed) const {
  if (!j_.contains(key)) return fallback;
  const std::string value = text(j_.at(key), where(path_, key));
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
    fail(key, "= '" + value + "' is not allowed; allowed: " + join(allowed));
  return value;
}
std::optional<MaterialKeys> MaterialKeys::object(const std::string& key, const std::vector<std::string>& allowed) const {
  if (!j_.contains(key)) return std::nullopt;
  check_keys(j_.at(key), where(path_, key), allowed);
  return MaterialKeys(j_.at(key), where(path_, key), terms_);
}
void MaterialKeys::fail(const std::string& key, const std::string& what) const {
  deck_json::fail("'" + where(path_, key) + "' " + what);
}
std::vector<MaterialKeys> MaterialKeys::objects(const std::string& key, std::size_t min_size, std::size_t max_size,
                                                const std::vector<std::string>& allowed) const {
  const json& list = need(j_, path_, key);
  const std::string name = where(path_, key);
  if (!list.is_array() || list.size() < min_size || list.size() > max_size)
    deck_json::fail("'" + name + "' must be a list of " + std::to_string(min_size) + " to " + std::to_string(max_size) + " objects");
  std::vector<MaterialKeys> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item = name + "[" + std::to_string(i) + "]";
    if (!list[i].is_object()) deck_json::fail("'" + item + "' must be a JSON object");
    check_keys(list[i], item, allowed);
    out.emplace_back(list[i], item, terms_);
  }
  return out;
}
double MaterialKeys::positive_with_term(const std::string& key, unsigned bit, const std::string& term) const {
  const bool on = terms_ & bit;
  if (on && !j_.contains(key)) deck_json::fail("physics term '" + term + "' is on but key '" + where(path_, key) + "' is missing");
  if (!on && j_.contains(key))
    deck_json::fail("key '" + where(path_, key) + "' is given but physics term '" + term + "' is not in 'physics'");
  return on ? positive(key) : 0.0;
}

}  // namespace sph
