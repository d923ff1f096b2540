// Two immiscible Newtonian layers of different density and viscosity between
// a fixed wall (y = 0) and a wall sliding at U (y = H), periodic along x:
// the steady two-layer Couette flow. The shear stress is the same in both
// layers, mu_1 du/dy = mu_2 du/dy, so the profile is piecewise linear with
// the interface speed U_i = U (h1/mu1) / (h1/mu1 + h2/mu2) at y = h1:
//   u(y) = U_i y / h1                          for y < h1
//   u(y) = U_i + (U - U_i) (y - h1) / h2       for y > h1.
// The pair viscosity across the interface is the harmonic mean (material.h).
#include <cmath>

#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "run.h"
#include "simulation.h"
#include "test_files.h"

using namespace sph;

namespace {

constexpr unsigned kTerms = term::morris_viscosity | term::several_materials;

}  // namespace

TEST(two_layer_couette_matches_piecewise_linear_profile) {
  const int columns = 8, rows = 20, layers = 3, rows_1 = 10;  // lower layer: rows 0..9
  const double dx = 1e-3, H = rows * dx, h1 = rows_1 * dx, h2 = H - h1, U = 0.05;
  const double rho_1 = 1000.0, rho_2 = 500.0, nu_1 = 0.01, nu_2 = 0.01;  // mu_1 = 10 Pa s, mu_2 = 5 Pa s
  RunParameters d;
  d.dimension = 2, d.terms = term::morris_viscosity;
  d.h = 1.3 * dx, d.dx = dx, d.v_max = U;
  d.materials.resize(2);
  for (int k = 0; k < 2; ++k) {
    MaterialSpec& m = d.materials[k];
    m.name = k ? "upper" : "lower", m.model = "newtonian", m.rho0 = k ? rho_2 : rho_1, m.c0 = 1.0;
    m.gamma = 7.0, m.background_pressure = 0.0, m.viscosity = k ? nu_2 : nu_1;
  }
  d.rho0 = rho_1, d.c0 = 1.0;
  d.periodic_axes = {0}, d.periodic_lo = {0.0}, d.periodic_hi = {columns * dx};
  Particles<2> P;
  P.resize(columns * (rows + 2 * layers));
  int k = 0;
  for (int i = 0; i < columns; ++i)
    for (int j = -layers; j < rows + layers; ++j, ++k) {
      const std::uint8_t mat = j < rows_1 ? 0 : 1;
      const double rho = mat == 0 ? rho_1 : rho_2;
      P.x[k] = {(i + 0.5) * dx, (j + 0.5) * dx};
      P.v[k] = {j >= rows ? U : 0.0, 0.0};
      P.rho[k] = rho, P.mass[k] = rho * dx * dx, P.id[k] = k, P.material[k] = mat;
      P.kind[k] = j < 0 || j >= rows ? Kind::boundary : Kind::fluid;
    }
  Simulation<2, kTerms> sim(d, P);
  const double mu_1 = rho_1 * nu_1, mu_2 = rho_2 * nu_2;
  const double u_i = U * (h1 / mu_1) / (h1 / mu_1 + h2 / mu_2);
  // Viscous time H^2/nu = 0.04 s; the slowest mode decays as exp(-pi^2 nu t / H^2): 0.06 s leaves < 1e-6.
  const double dt = 0.1 * d.h * d.h / std::max(nu_1, nu_2), t_end = 0.06;
  for (int s = 0; s * dt < t_end; ++s) CHECK(sim.step(dt, NoCrossings{}));
  CHECK(sim.check_stability().ok);
  const auto& Q = sim.particles();
  double worst = 0.0;
  for (std::size_t i = 0; i < Q.size(); ++i) {
    if (!Q.moves(i)) continue;
    const double y = Q.x[i][1];
    const double u = y < h1 ? u_i * y / h1 : u_i + (U - u_i) * (y - h1) / h2;
    worst = std::max(worst, std::abs(Q.v[i][0] - u) / U);
    CHECK(Q.material[i] == (Q.id[i] % (rows + 2 * layers) - layers < rows_1 ? 0 : 1));  // layers stay apart
  }
  std::fprintf(stderr, "  two-layer Couette: interface speed %.4g m/s (U = %.3g), worst |u - u_exact| / U = %.3g\n",
               u_i, U, worst);
  CHECK(worst < 0.02);
}

// The same flow as a deck with a `materials` list and the particle file's
// `material` dataset, through deck parsing, input, dispatch to the
// several-materials configuration and output; shorter, against the profile
// the Simulation above reaches at the same time.
TEST(two_material_deck_runs_through_the_executable_path) {
  const int columns = 8, rows = 20, layers = 3, rows_1 = 10;
  const double dx = 1e-3, U = 0.05, t_end = 0.01;
  const auto dir = testfiles::scratch("two_layers");
  testfiles::ParticleRows p;
  for (int i = 0; i < columns; ++i)
    for (int j = -layers; j < rows + layers; ++j) {
      const int mat = j < rows_1 ? 0 : 1;
      const double rho = mat == 0 ? 1000.0 : 500.0;
      p.add({(i + 0.5) * dx, (j + 0.5) * dx}, {j >= rows ? U : 0.0, 0.0}, rho * dx * dx, rho, j < 0 || j >= rows ? 1 : 0,
            mat);
    }
  p.write(dir / "particles.h5");
  nlohmann::json deck = nlohmann::json::parse(R"({
    "dimension": 2, "particles_file": "particles.h5", "physics": ["morris_viscosity"],
    "materials": [
      {"name": "lower", "model": "newtonian", "rho0": 1000, "c0": 1.0, "viscosity": 0.01},
      {"name": "upper", "model": "newtonian", "rho0": 500, "c0": 1.0, "viscosity": 0.01}],
    "v_max": 0.05, "h": 1.3e-3, "dx": 1e-3, "dt": 1.69e-5,
    "periodic": {"axes": [0], "lo": [0.0], "hi": [0.008]},
    "output": {"file": "out.h5", "frame_interval": 0.005}})");
  deck["t_end"] = t_end;
  testfiles::write_text(dir / "deck.json", deck.dump(2));
  CHECK(run_deck(load_deck((dir / "deck.json").string())) == 0);  // exit_ok
  const auto out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "ok");
  const auto v = testfiles::read_doubles(out, "/frames/2/velocities");
  const auto x = testfiles::read_doubles(out, "/frames/2/positions");
  const auto kind = testfiles::read_doubles(out, "/frames/2/kind");
  // The momentum has diffused into the upper layer but not yet through the lower one.
  double upper = 0.0, lower = 0.0;
  for (std::size_t i = 0; i < kind.size(); ++i) {
    if (kind[i] != 0) continue;
    (x[2 * i + 1] > rows_1 * dx ? upper : lower) += v[2 * i];
  }
  std::fprintf(stderr, "  two-material deck: summed u upper %.4g, lower %.4g m/s\n", upper, lower);
  CHECK(upper > 0.0 && lower > 0.0 && upper > 2.0 * lower);
  // A particle file with 'material' needs a 'materials' list; an index past the list is rejected.
  nlohmann::json plain = deck;
  plain.erase("materials");
  plain["rho0"] = 1000, plain["c0"] = 1.0, plain["viscosity"] = 0.01;
  testfiles::write_text(dir / "plain.json", plain.dump(2));
  bool rejected = false;
  try {
    run_deck(load_deck((dir / "plain.json").string()));
  } catch (const InputError& e) {
    rejected = std::string(e.what()).find("no 'materials' list") != std::string::npos;
  }
  CHECK(rejected);
}
