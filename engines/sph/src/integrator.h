// Monaghan's predictor-corrector leapfrog with one rate evaluation per step
// (a PEC scheme), written once over the integrated fields of Particles
// (particles.h: for_integrated). For a field f with rate Df (the rates of the
// previous step's evaluation, a^(n-1/2)):
//   predictor  f* = f + dt/2 Df^(n-1/2)                     (eq. P1)
//   corrector  f' = f + dt Df^(n+1/2)                       (eq. P2)
// and position by its own rule
//   predictor  x* = x + dt/2 v                              (eq. P3)
//   corrector  x' = x + dt (v + dt/2 a^(n+1/2)) = x + dt (v + v')/2   (eq. P4)
// A field integrates on the particles its Integrates says (fixed boundary
// particles keep position and velocity but evolve density, unless they have a wall point: holds_density).
#pragma once
#include <algorithm>
#include <cstddef>
#include <limits>
#include <type_traits>
#include <vector>

#include "box_policy.h"
#include "cell_list.h"
#include "material.h"
#include "parallel.h"
#include "particles.h"

namespace sph {

// Predictor in place (the Verlet list stays valid): start-of-step copies, then eqs. P1, P3.
template <int D>
inline void predict_in_place(Particles<D>& P, std::ptrdiff_t i, double half) {
  P.x0[i] = P.x[i];
  if (P.advects(i)) P.x[i] += half * P.v[i];  // unwrapped: the list's images stay right (uses v^n)
  P.for_integrated([&](auto& f, Integrates who) {
    f.start[i] = f.value[i];
    if (P.integrates(who, i)) f.value[i] += half * f.rate[i];
  });
}

// Reorder by cell after the predictor ran in place on every particle
// (predict_in_place): new index k takes old index o, whose wrapped predicted
// position is x_pred. Writes the second buffers of the state and of the
// start-of-step copies (x0 shifted by the same wrap as the prediction);
// swap_next() then makes them current. Under Lees-Edwards (Sheared) a
// particle remapped across the gradient faces also takes the velocity jump
// (box_policy.h, eq. LE2) in its start-of-step and predicted velocity.
template <int D, bool Sheared = false>
inline void reorder_predicted(Particles<D>& P, std::ptrdiff_t k, int o, const Vec<D>& x_pred,
                              const PeriodicImages<D>* images = nullptr) {
  P.next_x0[k] = P.x0[o] + (x_pred - P.x[o]);
  P.next_x[k] = x_pred;
  P.for_integrated([&](auto& f, Integrates) {
    f.next_start[k] = f.start[o];
    f.next_value[k] = f.value[o];
    f.next_rate[k] = f.rate[o];
  });
  P.for_carried([&](auto& a, auto& next) { next[k] = a[o]; });
  if constexpr (Sheared) {
    const Vec<D> dv = images->velocity_change(x_pred - P.x[o]);
    P.vel.next_start[k] += dv, P.vel.next_value[k] += dv;
  }
}

// Binning and reordering by cell of the predicted state (after
// predict_in_place on every particle): the wrapped predicted positions into
// x_pred (fixed boundary particles are not wrapped: they never move) with
// their bounding box, their cells, the counting sort (serial), then one pass
// that writes, for each new index k, the state of old index o
// (reorder_predicted) into the second buffers, which become the state. False
// if the particles spread over too many cells (blow-up); then the
// start-of-step copies hold the state of the start of the step, for the last good frame.
template <int D, bool Sheared = false>
bool rebin_predicted(Particles<D>& P, CellList<D>& cells, std::vector<Vec<D>>& x_pred, const PeriodicImages<D>& images) {
  const std::ptrdiff_t n = P.size();
  x_pred.resize(n);
  double lo[D], hi[D];
  for (int d = 0; d < D; ++d) lo[d] = std::numeric_limits<double>::infinity(), hi[d] = -lo[d];
  auto position = [&](std::ptrdiff_t i, double* lo, double* hi) {
    Vec<D> x = P.x[i];
    if (P.advects(i)) images.wrap(x);
    x_pred[i] = x;
    for (int d = 0; d < D; ++d) lo[d] = std::min(lo[d], x[d]), hi[d] = std::max(hi[d], x[d]);
  };
  if (go_parallel(n, parallel_min_light)) {
#pragma omp parallel for reduction(min : lo[:D]) reduction(max : hi[:D]) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi);
  } else {
    for (std::ptrdiff_t i = 0; i < n; ++i) position(i, lo, hi);
  }
  if (!cells.lay_out(Eigen::Map<const Vec<D>>(lo), Eigen::Map<const Vec<D>>(hi), n)) return false;
  parallel_for(n, parallel_min_light, [&](std::ptrdiff_t i) { cells.assign(i, x_pred[i]); });
  cells.sort_assigned();
  std::vector<int>& order = cells.items_for_reorder();
  P.size_next();
  parallel_for(n, parallel_min_light, [&](std::ptrdiff_t k) {
    const int o = order[k];
    order[k] = static_cast<int>(k);
    reorder_predicted<D, Sheared>(P, k, o, x_pred[o], &images);
  });
  P.swap_next();
  cells.mark_sorted_in_place();
  return true;
}

// Corrector of particle i with the mid-step rates (eqs. P2, P4).
template <int D>
inline void correct_at(Particles<D>& P, std::ptrdiff_t i, double dt) {
  P.for_integrated([&](auto& f, Integrates who) {
    if (P.integrates(who, i)) f.value[i] = f.start[i] + dt * f.rate[i];
  });
  if (P.advects(i)) P.x[i] = P.x0[i] + dt * (P.v0[i] + 0.5 * dt * P.acc[i]);
}

// crossed(x_old, dx, volume) for each moving particle over the step of dt (s) just taken: its start x0 wrapped
// into the box, its displacement dt (v0 + dt a / 2) (m) and its liquid's volume (m^3; a cavitating particle
// holds its mass at the floor's density, the rest is vapour), for the flow planes (recorder.h).
template <int D, class Crossed>
void step_displacements(const Particles<D>& P, const PeriodicImages<D>& images, const MaterialTable& materials,
                        double dt, Crossed&& crossed) {
  for (std::ptrdiff_t i = 0, n = P.size(); i < n; ++i)
    if (P.moves(i)) {
      Vec<D> x_old = P.x0[i];
      images.wrap(x_old);
      const double rho = std::max(P.rho[i], materials.eos(P.material[i]).floor_rho);
      crossed(x_old, Vec<D>(dt * (P.v0[i] + 0.5 * dt * P.acc[i])), P.mass[i] / rho);
    }
}

}  // namespace sph
