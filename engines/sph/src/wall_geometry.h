// Closest point of a point to a triangle (3D) or a segment (2D), with the
// feature (face interior, edge, vertex) it lies on.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>

#include "vec.h"

namespace sph {

// Identifies a face interior, an edge (two vertex ids) or a vertex of one mesh,
// so that a particle near an edge shared by two triangles feels it once.
struct Feature {
  enum Type : std::uint8_t { face = 0, edge = 1, vertex = 2 };
  std::uint64_t key = 0;
  static Feature of_face(int f) { return {(std::uint64_t{face} << 62) | std::uint64_t(f)}; }
  static Feature of_vertex(int v) { return {(std::uint64_t{vertex} << 62) | std::uint64_t(v)}; }
  static Feature of_edge(int v, int w) {
    if (v > w) std::swap(v, w);
    return {(std::uint64_t{edge} << 62) | (std::uint64_t(v) << 31) | std::uint64_t(w)};
  }
  Type type() const { return static_cast<Type>(key >> 62); }
};

template <int D>
struct ClosestPoint {
  Vec<D> point;
  Feature feature;
};

// The feature of a closest point from its barycentric weights (wa, wb, wc).
// Weights below a relative 1e-10 count as zero, so a point on a shared edge or
// vertex is named the same by every face that touches it despite rounding.
inline Feature feature_of(double wa, double wb, double wc, std::array<int, 3> ids, int f) {
  constexpr double eps = 1e-10;
  const bool ka = wa > eps, kb = wb > eps, kc = wc > eps;
  const int kept = ka + kb + kc;
  if (kept == 3) return Feature::of_face(f);
  if (kept == 2) return ka && kb ? Feature::of_edge(ids[0], ids[1])
                        : ka     ? Feature::of_edge(ids[0], ids[2])
                                 : Feature::of_edge(ids[1], ids[2]);
  const int i = wa >= wb && wa >= wc ? 0 : wb >= wc ? 1 : 2;
  return Feature::of_vertex(ids[i]);
}

// Closest point on triangle (a, b, c) with vertex ids and face id f, by the
// Voronoi region of p: three vertex regions, three edge regions, the face.
inline ClosestPoint<3> closest_on_triangle(const Vec<3>& p, const Vec<3>& a, const Vec<3>& b, const Vec<3>& c,
                                           std::array<int, 3> ids, int f) {
  const Vec<3> ab = b - a, ac = c - a, ap = p - a;
  auto at = [&](double wa, double wb, double wc) {
    return ClosestPoint<3>{wa * a + wb * b + wc * c, feature_of(wa, wb, wc, ids, f)};
  };
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return at(1, 0, 0);
  const Vec<3> bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return at(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return at(1 - t, t, 0);
  }
  const Vec<3> cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return at(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return at(1 - t, 0, t);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return at(0, 1 - t, t);
  }
  const double inv = 1.0 / (va + vb + vc);
  const double v = vb * inv, w = vc * inv;
  return at(1.0 - v - w, v, w);
}

// Closest point on segment (a, b) with vertex ids and segment id f.
inline ClosestPoint<2> closest_on_segment(const Vec<2>& p, const Vec<2>& a, const Vec<2>& b, std::array<int, 2> ids,
                                          int f) {
  constexpr double eps = 1e-10;
  const Vec<2> ab = b - a;
  const double t = std::clamp(ab.dot(p - a) / ab.squaredNorm(), 0.0, 1.0);
  if (t <= eps) return {a, Feature::of_vertex(ids[0])};
  if (t >= 1.0 - eps) return {b, Feature::of_vertex(ids[1])};
  return {a + t * ab, Feature::of_face(f)};
}

// Unit normal of a face (right-hand rule for triangles; ab rotated by +90 degrees for segments).
inline Vec<3> face_normal(const Vec<3>& a, const Vec<3>& b, const Vec<3>& c) {
  return (b - a).cross(c - a).normalized();
}
inline Vec<2> face_normal(const Vec<2>& a, const Vec<2>& b) {
  const Vec<2> t = (b - a).normalized();
  return Vec<2>(-t[1], t[0]);
}

// Penalty force magnitude of eq. 14, N: psi ((R-d)^4 - (R-s)^2 (R-d)^2) / (R^2 s (2R - s))
// for d <= R, else 0. F(0) = psi, F(s) = 0, repulsive below s and attractive between s and R.
inline double penalty_force(double d, double R, double s, double psi) {
  if (d > R) return 0.0;
  const double e = R - d, e2 = e * e, rs = R - s;
  return psi * (e2 * e2 - rs * rs * e2) / (R * R * s * (2.0 * R - s));
}

}  // namespace sph
