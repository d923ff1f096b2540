// Particle state as a structure of arrays, with the integrator's start-of-step copies.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "parallel.h"
#include "physics_terms.h"
#include "vec.h"

namespace sph {

template <int D>
struct Particles {
  std::vector<Vec<D>> x, v;       // position m, velocity m/s
  std::vector<double> rho, mass;  // kg/m^3, kg
  std::vector<Kind> kind;
  std::vector<std::int64_t> id;   // input row, or a new number for inflow (stable across reordering)
  // Rates of the last evaluation (the previous half step), used by the next predictor:
  std::vector<Vec<D>> acc;         // dv/dt, m/s^2
  std::vector<double> drho;        // drho/dt, kg/m^3/s
  // Derived each evaluation:
  std::vector<double> p, c;         // pressure Pa, sound speed m/s
  std::vector<double> vol, p_rho2;  // m/rho m^D, p/rho^2 (saves divisions in the pair loop)
  std::vector<Vec<D>> v_noslip;    // velocity seen by the viscous term: v for fluid, mirrored for boundary
  // Start-of-step state of the predictor-corrector:
  std::vector<Vec<D>> x0, v0;
  std::vector<double> rho0;
  // Second buffers of the persistent state: a reorder that reads the arrays
  // and writes these in the same pass (on several threads), then swap_next().
  struct Next {
    std::vector<Vec<D>> x, v, acc;
    std::vector<double> rho, mass, drho;
    std::vector<Kind> kind;
    std::vector<std::int64_t> id;
  } next;

  std::size_t size() const { return x.size(); }

  void resize(std::size_t n) {
    for (auto* a : {&x, &v, &acc, &v_noslip, &x0, &v0}) a->resize(n, Vec<D>::Zero());
    for (auto* a : {&rho, &mass, &p, &c, &drho, &vol, &p_rho2, &rho0}) a->resize(n, 0.0);
    kind.resize(n, Kind::fluid);
    id.resize(n, 0);
  }

  bool moves(std::size_t a) const { return kind[a] == Kind::fluid; }       // integrates the forces
  bool advects(std::size_t a) const { return kind[a] != Kind::boundary; }  // changes position

  // Capacity for n particles in every array, so later growth up to n does not allocate.
  void reserve(std::size_t n) {
    for (auto* a : {&x, &v, &acc, &v_noslip, &x0, &v0, &scratch_vec_, &next.x, &next.v, &next.acc}) a->reserve(n);
    for (auto* a : {&rho, &mass, &p, &c, &drho, &vol, &p_rho2, &rho0, &scratch_dbl_, &next.rho, &next.mass, &next.drho})
      a->reserve(n);
    kind.reserve(n), scratch_kind_.reserve(n), next.kind.reserve(n);
    id.reserve(n), scratch_id_.reserve(n), next.id.reserve(n);
  }

  // Size the second buffers for the current particle count (no allocation within the reserved capacity).
  void size_next() {
    const std::size_t n = size();
    for (auto* a : {&next.x, &next.v, &next.acc}) a->resize(n);
    for (auto* a : {&next.rho, &next.mass, &next.drho}) a->resize(n);
    next.kind.resize(n);
    next.id.resize(n);
  }
  // The second buffers become the persistent state (after a pass filled them).
  void swap_next() {
    x.swap(next.x), v.swap(next.v), acc.swap(next.acc);
    rho.swap(next.rho), mass.swap(next.mass), drho.swap(next.drho);
    kind.swap(next.kind), id.swap(next.id);
  }

  void append(const Vec<D>& pos, const Vec<D>& vel, double density, double m, Kind k, std::int64_t ident) {
    const std::size_t i = size();
    resize(i + 1);
    x[i] = pos, v[i] = vel, rho[i] = density, mass[i] = m, kind[i] = k, id[i] = ident;
  }

  // Keep the particles for which keep(i) holds, in order (persistent state and last rates).
  template <class Keep>
  void compact(Keep&& keep) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < size(); ++i) {
      if (!keep(i)) continue;
      x[k] = x[i], v[k] = v[i], rho[k] = rho[i], mass[k] = mass[i], kind[k] = kind[i], id[k] = id[i];
      acc[k] = acc[i], drho[k] = drho[i];
      ++k;
    }
    resize(k);
  }

  // Reorder the persistent state, the last rates and the start-of-step state by
  // `order` (new index k takes old index order[k]).
  // Scratch buffers keep their capacity, so this does not allocate once warmed up.
  void reorder(const std::vector<int>& order) {
    const std::size_t n = size();
    permute(x, order, n, scratch_vec_);
    permute(v, order, n, scratch_vec_);
    permute(rho, order, n, scratch_dbl_);
    permute(mass, order, n, scratch_dbl_);
    permute(kind, order, n, scratch_kind_);
    permute(id, order, n, scratch_id_);
    permute(acc, order, n, scratch_vec_);
    permute(drho, order, n, scratch_dbl_);
    permute(x0, order, n, scratch_vec_);
    permute(v0, order, n, scratch_vec_);
    permute(rho0, order, n, scratch_dbl_);
  }

 private:
  template <class T>
  static void permute(std::vector<T>& a, const std::vector<int>& order, std::size_t n, std::vector<T>& scratch) {
    scratch.resize(n);
    parallel_for(static_cast<std::ptrdiff_t>(n), parallel_min_light, [&](std::ptrdiff_t k) { scratch[k] = a[order[k]]; });
    a.swap(scratch);
  }
  std::vector<Vec<D>> scratch_vec_;
  std::vector<double> scratch_dbl_;
  std::vector<Kind> scratch_kind_;
  std::vector<std::int64_t> scratch_id_;
};

}  // namespace sph
