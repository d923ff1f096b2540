// Two immiscible Newtonian layers of different density and viscosity between
// a fixed wall (y = 0) and a wall sliding at U (y = H), periodic along x:
// the steady two-layer Couette flow. The shear stress is the same in both
// layers, mu_1 du/dy = mu_2 du/dy, so the profile is piecewise linear with
// the interface speed U_i = U (h1/mu1) / (h1/mu1 + h2/mu2) at y = h1:
//   u(y) = U_i y / h1                          for y < h1
//   u(y) = U_i + (U - U_i) (y - h1) / h2       for y > h1.
// The pair viscosity across the interface is the harmonic mean (material.h).
#include <cmath>

#include "check.h"
#include "simulation.h"

using namespace sph;

namespace {

constexpr unsigned kTerms = term::morris_viscosity | term::several_materials;

}  // namespace

TEST(two_layer_couette_matches_piecewise_linear_profile) {
  const int columns = 8, rows = 20, layers = 3, rows_1 = 10;  // lower layer: rows 0..9
  const double dx = 1e-3, H = rows * dx, h1 = rows_1 * dx, h2 = H - h1, U = 0.05;
  const double rho_1 = 1000.0, rho_2 = 500.0, nu_1 = 0.01, nu_2 = 0.01;  // mu_1 = 10 Pa s, mu_2 = 5 Pa s
  Deck d;
  d.dimension = 2, d.terms = term::morris_viscosity;
  d.h = 1.3 * dx, d.dx = dx, d.v_max = U;
  d.materials = {{"lower", "newtonian", rho_1, 1.0, 7.0, 0.0, nu_1}, {"upper", "newtonian", rho_2, 1.0, 7.0, 0.0, nu_2}};
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
