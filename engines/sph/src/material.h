// The run's materials at run time: per material its EOS and viscosity, and
// the pair viscosities of every two materials.
//
// Interface rule between materials (multi-phase Morris; Hu & Adams 2006,
// eq. 11; Morris, Fox & Zhu 1997, eq. 10 generalised): a pair term uses each
// particle's own parameters where the term is written per particle (p_a/rho_a^2
// and p_b/rho_b^2 in eq. 9, each particle's rho and c in eqs. 7 and 11-12);
// the viscous term of eq. 10, (mu_a + mu_b), takes for two different
// materials 2 mu_ab with the harmonic mean mu_ab = 2 mu_a mu_b / (mu_a + mu_b),
// which keeps the shear stress continuous across the interface (the
// harmonic mean is the series resistance of the two layers of fluid between
// the particles). A fluid beside a solid takes its own mu: the solid is a wall
// to it, moving with the solid's particles, which take the reaction (no slip
// at the interface); solids carry no Morris term. Two particles of one
// material use their mu exactly, so a one-material run is bitwise what it was
// before materials existed.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "eos.h"
#include "materials/solid_parameters.h"
#include "vec.h"

namespace sph {

// Whether a model is a solid (its static `solid`): its own EOS, rates and return over the particle's solid_state.
template <class M, class = void>
struct solid_of : std::false_type {};
template <class M>
struct solid_of<M, std::void_t<decltype(M::solid)>> : std::bool_constant<M::solid> {};
template <class M>
constexpr bool solid_v = solid_of<M>::value;

// A Cross-law viscosity eta(gamma_dot) = eta_inf + (eta_0 - eta_inf) / (1 + (K gamma_dot)^m), Pa s.
struct CrossViscosity {
  double eta_0 = 0.0, eta_inf = 0.0;  // zero- and infinite-shear viscosities, Pa s
  double time = 0.0, exponent = 1.0;  // K s, m - (0 < m <= 1)
  double operator()(double shear_rate) const {  // shear_rate 1/s
    return eta_inf + (eta_0 - eta_inf) / (1.0 + std::pow(time * shear_rate, exponent));
  }
};

// Parameters of a multi-mode viscoelastic model (materials/ptt.h).
struct ModeParameters {
  int count = 0;                                   // modes in use
  std::array<double, max_stress_modes> lambda{};   // relaxation times, s
  std::array<double, max_stress_modes> eta{};      // mode viscosities, Pa s
  double epsilon = 0.0;                            // PTT extensibility (0: Oldroyd-B / UCM)
  double eta_s = 0.0;                              // solvent viscosity, Pa s
  double plateau = 0.0;                            // G_p, Pa: > 0 adds the elastic column `count`
  bool cross = false;                              // a Cross-law solvent beside eta_s
  double diffusion = 0.0;                          // kappa m^2/s of eq. SD1 (materials/ptt.h; 0: none)
  CrossViscosity cross_law;
  // Stress columns of the material: its modes, and the plateau's elastic stress after them.
  int columns() const { return count + (plateau > 0.0 ? 1 : 0); }
};

struct Material {
  TaitEos eos;      // rho0, c0, gamma, p_B (eq. 6)
  double nu = 0.0;  // kinematic viscosity m^2/s (Newtonian with Morris)
  double mu = 0.0;  // dynamic viscosity rho0 nu, Pa s
  int model = 0;    // index of its model in the configuration's model list
  ModeParameters modes;  // viscoelastic models only
  SolidParameters solid;  // solids only (materials/johnson_cook_material.h)
  bool is_solid = false;  // its model is a solid (material_models.h)
};

class MaterialTable {
 public:
  void add(const Material& m) { list_.push_back(m), update(); }
  int size() const { return static_cast<int>(list_.size()); }
  const Material& operator[](std::size_t k) const { return list_[k]; }
  const TaitEos& eos(std::size_t k) const { return list_[k].eos; }
  // mu_ab of eq. 10 for materials ka, kb (mu_a when equal, else the harmonic mean; a fluid beside a solid: the
  // fluid's mu, as against a wall that moves with the solid's particles; two solids: 0).
  double pair_mu(std::uint8_t ka, std::uint8_t kb) const { return pair_mu_[ka * list_.size() + kb]; }
  const double* pair_mu_table() const { return pair_mu_.data(); }
  double c0_max() const { return c0_max_; }
  double nu_max() const { return nu_max_; }

 private:
  void update() {
    const std::size_t n = list_.size();
    pair_mu_.assign(n * n, 0.0);
    c0_max_ = nu_max_ = 0.0;
    for (std::size_t a = 0; a < n; ++a) {
      c0_max_ = std::max(c0_max_, list_[a].eos.c0), nu_max_ = std::max(nu_max_, list_[a].nu);
      for (std::size_t b = 0; b < n; ++b) {
        const double ma = list_[a].mu, mb = list_[b].mu;
        const bool sa = list_[a].is_solid, sb = list_[b].is_solid;
        if (sa || sb) pair_mu_[a * n + b] = sa && sb ? 0.0 : (sa ? mb : ma);
        else pair_mu_[a * n + b] = a == b ? ma : (ma + mb > 0.0 ? 2.0 * ma * mb / (ma + mb) : 0.0);
      }
    }
  }
  std::vector<Material> list_;
  std::vector<double> pair_mu_;
  double c0_max_ = 0.0, nu_max_ = 0.0;
};

}  // namespace sph
