// How the images of a particle are seen across the box: the image policy.
//
// The neighbour list stores, with each pair, the code of the image of b that
// a sees (periodic shifts of k_d box lengths, k_d in -2..2 per axis; code
// sum_d (k_d + 2) 5^d). The policy turns a code into the position shift
// (r_ab = x_a - x_b - shift(code)) and the velocity jump (v_ab = v_a - v_b -
// jump(code)) of that image.
//
// Plain periodic axes: no velocity jump. Lees-Edwards (set_lees_edwards; a
// sheared periodic cell, shear along axis s = 0, gradient along g = 1, strain
// gamma(t), L_s, L_g the box lengths):
//   an image across g (k_g != 0) sits at x_b + k_s L_s e_s + k_g (L_g e_g + delta e_s),
//     delta(t) = gamma(t) L_g (mod L_s)                                      (eq. LE1)
//   and moves at v_b + k_g u e_s,  u(t) = gamma_dot(t) L_g                   (eq. LE2)
//   steady shear gamma = gamma_dot t; oscillatory gamma = gamma_A sin(omega t),
//   gamma_dot = gamma_A omega cos(omega t).
// A particle crossing a g face is remapped the same way (wrap with its
// velocity). The Verlet list is built with delta_b, the offset at the build
// (taken mod L_s then); between builds the table uses the continuous
// delta_b + (gamma(t) - gamma_b) L_g, so a listed image moves smoothly with
// the shear (the list's validity check, simulation.h eq. LE3, measures
// displacements beside the affine shear). The pair loop reads jump(code) only in the
// sheared configurations (term::sheared).
#pragma once
#include <array>
#include <cmath>

#include "cell_list.h"
#include "parameters.h"
#include "vec.h"

namespace sph {

template <int D>
class PeriodicImages {
 public:
  static constexpr int codes = D == 2 ? 25 : 125;
  static constexpr int centre_code = D == 2 ? 2 + 2 * 5 : 2 + 2 * 5 + 2 * 25;  // no shift
  static constexpr int shear_axis = 0, gradient_axis = 1;

  PeriodicImages() = default;
  explicit PeriodicImages(const PeriodicBox<D>& box) : box_(box) {
    for (int code = 0; code < codes; ++code) {
      int c = code;
      for (int d = 0; d < D; ++d, c /= 5) periodic_shift_[code][d] = box.periodic[d] ? (c % 5 - 2) * length(d) : 0.0;
      k_gradient_[code] = (code / 5) % 5 - 2;  // digit of axis 1
      jump_[code] = Vec<D>::Zero();
    }
    shift_ = periodic_shift_;
  }
  // Lees-Edwards images (axes 0 and 1 must be periodic), at t = 0.
  void set_lees_edwards(const LeesEdwardsSpec& spec) {
    le_ = spec;
    update(0.0);
    rebase();
  }
  bool lees_edwards() const { return le_.on; }

  const PeriodicBox<D>& box() const { return box_; }
  const Vec<D>& shift(int code) const { return shift_[code]; }
  const Vec<D>* shifts() const { return shift_.data(); }
  const Vec<D>& jump(int code) const { return jump_[code]; }
  const Vec<D>* jumps() const { return jump_.data(); }

  // Strain gamma(t) and strain rate gamma_dot(t) 1/s of the Lees-Edwards cell.
  double strain(double t) const { return le_.shear_rate != 0.0 ? le_.shear_rate * t : le_.amplitude * std::sin(le_.omega * t); }
  double strain_rate(double t) const {
    return le_.shear_rate != 0.0 ? le_.shear_rate : le_.amplitude * le_.omega * std::cos(le_.omega * t);
  }
  // The images at time t (eqs. LE1, LE2, delta continuous since the last rebase).
  void update(double t) {
    if (!le_.on) return;
    gamma_ = strain(t);
    u_ = strain_rate(t) * length(gradient_axis);
    delta_ = delta_build_ + (gamma_ - gamma_build_) * length(gradient_axis);
    for (int code = 0; code < codes; ++code) {
      shift_[code] = periodic_shift_[code];
      shift_[code][shear_axis] += k_gradient_[code] * delta_;
      jump_[code] = Vec<D>::Zero();
      jump_[code][shear_axis] = k_gradient_[code] * u_;
    }
  }
  // A new Verlet list is built: its offset delta_b = gamma L_g mod L_s.
  void rebase() {
    if (!le_.on) return;
    const double Ls = length(shear_axis);
    gamma_build_ = gamma_;
    delta_build_ = gamma_ * length(gradient_axis);
    delta_build_ -= Ls * std::floor(delta_build_ / Ls);
    if (delta_build_ >= Ls) delta_build_ = 0.0;
    delta_ = delta_build_;
    update_tables_only();
  }
  double build_offset() const { return delta_build_; }    // delta_b, m, in [0, L_s)
  double strain_since_build() const { return gamma_ - gamma_build_; }
  double jump_speed() const { return u_; }                // u(t), m/s

  // Into the box (Lees-Edwards: across g also shifted by delta along s).
  void wrap(Vec<D>& x) const {
    if (le_.on) remap(x);
    box_.wrap(x);
  }
  // The same for a particle: its velocity jumps by the image velocity (eq. LE2).
  void wrap(Vec<D>& x, Vec<D>& v) const {
    if (le_.on) v[shear_axis] -= remap(x) * u_;
    box_.wrap(x);
  }
  // The velocity change of a particle displaced by `moved` in a wrap (whole gradient-axis lengths).
  Vec<D> velocity_change(const Vec<D>& moved) const {
    Vec<D> dv = Vec<D>::Zero();
    if (le_.on) dv[shear_axis] = std::round(moved[gradient_axis] / length(gradient_axis)) * u_;
    return dv;
  }

  // The code of a cell-list shift (whole box lengths along periodic axes; under
  // Lees-Edwards the shear-axis part of an image across g includes k_g delta_b).
  int code_of(const Vec<D>& shift) const {
    int k[D];
    for (int d = 0; d < D; ++d) k[d] = box_.periodic[d] ? static_cast<int>(std::lround(shift[d] / length(d))) : 0;
    if (le_.on)
      k[shear_axis] = static_cast<int>(std::lround((shift[shear_axis] - k[gradient_axis] * delta_build_) / length(shear_axis)));
    int code = 0, scale = 1;
    for (int d = 0; d < D; ++d, scale *= 5) code += (k[d] + 2) * scale;
    return code;
  }

 private:
  double length(int d) const { return box_.hi[d] - box_.lo[d]; }
  void update_tables_only() {
    for (int code = 0; code < codes; ++code) {
      shift_[code] = periodic_shift_[code];
      shift_[code][shear_axis] += k_gradient_[code] * delta_;
    }
  }
  // Across the g faces: x_g by whole L_g, x_s by as many delta; returns the crossings k (x_g -= k L_g).
  int remap(Vec<D>& x) const {
    const double lo = box_.lo[gradient_axis], L = length(gradient_axis);
    const int k = static_cast<int>(std::floor((x[gradient_axis] - lo) / L));
    if (k != 0) x[gradient_axis] -= k * L, x[shear_axis] -= k * delta_;
    return k;
  }

  PeriodicBox<D> box_;
  std::array<Vec<D>, codes> periodic_shift_{}, shift_{}, jump_{};
  std::array<int, codes> k_gradient_{};
  LeesEdwardsSpec le_;
  double gamma_ = 0.0, gamma_build_ = 0.0, delta_ = 0.0, delta_build_ = 0.0, u_ = 0.0;
};

// The periodic box of a run: the deck's periodic axes with their bounds, m.
template <int D>
PeriodicBox<D> periodic_box(const RunParameters& deck) {
  PeriodicBox<D> box;
  for (std::size_t i = 0; i < deck.periodic_axes.size(); ++i) {
    const int a = deck.periodic_axes[i];
    box.periodic[a] = true, box.lo[a] = deck.periodic_lo[i], box.hi[a] = deck.periodic_hi[i];
  }
  return box;
}

}  // namespace sph
