// The weakly compressible SPH solver for one dimension and one compile-time set of terms.
//
// Rates are gathered per particle (each particle sums over its own
// neighbours), so the result does not depend on the OpenMP schedule. Time
// integration is Monaghan's predictor-corrector leapfrog with one rate
// evaluation per step, at the half step (a PEC scheme). a^(n-1/2), Drho^(n-1/2)
// are the rates of the previous step's evaluation (of the initial state before
// the first step):
//   predictor  x* = x + dt/2 v,  v* = v + dt/2 a^(n-1/2),  rho* = rho + dt/2 Drho^(n-1/2)
//   evaluate   a* = a(x*, v*, rho*),  Drho* = Drho(x*, v*, rho*)   (kept as the next step's a^(n-1/2))
//   corrector  v' = v + dt a*,  rho' = rho + dt Drho*,  x' = x + dt (v + dt/2 a*) = x + dt (v + v')/2
// Fixed boundary particles keep position and velocity and evolve their density;
// inlet and outlet buffer particles do the same but move at their velocity.
#pragma once
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "cell_list.h"
#include "deck.h"
#include "eos.h"
#include "kernel.h"
#include "particles.h"
#include "physics_terms.h"
#include "wall_penalty.h"

namespace sph {

// Pass as `crossed` when no flow plane needs the particle displacements.
struct NoCrossings {
  template <class... Args>
  void operator()(Args&&...) const {}
};

struct StabilityReport {
  bool ok = true;
  std::string message;
};

template <int D, unsigned Terms>
class Simulation {
 public:
  using Model = FluidModel<D, Terms>;
  static constexpr bool has(unsigned t) { return Model::has(t); }

  // Cells of half the support (5^D stencil) test fewer far pairs than cells
  // of the full support (3^D): 25 h^2 against 36 h^2 of area in 2D, where the
  // branch-free candidate filter made that the faster choice too (measured).
  static constexpr int cell_reach = 2;

  Simulation(const Deck& deck, Particles<D> particles, WallPenalty<D> walls = {})
      : deck_(deck), P_(std::move(particles)), kernel_(deck.h), eos_{deck.rho0, deck.c0, deck.gamma,
                                                                       deck.background_pressure},
        walls_(std::move(walls)) {
    const double eta2 = 0.01 * deck.h * deck.h;
    model_.morris.mu = deck.rho0 * deck.viscosity;
    model_.morris.eta2 = eta2;
    model_.artificial = {deck.alpha, deck.beta, deck.h, eta2};
    if (!deck.body_force.empty())
      for (int d = 0; d < D; ++d) model_.body.g[d] = deck.body_force[d];
    for (std::size_t i = 0; i < deck.periodic_axes.size(); ++i) {
      const int a = deck.periodic_axes[i];
      box_.periodic[a] = true;
      box_.lo[a] = deck.periodic_lo[i];
      box_.hi[a] = deck.periodic_hi[i];
    }
    for (auto& x : P_.x) box_.wrap(x);
    walls_together_ = true;
    const Vec<D>* wall_velocity = nullptr;
    for (std::size_t i = 0; i < P_.size(); ++i)
      if (P_.kind[i] == Kind::boundary) {
        if (!wall_velocity) wall_velocity = &P_.v[i];
        walls_together_ = walls_together_ && P_.v[i] == *wall_velocity;
      }
    const std::size_t n = P_.size();
    P_.resize(n);
    cells_.reserve(P_.x.capacity());
    x_pred_.reserve(P_.x.capacity());
    cells_.configure(kernel_.support_radius(), cell_reach, box_, std::max<std::size_t>(64 * n, 1u << 22));
    sort_particles();
    equation_of_state();
  }

  Particles<D>& particles() { return P_; }
  const Particles<D>& particles() const { return P_; }
  const CellList<D>& cells() const { return cells_; }
  const WendlandC2<D>& kernel() const { return kernel_; }
  const TaitEos& eos() const { return eos_; }
  const PeriodicBox<D>& box() const { return box_; }
  const WallPenalty<D>& walls() const { return walls_; }

  // Bin and reorder the particles by cell (memory locality); false if they blew apart.
  bool sort_particles() {
    if (!cells_.build(P_.x, P_.size())) return false;
    P_.reorder(cells_.items());
    cells_.mark_sorted();
    mark_cells();
    return true;
  }

  // Pressure (and sound speed) of every particle from its density, eq. 6.
  // A fixed boundary particle never pulls: its pressure is that of
  // max(rho, rho0), so a wall under a free surface does not suck fluid in.
  void equation_of_state() {
    parallel_for(P_.size(), parallel_min_light, [this](std::ptrdiff_t i) { equation_of_state_at(i); });
  }
  void equation_of_state_at(std::ptrdiff_t i) {
    const double rho = P_.kind[i] == Kind::boundary ? std::max(P_.rho[i], deck_.rho0) : P_.rho[i];
    P_.p[i] = eos_.pressure(rho);
    if constexpr (has(term::artificial_viscosity)) P_.c[i] = eos_.sound_speed(rho);
    P_.vol[i] = P_.mass[i] / P_.rho[i];
    P_.p_rho2[i] = P_.p[i] / (P_.rho[i] * P_.rho[i]);
  }

  // acc and drho of every particle at the current x, v, rho; cells must be binned for x.
  void compute_rates() {
    rates_ready_ = true;
    maxima_.valid = false;  // acc changes
    const std::ptrdiff_t n = P_.size(), ncell = cells_.cell_count();
    assert(cells_.sorted());
    if (go_parallel(n, parallel_min_heavy)) {
      // One parallel region per evaluation (starting one costs a thread wake-up).
#pragma omp parallel
      {
#pragma omp for schedule(static)
        for (std::ptrdiff_t i = 0; i < n; ++i) equation_of_state_at(i);
        if constexpr (has(term::morris_viscosity)) {
#pragma omp for schedule(dynamic, 256)
          for (std::ptrdiff_t b = 0; b < n; ++b) no_slip_velocity_at(b);
        }
#pragma omp for schedule(dynamic, 16) nowait
        for (std::ptrdiff_t cell = 0; cell < ncell; ++cell) rates_of_cell(cell);
      }
    } else {
      for (std::ptrdiff_t i = 0; i < n; ++i) equation_of_state_at(i);
      if constexpr (has(term::morris_viscosity))
        for (std::ptrdiff_t b = 0; b < n; ++b) no_slip_velocity_at(b);
      for (std::ptrdiff_t cell = 0; cell < ncell; ++cell) rates_of_cell(cell);
    }
  }

  // The rates of the particles of one cell: they share their runs of neighbour cells.
  void rates_of_cell(std::ptrdiff_t cell) {
    using Run = typename CellList<D>::Run;
    const int first = cells_.cell_begin(cell), last = cells_.cell_end(cell);
    if (first == last) return;
    Run runs[CellList<D>::max_runs];
    const int nr = cells_.runs_of_cell(cell, runs);
    for (int a = first; a < last; ++a) {
      if (P_.moves(a)) {
        PairRates<D> r = gather<true>(a, runs, nr);
        if constexpr (has(term::body_force)) model_.body.add(r.acc);
        if constexpr (has(term::wall_penalty)) r.acc += walls_.force(P_.x[a]) / P_.mass[a];
        P_.acc[a] = r.acc;
        P_.drho[a] = r.drho;
      } else {
        P_.acc[a].setZero();
        // Outlet particles keep the density they left with (a zero-gradient outlet).
        P_.drho[a] = P_.kind[a] == Kind::outlet ? 0.0 : gather<false>(a, runs, nr).drho;
      }
    }
  }

  // No-slip at fixed boundary particles for the viscous term: a boundary
  // particle b takes 2 v_b - v~_b, with v~_b the Shepard average of the fluid
  // velocity around it, so the fluid sees the velocity mirrored through the
  // wall (as Adami et al. 2012). Its own v_b (the wall's velocity) is unchanged.
  void no_slip_velocities() {
    parallel_for(P_.size(), parallel_min_heavy, [this](std::ptrdiff_t b) { no_slip_velocity_at(b); });
  }
  void no_slip_velocity_at(std::ptrdiff_t b) {
    if (P_.kind[b] != Kind::boundary) {
      P_.v_noslip[b] = P_.v[b];
      return;
    }
    const double support2 = kernel_.support_radius() * kernel_.support_radius();
    Vec<D> sum = Vec<D>::Zero();
    double weight = 0.0;
    const Vec<D> xb = P_.x[b];
    cells_.for_each_neighbour(xb, [&](int f, const Vec<D>& shift) {
      if (!P_.moves(f)) return;
      const double r2 = (xb - P_.x[f] - shift).squaredNorm();
      if (r2 >= support2) return;
      const double w = kernel_.value(std::sqrt(r2));
      sum += w * P_.v[f];
      weight += w;
    });
    P_.v_noslip[b] = weight > 0.0 ? Vec<D>(2.0 * P_.v[b] - sum / weight) : P_.v[b];
  }

  // A particle of mass m appears (sign +1) or disappears (-1) at x: change the
  // density of the fixed boundary particles around it by its kernel share
  // m W, as a summation density would, so continuity does not keep a memory
  // of particles that an inlet created or an outlet removed. Boundary
  // particles never move, so the cells of the last binning still hold them.
  void boundary_density_event(const Vec<D>& x, double m, double sign) {
    Vec<D> xj = x;
    box_.wrap(xj);
    const double support2 = kernel_.support_radius() * kernel_.support_radius();
    cells_.for_each_neighbour(xj, [&](int b, const Vec<D>& shift) {
      if (static_cast<std::size_t>(b) >= P_.size() || P_.kind[b] != Kind::boundary) return;
      const double r2 = (P_.x[b] + shift - xj).squaredNorm();
      if (r2 < support2) P_.rho[b] += sign * m * kernel_.value(std::sqrt(r2));
    });
  }

  // Time step of eq. 13 extended by the viscous and force criteria, from the
  // rates just computed: min(cfl h/(c0 + v_max), viscous h^2/nu, force sqrt(h/a_max)).
  double adaptive_dt() {
    const StepMaxima& m = maxima();
    const double h = deck_.h;
    double dt = deck_.cfl * h / (deck_.c0 + std::sqrt(m.v2));
    if constexpr (has(term::morris_viscosity)) dt = std::min(dt, deck_.viscous_factor * h * h / deck_.viscosity);
    if (m.a2 > 0.0) dt = std::min(dt, deck_.force_factor * std::sqrt(h / std::sqrt(m.a2)));
    return dt;
  }

  // Forget the maxima the corrector took (call after adding, removing or changing particles).
  void forget_maxima() { maxima_.valid = false; }

  // Rates of the initial state, before the first step (later steps reuse the
  // rates of the previous step's half-step evaluation); cells must be binned.
  void ensure_rates() {
    if (!rates_ready_) compute_rates();
  }

  // Predictor: half step with the rates of the last evaluation, binning of the
  // predicted positions, and reordering by cell (the only binning of a step),
  // in three passes over the particles, each on the threads:
  //   1. predicted positions (by old index) and their bounding box;
  //   2. their cells (then the counting sort, serial);
  //   3. for each new index k, from old index o: the start-of-step state
  //      x0, v0, rho0, the persistent state and the predicted v, rho.
  // False if the predicted particles spread over too many cells (blow-up);
  // then x0, v0, rho0 hold the start-of-step state, for the last good frame.
  bool predict(double dt) {
    const double half = 0.5 * dt;
    const std::ptrdiff_t n = P_.size();
    x_pred_.resize(n);
    double lo[D], hi[D];
    for (int d = 0; d < D; ++d) lo[d] = std::numeric_limits<double>::infinity(), hi[d] = -lo[d];
    auto position = [this, half](std::ptrdiff_t i, double* lo, double* hi) {
      Vec<D> x = P_.x[i];
      if (P_.advects(i)) {  // fixed boundary particles stay
        x += half * P_.v[i];
        box_.wrap(x);
      }
      x_pred_[i] = x;
      for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
    };
    if (go_parallel(n, parallel_min_light)) {
#pragma omp parallel for reduction(min : lo[:D]) reduction(max : hi[:D]) schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi);
    } else {
      for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi);
    }
    if (!cells_.lay_out(Eigen::Map<const Vec<D>>(lo), Eigen::Map<const Vec<D>>(hi), n)) {
      P_.x0 = P_.x, P_.v0 = P_.v, P_.rho0 = P_.rho;
      return false;
    }
    parallel_for(n, parallel_min_light, [this](std::ptrdiff_t i) { cells_.assign(i, x_pred_[i]); });
    cells_.sort_assigned();
    std::vector<int>& order = cells_.items_for_reorder();
    P_.size_next();
    auto& N = P_.next;
    parallel_for(n, parallel_min_light, [&, half](std::ptrdiff_t k) {
      const int o = order[k];
      order[k] = static_cast<int>(k);
      P_.x0[k] = P_.x[o], P_.v0[k] = P_.v[o], P_.rho0[k] = P_.rho[o];
      N.mass[k] = P_.mass[o], N.kind[k] = P_.kind[o], N.id[k] = P_.id[o];
      N.acc[k] = P_.acc[o], N.drho[k] = P_.drho[o];
      N.x[k] = x_pred_[o];
      N.rho[k] = P_.rho[o] + half * P_.drho[o];
      N.v[k] = P_.advects(o) ? Vec<D>(P_.v[o] + half * P_.acc[o]) : P_.v[o];  // acc is zero for all but fluid
    });
    P_.swap_next();
    cells_.mark_sorted_in_place();
    mark_cells();
    return true;
  }

  // Corrector with the mid-step rates; in the same pass, the maxima that the
  // stability check and the next adaptive step read. Displacements are handed
  // to `crossed` (x_old, dx, volume) before wrapping, for flow-rate planes.
  template <class Crossed>
  void correct(double dt, Crossed&& crossed) {
    const std::ptrdiff_t n = P_.size();
    maxima_ = sweep_maxima([this, dt](std::ptrdiff_t i) {
      P_.rho[i] = P_.rho0[i] + dt * P_.drho[i];
      if (!P_.advects(i)) return;
      const Vec<D> dx = dt * (P_.v0[i] + 0.5 * dt * P_.acc[i]);
      P_.v[i] = P_.v0[i] + dt * P_.acc[i];
      P_.x[i] = P_.x0[i] + dx;
      box_.wrap(P_.x[i]);
    });
    if constexpr (!std::is_same_v<std::decay_t<Crossed>, NoCrossings>)
      for (std::ptrdiff_t i = 0; i < n; ++i)
        if (P_.moves(i)) crossed(P_.x0[i], Vec<D>(dt * (P_.v0[i] + 0.5 * dt * P_.acc[i])), P_.mass[i] / P_.rho[i]);
  }

  // One full step: one rate evaluation, at the half step. False if the
  // predicted particles spread over too many cells (blow-up).
  template <class Crossed>
  bool step(double dt, Crossed&& crossed) {
    ensure_rates();
    if (!predict(dt)) return false;
    compute_rates();
    correct(dt, crossed);
    return true;
  }

  // NaN anywhere, or a fluid particle whose density deviates from rho0 by more
  // than the threshold or that is faster than c0. (Boundary and buffer
  // densities are devices of the wall and open-boundary models.)
  StabilityReport check_stability() {
    const StepMaxima& m = maxima();
    if (!m.finite) return {false, "a particle's position, velocity or density is not finite"};
    if (m.worst_rho > deck_.max_density_deviation)
      return {false, "density deviates from rho0 by " + std::to_string(100.0 * m.worst_rho) + " % (limit " +
                         std::to_string(100.0 * deck_.max_density_deviation) + " %)"};
    if (m.v2 > deck_.c0 * deck_.c0)
      return {false, "a particle moves at " + std::to_string(std::sqrt(m.v2)) + " m/s, faster than c0 = " +
                         std::to_string(deck_.c0) + " m/s"};
    return {};
  }

  // max |rho/rho0 - 1| over the fluid particles.
  double max_density_deviation() const {
    double worst = 0.0;
    for (std::size_t i = 0; i < P_.size(); ++i)
      if (P_.moves(i)) worst = std::max(worst, std::abs(P_.rho[i] / deck_.rho0 - 1.0));
    return worst;
  }

 private:
  // Per cell, the particles that are not fixed boundary particles (gather<false> skips cells without them).
  void mark_cells() {
    const Kind* const kind = P_.kind.data();
    cells_.mark([kind](int i) { return kind[i] != Kind::boundary; });
  }

  // Over the particles after a corrector: largest |rho/rho0 - 1| and |v|^2 of
  // the fluid, largest |dv/dt|^2 of the fluid (last evaluation), and whether
  // every position, velocity and density is finite.
  struct StepMaxima {
    double worst_rho = 0.0, v2 = 0.0, a2 = 0.0;
    bool finite = true;
    bool valid = false;
  };
  void take_maxima(std::ptrdiff_t i, double& worst_rho, double& v2, double& a2, bool& finite) const {
    // One test for all: a sum is finite only when every term is (inf - inf is NaN).
    finite = finite && std::isfinite(P_.rho[i] + P_.x[i].sum() + P_.v[i].sum());
    if (!P_.moves(i)) return;
    worst_rho = std::max(worst_rho, std::abs(P_.rho[i] / deck_.rho0 - 1.0));
    v2 = std::max(v2, P_.v[i].squaredNorm());
    a2 = std::max(a2, P_.acc[i].squaredNorm());
  }
  // update(i) for every particle, then its part of the maxima (one pass, on the threads).
  template <class Update>
  StepMaxima sweep_maxima(Update&& update) {
    const std::ptrdiff_t n = P_.size();
    double worst_rho = 0.0, v2 = 0.0, a2 = 0.0;
    bool finite = true;
    auto body = [&](std::ptrdiff_t i, double& w, double& v, double& a, bool& f) {
      update(i);
      take_maxima(i, w, v, a, f);
    };
    if (go_parallel(n, parallel_min_light)) {
#pragma omp parallel for reduction(max : worst_rho, v2, a2) reduction(&& : finite) schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) body(i, worst_rho, v2, a2, finite);
    } else {
      for (std::ptrdiff_t i = 0; i < n; ++i) body(i, worst_rho, v2, a2, finite);
    }
    return {worst_rho, v2, a2, finite, true};
  }
  // The maxima of the current state: the corrector's, or taken now.
  const StepMaxima& maxima() {
    if (!maxima_.valid) maxima_ = sweep_maxima([](std::ptrdiff_t) {});
    return maxima_;
  }

  // Neighbours within 2h summed per batch by gather() (more are summed in several batches).
  static constexpr int batch = 128;

  // Sum the pair terms over the neighbours of particle a, given the runs of
  // cells around a's cell (particles sorted by cell: a run is a range of
  // particle indices). The candidates of the runs are first filtered, without a branch, to those
  // within 2h into a small batch; the pair terms then run over the batch
  // without a distance test. The order of the sum is the cell order: fixed
  // for a given binning, whatever the thread schedule. A fixed boundary
  // particle (Moves = false) skips the other boundary particles when all walls
  // move together (`walls_together_`: their pairs add exactly zero), and
  // gathers nothing when no fluid or buffer particle is in its cells.
  template <bool Moves>
  PairRates<D> gather(int a, const typename CellList<D>::Run* runs, int nr) const {
    const Vec<D>* const x = P_.x.data();
    const Kind* const kind = P_.kind.data();
    const double support2 = kernel_.support_radius() * kernel_.support_radius();
    const bool movers_only = !Moves && walls_together_ && kind[a] == Kind::boundary;
    PairRates<D> r;
    if (movers_only) {
      int movers = 0;
      for (int q = 0; q < nr; ++q) movers += cells_.marked(runs[q]);
      if (movers == 0) return r;
    }
    const Vec<D> xa = x[a];
    int nb[batch];
    Vec<D> rab[batch];
    double r2s[batch];
    int n = 0;
    for (int q = 0; q < nr; ++q) {
      const Vec<D> xs = xa - runs[q].shift;  // the image of a seen from the run's images of b
      const int end = cells_.item_end(runs[q]);
      for (int k = cells_.item_begin(runs[q]); k < end; ++k) {
        const int b = k;
        const Vec<D> d = xs - x[b];
        const double d2 = d.squaredNorm();
        nb[n] = b;
        rab[n] = d;
        r2s[n] = d2;
        bool keep = (d2 < support2) & (d2 != 0.0);  // within the support, not a itself
        if constexpr (!Moves) keep &= !movers_only | (kind[b] != Kind::boundary);
        n += keep;
        if (n == batch) {
          sum_pairs<Moves>(a, nb, rab, r2s, n, r);
          n = 0;
        }
      }
    }
    sum_pairs<Moves>(a, nb, rab, r2s, n, r);
    return r;
  }

  // Add the pair terms of a's neighbours nb[0..n) (r_ab = rab, r_ab^2 = r2s) to r.
  template <bool Moves>
  inline __attribute__((always_inline)) void sum_pairs(int a, const int* nb, const Vec<D>* rab,
                                                        const double* r2s, int n, PairRates<D>& r) const {
    // Raw pointers and local copies let the compiler keep them in registers.
    const Vec<D>* const v = P_.v.data();
    const Vec<D>* const v_noslip = P_.v_noslip.data();
    const double* const mass = P_.mass.data();
    const double* const rho = P_.rho.data();
    const double* const c = P_.c.data();
    const double* const vol = P_.vol.data();
    const double* const p_rho2 = P_.p_rho2.data();
    const WendlandC2<D> kernel = kernel_;
    const Model model = model_;
    const Vec<D> va = v[a];
    const double rho_a = rho[a], c_a = has(term::artificial_viscosity) ? c[a] : 0.0;
    const double p_rho2_a = p_rho2[a], inv_rho_a = 1.0 / rho_a;
    PairRates<D> sum = r;
    for (int k = 0; k < n; ++k) {
      const int b = nb[k];
      Pair<D> pr;
      pr.r_ab = rab[k];
      pr.r2 = r2s[k];
      pr.F = kernel.gradient_factor_inside(std::sqrt(pr.r2));
      pr.v_ab = va - v[b];
      pr.vr = pr.v_ab.dot(pr.r_ab);
      pr.m_b = mass[b];
      if constexpr (Moves) {
        if constexpr (has(term::morris_viscosity)) pr.v_ab_noslip = va - v_noslip[b];
        pr.vol_b = vol[b];
        pr.rho_a = rho_a;
        pr.inv_rho_a = inv_rho_a;
        pr.rho_b = rho[b];
        pr.p_rho2_a = p_rho2_a;
        pr.p_rho2_b = p_rho2[b];
        if constexpr (has(term::artificial_viscosity)) {
          pr.c_a = c_a;
          pr.c_b = c[b];
        }
        model.pair(pr, sum);
      } else {
        model.boundary_pair(pr, sum);
      }
    }
    r = sum;
  }

  Deck deck_;
  Particles<D> P_;
  WendlandC2<D> kernel_;
  TaitEos eos_;
  Model model_;
  PeriodicBox<D> box_;
  CellList<D> cells_;
  WallPenalty<D> walls_;
  bool walls_together_ = false;  // every fixed boundary particle has the same velocity
  bool rates_ready_ = false;  // acc, drho hold the rates of the last evaluation
  StepMaxima maxima_;         // of the current state when valid
  std::vector<Vec<D>> x_pred_;  // predicted positions by index before the reorder (scratch of predict)
};

}  // namespace sph
