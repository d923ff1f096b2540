// The gather stage's pair loop over the Verlet half list (neighbour_list.h):
// each pair is evaluated once and acts on both particles (Newton's third law).
// Scalar path (every material without deviatoric stress, e.g. Newtonian):
//   eq. 7   drho_a/dt += rho_a (m_b/rho_b) v_ab . grad_a W_ab
//   eq. 9   dv_a/dt   -= m_b (p_a/rho_a^2 + p_b/rho_b^2) grad_a W_ab
// Tensor path (a material of the run carries tau; sigma = -p I + tau):
//   eq. T1  dv_a/dt   += m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2) . grad_a W_ab
//   eq. T2  G_a       += V_b (v_b - v_a) (x) grad_a W_ab,  M_a += V_b (x_b - x_a) (x) grad_a W_ab
//           (velocity gradient L_a = G_a, or G_a M_a^-1 kernel-corrected: exact for linear v; close_rates)
// Both:  eqs. 11-12 artificial viscosity and eq. 10 Morris viscosity (mu_ab of material.h); grains: eq. G1 (G8).
// A fluid's particle beside a solid's: eq. FS1 in place of eq. T1 (fluid_solid.h).
// Lees-Edwards (term::sheared): b's image moves at v_b + jump(code) (box_policy.h, eq. LE2): v_ab = v_a - v_b - jump.
// Stress diffusion (term::stress_diffusion): eq. SD1's Laplacian sums of the mode stresses (stress_diffusion.h).
// grad_a W_ab = F r_ab with F of eq. 8; grad_b W_ba = -F r_ab. Pairs of the skin, beyond 2h, add exact zeros.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "boundary_particles.h"
#include "fluid_solid.h"
#include "grain_pairs.h"
#include "kernel.h"
#include "material.h"
#include "materials/johnson_cook_material.h"
#include "materials/solid_smoothing.h"
#include "neighbour_list.h"
#include "pair_chunk.h"
#include "pair_lanes.h"
#include "particles.h"
#include "physics_terms.h"
#include "solid_contact.h"
#include "stress_diffusion.h"
#include "tensor_pair_math.h"
#include "tensor_viscous.h"
#include "viscosity_correction.h"
#include "wall_sums.h"

namespace sph {

template <int D, unsigned Terms, class Models>
class PairLoop {
 public:
  using Model = FluidModel<D, Terms>;
  static constexpr bool has(unsigned t) { return (Terms & t) != 0; }
  static constexpr bool tensor = Models::any_stress;
  static constexpr bool corrected = has(term::viscosity_correction);  // eq. VC1 (viscosity_correction.h)
  static_assert(!corrected || (has(term::morris_viscosity) && !tensor), "eq. VC1: scalar path with Morris viscosity");
  static constexpr bool eddy = has(term::eddy_viscosity);  // eqs. SM1-SM2 (eddy_viscosity.h)
  static_assert(!eddy || (has(term::morris_viscosity) && !tensor && !corrected && !has(term::sheared) &&
                          !has(term::several_materials)), "eqs. SM1-SM2: one material's scalar path with Morris");
  // The mu_ab of eq. 10 per pair: several materials' table or the eddy viscosity's (pass A gathers it).
  static constexpr bool pair_mu = has(term::several_materials) || eddy;
  static constexpr bool grains = has(term::grains);  // eq. G1 (grain_pairs.h)
  static_assert(!grains || (!eddy && !(tensor && has(term::sheared))), "eq. G1: no eddy viscosity; tensor: no shear");
  // The fluid-fluid rows 4 pairs at a time (pair_lanes.h) in the plain scalar path.
  static constexpr bool lanes = !tensor && !corrected && !eddy && !grains && !has(term::sheared) && !pair_mu;
  PairLoop(Particles<D>& P, const NeighbourList<D>& list, const WendlandC2<D>& kernel, const Model& model,
           const MaterialTable& materials, std::vector<double>& shepard)
      : P_(P), list_(list), kernel_(kernel), model_(model), materials_(materials), shepard_(shepard) {}

  // The gather's pair loop over every block (in the block colours of the list), after eq. VC1's sums when corrected.
  void rates(bool par) {
    if constexpr (corrected) {
      const double eta2 = model_.morris.eta2;
      list_.for_blocks_coloured(par, [&](int k) { correction_.sums_of_block(list_, P_, kernel_, eta2, k); });
      for_each_index(par, P_.size(), [this](std::ptrdiff_t i) { correction_.finish_at(i); });
    }
    list_.for_blocks_coloured(par, [this](int k) { rates_of_block(k); });
  }
  // The lanes' records and sums (pair_lanes.h): room for the particles before an evaluation (on one thread), then
  // per particle i before the pair loop (after the equation of state) and after it (their sums to acc and drho).
  void fit() { if constexpr (lanes) lanes_.fit(P_.size()); }
  void start_at(std::ptrdiff_t i) { if constexpr (lanes) lanes_.pack(P_, i, has(term::artificial_viscosity)); }
  void finish_at(std::ptrdiff_t i) { if constexpr (lanes) lanes_.unpack(P_, i); }

  // The pairs owned by the particles of block k: fluid or not, owner and
  // neighbour, each combination its own branch-free loop. Compiled twice, for SSE2 and for AVX2 without
  // FMA, chosen at run time: the AVX2 copy vectorises pass B 4 wide and uses 3-operand (VEX) instructions
  // everywhere, and every operation rounds as in the SSE2 copy (no FMA contraction), so results do not
  // depend on the CPU.
  void rates_of_block(int k) const {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2 && !sse2_only) rates_of_block_avx2(k);
    else rates_of_block_default(k);
  }
  __attribute__((target("avx2"), noinline)) void rates_of_block_avx2(int k) const { rows_of_block(k); }
  __attribute__((noinline)) void rates_of_block_default(int k) const { rows_of_block(k); }

  // At each list build (particles reordered, added or removed): whether every particle has the same mass
  // (masses change only when particles come or go, which rebuilds the list; pass A then gathers no mass: its
  // chunk holds that mass in every slot), and the sums of eq. VC1 sized to the particles.
  void list_built() {
    const auto& m = P_.mass;
    uniform_mass_ = !m.empty() && std::all_of(m.begin(), m.end(), [&](double mi) { return mi == m[0]; });
    if constexpr (Models::any_solid) artificial_stress_ = ArtificialStressFactor::of(materials_, kernel_.h),
                                     smoothing_ = SolidSmoothing::of(materials_, kernel_.h), contact_ = SolidContact::of<D>(materials_);
    if constexpr (corrected) correction_.resize(P_.size());
    if constexpr (lanes) lanes_.set_shifts(list_.shifts());
  }

  inline __attribute__((always_inline)) void rows_of_block(int k) const {
    const std::uint32_t* const e = list_.entries(k);
    Chunk c;  // pass B's arrays, on the stack of the calling thread
    if (uniform_mass_) std::fill(c.m, c.m + chunk, P_.mass[0]);
    for (int a = list_.block_begin(k); a < list_.block_end(k); ++a) {
      const auto& row = list_.row(a);
      if (P_.moves(a)) {
        if constexpr (lanes)
          lanes_.template row<has(term::artificial_viscosity), has(term::morris_viscosity)>(
              a, e + row.begin, e + row.mid, model_, kernel_.inv_h, kernel_.grad_factor);
        else
          pair_row<true, true>(c, a, e + row.begin, e + row.mid);
        pair_row<true, false>(c, a, e + row.mid, e + row.end);
      } else {
        pair_row<false, true>(c, a, e + row.begin, e + row.mid);
        pair_row<false, false>(c, a, e + row.mid, e + row.end);
      }
    }
  }

  // The Shepard sums around the fixed boundary particles over block k (wall_sums.h); compiled for SSE2 and
  // for AVX2 without FMA as rates_of_block (the same roundings on every CPU).
  void no_slip_sums_of_block(int k) const {
    static const bool avx2 = __builtin_cpu_supports("avx2");
    if (avx2) no_slip_sums_of_block_avx2(k);
    else no_slip_sums_of_block_default(k);
  }
  __attribute__((target("avx2"), noinline)) void no_slip_sums_of_block_avx2(int k) const {
    wall_sums_of_block<tensor, Models>(P_, list_, kernel_, shepard_, k);
  }
  __attribute__((noinline)) void no_slip_sums_of_block_default(int k) const {
    wall_sums_of_block<tensor, Models>(P_, list_, kernel_, shepard_, k);
  }

 private:
  // The pair terms of owner a with the neighbours of entries [e, end), added to both particles. AMoves,
  // BMoves: whether a and the neighbours are fluid. A fluid particle takes continuity (eq. 7), momentum
  // (eq. 9 or T1) and the viscosities; any other takes the rate of the summation density
  // sum_b m_b v_ab . grad_a W_ab (and a grain's particle the reaction of eq. G1).
  // The row [e, end) in chunks of up to 128 entries. Tensor path: the pair terms in one loop (pair_terms).
  // Scalar path, in three passes per chunk:
  //   A. gather: r_ab, r^2, v_ab, v_ab . r_ab and b's values into local arrays, keeping only the pairs
  //      within the support 2h (the list also holds the skin, up to 1.1 2h: a fifth of the pairs in 2D, a
  //      quarter in 3D, whose terms are exact zeros); branch-free;
  //   B. the per-pair coefficients of eqs. 7, 9-12 (kernel, sqrt, divisions) over those arrays: no gathers,
  //      no sums, so the compiler vectorises it; B also multiplies the coefficients along r_ab by r_ab (the
  //      products C would form: the same roundings);
  //   C. the sums into a and the scatter to b, pair after pair in list order. Every accumulator receives the same
  // contributions in the same order as a single fused loop would give it (bitwise the same results).
  using Chunk = PairChunk<D>;
  using Owner = PairOwner;
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) void pair_row(Chunk& c, int a, const std::uint32_t* e,
                                                      const std::uint32_t* end) const {
    if constexpr (tensor) {
      (void)c;  // eqs. SS1 and SC1 chosen per row (no test per pair when off); inlined, the 4 variants cost 20 %
      if constexpr (Models::any_solid && AMoves && BMoves)
        if (smoothing_.on) return contact_.on ? pair_terms<AMoves, BMoves, true, true>(a, e, end)
                                              : pair_terms<AMoves, BMoves, true, false>(a, e, end);
      if constexpr (Models::any_solid) if (contact_.on) return pair_terms<AMoves, BMoves, false, true>(a, e, end);
      pair_terms<AMoves, BMoves, false, false>(a, e, end);
    } else {
      Vec<D> acc_a = Vec<D>::Zero();
      double drho_a = 0.0;
      for (const std::uint32_t* stop = e; e != end; e = stop) {
        stop = end - e > chunk ? e + chunk : end;
        scalar_chunk<AMoves, BMoves>(c, a, e, stop, acc_a, drho_a);
      }
      P_.acc[a] += acc_a;
      P_.drho[a] += drho_a;
    }
  }

  static constexpr int chunk = Chunk::size;
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) void scalar_chunk(Chunk& k, int a, const std::uint32_t* e,
                                                          const std::uint32_t* stop, Vec<D>& acc_a,
                                                          double& drho_a) const {
    const int n = gather_chunk<AMoves, BMoves>(k, a, e, stop);
    // B. per-pair coefficients (AVX2 where the CPU has it: no FMA, so every
    // lane rounds as the scalar code does and results do not depend on the CPU).
    const Owner o{P_.mass[a], P_.rho[a], P_.vol[a], P_.p_rho2[a], 1.0 / P_.rho[a],
                  has(term::artificial_viscosity) ? P_.c[a] : 0.0, kernel_.inv_h, kernel_.grad_factor,
                  corrected ? correction_.factors()[a] : 1.0};
    pair_coefficients<PairLoop, AMoves, BMoves>(k, n, o, model_);
    sum_chunk<AMoves, BMoves>(k, a, n, acc_a, drho_a);
  }
  // A. gather the entries [e, stop) of owner a into chunk k and keep the pairs within 2h; returns their number.
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) int gather_chunk(Chunk& k, int a, const std::uint32_t* e,
                                                         const std::uint32_t* stop) const {
    using List = NeighbourList<D>;
    const bool gather_mass = !uniform_mass_;
    const Vec<D>* const x = P_.x.data();
    const Vec<D>* const v = P_.v.data();
    const Vec<D>* const shifts = list_.shifts();
    const Vec<D>* const jumps = list_.jumps();
    const Vec<D> xa = x[a], va = v[a];
    const double support2 = 4.0 * kernel_.h * kernel_.h;
    const double* const mu_row = materials_.pair_mu_table() + P_.material[a] * materials_.size();
    const double* const nu_t = P_.nu_t.data();
    Vec<D> vns_a = Vec<D>::Zero();
    if constexpr (has(term::morris_viscosity)) vns_a = P_.v_noslip[a];
    int n = 0;
    for (; e != stop; ++e) {
      const int b = static_cast<int>(*e >> List::shift_bits);
      const Vec<D> r = xa - x[b] - shifts[*e & List::shift_mask];  // r_ab to the listed image of b
      Vec<D> v_ab = va - v[b];
      if constexpr (has(term::sheared)) v_ab -= jumps[*e & List::shift_mask], k.code[n] = *e & List::shift_mask;
      const double r2 = r.squaredNorm();
      k.b[n] = b, k.r2[n] = r2, k.vr[n] = v_ab.dot(r);
      for (int d = 0; d < D; ++d) k.r[d][n] = r[d];
      if (gather_mass) k.m[n] = P_.mass[b];
      k.rho[n] = P_.rho[b], k.vol[n] = P_.vol[b], k.p_rho2[n] = P_.p_rho2[b];
      if constexpr (has(term::artificial_viscosity)) k.c[n] = P_.c[b];
      if constexpr (has(term::several_materials)) k.mu[n] = mu_row[P_.material[b]];
      if constexpr (corrected) k.corr[n] = correction_.factors()[b];
      if constexpr (eddy && (AMoves || BMoves)) {  // eq. SM2: the fixed particle's nu_t is 0, the fluid's counts whole
        const double nu_ab = AMoves && BMoves ? 0.5 * (nu_t[a] + nu_t[b]) : model_.morris.eddy_wall * (nu_t[a] + nu_t[b]);
        k.mu[n] = model_.morris.mu + model_.morris.rho0 * nu_ab;
        Vec<D> vg = v_ab;  // eq. SM1: a fixed particle with its no-slip velocity
        if constexpr (AMoves && !BMoves) vg = va - P_.v_noslip[b];
        if constexpr (!AMoves && BMoves) vg = vns_a - v[b];
        for (int d = 0; d < D; ++d) k.vg[d][n] = vg[d];
      }
      n += r2 < support2;
    }
    return (void)jumps, n;
  }
  // C. the chunk's n pairs: sums into a (acc_a, drho_a), scatter to b, in list order.
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) void sum_chunk(const Chunk& k, int a, int n, Vec<D>& acc_a,
                                                       double& drho_a) const {
    const Vec<D>* const v = P_.v.data();
    const Vec<D>* const jumps = list_.jumps();
    const Vec<D> va = v[a];
    Vec<D> vns_a = Vec<D>::Zero();
    if constexpr (has(term::morris_viscosity)) vns_a = P_.v_noslip[a];
    Vec<D>* const acc = P_.acc.data();
    double* const drho = P_.drho.data();
    const Vec<D>* const v_noslip = P_.v_noslip.data();
    Mat<D>* const grad_v = P_.grad_v.data();
    Mat<D> G_a = Mat<D>::Zero();
    const double vol_a = P_.vol[a];
    for (int j = 0; j < n; ++j) {
      const int b = k.b[j];
      if constexpr (eddy && (AMoves || BMoves)) {  // eq. SM1: -F V (v_a - v_b) (x) r_ab on both sides
        Vec<D> vg, r;
        for (int d = 0; d < D; ++d) vg[d] = k.vg[d][j], r[d] = k.r[d][j];
        const Mat<D> vr_outer = vg * r.transpose();
        if constexpr (AMoves) G_a.noalias() -= (k.F[j] * k.vol[j]) * vr_outer;
        if constexpr (BMoves) grad_v[b].noalias() -= (k.F[j] * vol_a) * vr_outer;
      }
      drho_a += k.drho_a[j];
      drho[b] += k.drho_b[j];
      if constexpr (AMoves || BMoves) {
        Vec<D> f_a, f_b;
        for (int d = 0; d < D; ++d) f_a[d] = k.f_a[d][j], f_b[d] = k.f_b[d][j];
        if constexpr (AMoves) acc_a.noalias() += f_a;
        if constexpr (BMoves) acc[b].noalias() -= f_b;
        if constexpr (has(term::morris_viscosity) && has(term::sheared)) {
          const Vec<D>& jump = jumps[k.code[j]];
          if constexpr (AMoves) acc_a.noalias() += k.visc_a[j] * (va - v_noslip[b] - jump);
          if constexpr (BMoves) acc[b].noalias() += k.visc_b[j] * (v[b] + jump - vns_a);
        } else if constexpr (has(term::morris_viscosity)) {
          if constexpr (AMoves) acc_a.noalias() += k.visc_a[j] * (va - v_noslip[b]);
          if constexpr (BMoves) acc[b].noalias() += k.visc_b[j] * (v[b] - vns_a);
        }
        if constexpr (grains && AMoves != BMoves)
          grain_reaction<AMoves, has(term::morris_viscosity), has(term::sheared)>(P_, k, j, a, b, va, vns_a, jumps, acc_a);
      }
    }
    if constexpr (eddy && AMoves) grad_v[a] += G_a;
    (void)grad_v, (void)G_a, (void)vol_a, (void)jumps, (void)va, (void)vns_a;
  }

  template <bool AMoves, bool BMoves, bool Smooth, bool Bodies>
  __attribute__((noinline)) void pair_terms(int a, const std::uint32_t* e, const std::uint32_t* end) const {
    static_assert(tensor, "the tensor path's pair loop (pair_row)");
    using List = NeighbourList<D>;
    if (e == end) return;
    Vec<D>* const acc = P_.acc.data();
    double* const drho = P_.drho.data();
    const Vec<D> *const x = P_.x.data(), *const v = P_.v.data(), *const v_noslip = P_.v_noslip.data();
    const double *const mass = P_.mass.data(), *const rho = P_.rho.data();
    const double *const c = P_.c.data(), *const vol = P_.vol.data();
    const std::uint8_t* const mat = P_.material.data();
    const Mat<D>* const sigma_rho2 = P_.sigma_rho2.data();
    Mat<D>* const grad_v = P_.grad_v.data();
    Mat<D>* const shape = P_.shape.data();
    const Vec<D>* const shifts = list_.shifts();
    const Vec<D>* const jumps = list_.jumps();
    const double inv_h = kernel_.inv_h, grad_factor = kernel_.grad_factor, beyond2 = 4.0 * kernel_.h * kernel_.h * (1.0 + 1e-9);
    const Model model = model_;
    const Vec<D> xa = x[a], va = v[a];
    const double m_a = mass[a], rho_a = rho[a], vol_a = vol[a];
    const double inv_rho_a = 1.0 / rho_a, c_a = has(term::artificial_viscosity) ? c[a] : 0.0;
    const double* const mu_row = materials_.pair_mu_table() + mat[a] * materials_.size();
    const Vec<D> vns_a = v_noslip[a];
    const Mat<D> S_a = sigma_rho2[a];
    Mat<D> G_a = Mat<D>::Zero(), M_a = Mat<D>::Zero();
    Vec<D> acc_a = Vec<D>::Zero();
    double drho_a = 0.0, work_a = 0.0;
    for (; e != end; ++e) {
      const int b = static_cast<int>(*e >> List::shift_bits);
      const Vec<D> r = xa - x[b] - shifts[*e & List::shift_mask];  // r_ab to the listed image of b
      const double r2 = r.squaredNorm();
      if (!(r2 < beyond2)) continue;  // a skin pair (a quarter of the list, q > 2 whatever the rounding): exact zeros
      const double q = std::sqrt(r2) * inv_h, u = 1.0 - 0.5 * q;  // u > 0: the exact test at the support's edge
      if (!(u > 0.0)) continue;
      if constexpr (grains && Models::any_solid && AMoves != BMoves)  // eq. G8 acts between a grain and a solid
        if (AMoves ? P_.grain_beside_solid(b, a) : P_.grain_beside_solid(a, b)) continue;
      if constexpr (Bodies)  // eq. SC1 between two bodies (solid_contact.h)
        if (contact_.pair<AMoves, BMoves>(P_, a, b, r, r2, acc_a, acc)) continue;
      const double t = u, F = grad_factor * (t * t * t);  // grad_a W_ab = F r_ab (eq. 8)
      Vec<D> v_ab = va - v[b], jump = Vec<D>::Zero();
      if constexpr (has(term::sheared)) jump = jumps[*e & List::shift_mask], v_ab -= jump;
      const double Fvr = F * v_ab.dot(r);  // v_ab . grad_a W_ab (= v_ba . grad_b W_ba)
      const double m_b = mass[b], rho_b = rho[b];
      const auto [solid_a, solid_b] = interface_sides<Models>(P_, a, b);  // eq. FS2 (fluid_solid.h)
      continuity_pair<AMoves, BMoves>(drho_a, drho[b], Fvr, rho_a * vol[b], rho_b * vol_a, m_b, m_a, solid_a, solid_b);
      // Eq. T2 for both particles: -F V v_ab (x) r_ab and -F V r_ab (x) r_ab; a fixed
      // boundary particle enters with its no-slip velocity (boundary_particles.h).
      Vec<D> v_ab_grad = v_ab;
      if constexpr (AMoves && !BMoves) v_ab_grad = va - v_noslip[b] - jump;
      if constexpr (!AMoves && BMoves) v_ab_grad = vns_a - v[b] - jump;
      subtract_outer_products(v_ab_grad, r, solid_a ? 0.0 : F * vol[b], solid_b ? 0.0 : F * vol_a, G_a, M_a, grad_v[b],
                              shape[b]);
      if constexpr (has(term::stress_diffusion) && AMoves && BMoves) stress_diffusion_pair(P_, a, b, F, r2, kernel_.h);
      if constexpr (AMoves || BMoves) {
        // Eq. T1 and eqs. 11-12 (along r_ab): symmetric in a and b; grad_b W_ba = -F r_ab.
        const double radial = viscous_radial<AMoves, BMoves>(model, r2, v_ab.dot(r), rho_a, rho_b, c_a, c[b], F);
        Vec<D> f = pair_force(S_a, a, b, t, q, F, r);
        add_scaled(f, radial, r);
        if constexpr (AMoves) add_scaled(acc_a, m_b, f);
        if constexpr (BMoves) add_scaled(acc[b], -m_a, f);
        // A solid's internal energy takes what the pair's force takes from the kinetic energy, m_a m_b v_ab . f
        // (stress, artificial stress and viscosity), half to each: de_a/dt = -1/2 sum_b m_b v_ab . f_ab.
        if constexpr (Models::any_solid) {
          if constexpr (Smooth) smoothing_.pair(P_, a, b, F, r2);  // eq. SS1 (pair_row: both move)
          const double half_power = 0.5 * v_ab.dot(f);
          if constexpr (AMoves) work_a -= m_b * half_power;
          if constexpr (BMoves) P_.solid_state.rate[b][slot::energy] -= m_a * half_power;
        }
        if constexpr (has(term::morris_viscosity))
          tensor_morris_pair<AMoves, BMoves, has(term::sheared), has(term::several_materials)>(
              P_, model.morris, b, F, r2, jump, va, vns_a, vol_a, inv_rho_a, mu_row, acc_a);
        if constexpr (grains && AMoves != BMoves)  // eq. G1: a grain's particle takes the pair's reaction
          tensor_grain_reaction<AMoves, has(term::morris_viscosity), has(term::several_materials)>(
              P_, model.morris, mu_row, a, b, F, r2, f, va, vns_a, r, acc_a);
      }
    }
    acc[a] += acc_a, drho[a] += drho_a, grad_v[a] += G_a, shape[a] += M_a;
    if constexpr (Models::any_solid) P_.solid_state.rate[a][slot::energy] += work_a;
    (void)mu_row, (void)jumps, (void)work_a;
  }
  // Eqs. 11-12 of the pair: -Pi_ab F, the factor of m_b r_ab in dv_a/dt (times 0 or 1 against a fixed particle).
  template <bool AMoves, bool BMoves>
  inline __attribute__((always_inline)) double viscous_radial(const Model& model, double r2, double vr, double rho_a,
                                                              double rho_b, double c_a, double c_b, double F) const {
    if constexpr (!has(term::artificial_viscosity)) {
      return (void)model, (void)r2, (void)vr, (void)rho_a, (void)rho_b, (void)c_a, (void)c_b, (void)F, 0.0;
    } else {
      double pi = model.artificial.pi(r2, vr, rho_a, rho_b, c_a, c_b);
      if constexpr (!(AMoves && BMoves)) pi *= model.artificial.wall;
      return -pi * F;
    }
  }
  // Eq. T1's stress of the pair a, b, sigma_a/rho_a^2 (S_a) + sigma_b/rho_b^2; solids add Monaghan's artificial
  // stress f_ab^n (R_a + R_b), f_ab = W(r_ab) / W(dx) from t = max(1 - q/2, 0) and q = r_ab / h
  // (johnson_cook_material.h); times g = grad_a W_ab. Eq. FS1 between a fluid's and a solid's (fluid_solid.h).
  inline __attribute__((always_inline)) Vec<D> pair_force(const Mat<D>& S_a, int a, int b, double t, double q,
                                                          double F, const Vec<D>& r) const {
    const Vec<D> g = F * r;
    if constexpr (Models::any_solid) {
      if constexpr (!Models::all_solid)  // eq. FS1 between a fluid's particle and a solid's
        if (P_.solid_material[P_.material[a]] != P_.solid_material[P_.material[b]])
          return interface_force<Models::any_modes>(P_, model_.gravity, a, b, F, r);
      if (!artificial_stress_.on) return sum_times(S_a, P_.sigma_rho2[b], g);  // the same sum without adding zeros
      return sum_times(S_a, P_.sigma_rho2[b], artificial_stress_(t, q), P_.art_stress[a], P_.art_stress[b], g);
    } else
      return (void)a, (void)t, (void)q, sum_times(S_a, P_.sigma_rho2[b], g);
  }

  Particles<D>& P_;
  const NeighbourList<D>& list_;
  const WendlandC2<D>& kernel_;
  const Model& model_;
  const MaterialTable& materials_;
  std::vector<double>& shepard_;
  bool uniform_mass_ = false;
  ArtificialStressFactor artificial_stress_;  // solids (set at each list build)
  SolidSmoothing smoothing_;                  // eq. SS1 (solids with `smoothing`)
  SolidContact contact_;                      // eq. SC1 (two solid materials or more)
  ViscosityCorrection<D> correction_;  // eq. VC1 (corrected configurations only)
  mutable PairLanes<D> lanes_;         // the fluid-fluid rows' records and sums (lanes configurations only)
};
}  // namespace sph
