// The deck's rigid impactors (parameters.h ImpactorSpec, impactors.h): the `impactors` list.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <set>
#include <string>

#include "deck.h"
#include "deck_json.h"
#include "vec.h"

namespace sph {

using namespace deck_json;

namespace {

// A 3 x 3 inertia tensor (kg m^2) given as three rows: symmetric, with positive principal moments that a body can
// have (each at most the sum of the other two).
std::vector<double> inertia_tensor(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) fail("'" + path + "' must be a list of 3 rows of 3 numbers, got " + v.dump());
  Mat<3> I;
  std::vector<double> out;
  for (int r = 0; r < 3; ++r) {
    const auto row = vector_of(v[r], path + "[" + std::to_string(r) + "]", 3);
    for (int c = 0; c < 3; ++c) I(r, c) = row[c], out.push_back(row[c]);
  }
  const double scale = I.cwiseAbs().maxCoeff();
  if (!((I - I.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale)) fail("'" + path + "' must be symmetric");
  const Vec<3> m = Eigen::SelfAdjointEigenSolver<Mat<3>>(I).eigenvalues();
  if (!(m(0) > 0.0) || m(2) > (m(0) + m(1)) * (1.0 + 1e-9))
    fail("'" + path + "' is not the inertia of a body: principal moments " + std::to_string(m(0)) + ", " +
         std::to_string(m(1)) + ", " + std::to_string(m(2)) + " kg m^2 must be positive, each at most the sum of the "
         "other two");
  return out;
}

std::vector<double> vector_or_zero(const json& e, const std::string& path, const std::string& key) {
  return e.contains(key) ? vector_of(e[key], where(path, key), 3) : std::vector<double>(3, 0.0);
}

ImpactorSpec parse_impactor(const json& e, const std::string& path, std::set<std::string>& seen) {
  check_keys(e, path, {"name", "mass", "inertia", "centre", "velocity", "angular_velocity", "spheres", "stiffness",
                       "kinematic"});
  ImpactorSpec s;
  s.name = unique_name(e, path, seen);
  s.mass = positive(e, path, "mass");
  s.inertia = inertia_tensor(need(e, path, "inertia"), where(path, "inertia"));
  s.centre = vector_of(need(e, path, "centre"), where(path, "centre"), 3);
  s.velocity = vector_or_zero(e, path, "velocity");
  s.angular_velocity = vector_or_zero(e, path, "angular_velocity");
  s.stiffness = positive(e, path, "stiffness");
  if (e.contains("kinematic")) {
    if (!e["kinematic"].is_boolean()) fail("'" + where(path, "kinematic") + "' must be true or false");
    s.kinematic = e["kinematic"].get<bool>();
  }
  const json& spheres = need(e, path, "spheres");
  if (!spheres.is_array() || spheres.empty()) fail("'" + where(path, "spheres") + "' must be a non-empty list");
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    const std::string at = where(path, "spheres") + "[" + std::to_string(k) + "]";
    auto sphere = vector_of(spheres[k], at, 4);
    if (!(sphere[3] > 0.0)) fail("'" + at + "' radius (its 4th number) must be > 0");
    s.spheres.push_back(sphere);
  }
  return s;
}

}  // namespace

void parse_impactors(const json& j, RunParameters& d) {
  if (!j.is_array()) fail("'impactors' must be a list");
  if (!j.empty() && d.dimension != 3) fail("'impactors' act in 3D only (dimension = " + std::to_string(d.dimension) + ")");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < j.size(); ++i) d.impactors.push_back(parse_impactor(j[i], "impactors[" + std::to_string(i) + "]", seen));
}

}  // namespace sph
