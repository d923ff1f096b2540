// The deck keys of a Johnson-Cook solid (materials/johnson_cook_material.h; engines/sph/README.md, `materials`),
// read through MaterialKeys into MaterialSpec::solid. SI units; every error names its key.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "material_keys.h"
#include "materials/solid_parameters.h"
#include "parameters.h"

namespace sph {

// Johnson-Cook damage (eq. 14), optional: failure.d1 .. d5 (-), with the strength's rate form and reference rate.
inline void parse_failure(const MaterialKeys& k, SolidParameters& s) {
  std::vector<std::string> allowed = {"d1", "d2", "d3", "d4", "d5"};
  const auto f = k.object("failure", allowed);
  if (!f) return;
  s.fails = true;
  s.failure = {f->number("d1"), f->number("d2"), f->number("d3"), f->number_or("d4", 0.0), f->number_or("d5", 0.0),
               s.strength.reference_rate, s.strength.rate_form};
}

// Monaghan's artificial stress, optional: artificial_stress.epsilon (-, 0.3) and exponent (n, 4).
inline void parse_artificial_stress(const MaterialKeys& k, SolidParameters& s) {
  std::vector<std::string> allowed = {"epsilon", "exponent"};
  const auto a = k.object("artificial_stress", allowed);
  if (!a) return;
  s.artificial_stress = a->non_negative_or("epsilon", 0.3);
  const double n = a->positive_or("exponent", 4.0);
  if (n != std::floor(n) || n > 8) a->fail("exponent", "must be a whole number from 1 to 8");
  s.artificial_stress_exponent = static_cast<int>(n);
}

inline void parse_johnson_cook(const MaterialKeys& k, MaterialSpec& m) {
  SolidParameters& s = m.solid;
  s.shear_modulus = k.positive("shear_modulus");
  const bool linear = k.text_or("eos", "linear", {"linear", "mie_gruneisen"}) == "linear";
  for (const char* key : {"bulk_modulus", "bulk_sound_speed", "hugoniot_slope", "gruneisen"}) {
    const bool own = linear == (std::string(key) == "bulk_modulus");
    if (!own && k.has(key)) k.fail(key, std::string("is not a key of eos '") + (linear ? "linear" : "mie_gruneisen") + "'");
  }
  if (linear) {
    s.eos = SolidEos::linear, s.linear = {m.rho0, k.positive("bulk_modulus")};
  } else {
    s.eos = SolidEos::mie_gruneisen;
    s.shock = {m.rho0, k.positive("bulk_sound_speed"), k.non_negative("hugoniot_slope"), k.non_negative("gruneisen")};
  }
  s.plastic = k.has("yield_stress");
  const char* strength_keys[] = {"hardening_modulus", "hardening_exponent", "rate_sensitivity", "thermal_exponent",
                                 "reference_rate", "rate_form", "room_temperature", "melting_temperature", "failure"};
  if (!s.plastic) {
    for (const char* key : strength_keys)
      if (k.has(key)) k.fail(key, "is given but 'yield_stress' is not: an elastic solid has no strength or failure model");
  } else {
    solid::JohnsonCookStrength& j = s.strength;
    j.A = k.positive("yield_stress");
    j.B = k.non_negative_or("hardening_modulus", 0.0);
    j.n = k.positive_or("hardening_exponent", 1.0);
    j.C = k.non_negative_or("rate_sensitivity", 0.0);
    j.m = k.positive_or("thermal_exponent", 1.0);
    j.reference_rate = k.positive_or("reference_rate", 1.0);
    j.rate_form = k.text_or("rate_form", "power", {"power", "log"}) == "log" ? solid::RateForm::log : solid::RateForm::power;
    j.room_temperature = k.positive_or("room_temperature", 293.0);
    j.melting_temperature = k.positive("melting_temperature");
    if (!(j.melting_temperature > j.room_temperature))
      k.fail("melting_temperature", "= " + std::to_string(j.melting_temperature) + " K must be above room_temperature = " +
                                        std::to_string(j.room_temperature) + " K");
  }
  s.heat = {m.rho0, 0.0, k.non_negative_or("heat_fraction", 0.0)};
  if (s.heat.heat_fraction > 1.0) k.fail("heat_fraction", "must be <= 1 (the share of plastic work turned into heat)");
  if (s.heat.heat_fraction > 0.0) s.heat.heat_capacity = k.positive("heat_capacity");
  else if (k.has("heat_capacity")) k.fail("heat_capacity", "is given but heat_fraction is 0 (isothermal): give both or neither");
  parse_failure(k, s);
  parse_artificial_stress(k, s);
  s.corrected_momentum = k.text_or("momentum", "plain", {"plain", "corrected"}) == "corrected";  // eq. KC1
  s.smoothing = k.non_negative_or("smoothing", 0.0);  // eq. SS1's delta (solid_smoothing.h)
  m.c0 = s.wave_speed();
}

}  // namespace sph
