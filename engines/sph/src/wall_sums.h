// Shepard sums of the fluid around the fixed boundary particles, the gather
// stage's pass before the pair terms (PairLoop::no_slip_sums_of_block).
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "boundary_particles.h"
#include "kernel.h"
#include "neighbour_list.h"
#include "particles.h"

namespace sph {

// Shepard sums of the fluid velocity around the fixed boundary particles
// (for their no-slip velocity), over the fluid-boundary pairs of block k;
// tensor configurations: also of the fluid's extra stress (eq. W1); with
// wall points (Particles::has_wall_points), also of the fluid positions
// relative to the boundary particle b, x_fluid - x_b (periodic images
// included), and the fit of eq. WP2 (boundary_particles.h). Pairs of the
// skin (weight 0) add exact zeros and are skipped; a boundary particle's
// own row is summed into locals (the same additions in the same order).
// (Tensor: the run's models carry an extra stress.) Beside a solid (eq. FS2) a boundary particle sums the
// particles of its own kind of material only: a solid's held particles the solid, the fluid's walls the fluid.
template <bool tensor, class Models, int D>
inline __attribute__((always_inline)) void wall_sums_of_block(Particles<D>& P, const NeighbourList<D>& list, const WendlandC2<D>& kernel,
                        std::vector<double>& shepard, int k) {
  using List = NeighbourList<D>;
  const std::uint32_t* const e = list.entries(k);
  const Vec<D>* const shifts = list.shifts();
  const Vec<D>* const x = P.x.data();
  const bool positions = P.has_wall_points;
  Vec<D> no_x;  // the sums a run without wall points does not keep
  WallFit<D> no_fit;
  // Beyond this r^2 the weight is 0 for certain (no sqrt); nearer, value_clamped decides.
  const double far2 = 4.0 * kernel.h * kernel.h * (1.0 + 1e-9);
  auto weight = [&](int a, std::uint32_t entry, Vec<D>& r) {
    r = x[a] - x[entry >> List::shift_bits] - shifts[entry & List::shift_mask];
    const double r2 = r.squaredNorm();
    return r2 > far2 ? 0.0 : kernel.value_clamped(std::sqrt(r2));
  };
  for (int a = list.block_begin(k); a < list.block_end(k); ++a) {
    const auto& row = list.row(a);
    Vec<D> r;
    if (P.moves(a)) {  // a fluid: its boundary neighbours
      for (int j = row.mid; j < row.end; ++j) {
        const int b = static_cast<int>(e[j] >> List::shift_bits);
        if (!P.wall(b)) continue;  // boundary or a grain's particle
        if constexpr (Models::any_solid) if (P.grains && P.grain_beside_solid(b, a)) continue;  // eq. G8 instead
        if constexpr (Models::any_solid && !Models::all_solid) if (P.across_interface(a, b)) continue;  // eq. FS2
        const double w = weight(a, e[j], r);
        if (w == 0.0) continue;
        if constexpr (tensor) add_wall_stress<Models>(P, b, a, w);  // eq. W1 (boundary_particles.h)
        add_no_slip<D>(P, b, a, w, r,
                       {P.v_noslip[b], shepard[b], positions ? P.x_noslip[b] : no_x, positions ? P.wall_fit[b] : no_fit});
      }
    } else if (P.wall(a) && row.begin != row.mid) {  // a boundary or grain particle: its fluid neighbours
      Vec<D> v = P.v_noslip[a], xs = positions ? P.x_noslip[a] : no_x;
      double ws = shepard[a];
      WallFit<D> fit = positions ? P.wall_fit[a] : no_fit;
      for (int j = row.begin; j < row.mid; ++j) {
        const int b = static_cast<int>(e[j] >> List::shift_bits);
        if constexpr (Models::any_solid) if (P.grains && P.grain_beside_solid(a, b)) continue;  // eq. G8 instead
        if constexpr (Models::any_solid && !Models::all_solid) if (P.across_interface(a, b)) continue;  // eq. FS2
        const double w = weight(a, e[j], r);
        if (w == 0.0) continue;
        if constexpr (tensor) add_wall_stress<Models>(P, a, b, w);
        add_no_slip<D>(P, a, b, w, Vec<D>(-r), {v, ws, xs, fit});
      }
      P.v_noslip[a] = v, shepard[a] = ws;
      if (positions) P.x_noslip[a] = xs, P.wall_fit[a] = fit;
    }
  }
}

}  // namespace sph
