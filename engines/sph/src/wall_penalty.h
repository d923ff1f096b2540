// Penalty walls from triangle meshes (3D) or segment polylines (2D), eq. 14.
//
// The force on a particle from each face within range R acts along the line
// from the face's closest point to the particle (the face normal when the
// particle lies on the face). Meshes are static; their faces are binned once
// into a grid so a particle tests only nearby faces.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "wall_geometry.h"

namespace sph {

template <int D>
struct WallMesh {
  std::string name;
  std::vector<Vec<D>> vertices;          // m
  std::vector<std::array<int, D>> faces;  // D vertex ids per face (segments in 2D, triangles in 3D)
};

struct PenaltyParams {
  double range = 0.0;  // R, m
  double s = 0.0;      // sign change distance, m
  double psi = 0.0;    // F(0), N
};

template <int D>
class WallPenalty {
 public:
  WallPenalty() = default;
  WallPenalty(std::vector<WallMesh<D>> meshes, PenaltyParams params, double min_cell)
      : meshes_(std::move(meshes)), params_(params) {
    count_incidence();
    bin(std::max(min_cell, params_.range));
  }

  const std::vector<WallMesh<D>>& meshes() const { return meshes_; }
  const PenaltyParams& params() const { return params_; }

  // Closest point of face f of mesh m to p.
  ClosestPoint<D> closest(const Vec<D>& p, int m, int f) const {
    const auto& mesh = meshes_[m];
    const auto& ids = mesh.faces[f];
    if constexpr (D == 3)
      return closest_on_triangle(p, mesh.vertices[ids[0]], mesh.vertices[ids[1]], mesh.vertices[ids[2]], ids, f);
    else
      return closest_on_segment(p, mesh.vertices[ids[0]], mesh.vertices[ids[1]], ids, f);
  }

  // Total penalty force on a particle at x, N. sink(mesh, force_on_particle) is
  // called for every contributing contact (for the reaction on each mesh).
  //
  // A face interior within range always counts. An edge or vertex counts only
  // when every face sharing it reports it as its closest point, i.e. when it
  // is the nearest part of the surface locally (a convex edge or corner, or an
  // open rim). Near an edge of a flat or concave part the neighbouring face is
  // nearer, so the edge is skipped and a tessellated flat wall feels smooth.
  template <class Sink>
  Vec<D> force(const Vec<D>& x, Sink&& sink) const {
    Vec<D> total = Vec<D>::Zero();
    const int cell = cell_of(x);
    if (cell < 0) return total;
    struct Corner {
      std::uint64_t key;
      int mesh, reports, incidence;
      Vec<D> F;
    };
    constexpr int max_corners = 32;
    std::array<Corner, max_corners> corners;
    int n_corners = 0;
    for (int k = start_[cell]; k < start_[cell + 1]; ++k) {
      const auto [m, f] = entries_[k];
      const ClosestPoint<D> cp = closest(x, m, f);
      const Vec<D> delta = x - cp.point;
      const double d = delta.norm();
      if (d > params_.range) continue;
      const Vec<D> dir = d > 1e-12 * params_.range ? Vec<D>(delta / d) : normal(m, f);
      const Vec<D> F = penalty_force(d, params_.range, params_.s, params_.psi) * dir;
      if (cp.feature.type() == Feature::face) {
        total += F;
        sink(m, F);
        continue;
      }
      int i = 0;
      while (i < n_corners && !(corners[i].key == cp.feature.key && corners[i].mesh == m)) ++i;
      if (i < n_corners) {
        ++corners[i].reports;
      } else if (n_corners < max_corners) {
        corners[n_corners++] = {cp.feature.key, m, 1, incidence(m, f, cp.feature), F};
      }
    }
    for (int i = 0; i < n_corners; ++i) {
      if (corners[i].reports != corners[i].incidence) continue;
      total += corners[i].F;
      sink(corners[i].mesh, corners[i].F);
    }
    return total;
  }
  Vec<D> force(const Vec<D>& x) const {
    return force(x, [](int, const Vec<D>&) {});
  }

 private:
  // Number of faces of mesh m sharing the edge or vertex `feature` of face f.
  int incidence(int m, int f, Feature feature) const {
    const auto& ids = meshes_[m].faces[f];
    const auto& inc = incidence_[m][f];
    if (feature.type() == Feature::vertex) {
      for (int i = 0; i < D; ++i)
        if (feature.key == Feature::of_vertex(ids[i]).key) return inc[i];
    } else if constexpr (D == 3) {
      for (int i = 0; i < 3; ++i)
        if (feature.key == Feature::of_edge(ids[i], ids[(i + 1) % 3]).key) return inc[3 + i];
    }
    return 1;
  }

  // Per face: how many faces share each of its vertices (and, in 3D, each edge i -> i+1).
  void count_incidence() {
    incidence_.resize(meshes_.size());
    for (std::size_t m = 0; m < meshes_.size(); ++m) {
      const auto& faces = meshes_[m].faces;
      std::vector<int> per_vertex(meshes_[m].vertices.size(), 0);
      std::map<std::uint64_t, int> per_edge;
      for (const auto& f : faces) {
        for (int i = 0; i < D; ++i) ++per_vertex[f[i]];
        if constexpr (D == 3)
          for (int i = 0; i < 3; ++i) ++per_edge[Feature::of_edge(f[i], f[(i + 1) % 3]).key];
      }
      incidence_[m].resize(faces.size());
      for (std::size_t k = 0; k < faces.size(); ++k) {
        const auto& f = faces[k];
        for (int i = 0; i < D; ++i) incidence_[m][k][i] = per_vertex[f[i]];
        if constexpr (D == 3)
          for (int i = 0; i < 3; ++i) incidence_[m][k][3 + i] = per_edge[Feature::of_edge(f[i], f[(i + 1) % 3]).key];
      }
    }
  }

  Vec<D> normal(int m, int f) const {
    const auto& v = meshes_[m].vertices;
    const auto& ids = meshes_[m].faces[f];
    if constexpr (D == 3)
      return face_normal(v[ids[0]], v[ids[1]], v[ids[2]]);
    else
      return face_normal(v[ids[0]], v[ids[1]]);
  }

  int cell_of(const Vec<D>& x) const {
    int lin = 0;
    for (int d = D - 1; d >= 0; --d) {
      const double t = std::floor((x[d] - lo_[d]) / width_);
      if (!(t >= 0.0 && t < dims_[d])) return -1;
      lin = lin * dims_[d] + static_cast<int>(t);
    }
    return lin;
  }

  // Register each face in every grid cell it may reach within range R: its
  // bounding box grown by R, kept only where the cell centre is within
  // R + half the cell diagonal of the face.
  void bin(double cell) {
    Vec<D> lo = Vec<D>::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& m : meshes_)
      for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double R = params_.range;
    lo.array() -= R;
    hi.array() += R;
    width_ = cell;
    constexpr double max_cells = 1e7;
    for (;;) {
      double total = 1.0;
      for (int d = 0; d < D; ++d) total *= std::floor((hi[d] - lo[d]) / width_) + 1.0;
      if (total <= max_cells) break;
      width_ *= 1.5;
    }
    int ncell = 1;
    for (int d = 0; d < D; ++d) {
      dims_[d] = static_cast<int>(std::floor((hi[d] - lo[d]) / width_)) + 1;
      ncell *= dims_[d];
    }
    lo_ = lo;
    const double reach = R + 0.5 * width_ * std::sqrt(double(D));
    std::vector<std::vector<std::pair<int, int>>> per_cell(ncell);
    for (int m = 0; m < static_cast<int>(meshes_.size()); ++m) {
      for (int f = 0; f < static_cast<int>(meshes_[m].faces.size()); ++f) {
        Vec<D> flo = meshes_[m].vertices[meshes_[m].faces[f][0]], fhi = flo;
        for (int i = 1; i < D; ++i) {
          flo = flo.cwiseMin(meshes_[m].vertices[meshes_[m].faces[f][i]]);
          fhi = fhi.cwiseMax(meshes_[m].vertices[meshes_[m].faces[f][i]]);
        }
        std::array<int, D> c0{}, c1{};
        for (int d = 0; d < D; ++d) {
          c0[d] = std::max(0, static_cast<int>(std::floor((flo[d] - R - lo_[d]) / width_)));
          c1[d] = std::min(dims_[d] - 1, static_cast<int>(std::floor((fhi[d] + R - lo_[d]) / width_)));
        }
        std::array<int, D> c = c0;
        for (;;) {
          Vec<D> centre;
          int lin = 0;
          for (int d = D - 1; d >= 0; --d) {
            centre[d] = lo_[d] + (c[d] + 0.5) * width_;
            lin = lin * dims_[d] + c[d];
          }
          if ((centre - closest(centre, m, f).point).norm() <= reach) per_cell[lin].push_back({m, f});
          int d = 0;
          for (; d < D; ++d) {
            if (++c[d] <= c1[d]) break;
            c[d] = c0[d];
          }
          if (d == D) break;
        }
      }
    }
    start_.assign(ncell + 1, 0);
    for (int c = 0; c < ncell; ++c) start_[c + 1] = start_[c] + static_cast<int>(per_cell[c].size());
    entries_.clear();
    entries_.reserve(start_[ncell]);
    for (auto& list : per_cell) entries_.insert(entries_.end(), list.begin(), list.end());
  }

  std::vector<WallMesh<D>> meshes_;
  PenaltyParams params_;
  Vec<D> lo_ = Vec<D>::Zero();
  double width_ = 1.0;
  std::array<int, D> dims_{};
  std::vector<int> start_;
  std::vector<std::pair<int, int>> entries_;  // (mesh, face) per cell
  std::vector<std::vector<std::array<int, 2 * D>>> incidence_;  // [mesh][face]: vertices, then edges (3D)
};

}  // namespace sph
