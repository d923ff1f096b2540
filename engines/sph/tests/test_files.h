// Helpers for tests that go through files: a scratch directory, particle
// files written with the HDF5 C API, and reading results back.
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace testfiles {

inline std::filesystem::path scratch_root() {
  return std::filesystem::temp_directory_path() / ("sph_tests_" + std::to_string(::getpid()));
}

inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = scratch_root() / name;
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

template <class T>
void put(hid_t file, const char* name, hid_t type, const std::vector<T>& data, hsize_t rows, hsize_t cols) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols ? 2 : 1, dims, nullptr);
  hid_t ds = H5Dcreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Dclose(ds);
  H5Sclose(space);
}

struct ParticleRows {
  int dim = 2;
  std::vector<double> x, v, m, rho;
  std::vector<std::int8_t> kind;
  std::vector<std::int32_t> material;  // written only when some row gives one
  std::vector<double> wall_point;      // dim per row (NaN: none), written when some row gives one
  void add(std::vector<double> pos, std::vector<double> vel, double mass, double density, int k, int mat = -1) {
    x.insert(x.end(), pos.begin(), pos.end());
    v.insert(v.end(), vel.begin(), vel.end());
    m.push_back(mass), rho.push_back(density), kind.push_back(static_cast<std::int8_t>(k));
    if (mat >= 0) material.resize(size() - 1, 0), material.push_back(mat);
  }
  std::size_t size() const { return m.size(); }
  void write(const std::filesystem::path& path) const {
    hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    put(f, "positions", H5T_NATIVE_DOUBLE, x, size(), dim);
    put(f, "velocities", H5T_NATIVE_DOUBLE, v, size(), dim);
    put(f, "masses", H5T_NATIVE_DOUBLE, m, size(), 0);
    put(f, "densities", H5T_NATIVE_DOUBLE, rho, size(), 0);
    put(f, "kind", H5T_NATIVE_INT8, kind, size(), 0);
    if (!material.empty()) {
      std::vector<std::int32_t> all = material;
      all.resize(size(), 0);
      put(f, "material", H5T_NATIVE_INT32, all, size(), 0);
    }
    if (!wall_point.empty()) put(f, "wall_point", H5T_NATIVE_DOUBLE, wall_point, size(), dim);
    H5Fclose(f);
  }
};

inline std::vector<double> read_doubles(const std::filesystem::path& path, const std::string& name) {
  std::vector<double> out;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return out;
  hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  if (ds >= 0) {
    hid_t space = H5Dget_space(ds);
    out.resize(H5Sget_simple_extent_npoints(space));
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Sclose(space);
    H5Dclose(ds);
  }
  H5Fclose(f);
  return out;
}

inline std::string read_string_attr(const std::filesystem::path& path, const std::string& name) {
  std::string out;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t a = H5Aopen(f, name.c_str(), H5P_DEFAULT);
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  char* text = nullptr;
  if (H5Aread(a, type, &text) >= 0 && text) {
    out = text;
    H5free_memory(text);
  }
  H5Tclose(type);
  H5Aclose(a);
  H5Fclose(f);
  return out;
}

inline double read_double_attr(const std::filesystem::path& path, const std::string& object, const std::string& name) {
  double out = 0.0;
  hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t a = H5Aopen_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &out);
  H5Aclose(a);
  H5Fclose(f);
  return out;
}

}  // namespace testfiles
