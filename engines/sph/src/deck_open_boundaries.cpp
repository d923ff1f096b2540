// The deck's open boundaries (parameters.h InletSpec, OutletSpec): the `inlets` and `outlets` lists, and the plane
// patches they and the flow planes are made of.
#include <cmath>
#include <set>
#include <string>

#include "deck.h"
#include "deck_json.h"

namespace sph {

using namespace deck_json;

PlanePatch parse_patch(const json& e, const std::string& path, int dim, std::set<std::string>& seen) {
  PlanePatch f;
  f.name = unique_name(e, path, seen);
  f.center = vector_of(need(e, path, "center"), path + ".center", dim);
  f.normal = vector_of(need(e, path, "normal"), path + ".normal", dim);
  double norm = 0;
  for (double x : f.normal) norm += x * x;
  if (!(norm > 0)) fail("'" + path + ".normal' must not be zero");
  for (double& x : f.normal) x /= std::sqrt(norm);
  const bool disc = e.contains("radius"), rect = e.contains("half_extents");
  if (disc == rect) fail("'" + path + "' needs exactly one of 'radius' (disc) or 'half_extents' (rectangle)");
  if (disc) {
    f.radius = positive(e, path, "radius");
    if (e.contains("u")) fail("'" + path + ".u' is only for rectangles (with 'half_extents')");
    return f;
  }
  f.half_extents = vector_of(e["half_extents"], path + ".half_extents", dim == 3 ? 2 : 1);
  for (double x : f.half_extents)
    if (!(x > 0)) fail("'" + path + ".half_extents' must be > 0");
  if (dim == 2) {
    if (e.contains("u")) fail("'" + path + ".u' is not used in 2D (the segment is normal to 'normal')");
    return f;
  }
  f.u = vector_of(need(e, path, "u"), path + ".u", 3);
  double along = 0, uu = 0;
  for (int k = 0; k < 3; ++k) along += f.u[k] * f.normal[k], uu += f.u[k] * f.u[k];
  if (!(uu - along * along > 1e-12 * uu)) fail("'" + path + ".u' must not be parallel to 'normal'");
  return f;
}

namespace {

int buffer_layers(const json& e, const std::string& path, const RunParameters& d) {
  int layers = 3;
  if (e.contains("layers")) {
    if (!e["layers"].is_number_integer() || e["layers"].get<int>() < 1)
      fail("'" + path + ".layers' must be a positive integer, got " + e["layers"].dump());
    layers = e["layers"].get<int>();
  }
  if (layers * d.dx < 2.0 * d.h)
    fail("'" + path + ".layers' x dx must cover the kernel support 2h (" + std::to_string(layers) + " layers of " +
         std::to_string(d.dx) + " m < " + std::to_string(2.0 * d.h) + " m)");
  return layers;
}

// An inlet's profile, inner_radius, pressure and material (parameters.h InletSpec).
void parse_inlet_options(const json& e, const std::string& path, const RunParameters& d, InletSpec& in) {
  if (e.contains("profile")) in.profile = text(e["profile"], path + ".profile");
  const double v = in.velocity;
  double peak = v;  // largest speed of the profile, m/s
  if (in.profile == "parabolic") {
    peak = in.patch.radius > 0.0 && d.dimension == 3 ? 2.0 * v : 1.5 * v;
  } else if (in.profile == "annular") {
    if (d.dimension != 3 || !(in.patch.radius > 0.0))
      fail("'" + path + ".profile' = \"annular\" needs a disc patch (radius) in 3D");
    in.inner_radius = positive(e, path, "inner_radius");
    if (!(in.inner_radius < in.patch.radius))
      fail("'" + path + ".inner_radius' must be below 'radius' (" + std::to_string(in.patch.radius) + " m)");
    peak = 2.0 * v;  // the annulus profile peaks between 1.5 (thin gap) and 2 (pipe) times its mean
  } else if (in.profile != "plug") {
    fail("'" + path + ".profile' must be one of plug, parabolic, annular; got \"" + in.profile + "\"");
  }
  if (e.contains("inner_radius") && in.profile != "annular")
    fail("'" + path + ".inner_radius' is only for profile = \"annular\"");
  if (in.profile == "plug" && v > d.v_max)
    fail("'" + path + ".velocity' = " + std::to_string(v) + " m/s exceeds v_max");
  if (peak > d.v_max)
    fail("'" + path + ".velocity' = " + std::to_string(v) + " m/s gives a peak speed " + std::to_string(peak) +
         " m/s above v_max");
  if (e.contains("pressure")) {
    const std::string mode = text(e["pressure"], path + ".pressure");
    if (mode != "extrapolated" && mode != "summation")
      fail("'" + path + ".pressure' must be \"extrapolated\" or \"summation\"; got \"" + mode + "\"");
    in.extrapolated = mode == "extrapolated";
  }
  if (e.contains("ramp_time")) {
    in.ramp_time = number(e["ramp_time"], path + ".ramp_time");
    if (!(in.ramp_time >= 0.0)) fail("'" + path + ".ramp_time' must be >= 0 s");
  }
  if (e.contains("material")) {
    const std::string name = text(e["material"], path + ".material");
    const auto list = d.material_list();
    std::vector<std::string> names;
    for (const auto& m : list) names.push_back(m.name);
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) fail("'" + path + ".material' = \"" + name + "\" is not a material; materials: " + join(names));
    in.material = static_cast<int>(it - names.begin());
  }
}

// A column outlet's keys (outlet_buffer.h, eq. OB5): column_length > 0 (m), column_loss >= 0 (-), column_area > 0
// (m^2; default the patch's: an annular passage's outlet patch is a disc).
void parse_column(const json& e, const std::string& path, const RunParameters& d, OutletSpec& out) {
  for (const char* key : {"column_loss", "column_area"})
    if (e.contains(key) && !e.contains("column_length"))
      fail("'" + path + "." + key + "' needs '" + path + ".column_length': it is the column's");
  if (!e.contains("column_length")) return;
  out.column_length = positive(e, path, "column_length");
  out.column_loss = non_negative(e, path, "column_loss", 0.0);
  if (e.contains("column_area")) out.column_area = positive(e, path, "column_area");
  if (!out.pressure)
    fail("'" + path + ".column_length' needs '" + path + ".pressure': the column runs from the patch to that pressure");
  if (d.material_list().size() > 1)
    fail("'" + path + ".column_length' needs a deck of one material: the column holds the fluid's mean density");
}

}  // namespace

void parse_open_boundaries(const json& j, RunParameters& d) {
  std::set<std::string> seen;
  for (const char* key : {"inlets", "outlets"}) {
    if (!j.contains(key)) continue;
    const bool inlet = std::string(key) == "inlets";
    if (!j[key].is_array()) fail("'" + std::string(key) + "' must be a list");
    for (std::size_t i = 0; i < j[key].size(); ++i) {
      const std::string path = std::string(key) + "[" + std::to_string(i) + "]";
      const auto& e = j[key][i];
      if (inlet)
        check_keys(e, path, {"name", "center", "normal", "radius", "u", "half_extents", "velocity", "layers", "profile",
                             "inner_radius", "pressure", "material", "ramp_time"});
      else check_keys(e, path, {"name", "center", "normal", "radius", "u", "half_extents", "layers", "pressure", "backflow",
                                 "column_length", "column_loss", "column_area"});
      PlanePatch patch = parse_patch(e, path, d.dimension, seen);
      const int layers = buffer_layers(e, path, d);
      if (!inlet) {
        OutletSpec out{std::move(patch), layers, std::nullopt};
        if (e.contains("pressure")) {
          out.pressure = number(e["pressure"], path + ".pressure");
          for (const auto& m : d.material_list())  // eq. 6 must give a density for it
            if (!(1.0 + m.gamma * (*out.pressure - m.background_pressure) / (m.rho0 * m.c0 * m.c0) > 0.0))
              fail("'" + path + ".pressure' = " + std::to_string(*out.pressure) +
                   " Pa is below the lowest pressure of material '" + m.name + "' (eq. 6)");
        }
        if (e.contains("backflow")) {
          if (!e["backflow"].is_boolean()) fail("'" + path + ".backflow' must be true or false");
          out.backflow = e["backflow"].get<bool>();
          if (out.backflow && !out.pressure)
            fail("'" + path + ".backflow' needs '" + path + ".pressure': the fluid that enters takes the held pressure");
        }
        parse_column(e, path, d, out);
        d.outlets.push_back(std::move(out));
        continue;
      }
      InletSpec in{std::move(patch), positive(e, path, "velocity"), layers};
      parse_inlet_options(e, path, d, in);
      d.inlets.push_back(std::move(in));
    }
  }
}

}  // namespace sph
