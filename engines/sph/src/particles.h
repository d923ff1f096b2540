// Particle state as a structure of arrays, each field declared once.
//
// Integrated fields (velocity, density, deviatoric stress) are listed once in
// `for_integrated`, each with its rate (the rate of the last evaluation: the
// previous half step), its start-of-step copy, its second buffers and which
// particles integrate it; carried fields (mass, kind, id, material) once in
// `for_carried`. resize, reserve, reorder, compact, the predictor, the
// corrector (integrator.h) and the frames (recorder.h) loop over these lists,
// so a new state variable is one line here. Position is integrated by its own
// rule (x' = x + dt (v + v')/2, integrator.h) and listed apart.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "input_h5.h"
#include "materials/solid_state.h"
#include "parallel.h"
#include "physics_terms.h"
#include "vec.h"

namespace sph {

// Which particles integrate a field: all of them, or those that change position (not fixed boundary).
enum class Integrates : std::uint8_t { all, advecting };

// One integrated field: value, rate d value/dt, start-of-step copy, second buffers of the three.
template <class T>
struct Field {
  explicit Field(const char* name) : output(name) {}
  const char* output;  // frame dataset name
  std::vector<T> value, rate, start, next_value, next_rate, next_start;
  template <class F>
  void each_array(F&& f) {
    f(value), f(rate), f(start), f(next_value), f(next_rate), f(next_start);
  }
};

// Sums of the weighted least-squares fit of a fixed boundary particle's wall
// extrapolation (boundary_particles.h, eq. WP2): sum w a a^T and sum w a (v_f - v_w)^T
// over its fluid neighbours, a = the fit's K basis values; zero between evaluations.
// The normal matrix is symmetric and its LDLT reads the lower triangle only, so only
// that is summed, packed row by row: entry (i, j), j <= i, at i (i + 1) / 2 + j.
template <int D>
struct WallFit {
  static constexpr int K = D == 3 ? 5 : 3;
  static constexpr int packed = K * (K + 1) / 2;
  std::array<double, packed> normal{};  // lower triangle of sum w a a^T
  Eigen::Matrix<double, K, D> rhs = Eigen::Matrix<double, K, D>::Zero();
  double behind = 0.0;    // sum of w over fluid neighbours behind the wall's tangent plane (s < 0)
  double pressure = 0.0;  // sum of w p_f (the wall pressure, eq. WP3)
  double density = 0.0;   // sum of w rho_f (the wall density, eq. WP3)
};

// A boundary particle's wall frame for the fit of eq. WP2, a function of its
// wall_offset x_w - x_b alone (walls never move, so it is taken once: see
// Particles::set_wall_frames): depth d_b = |x_w - x_b| (NaN: no wall point;
// 0: on the wall surface), unit normal n = (x_w - x_b) / d_b and, in 3D, a
// tangent pair e1, e2 (any orthonormal pair: the fit's quadratic form in
// (t1, t2) does not depend on which). n, e1, e2 are NaN unless d_b > 0.
template <int D>
struct WallFrame {
  Vec<D> n, e1, e2;
  double depth;
};
template <int D>
WallFrame<D> wall_frame_of(const Vec<D>& offset) {
  const Vec<D> nan = Vec<D>::Constant(std::numeric_limits<double>::quiet_NaN());
  WallFrame<D> f{nan, nan, nan, offset.norm()};
  if (!(f.depth > 0.0)) return f;
  f.n = offset / f.depth;
  if constexpr (D == 3) {
    int k = 0;
    for (int d = 1; d < 3; ++d)
      if (std::abs(f.n[d]) < std::abs(f.n[k])) k = d;
    f.e1 = f.n.cross(Vec<D>::Unit(k)).normalized(), f.e2 = f.n.cross(f.e1);
  }
  return f;
}

template <int D>
struct Particles {
  // -- integrated (value, rate, start-of-step copy); names are the frame datasets
  std::vector<Vec<D>> x, x0, next_x, next_x0;  // position m (rate: v, integrator.h), its start copy, second buffers
  Field<Vec<D>> vel{"velocities"};   // velocity m/s, rate dv/dt m/s^2
  Field<double> dens{"densities"};    // density kg/m^3, rate drho/dt kg/m^3/s
  Field<Mat<D>> stress{"stress"};     // deviatoric stress tau Pa, rate Pa/s (only when has_stress), frames (n, D*D) row-major
  bool has_stress = false;            // a material of the run carries a deviatoric stress
  bool eddy = false;                  // Smagorinsky eddy viscosity (eddy_viscosity.h): nu_t carried, grad_v summed
  std::vector<double> nu_t, next_nu_t;  // eddy viscosity m^2/s of the last evaluation (eddy; 0 for fixed particles)
  Field<ModeStress<D>> mode_stress{"mode_stress"};  // per-mode stresses tau_i Pa (PTT), rate Pa/s; only when modes > 0
  int modes = 0;                      // stress modes of the run (0: none)
  Field<SolidState> solid_state{"solid_state"};  // a solid's scalars (materials/solid_state.h); only when solid
  bool solid = false;                 // the run's materials are solids
  std::vector<SavedField> saved;      // a resumed run's fields from the particle file, until restore_fields.h sets them
  // -- carried (reordered, compacted, never integrated)
  std::vector<double> mass;             // kg
  std::vector<Kind> kind;
  std::vector<std::int64_t> id;         // input row, or a new number for inflow (stable across reordering)
  std::vector<std::uint8_t> material;   // index into the run's materials
  std::vector<double> next_mass;
  std::vector<Kind> next_kind;
  std::vector<std::int64_t> next_id;
  std::vector<std::uint8_t> next_material;
  std::vector<Mat<D>> tau_solvent, next_tau_solvent;  // solvent stress 2 eta_s D Pa of the last evaluation (modes > 0)
  bool has_wall_points = false;                       // the input gave `wall_point` (boundary_particles.h)
  std::vector<Vec<D>> wall_offset, next_wall_offset;  // m: wall point - position (boundary; wrap-proof); NaN: none
  std::vector<WallFrame<D>> wall_frame, next_wall_frame;  // of wall_offset (set_wall_frames; fresh entries: none)
  bool grains = false;                                // the run has rigid grains (grains.h)
  std::vector<std::int32_t> grain, next_grain;        // a body particle's grain (index into the deck's), else -1
  std::vector<Vec<D>> grain_offset, next_grain_offset;  // m: a body particle's offset in its grain's body frame
  std::vector<Vec<D>> grain_spin, next_grain_spin;  // rad/s: a body particle's grain's angular velocity (3D)
  std::vector<Vec<D>> grain_lever, next_grain_lever;  // m/s: a body particle's sum of eq. G5 (zero between evaluations)
  std::array<bool, 256> solid_material{};  // per material index: a solid (start_solids; eqs. FS1, G8)
  bool corrected_momentum = false;  // a material sums momentum with eq. KC1: grad_correction carried
  std::vector<Mat<D>> grad_correction, next_grad_correction;  // M^-T of the last evaluation (eq. KC1), else I
  // -- derived each evaluation
  std::vector<double> p, c;          // pressure Pa, sound speed m/s
  std::vector<double> vol, p_rho2;   // m/rho m^D, p/rho^2 (saves divisions in the pair loop)
  std::vector<Vec<D>> v_noslip;      // velocity seen by the viscous term: v for fluid, mirrored for boundary
  std::vector<Vec<D>> x_noslip;      // Shepard sum of the fluid positions around a boundary particle (has_wall_points)
  std::vector<WallFit<D>> wall_fit;  // weighted quadratic-fit sums of the same fluid (has_wall_points; vec.h)
  std::vector<Mat<D>> grad_v;        // velocity gradient (tensor() or eddy): row i, column j is d v_i / d x_j
  std::vector<Mat<D>> shape;         // kernel-correction sum M of eq. T2, its upper triangle (tensor())
  std::vector<Mat<D>> sigma_rho2;    // (-p I + tau) / rho^2 (tensor())
  std::vector<Mat<D>> art_stress;    // Monaghan's artificial stress R / rho^2 (solid)
  bool diffuses = false;             // stress diffusion (eq. SD1 of materials/ptt.h): mode_laplacian summed
  std::vector<ModeStress<D>> mode_laplacian;  // sum_b V_b 2 F r^2 / (r^2 + 0.01 h^2) (tau_a - tau_b) per mode, Pa/m^2

  // Short names of the integrated values and rates used all over the solver.
  std::vector<Vec<D>>& v = vel.value;
  std::vector<Vec<D>>& acc = vel.rate;
  std::vector<Vec<D>>& v0 = vel.start;
  std::vector<double>& rho = dens.value;
  std::vector<double>& drho = dens.rate;
  std::vector<double>& rho0 = dens.start;
  std::vector<Mat<D>>& tau = stress.value;
  std::vector<Mat<D>>& dtau = stress.rate;

  Particles() = default;
  Particles(const Particles& o) { *this = o; }
  Particles(Particles&& o) noexcept { *this = std::move(o); }
  Particles& operator=(const Particles& o) { return assign(o); }
  Particles& operator=(Particles&& o) noexcept { return assign(std::move(o)); }

  // f(field, integrates) for every integrated field but position (one line per field).
  template <class F>
  void for_integrated(F&& f) {
    f(vel, Integrates::advecting);  // acc is zero for all but fluid
    f(dens, Integrates::all);
    if (has_stress) f(stress, Integrates::advecting);
    if (modes) f(mode_stress, Integrates::advecting);
    if (solid) f(solid_state, Integrates::advecting);
  }
  // f(array, second buffer) for every carried field.
  template <class F>
  void for_carried(F&& f) {
    f(mass, next_mass), f(kind, next_kind), f(id, next_id), f(material, next_material);
    if (modes) f(tau_solvent, next_tau_solvent);
    if (eddy) f(nu_t, next_nu_t);
    if (has_wall_points) f(wall_offset, next_wall_offset), f(wall_frame, next_wall_frame);
    if (grains) f(grain, next_grain), f(grain_offset, next_grain_offset), f(grain_spin, next_grain_spin),
                    f(grain_lever, next_grain_lever);
    if (corrected_momentum) f(grad_correction, next_grad_correction);
  }

  // The wall frames of every particle from its wall_offset (call after setting wall offsets; Simulation does).
  void set_wall_frames() {
    if (has_wall_points)
      parallel_for(static_cast<std::ptrdiff_t>(size()), parallel_min_light,
                   [this](std::ptrdiff_t i) { wall_frame[i] = wall_frame_of(wall_offset[i]); });
  }

  std::size_t size() const { return x.size(); }
  bool tensor() const { return has_stress || modes > 0; }  // momentum in the tensor form: gradients and sigma
  bool moves(std::size_t a) const { return kind[a] == Kind::fluid; }       // integrates the forces
  bool advects(std::size_t a) const { return kind[a] != Kind::boundary; }  // changes position
  bool wall(std::size_t a) const { return kind[a] == Kind::boundary || kind[a] == Kind::body; }  // no-slip, never pulls
  // A grain's particle g beside a solid's particle s: no pair terms between them (eq. G8 of grains.h acts instead).
  bool grain_beside_solid(std::size_t g, std::size_t s) const {
    return kind[g] == Kind::body && solid_material[material[s]];
  }
  // Whether a and b are across a fluid-solid interface: one of a solid's material, the other not (eq. FS2).
  bool across_interface(int a, int b) const { return solid_material[material[a]] != solid_material[material[b]]; }
  bool integrates(Integrates who, std::size_t a) const { return who == Integrates::all || advects(a); }

  void resize(std::size_t n) {
    for (auto* a : {&x, &x0, &v_noslip}) a->resize(n, Vec<D>::Zero());
    for (auto* a : {&p, &c, &vol, &p_rho2}) a->resize(n, 0.0);
    for_integrated([n, this](auto& f, Integrates) {
      const auto z = zero<typename std::decay_t<decltype(f.value)>::value_type>(modes);
      f.value.resize(n, z), f.rate.resize(n, z), f.start.resize(n, z);
    });
    const std::size_t had = tau_solvent.size(), had_walls = wall_offset.size(), had_eddy = nu_t.size(),
                      had_grains = grain_lever.size(), had_solid = grad_correction.size();
    for_carried([n](auto& a, auto&) { a.resize(n); });
    if (grains)
      for (std::size_t i = had_grains; i < n; ++i) grain_lever[i].setZero(), grain_spin[i].setZero();  // eq. G5's sums
    if (corrected_momentum)
      for (std::size_t i = had_solid; i < n; ++i) grad_correction[i].setIdentity();  // eq. KC1: uncorrected until evaluated
    if (modes)
      for (std::size_t i = had; i < n; ++i) tau_solvent[i].setZero();  // fresh entries hold no stress
    if (eddy)
      for (std::size_t i = had_eddy; i < n; ++i) nu_t[i] = 0.0;  // fresh entries: no eddy viscosity yet
    if (has_wall_points) {
      for (std::size_t i = had_walls; i < n; ++i)
        wall_offset[i].setConstant(std::numeric_limits<double>::quiet_NaN()), wall_frame[i] = wall_frame_of(wall_offset[i]);
      x_noslip.resize(n, Vec<D>::Zero());
      wall_fit.resize(n, WallFit<D>{});
    }
    if (tensor())
      for (auto* a : {&grad_v, &shape, &sigma_rho2}) a->resize(n, Mat<D>::Zero());
    else if (eddy)
      grad_v.resize(n, Mat<D>::Zero());
    if (solid) art_stress.resize(n, Mat<D>::Zero());
    if (diffuses && modes) mode_laplacian.resize(n, zero<ModeStress<D>>(modes));
  }

  // Capacity for n particles in every array, so later growth up to n does not allocate.
  void reserve(std::size_t n) {
    for (auto* a : {&x, &x0, &next_x, &next_x0, &v_noslip, &scratch_vec_}) a->reserve(n);
    for (auto* a : {&p, &c, &vol, &p_rho2}) a->reserve(n);
    if (has_wall_points) x_noslip.reserve(n), wall_fit.reserve(n);
    for_integrated([n](auto& f, Integrates) { f.each_array([n](auto& a) { a.reserve(n); }); });
    for_carried([n](auto& a, auto& next) { a.reserve(n), next.reserve(n); });
    if (tensor())
      for (auto* a : {&grad_v, &shape, &sigma_rho2}) a->reserve(n);
    else if (eddy)
      grad_v.reserve(n);
    if (solid) art_stress.reserve(n);
    if (diffuses && modes) mode_laplacian.reserve(n);
    reserved_ = n;
  }

  // Size the second buffers for the current particle count (no allocation within the reserved capacity).
  void size_next() {
    const std::size_t n = size();
    next_x.resize(n), next_x0.resize(n);
    for_integrated([n](auto& f, Integrates) { f.next_value.resize(n), f.next_rate.resize(n), f.next_start.resize(n); });
    for_carried([n](auto&, auto& next) { next.resize(n); });
  }
  // The second buffers become the state and the start-of-step copies (after a pass filled them).
  void swap_next() {
    x.swap(next_x), x0.swap(next_x0);
    for_integrated([](auto& f, Integrates) {
      f.value.swap(f.next_value), f.rate.swap(f.next_rate), f.start.swap(f.next_start);
    });
    for_carried([](auto& a, auto& next) { a.swap(next); });
  }

  // Position and velocity by value: a caller may pass another particle's, which resize() can move.
  void append(const Vec<D> pos, const Vec<D> velocity, double density, double m, Kind k, std::int64_t ident,
              std::uint8_t mat = 0) {
    const std::size_t i = size();
    resize(i + 1);
    x[i] = pos, v[i] = velocity, rho[i] = density, mass[i] = m, kind[i] = k, id[i] = ident, material[i] = mat;
  }

  // Keep the particles for which keep(i) holds, in order (persistent state and last rates).
  template <class Keep>
  void compact(Keep&& keep) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < size(); ++i) {
      if (!keep(i)) continue;
      x[k] = x[i];
      for_integrated([i, k](auto& f, Integrates) { f.value[k] = f.value[i], f.rate[k] = f.rate[i]; });
      for_carried([i, k](auto& a, auto&) { a[k] = a[i]; });
      ++k;
    }
    resize(k);
  }

  // Reorder the persistent state, the last rates and the start-of-step state by
  // `order` (new index k takes old index order[k]); no allocation once warmed up
  // (the second buffers serve as scratch).
  void reorder(const std::vector<int>& order) {
    const std::size_t n = size();
    size_next();
    permute(x, order, n, scratch_vec_);
    permute(x0, order, n, scratch_vec_);
    for_integrated([&](auto& f, Integrates) {
      permute(f.value, order, n, f.next_value);
      permute(f.rate, order, n, f.next_value);
      permute(f.start, order, n, f.next_value);
    });
    for_carried([&](auto& a, auto& next) { permute(a, order, n, next); });
  }

 private:
  template <class T>
  static void permute(std::vector<T>& a, const std::vector<int>& order, std::size_t n, std::vector<T>& scratch) {
    scratch.resize(n);
    parallel_for(static_cast<std::ptrdiff_t>(n), parallel_min_light, [&](std::ptrdiff_t k) { scratch[k] = a[order[k]]; });
    a.swap(scratch);
  }
  template <class T>
  static T zero(int modes) {
    if constexpr (std::is_arithmetic_v<T>) return T(0);
    else if constexpr (T::ColsAtCompileTime == Eigen::Dynamic) return T::Zero(T::RowsAtCompileTime, modes);
    else return T::Zero();
  }
  // Copy or move every array (the short names above are references into the fields, so the
  // implicit copy and move would alias the source); a copy keeps the reserved capacity.
  template <class P>
  Particles& assign(P&& o) {
#define SPH_TAKE(m) m = std::forward<P>(o).m
    const std::size_t cap = std::max(o.reserved_, o.x.capacity());
    SPH_TAKE(x), SPH_TAKE(x0), SPH_TAKE(next_x), SPH_TAKE(next_x0), SPH_TAKE(vel), SPH_TAKE(dens), SPH_TAKE(stress);
    SPH_TAKE(has_stress), SPH_TAKE(eddy), SPH_TAKE(nu_t), SPH_TAKE(next_nu_t), SPH_TAKE(mode_stress), SPH_TAKE(modes), SPH_TAKE(tau_solvent), SPH_TAKE(next_tau_solvent);
    SPH_TAKE(solid_state), SPH_TAKE(solid), SPH_TAKE(saved), SPH_TAKE(art_stress), SPH_TAKE(diffuses), SPH_TAKE(mode_laplacian);
    SPH_TAKE(has_wall_points), SPH_TAKE(wall_offset), SPH_TAKE(next_wall_offset), SPH_TAKE(wall_frame),
    SPH_TAKE(next_wall_frame), SPH_TAKE(x_noslip), SPH_TAKE(wall_fit);
    SPH_TAKE(grains), SPH_TAKE(grain), SPH_TAKE(next_grain), SPH_TAKE(grain_offset), SPH_TAKE(next_grain_offset),
        SPH_TAKE(grain_spin), SPH_TAKE(next_grain_spin), SPH_TAKE(grain_lever), SPH_TAKE(solid_material),
        SPH_TAKE(next_grain_lever), SPH_TAKE(corrected_momentum), SPH_TAKE(grad_correction),
        SPH_TAKE(next_grad_correction);
    SPH_TAKE(mass), SPH_TAKE(kind), SPH_TAKE(id), SPH_TAKE(material);
    SPH_TAKE(next_mass), SPH_TAKE(next_kind), SPH_TAKE(next_id), SPH_TAKE(next_material);
    SPH_TAKE(p), SPH_TAKE(c), SPH_TAKE(vol), SPH_TAKE(p_rho2), SPH_TAKE(v_noslip);
    SPH_TAKE(grad_v), SPH_TAKE(shape), SPH_TAKE(sigma_rho2), SPH_TAKE(scratch_vec_);
#undef SPH_TAKE
    reserve(cap);
    return *this;
  }
  std::vector<Vec<D>> scratch_vec_;
  std::size_t reserved_ = 0;
};

}  // namespace sph
