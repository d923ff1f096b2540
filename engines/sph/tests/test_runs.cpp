// Whole runs through files (deck JSON + particle HDF5 -> output HDF5):
// 2D Poiseuille flow against its series solution, a hydrostatic tank, and
// the stop on numerical instability.
#include <cmath>

#include <nlohmann/json.hpp>

#include "check.h"
#include "deck.h"
#include "run.h"
#include "run_loop.h"
#include "test_files.h"

using namespace sph;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Channel of width L between walls y = 0 and y = L, periodic in x, driven by body force F.
struct Channel {
  double L = 0.01, dx = 0.01 / 20, nu = 1e-4, F = 0.8, rho0 = 1000.0;
  int columns = 10;
  double length() const { return columns * dx; }

  // Transient velocity (Morris et al. 1997): steady F y (L - y) / (2 nu) minus its decaying sine series.
  double velocity(double y, double t) const {
    double u = F / (2.0 * nu) * y * (L - y);
    for (int n = 1; n < 200; n += 2)
      u -= 4.0 * F * L * L / (nu * std::pow(M_PI * n, 3)) * std::sin(n * M_PI * y / L) *
           std::exp(-n * n * M_PI * M_PI * nu * t / (L * L));
    return u;
  }
  // Mean volume flux per unit depth over [t1, t2], m^2/s.
  double mean_flux(double t1, double t2) const {
    double q = F * L * L * L / (12.0 * nu);
    for (int n = 1; n < 200; n += 2) {
      const double k = n * n * M_PI * M_PI * nu / (L * L);
      q -= 8.0 * F * L * L * L / (nu * std::pow(M_PI * n, 4)) * (std::exp(-k * t1) - std::exp(-k * t2)) /
           (k * (t2 - t1));
    }
    return q;
  }

  testfiles::ParticleRows particles() const {
    testfiles::ParticleRows p;
    const double m = rho0 * dx * dx;
    const int rows = static_cast<int>(std::lround(L / dx));
    for (int i = 0; i < columns; ++i)
      for (int j = -3; j < rows + 3; ++j) {
        const bool wall = j < 0 || j >= rows;
        p.add({(i + 0.5) * dx, (j + 0.5) * dx}, {0.0, 0.0}, m, rho0, wall ? 1 : 0);
      }
    return p;
  }

  json deck(double t_end) const {
    json j = {{"dimension", 2},
              {"particles_file", "particles.h5"},
              {"physics", {"morris_viscosity", "body_force"}},
              {"rho0", rho0},
              {"c0", 1.5},
              {"v_max", 0.12},
              {"viscosity", nu},
              {"h", 1.5 * dx},
              {"dx", dx},
              {"body_force", {F, 0.0}},
              {"periodic", {{"axes", {0}}, {"lo", {0.0}}, {"hi", {length()}}}},
              {"t_end", t_end},
              {"threads", 2}};
    j["output"] = {{"file", "out.h5"},
                   {"frame_interval", t_end / 2},
                   {"series_interval", 0.05},
                   {"probes", {{{"name", "centre"}, {"point", {length() / 2, L / 2}}}}},
                   {"flow_planes",
                    {{{"name", "section"}, {"center", {length() / 2, L / 2}}, {"normal", {1.0, 0.0}}, {"radius", L / 2}}}}};
    return j;
  }
};

int run_in(const fs::path& dir, const json& deck) {
  testfiles::write_text(dir / "deck.json", deck.dump(2));
  return run_deck(load_deck((dir / "deck.json").string()));
}

}  // namespace

TEST(poiseuille_flow_matches_series_solution) {
  const Channel c;
  const fs::path dir = testfiles::scratch("poiseuille");
  c.particles().write(dir / "particles.h5");
  const double t_end = 0.5;
  CHECK(run_in(dir, c.deck(t_end)) == exit_ok);
  const fs::path out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "ok");
  CHECK_CLOSE(testfiles::read_double_attr(out, "/frames/2", "time"), t_end, 1e-9);
  const auto x = testfiles::read_doubles(out, "/frames/2/positions");
  const auto v = testfiles::read_doubles(out, "/frames/2/velocities");
  const auto kind = testfiles::read_doubles(out, "/frames/2/kind");
  const double u_max = c.velocity(c.L / 2, t_end);
  double err2 = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < kind.size(); ++i) {
    if (kind[i] != 0) continue;
    const double e = v[2 * i] - c.velocity(x[2 * i + 1], t_end);
    err2 += e * e;
    ++n;
    CHECK(std::abs(v[2 * i + 1]) < 0.01 * u_max);
  }
  const double rms = std::sqrt(err2 / n) / u_max;
  std::fprintf(stderr, "  poiseuille: u_max = %.5f m/s, rms error %.3f %% of u_max\n", u_max, 100 * rms);
  CHECK(rms < 0.03);
  // Flow rate through the section, averaged over the last five series intervals
  // (counting particle crossings is quantised by the particle volume).
  const auto q = testfiles::read_doubles(out, "/series/flow_rate_section");
  const auto t = testfiles::read_doubles(out, "/series/time");
  CHECK(q.size() == t.size() && t.size() == 11);
  const double measured = (q[6] + q[7] + q[8] + q[9] + q[10]) / 5.0;
  const double expected = c.mean_flux(t[5], t[10]);
  std::fprintf(stderr, "  poiseuille: flow rate %.6g vs %.6g m^2/s\n", measured, expected);
  CHECK_CLOSE(measured, expected, 0.04);
  const auto p = testfiles::read_doubles(out, "/series/pressure_probe_centre");
  CHECK(std::abs(p.back()) < 0.01 * c.rho0 * 1.5 * 1.5);  // background 0, flow is along x
}

TEST(hydrostatic_tank_settles_to_rho_g_depth) {
  // Water column H = 0.1 m in a tank 0.1 m wide; three layers of boundary particles.
  const double dx = 5e-3, H = 0.1, W = 0.1, rho0 = 1000.0, g = 9.81, c0 = 15.0;
  const double B = rho0 * c0 * c0 / 7.0;
  testfiles::ParticleRows p;
  const int nx = static_cast<int>(std::lround(W / dx)), ny = static_cast<int>(std::lround(H / dx));
  for (int i = -3; i < nx + 3; ++i)
    for (int j = -3; j < ny + 4; ++j) {
      const bool wall = i < 0 || i >= nx || j < 0;
      if (!wall && j >= ny) continue;
      const double y = (j + 0.5) * dx;
      const double rho = rho0 * std::pow(1.0 + rho0 * g * (H - y) / B, 1.0 / 7.0);
      p.add({(i + 0.5) * dx, y}, {0.0, 0.0}, rho0 * dx * dx, rho, wall ? 1 : 0);
    }
  const fs::path dir = testfiles::scratch("hydrostatic");
  p.write(dir / "particles.h5");
  const double depth_probe = 0.07;
  json deck = {{"dimension", 2},
               {"particles_file", "particles.h5"},
               {"physics", {"artificial_viscosity", "body_force"}},
               {"rho0", rho0},
               {"c0", c0},
               {"v_max", 1.4},
               {"alpha", 0.1},
               {"h", 1.3 * dx},
               {"dx", dx},
               {"body_force", {0.0, -g}},
               {"t_end", 0.5},
               {"threads", 1},
               {"stability", {{"max_density_deviation", 0.03}}},
               {"output",
                {{"file", "out.h5"},
                 {"frame_interval", 0.25},
                 {"series_interval", 0.01},
                 {"probes", {{{"name", "deep"}, {"point", {W / 2, H - depth_probe}}}}}}}};
  CHECK(run_in(dir, deck) == exit_ok);
  const fs::path out = dir / "out.h5";
  const auto pr = testfiles::read_doubles(out, "/series/pressure_probe_deep");
  double mean = 0.0;
  for (std::size_t i = pr.size() - 10; i < pr.size(); ++i) mean += pr[i] / 10.0;
  std::fprintf(stderr, "  hydrostatic: probe %.1f Pa vs rho g d = %.1f Pa\n", mean, rho0 * g * depth_probe);
  CHECK_CLOSE(mean, rho0 * g * depth_probe, 0.05);
  const auto ke = testfiles::read_doubles(out, "/series/kinetic_energy");
  const double potential_scale = rho0 * W * H * g * H;
  CHECK(ke.back() < 1e-4 * potential_scale);
}

TEST(instability_stops_with_status_and_last_good_frame) {
  const Channel c;
  const fs::path dir = testfiles::scratch("unstable");
  c.particles().write(dir / "particles.h5");
  json deck = c.deck(0.5);
  deck["dt"] = 5e-3;  // 40 times the CFL limit
  CHECK(run_in(dir, deck) == exit_unstable);
  const fs::path out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "unstable");
  const std::string msg = testfiles::read_string_attr(out, "message");
  CHECK(msg.find("unstable at t") != std::string::npos);
  std::fprintf(stderr, "  unstable: %s\n", msg.c_str());
  const double last = testfiles::read_double_attr(out, "/", "last_good_frame");
  const auto rho = testfiles::read_doubles(out, "/frames/" + std::to_string(static_cast<int>(last)) + "/densities");
  CHECK(!rho.empty());
  for (double r : rho) CHECK(std::isfinite(r) && std::abs(r / 1000.0 - 1.0) <= 0.1);
}

TEST(fluid_rests_on_a_penalty_mesh_floor_in_3d) {
  // A 10 x 10 x 10 block of water on a two-triangle floor (HDF5 mesh), periodic in x and y.
  const double dx = 5e-3, rho0 = 1000.0, g = 9.81, L = 10 * dx, H = 10 * dx, c0 = 10.0;
  const double B = rho0 * c0 * c0 / 7.0;
  testfiles::ParticleRows p;
  p.dim = 3;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      for (int k = 0; k < 10; ++k) {
        const double z = (k + 0.5) * dx;
        p.add({(i + 0.5) * dx, (j + 0.5) * dx, z}, {0, 0, 0}, rho0 * dx * dx * dx,
              rho0 * std::pow(1.0 + rho0 * g * (H - z) / B, 1.0 / 7.0), 0);
      }
  const fs::path dir = testfiles::scratch("floor3d");
  p.write(dir / "particles.h5");
  {
    hid_t f = H5Fcreate((dir / "meshes.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    hid_t grp = H5Gcreate2(f, "floor", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    testfiles::put(grp, "vertices", H5T_NATIVE_DOUBLE, std::vector<double>{-L, -L, 0, 2 * L, -L, 0, 2 * L, 2 * L, 0, -L, 2 * L, 0}, 4, 3);
    testfiles::put(grp, "faces", H5T_NATIVE_INT, std::vector<int>{0, 1, 2, 0, 2, 3}, 2, 3);
    H5Gclose(grp);
    H5Fclose(f);
  }
  json deck = {{"dimension", 3},
               {"particles_file", "particles.h5"},
               {"physics", {"artificial_viscosity", "body_force", "wall_penalty"}},
               {"rho0", rho0},
               {"c0", c0},
               {"v_max", 1.0},
               {"alpha", 0.2},
               {"h", 1.3 * dx},
               {"dx", dx},
               {"body_force", {0.0, 0.0, -g}},
               {"meshes", {{{"name", "floor"}, {"file", "meshes.h5"}, {"group", "/floor"}}}},
               {"wall", {{"range", dx}, {"s", 0.5 * dx}, {"psi", 0.5}}},
               {"periodic", {{"axes", {0, 1}}, {"lo", {0.0, 0.0}}, {"hi", {L, L}}}},
               {"t_end", 0.3},
               {"threads", 1},
               {"output", {{"file", "out.h5"}, {"frame_interval", 0.15}, {"series_interval", 0.01}}}};
  CHECK(run_in(dir, deck) == exit_ok);
  const fs::path out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "ok");
  const auto x = testfiles::read_doubles(out, "/frames/2/positions");
  double zmin = 1.0;
  for (std::size_t i = 2; i < x.size(); i += 3) zmin = std::min(zmin, x[i]);
  CHECK(zmin > 0.0);
  const auto F = testfiles::read_doubles(out, "/series/wall_force_floor");  // (n, 3), N
  double fz = 0.0;
  for (std::size_t r = F.size() / 3 - 10; r < F.size() / 3; ++r) fz += F[3 * r + 2] / 10.0;
  const double weight = -1000.0 * rho0 * dx * dx * dx * g;  // the floor is pushed down by the weight
  std::fprintf(stderr, "  floor: lowest particle z = %.3g mm, floor force %.4f N vs weight %.4f N\n", 1e3 * zmin, fz,
               weight);
  CHECK_CLOSE(fz, weight, 0.05);
}

TEST(channel_with_velocity_inlet_and_outlet) {
  // Plug flow at U through a 2D channel 40 x 20 dx: fluid enters through the
  // inlet, leaves through the outlet; after 1.5 channel lengths the flow
  // rates and the amount of fluid match U L. The fluid initially fills the
  // outlet buffer too (3 dx), as a steady start needs.
  const double dx = 5e-4, L = 20 * dx, Lx = 40 * dx, U = 0.1, rho0 = 1000.0;
  testfiles::ParticleRows p;
  for (int i = -4; i < 44; ++i)
    for (int j = -3; j < 23; ++j) {
      const bool wall = j < 0 || j >= 20;
      const bool fluid = !wall && i >= 0 && i < 43;
      if (!wall && !fluid) continue;
      p.add({(i + 0.5) * dx, (j + 0.5) * dx}, {fluid ? U : 0.0, 0.0}, rho0 * dx * dx, rho0, wall ? 1 : 0);
    }
  const fs::path dir = testfiles::scratch("inlet_outlet");
  p.write(dir / "particles.h5");
  const double t_end = 0.3;
  json deck = {{"dimension", 2},
               {"particles_file", "particles.h5"},
               {"physics", {"artificial_viscosity"}},
               {"rho0", rho0},
               {"c0", 2.0},
               {"v_max", 0.2},
               {"alpha", 0.05},
               {"h", 1.3 * dx},
               {"dx", dx},
               {"inlets", {{{"name", "feed"}, {"center", {0.0, L / 2}}, {"normal", {1.0, 0.0}}, {"radius", L / 2},
                            {"velocity", U}}}},
               {"outlets", {{{"name", "drain"}, {"center", {Lx, L / 2}}, {"normal", {1.0, 0.0}}, {"radius", L / 2}}}},
               {"t_end", t_end},
               {"threads", 1},
               {"output", {{"file", "out.h5"}, {"frame_interval", t_end}, {"series_interval", 0.05}}}};
  CHECK(run_in(dir, deck) == exit_ok);
  const fs::path out = dir / "out.h5";
  CHECK(testfiles::read_string_attr(out, "status") == "ok");
  const auto qin = testfiles::read_doubles(out, "/series/inflow_feed");
  const auto qout = testfiles::read_doubles(out, "/series/outflow_drain");
  double in = 0.0, outflow = 0.0;
  for (std::size_t i = 1; i < qin.size(); ++i) in += qin[i] / (qin.size() - 1), outflow += qout[i] / (qout.size() - 1);
  std::fprintf(stderr, "  channel: inflow %.4g, outflow %.4g, U L = %.4g m^2/s\n", in, outflow, U * L);
  CHECK_CLOSE(in, U * L, 0.03);
  CHECK_CLOSE(outflow, U * L, 0.03);
  const auto kind = testfiles::read_doubles(out, "/frames/1/kind");
  const auto v = testfiles::read_doubles(out, "/frames/1/velocities");
  const auto ids = testfiles::read_doubles(out, "/frames/1/ids");
  int fluid = 0;
  double u_mean = 0.0;
  for (std::size_t i = 0; i < kind.size(); ++i)
    if (kind[i] == 0) ++fluid, u_mean += v[2 * i];
  u_mean /= fluid;
  std::fprintf(stderr, "  channel: %d fluid particles (800 at start), mean u %.4f m/s\n", fluid, u_mean);
  CHECK(std::abs(fluid - 800) <= 40);
  CHECK_CLOSE(u_mean, U, 0.05);
  bool increasing = true;
  for (std::size_t i = 1; i < ids.size(); ++i) increasing = increasing && ids[i] > ids[i - 1];
  CHECK(increasing);
}
