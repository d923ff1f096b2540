// Verlet half list with a skin, over particles sorted by cell, in blocks
// whose pair loops can run on several threads with a reduction order that
// does not depend on the schedule.
//
// Built from a CellList whose cells are at least (support + skin)/2 wide
// (reach 2): every pair closer than support + skin at the build is listed
// once (half list), at its owner. The list stays valid while no particle has
// moved more than skin/2 since the build (the caller checks).
//
// Blocks: the particles are sorted by cell with the last axis slowest, so a
// slab of cell layers along the last axis is a range of particle indices.
// Block k holds layers 2k, 2k+1 (the last block also a third when the count
// is odd). A listed pair spans at most two layers (cells >= range/2), so its
// two particles lie in one block or in two neighbouring ones. Owner: within a
// block the lower index (for a particle and its own periodic image, the
// image with the larger shift code); across blocks the particle of block k
// for a pair with block k+1 (cyclically along a periodic last axis). So the
// pair loop of block k writes only to blocks k and k+1.
//
// Colours: blocks of one colour write to disjoint particles; the pair loop
// runs colour after colour (on threads: a block starts when its neighbouring
// blocks of earlier colours are done, see for_blocks_coloured), each block by
// one thread in index order. Every particle therefore receives its
// contributions in the same order whatever the number of threads: results
// are bitwise independent of the thread count. Even/odd blocks; along a
// periodic last axis with an odd count the last block gets a third colour;
// with fewer than 3 blocks there (or 2 layers in all) one block holds everything.
#pragma once
#include <omp.h>

#include <sched.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

#include "box_policy.h"
#include "cell_list.h"
#include "cell_movers.h"
#include "physics_terms.h"
#include "vec.h"

namespace sph {

template <int D>
class NeighbourList {
 public:
  // An entry packs the neighbour's index b (upper bits) and the code of the
  // periodic image it is seen at (lower 7 bits: (k_d + 2) 5^d for a shift of
  // k_d box lengths along axis d, k_d in -2..2).
  static constexpr int shift_bits = 7;
  static constexpr std::uint32_t shift_mask = (1u << shift_bits) - 1;
  static constexpr int centre_code = PeriodicImages<D>::centre_code;  // no shift

  // A particle's entries: [begin, mid) fluid neighbours, [mid, end) the others, in its block's list.
  struct Row {
    int begin, mid, end;
  };

  // The image policy (held by reference: its shift table changes with time under Lees-Edwards). With
  // split_at > 0 a row's fluid neighbours closer than split_at at the build come first, those of the skin after
  // them (pair_lanes.h skips groups of four beyond the support).
  void configure(const PeriodicImages<D>& images, double split_at = 0.0) {
    images_ = &images;
    box_ = images.box();
    split2_ = split_at * split_at;
  }

  // Room for n particles (rows, block ids) without allocating later.
  void reserve(std::size_t n) {
    rows_.reserve(n);
    block_of_.reserve(n);
    movers_.reserve(n);
  }

  // List the pairs of x[0..n) closer than `range` (kind: fluid first in each
  // row; pairs of two fixed boundary particles left out when skip_walls).
  void build(const CellList<D>& cells, const std::vector<Vec<D>>& x, const std::vector<Kind>& kind, double range,
             bool skip_walls) {
    const int layer_cells = plan_blocks(cells, x.size());
    const int nb = blocks_;
    const double range2 = range * range;
    if (skip_walls) movers_.count(cells, kind);
    auto build_block = [&](int k) {
      for (int i = begin_[k]; i < begin_[k + 1]; ++i) block_of_[i] = k;
    };
    auto list_block = [&](int k) { list_block_pairs(cells, x, kind, range2, skip_walls, layer_cells, k); };
    if (omp_get_max_threads() > 1 && nb > 1) {
#pragma omp parallel
      {
#pragma omp for schedule(static)
        for (int k = 0; k < nb; ++k) build_block(k);
        // Most pairs of the last build first (the list does not depend on the thread that builds it).
        const bool planned = static_cast<int>(build_order_.size()) == nb;
#pragma omp for schedule(dynamic, 1)
        for (int j = 0; j < nb; ++j) list_block(planned ? build_order_[j] : j);
      }
    } else {
      for (int k = 0; k < nb; ++k) build_block(k);
      for (int k = 0; k < nb; ++k) list_block(k);
    }
    // Headroom, so later builds rarely allocate: every block's list has room
    // for 1.25 x the largest block's pairs (particles move between blocks, so
    // a block's count changes from build to build).
    std::size_t biggest = 0;
    for (int k = 0; k < nb; ++k) biggest = std::max(biggest, lists_[k].size());
    for (int k = 0; k < nb; ++k)
      if (lists_[k].capacity() < biggest + biggest / 4) lists_[k].reserve(biggest + biggest / 2);
    plan_schedule(nb);
  }

  // body(k) for every block, colour after colour; on the threads when
  // `parallel` (call inside an omp parallel region then, from every thread).
  // On the threads there is no barrier between colours: a thread takes the
  // next block of the queue (colour after colour, most pairs first) and waits
  // until its neighbouring blocks of earlier colours are done, so every
  // particle still receives the contributions of its two blocks in colour
  // order, as with a barrier between colours (bitwise the same results), but
  // a thread short of work in one colour goes on with the next (the 3D dam
  // break has 3 or 4 blocks with fluid per colour: with a barrier per colour
  // its pair counts bound the 2-thread pair loop to 1.67-1.80 x). The queue
  // and the done flags are reset by the master thread after the closing
  // barrier, so a pass needs no barrier at its start; two passes on the
  // threads must be separated by a barrier (a worksharing loop or the end of
  // the region: so they are in Simulation).
  template <class Body>
  void for_blocks_coloured(bool parallel, Body&& body) const {
    if (!parallel) {
      for (const auto& colour : colours_)
        for (int k : colour) body(k);
      return;
    }
    const int total = static_cast<int>(queue_.size());
    for (int t; (t = next_.fetch_add(1, std::memory_order_relaxed)) < total;) {
      const int k = queue_[t];
      for (int j : after_[k])
        for (int spins = 0; j >= 0 && !done_[j].load(std::memory_order_acquire); ++spins)
          if (spins > 100) sched_yield();
      body(k);
      done_[k].store(1, std::memory_order_release);
    }
#pragma omp barrier
#pragma omp master
    reset_queue();  // published to the other threads by the barrier before the next pass
  }

  // The particles `changed` turned fluid or from fluid into buffer particles since the build (open
  // boundaries' conversions; kind: now): move each one's entries to the right part of every row that
  // lists it ([begin, mid) fluid, [mid, end) the others), so the list holds without a rebuild. x_build:
  // the positions at the build, whose binning `cells` still holds; a row that lists c belongs to a
  // particle of the stencil around c's cell. A row's entries change order (one swap each), not the pairs.
  void reclassify(const CellList<D>& cells, const std::vector<Vec<D>>& x_build, const std::vector<Kind>& kind,
                  const std::vector<std::size_t>& changed) {
    for (std::size_t c : changed) reclassify_one(cells, x_build[c], static_cast<int>(c), kind[c] == Kind::fluid);
  }
  void reclassify_one(const CellList<D>& cells, const Vec<D>& x_build_c, int c, bool now_fluid) {
    using Run = typename CellList<D>::Run;
    Run runs[CellList<D>::max_runs];
    const int nr = cells.runs(x_build_c, runs);
    const std::uint32_t target = static_cast<std::uint32_t>(c);
    for (int q = 0; q < nr; ++q)
      for (int a = cells.item_begin(runs[q]), end = cells.item_end(runs[q]); a < end; ++a) {
        Row& row = rows_[a];
        std::uint32_t* e = lists_[block_of_[a]].data();
        if (now_fluid) {
          for (int j = row.mid; j < row.end; ++j)
            if ((e[j] >> shift_bits) == target) std::swap(e[j], e[row.mid++]);
        } else {
          for (int j = row.begin; j < row.mid;)
            if ((e[j] >> shift_bits) == target) std::swap(e[j], e[--row.mid]);
            else ++j;
        }
      }
  }

  int blocks() const { return blocks_; }
  int block_begin(int k) const { return begin_[k]; }
  int block_end(int k) const { return begin_[k + 1]; }
  const Row& row(int a) const { return rows_[a]; }
  const std::uint32_t* entries(int k) const { return lists_[k].data(); }
  const Vec<D>* shifts() const { return images_->shifts(); }
  const Vec<D>* jumps() const { return images_->jumps(); }  // velocity jump per image code (Lees-Edwards)
  std::size_t pair_count() const {
    std::size_t s = 0;
    for (int k = 0; k < blocks_; ++k) s += lists_[k].size();
    return s;
  }

 private:
  int code_of(const Vec<D>& shift) const { return images_->code_of(shift); }

  // The blocks of n particles sorted into `cells` (their particle ranges and colours, see the top of the file);
  // returns the number of cells in a layer along the last axis.
  int plan_blocks(const CellList<D>& cells, std::size_t n) {
    rows_.resize(n);
    block_of_.resize(n);
    const auto& dims = cells.dims();
    const int layers = dims[D - 1];
    int layer_cells = 1;
    for (int d = 0; d + 1 < D; ++d) layer_cells *= dims[d];
    periodic_last_ = cells.periodic_internal(D - 1);
    int nb = std::max(1, layers / 2);
    if (periodic_last_ && nb < 3) nb = 1;
    blocks_ = nb;
    if (static_cast<int>(lists_.size()) < nb) lists_.resize(nb), others_.resize(nb), skins_.resize(nb);
    if (static_cast<int>(begin_.size()) < nb + 1) begin_.resize(nb + 1);
    for (int k = 0; k < nb; ++k) begin_[k] = cells.cell_begin(static_cast<std::ptrdiff_t>(2 * k) * layer_cells);
    begin_[0] = 0;
    begin_[nb] = static_cast<int>(n);
    for (auto& c : colours_) c.clear();
    for (int k = 0; k < nb; ++k) {
      int colour = k % 2;
      if (periodic_last_ && nb % 2 == 1 && k == nb - 1 && nb > 1) colour = 2;
      colours_[colour].push_back(k);
    }
    return layer_cells;
  }

  // The rows of block k's particles, cell by cell, into lists_[k].
  void list_block_pairs(const CellList<D>& cells, const std::vector<Vec<D>>& x, const std::vector<Kind>& kind,
                        double range2, bool skip_walls, int layer_cells, int k) {
    std::vector<std::uint32_t>& list = lists_[k];
    list.clear();
    typename CellList<D>::Run runs[CellList<D>::max_runs];
    int codes[CellList<D>::max_runs];
    const std::ptrdiff_t first_cell = static_cast<std::ptrdiff_t>(2 * k) * layer_cells;
    const std::ptrdiff_t last_cell =
        k + 1 == blocks_ ? cells.cell_count() : static_cast<std::ptrdiff_t>(2 * (k + 1)) * layer_cells;
    for (std::ptrdiff_t cell = first_cell; cell < last_cell; ++cell) {
      const int first = cells.cell_begin(cell), last = cells.cell_end(cell);
      if (first == last) continue;
      if (skip_walls && !movers_.around(cells, cell)) {  // only boundary particles here, none other in reach: their rows are empty
        for (int a = first; a < last; ++a) rows_[a] = {static_cast<int>(list.size()), static_cast<int>(list.size()),
                                                       static_cast<int>(list.size())};
        continue;
      }
      const int nr = cells.runs_of_cell(cell, runs);
      for (int q = 0; q < nr; ++q) codes[q] = code_of(runs[q].shift);
      std::vector<std::uint32_t>& others = others_[k];
      if (others.capacity() < 4096) others.reserve(4096);  // a row's non-fluid neighbours: no growth later
      if (skins_[k].capacity() < 4096) skins_[k].reserve(4096);
      for (int a = first; a < last; ++a) list_row(cells, x, kind, range2, skip_walls, k, runs, codes, nr, a);
    }
  }

  // Particle a's row of block k from the runs of cells around its cell (and their image codes).
  inline __attribute__((always_inline)) void list_row(const CellList<D>& cells, const std::vector<Vec<D>>& x,
                                                      const std::vector<Kind>& kind, double range2, bool skip_walls,
                                                      int k, const typename CellList<D>::Run* runs, const int* codes,
                                                      int nr, int a) {
    std::vector<std::uint32_t>& list = lists_[k];
    std::vector<std::uint32_t>& others = others_[k];
    std::vector<std::uint32_t>& skin = skins_[k];
    const int nb = blocks_;
    Row& row = rows_[a];
    const bool a_wall = kind[a] == Kind::boundary;
    row.begin = static_cast<int>(list.size());
    others.clear(), skin.clear();
    // One sweep over the candidates: fluid neighbours go to the list,
    // the others to a side buffer appended after them (the row's
    // [mid, end)). Two sweeps (fluid, then the others) cost the 2D dam
    // break a fifth of its run time.
    const bool only_movers = skip_walls && a_wall;  // a wall's row lists no wall
    for (int q = 0; q < nr; ++q) {
      if (only_movers && movers_.in(runs[q]) == 0) continue;  // no candidate of this run would be listed
      // A run's cells lie in one layer, so in one block kb: a owns none of it when kb is block k - 1,
      // all of it when kb is k + 1, and in its own block the particles from `from` on (owns); the sweep
      // skips the rest (half the candidates; the same pairs in the same order).
      int from = cells.item_begin(runs[q]);
      if (from == cells.item_end(runs[q])) continue;
      const int kb = block_of_[from];
      if (kb == k) from = std::max(from, codes[q] > centre_code ? a : a + 1);
      else if (!(kb == k + 1 || (periodic_last_ && k == nb - 1 && kb == 0))) continue;
      const Vec<D> xs = x[a] - runs[q].shift;
      const std::uint32_t code = static_cast<std::uint32_t>(codes[q]);
      auto candidate = [&](int b) {
        const double r2 = (xs - x[b]).squaredNorm();
        if (r2 >= range2) return;
        if (!owns(a, b, codes[q], k)) return;  // also drops a itself at the centre image
        const std::uint32_t entry = static_cast<std::uint32_t>(b) << shift_bits | code;
        if (kind[b] == Kind::fluid) {
          (r2 < split2_ || split2_ == 0.0 ? list : skin).push_back(entry);
        } else if (!(skip_walls && a_wall && kind[b] == Kind::boundary)) {
          others.push_back(entry);
        }
      };
      if (only_movers) {  // the run's movers only, in index order (the others would be dropped)
        const int* const first_mover = movers_.begin(runs[q]);
        const int* const end = movers_.end(runs[q]);
        for (const int* m = std::lower_bound(first_mover, end, from); m < end; ++m) candidate(*m);
      } else {
        for (int b = from, end = cells.item_end(runs[q]); b < end; ++b) candidate(b);
      }
    }
    list.insert(list.end(), skin.begin(), skin.end());
    row.mid = static_cast<int>(list.size());
    list.insert(list.end(), others.begin(), others.end());
    row.end = static_cast<int>(list.size());
  }


  // The queue of for_blocks_coloured: colour after colour, in a colour most
  // pairs first (ties: lower index; the last block a thread takes is a small
  // one); and per block its neighbouring blocks of earlier colours (-1: none).
  void plan_schedule(int nb) {
    for (auto& c : colours_)
      std::sort(c.begin(), c.end(), [this](int a, int b) {
        return lists_[a].size() > lists_[b].size() || (lists_[a].size() == lists_[b].size() && a < b);
      });
    queue_.clear();
    for (const auto& c : colours_) queue_.insert(queue_.end(), c.begin(), c.end());
    build_order_.assign(queue_.begin(), queue_.end());
    std::sort(build_order_.begin(), build_order_.end(), [this](int a, int b) {
      return lists_[a].size() > lists_[b].size() || (lists_[a].size() == lists_[b].size() && a < b);
    });
    if (static_cast<int>(after_.size()) < nb) after_.resize(nb), colour_of_.resize(nb);
    for (int c = 0; c < 3; ++c)
      for (int k : colours_[c]) colour_of_[k] = c;
    for (int k = 0; k < nb; ++k) {
      int below = k - 1, above = k + 1;
      if (periodic_last_ && nb > 1) below = (k + nb - 1) % nb, above = (k + 1) % nb;
      after_[k] = {-1, -1};
      if (below >= 0 && below != k && colour_of_[below] < colour_of_[k]) after_[k][0] = below;
      if (above < nb && above != k && colour_of_[above] < colour_of_[k]) after_[k][1] = above;
    }
    if (done_capacity_ < nb) done_.reset(new std::atomic<int>[nb]), done_capacity_ = nb;
    reset_queue();
  }
  // No block taken, none done (for the next pass of for_blocks_coloured).
  void reset_queue() const {
    next_.store(0, std::memory_order_relaxed);
    for (int k = 0; k < blocks_; ++k) done_[k].store(0, std::memory_order_relaxed);
  }
  // Whether a (of block ka) owns its pair with b seen at shift `code`.
  bool owns(int a, int b, int code, int ka) const {
    const int kb = block_of_[b];
    if (kb == ka) return a < b || (a == b && code > centre_code);
    if (kb == ka + 1) return true;
    return periodic_last_ && ka == blocks_ - 1 && kb == 0;
  }

  const PeriodicImages<D>* images_ = nullptr;
  PeriodicBox<D> box_;
  std::vector<Row> rows_;
  std::vector<int> block_of_, begin_;
  CellMovers<D> movers_;  // a wall's candidates (skip_walls)
  std::vector<std::vector<std::uint32_t>> lists_;
  std::vector<std::vector<std::uint32_t>> others_;  // per block: a row's non-fluid neighbours while it is built
  std::vector<std::vector<std::uint32_t>> skins_;   // per block: its fluid neighbours beyond split_at (split2_ > 0)
  double split2_ = 0.0;                             // m^2
  std::array<std::vector<int>, 3> colours_;
  std::vector<int> queue_, colour_of_;                 // for_blocks_coloured's order; each block's colour
  std::vector<int> build_order_;                       // every block, most pairs first (the next build's order)
  std::vector<std::array<int, 2>> after_;              // per block: neighbours of earlier colours it waits for
  mutable std::atomic<int> next_{0};                   // the next queue entry to take
  mutable std::unique_ptr<std::atomic<int>[]> done_;   // per block: done in this pass
  int done_capacity_ = 0;
  int blocks_ = 0;
  bool periodic_last_ = false;
};

}  // namespace sph
