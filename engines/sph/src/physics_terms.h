// The physics terms of the executable, each compiled in only when the deck asks for it.
//
// A term is a small struct with a per-pair `add(pair, rates)` (summed over a
// particle's neighbours) or a per-particle `add(...)`. `FluidModel<D, Terms>`
// composes them; the bit set `Terms` is a compile-time constant, so a term the
// deck does not switch on is removed from the inner loop by `if constexpr`.
// New terms (PTT viscoelastic stress, Johnson-Cook solid stress, rigid grains)
// get a bit here, a struct, and a line in FluidModel::pair.
#pragma once
#include <cmath>
#include <cstdint>

#include "parameters.h"
#include "vec.h"

namespace sph {

namespace term {
// Always on: continuity density (eq. 7), Tait EOS (eq. 6), pressure gradient (eq. 9).
constexpr unsigned morris_viscosity = 1u << 0;      // eq. 10
constexpr unsigned artificial_viscosity = 1u << 1;  // eqs. 11-12
constexpr unsigned body_force = 1u << 2;            // f in eq. 4
constexpr unsigned wall_penalty = 1u << 3;          // eq. 14
constexpr unsigned count = 4;
constexpr unsigned all = (1u << count) - 1;
// Terms of the pair loop (compile time); body force and walls are runtime switches outside it.
constexpr unsigned pair_terms = morris_viscosity | artificial_viscosity;
// Not a deck term: set by the dispatcher for runs with several materials and
// Morris viscosity (the pair loop then looks up mu_ab, material.h).
constexpr unsigned several_materials = 1u << 8;
// Not a deck term: set by the dispatcher for Lees-Edwards runs (the pair loop
// then subtracts the velocity jump of a sheared image, box_policy.h eq. LE2).
constexpr unsigned sheared = 1u << 9;
// Not a deck term: set by the dispatcher for the deck key `viscosity_correction`
// (the pair loop scales each particle's Morris sum by k_a, viscosity_correction.h eq. VC1).
constexpr unsigned viscosity_correction = 1u << 10;
// Not a deck term: set by the dispatcher for the deck key `eddy_viscosity` (Smagorinsky's sub-particle
// viscosity nu_t = (cs dx)^2 |S| added to the Morris term's, eq. SM1 of eddy_viscosity.h).
constexpr unsigned eddy_viscosity = 1u << 11;
// Not a deck term: set by the dispatcher for the deck key `grains` (rigid grains of particles that the fluid drags:
// the pair loop also sums the fluid's pair forces on the grains' particles, grain_pairs.h eq. G1).
constexpr unsigned grains = 1u << 12;
// Not a deck term: set by the dispatcher when a PTT material gives `stress_diffusion` (the pair loop then sums the
// Laplacian of the mode stresses, eq. SD1 of materials/ptt.h).
constexpr unsigned stress_diffusion = 1u << 13;

struct Named {
  const char* name;
  unsigned bit;
};
inline constexpr Named optional[count] = {{"morris_viscosity", morris_viscosity},
                                          {"artificial_viscosity", artificial_viscosity},
                                          {"body_force", body_force},
                                          {"wall_penalty", wall_penalty}};
}  // namespace term

// fluid: moved by the forces; boundary: fixed, carries density and pressure;
// inlet / outlet: buffer particles of an open boundary, carried at a fixed
// velocity, carrying density and pressure like boundary particles; body: a
// particle of a rigid grain (grains.h), a moving boundary particle placed by
// its grain's motion.
enum class Kind : std::int8_t { fluid = 0, boundary = 1, inlet = 2, outlet = 3, body = 4 };

// Everything a pair term may read about particles a and b (b within the support 2h of a).
template <int D>
struct Pair {
  Vec<D> r_ab;     // x_a - x_b, m
  double r2;       // |r_ab|^2, m^2
  double F;        // kernel gradient factor: grad_a W_ab = F r_ab, 1/m^(D+2)
  Vec<D> v_ab;     // v_a - v_b, m/s
  double vr;       // v_ab . r_ab, m^2/s (so v_ab . grad_a W_ab = F vr)
  Vec<D> v_ab_noslip;  // v_a - (no-slip velocity of b: mirrored for boundary particles), m/s
  double m_b;      // kg
  double vol_b;    // m_b / rho_b, m^D
  double rho_a, rho_b;        // kg/m^3
  double p_rho2_a, p_rho2_b;  // p / rho^2, m^5/(kg s^2)
  double inv_rho_a;           // 1 / rho_a
  double c_a, c_b;            // sound speeds, m/s
};

// The sums over a particle's neighbours.
template <int D>
struct PairRates {
  Vec<D> acc = Vec<D>::Zero();  // dv_a/dt, m/s^2
  double drho = 0.0;            // drho_a/dt, kg/m^3/s
};

// Terms along r_ab (pressure, artificial viscosity) add the coefficient of
// r_ab to `radial` (m/s^2 per m), so a pair updates the acceleration once:
// dv_a/dt += radial r_ab. Other terms add to PairRates directly.

// Eq. 7 with the sign of d rho/dt = -rho div v: drho_a/dt = rho_a sum_b m_b/rho_b v_ab . grad_a W_ab
// (the paper prints a leading minus, which would make approaching particles lighter).
struct Continuity {
  template <int D>
  void add(const Pair<D>& p, PairRates<D>& out) const {
    out.drho += p.rho_a * p.vol_b * (p.F * p.vr);
  }
};

// For particles that do not move with the fluid (boundary, inlet, outlet):
// drho_a/dt = sum_b m_b v_ab . grad_a W_ab, the exact rate of the summation
// density sum_b m_b W_ab, so particles an inlet adds or an outlet removes can
// be booked in and out (Simulation::boundary_density_event) without drift.
struct SummationContinuity {
  template <int D>
  void add(const Pair<D>& p, PairRates<D>& out) const {
    out.drho += p.m_b * (p.F * p.vr);
  }
};

// Eq. 9 divided by rho_a: -grad p_a / rho_a = -sum_b m_b (p_a/rho_a^2 + p_b/rho_b^2) grad_a W_ab
struct PressureGradient {
  template <int D>
  void add(const Pair<D>& p, double& radial) const {
    radial -= p.m_b * (p.p_rho2_a + p.p_rho2_b) * p.F;
  }
};

// Eq. 10 divided by rho_a with mu_a = mu_b = mu (= rho0 nu):
// sum_b m_b (mu_a + mu_b) r_ab . grad_a W_ab / (rho_a rho_b (r_ab^2 + 0.01 h^2)) v_ab
// where a boundary particle b enters with its no-slip velocity (see Simulation::no_slip_velocity_at).
struct MorrisViscosity {
  double mu = 0.0;    // dynamic viscosity, Pa s
  double eta2 = 0.0;  // 0.01 h^2, m^2
  double rho0 = 0.0;  // kg/m^3: the eddy viscosity's mu_t = rho0 nu_t (eddy_viscosity.h, eq. SM2)
  double eddy_wall = 1.0;  // factor on nu_t for pairs with a fixed particle: 1, or 0 (deck eddy_viscosity.walls = false)
  template <int D>
  void add(const Pair<D>& p, PairRates<D>& out) const {
    const double s = 2.0 * mu * p.vol_b * p.inv_rho_a * (p.F * p.r2) / (p.r2 + eta2);
    out.acc.noalias() += s * p.v_ab_noslip;
  }
  // The part shared by both particles of a pair: 2 mu (r_ab . grad_a W_ab) / (r_ab^2 + 0.01 h^2),
  // so dv_a/dt += factor m_b/(rho_a rho_b) (v_a - v_b) (eq. 10).
  double factor(double F, double r2) const { return 2.0 * mu * (F * r2) / (r2 + eta2); }
  // The same with the pair viscosity mu_ab of two materials (material.h).
  static double factor(double mu_ab, double F, double r2, double eta2) { return 2.0 * mu_ab * (F * r2) / (r2 + eta2); }
  double factor(double mu_ab, double F, double r2) const { return factor(mu_ab, F, r2, eta2); }
};

// Eqs. 11-12: Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab for v_ab . r_ab < 0 (else 0),
// mu_ab = h v_ab . r_ab / (r_ab^2 + 0.01 h^2); dv_a/dt -= sum_b m_b Pi_ab grad_a W_ab.
// Without a branch: mu_ab is taken from min(v_ab . r_ab, 0), which makes Pi_ab
// zero for separating pairs (a branch on the sign of v_ab . r_ab is
// mispredicted about every other pair and costs more than the flops).
struct ArtificialViscosity {
  double alpha = 0.0, beta = 0.0;
  double h = 0.0, eta2 = 0.0;
  // Factor on Pi_ab for pairs with a fixed (boundary, inlet or outlet) particle:
  // 1 (deck artificial_viscosity.walls = true) or 0 (only fluid-fluid pairs).
  double wall = 1.0;
  // Pi_ab of eq. 11 (symmetric in a and b) from r_ab^2 and v_ab . r_ab.
  double pi(double r2, double vr, double rho_a, double rho_b, double c_a, double c_b) const {
    const double d = r2 + eta2, rho_ab = 0.5 * (rho_a + rho_b);
    const double inv = 1.0 / (d * rho_ab);  // one division for 1/d and 1/rho_ab
    const double vr_in = 0.5 * (vr - std::abs(vr));  // exactly min(vr, 0), without a branch
    const double mu_ab = h * vr_in * inv * rho_ab;
    const double c_ab = 0.5 * (c_a + c_b);
    return (-alpha * c_ab * mu_ab + beta * mu_ab * mu_ab) * inv * d;
  }
  template <int D>
  void add(const Pair<D>& p, double& radial) const {
    const double d = p.r2 + eta2, rho_ab = 0.5 * (p.rho_a + p.rho_b);
    const double inv = 1.0 / (d * rho_ab);  // one division for 1/d and 1/rho_ab
    const double vr_in = 0.5 * (p.vr - std::abs(p.vr));  // exactly min(vr, 0), without a branch
    const double mu_ab = h * vr_in * inv * rho_ab;
    const double c_ab = 0.5 * (p.c_a + p.c_b);
    const double pi_ab = (-alpha * c_ab * mu_ab + beta * mu_ab * mu_ab) * inv * d;
    radial -= p.m_b * pi_ab * p.F;
  }
};

// Eq. DD1, the density diffusion of Molteni & Colagrossi (2009) between two fluid particles, with the hydrostatic
// part taken out (Fourtakas et al. 2019, linearised: rho_a^H - rho_b^H = rho0/c0^2 g . r_ab):
//   drho_a/dt += 2 delta h c0 sum_b V_b (rho_a - rho_b - rho0/c0^2 g . r_ab) F r_ab^2 / (r_ab^2 + 0.01 h^2)
// (F < 0: a Laplacian of the Morris form, eq. 10). It damps the density's particle-scale noise that a weakly
// compressible flow with little artificial viscosity accumulates; a uniform or hydrostatic density gives zero.
template <int D>
struct DensityDiffusion {
  double kappa2 = 0.0;              // 2 delta h c0, m^2/s (0: off)
  double eta2 = 0.0;                // 0.01 h^2, m^2
  Vec<D> g_rho = Vec<D>::Zero();    // rho0 / c0^2 g, kg s^2/m^5 . m/s^2
  bool on() const { return kappa2 > 0.0; }
  // The pair's weight w = kappa2 F r^2 / (r^2 + eta2) times the density difference: a's rate per V_b.
  double rate(double F, double r2, double rho_a, double rho_b, const Vec<D>& r) const {
    return kappa2 * (F * r2) / (r2 + eta2) * (rho_a - rho_b - g_rho.dot(r));
  }
};

// Per-particle body force per unit mass (gravity), m/s^2.
template <int D>
struct BodyForce {
  Vec<D> g = Vec<D>::Zero();
  void add(Vec<D>& acc) const { acc += g; }
};

// The compile-time selection of pair terms for one particle a.
template <int D, unsigned Terms>
struct FluidModel {
  static constexpr bool has(unsigned t) { return (Terms & t) != 0; }
  Continuity continuity;
  SummationContinuity boundary_continuity;
  PressureGradient pressure;
  MorrisViscosity morris;
  ArtificialViscosity artificial;
  DensityDiffusion<D> diffusion;  // eq. DD1 (fluid-fluid pairs)
  Vec<D> gravity = Vec<D>::Zero();  // the body force, m/s^2 (eq. FS1 of pair_loop.h)

  // Pair terms acting on a moving (fluid) particle a.
  void pair(const Pair<D>& p, PairRates<D>& out) const {
    continuity.add(p, out);
    double radial = 0.0;
    pressure.add(p, radial);
    if constexpr (has(term::artificial_viscosity)) artificial.add(p, radial);
    out.acc.noalias() += radial * p.r_ab;
    if constexpr (has(term::morris_viscosity)) morris.add(p, out);
  }
  // A fixed boundary particle carries density (and so pressure) but does not move.
  void boundary_pair(const Pair<D>& p, PairRates<D>& out) const { boundary_continuity.add(p, out); }
};

// The pair terms of a run: its first material's dynamic viscosity mu (Pa s) and density rho0 (kg/m^3), and the
// deck's smoothing length, artificial viscosity, eddy viscosity's wall factor, body force and density diffusion
// (with the material's c0, m/s).
template <int D, unsigned Terms>
FluidModel<D, Terms> fluid_model(const RunParameters& deck, double mu, double rho0, double c0) {
  FluidModel<D, Terms> model;
  const double eta2 = 0.01 * deck.h * deck.h;
  model.morris.mu = mu;
  model.morris.eta2 = eta2;
  model.morris.rho0 = rho0;
  model.morris.eddy_wall = deck.eddy_walls ? 1.0 : 0.0;
  model.artificial = {deck.alpha, deck.beta, deck.h, eta2, deck.av_walls ? 1.0 : 0.0};
  if ((deck.terms & term::body_force) && !deck.body_force.empty())
    for (int d = 0; d < D; ++d) model.gravity[d] = deck.body_force[d];
  model.diffusion.kappa2 = 2.0 * deck.density_diffusion * deck.h * c0;
  model.diffusion.eta2 = eta2;
  model.diffusion.g_rho = rho0 / (c0 * c0) * model.gravity;
  return model;
}

}  // namespace sph
