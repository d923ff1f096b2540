// An outlet's buffer (open_boundaries.h): its patch and options, and the zero-gradient velocity its
// particles take from the fluid before the patch.
//
// Options (parameters.h OutletSpec):
// - pressure p_ref: the buffer holds rho_ref = rho0 (1 + gamma (p_ref - p_B)
//   / (rho0 c0^2))^(1/gamma) (eq. 6 inverted), the domain's reference
//   pressure, so the mean density cannot drift; its particles move at the
//   fluid's normal speed before the patch (velocity_behind);
// - backflow (with a pressure): a pressure opening, whose buffer may move
//   inward at that speed; a buffer particle crossing the patch inward becomes
//   fluid at the held pressure and a new one takes its place layers dx
//   downstream (OpenBoundaries::enter_through);
// - column_length L, column_loss K (with a pressure; one material): a column
//   outlet. Beyond the patch lies a liquid column of length L (the part of a
//   pipe or gap the scene leaves out, of cross-section A: column_area, by
//   default the patch's area) that ends at the
//   held pressure p_ref. It is lumped as a chamber of volume V = 4 A L / pi^2
//   (the column's compliance with the fluid's EOS, so that the lumped column
//   rings at its quarter-wave frequency pi c0 / (2 L)) and, beyond it, the
//   column's inertia and loss (eq. OB5):
//       d(rho_c V)/dt = m_in - rho_c A u,
//       rho0 L du/dt  = p(rho_c) - p_ref - K rho0 u |u| / 2,
//   m_in the mass rate the fluid brings across the patch, sum m v_n / (layers
//   dx) over the fluid within layers dx before it (a smooth measure: counting
//   the particles as they cross would kick the chamber by one particle's
//   mass at a time). The buffer holds the chamber's density rho_c
//   (a pressure outlet whose pressure is the chamber's) and the fluid's
//   zero-gradient speeds. At steady flow p(rho_c) = p_ref + K rho0 u^2 / 2,
//   and while the flow changes the column's inertia holds the fluid back: a
//   truncated leak path no longer drains a scene at rest in microseconds.
//   rho_c and u start from the buffer's particles (their mean density and
//   normal speed: a resumed run carries on).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "eos.h"
#include "parameters.h"
#include "particles.h"
#include "plane_patch.h"
#include "vec.h"

namespace sph {

// An outlet: fluid crossing its patch becomes buffer, removed `layers` dx downstream.
template <int D>
struct OutletBuffer {
  OutletBuffer(const Patch<D>& p, int l) : patch(p), layers(l) {}
  Patch<D> patch;
  int layers;
  double volume = 0.0;
  bool holds = false;                 // holds a reference pressure
  bool backflow = false;              // a pressure opening: its buffer may move inward and feed the fluid
  std::vector<double> rho0, rho_ref;  // per material, kg/m^3
  std::vector<Vec<D>> behind_q;       // in-plane offsets of the fluid within layers dx before the patch
  std::vector<double> behind_v;       // and their speeds along the normal, m/s
  // behind_q binned in the plane: (cell key, index) sorted, cells 2 dx (1 + 1e-9) wide along u (and w)
  std::vector<std::pair<std::int64_t, std::uint32_t>> behind_cells;
  double cell_width = 0.0;
  // A column outlet (eq. OB5): length, loss coefficient, the column's speed u and the chamber's density.
  double column_length = 0.0, column_loss = 0.0;  // m, -
  double column_area = 0.0;                        // A, m^2
  double column_speed = 0.0, chamber_rho = 0.0;    // u m/s, rho_c kg/m^3
  double mass_flux = 0.0;                           // m_in, kg/s (gather_fluid_behind)
  bool column_started = false;
  double p_ref = 0.0;                              // the held pressure, Pa
  TaitEos eos{};                                   // the material's (with its floor)

  bool column() const { return column_length > 0.0; }
  // The density a buffer particle of material m takes: the held one, or a column's chamber density.
  double buffer_density(std::uint8_t m) const { return column() && column_started ? chamber_rho : rho_ref[m]; }

  // Eq. OB5 over dt (s): the chamber's mass balance, then the column's speed (its loss implicit).
  void advance_column(double dt) {
    const double area = column_area, volume = 4.0 * area * column_length / (M_PI * M_PI);
    chamber_rho += dt * (mass_flux - chamber_rho * area * column_speed) / volume;
    const double u = column_speed + dt * (eos.pressure(chamber_rho) - p_ref) / (rho0[0] * column_length);
    column_speed = u / (1.0 + dt * column_loss * std::abs(column_speed) / (2.0 * column_length));
  }
  // rho_c and u from the buffer's particles (the held density and rest if it has none).
  void start_column(const Particles<D>& P, double dx) {
    double rho = 0.0, speed = 0.0, count = 0.0;
    for (std::size_t i = 0; i < P.size(); ++i) {
      const Vec<D> q = P.x[i] - patch.c;
      const double s = q.dot(patch.n);
      if (P.kind[i] != Kind::outlet || s < 0.0 || s > layers * dx || !patch.contains(q)) continue;
      rho += P.rho[i], speed += P.v[i].dot(patch.n), count += 1.0;
    }
    chamber_rho = count > 0.0 ? rho / count : rho_ref[0];
    column_speed = count > 0.0 ? speed / count : 0.0;
    column_started = true;
  }

  // The fluid within layers dx before an outlet's patch: in-plane offsets and normal speeds.
  void gather_fluid_behind(const Particles<D>& P, double dx) {
    behind_q.clear(), behind_v.clear();
    mass_flux = 0.0;
    for (std::size_t i = 0; i < P.size(); ++i) {
      if (P.kind[i] != Kind::fluid) continue;
      const Vec<D> q = P.x[i] - patch.c;
      const double s = q.dot(patch.n);
      if (s >= 0.0 || s < -layers * dx || !patch.contains(q)) continue;
      behind_q.push_back(q - s * patch.n);
      behind_v.push_back(P.v[i].dot(patch.n));
      mass_flux += P.mass[i] * behind_v.back() / (layers * dx);
    }
    cell_width = 2.0 * dx * (1.0 + 1e-9);  // the widest reach of velocity_behind, with room for round-off
    behind_cells.clear();
    for (std::size_t j = 0; j < behind_q.size(); ++j) behind_cells.emplace_back(cell_key(behind_q[j], 0, 0), j);
    std::sort(behind_cells.begin(), behind_cells.end());
  }
  // The key of the in-plane cell of offset q, shifted by (du, dw) cells.
  std::int64_t cell_key(const Vec<D>& q, int du, int dw) const {
    const auto cell = [&](const Vec<D>& axis) { return static_cast<std::int64_t>(std::floor(q.dot(axis) / cell_width)); };
    const std::int64_t iu = cell(patch.u) + du, iw = D == 3 ? cell(patch.w) + dw : 0;
    return (iu + (std::int64_t{1} << 30)) * (std::int64_t{1} << 31) + (iw + (std::int64_t{1} << 30));
  }
  // Normal speed of an outlet buffer particle at in-plane offset q (normal part
  // ignored): the fluid's normal speed before the patch averaged over the
  // in-plane distance d < R with weight (1 - d / R)^2 (zero-gradient
  // velocity, as the outlets of Tafuni et al. 2018), not below 0 unless the
  // outlet lets fluid back in (backflow), m/s. R = 2 dx; an opening's R = dx
  // (2 dx where no fluid lies that close): its columns beside a wall feed the
  // fluid, and at the core's speed they pushed it into the wall (test_open_boundaries.cpp).
  double velocity_behind(const Vec<D>& x_rel, double dx) const {
    const Vec<D> q = x_rel - x_rel.dot(patch.n) * patch.n;
    // the fluid in the 3 x 3 cells about q (3 in 2D), in the order gathered (the sums' order: as a sweep of all)
    thread_local std::vector<std::uint32_t> near;
    near.clear();
    for (int du = -1; du <= 1; ++du)
      for (int dw = D == 3 ? -1 : 0; dw <= (D == 3 ? 1 : 0); ++dw) {
        const std::int64_t key = cell_key(q, du, dw);
        auto it = std::lower_bound(behind_cells.begin(), behind_cells.end(), std::make_pair(key, std::uint32_t{0}));
        for (; it != behind_cells.end() && it->first == key; ++it) near.push_back(it->second);
      }
    std::sort(near.begin(), near.end());
    for (double reach = backflow ? dx : 2.0 * dx; reach <= 2.0 * dx; reach *= 2.0) {
      double sum = 0.0, weight = 0.0;
      for (const std::uint32_t j : near) {
        const double d = (behind_q[j] - q).norm();
        if (d >= reach) continue;
        const double w = (1.0 - d / reach) * (1.0 - d / reach);
        sum += w * behind_v[j], weight += w;
      }
      if (weight <= 0.0) continue;
      return backflow ? sum / weight : std::max(sum / weight, 0.0);
    }
    return 0.0;
  }
};

// An outlet's buffer from its deck entry `s`, for the run's materials.
template <int D>
OutletBuffer<D> make_outlet(const OutletSpec& s, const std::vector<MaterialSpec>& materials) {
  OutletBuffer<D> out(Patch<D>(s.patch), s.layers);
  out.holds = s.pressure.has_value();
  out.backflow = s.backflow;
  for (const auto& m : materials) {
    out.rho0.push_back(m.rho0);
    if (out.holds) out.rho_ref.push_back(material_eos(m).density(*s.pressure));  // eq. 6 (or 9) inverted
  }
  out.column_length = s.column_length, out.column_loss = s.column_loss;
  out.column_area = s.column_area > 0.0 ? s.column_area : out.patch.area();
  if (out.column()) out.p_ref = *s.pressure, out.eos = material_eos(materials[0]);
  return out;
}

}  // namespace sph
