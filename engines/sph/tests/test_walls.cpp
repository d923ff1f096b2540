// Penalty walls: eq. 14 by hand, closest points on triangles and segments,
// and the force a particle feels near faces, shared edges and convex edges.
#include <cmath>
#include <random>

#include <set>
#include <utility>
#include <vector>

#include "check.h"
#include "neighbour_list.h"
#include "wall_penalty.h"

using namespace sph;

TEST(penalty_force_matches_eq14_by_hand) {
  const double R = 1e-3, s = 0.4e-3, psi = 2.0;
  // F(d) = psi ((R-d)^4 - (R-s)^2 (R-d)^2) / (R^2 s (2R - s)); denominator = 0.64e-12 m^4
  CHECK_CLOSE(penalty_force(0.0, R, s, psi), 2.0, 1e-12);                    // F(0) = psi
  CHECK_CLOSE(penalty_force(0.2e-3, R, s, psi), 2.0 * 0.1792 / 0.64, 1e-12);  // (0.4096 - 0.36*0.64)
  CHECK(std::abs(penalty_force(0.4e-3, R, s, psi)) < 1e-12);                 // F(s) = 0
  CHECK_CLOSE(penalty_force(0.7e-3, R, s, psi), 2.0 * (0.0081 - 0.0324) / 0.64, 1e-12);  // attractive
  CHECK(std::abs(penalty_force(R, R, s, psi)) < 1e-15);
  CHECK(penalty_force(1.2e-3, R, s, psi) == 0.0);
}

TEST(closest_point_on_triangle_regions) {
  const Vec<3> a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const std::array<int, 3> ids{10, 11, 12};
  auto cp = [&](double x, double y, double z) { return closest_on_triangle(Vec<3>(x, y, z), a, b, c, ids, 7); };
  auto near = [](const Vec<3>& p, double x, double y, double z) { return (p - Vec<3>(x, y, z)).norm() < 1e-14; };
  CHECK(near(cp(0.2, 0.2, 0.5).point, 0.2, 0.2, 0) && cp(0.2, 0.2, 0.5).feature.key == Feature::of_face(7).key);
  CHECK(near(cp(0.5, -0.3, 0.1).point, 0.5, 0, 0) && cp(0.5, -0.3, 0.1).feature.key == Feature::of_edge(11, 10).key);
  CHECK(near(cp(-0.2, -0.3, 0).point, 0, 0, 0) && cp(-0.2, -0.3, 0).feature.key == Feature::of_vertex(10).key);
  CHECK(near(cp(0.8, 0.8, -1).point, 0.5, 0.5, 0) && cp(0.8, 0.8, -1).feature.key == Feature::of_edge(11, 12).key);
  CHECK(near(cp(2, -0.5, 0).point, 1, 0, 0) && cp(2, -0.5, 0).feature.key == Feature::of_vertex(11).key);
  CHECK(near(cp(-0.5, 0.5, 0.3).point, 0, 0.5, 0) && cp(-0.5, 0.5, 0.3).feature.key == Feature::of_edge(10, 12).key);
  CHECK(near(cp(-0.5, 2, 0).point, 0, 1, 0) && cp(-0.5, 2, 0).feature.key == Feature::of_vertex(12).key);
}

TEST(closest_point_on_triangle_against_brute_force) {
  const Vec<3> a(0.1, -0.2, 0.3), b(1.2, 0.1, -0.4), c(-0.3, 0.9, 0.2);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  const int n = 400;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec<3> p(u(rng), u(rng), u(rng));
    const double d = (p - closest_on_triangle(p, a, b, c, {0, 1, 2}, 0).point).norm();
    double best = 1e30;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        best = std::min(best, (p - (a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n))).norm());
    CHECK(d <= best + 1e-12);
    CHECK(d >= best - 2e-3);  // lattice resolution of the brute force
  }
}

TEST(closest_point_on_segment) {
  const Vec<2> a(0, 0), b(2, 0);
  auto cp = closest_on_segment(Vec<2>(0.5, 1.0), a, b, {3, 4}, 1);
  CHECK((cp.point - Vec<2>(0.5, 0)).norm() < 1e-15 && cp.feature.key == Feature::of_face(1).key);
  cp = closest_on_segment(Vec<2>(-1, 1), a, b, {3, 4}, 1);
  CHECK(cp.point == a && cp.feature.key == Feature::of_vertex(3).key);
  cp = closest_on_segment(Vec<2>(3, -1), a, b, {3, 4}, 1);
  CHECK(cp.point == b && cp.feature.key == Feature::of_vertex(4).key);
}

namespace {
const PenaltyParams kWall{1e-3, 0.4e-3, 2.0};

// A flat square 0..L x 0..L in z = 0 split into two triangles along its diagonal.
WallPenalty<3> flat_square(double L) {
  WallMesh<3> m;
  m.name = "floor";
  m.vertices = {Vec<3>(0, 0, 0), Vec<3>(L, 0, 0), Vec<3>(L, L, 0), Vec<3>(0, L, 0)};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return WallPenalty<3>({m}, kWall, 2e-3);
}
}  // namespace

TEST(penalty_on_a_flat_tessellated_wall) {
  const WallPenalty<3> w = flat_square(1e-2);
  for (double d : {0.0, 0.1e-3, 0.3e-3, 0.6e-3, 0.95e-3}) {
    // Above the interior, right next to the shared diagonal: one contribution, along +z.
    for (Vec<3> p : {Vec<3>(3.2e-3, 3.0e-3, d), Vec<3>(3.0e-3, 3.0e-3, d), Vec<3>(5e-3, 1e-3, d)}) {
      const Vec<3> F = w.force(p);
      CHECK_CLOSE(F[2], penalty_force(d, 1e-3, 0.4e-3, 2.0), 1e-12, 1e-12);
      CHECK(std::abs(F[0]) < 1e-12 && std::abs(F[1]) < 1e-12);
    }
  }
  CHECK(w.force(Vec<3>(5e-3, 5e-3, 1.1e-3)).norm() == 0.0);   // out of range
  CHECK(w.force(Vec<3>(5e-3, 5e-3, -0.3e-3))[2] < 0.0);        // from below: pushed down
}

TEST(penalty_at_a_convex_edge_counts_once) {
  // Two faces meeting at a right angle along the x axis (a convex edge):
  // one in z = 0 (y < 0), one in y = 0 (z < 0).
  WallMesh<3> m;
  m.name = "step";
  const double L = 1e-2;
  m.vertices = {Vec<3>(0, 0, 0), Vec<3>(L, 0, 0), Vec<3>(L, -L, 0), Vec<3>(0, -L, 0), Vec<3>(L, 0, -L),
                Vec<3>(0, 0, -L)};
  m.faces = {{0, 1, 2}, {0, 2, 3}, {0, 5, 4}, {0, 4, 1}};
  const WallPenalty<3> w({m}, kWall, 2e-3);
  const double d = 0.5e-3;
  const Vec<3> p(4e-3, d / std::sqrt(2.0), d / std::sqrt(2.0));
  const Vec<3> F = w.force(p);
  const double f = penalty_force(d, 1e-3, 0.4e-3, 2.0);
  CHECK_CLOSE(F[1], f / std::sqrt(2.0), 1e-10);
  CHECK_CLOSE(F[2], f / std::sqrt(2.0), 1e-10);
  CHECK(std::abs(F[0]) < 1e-12);
  // The rim of an open mesh pushes outwards, once.
  const Vec<3> beyond(L + 0.3e-3, -5e-3, 0.0);
  CHECK_CLOSE(w.force(beyond)[0], penalty_force(0.3e-3, 1e-3, 0.4e-3, 2.0), 1e-10);
}

TEST(penalty_in_2d_from_a_polyline) {
  WallMesh<2> m;
  m.name = "floor";
  m.vertices = {Vec<2>(0, 0), Vec<2>(1e-2, 0), Vec<2>(2e-2, 0), Vec<2>(2e-2, 1e-2)};
  m.faces = {{0, 1}, {1, 2}, {2, 3}};
  const WallPenalty<2> w({m}, kWall, 2e-3);
  const double d = 0.3e-3, f = penalty_force(d, 1e-3, 0.4e-3, 2.0);
  // Over the shared vertex of two collinear segments: once.
  CHECK_CLOSE(w.force(Vec<2>(1e-2, d))[1], f, 1e-12);
  CHECK_CLOSE(w.force(Vec<2>(1e-2 + 0.1e-3, d))[1], f, 1e-12);
  // Inside the concave corner at (2e-2, 0): both walls push.
  const Vec<2> F = w.force(Vec<2>(2e-2 - d, d));
  CHECK_CLOSE(F[0], -f, 1e-12);
  CHECK_CLOSE(F[1], f, 1e-12);
}

// The Verlet list over a slab of boundary particles with a small fluid blob on it (the drill's walls):
// the walls far from the fluid get empty rows without a sweep, and the listed pairs are exactly those
// closer than the range that are not two walls, each once; along x periodic or not.
TEST(neighbour_list_skips_walls_far_from_fluid) {
  for (bool periodic : {false, true}) {
    const double dx = 1.0, range = 2.6;
    std::vector<Vec<3>> x;
    std::vector<Kind> kind;
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j < 12; ++j)
        for (int k = 0; k < 3; ++k) x.emplace_back(i * dx, j * dx, k * dx), kind.push_back(Kind::boundary);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 2; ++k)
          x.emplace_back(4.3 + i * dx, 5.2 + j * dx, 3.1 + k * dx), kind.push_back(Kind::fluid);
    PeriodicBox<3> box;
    if (periodic) box.periodic[0] = true, box.lo[0] = -0.5, box.hi[0] = 29.5;
    PeriodicImages<3> images(box);
    CellList<3> cells;
    cells.configure(range, 2, box, 1u << 20);
    CHECK(cells.build(x, x.size()));
    std::vector<Vec<3>> xs;
    std::vector<Kind> ks;
    for (int o : cells.items()) xs.push_back(x[o]), ks.push_back(kind[o]);
    cells.mark_sorted();
    NeighbourList<3> list;
    list.configure(images);
    list.build(cells, xs, ks, range, true);
    std::set<std::pair<int, int>> listed;
    int entries = 0, empty_walls = 0;
    for (int k = 0; k < list.blocks(); ++k)
      for (int a = list.block_begin(k); a < list.block_end(k); ++a) {
        const auto& row = list.row(a);
        if (ks[a] == Kind::boundary && row.begin == row.end) ++empty_walls;
        for (int e = row.begin; e < row.end; ++e, ++entries) {
          const int b = static_cast<int>(list.entries(k)[e] >> NeighbourList<3>::shift_bits);
          listed.insert({std::min(a, b), std::max(a, b)});
        }
      }
    std::set<std::pair<int, int>> expected;
    const int n = static_cast<int>(xs.size());
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) {
        if (ks[a] == Kind::boundary && ks[b] == Kind::boundary) continue;
        Vec<3> r = xs[a] - xs[b];
        if (periodic) r[0] -= 30.0 * std::round(r[0] / 30.0);
        if (r.squaredNorm() < range * range) expected.insert({a, b});
      }
    CHECK(listed == expected);
    CHECK(entries == static_cast<int>(expected.size()));  // each pair once
    CHECK(empty_walls > 900);  // of 1080 walls only those under the blob have fluid within reach
  }
}
