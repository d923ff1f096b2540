// The weakly compressible SPH solver for one dimension and one compile-time set of terms.
//
// Rates are summed over a Verlet half list (neighbour_list.h): each pair is
// evaluated once and acts on both particles (Newton's third law); the blocks
// of the list run colour after colour, so every particle receives its
// contributions in an order that does not depend on the OpenMP schedule. Time
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
#include "neighbour_list.h"
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

// Wall time per stage of the steps so far (s), and neighbour-list builds.
struct StageTimes {
  double predict = 0.0;     // predictor and displacement check
  double neighbours = 0.0;  // binning, reordering by cell, Verlet list build
  double eos = 0.0;         // EOS (eq. 6), zeroing the sums, no-slip velocities
  double pairs = 0.0;       // the pair loop (eqs. 7, 9-12)
  double particle = 0.0;    // per-particle terms after the pair loop (body force, walls)
  double correct = 0.0;     // corrector and step maxima
  long builds = 0;          // Verlet list builds
  long evaluations = 0;     // rate evaluations
};

template <int D, unsigned Terms>
class Simulation {
 public:
  using Model = FluidModel<D, Terms>;
  static constexpr bool has(unsigned t) { return Model::has(t); }

  // Cells of half the list range (5^D stencil) test fewer far pairs than cells
  // of the full range (3^D), and two layers of them make a block of the list.
  static constexpr int cell_reach = 2;
  // Verlet skin as a fraction of the support 2h (LAMMPS's 0.3 mm on a 3 mm
  // cutoff is 0.1): the list holds pairs closer than (1 + skin) 2h and is
  // rebuilt when a particle has moved skin/2 since the last build.
  static constexpr double skin_fraction = 0.1;

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
    x_build_.reserve(P_.x.capacity());
    shepard_.reserve(P_.x.capacity());
    list_.reserve(P_.x.capacity());
    list_.configure(box_);
    skin_ = skin_fraction * kernel_.support_radius();
    cells_.configure(kernel_.support_radius() + skin_, cell_reach, box_, std::max<std::size_t>(64 * n, 1u << 22));
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
  const NeighbourList<D>& neighbour_list() const { return list_; }
  const StageTimes& stage_times() const { return times_; }

  // Wrap the positions into the periodic box, bin and reorder the particles by
  // cell (memory locality) and build the Verlet list; false if they blew apart.
  bool sort_particles() {
    const double t0 = omp_get_wtime();
    for (auto& x : P_.x) box_.wrap(x);
    if (!cells_.build(P_.x, P_.size())) return false;
    P_.reorder(cells_.items());
    cells_.mark_sorted();
    build_list();
    times_.neighbours += omp_get_wtime() - t0;
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

  // acc and drho of every particle at the current x, v, rho (the Verlet list must hold them).
  // One parallel region: EOS and zeroed sums; no-slip velocities (Morris);
  // the pair loop, colour after colour; the per-particle terms.
  void compute_rates() {
    rates_ready_ = true;
    maxima_.valid = false;  // acc changes
    if (list_stale_) build_list();
    ++times_.evaluations;
    const std::ptrdiff_t n = P_.size();
    double t[4];
    auto body = [&](bool par) {
      stamp(par, t[0]);
      for_particles(par, n, [this](std::ptrdiff_t i) { start_rates_at(i); });
      if constexpr (has(term::morris_viscosity)) {
        list_.for_blocks_coloured(par, [this](int k) { no_slip_sums_of_block(k); });
        for_particles(par, n, [this](std::ptrdiff_t i) { no_slip_velocity_at(i); });
      }
      stamp(par, t[1]);
      list_.for_blocks_coloured(par, [this](int k) { rates_of_block(k); });
      stamp(par, t[2]);
      for_particles(par, n, [this](std::ptrdiff_t i) { finish_rates_at(i); });
      stamp(par, t[3]);
    };
    if (go_parallel(n, parallel_min_heavy) && list_.blocks() > 1) {
#pragma omp parallel
      body(true);
    } else {
      body(false);
    }
    times_.eos += t[1] - t[0];
    times_.pairs += t[2] - t[1];
    times_.particle += omp_get_wtime() - t[2];
  }

 private:
  // The time now into `at` (by the master thread, after the barrier of the previous loop when parallel).
  static void stamp(bool par, double& at) {
    if (!par) {
      at = omp_get_wtime();
      return;
    }
#pragma omp master
    at = omp_get_wtime();
  }
  // body(i) for i < n: a worksharing loop of the enclosing region when par, else a plain loop.
  template <class Body>
  static void for_particles(bool par, std::ptrdiff_t n, Body&& body) {
    if (par) {
#pragma omp for schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
    } else {
      for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
    }
  }

  // EOS of particle i and its sums set to zero (and, with Morris, its Shepard sums).
  void start_rates_at(std::ptrdiff_t i) {
    equation_of_state_at(i);
    P_.acc[i].setZero();
    P_.drho[i] = 0.0;
    if constexpr (has(term::morris_viscosity)) {
      P_.v_noslip[i].setZero();  // the Shepard sum of the fluid velocities around a boundary particle
      shepard_[i] = 0.0;
    }
  }
  // Body force and wall penalty of a fluid particle; an outlet particle keeps
  // the density it left with (a zero-gradient outlet).
  void finish_rates_at(std::ptrdiff_t a) {
    if (P_.moves(a)) {
      if constexpr (has(term::body_force)) model_.body.add(P_.acc[a]);
      if constexpr (has(term::wall_penalty)) {
        Vec<D> xa = P_.x[a];
        box_.wrap(xa);  // between list builds positions may lie up to skin/2 outside the box
        P_.acc[a] += walls_.force(xa) / P_.mass[a];
      }
    } else if (P_.kind[a] == Kind::outlet) {
      P_.drho[a] = 0.0;
    }
  }

  // The pairs owned by the particles of block k (neighbour_list.h): fluid or
  // not, owner and neighbour, each combination its own branch-free loop.
  void rates_of_block(int k) {
    const std::uint32_t* const e = list_.entries(k);
    for (int a = list_.block_begin(k); a < list_.block_end(k); ++a) {
      const auto& row = list_.row(a);
      if (P_.moves(a)) {
        pair_row<true, true>(a, e + row.begin, e + row.mid);
        pair_row<true, false>(a, e + row.mid, e + row.end);
      } else {
        pair_row<false, true>(a, e + row.begin, e + row.mid);
        pair_row<false, false>(a, e + row.mid, e + row.end);
      }
    }
  }

  // The pair terms of owner a with the neighbours of entries [e, end), added
  // to both particles (eqs. 7, 9-12). AMoves, BMoves: whether a and the
  // neighbours are fluid. A fluid particle takes continuity (eq. 7), the
  // pressure gradient (eq. 9) and the viscosities; any other takes the rate of
  // the summation density sum_b m_b v_ab . grad_a W_ab. Pairs of the skin,
  // beyond the support 2h, add exact zeros (the kernel factor is clamped to 0).
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) void pair_row(int a, const std::uint32_t* e, const std::uint32_t* end) {
    using List = NeighbourList<D>;
    if (e == end) return;
    Vec<D>* const acc = P_.acc.data();
    double* const drho = P_.drho.data();
    const Vec<D>* const x = P_.x.data();
    const Vec<D>* const v = P_.v.data();
    const Vec<D>* const v_noslip = P_.v_noslip.data();
    const double* const mass = P_.mass.data();
    const double* const rho = P_.rho.data();
    const double* const c = P_.c.data();
    const double* const vol = P_.vol.data();
    const double* const p_rho2 = P_.p_rho2.data();
    const Vec<D>* const shifts = list_.shifts();
    const double inv_h = kernel_.inv_h, grad_factor = kernel_.grad_factor;
    const Model model = model_;
    const Vec<D> xa = x[a], va = v[a];
    const double m_a = mass[a], rho_a = rho[a], vol_a = vol[a], p_rho2_a = p_rho2[a];
    const double inv_rho_a = 1.0 / rho_a, c_a = has(term::artificial_viscosity) ? c[a] : 0.0;
    Vec<D> vns_a = Vec<D>::Zero();
    if constexpr (has(term::morris_viscosity)) vns_a = v_noslip[a];
    Vec<D> acc_a = Vec<D>::Zero();
    double drho_a = 0.0;
    for (; e != end; ++e) {
      const int b = static_cast<int>(*e >> List::shift_bits);
      const Vec<D> r = xa - x[b] - shifts[*e & List::shift_mask];  // r_ab to the listed image of b
      const double r2 = r.squaredNorm();
      const double u = 1.0 - 0.5 * (std::sqrt(r2) * inv_h);
      const double t = 0.5 * (u + std::abs(u));  // exactly max(u, 0), without a branch (a third of the list is skin)
      const double F = grad_factor * (t * t * t);  // grad_a W_ab = F r_ab (eq. 8), 0 beyond 2h
      const Vec<D> v_ab = va - v[b];
      const double Fvr = F * v_ab.dot(r);  // v_ab . grad_a W_ab (= v_ba . grad_b W_ba)
      const double m_b = mass[b], rho_b = rho[b];
      // Eq. 7 for fluid (drho_a = rho_a sum m_b/rho_b v_ab . grad W), the summation rate otherwise.
      if constexpr (AMoves) drho_a += rho_a * vol[b] * Fvr;
      else drho_a += m_b * Fvr;
      if constexpr (BMoves) drho[b] += rho_b * vol_a * Fvr;
      else drho[b] += m_a * Fvr;
      if constexpr (AMoves || BMoves) {
        // Eq. 9 and eqs. 11-12: symmetric in a and b, along r_ab.
        double radial = -(p_rho2_a + p_rho2[b]) * F;
        if constexpr (has(term::artificial_viscosity))
          radial -= model.artificial.pi(r2, v_ab.dot(r), rho_a, rho_b, c_a, c[b]) * F;
        if constexpr (AMoves) acc_a.noalias() += (m_b * radial) * r;
        if constexpr (BMoves) acc[b].noalias() -= (m_a * radial) * r;
        if constexpr (has(term::morris_viscosity)) {
          // Eq. 10: 2 mu (r_ab . grad W)/(r_ab^2 + 0.01 h^2) m/(rho_a rho_b) times the
          // velocity difference, each side against the other's no-slip velocity.
          const double s = model.morris.factor(F, r2);
          if constexpr (AMoves) acc_a.noalias() += (s * vol[b] * inv_rho_a) * (va - v_noslip[b]);
          if constexpr (BMoves) acc[b].noalias() += (s * vol_a / rho_b) * (v[b] - vns_a);
        }
      }
    }
    acc[a] += acc_a;
    drho[a] += drho_a;
  }

  // Shepard sums of the fluid velocity around the fixed boundary particles
  // (for their no-slip velocity), over the fluid-boundary pairs of block k.
  void no_slip_sums_of_block(int k) {
    using List = NeighbourList<D>;
    const std::uint32_t* const e = list_.entries(k);
    const Vec<D>* const shifts = list_.shifts();
    const Vec<D>* const x = P_.x.data();
    for (int a = list_.block_begin(k); a < list_.block_end(k); ++a) {
      const auto& row = list_.row(a);
      const bool a_fluid = P_.moves(a), a_wall = P_.kind[a] == Kind::boundary;
      if (!a_fluid && !a_wall) continue;
      // a fluid: its non-fluid neighbours; a boundary particle: its fluid neighbours.
      const int from = a_fluid ? row.mid : row.begin, to = a_fluid ? row.end : row.mid;
      for (int j = from; j < to; ++j) {
        const int b = static_cast<int>(e[j] >> List::shift_bits);
        if (a_fluid && P_.kind[b] != Kind::boundary) continue;
        const Vec<D> r = x[a] - x[b] - shifts[e[j] & List::shift_mask];
        const double w = kernel_.value_clamped(std::sqrt(r.squaredNorm()));
        const int wall = a_fluid ? b : a, fluid = a_fluid ? a : b;
        P_.v_noslip[wall] += w * P_.v[fluid];
        shepard_[wall] += w;
      }
    }
  }

 public:
  // No-slip at fixed boundary particles for the viscous term: a boundary
  // particle b takes 2 v_b - v~_b, with v~_b the Shepard average of the fluid
  // velocity around it, so the fluid sees the velocity mirrored through the
  // wall (as Adami et al. 2012). Its own v_b (the wall's velocity) is unchanged.
  // (v_noslip holds the Shepard sum of no_slip_sums_of_block before.)
  void no_slip_velocity_at(std::ptrdiff_t b) {
    if (P_.kind[b] != Kind::boundary) {
      P_.v_noslip[b] = P_.v[b];
      return;
    }
    const double weight = shepard_[b];
    P_.v_noslip[b] = weight > 0.0 ? Vec<D>(2.0 * P_.v[b] - P_.v_noslip[b] / weight) : P_.v[b];
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
  // (Indices change too: the Verlet list is rebuilt before the next evaluation.)
  void forget_maxima() {
    maxima_.valid = false;
    list_stale_ = true;
  }

  // Rates of the initial state, before the first step (later steps reuse the
  // rates of the previous step's half-step evaluation); cells must be binned.
  void ensure_rates() {
    if (!rates_ready_) compute_rates();
  }

  // Predictor: half step with the rates of the last evaluation. When no
  // particle has moved more than skin/2 since the Verlet list was built, in
  // place (one pass, no binning). Otherwise binning of the predicted positions
  // and reordering by cell, in three passes over the particles, each on the
  // threads:
  //   1. predicted positions (by old index), wrapped, and their bounding box;
  //   2. their cells (then the counting sort, serial);
  //   3. for each new index k, from old index o: the start-of-step state
  //      x0, v0, rho0 (x0 shifted by the same wrap as the predicted x), the
  //      persistent state and the predicted v, rho;
  // then the list is rebuilt. Between builds positions are not wrapped (the
  // list holds the images), so they may lie up to skin/2 outside the box.
  // False if the predicted particles spread over too many cells (blow-up);
  // then x0, v0, rho0 hold the start-of-step state, for the last good frame.
  bool predict(double dt) {
    const double t_start = omp_get_wtime();
    const double half = 0.5 * dt;
    const std::ptrdiff_t n = P_.size();
    x_pred_.resize(n);
    double lo[D], hi[D], moved2 = 0.0;
    for (int d = 0; d < D; ++d) lo[d] = std::numeric_limits<double>::infinity(), hi[d] = -lo[d];
    const bool check = !list_stale_;  // x_build_ matches the particles
    auto position = [this, half, check](std::ptrdiff_t i, double* lo, double* hi, double& moved2) {
      Vec<D> x = P_.x[i];
      if (P_.advects(i)) {  // fixed boundary particles stay
        x += half * P_.v[i];
        if (check) moved2 = std::max(moved2, (x - x_build_[i]).squaredNorm());
        box_.wrap(x);
      }
      x_pred_[i] = x;
      for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
    };
    if (go_parallel(n, parallel_min_light)) {
#pragma omp parallel for reduction(min : lo[:D]) reduction(max : hi[:D], moved2) schedule(static)
      for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi, moved2);
    } else {
      for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi, moved2);
    }
    if (check && moved2 <= 0.25 * skin_ * skin_) {
      parallel_for(n, parallel_min_light, [this, half](std::ptrdiff_t i) {
        P_.x0[i] = P_.x[i], P_.v0[i] = P_.v[i], P_.rho0[i] = P_.rho[i];
        P_.rho[i] += half * P_.drho[i];
        if (P_.advects(i)) {
          P_.x[i] += half * P_.v[i];   // unwrapped: the list's images stay right
          P_.v[i] += half * P_.acc[i];  // acc is zero for all but fluid
        }
      });
      times_.predict += omp_get_wtime() - t_start;
      return true;
    }
    const double t_bin = omp_get_wtime();
    times_.predict += t_bin - t_start;
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
      const Vec<D> unwrapped = P_.advects(o) ? Vec<D>(P_.x[o] + half * P_.v[o]) : P_.x[o];
      P_.x0[k] = P_.x[o] + (x_pred_[o] - unwrapped), P_.v0[k] = P_.v[o], P_.rho0[k] = P_.rho[o];
      N.mass[k] = P_.mass[o], N.kind[k] = P_.kind[o], N.id[k] = P_.id[o];
      N.acc[k] = P_.acc[o], N.drho[k] = P_.drho[o];
      N.x[k] = x_pred_[o];
      N.rho[k] = P_.rho[o] + half * P_.drho[o];
      N.v[k] = P_.advects(o) ? Vec<D>(P_.v[o] + half * P_.acc[o]) : P_.v[o];  // acc is zero for all but fluid
    });
    P_.swap_next();
    cells_.mark_sorted_in_place();
    build_list();
    times_.neighbours += omp_get_wtime() - t_bin;
    return true;
  }

  // Corrector with the mid-step rates; in the same pass, the maxima that the
  // stability check and the next adaptive step read. Displacements are handed
  // to `crossed` (x_old, dx, volume) before wrapping, for flow-rate planes.
  // Positions are not wrapped here (see predict); x_old is handed wrapped.
  template <class Crossed>
  void correct(double dt, Crossed&& crossed) {
    const double t_start = omp_get_wtime();
    const std::ptrdiff_t n = P_.size();
    maxima_ = sweep_maxima([this, dt](std::ptrdiff_t i) {
      P_.rho[i] = P_.rho0[i] + dt * P_.drho[i];
      if (!P_.advects(i)) return;
      const Vec<D> dx = dt * (P_.v0[i] + 0.5 * dt * P_.acc[i]);
      P_.v[i] = P_.v0[i] + dt * P_.acc[i];
      P_.x[i] = P_.x0[i] + dx;
    });
    if constexpr (!std::is_same_v<std::decay_t<Crossed>, NoCrossings>)
      for (std::ptrdiff_t i = 0; i < n; ++i)
        if (P_.moves(i)) {
          Vec<D> x_old = P_.x0[i];
          box_.wrap(x_old);
          crossed(x_old, Vec<D>(dt * (P_.v0[i] + 0.5 * dt * P_.acc[i])), P_.mass[i] / P_.rho[i]);
        }
    times_.correct += omp_get_wtime() - t_start;
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
  std::vector<Vec<D>> x_build_;  // positions at the last Verlet list build
  std::vector<double> shepard_;  // Shepard weight sums of the boundary particles (Morris)
  NeighbourList<D> list_;
  double skin_ = 0.0;
  bool list_stale_ = true;  // the list must be rebuilt before the next evaluation
  StageTimes times_;

  // The Verlet list of the current (binned, sorted) positions.
  void build_list() {
    list_.build(cells_, P_.x, P_.kind, kernel_.support_radius() + skin_, walls_together_);
    x_build_.assign(P_.x.begin(), P_.x.end());
    shepard_.resize(P_.size());
    list_stale_ = false;
    ++times_.builds;
  }
};

}  // namespace sph
