// Boundary particles that know the nearest point of the true wall (input
// dataset `wall_point`, boundary_particles.h): steady plane Couette and
// Poiseuille flows between walls placed off the lattice match the exact
// profiles with the walls at their true positions, much better than Adami's
// mirror (whose no-slip lies halfway between the lattice layers); NaN rows
// are Adami's mirror, bitwise; whole steps do not depend on the thread count.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "fixtures.h"
#include "input_h5.h"
#include "run.h"
#include "run_loop.h"
#include "simulation.h"
#include "test_files.h"

using namespace sph;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A 2D channel periodic in x: fluid rows j = 0..rows-1 at y = (j + 1/2) dx,
// three rows of boundary particles below and above. The true walls are off
// the lattice: the lower at y = -0.3 dx (0.2 dx behind the first boundary
// row), the upper at y = rows dx - 0.2 dx (0.3 dx above the last fluid row,
// inside the lattice layer between fluid and boundary). Driven by a body
// force F (Poiseuille) or by the upper wall moving at U (Couette).
struct OffLatticeChannel {
  double dx = 5e-4, nu = 1e-4, rho0 = 1000.0, F = 0.0, U = 0.0;
  int rows = 12, columns = 8;
  double y_lo() const { return -0.3 * dx; }
  double y_hi() const { return rows * dx - 0.2 * dx; }
  double width() const { return y_hi() - y_lo(); }

  // The steady profile between the true walls, m/s.
  double exact(double y) const {
    if (U != 0.0) return U * (y - y_lo()) / width();
    return F / (2.0 * nu) * (y - y_lo()) * (y_hi() - y);
  }
  double peak() const { return U != 0.0 ? U : F * width() * width() / (8.0 * nu); }

  // wall_points: 0 none (no dataset), 1 on the true walls, 2 a dataset of NaN rows.
  testfiles::ParticleRows particles(int wall_points, std::vector<double>& points) const {
    testfiles::ParticleRows p;
    points.clear();
    const double m = rho0 * dx * dx, nan = std::nan("");
    for (int i = 0; i < columns; ++i)
      for (int j = -3; j < rows + 3; ++j) {
        const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
        const bool lower = j < 0, upper = j >= rows;
        p.add({x, y}, {upper ? U : 0.0, 0.0}, m, rho0, lower || upper ? 1 : 0);
        const double wall = lower ? y_lo() : upper ? y_hi() : nan;
        points.push_back(wall_points == 1 ? x : nan);
        points.push_back(wall_points == 1 ? wall : nan);
      }
    if (!wall_points) points.clear();
    return p;
  }

  json deck(double t_end) const {
    json j = {{"dimension", 2},
              {"particles_file", "particles.h5"},
              {"physics", F != 0.0 ? json{"morris_viscosity", "body_force"} : json{"morris_viscosity"}},
              {"rho0", rho0},
              {"c0", 1.0},
              {"v_max", 0.05},
              {"viscosity", nu},
              {"h", 1.5 * dx},
              {"dx", dx},
              {"periodic", {{"axes", {0}}, {"lo", {0.0}}, {"hi", {columns * dx}}}},
              {"t_end", t_end},
              {"threads", 1}};
    if (F != 0.0) j["body_force"] = {F, 0.0};
    j["output"] = {{"file", "out.h5"}, {"frame_interval", t_end}};
    return j;
  }
};

void write_particles(const fs::path& path, const testfiles::ParticleRows& p, const std::vector<double>& points) {
  p.write(path);
  if (points.empty()) return;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  testfiles::put(f, "wall_point", H5T_NATIVE_DOUBLE, points, p.size(), 2);
  H5Fclose(f);
}

struct Profile {
  std::vector<double> x, v;  // the last frame's fluid rows, by id
  double worst = 0.0;        // max |u - u_exact| / peak over the fluid particles
};

Profile run_channel(const OffLatticeChannel& c, int wall_points, const std::string& name) {
  const fs::path dir = testfiles::scratch(name);
  std::vector<double> points;
  write_particles(dir / "particles.h5", c.particles(wall_points, points), points);
  const double t_end = 0.6;  // 15 decay times of the slowest mode, width^2 / (pi^2 nu)
  testfiles::write_text(dir / "deck.json", c.deck(t_end).dump(2));
  CHECK(run_deck(load_deck((dir / "deck.json").string())) == exit_ok);
  const fs::path out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "ok");
  Profile p;
  p.x = testfiles::read_doubles(out, "/frames/1/positions");
  p.v = testfiles::read_doubles(out, "/frames/1/velocities");
  const auto kind = testfiles::read_doubles(out, "/frames/1/kind");
  for (std::size_t i = 0; i < kind.size(); ++i)
    if (kind[i] == 0) p.worst = std::max(p.worst, std::abs(p.v[2 * i] - c.exact(p.x[2 * i + 1])) / c.peak());
  return p;
}

// A jittered block of water on boundary particles (fixtures::block) under gravity, with Morris and artificial
// viscosity: the deck of the tests that step whole blocks with wall points.
constexpr unsigned kBlockTerms = term::morris_viscosity | term::artificial_viscosity | term::body_force;
RunParameters block_deck() {
  RunParameters d;
  d.dimension = 2, d.terms = kBlockTerms;
  d.rho0 = 1000.0, d.c0 = 20.0, d.gamma = 7.0, d.v_max = 2.0, d.viscosity = 1e-4, d.alpha = 0.2, d.beta = 0.1;
  d.h = 1.3e-3, d.dx = 1e-3, d.body_force = {0.0, -9.81};
  return d;
}

}  // namespace

TEST(off_lattice_couette_matches_the_true_walls) {
  OffLatticeChannel c;
  c.U = 0.02;
  const double with = run_channel(c, 1, "couette_wall_points").worst;
  const double without = run_channel(c, 0, "couette_mirror").worst;
  std::fprintf(stderr, "  Couette, walls off the lattice: worst |u - exact| / U %.3f %% with wall points, %.3f %% without\n",
               100 * with, 100 * without);
  CHECK(with < 0.0005);     // linear: the extrapolation is exact (0.015 % measured)
  CHECK(without > 0.015);   // the mirror's no-slip on the lattice's mid-planes
}

// The no-slip where the steady profile vanishes: a parabola u = c (y - y1)(y2 - y)
// fitted (least squares) to every fluid particle; y1, y2 in units of dx, c in 1/(m s).
struct Parabola {
  double y1, y2, c;
};
Parabola fit_parabola(const OffLatticeChannel& ch, const Profile& p) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; 2 * i + 1 < p.x.size(); ++i) {
    const double y = p.x[2 * i + 1] / ch.dx;
    if (y < 0.0 || y > ch.rows) continue;  // the fluid rows (boundary particles sit outside)
    const Eigen::Vector3d f(y * y, y, 1.0);
    A += f * f.transpose(), rhs += f * p.v[2 * i];
  }
  const Eigen::Vector3d k = A.ldlt().solve(rhs);  // u = k0 y^2 + k1 y + k2
  const double disc = std::sqrt(k[1] * k[1] - 4.0 * k[0] * k[2]);
  const double r1 = (-k[1] + disc) / (2.0 * k[0]), r2 = (-k[1] - disc) / (2.0 * k[0]);
  return {std::min(r1, r2), std::max(r1, r2), -k[0] / (ch.dx * ch.dx)};
}

TEST(off_lattice_poiseuille_matches_the_true_walls) {
  OffLatticeChannel c;
  c.F = 0.04;  // peak F w^2 / (8 nu) = 0.019 m/s
  const Profile with = run_channel(c, 1, "poiseuille_wall_points");
  const Profile without = run_channel(c, 0, "poiseuille_mirror");
  const Parabola a = fit_parabola(c, with), b = fit_parabola(c, without);
  std::fprintf(stderr, "  Poiseuille, true walls at y = -0.3 and 11.8 dx: the fitted profile vanishes at %.3f and %.3f dx "
               "with wall points, %.3f and %.3f dx without; curvature / F/(2 nu) %.4f, %.4f; worst |u - exact| / peak "
               "%.2f %%, %.2f %%\n", a.y1, a.y2, b.y1, b.y2, a.c / (c.F / (2 * c.nu)), b.c / (c.F / (2 * c.nu)),
               100 * with.worst, 100 * without.worst);
  const double lo = c.y_lo() / c.dx, hi = c.y_hi() / c.dx;
  // the no-slip within 0.02 dx of the true walls (measured 0.013, 0.004 dx with the quadratic fit WP2;
  // 0.027, 0.029 dx with the linear extrapolation WP1, whose O(dx^2) slip the fit removes)
  CHECK(std::abs(a.y1 - lo) < 0.02 && std::abs(a.y2 - hi) < 0.02);
  CHECK(std::abs(b.y1 - lo) > 0.2 && std::abs(b.y2 - hi) > 0.2);     // the mirror's near the lattice mid-planes 0, 12
  // The curvature is the Morris term's on this lattice (its sum over the lattice is 0.985 of the
  // Laplacian at h = 1.5 dx): 1.5 % high, with or without wall points.
  CHECK_CLOSE(a.c, c.F / (2 * c.nu) / 0.985, 0.005);
  CHECK(with.worst < 0.03 && without.worst > 0.07);
}

TEST(nan_wall_points_are_the_mirror_bitwise) {
  OffLatticeChannel c;
  c.F = 0.04;
  const Profile none = run_channel(c, 0, "poiseuille_no_dataset");
  const Profile nans = run_channel(c, 2, "poiseuille_nan_rows");
  CHECK(none.v == nans.v && none.x == nans.x && !none.v.empty());
}

TEST(wall_point_dataset_is_checked) {
  const fs::path dir = testfiles::scratch("wall_point_shape");
  OffLatticeChannel c;
  std::vector<double> points;
  testfiles::ParticleRows p = c.particles(0, points);
  p.write(dir / "bad.h5");
  hid_t f = H5Fopen((dir / "bad.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  testfiles::put(f, "wall_point", H5T_NATIVE_DOUBLE, std::vector<double>(p.size(), 0.0), p.size(), 0);  // (n), not (n,2)
  H5Fclose(f);
  std::string message;
  try {
    read_particles((dir / "bad.h5").string(), 2);
  } catch (const InputError& e) {
    message = e.what();
  }
  CHECK(message.find("'wall_point'") != std::string::npos && message.find("shape (n,2)") != std::string::npos);
  std::vector<double> inf(2 * p.size(), 0.0);
  inf[3] = INFINITY;
  p.write(dir / "inf.h5");
  f = H5Fopen((dir / "inf.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  testfiles::put(f, "wall_point", H5T_NATIVE_DOUBLE, inf, p.size(), 2);
  H5Fclose(f);
  message.clear();
  try {
    read_particles((dir / "inf.h5").string(), 2);
  } catch (const InputError& e) {
    message = e.what();
  }
  CHECK(message.find("'wall_point'") != std::string::npos && message.find("infinite") != std::string::npos);
}

TEST(wall_point_steps_do_not_depend_on_the_thread_count) {
  constexpr unsigned terms = kBlockTerms;
  const RunParameters d = block_deck();
  fixtures::Block b;
  b.columns = 24, b.rows = 24, b.seed = 11, b.jitter = 0.1, b.speed = 0.5;
  Particles<2> start = fixtures::block(b);
  fixtures::wall_points_at(start, -0.4e-3);  // between the first boundary row (-1 mm) and the fluid (0)
  auto advance = [&](int steps) {
    Simulation<2, terms> sim(d, start);
    for (int s = 0; s < steps; ++s) CHECK(sim.step(1e-5, NoCrossings{}));
    std::vector<Vec<2>> v(start.size());
    const auto& P = sim.particles();
    for (std::size_t i = 0; i < P.size(); ++i) v[P.id[i]] = P.v[i];
    return v;
  };
  const int before = omp_get_max_threads();
  const std::ptrdiff_t light = parallel_min_light;
  omp_set_num_threads(1);
  const auto one = advance(30);
  omp_set_num_threads(2);
  const auto two = advance(30);
  parallel_min_light = 64;  // the no-slip velocities on the threads too
  const auto two_light = advance(30);
  parallel_min_light = light;
  omp_set_num_threads(before);
  CHECK(one == two);
  CHECK(one == two_light);
  // the wall points change the run (the extrapolated no-slip differs from the mirror)
  Particles<2> mirror = fixtures::block(b);
  Simulation<2, terms> sim(d, mirror);
  for (int s = 0; s < 30; ++s) CHECK(sim.step(1e-5, NoCrossings{}));
  double differ = 0.0;
  for (std::size_t i = 0; i < sim.particles().size(); ++i)
    differ = std::max(differ, (sim.particles().v[i] - one[sim.particles().id[i]]).norm());
  CHECK(differ > 1e-6);
}

// The fit of eq. WP2 as summed now (the wall frame taken once per particle, the lower triangle
// of the normal matrix packed) equals, bitwise, the sums as the fit took them per pair before
// (the frame from the offset at every pair, Eigen's w (a a^T) and w (a dv^T)), and so does the
// extrapolated velocity (the LDLT reads the lower triangle only).
TEST(wall_fit_sums_are_the_per_pair_outer_products_bitwise) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int ghosts = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec<3> offset(u(gen) * 1e-4, u(gen) * 1e-4, u(gen) * 1e-4);
    const WallFrame<3> frame = wall_frame_of(offset);
    const double d_b = offset.norm();
    const Vec<3> n = offset / d_b;
    int k = 0;
    for (int d = 1; d < 3; ++d)
      if (std::abs(n[d]) < std::abs(n[k])) k = d;
    const Vec<3> e1 = n.cross(Vec<3>::Unit(k)).normalized(), e2 = n.cross(e1);
    WallFit<3> fit;
    Eigen::Matrix<double, 5, 5> normal = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 3> rhs = Eigen::Matrix<double, 5, 3>::Zero();
    for (int f = 0; f < 40; ++f) {  // fluid in front of the wall's tangent plane, up to 2 dx off along it
      const Vec<3> r = n * (d_b + 6e-4 * (0.05 + std::abs(u(gen)))) + 6e-4 * (u(gen) * e1 + u(gen) * e2);
      const Vec<3> dv(u(gen), u(gen), u(gen));
      const double w = 0.5 * (1.0 + u(gen));
      add_wall_fit(fit, frame, w, r, dv, 1e5, 1000.0);
      const double s = r.dot(n) - d_b, t1 = r.dot(e1), t2 = r.dot(e2);
      Eigen::Matrix<double, 5, 1> a;
      a << s, s * s, t1 * t1, t2 * t2, t1 * t2;
      normal.noalias() += w * (a * a.transpose());
      rhs.noalias() += w * (a * dv.transpose());
    }
    for (int i = 0, p = 0; i < 5; ++i)
      for (int j = 0; j <= i; ++j, ++p) CHECK(fit.normal[p] == normal(i, j));
    CHECK(fit.rhs == rhs && fit.behind == 0.0);
    // The extrapolation as before, from Eigen's full (not quite symmetric) sums.
    const Eigen::Matrix<double, 5, 1> scale = normal.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::LDLT<Eigen::Matrix<double, 5, 5>> ldlt(Eigen::Matrix<double, 5, 5>(scale.asDiagonal() * normal * scale.asDiagonal()));
    const Eigen::Matrix<double, 5, 3> c = scale.asDiagonal() * ldlt.solve(scale.asDiagonal() * rhs);
    const Vec<3> v_w(0.1, 0.2, 0.3);
    const Vec<3> before = v_w + (d_b * d_b) * c.row(1).transpose() - d_b * c.row(0).transpose();
    Vec<3> now = Vec<3>::Zero();
    if (quadratic_ghost(fit, frame.depth, 1.0, v_w, now)) {
      ++ghosts;
      CHECK(now == before);
    }
  }
  CHECK(ghosts > 100);
}

// Eq. WP3 with its floor: a boundary particle with a wall point takes the Shepard average of the
// fluid pressure around it, and never less than p_rest (a wall never pulls): fluid at a tension
// beside it (a free jet's spreading) would otherwise pull itself into the wall. Its density, the
// fluid's Shepard density, stops at rho_rest likewise (stretched fluid would make the wall's volume
// m_b / rho_b too big in the fluid's continuity sums).
TEST(wall_pressure_is_the_fluids_shepard_average_never_below_rest) {
  for (double p_fluid : {-2.0e8, -1.0e5, 0.0, 3.0e6}) {
    Particles<3> P;
    P.has_wall_points = true;
    P.resize(4);
    const double dx = 1e-4, rest = 5.0e3;  // Pa: a background pressure
    P.kind = {Kind::boundary, Kind::fluid, Kind::fluid, Kind::fluid};
    P.wall_offset[0] = Vec<3>(0.0, 0.0, 0.5 * dx);  // wall plane z = 0.5 dx, fluid above it
    P.set_wall_frames();
    std::vector<double> shepard(4, 0.0);
    const double w[3] = {0.5, 0.3, 0.2};
    for (int f = 1; f < 4; ++f) {
      P.x[f] = Vec<3>(0.3 * f * dx, 0.0, (0.5 + f) * dx);
      P.p[f] = p_fluid * (1.0 + 0.1 * f), P.rho[f] = (p_fluid < 0.0 ? 900.0 : 1000.0) + f;
      add_no_slip<3>(P, 0, f, w[f - 1], P.x[f], {P.v_noslip[0], shepard[0], P.x_noslip[0], P.wall_fit[0]});
    }
    P.mass[0] = 1e-9;
    no_slip_velocity(P, shepard, 0, rest, 1000.0);
    const double mean = p_fluid * (0.5 * 1.1 + 0.3 * 1.2 + 0.2 * 1.3);  // weights sum to 1
    CHECK_CLOSE(P.p[0], std::max(mean, rest), 1e-12);
    const double rho_mean = (p_fluid < 0.0 ? 900.0 : 1000.0) + 0.5 * 1 + 0.3 * 2 + 0.2 * 3;  // 901.7 or 1001.7
    CHECK_CLOSE(P.rho[0], std::max(rho_mean, 1000.0), 1e-12);
    CHECK_CLOSE(P.p_rho2[0], P.p[0] / (P.rho[0] * P.rho[0]), 1e-12);
  }
}

// A wall particle with a wall point takes the fluid's Shepard density at every evaluation (eq. WP3), so
// its stored density is no state: no continuity rate, and particles that appear or disappear beside it
// are not booked into it (integrated, it drifted to -11,000 kg/m^3 beside the drill's outlet). A wall
// particle without a wall point (NaN row) keeps both, as before.
TEST(wall_particles_with_a_wall_point_hold_their_density) {
  constexpr unsigned terms = kBlockTerms;
  const RunParameters d = block_deck();
  fixtures::Block b;
  b.columns = 12, b.rows = 8, b.seed = 11, b.jitter = 0.1, b.speed = 0.5, b.density_jitter = 0.01;
  Particles<2> start = fixtures::block(b);
  fixtures::wall_points_at(start, -0.4e-3);
  const double nan = std::nan("");
  for (std::size_t i = 0; i < start.size(); ++i)  // the row next to the fluid: no wall point
    if (start.kind[i] == Kind::boundary && start.x[i][1] > -1.5e-3) start.wall_offset[i] = Vec<2>(nan, nan);
  CHECK(holds_density(start, 0) == (start.kind[0] == Kind::boundary && !std::isnan(start.wall_offset[0][0])));
  Simulation<2, terms> sim(d, start);
  for (int s = 0; s < 5; ++s) CHECK(sim.step(1e-5, NoCrossings{}));
  const auto& P = sim.particles();
  int holding = 0, integrating = 0, integrating_moved = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const bool point = P.kind[i] == Kind::boundary && !std::isnan(P.wall_offset[i][0]);
    CHECK(holds_density(P, i) == point);
    if (point) {
      ++holding;
      CHECK(P.drho[i] == 0.0);
    }
    if (P.kind[i] == Kind::boundary && !point) ++integrating, integrating_moved += P.drho[i] != 0.0;
  }
  CHECK(holding == 24 && integrating == 12);
  CHECK(integrating_moved > 0);  // the NaN row still integrates the fluid's continuity
  // a particle appears between the rows: only the NaN row's density takes its share
  std::vector<double> before(P.size());
  for (std::size_t i = 0; i < P.size(); ++i) before[i] = P.rho[i];
  sim.boundary_density_event(Vec<2>(5.5e-3, -1.5e-3), 1e-3, 1.0);
  int booked = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (holds_density(P, i) || P.kind[i] != Kind::boundary) CHECK(P.rho[i] == before[i]);
    else booked += P.rho[i] > before[i];
  }
  CHECK(booked >= 2);
  Particles<2> none = start;
  none.has_wall_points = false;
  for (std::size_t i = 0; i < none.size(); ++i) CHECK(!holds_density(none, i));
}
