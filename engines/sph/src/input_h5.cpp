#include "input_h5.h"

#include <algorithm>
#include <cmath>

#include "parameters.h"
#include "h5_handle.h"

namespace sph {
namespace {

[[noreturn]] void fail(const std::string& msg) { throw InputError(msg); }

struct Silence {  // HDF5 prints its own error stack otherwise
  Silence() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }
};

H5Handle open_file(const std::string& path) {
  static Silence silence;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) fail("cannot open HDF5 file '" + path + "'");
  return {f, H5Fclose};
}

// Read dataset `name` (relative to loc) as `type`, checking its shape is (rows, cols) or (rows) for cols == 0.
template <class T>
std::vector<T> read(hid_t loc, const std::string& file, const std::string& name, hid_t type, std::size_t& rows,
                    int cols) {
  if (H5Lexists(loc, name.c_str(), H5P_DEFAULT) <= 0) fail("'" + file + "' has no dataset '" + name + "'");
  H5Handle ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) fail("cannot open dataset '" + name + "' in '" + file + "'");
  H5Handle space(H5Dget_space(ds), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  const int want_rank = cols ? 2 : 1;
  if (rank != want_rank || (cols && dims[1] != static_cast<hsize_t>(cols)))
    fail("dataset '" + name + "' in '" + file + "' must have shape (n" + (cols ? "," + std::to_string(cols) : "") +
         ")");
  if (rows && dims[0] != rows)
    fail("dataset '" + name + "' in '" + file + "' has " + std::to_string(dims[0]) + " rows, expected " +
         std::to_string(rows));
  rows = dims[0];
  std::vector<T> out(rows * (cols ? cols : 1));
  if (!out.empty() && H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail("cannot read dataset '" + name + "' in '" + file + "' as numbers");
  return out;
}

// The column count of 2-D dataset `name` (its shape then checked by read).
int columns(hid_t loc, const std::string& file, const std::string& name) {
  H5Handle ds(H5Dopen2(loc, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) fail("cannot open dataset '" + name + "' in '" + file + "'");
  H5Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space) != 2) fail("dataset '" + name + "' in '" + file + "' must have shape (n, columns)");
  H5Sget_simple_extent_dims(space, dims, nullptr);
  if (dims[1] == 0) fail("dataset '" + name + "' in '" + file + "' has no columns");
  return static_cast<int>(dims[1]);
}

void all_finite(const std::vector<double>& v, const std::string& file, const std::string& name) {
  for (double x : v)
    if (!std::isfinite(x)) fail("dataset '" + name + "' in '" + file + "' holds a non-finite value");
}

}  // namespace

ParticleInput read_particles(const std::string& path, int dimension) {
  H5Handle f = open_file(path);
  ParticleInput p;
  p.dimension = dimension;
  std::size_t n = 0;
  p.positions = read<double>(f, path, "positions", H5T_NATIVE_DOUBLE, n, dimension);
  if (n == 0) fail("'" + path + "' holds no particles");
  p.velocities = read<double>(f, path, "velocities", H5T_NATIVE_DOUBLE, n, dimension);
  p.masses = read<double>(f, path, "masses", H5T_NATIVE_DOUBLE, n, 0);
  p.densities = read<double>(f, path, "densities", H5T_NATIVE_DOUBLE, n, 0);
  p.kind = read<std::int8_t>(f, path, "kind", H5T_NATIVE_INT8, n, 0);
  // Optional: each particle's index into the deck's materials (0 for all when absent).
  if (H5Lexists(f, "material", H5P_DEFAULT) > 0) p.material = read<std::int32_t>(f, path, "material", H5T_NATIVE_INT32, n, 0);
  // Optional: each body particle's grain (index into the deck's grains; ignored for other kinds).
  if (H5Lexists(f, "grain", H5P_DEFAULT) > 0) p.grain = read<std::int32_t>(f, path, "grain", H5T_NATIVE_INT32, n, 0);
  // Optional: the nearest point of the true wall of each boundary particle (NaN: none).
  if (H5Lexists(f, "wall_point", H5P_DEFAULT) > 0) {
    p.wall_point = read<double>(f, path, "wall_point", H5T_NATIVE_DOUBLE, n, dimension);
    for (double x : p.wall_point)
      if (std::isinf(x)) fail("dataset 'wall_point' in '" + path + "' holds an infinite value (NaN rows mean none)");
  }
  // Optional: the ids of a resumed run's frame (unique, >= 0), so particles keep their ids across the parts.
  if (H5Lexists(f, "ids", H5P_DEFAULT) > 0) {
    p.ids = read<std::int64_t>(f, path, "ids", H5T_NATIVE_INT64, n, 0);
    std::vector<std::int64_t> sorted = p.ids;
    std::sort(sorted.begin(), sorted.end());
    if (!sorted.empty() && sorted.front() < 0) fail("dataset 'ids' in '" + path + "' holds a negative id");
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      fail("dataset 'ids' in '" + path + "' holds an id twice");
  }
  // Optional: a resumed run's integrated fields beyond velocity and density, as its frame wrote them.
  for (const char* name : {"stress", "mode_stress", "solid_state"}) {
    if (H5Lexists(f, name, H5P_DEFAULT) <= 0) continue;
    SavedField field{name, columns(f, path, name), {}};
    field.values = read<double>(f, path, name, H5T_NATIVE_DOUBLE, n, field.cols);
    all_finite(field.values, path, name);
    p.saved.push_back(std::move(field));
  }
  p.n = n;
  all_finite(p.positions, path, "positions");
  all_finite(p.velocities, path, "velocities");
  all_finite(p.masses, path, "masses");
  all_finite(p.densities, path, "densities");
  for (std::size_t i = 0; i < n; ++i) {
    if (!(p.masses[i] > 0)) fail("masses[" + std::to_string(i) + "] in '" + path + "' must be > 0");
    if (!(p.densities[i] > 0)) fail("densities[" + std::to_string(i) + "] in '" + path + "' must be > 0");
    if (p.kind[i] < 0 || p.kind[i] > 4)
      fail("kind[" + std::to_string(i) + "] in '" + path +
           "' must be 0 (fluid), 1 (boundary), 2 (inlet), 3 (outlet) or 4 (a grain's particle)");
    p.has_buffers = p.has_buffers || p.kind[i] == 2 || p.kind[i] == 3;
  }
  return p;
}

MeshInput read_mesh(const std::string& path, const std::string& group, int dimension) {
  H5Handle f = open_file(path);
  if (group != "/" && H5Lexists(f, group.c_str(), H5P_DEFAULT) <= 0)
    fail("'" + path + "' has no group '" + group + "'");
  H5Handle g(H5Gopen2(f, group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail("cannot open group '" + group + "' in '" + path + "'");
  MeshInput m;
  std::size_t nv = 0, nf = 0;
  const std::string where = path + ":" + group;
  m.vertices = read<double>(g, where, "vertices", H5T_NATIVE_DOUBLE, nv, dimension);
  m.faces = read<long>(g, where, "faces", H5T_NATIVE_LONG, nf, dimension);
  all_finite(m.vertices, where, "vertices");
  return m;
}

}  // namespace sph
