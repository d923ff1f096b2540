// How the images of a particle are seen across the box: the image policy.
//
// The neighbour list stores, with each pair, the code of the image of b that
// a sees (periodic shifts of k_d box lengths, k_d in -2..2 per axis; code
// sum_d (k_d + 2) 5^d). The policy turns a code into the position shift
// (r_ab = x_a - x_b - shift(code)) and the velocity jump (v_ab = v_a - v_b -
// jump(code)) of that image.
//
// PeriodicImages: plain periodic axes, no velocity jump (compiled out:
// has_velocity_jump is false). Lees-Edwards (sheared periodic box, shear
// along axis s with gradient axis g and rate gamma_dot) is a second policy
// with the same interface: an image across the g axis (k_g != 0) is shifted
// by k_g (L_s gamma_dot L_g t mod L_s) along s in addition to its periodic
// shift, and carries the velocity jump k_g gamma_dot L_g along s; its
// update(t) refreshes the shift table each step, and wrap() also changes the
// velocity of a particle that crosses the g faces. The pair loop reads
// jump(code) only when has_velocity_jump.
#pragma once
#include <array>
#include <cmath>

#include "cell_list.h"
#include "vec.h"

namespace sph {

template <int D>
class PeriodicImages {
 public:
  static constexpr int codes = D == 2 ? 25 : 125;
  static constexpr int centre_code = D == 2 ? 2 + 2 * 5 : 2 + 2 * 5 + 2 * 25;  // no shift
  static constexpr bool has_velocity_jump = false;

  PeriodicImages() = default;
  explicit PeriodicImages(const PeriodicBox<D>& box) : box_(box) {
    for (int code = 0; code < codes; ++code) {
      int c = code;
      for (int d = 0; d < D; ++d, c /= 5) shift_[code][d] = box.periodic[d] ? (c % 5 - 2) * (box.hi[d] - box.lo[d]) : 0.0;
    }
  }
  const PeriodicBox<D>& box() const { return box_; }
  void wrap(Vec<D>& x) const { box_.wrap(x); }
  const Vec<D>& shift(int code) const { return shift_[code]; }
  const Vec<D>* shifts() const { return shift_.data(); }
  Vec<D> jump(int) const { return Vec<D>::Zero(); }
  void update(double) {}  // time-dependent images (Lees-Edwards) refresh here
  // The code of a cell-list shift (whole box lengths along periodic axes).
  int code_of(const Vec<D>& shift) const {
    int code = 0, scale = 1;
    for (int d = 0; d < D; ++d, scale *= 5) {
      const int k = box_.periodic[d] ? static_cast<int>(std::lround(shift[d] / (box_.hi[d] - box_.lo[d]))) : 0;
      code += (k + 2) * scale;
    }
    return code;
  }

 private:
  PeriodicBox<D> box_;
  std::array<Vec<D>, codes> shift_{};
};

}  // namespace sph
