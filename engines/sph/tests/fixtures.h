// Shared fixtures of the C++ tests: a jittered 2D block of fluid on three
// layers of boundary particles, a model that carries a (constant) deviatoric
// stress, and a homogeneous shear cell for the Lees-Edwards tests.
#pragma once
#include <random>

#include "simulation.h"

namespace fixtures {

using namespace sph;

// A model that carries a deviatoric stress but never changes it: tau stays 0,
// so sigma = -p I on the tensor path.
struct InertStress : Newtonian {
  static constexpr const char* name = "inert_stress";
  static constexpr bool has_stress = true;
};

// A jittered block of columns x rows fluid particles (spacing 1 mm, positions
// jittered by +-jitter mm) on three rows of boundary particles below. Fluid
// velocities are G x + (0.1, -0.2) m/s when `linear`, else random in +-speed
// m/s (walls at rest). Density 1000 (1 + density_jitter (1 + j)), j in
// +-jitter, for the fluid and, when walls_jittered, for the walls too.
struct Block {
  int columns = 14, rows = 12;
  unsigned seed = 5;
  double jitter = 0.15, speed = 0.5;
  double density_jitter = 0.0;
  bool walls_jittered = false;
  bool linear = false;
  Mat<2> G = Mat<2>::Zero();
  bool reserve = false;  // reserve exactly the particles (allocation test)
};

inline Particles<2> block(const Block& b) {
  std::mt19937 rng(b.seed);
  std::uniform_real_distribution<double> jitter(-b.jitter, b.jitter), speed(-b.speed, b.speed);
  Particles<2> P;
  const std::size_t n = b.columns * (b.rows + 3);
  if (b.reserve) P.reserve(n);
  P.resize(n);
  int k = 0;
  for (int i = 0; i < b.columns; ++i)
    for (int j = -3; j < b.rows; ++j, ++k) {
      const bool wall = j < 0;
      P.x[k] = 1e-3 * Vec<2>(i + (wall ? 0.0 : jitter(rng)), j + (wall ? 0.0 : jitter(rng)));
      P.v[k] = b.linear ? Vec<2>(b.G * P.x[k] + Vec<2>(0.1, -0.2))
                        : (wall ? Vec<2>::Zero() : Vec<2>(speed(rng), speed(rng)));
      if (b.density_jitter == 0.0) P.rho[k] = 1000.0;
      else if (wall && !b.walls_jittered) P.rho[k] = 1000.0;
      else P.rho[k] = 1000.0 * (1.0 + b.density_jitter * (1.0 + jitter(rng)));
      P.mass[k] = 1e-3, P.id[k] = k;
      P.kind[k] = wall ? Kind::boundary : Kind::fluid;
    }
  return P;
}

// A 2D Lees-Edwards cell [0, L) x [0, L) of n x n fluid particles (spacing
// L/n, jittered by +-jitter spacings) of density rho0, moving at the simple
// shear u_x = gamma_dot (y - L/2); h = 1.3 dx.
inline Particles<2> shear_cell(int n, double L, double rho0, double gamma_dot, double jitter = 0.0, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> j(-jitter, jitter);
  const double dx = L / n;
  Particles<2> P;
  P.reserve(n * n);
  P.resize(n * n);
  int k = 0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b, ++k) {
      const double x = (a + 0.5 + j(rng)) * dx, y = (b + 0.5 + j(rng)) * dx;
      P.x[k] = Vec<2>(x, y);
      P.v[k] = Vec<2>(gamma_dot * (y - 0.5 * L), 0.0);
      P.rho[k] = rho0, P.mass[k] = rho0 * dx * dx, P.id[k] = k, P.kind[k] = Kind::fluid;
    }
  return P;
}

// The deck of a shear cell: periodic [0, L)^2 with Lees-Edwards steady shear.
inline RunParameters shear_deck(int n, double L, double rho0, double c0, double gamma_dot) {
  RunParameters d;
  d.dimension = 2;
  d.rho0 = rho0, d.c0 = c0, d.gamma = 7.0, d.v_max = 0.5 * gamma_dot * L;
  d.dx = L / n, d.h = 1.3 * d.dx;
  d.periodic_axes = {0, 1}, d.periodic_lo = {0.0, 0.0}, d.periodic_hi = {L, L};
  d.lees_edwards.on = true, d.lees_edwards.shear_rate = gamma_dot;
  return d;
}

// Give every boundary particle of P a wall point on the plane y = y_wall m
// (boundary_particles.h: the no-slip extrapolated to that plane).
inline void wall_points_at(Particles<2>& P, double y_wall) {
  P.has_wall_points = true;
  P.resize(P.size());
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.kind[i] == Kind::boundary) P.wall_offset[i] = Vec<2>(0.0, y_wall - P.x[i][1]);
}

}  // namespace fixtures
