// Turning the deck and its input files into particles and wall meshes.
#pragma once
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "parameters.h"
#include "input_h5.h"
#include "particles.h"
#include "wall_penalty.h"

namespace sph {

// The input particles, with room for `extra` more (inflow) in every array.
template <int D>
Particles<D> make_particles(const RunParameters& deck, const ParticleInput& in, std::size_t extra = 0) {
  Particles<D> P;
  P.has_wall_points = !in.wall_point.empty();
  P.saved = in.saved;
  P.grains = !deck.grains.empty();
  P.reserve(in.n + extra);
  P.resize(in.n);
  const std::vector<MaterialSpec> materials = deck.material_list();
  const std::size_t nm = materials.size();
  const bool resumed = deck.t_start > 0.0 || deck.step_start > 0;
  std::vector<double> mass_sum(nm, 0.0);
  std::vector<std::size_t> fluid(nm, 0);
  if (!in.material.empty() && deck.materials.empty())
    throw InputError("the particle file gives 'material' but the deck has no 'materials' list");
  for (std::size_t i = 0; i < in.n; ++i) {
    for (int d = 0; d < D; ++d) {
      P.x[i][d] = in.positions[i * D + d];
      P.v[i][d] = in.velocities[i * D + d];
    }
    if (P.has_wall_points)  // kept relative to the particle: wrapping into a periodic box moves both
      for (int d = 0; d < D; ++d) P.wall_offset[i][d] = in.wall_point[i * D + d] - P.x[i][d];
    P.mass[i] = in.masses[i];
    P.rho[i] = in.densities[i];
    P.kind[i] = static_cast<Kind>(in.kind[i]);
    if (deck.lees_edwards.on && P.kind[i] != Kind::fluid && P.kind[i] != Kind::body)
      throw InputError("particle " + std::to_string(i) + " is neither fluid nor a grain's (kind " +
                       std::to_string(in.kind[i]) + "): a 'lees_edwards' cell takes fluid and grains only");
    P.id[i] = in.ids.empty() ? static_cast<std::int64_t>(i) : in.ids[i];
    const std::int32_t mat = in.material.empty() ? 0 : in.material[i];
    if (mat < 0 || static_cast<std::size_t>(mat) >= nm)
      throw InputError("material[" + std::to_string(i) + "] = " + std::to_string(mat) + " in the particle file is not an index into 'materials' (0.." +
                       std::to_string(nm - 1) + ")");
    P.material[i] = static_cast<std::uint8_t>(mat);
    if (P.grains) P.grain[i] = -1, P.grain_offset[i].setZero();
    if (P.kind[i] == Kind::body) {
      const std::int32_t g = in.grain.empty() ? -1 : in.grain[i];
      if (g < 0 || static_cast<std::size_t>(g) >= deck.grains.size())
        throw InputError("particle " + std::to_string(i) + " is a grain's (kind 4) but its 'grain' = " + std::to_string(g) +
                         " in the particle file is not an index into the deck's 'grains' (" +
                         std::to_string(deck.grains.size()) + " of them)");
      P.grain[i] = g;
    }
    if (P.kind[i] == Kind::fluid) {
      const double speed = P.v[i].norm();
      // A new run's fluid starts within v_max, the speed its c0 was chosen for. A resumed run (t_start or
      // step_start > 0) continues a state its run reached, where a jet may exceed v_max; only c0 (the run's
      // own stop criterion, check_stability) bounds it.
      if (resumed && speed > materials[mat].c0)
        throw InputError("particle " + std::to_string(i) + " starts at " + std::to_string(speed) +
                         " m/s, above its material's c0 = " + std::to_string(materials[mat].c0) +
                         " m/s: the state this run resumes from is not weakly compressible");
      if (!resumed && speed > deck.v_max)
        throw InputError("particle " + std::to_string(i) + " starts at " + std::to_string(speed) +
                         " m/s, above v_max = " + std::to_string(deck.v_max) + " m/s; raise v_max (and c0)");
      mass_sum[mat] += P.mass[i];
      ++fluid[mat];
    }
  }
  for (std::size_t k = 0; k < deck.periodic_axes.size(); ++k) {
    const int a = deck.periodic_axes[k];
    for (std::size_t i = 0; i < in.n; ++i)
      if (P.x[i][a] < deck.periodic_lo[k] - deck.dx || P.x[i][a] > deck.periodic_hi[k] + deck.dx)
        throw InputError("particle " + std::to_string(i) + " lies outside the periodic box along axis " +
                         std::to_string(a) + " (periodic.lo .. periodic.hi)");
  }
  for (std::size_t k = 0; k < nm; ++k) {
    if (!fluid[k]) continue;
    const double expected = materials[k].rho0 * std::pow(deck.dx, D);
    const double mean = mass_sum[k] / fluid[k];
    if (std::abs(mean / expected - 1.0) > 0.2)
      std::fprintf(stderr, "warning: mean fluid particle mass %.4g kg differs from rho0 dx^%d = %.4g kg by more "
                   "than 20 %%\n", mean, D, expected);
  }
  return P;
}

template <int D>
WallMesh<D> make_mesh(const MeshSpec& spec) {
  WallMesh<D> m;
  m.name = spec.name;
  const std::string where = "mesh '" + spec.name + "'";
  if (!spec.file.empty()) {
    const MeshInput in = read_mesh(spec.file, spec.group, D);
    for (std::size_t i = 0; i + D <= in.vertices.size(); i += D) m.vertices.push_back(Eigen::Map<const Vec<D>>(&in.vertices[i]));
    for (std::size_t i = 0; i + D <= in.faces.size(); i += D) {
      std::array<int, D> f{};
      for (int k = 0; k < D; ++k) f[k] = static_cast<int>(in.faces[i + k]);
      m.faces.push_back(f);
    }
  } else {
    for (const auto& v : spec.vertices) m.vertices.push_back(Eigen::Map<const Vec<D>>(v.data()));
    for (const auto& face : spec.faces) {
      std::array<int, D> f{};
      for (int k = 0; k < D; ++k) f[k] = static_cast<int>(face[k]);
      m.faces.push_back(f);
    }
  }
  if (m.faces.empty()) throw InputError(where + " has no faces");
  const int nv = static_cast<int>(m.vertices.size());
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    for (int id : m.faces[f])
      if (id < 0 || id >= nv)
        throw InputError(where + ": face " + std::to_string(f) + " uses vertex " + std::to_string(id) +
                         ", outside 0.." + std::to_string(nv - 1));
    const auto& v = m.vertices;
    const auto& ids = m.faces[f];
    double size;
    if constexpr (D == 3) size = (v[ids[1]] - v[ids[0]]).cross(v[ids[2]] - v[ids[0]]).norm();
    else size = (v[ids[1]] - v[ids[0]]).norm();
    if (!(size > 0.0)) throw InputError(where + ": face " + std::to_string(f) + " is degenerate (zero size)");
  }
  return m;
}

template <int D>
WallPenalty<D> make_walls(const RunParameters& deck) {
  if (deck.meshes.empty()) return {};
  std::vector<WallMesh<D>> meshes;
  for (const auto& spec : deck.meshes) meshes.push_back(make_mesh<D>(spec));
  return WallPenalty<D>(std::move(meshes), {deck.wall_range, deck.wall_s, deck.wall_psi}, 2.0 * deck.h);
}

}  // namespace sph
