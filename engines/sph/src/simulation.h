// The weakly compressible SPH solver for one dimension and one compiled configuration (configurations.h). One step
// runs the stages of stages.h. The pair loop visits a Verlet half list (neighbour_list.h) in block colours, so every
// particle receives its contributions in an order that does not depend on the OpenMP schedule (bitwise identical
// results on any thread count). Images come from box_policy.h. Fixed boundary particles keep position and velocity
// and evolve their density; inlet/outlet buffers move at their velocity.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "boundary_particles.h"
#include "box_policy.h"
#include "cell_list.h"
#include "constitutive_rates.h"
#include "parameters.h"
#include "eddy_viscosity.h"
#include "extra_stress.h"
#include "external_forces.h"
#include "grains.h"
#include "integrator.h"
#include "kernel.h"
#include "material.h"
#include "material_models.h"
#include "neighbour_list.h"
#include "pair_loop.h"
#include "particles.h"
#include "physics_terms.h"
#include "stages.h"
#include "step_maxima.h"
#include "verlet_skin.h"

namespace sph {

template <int D, unsigned Terms, class Models = ModelList<Newtonian>>
class Simulation {
 public:
  using Model = FluidModel<D, Terms>;
  using Images = PeriodicImages<D>;
  static constexpr bool has(unsigned t) { return Model::has(t); }
  static constexpr bool tensor = Models::any_stress;  // momentum in the tensor form (eq. T1)
  static constexpr bool sheared = has(term::sheared);  // Lees-Edwards images (box_policy.h)
  // No-slip velocities of boundary particles (Morris term; tensor path: eq. T2 and the wall stress, eq. W1).
  static constexpr bool no_slip = has(term::morris_viscosity) || tensor;
  static constexpr bool eddy = has(term::eddy_viscosity);  // Smagorinsky's nu_t (eddy_viscosity.h)
  // Cells of half the list range (5^D stencil) test fewer far pairs than cells of the full range (3^D).
  static constexpr int cell_reach = 2;  // the Verlet skin: deck.neighbour_skin (parameters.h)

  Simulation(const RunParameters& deck, Particles<D> particles, WallPenalty<D> walls = {})
      : deck_(deck), P_(std::move(particles)), kernel_(deck.h),
        pairs_(P_, list_, kernel_, model_, materials_, shepard_),
        external_(deck, std::move(walls)) {
    const int modes = add_materials<Models>(deck, materials_);
    for (int m = 0; m < materials_.size(); ++m) P_.corrected_momentum |= materials_[m].solid.corrected_momentum;
    model_ = fluid_model<D, Terms>(deck, materials_[0].mu, materials_[0].eos.rho0, materials_[0].eos.c0);
    smagorinsky_.length2 = deck.smagorinsky_cs * deck.smagorinsky_cs * deck.dx * deck.dx;
    hold_inlets_ = deck.inlets_extrapolated(), grains_.start(deck.grains, P_, materials_, deck.dx);  // grains: unwrapped
    const PeriodicBox<D> box = periodic_box<D>(deck);
    images_ = Images(box);
    if (deck.lees_edwards.on) images_.set_lees_edwards(deck.lees_edwards), cells_.set_lees_edwards(true);
    for (std::size_t i = 0; i < P_.size(); ++i) images_.wrap(P_.x[i], P_.v[i]);
    walls_together_ = walls_move_together(P_);
    const std::size_t n = P_.size(), capacity = P_.x.capacity();
    P_.has_stress = Models::any_single_stress, P_.modes = Models::any_modes ? modes : 0, P_.eddy = eddy, P_.solid = Models::any_solid,
    P_.diffuses = has(term::stress_diffusion);  // eq. SD1 (stress_diffusion.h)
    P_.resize(n), P_.set_wall_frames(), start_solids<Models>(P_, materials_);  // the caller's wall offsets; solids at T0
    P_.reserve(capacity);
    for (auto* a : {&x_pred_, &x_build_}) a->reserve(capacity);
    shepard_.reserve(capacity);
    list_.reserve(capacity);
    list_.configure(images_, decltype(pairs_)::lanes ? kernel_.support_radius() : 0.0);  // (pair_lanes.h)
    skin_ = deck.neighbour_skin * kernel_.support_radius();
    grains_.configure(deck, box, Images::gradient_axis, kernel_.support_radius() + skin_, P_);
    cells_.configure(kernel_.support_radius() + skin_, cell_reach, box, std::max<std::size_t>(64 * n, 1u << 22));
    sort_particles();
    equation_of_state();
    external_.impactors().check_clear(P_);
  }
  Simulation(const Simulation&) = delete;  // the pair loop holds references to the members
  Simulation& operator=(const Simulation&) = delete;
  Particles<D>& particles() { return P_; }
  const Particles<D>& particles() const { return P_; }
  const CellList<D>& cells() const { return cells_; }
  const WendlandC2<D>& kernel() const { return kernel_; }
  const MaterialTable& materials() const { return materials_; }
  const TaitEos& eos(std::size_t material = 0) const { return materials_.eos(material); }
  const PeriodicBox<D>& box() const { return images_.box(); }
  const WallPenalty<D>& walls() const { return external_.walls(); }
  const NeighbourList<D>& neighbour_list() const { return list_; }
  const StageTimes& stage_times() const { return times_; }
  const Impactors<D>& impactors() const { return external_.impactors(); }
  const Grains<D>& grains() const { return grains_; }
  // Kernel-corrected velocity gradient (eq. T2; default on): exact for a linear velocity field.
  void set_gradient_correction(bool on) { correct_gradient_ = on; }
  // Wrap the positions into the periodic box, bin and reorder the particles by
  // cell (memory locality) and build the Verlet list; false if they blew apart.
  bool sort_particles() {
    const double t0 = omp_get_wtime();
    if constexpr (sheared) images_.update(time_);
    for (std::size_t i = 0; i < P_.size(); ++i) images_.wrap(P_.x[i], P_.v[i]);
    if (!cells_.build(P_.x, P_.size())) return false;
    P_.reorder(cells_.items());
    cells_.mark_sorted();
    build_list();
    times_.neighbours += omp_get_wtime() - t0;
    return true;
  }
  // Pressure (and sound speed) of every particle from its density, eq. 6.
  void equation_of_state() {
    parallel_for(P_.size(), parallel_min_light, [this](std::ptrdiff_t i) { equation_of_state_at(i); });
  }
  // Eq. 6 with the particle's material (a solid: its model's). A fixed boundary particle never pulls: its pressure
  // is that of max(rho, rho0), so a wall under a free surface does not suck fluid in.
  // A cavitating particle (below the floor's density) takes p / rho^2 at the floor's density, its liquid's (as
  // the volume balances count it): at its own density the floor's tension grew as 1 / rho^2 (8 x at 35 % of rho0).
  void equation_of_state_at(std::ptrdiff_t i) {
    if constexpr (Models::any_solid)  // a fluid beside solids carries no artificial stress (zero from the start)
      if (Models::all_solid || materials_[P_.material[i]].is_solid) return solid_equation_of_state<Models>(P_, materials_, i);
    const TaitEos& eos = materials_.eos(P_.material[i]);
    const double rho = P_.kind[i] == Kind::boundary ? std::max(P_.rho[i], eos.rho0) : P_.rho[i];
    P_.p[i] = eos.pressure(rho);
    if constexpr (has(term::artificial_viscosity)) P_.c[i] = eos.sound_speed(rho);
    P_.vol[i] = P_.mass[i] / P_.rho[i];
    const double rho_liquid = std::max(P_.rho[i], eos.floor_rho);  // a cavitating particle's liquid (eos.h)
    P_.p_rho2[i] = P_.p[i] / (rho_liquid * rho_liquid);
    if constexpr (tensor) P_.sigma_rho2[i] = stress_over_rho2<Models>(P_, i, background_stress_);  // eq. T1
  }

  // Volume average of the fluid's extra stress, Pa (extra_stress.h; sigma_xy of a Lees-Edwards cell is its (0, 1) entry).
  Mat<D> mean_extra_stress() const { return sph::mean_extra_stress<Models>(P_); }
  const PeriodicImages<D>& images() const { return images_; }
  double time() const { return time_; }  // s, advanced by each step's dt

  // Rates of every particle at the current x, v, rho (the Verlet list must hold them): the gather
  // and close_rates stages in one parallel region.
  void compute_rates() {
    rates_ready_ = true, background_stress_ = background_stress<Models>(P_, sheared && deck_.lees_edwards.subtract_mean_stress);
    maxima_.valid = false, pairs_.fit();  // acc changes; the pair loop's room for the particles
    if (list_stale_) build_list();
    ++times_.evaluations;
    double t[4];
    run_region([&](bool par) {
      stamp_time(par, t[0]);
      evaluate_and_correct(par, false, 0.0, t);
    });
    times_.eos += t[1] - t[0], times_.pairs += t[2] - t[1], times_.particle += omp_get_wtime() - t[2];
  }

 private:
  // body(par) once, in a parallel region when the gather pays for it (and the list has blocks to share).
  template <class Body>
  void run_region(Body&& body) {
    if (go_parallel(P_.size(), parallel_min_heavy) && list_.blocks() > 1) {
      const std::size_t threads = omp_get_max_threads();
      if (moved_partials_.size() < threads) moved_partials_.resize(threads), maxima_partials_.resize(threads);
#pragma omp parallel
      body(true);
    } else {
      body(false);
    }
  }
  // The gather (its start pass unless `started`: EOS and zeroed sums), the impactors' reactions, then
  // close_rates; with dt > 0 fused per particle with the corrector, post_correct and the step maxima (into
  // maxima_, on the threads by finish_maxima). Stamps t[1] (EOS, no-slip velocities done), t[2] (pairs done), t[3].
  void evaluate_and_correct(bool par, bool started, double dt, double* t) {
    const std::ptrdiff_t n = P_.size();
    if (!started) for_each_index(par, n, [this](std::ptrdiff_t i) { start_rates_at(i); });
    if constexpr (no_slip) {
      if (has(term::morris_viscosity) || non_fluid_) {  // tensor path: only with walls or buffers
        list_.for_blocks_coloured(par, [this](int k) { pairs_.no_slip_sums_of_block(k); });
        for_each_index(par, n, [this](std::ptrdiff_t i) { no_slip_velocity_at(i); });
      }
    }
    stamp_time(par, t[1]);
    pairs_.rates(par);  // the pair loop in the block colours (pair_loop.h)
    stamp_time(par, t[2]);
    if (!external_.impactors().empty() || has(term::grains)) gather_bodies(dt);
    if (dt <= 0.0) {
      for_each_index(par, n, [this](std::ptrdiff_t i) { close_rates_at(i); });
      return;
    }
    // On the threads without a closing barrier (the region's end is one; finish_maxima combines after it).
    StepMaxima m = partial_each_index(par, n, maxima_partials_, StepMaxima{}, [&](std::ptrdiff_t i, StepMaxima& part) {
      close_rates_at(i);
      correct_at(P_, i, dt);
      if constexpr (has(term::grains)) grains_.place(P_, i);  // at the grain's corrected pose (eq. G3)
      if constexpr (tensor) post_correct_material<Models>(P_, materials_, i, dt);
      take_maxima(P_, materials_, i, part.worst_rho, part.v2, part.a2, part.finite);
    });
    if (!par) maxima_ = m, maxima_.valid = true, t[3] = omp_get_wtime();
#pragma omp master
    if (par) maxima_threads_ = omp_get_num_threads();
  }
  // On one thread (also outside a region): the impactors' reactions (impactors.h, I2), the grains' wrenches, G2-G3.
  void gather_bodies(double dt) {
#pragma omp single
    {
      if (!external_.impactors().empty()) external_.impactors().gather(P_);
      if constexpr (has(term::grains)) grains_.gather(P_, dt);
    }
  }
  // After a region that corrected on the threads: their maxima, in thread order (exact), into maxima_; stamps `at`.
  void finish_maxima(double& at) {
    if (maxima_threads_ == 0) return;
    maxima_ = combine_partials(maxima_partials_, maxima_threads_, StepMaxima{}, combine_maxima);
    maxima_.valid = true, maxima_threads_ = 0, at = omp_get_wtime();
  }

  // Gather, per particle: EOS and its sums set to zero (and, with Morris, its Shepard sums).
  void start_rates_at(std::ptrdiff_t i) {
    equation_of_state_at(i);
    P_.acc[i].setZero(), P_.drho[i] = 0.0, pairs_.start_at(i);
    if constexpr (no_slip) {
      if (has(term::morris_viscosity) || non_fluid_) {  // the no-slip pass runs (compute_rates)
        P_.v_noslip[i].setZero();  // the Shepard sum of the fluid velocities around a boundary particle
        shepard_[i] = 0.0;
        if constexpr (tensor) clear_wall_stress<Models>(P_, i);  // its sum of the fluid stresses (eq. W1)
      }
    }
    if constexpr (tensor) P_.grad_v[i].setZero(), P_.shape[i].setZero(), clear_laplacian<has(term::stress_diffusion)>(P_, i);
    if constexpr (eddy) P_.grad_v[i].setZero();
    if constexpr (Models::any_solid) P_.solid_state.rate[i].setZero(), P_.dtau[i].setZero();  // de/dt, eq. SS1 sums
  }
  // close_rates of particle a: body force and walls of a fluid particle; L = G M^-1 (eq. T2) and d tau/dt of its
  // material (constitutive_rates.h; eq. SD1); an outlet keeps the density it left with, an extrapolating inlet its last.
  void close_rates_at(std::ptrdiff_t a) {
    if constexpr (eddy) P_.nu_t[a] = P_.moves(a) ? smagorinsky_.nu_t<D>(P_.grad_v[a]) : 0.0;  // eq. SM1, next step's
    if (P_.moves(a)) {
      pairs_.finish_at(a);  // the sums of its fluid pairs' lanes
      external_.add(images_, P_.x[a], P_.mass[a], P_.solid_material[P_.material[a]], P_.acc[a]);  // body force, walls
      if constexpr (tensor) close_constitutive_rates<Models>(P_, materials_, a, correct_gradient_);
      if constexpr (has(term::stress_diffusion)) add_stress_diffusion(P_, materials_, a);  // eq. SD1
    } else if (P_.kind[a] == Kind::outlet || (hold_inlets_ && P_.kind[a] == Kind::inlet) || holds_density(P_, a)) {
      P_.drho[a] = 0.0;
    }
  }

 public:
  // No-slip velocity of a fixed boundary particle (boundary_particles.h); tensor: also its extra stress (eq. W1).
  void no_slip_velocity_at(std::ptrdiff_t b) {
    const TaitEos& eos = materials_.eos(P_.material[b]);
    no_slip_velocity(P_, shepard_, b, eos.pressure(eos.rho0), eos.rho0);  // a wall's floor: its rest state
    if constexpr (tensor)
      if (P_.wall(b)) wall_stress<Models>(P_, shepard_, b), equation_of_state_at(b);  // a grain's too
  }
  // A particle of mass m appears (sign +1) or disappears (-1) at x (boundary_particles.h).
  void boundary_density_event(Vec<D> x, double m, double sign) {
    images_.wrap(x), book_boundary_density(P_, cells_, kernel_, x, m, sign);
  }

  // Time step of eq. 13 extended by the viscous and force criteria, from the rates just computed:
  // min(cfl h/(c0 + v_max), viscous h^2/nu, force sqrt(h/a_max)) (largest c0 and nu over the materials).
  // With the eddy viscosity the viscous criterion takes nu + the largest nu_t of the last evaluation.
  double adaptive_dt() {
    const double dt = adaptive_time_step(maxima(), deck_, materials_, has(term::morris_viscosity));
    return eddy ? eddy_time_step(dt, deck_, materials_, max_eddy_viscosity()) : dt;
  }
  // m^2/s, the largest nu_t of the last evaluation (0 without eddy viscosity).
  double max_eddy_viscosity() const { return P_.nu_t.empty() ? 0.0 : *std::max_element(P_.nu_t.begin(), P_.nu_t.end()); }

  // Forget the maxima (call after adding, removing or changing particles: the list is rebuilt before use).
  void forget_maxima() { maxima_.valid = false, list_stale_ = true; }
  // Open boundaries changed these particles' kinds, nothing came or went: their entries re-sorted, the list holds.
  void kinds_changed(const std::vector<std::size_t>& changed) {
    maxima_.valid = false;
    if (!list_stale_) list_.reclassify(cells_, x_build_, P_.kind, changed), non_fluid_ = non_fluid_ || !changed.empty();
  }
  // Whether the list will probably be rebuilt within a step (3/4 of the allowed displacement used up).
  bool rebuild_near() const { return list_stale_ || last_moved_ > 0.75 * last_allowed_; }
  // The initial state's rates (cells binned); evaluated twice when eq. KC1 takes the M^-T of the first.
  void ensure_rates() { if (!rates_ready_) compute_rates(), P_.corrected_momentum ? compute_rates() : void(); }

  // One full step (stages.h), one rate evaluation at the half step. While the Verlet list stays valid (verlet_skin.h)
  // the step is one parallel region: predictor fused with the EOS and zeroed sums, the pair loop, then close_rates
  // fused with corrector, post_correct and step maxima. Otherwise the predicted state is rebinned (rebin_predicted)
  // and the list rebuilt. Between builds positions stay unwrapped (up to skin/2 outside the box). Displacements go to
  // `crossed` (x_old wrapped, dx, volume) for flow planes. False if the predicted particles spread over too many
  // cells (blow-up).
  template <class Crossed>
  bool step(double dt, Crossed&& crossed) {
    ensure_rates(), background_stress_ = background_stress<Models>(P_, sheared && deck_.lees_edwards.subtract_mean_stress);
    const double half = 0.5 * dt;
    const std::ptrdiff_t n = P_.size();
    const bool check = !list_stale_;  // x_build_ and the list match the particles
    double strain = 0.0, y_mid = 0.0;  // Lees-Edwards: strain since the build, mid-plane of the cell
    if constexpr (sheared) {
      images_.update(time_ + half);  // the images at the half step
      strain = images_.strain_since_build(), y_mid = 0.5 * (images_.box().lo[1] + images_.box().hi[1]);
    }
    const double allowed = allowed_displacement<sheared>(kernel_.support_radius(), skin_, strain);
    rates_ready_ = true, maxima_.valid = false, pairs_.fit();
    external_.impactors().predict(dt);  // their mid-step pose (impactors.h, eq. I3)
    if constexpr (has(term::grains)) grains_.predict(dt);  // the grains' (grains.h, eq. G3)
    ++times_.evaluations;
    double t[5];  // stamps: start, predicted, no-slip velocities, pairs, corrected
    auto region = [&](bool par) {
      stamp_time(par, t[0]);
      const double moved = reduce_each_index(
          par, n, moved_partials_, 0.0,
          [&](std::ptrdiff_t i, double& m) {
            predict_in_place(P_, i, half);
            if constexpr (has(term::grains)) grains_.place(P_, i);
            if (!check) return;  // rebuilt anyway (and shepard_ may not match the particles)
            if (P_.advects(i)) m = std::max(m, displacement_since_build<D, sheared>(P_.x[i], x_build_[i], strain, y_mid).squaredNorm());
            start_rates_at(i);
          },
          [](double& total, double part) { total = std::max(total, part); });
      stamp_time(par, t[1]);
#pragma omp master
      if (check) last_moved_ = std::sqrt(moved), last_allowed_ = allowed;
      if (!check || moved > allowed * allowed) return;  // the same on every thread
      evaluate_and_correct(par, true, dt, t + 1);  // sets maxima_ (valid)
    };
    run_region(region);
    finish_maxima(t[4]);
    times_.predict += t[1] - t[0];
    if (!maxima_.valid) {  // the region stopped after the predictor: the list must be rebuilt
      if (!rebin()) return false;
      run_region([&](bool par) {
        stamp_time(par, t[1]);
        evaluate_and_correct(par, false, dt, t + 1);
      });
      finish_maxima(t[4]);
    }
    times_.eos += t[2] - t[1], times_.pairs += t[3] - t[2], times_.correct += t[4] - t[3];
    time_ += dt;
    external_.impactors().correct(dt);
    if constexpr (!std::is_same_v<std::decay_t<Crossed>, NoCrossings>) step_displacements(P_, images_, materials_, dt, crossed);
    return true;
  }

  // NaN anywhere, or a fluid particle whose density deviates from its rho0 by more than the threshold or that is
  // faster than c0. (Boundary and buffer densities are devices of the wall and open-boundary models.)
  StabilityReport check_stability() { return stability_report(maxima(), deck_.max_density_deviation, materials_.c0_max()); }
  // max |rho/rho0 - 1| over the fluid particles (rho0 of each particle's material).
  double max_density_deviation() const { return sph::max_density_deviation(P_, materials_); }

 private:
  // The maxima of the current state: the corrector's, or taken now.
  const StepMaxima& maxima() {
    if (!maxima_.valid) maxima_ = sweep_maxima(P_, materials_, [](std::ptrdiff_t) {});
    return maxima_;
  }

  // After the predictor in place: bin and reorder the predicted state by
  // cell (rebin_predicted), rebuild the list. False on a blow-up.
  bool rebin() {
    const double t_start = omp_get_wtime();
    if (!rebin_predicted<D, sheared>(P_, cells_, x_pred_, images_)) return false;
    build_list();
    times_.neighbours += omp_get_wtime() - t_start;
    return true;
  }

  // The Verlet list of the current (binned, sorted) positions.
  void build_list() {
    if constexpr (sheared) images_.rebase(), cells_.set_shear_offset(images_.build_offset());
    list_.build(cells_, P_.x, P_.kind, kernel_.support_radius() + skin_, walls_together_);
    pairs_.list_built();
    x_build_.assign(P_.x.begin(), P_.x.end());
    last_moved_ = 0.0;  // nothing has moved since this build (a stale value kept rebuild_near true, and so the
                        // open boundaries flushed and rebuilt again a step later: every 2 steps in the drill)
    shepard_.resize(P_.size());
    if constexpr (tensor) non_fluid_ = std::any_of(P_.kind.begin(), P_.kind.end(), [](Kind k) { return k != Kind::fluid; });
    list_stale_ = false;
    ++times_.builds;
  }

  RunParameters deck_;
  Particles<D> P_;
  WendlandC2<D> kernel_;
  MaterialTable materials_;
  Model model_;
  Images images_;
  CellList<D> cells_;
  NeighbourList<D> list_;
  std::vector<double> shepard_;  // Shepard weight sums of the boundary particles (Morris)
  PairLoop<D, Terms, Models> pairs_;
  ExternalForces<D> external_;
  Grains<D> grains_;
  bool hold_inlets_ = false;  // every inlet extrapolates: its particles' density rate is 0 (close_rates_at)
  bool walls_together_ = false;  // every fixed boundary particle has the same velocity
  bool non_fluid_ = true;  // tensor path: a particle is not fluid (the no-slip pass runs), at the last list build
  bool correct_gradient_ = true;
  bool rates_ready_ = false;  // acc, drho hold the rates of the last evaluation
  StepMaxima maxima_;         // of the current state when valid
  std::vector<Vec<D>> x_pred_;   // wrapped predicted positions by index before the reorder (scratch of rebin)
  std::vector<ThreadPartial<double>> moved_partials_;  // per thread: largest squared displacement (step)
  std::vector<ThreadPartial<StepMaxima>> maxima_partials_;  // per thread: the corrector's maxima
  int maxima_threads_ = 0;  // threads whose maxima_partials_ finish_maxima has still to combine
  std::vector<Vec<D>> x_build_;  // positions at the last Verlet list build
  double skin_ = 0.0, time_ = 0.0;  // m (the Verlet skin), s
  double last_moved_ = 0.0, last_allowed_ = 1.0;  // m: the last step's largest displacement since the build, its bound
  Mat<D> background_stress_ = Mat<D>::Zero();  // Pa, tau_B of eq. T1 (extra_stress.h)
  bool list_stale_ = true;  // the list must be rebuilt before the next evaluation
  StageTimes times_;
  Smagorinsky smagorinsky_;  // eq. SM1 (eddy only)
};
}  // namespace sph
