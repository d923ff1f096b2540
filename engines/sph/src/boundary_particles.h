// Fixed boundary particles: their no-slip velocity for the viscous term (and
// the velocity gradient, eq. T2), their extra stress (tensor configurations)
// and their density when an open boundary adds or removes a particle nearby.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstddef>
#include <vector>

#include <Eigen/Cholesky>

#include "cell_list.h"
#include "kernel.h"
#include "particles.h"

namespace sph {

// No-slip at fixed boundary particles for the viscous term: a boundary
// particle b takes 2 v_b - v~_b, with v~_b the Shepard average of the fluid
// velocity around it, so the fluid sees the velocity mirrored through the
// wall (as Adami et al. 2012). Its own v_b (the wall's velocity) is unchanged.
// (v_noslip holds the Shepard sum of PairLoop::no_slip_sums_of_block before,
// shepard the weight sums.)
//
// A grain's particle mirrors the fluid's velocity relative to the grain's
// rigid motion, not to its own velocity: with omega its grain's angular
// velocity and r_fb = x_f - x_b,
//   v_b' = v_b - sum_f W_bf (v_f - v_b - omega x r_fb) / sum_f W_bf       (eq. G4)
// i.e. 2 v_b - v~_b + omega x r~_b (r~_b the Shepard mean of r_fb), so fluid
// turning with the grain sees exactly the rigid rotation (eq. 10 sums to
// zero on it). The plain mirror 2 v_b - v~_b is that of a wall translating at
// v_b: next to a turning grain it hands the fluid the rigid velocity of the
// point mirrored inward, slower by omega |r~_b| (about omega dx), as large as
// the shear across the first layer at any resolution.
//
// With a wall point x_w (the nearest point of the true wall surface, input
// dataset `wall_point`; Particles::has_wall_points), the fluid velocity is
// extrapolated along the wall normal instead, so the no-slip lies on the true
// wall rather than halfway between the lattice layers (Takeda et al. 1994,
// Morris et al. 1997 extrapolate linearly per pair). With
//   n = (x_w - x_b) / |x_w - x_b|, d_b = |x_w - x_b|,
// and, for each fluid neighbour f, its height s = (x_f - x_w) . n above the
// wall's tangent plane and its offsets t1, t2 along that plane (t in 2D):
// (WP2) a weighted least-squares fit (weights W_bf) of
//   v_f - v_w = a s + b s^2 + C11 t1^2 + C22 t2^2 + C12 t1 t2     (2D: a s + b s^2 + C t^2)
// gives v_b' = v_w - a d_b + b d_b^2 (v_w = v_b). It is exact for a
// quadratic profile along the normal (Poiseuille between plates), and the
// t terms take up the wall's curvature: next to a cylinder the fluid at a
// lateral offset t lies t^2 / (2R) nearer to (or farther from) the wall than
// s says, so a fit in s alone biases the slope. (A periodic pipe of R = 6 dx,
// h = 1.5 dx, at the exact body force: flow +4.3 % with the linear
// extrapolation below, no-slip fitted at 6.047 dx; +1.3 % and 6.0003 dx
// with WP2; annulus 3..8 dx +9.5 % -> +2.6 %, no-slip 2.934 / 8.074 ->
// 2.973 / 8.002 dx; the rest is the Morris sum's lattice bias.)
// When the fit's normal matrix is singular (the smallest LDLT pivot of the
// Jacobi-scaled matrix below min_fit_pivot times the largest: boundary
// particles deep in the wall that see a few fluid particles at one height),
// the velocity is extrapolated linearly (WP1):
//   d_f = (x~_b - x_w) . n,
//   v_b' = v_w - min(d_b / d_f, max_wall_extrapolation) (v~_b - v_w),
// with x~_b the Shepard-weighted mean position of the same fluid particles
// (x_noslip holds its sum relative to x_b, wall_fit the sums of WP2; both are
// zeroed here after use, so they are zero between evaluations), and x_w - x_b
// kept as Particles::wall_offset. v~_b is the velocity at x~_b for a linear
// field, so WP1 is exact for a linear profile; the ratio
// is taken as the limit when d_f <= d_b / max_wall_extrapolation (d_f <= 0
// included: the fluid's mean on or behind the wall surface). A boundary
// particle on the wall surface (d_b = 0) takes v_w; a NaN wall point means
// none (Adami's mirror).
//
// (WP3) A boundary particle with a wall point also takes the Shepard average of
// the fluid pressure around it, p_b = sum_f W_bf p_f / sum_f W_bf (Adami et al.
// 2012, walls at rest without body force), instead of the pressure of its own
// (summation) density, which follows how closely the fluid packs against it
// rather than the fluid's pressure: in the open pipe (R = 6 dx, h = 1.3 dx) the
// fluid's pressure gradient was 5.3 % below Hagen-Poiseuille with WP2 alone
// while its velocity profile implied 1.5 % (the walls' pressures carried part of
// the axial force); with WP3 2.2 %. The wall particle also takes the Shepard
// average of the fluid density, rho_b = sum_f W_bf rho_f / sum_f W_bf, the
// density that goes with p_b (Adami et al. invert the EOS for it), in p_b /
// rho_b^2 and V_b = m_b / rho_b: its own summation density may lie far below
// rho0 where the fluid has not yet filled its support (walls built with their
// empty sites booked out), and p_b / rho_b^2 from that density makes the
// fluid's first contact with such a wall unstable.
// A wall never pulls (as the EOS of a wall's own density, Simulation::equation_of_state_at): p_b is at
// least p_rest, the pressure of the wall material at rho0 (its background pressure). Fluid beside a wall
// at a negative gauge pressure (a fast jet leaving a hole) would otherwise give the wall's particles that
// tension, and the pairs' p_a/rho_a^2 + p_b/rho_b^2 would pull the fluid into the wall. The density that
// goes with the floor is rho_rest (rho0): at a stretched fluid's Shepard density, V_b = m_b / rho_b would
// make the wall look larger than it is in the fluid's continuity sums and drive fluid gliding past it into
// tension.
// Measured limits of WP2: max_fit_gain, the fit's noise gain
// sum_f W_bf e^T N^-1 e (N the normal matrix, e = (-d_b, d_b^2, 0, ...); a
// mirror-like linear fit gives (d_b / d_f)^2): the open pipe at h = 1.5 dx went
// unstable at 0.04 s with no limit, ran with 1e5, 1e4 and 1e3 (periodic pipe /
// annulus flow +1.28 / +2.59 %, +1.47 / +2.91 %, +1.58 / +4.15 %); fluid behind
// the wall plane (s < 0, squeezed into the staircase's gaps) is outside the
// fit's model, and the open annulus at h = 1.5 dx went unstable at 0.36 s until
// such boundary particles fell back to WP1.
//
// The limit of WP1, 8 (measured before WP2): on a flat wall of the lattice with h = 1.3 dx the second
// layer already has d_b / d_f = 3 (the first 0.97), and a wall 0.2 dx inside
// the lattice layer gives about 6, so a lower limit loses a linear profile
// (Couette between walls off the lattice, tests/test_wall_points.cpp: worst
// error 0.77 % of U with a limit of 1.5, 0.13 % with 4, 0.015 % with 8 or
// none); boundary particles deep behind a convex wall see only a few fluid
// particles at the edge of the kernel (the annulus's core: ratios up to 21)
// and the limit bounds how much their noise is amplified (a periodic annulus
// 3..8 dx: flow 7.6 % high with no limit, 7.8 % with 8, 9.0 % with 4).
// Morris et al.'s 1.5 bounds 1 + d_b/d_a per pair, whose d_a, one fluid
// particle's distance, may vanish; d_f, a Shepard mean, stays near dx/2.
inline constexpr double max_wall_extrapolation = 8.0;
inline constexpr double min_fit_pivot = 1e-6;  // smallest LDLT pivot / largest of the scaled fit (eq. WP2)
inline constexpr double max_fit_gain = 1e4;    // largest noise gain of the fit (eq. WP2), see no_slip_velocity

// Whether every fixed boundary particle has the same velocity (pairs of two of them are then left out of the list).
template <int D>
bool walls_move_together(const Particles<D>& P) {
  const Vec<D>* first = nullptr;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.kind[i] == Kind::boundary) {
      if (!first) first = &P.v[i];
      if (!(P.v[i] == *first)) return false;
    }
  return true;
}

// Whether fixed boundary particle b has a wall point: its density and pressure are the Shepard values
// of the fluid around it at each evaluation (eq. WP3, no_slip_velocity), so its stored density is
// not a state and stays as it is (no continuity rate, no booking of particles that come or go;
// integrated, it drifts over a long run beside an outlet).
template <int D>
bool holds_density(const Particles<D>& P, std::ptrdiff_t b) {
  return P.has_wall_points && P.kind[b] == Kind::boundary && !std::isnan(P.wall_offset[b][0]);
}

// The 3D fit's products (w a_i) a_j into the packed lower triangle (row after row: 1, 2, 3, 4, 5 entries)
// and (w a_i) dv_d into rhs (5 x 3, column-major), four lanes at a time: each sum takes the same product
// with the same rounding as one at a time (elementwise IEEE operations, no FMA).
inline __attribute__((always_inline)) void add_wall_fit_3d(double* lower, double* rhs, double w, const double* a,
                                                          const Vec<3>& dv) {
  typedef double v4 __attribute__((vector_size(32)));
  const auto add = [](double* to, v4 x) {
    v4 t;
    std::memcpy(&t, to, sizeof t);
    t += x;
    std::memcpy(to, &t, sizeof t);
  };
  const double wa[5] = {w * a[0], w * a[1], w * a[2], w * a[3], w * a[4]};
  const v4 a4 = {a[0], a[1], a[2], a[3]}, wa4 = {wa[0], wa[1], wa[2], wa[3]};
  add(lower, v4{wa[0], wa[1], wa[1], wa[2]} * v4{a[0], a[0], a[1], a[0]});  // rows 0-2: entries 0-3
  lower[4] += wa[2] * a[1], lower[5] += wa[2] * a[2];
  add(lower + 6, wa[3] * a4);   // row 3
  add(lower + 10, wa[4] * a4);  // row 4
  lower[14] += wa[4] * a[4];
  for (int d = 0; d < 3; ++d) add(rhs + 5 * d, wa4 * dv[d]), rhs[5 * d + 4] += wa[4] * dv[d];
}

// Add a fluid neighbour at r_fb = x_f - x_b, weight w, with velocity v_f - v_b = dv, pressure p_f and
// density rho_f, to the fit sums `fit` of a boundary particle of wall frame `frame` (eq. WP2). Each
// sum takes w a_i a_j as (w a_i) a_j (as Eigen's w * (a * a^T) rounds it), the lower triangle only.
template <int D>
inline __attribute__((always_inline)) void add_wall_fit(WallFit<D>& fit, const WallFrame<D>& frame, double w, const Vec<D>& r_fb, const Vec<D>& dv,
                         double p_f, double rho_f) {
  constexpr int K = WallFit<D>::K;
  fit.pressure += w * p_f;
  fit.density += w * rho_f;
  const double d_b = frame.depth;
  if (!(d_b > 0.0)) return;  // NaN (no wall point) or on the wall surface
  const double s = r_fb.dot(frame.n) - d_b;  // height above the wall's tangent plane
  double a[K];
  if constexpr (D == 3) {
    const double t1 = r_fb.dot(frame.e1), t2 = r_fb.dot(frame.e2);
    a[0] = s, a[1] = s * s, a[2] = t1 * t1, a[3] = t2 * t2, a[4] = t1 * t2;
  } else {
    const double t = frame.n[0] * r_fb[1] - frame.n[1] * r_fb[0];
    a[0] = s, a[1] = s * s, a[2] = t * t;
  }
  if constexpr (D == 3) {
    add_wall_fit_3d(fit.normal.data(), fit.rhs.data(), w, a, dv);
  } else {
    double* lower = fit.normal.data();
    for (int i = 0; i < K; ++i) {
      const double wa = w * a[i];
      for (int j = 0; j <= i; ++j) *lower++ += wa * a[j];
      for (int d = 0; d < D; ++d) fit.rhs(i, d) += wa * dv[d];
    }
  }
  if (s < 0.0) fit.behind += w;
}

// The no-slip sums of a boundary particle b (its Shepard sums of the fluid velocity and weight and,
// with wall points, of the fluid positions relative to it and the fit of eq. WP2), held where the
// caller accumulates them: in the particle arrays, or in locals over b's own row.
template <int D>
struct NoSlipSums {
  Vec<D>& v;
  double& weight;
  Vec<D>& x;
  WallFit<D>& fit;
};
// Add fluid particle f at r_fb = x_f - x_b, weight w > 0, to the sums s of boundary particle b.
template <int D>
inline __attribute__((always_inline)) void add_no_slip(const Particles<D>& P, int b, int f, double w, const Vec<D>& r_fb, NoSlipSums<D> s) {
  if constexpr (D == 3) {
    if (P.grains && P.kind[b] == Kind::body) {  // eq. G4: the fluid's velocity relative to the grain's rotation
      s.v += w * Vec<D>(P.v[f] - P.grain_spin[b].cross(r_fb));
      s.weight += w;
      return;
    }
  }
  s.v += w * P.v[f];
  s.weight += w;
  if (!P.has_wall_points) return;
  s.x += w * r_fb;
  add_wall_fit(s.fit, P.wall_frame[b], w, r_fb, Vec<D>(P.v[f] - P.v[b]), P.p[f], P.rho[f]);  // eq. WP2
}

// The quadratic extrapolation of eq. WP2 into boundary particle b at depth d_b behind its
// wall point: false (and v untouched) when the fit's normal matrix is singular.
template <int D>
bool quadratic_ghost(const WallFit<D>& fit, double d_b, double weight, const Vec<D>& v_w, Vec<D>& v) {
  constexpr int K = WallFit<D>::K;
  if (fit.behind > 0.0) return false;
  Eigen::Matrix<double, K, K> normal;
  for (int i = 0, k = 0; i < K; ++i)
    for (int j = 0; j <= i; ++j, ++k) normal(i, j) = normal(j, i) = fit.normal[k];
  const Eigen::Matrix<double, K, 1> diag = normal.diagonal();
  if (!(diag.minCoeff() > 0.0)) return false;
  const Eigen::Matrix<double, K, 1> scale = diag.cwiseSqrt().cwiseInverse();  // Jacobi scaling
  const Eigen::Matrix<double, K, K> scaled = scale.asDiagonal() * normal * scale.asDiagonal();
  const Eigen::LDLT<Eigen::Matrix<double, K, K>> ldlt(scaled);  // reads the lower triangle
  const auto pivots = ldlt.vectorD();
  if (ldlt.info() != Eigen::Success || !(pivots.minCoeff() > min_fit_pivot * pivots.maxCoeff())) return false;
  Eigen::Matrix<double, K, 1> e = Eigen::Matrix<double, K, 1>::Zero();
  e[0] = -d_b, e[1] = d_b * d_b;
  const Eigen::Matrix<double, K, 1> se = scale.asDiagonal() * e;
  const double gain = weight * se.dot(ldlt.solve(se));
  if (!(gain >= 0.0 && gain <= max_fit_gain)) return false;
  const Eigen::Matrix<double, K, D> c = scale.asDiagonal() * ldlt.solve(scale.asDiagonal() * fit.rhs);
  v = v_w + (d_b * d_b) * c.row(1).transpose() - d_b * c.row(0).transpose();
  return true;
}

template <int D>
void no_slip_velocity(Particles<D>& P, const std::vector<double>& shepard, std::ptrdiff_t b, double p_rest,
                      double rho_rest) {
  if (!P.wall(b)) {  // fluid and buffers; a grain's particle (Kind::body) is a moving wall
    P.v_noslip[b] = P.v[b];
    return;
  }
  const double weight = shepard[b];
  if (weight == 0.0) {  // no fluid in reach: no sum was touched (pairs of weight 0 add nothing)
    P.v_noslip[b] = P.v[b];
    return;
  }
  if (P.has_wall_points) {
    const Vec<D>& offset = P.wall_offset[b];  // x_w - x_b
    const Vec<D> mean_offset = P.x_noslip[b];  // sum w (x_f - x_b)
    const WallFit<D> fit = P.wall_fit[b];
    P.x_noslip[b].setZero();
    P.wall_fit[b] = WallFit<D>{};
    if (weight > 0.0 && !std::isnan(offset[0])) {
      P.p[b] = std::max(fit.pressure / weight, p_rest);  // eq. WP3; a wall never pulls
      P.rho[b] = std::max(fit.density / weight, rho_rest);  // the density that goes with it (Adami et al. 2012)
      P.vol[b] = P.mass[b] / P.rho[b];
      P.p_rho2[b] = P.p[b] / (P.rho[b] * P.rho[b]);
      const double d_b = P.wall_frame[b].depth;  // |offset|
      const Vec<D>& v_w = P.v[b];
      if (d_b > 0.0 && quadratic_ghost(fit, d_b, weight, v_w, P.v_noslip[b])) return;
      const Vec<D> v_mean = P.v_noslip[b] / weight;
      double ratio = 0.0;  // d_b = 0: the particle lies on the wall surface
      if (d_b > 0.0) {
        const double d_f = mean_offset.dot(offset) / (weight * d_b) - d_b;  // (x~_b - x_w) . n
        ratio = d_f * max_wall_extrapolation > d_b ? d_b / d_f : max_wall_extrapolation;
      }
      P.v_noslip[b] = v_w - ratio * (v_mean - v_w);
      return;
    }
  }
  P.v_noslip[b] = weight > 0.0 ? Vec<D>(2.0 * P.v[b] - P.v_noslip[b] / weight) : P.v[b];
}

// Extra stress of fixed boundary particles (tensor configurations: models
// with a deviatoric stress): a boundary particle b takes the Shepard average
// of the extra stress of the fluid around it,
//   tau_b = sum_f tau_f W_bf / sum_f W_bf                                  (eq. W1)
// per mode (and the solvent stress, or the single tau), as Adami et al. 2012
// extrapolate the pressure into the wall, so the fluid next to a wall feels
// the wall shear stress in eq. T1 instead of its own stress alone. A boundary
// particle with no fluid in its support keeps zero extra stress. Its pressure
// is unchanged (eq. 6 of its own density). The sums are taken with the
// no-slip sums (PairLoop::no_slip_sums_of_block), over the same weights.
// A grain's particle (Kind::body) is a moving wall and takes eq. W1 the same
// way (a PTT medium's stress at a grain's surface).
// Set the sums of boundary or grain particle b to zero (start of the gather stage).
template <class Models, int D>
void clear_wall_stress(Particles<D>& P, std::ptrdiff_t b) {
  if (!P.wall(b)) return;
  if constexpr (Models::any_single_stress) P.tau[b].setZero();
  if constexpr (Models::any_modes) P.mode_stress.value[b].setZero(), P.tau_solvent[b].setZero();
}
// Add fluid particle f's stress with weight w to the sums of boundary particle b.
template <class Models, int D>
inline void add_wall_stress(Particles<D>& P, int b, int f, double w) {
  if constexpr (Models::any_single_stress) P.tau[b].noalias() += w * P.tau[f];
  if constexpr (Models::any_modes) {
    P.mode_stress.value[b].noalias() += w * P.mode_stress.value[f];
    P.tau_solvent[b].noalias() += w * P.tau_solvent[f];
  }
}
// Divide the sums of boundary or grain particle b by its Shepard weight (eq. W1).
template <class Models, int D>
void wall_stress(Particles<D>& P, const std::vector<double>& shepard, std::ptrdiff_t b) {
  if (!P.wall(b) || !(shepard[b] > 0.0)) return;
  const double inv = 1.0 / shepard[b];
  if constexpr (Models::any_single_stress) P.tau[b] *= inv;
  if constexpr (Models::any_modes) P.mode_stress.value[b] *= inv, P.tau_solvent[b] *= inv;
}

// A particle of mass m appears (sign +1) or disappears (-1) at x (wrapped):
// change the density of the fixed boundary particles around it by its kernel
// share m W, as a summation density would, so continuity does not keep a
// memory of particles that an inlet created or an outlet removed. Boundary
// particles never move, so the cells of the last binning still hold them.
// (Not those with a wall point: their density is not a state, see holds_density.)
template <int D>
void book_boundary_density(Particles<D>& P, const CellList<D>& cells, const WendlandC2<D>& kernel, const Vec<D>& x,
                           double m, double sign) {
  const double support2 = kernel.support_radius() * kernel.support_radius();
  cells.for_each_neighbour(x, [&](int b, const Vec<D>& shift) {
    if (static_cast<std::size_t>(b) >= P.size() || P.kind[b] != Kind::boundary || holds_density(P, b)) return;
    const double r2 = (P.x[b] + shift - x).squaredNorm();
    if (r2 < support2) P.rho[b] += sign * m * kernel.value(std::sqrt(r2));
  });
}

}  // namespace sph
