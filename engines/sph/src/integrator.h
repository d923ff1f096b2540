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
// particles keep position and velocity but evolve density).
#pragma once
#include <cstddef>
#include <type_traits>
#include <vector>

#include "box_policy.h"
#include "cell_list.h"
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

// Predictor fused with the reorder by cell: new index k from old index o,
// x_pred the predicted (wrapped) position of o. Writes the start-of-step
// copies (x0 shifted by the same wrap as the prediction) and the second
// buffers of the persistent state; swap_next() then makes them current.
// Under Lees-Edwards (Sheared) a particle remapped across the gradient faces
// also takes the velocity jump (box_policy.h, eq. LE2) in its start-of-step
// and predicted velocity.
template <int D, bool Sheared = false>
inline void predict_reordered(Particles<D>& P, std::ptrdiff_t k, int o, const Vec<D>& x_pred, double half,
                              const PeriodicImages<D>* images = nullptr) {
  const Vec<D> unwrapped = P.advects(o) ? Vec<D>(P.x[o] + half * P.v[o]) : P.x[o];
  P.x0[k] = P.x[o] + (x_pred - unwrapped);
  P.next_x[k] = x_pred;
  P.for_integrated([&](auto& f, Integrates who) {
    f.start[k] = f.value[o];
    f.next_rate[k] = f.rate[o];
    using T = typename std::decay_t<decltype(f.value)>::value_type;
    f.next_value[k] = P.integrates(who, o) ? T(f.value[o] + half * f.rate[o]) : f.value[o];
  });
  P.for_carried([&](auto& a, auto& next) { next[k] = a[o]; });
  if constexpr (Sheared) {
    const Vec<D> dv = images->velocity_change(x_pred - unwrapped);
    P.vel.start[k] += dv, P.vel.next_value[k] += dv;
  }
}

// The predictor with binning and reordering by cell: the cells of the
// predicted positions x_pred (bounding box lo, hi), the counting sort
// (serial), then one pass that writes, for each new index k, the predicted
// state of old index o (predict_reordered) into the second buffers, which
// become the state. False if the particles spread over too many cells
// (blow-up); then the start-of-step copies hold the state, for the last good frame.
template <int D, bool Sheared = false>
bool predict_rebinned(Particles<D>& P, CellList<D>& cells, const std::vector<Vec<D>>& x_pred, const double* lo,
                      const double* hi, double half, const PeriodicImages<D>* images = nullptr) {
  const std::ptrdiff_t n = P.size();
  if (!cells.lay_out(Eigen::Map<const Vec<D>>(lo), Eigen::Map<const Vec<D>>(hi), n)) {
    parallel_for(n, parallel_min_light, [&](std::ptrdiff_t i) {
      P.x0[i] = P.x[i];
      P.for_integrated([i](auto& f, Integrates) { f.start[i] = f.value[i]; });
    });
    return false;
  }
  parallel_for(n, parallel_min_light, [&](std::ptrdiff_t i) { cells.assign(i, x_pred[i]); });
  cells.sort_assigned();
  std::vector<int>& order = cells.items_for_reorder();
  P.size_next();
  parallel_for(n, parallel_min_light, [&](std::ptrdiff_t k) {
    const int o = order[k];
    order[k] = static_cast<int>(k);
    predict_reordered<D, Sheared>(P, k, o, x_pred[o], half, images);
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

}  // namespace sph
