// What a run writes: frames (rows ordered by particle id) and the time series
// of probes, flow planes, inflow/outflow, wall forces, kinetic energy and
// density deviation.
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "parameters.h"
#include "open_boundaries.h"
#include "output_h5.h"
#include "probes.h"
#include "simulation.h"

namespace sph {

// Each impactor's series (impactors.h): its centre, velocity, angular velocity, orientation (the quaternion w, x, y, z
// turning body axes into world ones), the contact force on it (of the last evaluation: mid-step during a run), its
// kinetic energy and its contact energy with the particles as they are.
inline constexpr std::tuple<const char*, int, const char*> impactor_series[] = {
    {"position", 3, "m"}, {"velocity", 3, "m/s"}, {"angular_velocity", 3, "rad/s"}, {"orientation", 4, "1"},
    {"force", 3, "N"}, {"kinetic_energy", 0, "J"}, {"contact_energy", 0, "J"}};
inline constexpr int impactor_columns = 18;
// Each grain's series (grains.h): its centre of mass, velocity, angular velocity, orientation, the fluid's force
// and torque about its centre on it (eq. G2), and its contacts' force (eqs. G6-G8), of the last evaluation (mid-step
// during a run; its body force apart); then over every step since the previous record the contacts' impulse, their
// largest force and the time they acted.
inline constexpr std::tuple<const char*, int, const char*> grain_series[] = {
    {"position", 3, "m"}, {"velocity", 3, "m/s"}, {"angular_velocity", 3, "rad/s"}, {"orientation", 4, "1"},
    {"force", 3, "N"}, {"torque", 3, "N m"}, {"contact", 3, "N"}, {"contact_impulse", 3, "N s"},
    {"contact_peak", 0, "N"}, {"contact_time", 0, "s"}};
inline constexpr int grain_columns = 27;

template <int D, class Sim>
class Recorder {
 public:
  Recorder(const RunParameters& deck, Sim& sim, OpenBoundaries<D>& open, OutputFile& out)
      : sim_(sim), open_(open), out_(out) {
    out.attr("engine", std::string("sph"));
    out.attr("engine_version", std::string(SPH_VERSION));
    out.attr("dimension", static_cast<long>(D));
    out.attr("physics", deck.terms_string());
    out.attr("n_particles", static_cast<long>(sim.particles().size()));
    out.attr("h", deck.h);
    out.attr("dx", deck.dx);
    out.attr("status", std::string("running"));
    out.attr("message", std::string());
    const std::string area_flux = D == 3 ? "m^3/s" : "m^2/s";
    for (const auto& p : deck.probes) {
      probes_.push_back(Eigen::Map<const Vec<D>>(p.point.data()));
      out.series("pressure_probe_" + p.name, 0, "Pa");
    }
    for (const auto& f : deck.flow_planes) {
      planes_.emplace_back(f);
      out.series("flow_rate_" + f.name, 0, area_flux);
    }
    for (std::size_t k = 0; k < open.count(); ++k)
      out.series((open.is_inlet(k) ? "inflow_" : "outflow_") + open.name(k), 0, area_flux);
    for (std::size_t j : open.columns()) {
      out.series("column_pressure_" + open.outlet_name(j), 0, "Pa");
      out.series("column_speed_" + open.outlet_name(j), 0, "m/s");
    }
    if (deck.terms & term::wall_penalty)
      for (const auto& m : sim.walls().meshes()) out.series("wall_force_" + m.name, D, D == 3 ? "N" : "N/m");
    out.series("kinetic_energy", 0, D == 3 ? "J" : "J/m");
    out.series("max_density_deviation", 0, "1");
    if constexpr (Sim::tensor) {
      out.series("shear_stress", 0, "Pa");
      out.series("first_normal_stress_difference", 0, "Pa");
    }
    if (sim.images().lees_edwards()) {
      out.series("shear_strain", 0, "1");
      out.series("shear_rate", 0, "1/s");
    }
    for (const auto& b : sim.impactors().bodies())
      for (const auto& [what, cols, units] : impactor_series) out.series("impactor_" + b.name + "_" + what, cols, units);
    for (const auto& g : sim.grains().grains())
      for (const auto& [what, cols, units] : grain_series) out.series("grain_" + g.name + "_" + what, cols, units);
    const std::size_t extra = (Sim::tensor ? 2 : 0) + (sim.images().lees_edwards() ? 2 : 0);
    const std::size_t bodies = sim.impactors().bodies().size(), grains = sim.grains().grains().size();
    const std::size_t n = sim.particles().x.capacity();
    const std::size_t scalars = probes_.size() + planes_.size() + open.count() + 2 * open.columns().size();
    values_.resize(scalars + D * sim.walls().meshes().size() + 2 + extra + impactor_columns * bodies +
                   grain_columns * grains);
    std::size_t j = 0;  // where each series' row starts in values_
    for (std::size_t i = 0; i < scalars; ++i) rows_.push_back(&values_[j++]);
    for (std::size_t m = 0; m < sim.walls().meshes().size(); ++m, j += D) rows_.push_back(&values_[j]);
    rows_.push_back(&values_[j++]);
    rows_.push_back(&values_[j++]);
    for (std::size_t e = 0; e < extra; ++e) rows_.push_back(&values_[j++]);
    for (std::size_t b = 0; b < bodies; ++b)
      for (const auto& series : impactor_series) rows_.push_back(&values_[j]), j += std::max(1, std::get<1>(series));
    for (std::size_t g = 0; g < grains; ++g)
      for (const auto& series : grain_series) rows_.push_back(&values_[j]), j += std::max(1, std::get<1>(series));
    ids_.reserve(n), kind_.reserve(n), x_.reserve(n * D), v_.reserve(n * D), rho_.reserve(n), p_.reserve(n);
    order_.reserve(n);
    if (sim.particles().has_stress) field_.reserve(n * D * D);
    if (sim.particles().modes) field_.reserve(n * D * D * sim.particles().modes);
    if (sim.particles().solid) field_.reserve(n * SolidState::SizeAtCompileTime);
  }

  bool has_flow_planes() const { return !planes_.empty(); }
  void cross(const Vec<D>& x_old, const Vec<D>& dx, double volume) {
    for (auto& plane : planes_) plane.crossing(x_old, dx, volume, sim_.box());
  }
  double last_series_time() const { return last_series_; }
  double last_frame_time() const { return last_frame_; }

  // One row of every series at time t; the simulation must be sorted and its EOS current.
  void series(double t) {
    const auto& P = sim_.particles();
    std::size_t k = 0;
    for (const auto& point : probes_) values_[k++] = probe_pressure(point, P, sim_.cells(), sim_.kernel(), sim_.box());
    const double elapsed = last_series_ < 0.0 ? 0.0 : t - last_series_;
    for (auto& plane : planes_) values_[k++] = plane.flow_rate(elapsed);
    for (std::size_t b = 0; b < open_.count(); ++b) values_[k++] = open_.flow_rate(b, elapsed);
    for (std::size_t j : open_.columns()) values_[k++] = open_.column_pressure(j), values_[k++] = open_.column_speed(j);
    const std::size_t wall_base = k;
    if (!sim_.walls().meshes().empty()) {
      const std::size_t nm = sim_.walls().meshes().size();
      std::fill(values_.begin() + k, values_.begin() + k + D * nm, 0.0);
      for (std::size_t i = 0; i < P.size(); ++i)
        if (P.moves(i))
          sim_.walls().force(P.x[i], [&](int m, const Vec<D>& F) {
            for (int d = 0; d < D; ++d) values_[wall_base + D * m + d] -= F[d];  // reaction on the mesh
          });
      k += D * nm;
    }
    double ke = 0.0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (P.moves(i)) ke += 0.5 * P.mass[i] * P.v[i].squaredNorm();
    values_[k++] = ke;
    values_[k++] = sim_.max_density_deviation();
    if constexpr (Sim::tensor) {  // the fluid's volume-averaged extra stress (Lees-Edwards cell: the rheometer's)
      const Mat<D> tau = sim_.mean_extra_stress();
      values_[k++] = tau(0, 1);
      values_[k++] = tau(0, 0) - tau(1, 1);
    }
    if (sim_.images().lees_edwards()) {
      values_[k++] = sim_.images().strain(t);
      values_[k++] = sim_.images().strain_rate(t);
    }
    for (std::size_t i = 0; i < sim_.impactors().bodies().size(); ++i) {
      const auto& b = sim_.impactors().bodies()[i];
      const auto& q = b.state.orientation;
      const double row[impactor_columns] = {
          b.state.position.x(), b.state.position.y(), b.state.position.z(), b.state.velocity.x(), b.state.velocity.y(),
          b.state.velocity.z(), b.state.angular_velocity.x(), b.state.angular_velocity.y(), b.state.angular_velocity.z(),
          q.w(), q.x(), q.y(), q.z(), b.wrench.force.x(), b.wrench.force.y(), b.wrench.force.z(),
          rigid::kinetic_energy(b.body, b.state), sim_.impactors().contact_energy_at(P, static_cast<int>(i))};
      std::copy(row, row + impactor_columns, values_.begin() + k), k += impactor_columns;
    }
    for (const auto& g : sim_.grains().grains()) {
      const auto& s = g.state;
      const auto& q = s.orientation;
      const double row[grain_columns] = {
          s.position.x(), s.position.y(), s.position.z(), s.velocity.x(), s.velocity.y(), s.velocity.z(),
          s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z(), q.w(), q.x(), q.y(), q.z(),
          g.wrench.force.x(), g.wrench.force.y(), g.wrench.force.z(), g.wrench.torque.x(), g.wrench.torque.y(),
          g.wrench.torque.z(), g.contact.x(), g.contact.y(), g.contact.z(), g.contact_impulse.x(),
          g.contact_impulse.y(), g.contact_impulse.z(), g.contact_peak, g.contact_time};
      std::copy(row, row + grain_columns, values_.begin() + k), k += grain_columns;
      g.close_interval();
    }
    out_.record(t, rows_);
    last_series_ = t;
  }

  // The current state as a frame, rows in input order.
  void frame(double t, long step) {
    const auto& P = sim_.particles();
    write(t, step, P.x, P.v, P.rho, false);
  }

  // The start-of-step state of a failed step (the last state that passed the checks).
  void last_good_frame(double t, long step) {
    const auto& P = sim_.particles();
    write(t, step, P.x0, P.v0, P.rho0, true);
    out_.attr("last_good_frame", static_cast<long>(out_.frames_written() - 1));
  }

 private:
  void write(double t, long step, const std::vector<Vec<D>>& x, const std::vector<Vec<D>>& v,
             const std::vector<double>& rho, bool start_state) {
    const bool recompute_pressure = start_state;
    const auto& P = sim_.particles();
    const std::size_t n = P.size();
    order_.resize(n);
    for (std::size_t i = 0; i < n; ++i) order_[i] = i;
    std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) { return P.id[a] < P.id[b]; });
    ids_.resize(n), kind_.resize(n), x_.resize(n * D), v_.resize(n * D), rho_.resize(n), p_.resize(n);
    for (std::size_t r = 0; r < n; ++r) {
      const std::size_t i = order_[r];
      ids_[r] = P.id[i];
      kind_[r] = static_cast<std::int8_t>(P.kind[i]);
      for (int d = 0; d < D; ++d) x_[r * D + d] = x[i][d], v_[r * D + d] = v[i][d];
      rho_[r] = rho[i];
      p_[r] = recompute_pressure ? sim_.eos(P.material[i]).pressure(rho[i]) : P.p[i];
    }
    out_.frame(t, step, n, D, ids_.data(), kind_.data(), x_.data(), v_.data(), rho_.data(), p_.data());
    // The integrated fields beyond velocity and density (each declared once in Particles), as its own dataset.
    auto& Q = sim_.particles();
    Q.for_integrated([&](auto& f, Integrates) {
      using T = typename std::decay_t<decltype(f.value)>::value_type;
      if constexpr (!std::is_arithmetic_v<T>) {
        if constexpr (T::ColsAtCompileTime == Eigen::Dynamic) {  // per-mode stresses: (n, modes D D), row-major per mode
          const auto& values = start_state ? f.start : f.value;
          const int cols = Q.modes * D * D;
          field_.resize(n * cols);
          for (std::size_t r = 0; r < n; ++r)
            for (int c = 0; c < cols; ++c) {
              const int mode = c / (D * D), i = c % (D * D) / D, j = c % D;
              field_[r * cols + c] = values[order_[r]](j * D + i, mode);  // column-major tau of the mode
            }
          out_.frame_field(f.output, n, cols, field_.data());
        } else if constexpr (T::SizeAtCompileTime != D) {  // velocities are written above
          const auto& values = start_state ? f.start : f.value;
          constexpr int cols = T::SizeAtCompileTime;
          field_.resize(n * cols);
          for (std::size_t r = 0; r < n; ++r)
            for (int c = 0; c < cols; ++c) {
              if constexpr (T::ColsAtCompileTime == 1) field_[r * cols + c] = values[order_[r]](c);  // a solid's scalars
              else field_[r * cols + c] = values[order_[r]](c / D, c % D);
            }
          out_.frame_field(f.output, n, cols, field_.data());
        }
      }
    });
    last_frame_ = t;
  }

  Sim& sim_;
  OpenBoundaries<D>& open_;
  OutputFile& out_;
  std::vector<Vec<D>> probes_;
  std::vector<FlowPlane<D>> planes_;
  std::vector<double> values_;
  std::vector<const double*> rows_;
  double last_series_ = -1.0, last_frame_ = -1.0;
  std::vector<std::int64_t> ids_;
  std::vector<std::int8_t> kind_;
  std::vector<double> x_, v_, rho_, p_, field_;
  std::vector<std::size_t> order_;
};

}  // namespace sph
