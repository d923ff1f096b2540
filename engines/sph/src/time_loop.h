// The time loop of a run: stepping, the open boundaries' exchange, recording, progress, stability stop.
#pragma once
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

#include "open_boundaries.h"
#include "output_h5.h"
#include "parameters.h"
#include "recorder.h"

namespace sph {

enum ExitCode { exit_ok = 0, exit_failed = 1, exit_bad_input = 2, exit_unstable = 3, exit_terminated = 4 };

inline volatile std::sig_atomic_t stop_requested = 0;
inline void request_stop(int) { stop_requested = 1; }

// Steps a simulation `Sim` of dimension D from the deck's t_start to its t_end (or max_steps, a signal, an
// instability), with its open boundaries, and records series and frames at their intervals.
template <int D, class Sim>
class TimeLoop {
 public:
  using Clock = std::chrono::steady_clock;

  // `next_id`: the first particle id the open boundaries may give; `started`: when the run began (wall clock).
  TimeLoop(const RunParameters& deck, Sim& sim, Recorder<D, Sim>& rec, OpenBoundaries<D>& open, std::int64_t next_id,
           Clock::time_point started)
      : deck_(deck), sim_(sim), rec_(rec), open_(open), next_id_(next_id), started_(started),
        last_progress_(started), fixed_(deck.dt.has_value()), step0_(deck.step_start), step_(step0_),
        series_count_(intervals_done(deck.series_interval)), frame_count_(intervals_done(deck.frame_interval)),
        t_(deck.t_start), dt_(fixed_ ? *deck.dt : 0.0) {}

  // Run to the end; returns the exit code (ExitCode).
  int run() {
    open_.decide_list_keeping(sim_.particles());
    rec_.series(t_);
    rec_.frame(t_, step_);
    while (t_ < deck_.t_end * (1.0 - 1e-12) && !(deck_.max_steps && step_ - step0_ >= deck_.max_steps)) {
      if (stop_requested) {
        status_ = "terminated", message_ = "stopped by a signal", code_ = exit_terminated;
        break;
      }
      if (!advance()) break;
      exchange_open_boundaries();
      record_due();
      report_progress();
    }
    record_the_end();
    return code_;
  }

  // The run's status, steps, times and where the wall time went, as attributes of `out` and a STAGES line.
  void write_summary(OutputFile& out) const {
    const double wall = std::chrono::duration<double>(Clock::now() - started_).count();
    const long steps = step_ - step0_;
    std::fprintf(stderr, "PROGRESS step=%ld of %ld phase=done t=%.6g\n", steps, steps, t_);
    out.attr("status", status_);
    out.attr("message", message_);
    out.attr("n_steps", steps);
    out.attr("dt_mean", steps ? dt_sum_ / steps : 0.0);
    out.attr("t_start", deck_.t_start);
    out.attr("t_final", t_);
    out.attr("wall_time_s", wall);
    out.attr("particle_steps_per_s", wall > 0 ? static_cast<double>(sim_.particles().size()) * steps / wall : 0.0);
    // Where the time went (wall s per stage; output includes the re-binning before each record).
    const StageTimes& st = sim_.stage_times();
    const std::pair<const char*, double> stages[] = {
        {"predict", st.predict}, {"neighbours", st.neighbours}, {"eos", st.eos}, {"pairs", st.pairs},
        {"particle", st.particle}, {"correct", st.correct}, {"output", output_s_}};
    std::string line = "STAGES";
    for (const auto& [name, seconds] : stages) {
      out.attr(std::string("time_") + name + "_s", seconds);
      line += " " + std::string(name) + "=" + std::to_string(seconds);
    }
    out.attr("neighbour_list_builds", st.builds);
    std::fprintf(stderr, "%s list_builds=%ld pairs_listed=%zu wall=%f\n", line.c_str(), st.builds,
                 sim_.neighbour_list().pair_count(), wall);
  }

  const std::string& message() const { return message_; }

 private:
  // Intervals of `interval` s that a resumed run's t_start has already recorded.
  long intervals_done(double interval) const {
    return static_cast<long>(std::floor(deck_.t_start / interval * (1.0 + 1e-9)));
  }

  // Steps the run is expected to take (the steps so far at their mean size over the time left).
  long planned() const {
    const double left = std::max(0.0, deck_.t_end - t_);
    const long done = step_ - step0_;
    const double dt_typical = fixed_ || done == 0 ? dt_ : dt_sum_ / done;
    long m = done + static_cast<long>(std::ceil(left / std::max(dt_typical, 1e-300) - 1e-9));
    return deck_.max_steps ? std::min(m, deck_.max_steps) : m;
  }

  // A particle the open boundaries add (sign +1) or remove (-1) at x, of mass m, kg.
  auto booking() {
    return [this](const Vec<D>& x, double m, double sign) { sim_.boundary_density_event(x, m, sign); };
  }

  // One step: its size (adaptive steps end on the next record's time), the step, the stability check. False
  // when the run is unstable (its last good frame is then recorded).
  bool advance() {
    sim_.ensure_rates();  // the initial state's, before the first step; later the last half step's
    if (!fixed_) {
      dt_ = sim_.adaptive_dt();
      const double target = std::min({(series_count_ + 1) * deck_.series_interval,
                                      (frame_count_ + 1) * deck_.frame_interval, deck_.t_end});
      if (t_ + 1.01 * dt_ >= target) dt_ = std::max(target - t_, 1e-6 * dt_);
    }
    const bool binned = rec_.has_flow_planes()
                            ? sim_.step(dt_, [&](const Vec<D>& x_old, const Vec<D>& dx,
                                                 double volume) { rec_.cross(x_old, dx, volume); })
                            : sim_.step(dt_, NoCrossings{});
    ++step_;
    const double t_before = t_;
    t_ = fixed_ ? deck_.t_start + (step_ - step0_) * dt_ : t_ + dt_;
    dt_sum_ += dt_;
    sorted_ = false;
    const StabilityReport report = binned ? sim_.check_stability() : StabilityReport{false, "particles blew apart"};
    if (report.ok) return true;
    status_ = "unstable";
    message_ = "unstable at t = " + std::to_string(t_) + " s (step " + std::to_string(step_) + "): " + report.message;
    code_ = exit_unstable;
    rec_.last_good_frame(t_before, step_ - 1);
    return false;
  }

  // Particles that crossed an inlet or an outlet change kind, come in or leave.
  void exchange_open_boundaries() {
    if (open_.empty()) return;
    next_id_ = open_.update(sim_.particles(), next_id_, t_, booking());
    if (open_.particles_kept()) sim_.kinds_changed(open_.changed());  // the list holds (open_boundaries.h)
    else sim_.forget_maxima();  // particles came in or left: the list is rebuilt
  }

  // The series and the frame that are due at t, on particles sorted into their cells.
  void record_due() {
    const double tol = 1e-6 * dt_;
    const bool series_due = t_ >= (series_count_ + 1) * deck_.series_interval - tol;
    const bool frame_due = t_ >= (frame_count_ + 1) * deck_.frame_interval - tol;
    // The particles that wait to come in or go join before an output sort or a build that is due anyway.
    if (open_.has_waiting() && (series_due || frame_due || sim_.rebuild_near()) && open_.flush(sim_.particles(), booking()))
      sim_.forget_maxima();
    const double t_output = omp_get_wtime();
    if (series_due || frame_due) {
      sorted_ = sim_.sort_particles();
      sim_.equation_of_state();
    }
    if (series_due) {
      rec_.series(t_);
      while ((series_count_ + 1) * deck_.series_interval <= t_ + tol) ++series_count_;
    }
    if (frame_due) {
      rec_.frame(t_, step_);
      while ((frame_count_ + 1) * deck_.frame_interval <= t_ + tol) ++frame_count_;
    }
    output_s_ += omp_get_wtime() - t_output;
  }

  // A PROGRESS line each progress_interval of wall time; the first one also estimates the run's duration.
  void report_progress() {
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_progress_).count() < deck_.progress_interval) return;
    last_progress_ = now;
    std::fprintf(stderr, "PROGRESS step=%ld of %ld phase=run t=%.6g\n", step_ - step0_, planned(), t_);
    if (!timing_printed_) {
      const double per_step = std::chrono::duration<double>(now - started_).count() / (step_ - step0_);
      std::fprintf(stderr, "TIMING s_per_step=%.6g planned_steps=%ld estimate_s=%.6g\n", per_step, planned(),
                   per_step * planned());
      timing_printed_ = true;
    }
    std::fflush(stderr);
  }

  // The last state as a series record and a frame, unless they are written already (or the run is unstable).
  void record_the_end() {
    if (code_ == exit_unstable || !(rec_.last_series_time() < t_ || rec_.last_frame_time() < t_)) return;
    if (open_.flush(sim_.particles(), booking())) sorted_ = false;
    if (!sorted_) sim_.sort_particles();
    sim_.equation_of_state();
    if (rec_.last_series_time() < t_) rec_.series(t_);
    if (rec_.last_frame_time() < t_) rec_.frame(t_, step_);
  }

  const RunParameters& deck_;
  Sim& sim_;
  Recorder<D, Sim>& rec_;
  OpenBoundaries<D>& open_;
  std::int64_t next_id_;
  const Clock::time_point started_;
  Clock::time_point last_progress_;
  // A resumed run starts at its frame's time and step (deck t_start, step_start); max_steps and the
  // n_steps, dt_mean it reports count its own steps.
  const bool fixed_;
  const long step0_;
  long step_, series_count_, frame_count_;
  double t_, dt_, dt_sum_ = 0.0;
  std::string status_ = "ok", message_;
  int code_ = exit_ok;
  double output_s_ = 0.0;  // series and frames (with their re-binning)
  bool sorted_ = true;     // binned at the current positions
  bool timing_printed_ = false;
};

}  // namespace sph
