// The deck's rigid grains (parameters.h GrainSpec, grains.h): the `grains` list.
#include <cmath>
#include <set>
#include <string>

#include "deck.h"
#include "deck_json.h"
#include "physics_terms.h"

namespace sph {

using namespace deck_json;

void parse_grains(const json& j, RunParameters& d) {
  if (!j.is_array()) fail("'grains' must be a list");
  if (!j.empty() && d.dimension != 3) fail("'grains' act in 3D only (dimension = " + std::to_string(d.dimension) + ")");
  // A resumed run (t_start, step_start) builds each grain from its particles' positions as any run does (its body
  // frame, the principal one of those positions, is where its orientation starts again); the deck gives its
  // velocity and angular velocity at that time (the Python layer's resume.grain_motion).
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const json& e = j[i];
    const std::string path = "grains[" + std::to_string(i) + "]";
    check_keys(e, path, {"name", "density", "velocity", "angular_velocity", "body_force", "contact_radius"});
    GrainSpec s;
    s.name = unique_name(e, path, seen);
    s.density = positive(e, path, "density");
    auto three = [&](const char* key, const std::vector<double>& fallback) {
      return e.contains(key) ? vector_of(e[key], where(path, key), 3) : fallback;
    };
    const std::vector<double> zero(3, 0.0);
    s.velocity = three("velocity", zero);
    s.angular_velocity = three("angular_velocity", zero);
    s.body_force = three("body_force", (d.terms & term::body_force) ? d.body_force : zero);
    if (e.contains("contact_radius")) s.contact_radius = positive(e, path, "contact_radius");
    d.grains.push_back(s);
  }
}

void parse_grain_contact(const json& j, RunParameters& d) {
  check_keys(j, "grain_contact", {"stiffness", "restitution", "walls", "solid_stiffness"});
  if (d.grains.empty()) fail("'grain_contact' needs 'grains'");
  if (j.contains("solid_stiffness")) d.grain_contact.solid_stiffness = positive(j, "grain_contact", "solid_stiffness");
  if (!j.contains("stiffness")) {  // the grains touch the solids only (eq. G8)
    if (!j.contains("solid_stiffness")) fail("'grain_contact' needs 'stiffness' or 'solid_stiffness'");
    if (j.contains("restitution") || j.contains("walls"))
      fail("'grain_contact.restitution' and 'grain_contact.walls' need 'grain_contact.stiffness'");
    return;
  }
  d.grain_contact.stiffness = positive(j, "grain_contact", "stiffness");
  if (j.contains("restitution")) {
    const double e = positive(j, "grain_contact", "restitution");
    if (e > 1.0) fail("'grain_contact.restitution' must be in (0, 1] (got " + std::to_string(e) + ")");
    d.grain_contact.restitution = e;
  }
  if (!j.contains("walls")) return;
  if (!j["walls"].is_array()) fail("'grain_contact.walls' must be a list of planes {point, normal}");
  if (d.dimension != 3) fail("'grain_contact.walls' act in 3D only");
  for (std::size_t i = 0; i < j["walls"].size(); ++i) {  // eq. G7's planes
    const json& w = j["walls"][i];
    const std::string path = "grain_contact.walls[" + std::to_string(i) + "]";
    check_keys(w, path, {"point", "normal"});
    if (!w.contains("point") || !w.contains("normal")) fail("'" + path + "' needs 'point' and 'normal'");
    const std::vector<double> p = vector_of(w["point"], where(path, "point"), 3);
    std::vector<double> n = vector_of(w["normal"], where(path, "normal"), 3);
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(length > 0.0)) fail("'" + path + ".normal' must not be zero");
    d.grain_contact.walls.push_back({p[0], p[1], p[2], n[0] / length, n[1] / length, n[2] / length});
  }
}

}  // namespace sph
