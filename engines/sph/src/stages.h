// Small types of the solver's stages (simulation.h): stage timers, the
// stability report, the per-body reduction hook.
//
// One step (Monaghan's predictor-corrector with one rate evaluation, at the
// half step; integrator.h) runs these stages:
//
//   predict ──> gather ──────────────> close_rates ─────────> bodies ──> correct ──> post_correct
//   (eqs. P1,  EOS (eq. 6), sigma/rho^2; per particle: body    per-body   (eqs. P2,  per material:
//    P3; list  no-slip velocities;     force, walls (eq. 14);  reduction  P4)        return mapping,
//    rebuild   pair loop: eqs. 7, 9    velocity gradient        (rigid                failure
//    when      or T1, 10-12, T2        G M^-1; constitutive     grains;               (models with
//    stale)    (pair_loop.h)           rates d tau/dt           none yet)             stress)
#pragma once
#include <string>

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
// In a step whose Verlet list stays valid, the predictor pass also does the
// gather's EOS and zeroing, and close_rates runs fused with the corrector.
struct StageTimes {
  double predict = 0.0;     // predictor, displacement check (and EOS, zeroed sums when the list stays)
  double neighbours = 0.0;  // binning, reordering by cell, Verlet list build
  double eos = 0.0;         // gather: EOS (eq. 6) and zeroed sums after a rebuild; no-slip velocities
  double pairs = 0.0;       // gather: the pair loop (eqs. 7, 9 or T1, 10-12, T2)
  double particle = 0.0;    // close_rates alone (rates of the initial state; compute_rates)
  double correct = 0.0;     // close_rates (body force, walls, constitutive rates), corrector, post_correct, maxima
  long builds = 0;          // Verlet list builds
  long evaluations = 0;     // rate evaluations
};

}  // namespace sph
