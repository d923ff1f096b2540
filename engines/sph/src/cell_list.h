// Cell-list neighbour search with periodic axes.
//
// Cells are at least support/reach wide (reach = 1 or 2), so all neighbours
// of a point lie within `reach` cells of its own: (2 reach + 1)^D cells.
// Along a periodic axis the box [lo, hi) is split into n >= 1 equal cells and
// a neighbour cell across the box edge is visited with a shift of +-L, so the
// pair vector is
// x_a - (x_b + shift). Along other axes the grid spans the particles' bounding
// box, recomputed at every build.
#pragma once
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "vec.h"

namespace sph {

template <int D>
struct PeriodicBox {
  std::array<bool, D> periodic{};
  Vec<D> lo = Vec<D>::Zero(), hi = Vec<D>::Zero();
  bool any() const { return std::find(periodic.begin(), periodic.end(), true) != periodic.end(); }
  // Map a position into [lo, hi) along the periodic axes.
  void wrap(Vec<D>& x) const {
    for (int d = 0; d < D; ++d) {
      if (!periodic[d]) continue;
      const double L = hi[d] - lo[d];
      if (x[d] >= hi[d] || x[d] < lo[d]) x[d] -= L * std::floor((x[d] - lo[d]) / L);
      if (x[d] >= hi[d]) x[d] = lo[d];  // rounding at the upper edge
    }
  }
};

template <int D>
class CellList {
 public:
  // Cells are at least support / reach wide; a point's neighbours lie within
  // `reach` cells of its own along each axis.
  void configure(double support, int reach, const PeriodicBox<D>& box, std::size_t max_cells) {
    assert(reach >= 1 && reach <= 2);  // max_runs
    reach_ = reach;
    min_cell_ = support / reach;
    box_ = box;
    max_cells_ = max_cells;
  }

  void reserve(std::size_t n) {
    cell_of_.reserve(n);
    items_.reserve(n);
  }

  // Bin positions x[0..n) (counting sort). Afterwards items() lists particle
  // indices cell by cell. Returns false when the particles spread over more
  // than max_cells cells (a blown-up run).
  bool build(const std::vector<Vec<D>>& x, std::size_t n) {
    Vec<D> lo = Vec<D>::Constant(std::numeric_limits<double>::infinity());
    Vec<D> hi = -lo;
    for (std::size_t i = 0; i < n; ++i) {
      lo = lo.cwiseMin(x[i]);
      hi = hi.cwiseMax(x[i]);
    }
    if (!lay_out(lo, hi, n)) return false;
    for (std::size_t i = 0; i < n; ++i) assign(i, x[i]);
    sort_assigned();
    return true;
  }

  // build() in three parts, so a caller can run the per-particle part on
  // threads: lay_out the grid over the bounding box [lo, hi] of n positions
  // (false for a blown-up run), assign(i, x_i) for every i (independent per
  // i), then sort_assigned() (the counting sort, serial: its order is fixed).
  bool lay_out(const Vec<D>& lo, const Vec<D>& hi, std::size_t n) {
    sorted_ = false;
    double cells = 1.0;
    std::array<int, D> dims{};
    Vec<D> lo_p, width_p, length_p;
    for (int d = 0; d < D; ++d) {  // per physical axis
      if (box_.periodic[d]) {
        const double L = box_.hi[d] - box_.lo[d];
        dims[d] = std::max(1, static_cast<int>(std::floor(L / min_cell_)));
        lo_p[d] = box_.lo[d];
        width_p[d] = L / dims[d];
        length_p[d] = L;
      } else {
        const double span = n ? hi[d] - lo[d] : 0.0;
        if (!std::isfinite(span)) return false;
        const double count = std::floor(span / min_cell_) + 1.0;
        if (count > static_cast<double>(max_cells_)) return false;
        dims[d] = static_cast<int>(count);
        lo_p[d] = n ? lo[d] : 0.0;
        width_p[d] = min_cell_;
        length_p[d] = 0.0;
      }
      cells *= dims[d];
    }
    // Internal axis order: the physical axis with the most cells (the first
    // of equals) goes last, the slowest in memory, so it gives the most
    // blocks of the neighbour list (better balance on the threads); the
    // others keep their order.
    int longest = D - 1;
    for (int d = D - 2; d >= 0; --d)
      if (dims[d] > dims[longest]) longest = d;
    if (lees_edwards_) longest = 1;
    for (int k = 0, d = 0; d < D; ++d)
      if (d != longest) perm_[k++] = d;
    perm_[D - 1] = longest;
    for (int k = 0; k < D; ++k) {
      const int d = perm_[k];
      dims_[k] = dims[d], lo_[k] = lo_p[d], width_[k] = width_p[d], length_[k] = length_p[d];
      periodic_[k] = box_.periodic[d];
    }
    if (cells > static_cast<double>(max_cells_)) return false;
    start_.assign(static_cast<std::size_t>(cells) + 1, 0);
    cell_of_.resize(n);
    items_.resize(n);
    return true;
  }
  void assign(std::size_t i, const Vec<D>& x) { cell_of_[i] = linear(coords(x)); }
  void sort_assigned() {
    const std::size_t n = cell_of_.size(), ncell = start_.size() - 1;
    for (std::size_t i = 0; i < n; ++i) ++start_[cell_of_[i] + 1];
    for (std::size_t c = 0; c < ncell; ++c) start_[c + 1] += start_[c];
    fill_.assign(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) items_[fill_[cell_of_[i]]++] = static_cast<int>(i);
  }

  const std::vector<int>& items() const { return items_; }
  // After the particle arrays were reordered by items(): particle k is items()[k].
  void mark_sorted() {
    for (std::size_t k = 0; k < items_.size(); ++k) items_[k] = static_cast<int>(k);
    sorted_ = true;
  }
  // The same when the caller already wrote items()[k] = k (see items_for_reorder).
  void mark_sorted_in_place() { sorted_ = true; }
  // items() for a reorder that sets items_for_reorder()[k] = k as it goes (k by one thread).
  std::vector<int>& items_for_reorder() { return items_; }
  // True after mark_sorted() until the next build(): items()[k] == k.
  bool sorted() const { return sorted_; }

  // A run of cells [cell_begin, cell_end) contiguous in memory (along axis 0)
  // around a point, whose particles are seen at x_b + shift.
  struct Run {
    int cell_begin, cell_end;
    Vec<D> shift;
  };
  // Most runs around a point: (2 reach + 1)^D for reach <= 2 (a periodic axis
  // shorter than the stencil splits a row into single cells); a Lees-Edwards
  // row across the gradient axis spans 2 reach + 2 cells.
  static constexpr int max_runs = D == 2 ? 30 : 150;

  // Lees-Edwards cell (box_policy.h): shear axis 0 is the fastest internal
  // axis and gradient axis 1 the slowest (the neighbour list's blocks are
  // slabs across the gradient, so a sheared image never spans far blocks);
  // rows across the gradient faces are searched around x - k_g delta.
  void set_lees_edwards(bool on) { lees_edwards_ = on; }
  void set_shear_offset(double delta) { delta_ = delta; }  // delta_b of box_policy.h, m, in [0, L_0)

  // The runs of cells around point xa (wrapped into the periodic box), in a
  // fixed order: up to three along axis 0 per row of the other axes. Returns their count.
  int runs(const Vec<D>& xa, Run* out) const { return runs_around(coords_unclamped(xa), out); }

  // The runs around cell `cell` (a linear index) of the last build.
  int runs_of_cell(std::ptrdiff_t cell, Run* out) const {
    std::array<int, D> c{};
    for (int d = 0; d < D; ++d) {
      c[d] = static_cast<int>(cell % dims_[d]);
      cell /= dims_[d];
    }
    return runs_around(c, out);
  }
  // Cells of the last build, and the item range [cell_begin, cell_end) of one.
  std::ptrdiff_t cell_count() const { return static_cast<std::ptrdiff_t>(start_.size()) - 1; }
  int cell_begin(std::ptrdiff_t cell) const { return start_[cell]; }
  int cell_end(std::ptrdiff_t cell) const { return start_[cell + 1]; }

 private:
  int runs_around(const std::array<int, D>& c, Run* out) const {
    std::array<int, D> o{};
    for (int d = 0; d < D; ++d) o[d] = -reach_;
    o[0] = 0;
    int count = 0;
    while (true) {
      std::array<int, D> cc{};
      Vec<D> shift = Vec<D>::Zero();
      bool inside = true;
      for (int d = 1; d < D && inside; ++d) inside = neighbour_index(c[d] + o[d], d, cc[d], shift[d]);
      if (inside && lees_edwards_ && shift[D - 1] != 0.0) sweep_sheared(c[0], cc, shift, out, count);
      else if (inside) sweep_axis0(c[0], cc, shift, out, count);
      int d = 1;
      for (; d < D; ++d) {
        if (++o[d] <= reach_) break;
        o[d] = -reach_;
      }
      if (d == D) break;
    }
    return count;
  }

 public:
  // Positions [item_begin, item_end) in items() of a run's particles.
  int item_begin(const Run& r) const { return start_[r.cell_begin]; }
  int item_end(const Run& r) const { return start_[r.cell_end]; }
  // Number of marked particles in a run (see mark()).
  int marked(const Run& r) const { return marked_[r.cell_end] - marked_[r.cell_begin]; }

  // Count, per cell, the particles i for which marked(i) holds (after build()).
  template <class Pred>
  void mark(Pred&& is_marked) {
    const std::size_t ncell = start_.size() - 1;
    marked_.resize(ncell + 1);
    marked_[0] = 0;
    for (std::size_t c = 0; c < ncell; ++c) {
      int m = 0;
      for (int k = start_[c]; k < start_[c + 1]; ++k) m += is_marked(items_[k]) ? 1 : 0;
      marked_[c + 1] = marked_[c] + m;
    }
  }

  // Call f(b, shift) for every particle b in the cells around point xa, where
  // the image of b is x_b + shift. xa must be wrapped into the periodic box.
  template <class F>
  void for_each_neighbour(const Vec<D>& xa, F&& f) const {
    Run r[max_runs];
    const int nr = runs(xa, r);
    for (int q = 0; q < nr; ++q)
      for (int k = item_begin(r[q]); k < item_end(r[q]); ++k) f(items_[k], static_cast<const Vec<D>&>(r[q].shift));
  }

  // Cells per internal axis (axis 0 fastest in memory; internal axis k is physical axis axis(k)).
  const std::array<int, D>& dims() const { return dims_; }
  int axis(int k) const { return perm_[k]; }
  bool periodic_internal(int k) const { return periodic_[k]; }
  int reach() const { return reach_; }  // cells around a point's own that hold its neighbours, per axis

 private:
  // Cells c0 - reach .. c0 + reach along axis 0 (others fixed in cc) are
  // contiguous in memory: visit them as at most three runs (below the
  // periodic edge, inside, above it), each with its own shift.
  void sweep_axis0(int c0, std::array<int, D>& cc, const Vec<D>& shift, Run* out, int& count) const {
    const int n0 = dims_[0];
    const int first = c0 - reach_, last = c0 + reach_;
    auto run = [&](int from, int to, double s) {  // cells from..to (inside 0..n0-1)
      if (from > to) return;
      Run& r = out[count++];
      cc[0] = from;
      r.cell_begin = linear(cc);
      r.cell_end = r.cell_begin + (to - from) + 1;
      for (int k = 1; k < D; ++k) r.shift[perm_[k]] = shift[k];  // internal axes to physical
      r.shift[perm_[0]] = s;
    };
    if (!periodic_[0]) {
      run(std::max(first, 0), std::min(last, n0 - 1), 0.0);
    } else if (2 * reach_ + 1 <= n0) {
      run(std::max(first, 0), std::min(last, n0 - 1), 0.0);
      if (first < 0) run(first + n0, n0 - 1, -length_[0]);
      if (last >= n0) run(0, last - n0, length_[0]);
    } else {  // fewer cells than the stencil: every offset is its own image
      for (int off = -reach_; off <= reach_; ++off) {
        int c = 0;
        double s = 0.0;
        neighbour_index(c0 + off, 0, c, s);
        run(c, c, s);
      }
    }
  }

  // A Lees-Edwards row across the gradient faces (k_g = shift / L_g): its
  // images sit k_g delta further along axis 0, so the row is searched over the
  // 2 reach + 2 cells around c0 - k_g delta / width, each run shifted by k_g delta too.
  void sweep_sheared(int c0, std::array<int, D>& cc, const Vec<D>& shift, Run* out, int& count) const {
    const int n0 = dims_[0];
    const double offset = std::lround(shift[D - 1] / length_[D - 1]) * delta_;
    const int m = static_cast<int>(std::floor(offset / width_[0]));
    int first = c0 - m - 1 - reach_, last = c0 - m + reach_;
    auto run = [&](int from, int to, double s) {
      Run& r = out[count++];
      cc[0] = from;
      r.cell_begin = linear(cc);
      r.cell_end = r.cell_begin + (to - from) + 1;
      for (int k = 1; k < D; ++k) r.shift[perm_[k]] = shift[k];
      r.shift[perm_[0]] = s + offset;
    };
    if (last - first + 1 > n0) {  // fewer cells than the window: every cell its own image
      for (int c = first; c <= last; ++c) {
        int cell = 0;
        double s = 0.0;
        neighbour_index(c, 0, cell, s);
        run(cell, cell, s);
      }
      return;
    }
    const int wraps = first < 0 ? -((-first + n0 - 1) / n0) : first / n0;  // floor(first / n0)
    first -= wraps * n0, last -= wraps * n0;
    const double base = wraps * length_[0];
    run(first, std::min(last, n0 - 1), base);
    if (last >= n0) run(0, last - n0, base + length_[0]);
  }

  bool neighbour_index(int c, int d, int& out, double& shift) const {
    const int n = dims_[d];
    if (c >= 0 && c < n) {
      out = c;
      shift = 0.0;
      return true;
    }
    if (!periodic_[d]) return false;
    const int wraps = c < 0 ? -((-c + n - 1) / n) : c / n;  // floor(c / n)
    out = c - wraps * n;
    shift = wraps * length_[d];
    return true;
  }

  std::array<int, D> coords_unclamped(const Vec<D>& x) const {
    std::array<int, D> c{};
    for (int d = 0; d < D; ++d) {
      const double t = std::floor((x[perm_[d]] - lo_[d]) / width_[d]);
      c[d] = static_cast<int>(std::clamp(t, -1.0 - reach_, static_cast<double>(dims_[d] + reach_)));
      if (periodic_[d]) c[d] = std::clamp(c[d], 0, dims_[d] - 1);
    }
    return c;
  }
  std::array<int, D> coords(const Vec<D>& x) const {
    std::array<int, D> c = coords_unclamped(x);
    for (int d = 0; d < D; ++d) c[d] = std::clamp(c[d], 0, dims_[d] - 1);
    return c;
  }
  int linear(const std::array<int, D>& c) const {
    int lin = c[D - 1];
    for (int d = D - 2; d >= 0; --d) lin = lin * dims_[d] + c[d];
    return lin;
  }

  bool lees_edwards_ = false;
  double delta_ = 0.0;
  double min_cell_ = 1.0;
  int reach_ = 1;
  std::size_t max_cells_ = 0;
  PeriodicBox<D> box_;
  std::array<int, D> dims_{};  // per internal axis
  std::array<int, D> perm_ = identity();
  std::array<bool, D> periodic_{};
  static std::array<int, D> identity() {
    std::array<int, D> p{};
    for (int d = 0; d < D; ++d) p[d] = d;
    return p;
  }
  Vec<D> lo_ = Vec<D>::Zero(), width_ = Vec<D>::Ones(), length_ = Vec<D>::Zero();  // per internal axis
  std::vector<int> start_, cell_of_, items_, fill_;
  std::vector<int> marked_;  // marked_[c]: marked particles in cells before c
  bool sorted_ = false;
};

}  // namespace sph
