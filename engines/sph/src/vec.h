// Fixed-size vectors of the simulation's dimension.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace sph {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

static_assert(sizeof(Vec<2>) == 16 && sizeof(Vec<3>) == 24, "packed vectors expected");

}  // namespace sph
