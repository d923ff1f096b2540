// The tests' tiny pipe with open ends (test_open_boundaries.cpp, test_column_outlet.cpp): its deck and particles,
// and the fluid of a frame.
#pragma once
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deck.h"
#include "test_files.h"

namespace testpipe {

using nlohmann::json;
namespace fs = std::filesystem;

// A pipe of radius R = 3 dx and length 10 dx along x, walls of 3 layers of
// boundary particles on the same Cartesian lattice, Re = 2 U R / nu = 0.6.
struct TinyPipe {
  double dx = 1e-3, R = 3e-3, L = 10e-3, U = 0.01, nu = 1e-4, rho0 = 1000.0, c0 = 1.0;
  int layers = 3;
  int fluid = 0;
  bool wall_points = false;  // the walls' particles carry their nearest points of the cylinder r = R
  double opening = -1.0;     // >= 0: no inlet; a pressure opening at x = 0 holding this pressure (Pa) feeds the pipe

  json deck(const fs::path& dir, double t_end) {
    testfiles::ParticleRows p;
    p.dim = 3;
    const int nr = static_cast<int>(std::lround(R / dx)) + layers, nx = static_cast<int>(std::lround(L / dx));
    for (int i = -layers - 2; i < nx + layers + 2; ++i)
      for (int j = -nr; j < nr; ++j)
        for (int k = -nr; k < nr; ++k) {
          const double x = (i + 0.5) * dx, y = (j + 0.5) * dx, z = (k + 0.5) * dx, r = std::hypot(y, z);
          const bool is_fluid = r < R && x > (opening >= 0.0 ? -layers * dx : 0.0) && x < L + layers * dx;
          const bool is_wall = r >= R && r < R + layers * dx;
          if (!is_fluid && !is_wall) continue;
          fluid += is_fluid;
          p.add({x, y, z}, {0.0, 0.0, 0.0}, rho0 * dx * dx * dx, rho0, is_wall ? 1 : 0);
          if (wall_points) {
            const double nan = std::nan("");
            const std::vector<double> w = is_wall ? std::vector<double>{x, R * y / r, R * z / r}
                                                  : std::vector<double>{nan, nan, nan};
            p.wall_point.insert(p.wall_point.end(), w.begin(), w.end());
          }
        }
    p.write(dir / "particles.h5");
    json deck = {{"dimension", 3},
            {"particles_file", "particles.h5"},
            {"physics", {"morris_viscosity"}},
            {"rho0", rho0},
            {"c0", c0},
            {"v_max", 2.5 * U},
            {"viscosity", nu},
            {"h", 1.3 * dx},
            {"dx", dx},
            {"inlets",
             {{{"name", "feed"}, {"center", {0.0, 0.0, 0.0}}, {"normal", {1.0, 0.0, 0.0}}, {"radius", R},
               {"velocity", U}, {"profile", "parabolic"}, {"pressure", "extrapolated"}}}},
            {"outlets",
             {{{"name", "drain"}, {"center", {L, 0.0, 0.0}}, {"normal", {1.0, 0.0, 0.0}}, {"radius", R},
               {"pressure", 0.0}}}},
            {"t_end", t_end},
            {"threads", 1},
            {"output", {{"file", "out.h5"}, {"frame_interval", t_end / 6}, {"series_interval", t_end / 20}}}};
    if (opening >= 0.0) {
      deck.erase("inlets");
      deck["outlets"][0]["backflow"] = true;
      deck["outlets"].push_back({{"name", "feed"}, {"center", {0.0, 0.0, 0.0}}, {"normal", {-1.0, 0.0, 0.0}},
                                 {"radius", R}, {"pressure", opening}, {"backflow", true}});
    }
    return deck;
  }
  // The inlet's lattice columns (plane_patch.h): offsets ((i + 1/2) dx - R, (j + 1/2) dx - R) inside R.
  template <class F>
  void for_each_column(F&& f) const {
    const int n = static_cast<int>(std::lround(2.0 * R / dx));
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double a = (i + 0.5) * dx - R, b = (j + 0.5) * dx - R, r2 = a * a + b * b;
        if (r2 < R * R) f(1.0 - r2 / (R * R));  // the parabolic shape, eq. OB1
      }
  }
  double column_shape_sum() const {
    double sum = 0.0;
    for_each_column([&](double f) { sum += f; });
    return sum;
  }
  // Volume of the whole particles that cross the patch when column j has moved scale f_j t, m^3.
  double lattice_volume(double scale_t) const {
    double count = 0.0;
    for_each_column([&](double f) { count += std::floor(scale_t * f / dx + 0.5); });
    return count * dx * dx * dx;
  }
};

struct FluidState {
  double count = 0.0, mean_rho = 0.0;
};
inline FluidState fluid_of_frame(const fs::path& out, int frame) {
  const std::string g = "/frames/" + std::to_string(frame);
  const auto kind = testfiles::read_doubles(out, g + "/kind");
  const auto rho = testfiles::read_doubles(out, g + "/densities");
  FluidState s;
  for (std::size_t i = 0; i < kind.size(); ++i)
    if (kind[i] == 0) s.count += 1.0, s.mean_rho += rho[i];
  s.mean_rho /= s.count;
  return s;
}

// Why the deck j is rejected (InputError's message), or "" if it is accepted.
inline std::string rejection(const json& j, const fs::path& dir) {
  try {
    sph::parse_deck(j, dir.string());
  } catch (const sph::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace testpipe
