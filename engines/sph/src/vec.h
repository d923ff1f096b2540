// Fixed-size vectors and matrices of the simulation's dimension.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <Eigen/LU>        // small matrix inverses (kernel-corrected gradients)

namespace sph {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;  // stress, velocity gradient (row i, column j: d v_i / d x_j)

static_assert(sizeof(Vec<2>) == 16 && sizeof(Vec<3>) == 24, "packed vectors expected");

}  // namespace sph
