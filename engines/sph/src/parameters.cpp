#include "parameters.h"

#include <algorithm>
#include <string>
#include <vector>

#include "physics_terms.h"

namespace sph {

std::string RunParameters::terms_string() const {
  std::string out = "continuity,tait_eos,pressure_gradient";
  for (const auto& t : term::optional)
    if (terms & t.bit) out += std::string(",") + t.name;
  if (smagorinsky_cs > 0) out += " with eddy_viscosity";
  return viscosity_correction ? out + " with viscosity_correction" : out;
}

bool RunParameters::inlets_extrapolated() const {
  return !inlets.empty() && std::all_of(inlets.begin(), inlets.end(), [](const InletSpec& in) { return in.extrapolated; });
}

std::vector<MaterialSpec> RunParameters::material_list() const {
  if (!materials.empty()) return materials;
  MaterialSpec m;
  m.name = "fluid", m.model = "newtonian";
  m.rho0 = rho0, m.c0 = c0, m.gamma = gamma, m.background_pressure = background_pressure, m.viscosity = viscosity;
  m.min_pressure = min_pressure;
  return {m};
}

}  // namespace sph
