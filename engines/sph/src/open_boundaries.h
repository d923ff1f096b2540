// Velocity inlets and outlets (open boundaries) made of buffer particles.
//
// Inlet: `layers` layers of inlet particles on a lattice of spacing dx sit
// behind the patch (opposite its normal) and move at the inlet velocity
// along the normal. They carry density and pressure like boundary particles.
// One that crosses the patch becomes fluid, and a new inlet particle takes
// its lateral place `layers` dx upstream, so the buffer stays full.
// Outlet: a fluid particle crossing the patch becomes an outlet particle that
// keeps its density and the normal part of its velocity (so the fluid
// upstream still sees full neighbourhoods) and is removed `layers` dx downstream.
// The volume converted at each patch gives the inflow and outflow rates.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deck.h"
#include "particles.h"
#include "plane_patch.h"

namespace sph {

template <int D>
class OpenBoundaries {
 public:
  explicit OpenBoundaries(const Deck& deck) : dx_(deck.dx), rho0_(deck.rho0) {
    for (const auto& s : deck.inlets) inlets_.push_back({Patch<D>(s.patch), s.velocity, s.layers});
    for (const auto& s : deck.outlets) outlets_.push_back({Patch<D>(s.patch), s.layers});
  }

  bool empty() const { return inlets_.empty() && outlets_.empty(); }
  std::size_t count() const { return inlets_.size() + outlets_.size(); }
  const std::string& name(std::size_t k) const {
    return k < inlets_.size() ? inlets_[k].patch.name : outlets_[k - inlets_.size()].patch.name;
  }
  bool is_inlet(std::size_t k) const { return k < inlets_.size(); }

  // Particles the inlets add over a run of t_end seconds (with a margin), for reserving.
  std::size_t extra_capacity(double t_end) const {
    double extra = 0.0;
    for (const auto& in : inlets_)
      extra += 1.2 * in.patch.area() * in.velocity * t_end / std::pow(dx_, D) +
               (in.layers + 1.0) * in.patch.lattice(dx_).size();
    return static_cast<std::size_t>(extra) + 16;
  }

  // Append the inlet buffers; returns the next free particle id.
  std::int64_t fill(Particles<D>& P, std::int64_t next_id) const {
    const double mass = rho0_ * std::pow(dx_, D);
    for (const auto& in : inlets_)
      for (const auto& q : in.patch.lattice(dx_))
        for (int l = 0; l < in.layers; ++l)
          P.append(in.patch.c + q - (l + 0.5) * dx_ * in.patch.n, in.velocity * in.patch.n, rho0_, mass, Kind::inlet,
                   next_id++);
    return next_id;
  }

  // Fluid that starts inside an outlet buffer is outlet fluid from the start
  // (not counted as outflow).
  void classify_initial(Particles<D>& P) const {
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      for (const auto& out : outlets_) {
        const double s = out.patch.height(P.x[i]);
        if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
        P.kind[i] = Kind::outlet;
        P.v[i] = std::max(P.v[i].dot(out.patch.n), 0.0) * out.patch.n;
        break;
      }
    }
  }

  // After a step: convert and remove buffer particles. event(x, m, +1 / -1)
  // is called for each particle created / removed. Returns the next free id.
  template <class Event>
  std::int64_t update(Particles<D>& P, std::int64_t next_id, Event&& event) {
    const std::size_t n = P.size();
    bool removals = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (P.kind[i] == Kind::inlet) {
        for (auto& in : inlets_) {
          const double s = in.patch.height(P.x[i]);
          if (s < 0.0 || s > 2.0 * dx_ || !in.patch.contains(P.x[i] - in.patch.c)) continue;
          P.kind[i] = Kind::fluid;
          in.volume += P.mass[i] / P.rho[i];
          const Vec<D> spawn = P.x[i] - in.layers * dx_ * in.patch.n;
          event(spawn, P.mass[i], 1.0);
          P.append(spawn, in.velocity * in.patch.n, rho0_, P.mass[i], Kind::inlet, next_id++);
          break;
        }
      } else if (P.kind[i] == Kind::fluid) {
        for (auto& out : outlets_) {
          const double s = out.patch.height(P.x[i]);
          if (s < 0.0 || s > out.layers * dx_ || !out.patch.contains(P.x[i] - out.patch.c)) continue;
          P.kind[i] = Kind::outlet;
          P.v[i] = std::max(P.v[i].dot(out.patch.n), 0.0) * out.patch.n;  // straight out, not into walls
          out.volume += P.mass[i] / P.rho[i];
          break;
        }
      } else if (P.kind[i] == Kind::outlet) {
        for (auto& out : outlets_)
          if (out.patch.height(P.x[i]) >= out.layers * dx_ && out.patch.contains(P.x[i] - out.patch.c)) {
            event(P.x[i], P.mass[i], -1.0);
            P.mass[i] = 0.0;  // marks it for removal (real particles have mass > 0)
            removals = true;
            break;
          }
      }
    }
    if (removals) P.compact([&](std::size_t i) { return P.mass[i] > 0.0; });
    return next_id;
  }

  // Mean inflow (k an inlet) or outflow (k an outlet) since the last reading, m^3/s (m^2/s in 2D).
  double flow_rate(std::size_t k, double elapsed) {
    double& v = k < inlets_.size() ? inlets_[k].volume : outlets_[k - inlets_.size()].volume;
    const double q = elapsed > 0.0 ? v / elapsed : 0.0;
    v = 0.0;
    return q;
  }

 private:
  struct Inlet {
    Patch<D> patch;
    double velocity;
    int layers;
    double volume = 0.0;
  };
  struct Outlet {
    Patch<D> patch;
    int layers;
    double volume = 0.0;
  };
  double dx_, rho0_;
  std::vector<Inlet> inlets_;
  std::vector<Outlet> outlets_;
};

}  // namespace sph
