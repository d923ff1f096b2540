// The tensor-stress path (eq. T1) and the velocity gradient (eq. T2): with
// sigma = -p I the tensor momentum reproduces the scalar one to round-off,
// and the kernel-corrected gradient of a linear velocity field is exact
// (beyond the reach of the walls, whose particles enter with their no-slip velocity).
#include <cmath>

#include "check.h"
#include "fixtures.h"
#include "simulation.h"

using namespace sph;

namespace {

using fixtures::InertStress;

constexpr unsigned kTerms = term::morris_viscosity | term::artificial_viscosity | term::body_force;
using Scalar = Simulation<2, kTerms>;
using Tensor = Simulation<2, kTerms, ModelList<Newtonian, InertStress>>;

RunParameters deck() {
  RunParameters d;
  d.dimension = 2, d.terms = kTerms;
  d.rho0 = 1000.0, d.c0 = 20.0, d.gamma = 7.0, d.v_max = 2.0, d.viscosity = 1e-3, d.alpha = 0.2, d.beta = 0.1;
  d.h = 1.3e-3, d.dx = 1e-3, d.body_force = {0.0, -9.81};
  return d;
}

// The shared jittered block (fixtures.h); v = G x + v0 when linear, random otherwise.
Particles<2> block(bool linear, const Mat<2>& G) {
  fixtures::Block b;
  b.seed = 5, b.jitter = 0.15, b.speed = 0.5, b.density_jitter = 0.004, b.walls_jittered = true;
  b.linear = linear, b.G = G;
  return fixtures::block(b);
}

}  // namespace

TEST(tensor_path_with_pressure_only_stress_matches_scalar_path) {
  const Particles<2> start = block(false, Mat<2>::Zero());
  Scalar scalar(deck(), start);
  Tensor tensor(deck(), start);
  scalar.compute_rates();
  tensor.compute_rates();
  const auto &A = scalar.particles(), &B = tensor.particles();
  CHECK(A.size() == B.size());
  double acc_scale = 0.0, drho_scale = 0.0, acc_err = 0.0, drho_err = 0.0;
  for (std::size_t i = 0; i < A.size(); ++i) {
    CHECK(A.id[i] == B.id[i]);  // same binning, same order
    acc_scale = std::max(acc_scale, A.acc[i].norm()), drho_scale = std::max(drho_scale, std::abs(A.drho[i]));
    acc_err = std::max(acc_err, (A.acc[i] - B.acc[i]).norm()), drho_err = std::max(drho_err, std::abs(A.drho[i] - B.drho[i]));
  }
  std::fprintf(stderr, "  tensor vs scalar: |d acc| %.3g of %.3g, |d drho| %.3g of %.3g\n", acc_err, acc_scale, drho_err,
               drho_scale);
  CHECK(acc_scale > 0.0 && acc_err <= 1e-12 * acc_scale);
  CHECK(drho_err <= 1e-12 * drho_scale);
  // A few steps keep agreeing to round-off (tau stays zero).
  for (int s = 0; s < 5; ++s) CHECK(scalar.step(5e-6, NoCrossings{}) && tensor.step(5e-6, NoCrossings{}));
  double x_err = 0.0;
  for (std::size_t i = 0; i < A.size(); ++i) x_err = std::max(x_err, (A.x[i] - B.x[i]).norm());
  CHECK(x_err < 1e-15);
}

TEST(corrected_velocity_gradient_of_a_linear_field_is_exact) {
  Mat<2> G;
  G << 3.0, -1.5, 0.7, 2.0;  // 1/s
  for (bool corrected : {true, false}) {
    Tensor sim(deck(), block(true, G));
    sim.set_gradient_correction(corrected);
    sim.compute_rates();
    const auto& P = sim.particles();
    double worst = 0.0, worst_inside = 0.0;
    const double support2 = 4.0 * deck().h * deck().h;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (!P.moves(i)) continue;
      const double err = (P.grad_v[i] - G).norm() / G.norm();
      // Boundary particles enter eq. T2 with their no-slip velocity (mirrored through the
      // wall, boundary_particles.h), not the linear field: exact away from them.
      bool near_wall = false;
      for (std::size_t j = 0; j < P.size(); ++j)
        near_wall = near_wall || (P.kind[j] == Kind::boundary && (P.x[j] - P.x[i]).squaredNorm() < support2);
      if (!near_wall) worst = std::max(worst, err);
      const bool inside = P.x[i][0] > 3e-3 && P.x[i][0] < 10e-3 && P.x[i][1] < 8e-3;  // full support of fluid and wall
      if (inside) worst_inside = std::max(worst_inside, err);
    }
    std::fprintf(stderr, "  grad v (%s): worst relative error %.3g, inside %.3g\n", corrected ? "corrected" : "plain",
                 worst, worst_inside);
    if (corrected) CHECK(worst < 1e-10);  // every fluid particle beyond the walls' reach, free surface included
    else CHECK(worst_inside < 0.5 && worst > 1e-3);  // plain SPH: approximate only
  }
}
