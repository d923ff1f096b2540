// The deck's `lees_edwards` object (parameters.h: LeesEdwardsSpec).
#include <algorithm>
#include <cmath>
#include <string>

#include "deck.h"
#include "deck_json.h"

namespace sph {

using namespace deck_json;

// {"shear_rate": 1/s} (steady) or {"amplitude": -, "omega": rad/s} (oscillatory);
// axes 0 (shear) and 1 (gradient) must be periodic.
void parse_lees_edwards(const json& j, RunParameters& d) {
  const std::string path = "lees_edwards";
  if (!j.is_object()) fail("'lees_edwards' must be a JSON object: {\"shear_rate\": 1/s} or {\"amplitude\": -, \"omega\": rad/s}");
  check_keys(j, path, {"shear_rate", "amplitude", "omega", "subtract_mean_stress"});
  LeesEdwardsSpec& le = d.lees_edwards;
  le.on = true;
  if (j.contains("subtract_mean_stress")) {
    if (!j["subtract_mean_stress"].is_boolean()) fail("'lees_edwards.subtract_mean_stress' must be true or false");
    le.subtract_mean_stress = j["subtract_mean_stress"].get<bool>();
  }
  const bool steady = j.contains("shear_rate"), oscillatory = j.contains("amplitude") || j.contains("omega");
  if (steady == oscillatory)
    fail("'lees_edwards' takes either 'shear_rate' (steady shear, 1/s) or 'amplitude' and 'omega' (oscillatory "
         "strain gamma_A sin(omega t)), not both and not neither");
  if (steady) {
    le.shear_rate = number(j["shear_rate"], where(path, "shear_rate"));
  } else {
    le.amplitude = number(need(j, path, "amplitude"), where(path, "amplitude"));
    le.omega = positive(j, path, "omega");
  }
  for (int axis : {0, 1})
    if (std::find(d.periodic_axes.begin(), d.periodic_axes.end(), axis) == d.periodic_axes.end())
      fail("'lees_edwards' shears along axis 0 with gradient along axis 1: 'periodic.axes' must list axes 0 and 1");
  const std::size_t x = std::find(d.periodic_axes.begin(), d.periodic_axes.end(), 0) - d.periodic_axes.begin();
  // Two cells of the neighbour search (1.1 h each) along x: a sheared row then never wraps more than twice.
  if (!(d.periodic_hi[x] - d.periodic_lo[x] >= 2.2 * d.h))
    fail("'lees_edwards' needs the periodic box along x (axis 0) at least 2.2 h long");
}

}  // namespace sph
