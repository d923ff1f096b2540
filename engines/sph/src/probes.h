// Measurements: kernel-interpolated pressure at a point and volume flux through a plane patch.
#pragma once
#include <cmath>
#include <limits>
#include <string>

#include "cell_list.h"
#include "kernel.h"
#include "particles.h"
#include "plane_patch.h"

namespace sph {

// Shepard-normalised pressure of the fluid particles around `point`, Pa:
// sum_b V_b p_b W_b / sum_b V_b W_b with V_b = m_b / rho_b. NaN when no fluid
// particle is within 2h (the probe is dry).
template <int D>
double probe_pressure(const Vec<D>& point, const Particles<D>& P, const CellList<D>& cells, const WendlandC2<D>& W,
                      const PeriodicBox<D>& box) {
  Vec<D> x = point;
  box.wrap(x);
  const double support2 = W.support_radius() * W.support_radius();
  double num = 0.0, den = 0.0;
  cells.for_each_neighbour(x, [&](int b, const Vec<D>& shift) {
    if (P.kind[b] != Kind::fluid) return;
    const double r2 = (x - P.x[b] - shift).squaredNorm();
    if (r2 >= support2) return;
    const double w = P.mass[b] / P.rho[b] * W.value(std::sqrt(r2));
    num += w * P.p[b];
    den += w;
  });
  return den > 0.0 ? num / den : std::numeric_limits<double>::quiet_NaN();
}

// Counts the signed volume m/rho of fluid particles whose step displacement
// crosses the patch (+ along its normal), so flow_rate() is the mean volume
// flux since the last reading: m^3/s in 3D, m^2/s (per unit depth) in 2D.
template <int D>
class FlowPlane {
 public:
  explicit FlowPlane(const PlanePatch& spec) : name(spec.name), patch_(spec) {}

  std::string name;

  // Displacement x_old -> x_old + dx of one particle of volume V during a step.
  // x_old is taken to the image nearest the plane centre along periodic axes.
  void crossing(Vec<D> x_old, const Vec<D>& dx, double volume, const PeriodicBox<D>& box) {
    for (int d = 0; d < D; ++d) {
      if (!box.periodic[d]) continue;
      const double L = box.hi[d] - box.lo[d];
      x_old[d] -= L * std::round((x_old[d] - patch_.c[d]) / L);
    }
    const double s0 = patch_.height(x_old), s1 = s0 + dx.dot(patch_.n);
    const bool forward = s0 < 0.0 && s1 >= 0.0, backward = s0 >= 0.0 && s1 < 0.0;
    if (!forward && !backward) return;
    if (!patch_.contains(x_old + (s0 / (s0 - s1)) * dx - patch_.c)) return;
    volume_ += forward ? volume : -volume;
  }

  // Mean flux since the previous call over `elapsed` seconds; resets the count.
  double flow_rate(double elapsed) {
    const double q = elapsed > 0.0 ? volume_ / elapsed : 0.0;
    volume_ = 0.0;
    return q;
  }

 private:
  Patch<D> patch_;
  double volume_ = 0.0;
};

}  // namespace sph
