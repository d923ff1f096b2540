// The scalars of a solid particle (materials/johnson_cook_material.h), one integrated field of Particles: a value,
// a rate and a start-of-step copy each, so they are reordered, compacted and written with the other fields.
// Frames write them as `solid_state` (n, 6), columns in the order of `slot`.
#pragma once
#include <Eigen/Core>

namespace sph {

using SolidState = Eigen::Matrix<double, 6, 1>;

namespace slot {
enum : int {
  energy = 0,          // specific internal energy e, J/kg (rate: sigma : D / rho)
  plastic_strain = 1,  // equivalent plastic strain eps_p, - (rate 0: post_correct adds the step's increment)
  plastic_rate = 2,    // its rate over the last step, 1/s
  temperature = 3,     // T, K (eq. 12)
  damage = 4,          // D of eq. 13, -: failed at 1
  szz = 5,             // 2D (plane strain): the deviatoric s_zz, Pa (rate -2 G tr D / 3); 3D: 0
};
}  // namespace slot

}  // namespace sph
