// Helpers for reading deck JSON: every error names the key and what is allowed.
#pragma once
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deck.h"

namespace sph {
namespace deck_json {

using nlohmann::json;


inline std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

inline std::string where(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

[[noreturn]] inline void fail(const std::string& msg) { throw InputError(msg); }

inline void check_keys(const json& j, const std::string& path, const std::vector<std::string>& allowed) {
  if (!j.is_object()) fail("'" + (path.empty() ? std::string("deck") : path) + "' must be a JSON object");
  for (const auto& item : j.items())
    if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
      fail("unknown key '" + where(path, item.key()) + "'; allowed keys: " + join(allowed));
}

inline const json& need(const json& j, const std::string& path, const std::string& key) {
  if (!j.contains(key)) fail("missing key '" + where(path, key) + "'");
  return j.at(key);
}

inline double number(const json& v, const std::string& name) {
  if (!v.is_number()) fail("'" + name + "' must be a number, got " + v.dump());
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail("'" + name + "' must be finite");
  return x;
}

// A cavitation floor of the pressure (eos.h), Pa: finite and below the rest pressure p_B.
inline double min_pressure(const json& v, const std::string& name, double background_pressure) {
  const double x = number(v, name);
  if (!(x < background_pressure))
    fail("'" + name + "' = " + std::to_string(x) + " Pa must lie below the rest pressure (background_pressure = " +
         std::to_string(background_pressure) + " Pa)");
  return x;
}

inline double positive(const json& j, const std::string& path, const std::string& key) {
  const double x = number(need(j, path, key), where(path, key));
  if (!(x > 0)) fail("'" + where(path, key) + "' must be > 0, got " + std::to_string(x));
  return x;
}

inline double non_negative(const json& j, const std::string& path, const std::string& key, double fallback) {
  if (!j.contains(key)) return fallback;
  const double x = number(j.at(key), where(path, key));
  if (x < 0) fail("'" + where(path, key) + "' must be >= 0, got " + std::to_string(x));
  return x;
}

inline std::string text(const json& v, const std::string& name) {
  if (!v.is_string() || v.get<std::string>().empty()) fail("'" + name + "' must be a non-empty string");
  return v.get<std::string>();
}

inline std::vector<double> vector_of(const json& v, const std::string& name, std::size_t size) {
  if (!v.is_array() || v.size() != size)
    fail("'" + name + "' must be a list of " + std::to_string(size) + " numbers, got " + v.dump());
  std::vector<double> out;
  for (std::size_t i = 0; i < size; ++i) out.push_back(number(v[i], name + "[" + std::to_string(i) + "]"));
  return out;
}

inline std::string unique_name(const json& j, const std::string& path, std::set<std::string>& seen) {
  const std::string name = text(need(j, path, "name"), where(path, "name"));
  if (name.find_first_of("/ \t") != std::string::npos) fail("'" + where(path, "name") + "' must not contain '/' or spaces");
  if (!seen.insert(name).second) fail("duplicate name '" + name + "' in '" + path + "'");
  return name;
}

}  // namespace deck_json
}  // namespace sph
