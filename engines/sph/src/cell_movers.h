// The particles other than fixed boundary ones (movers) of a CellList, cell by cell: the neighbour list
// (neighbour_list.h) lists a wall's row from them alone, since walls never pair with walls there.
#pragma once
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "cell_list.h"
#include "physics_terms.h"

namespace sph {

template <int D>
class CellMovers {
 public:
  // Room for n particles without allocating later.
  void reserve(std::size_t n) { items_.reserve(n); }

  // before_[c]: particles other than fixed boundary ones (movers) in the cells before c (particles sorted by
  // cell), items_ their indices in order (a run's movers: items_[before_[begin], before_[end])).
  // Walls never pair with walls when skip_walls, so a wall's row needs only the runs' movers:
  // the walls far from any fluid or buffer cost one look at their cell (not a sweep of its stencil),
  // the others a sweep of the movers around them only (the drill's walls outnumber its fluid 6 to 1).
  void count(const CellList<D>& cells, const std::vector<Kind>& kind) {
    const std::ptrdiff_t nc = cells.cell_count();
    if (before_.capacity() < static_cast<std::size_t>(nc) + 1) before_.reserve(nc + nc / 4 + 1);
    before_.resize(nc + 1);
    before_[0] = 0;
    if (items_.capacity() < kind.size()) items_.reserve(kind.size() + kind.size() / 4);
    items_.clear();
    for (std::ptrdiff_t c = 0; c < nc; ++c) {
      for (int i = cells.cell_begin(c), e = cells.cell_end(c); i < e; ++i)
        if (kind[i] != Kind::boundary) items_.push_back(i);
      before_[c + 1] = static_cast<int>(items_.size());
    }
  }
  // Whether a particle other than a fixed boundary one lies in the cell or its (2 reach + 1)^D stencil.
  // Without periodic axes the stencil is a box of cells clamped to the grid (rows along axis 0 are
  // contiguous); otherwise the cell list's runs (their shifts and Lees-Edwards rows) decide.
  bool around(const CellList<D>& cells, std::ptrdiff_t cell) const {
    if (before_[cell + 1] != before_[cell]) return true;
    const auto& dims = cells.dims();
    bool periodic = false;
    for (int d = 0; d < D; ++d) periodic = periodic || cells.periodic_internal(d);
    if (periodic) {
      typename CellList<D>::Run runs[CellList<D>::max_runs];
      const int nr = cells.runs_of_cell(cell, runs);
      for (int q = 0; q < nr; ++q)
        if (in(runs[q]) != 0) return true;
      return false;
    }
    const int reach = cells.reach();
    std::array<int, D> c{}, lo{}, hi{};
    for (int d = 0; d < D; ++d) {
      c[d] = static_cast<int>(cell % dims[d]);
      cell /= dims[d];
      lo[d] = std::max(0, c[d] - reach), hi[d] = std::min(dims[d] - 1, c[d] + reach);
    }
    std::array<int, D> o = lo;  // o[0] unused: a row lo[0]..hi[0] at a time
    while (true) {
      std::ptrdiff_t row = 0;
      for (int d = D - 1; d >= 1; --d) row = row * dims[d] + o[d];
      row *= dims[0];
      if (before_[row + hi[0] + 1] != before_[row + lo[0]]) return true;
      int d = 1;
      for (; d < D; ++d) {
        if (++o[d] <= hi[d]) break;
        o[d] = lo[d];
      }
      if (d == D) return false;
    }
  }
  // A run's movers: their number, and their indices [begin, end) in index order.
  int in(const typename CellList<D>::Run& r) const { return before_[r.cell_end] - before_[r.cell_begin]; }
  const int* begin(const typename CellList<D>::Run& r) const { return items_.data() + before_[r.cell_begin]; }
  const int* end(const typename CellList<D>::Run& r) const { return items_.data() + before_[r.cell_end]; }

 private:
  std::vector<int> before_, items_;
};

}  // namespace sph
