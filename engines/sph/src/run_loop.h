// The time loop of a run: stepping, recording, progress, stability stop.
#pragma once
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "configurations.h"
#include "open_boundaries.h"
#include "output_h5.h"
#include "recorder.h"
#include "setup.h"
#include "simulation.h"

namespace sph {

enum ExitCode { exit_ok = 0, exit_failed = 1, exit_bad_input = 2, exit_unstable = 3, exit_terminated = 4 };

inline volatile std::sig_atomic_t stop_requested = 0;
inline void request_stop(int) { stop_requested = 1; }

template <int D, unsigned Terms, class Models>
int run_simulation(const Deck& deck, Particles<D> particles, WallPenalty<D> walls, OpenBoundaries<D> open) {
  using Clock = std::chrono::steady_clock;
  const auto started = Clock::now();
  std::int64_t next_id = 0;
  for (auto id : particles.id) next_id = std::max(next_id, id + 1);
  using Sim = Simulation<D, Terms, Models>;
  Sim sim(deck, std::move(particles), std::move(walls));
  OutputFile out(deck.output_file);
  Recorder<D, Sim> rec(deck, sim, open, out);
  std::signal(SIGTERM, request_stop);
  std::signal(SIGINT, request_stop);

  const bool fixed = deck.dt.has_value();
  // A resumed run starts at its frame's time and step (deck t_start, step_start); max_steps and the
  // n_steps, dt_mean it reports count its own steps.
  const long step0 = deck.step_start;
  const auto intervals_done = [&](double interval) {
    return static_cast<long>(std::floor(deck.t_start / interval * (1.0 + 1e-9)));
  };
  long step = step0, series_count = intervals_done(deck.series_interval),
       frame_count = intervals_done(deck.frame_interval);
  double t = deck.t_start, dt = fixed ? *deck.dt : 0.0, dt_sum = 0.0;
  auto planned = [&] {
    const double left = std::max(0.0, deck.t_end - t);
    const long done = step - step0;
    const double dt_typical = fixed || done == 0 ? dt : dt_sum / done;
    long m = done + static_cast<long>(std::ceil(left / std::max(dt_typical, 1e-300) - 1e-9));
    return deck.max_steps ? std::min(m, deck.max_steps) : m;
  };
  // A particle the open boundaries add (sign +1) or remove (-1) at x, of mass m, kg.
  const auto booking = [&](const Vec<D>& x, double m, double sign) { sim.boundary_density_event(x, m, sign); };
  open.decide_list_keeping(sim.particles());
  rec.series(t);
  rec.frame(t, step);
  std::string status = "ok", message;
  int code = exit_ok;
  double output_s = 0.0;  // series and frames (with their re-binning)
  bool sorted = true, timing_printed = false;  // sorted: binned at the current positions
  auto last_progress = started;

  while (t < deck.t_end * (1.0 - 1e-12) && !(deck.max_steps && step - step0 >= deck.max_steps)) {
    if (stop_requested) {
      status = "terminated", message = "stopped by a signal", code = exit_terminated;
      break;
    }
    sim.ensure_rates();  // the initial state's, before the first step; later the last half step's
    if (!fixed) {
      dt = sim.adaptive_dt();
      const double target = std::min({(series_count + 1) * deck.series_interval,
                                      (frame_count + 1) * deck.frame_interval, deck.t_end});
      if (t + 1.01 * dt >= target) dt = std::max(target - t, 1e-6 * dt);
    }
    const bool binned = rec.has_flow_planes()
                            ? sim.step(dt, [&](const Vec<D>& x_old, const Vec<D>& dx,
                                               double volume) { rec.cross(x_old, dx, volume); })
                            : sim.step(dt, NoCrossings{});
    ++step;
    const double t_before = t;
    t = fixed ? deck.t_start + (step - step0) * dt : t + dt;
    dt_sum += dt;
    sorted = false;
    const StabilityReport report = binned ? sim.check_stability() : StabilityReport{false, "particles blew apart"};
    if (!report.ok) {
      status = "unstable";
      message = "unstable at t = " + std::to_string(t) + " s (step " + std::to_string(step) + "): " + report.message;
      code = exit_unstable;
      rec.last_good_frame(t_before, step - 1);
      break;
    }
    if (!open.empty()) {
      next_id = open.update(sim.particles(), next_id, t, booking);
      if (open.particles_kept()) sim.kinds_changed(open.changed());  // the list holds (open_boundaries.h)
      else sim.forget_maxima();  // particles came in or left: the list is rebuilt
    }
    const double tol = 1e-6 * dt;
    const bool series_due = t >= (series_count + 1) * deck.series_interval - tol;
    const bool frame_due = t >= (frame_count + 1) * deck.frame_interval - tol;
    // The particles that wait to come in or go join before an output sort or a build that is due anyway.
    if (open.has_waiting() && (series_due || frame_due || sim.rebuild_near()) && open.flush(sim.particles(), booking))
      sim.forget_maxima();
    const double t_output = omp_get_wtime();
    if (series_due || frame_due) {
      sorted = sim.sort_particles();
      sim.equation_of_state();
    }
    if (series_due) {
      rec.series(t);
      while ((series_count + 1) * deck.series_interval <= t + tol) ++series_count;
    }
    if (frame_due) {
      rec.frame(t, step);
      while ((frame_count + 1) * deck.frame_interval <= t + tol) ++frame_count;
    }
    output_s += omp_get_wtime() - t_output;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_progress).count() >= deck.progress_interval) {
      last_progress = now;
      std::fprintf(stderr, "PROGRESS step=%ld of %ld phase=run t=%.6g\n", step - step0, planned(), t);
      if (!timing_printed) {
        const double per_step = std::chrono::duration<double>(now - started).count() / (step - step0);
        std::fprintf(stderr, "TIMING s_per_step=%.6g planned_steps=%ld estimate_s=%.6g\n", per_step, planned(),
                     per_step * planned());
        timing_printed = true;
      }
      std::fflush(stderr);
    }
  }
  if (code != exit_unstable && (rec.last_series_time() < t || rec.last_frame_time() < t)) {
    if (open.flush(sim.particles(), booking)) sorted = false;
    if (!sorted) sim.sort_particles();
    sim.equation_of_state();
    if (rec.last_series_time() < t) rec.series(t);
    if (rec.last_frame_time() < t) rec.frame(t, step);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - started).count();
  const long steps = step - step0;
  std::fprintf(stderr, "PROGRESS step=%ld of %ld phase=done t=%.6g\n", steps, steps, t);
  out.attr("status", status);
  out.attr("message", message);
  out.attr("n_steps", steps);
  out.attr("dt_mean", steps ? dt_sum / steps : 0.0);
  out.attr("t_start", deck.t_start);
  out.attr("t_final", t);
  out.attr("wall_time_s", wall);
  out.attr("particle_steps_per_s", wall > 0 ? static_cast<double>(sim.particles().size()) * steps / wall : 0.0);
  // Where the time went (wall s per stage; output includes the re-binning before each record).
  const StageTimes& st = sim.stage_times();
  const std::pair<const char*, double> stages[] = {
      {"predict", st.predict}, {"neighbours", st.neighbours}, {"eos", st.eos}, {"pairs", st.pairs},
      {"particle", st.particle}, {"correct", st.correct}, {"output", output_s}};
  std::string line = "STAGES";
  for (const auto& [name, seconds] : stages) {
    out.attr(std::string("time_") + name + "_s", seconds);
    line += " " + std::string(name) + "=" + std::to_string(seconds);
  }
  out.attr("neighbour_list_builds", st.builds);
  std::fprintf(stderr, "%s list_builds=%ld pairs_listed=%zu wall=%f\n", line.c_str(), st.builds,
               sim.neighbour_list().pair_count(), wall);
  out.flush();
  if (code == exit_unstable) std::fprintf(stderr, "error: numerically %s\n", message.c_str());
  return code;
}

// The pair terms and the material models of a deck, as the closed list of
// configurations (configurations.h) names them.
struct Wanted {
  unsigned terms;                   // pair terms (| several_materials)
  std::vector<std::string> models;  // distinct model names of the deck's materials
};
inline Wanted wanted_by(const Deck& deck) {
  Wanted w{deck.terms & term::pair_terms, {}};
  const auto materials = deck.material_list();
  for (const auto& m : materials)
    if (std::find(w.models.begin(), w.models.end(), m.model) == w.models.end()) w.models.push_back(m.model);
  if (materials.size() > 1 && (w.terms & term::morris_viscosity)) w.terms |= term::several_materials;
  if (deck.lees_edwards.on) w.terms |= term::sheared;
  if (deck.viscosity_correction) w.terms |= term::viscosity_correction;
  if (deck.smagorinsky_cs > 0) w.terms |= term::eddy_viscosity;
  return w;
}
template <class Models>
bool same_models(const std::vector<std::string>& names) {
  if (static_cast<int>(names.size()) != Models::size) return false;
  for (const auto& n : names)
    if (Models::index(n) < 0) return false;
  return true;
}

// Run the configuration of the closed list that matches the deck exactly.
template <int D, std::size_t I = 0>
int dispatch(const Wanted& w, const Deck& deck, Particles<D> P, WallPenalty<D> walls, OpenBoundaries<D> open) {
  if constexpr (I == std::tuple_size_v<Configurations>) {
    std::string models;
    for (const auto& m : w.models) models += (models.empty() ? "" : ", ") + m;
    throw InputError("no compiled configuration runs materials of model(s) " + models + " with physics '" +
                     deck.terms_string() + "'; add one to src/configurations.h");
  } else {
    using C = std::tuple_element_t<I, Configurations>;
    if (C::terms == w.terms && same_models<typename C::models>(w.models))
      return run_simulation<D, C::terms, typename C::models>(deck, std::move(P), std::move(walls), std::move(open));
    return dispatch<D, I + 1>(w, deck, std::move(P), std::move(walls), std::move(open));
  }
}

// Read the inputs of a deck of dimension D and run it.
template <int D>
int run_dimension(const Deck& deck) {
  if (deck.threads > 0) omp_set_num_threads(deck.threads);
  configure_parallel();
  const ParticleInput in = read_particles(deck.particles_file, D);
  OpenBoundaries<D> open(deck);
  Particles<D> P = make_particles<D>(deck, in, open.extra_capacity(deck.t_end - deck.t_start));
  if (in.has_buffers) {  // a resumed run: its frame holds the buffers as they were
    for (std::size_t i = 0; i < in.n; ++i)
      if ((in.kind[i] == 2 && deck.inlets.empty()) || (in.kind[i] == 3 && deck.outlets.empty()))
        throw InputError("particle " + std::to_string(i) + " is an " + (in.kind[i] == 2 ? "inlet" : "outlet") +
                         " particle (kind " + std::to_string(in.kind[i]) + ") but the deck has no " +
                         (in.kind[i] == 2 ? "inlets" : "outlets"));
    open.start_at(deck.t_start);
  } else {
    open.fill(P, static_cast<std::int64_t>(in.n));
  }
  open.classify_initial(P);
  WallPenalty<D> walls = make_walls<D>(deck);
  return dispatch<D>(wanted_by(deck), deck, std::move(P), std::move(walls), std::move(open));
}

}  // namespace sph
