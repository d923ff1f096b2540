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

// Most relaxation modes of a multi-mode model (PTT); a run uses as many as its materials give.
constexpr int max_stress_modes = 8;
// The stresses of a particle's modes: column k is mode k's tau (D x D, column-major), as
// many columns as the run's modes; fixed capacity, so no heap allocation.
template <int D>
using ModeStress = Eigen::Matrix<double, D * D, Eigen::Dynamic, Eigen::ColMajor, D * D, max_stress_modes>;

static_assert(sizeof(Vec<2>) == 16 && sizeof(Vec<3>) == 24, "packed vectors expected");

}  // namespace sph
