#include "output_h5.h"

#include <stdexcept>

namespace sph {
namespace {

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5 output failed: " + what);
}

H5Handle group(hid_t loc, const std::string& name) {
  H5Handle g(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) throw std::runtime_error("HDF5 output failed: cannot create group " + name);
  return g;
}

template <class T>
void dataset(hid_t loc, const std::string& name, hid_t type, std::size_t rows, int cols, const T* data) {
  hsize_t dims[2] = {rows, static_cast<hsize_t>(cols)};
  H5Handle space(H5Screate_simple(cols ? 2 : 1, dims, nullptr), H5Sclose);
  H5Handle ds(H5Dcreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 output failed: cannot create " + name);
  if (rows) check(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + name);
}

void write_attr(hid_t loc, const std::string& name, hid_t type, const void* value) {
  if (H5Aexists(loc, name.c_str()) > 0) H5Adelete(loc, name.c_str());
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle a(H5Acreate2(loc, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!a.valid()) throw std::runtime_error("HDF5 output failed: attribute " + name);
  check(H5Awrite(a, type, value), "attribute " + name);
}

// Variable-length UTF-8, which h5py reads as str.
void string_attr(hid_t loc, const std::string& name, const std::string& value) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  const char* text = value.c_str();
  write_attr(loc, name, type, &text);
}

H5Handle extendible(hid_t loc, const std::string& name, int cols) {
  hsize_t dims[2] = {0, static_cast<hsize_t>(cols)};
  hsize_t maxdims[2] = {H5S_UNLIMITED, static_cast<hsize_t>(cols)};
  hsize_t chunk[2] = {256, static_cast<hsize_t>(cols ? cols : 1)};
  const int rank = cols ? 2 : 1;
  H5Handle space(H5Screate_simple(rank, dims, maxdims), H5Sclose);
  H5Handle plist(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(plist, rank, chunk);
  H5Handle ds(H5Dcreate2(loc, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, plist, H5P_DEFAULT), H5Dclose);
  if (!ds.valid()) throw std::runtime_error("HDF5 output failed: cannot create series " + name);
  return ds;
}

}  // namespace

OutputFile::OutputFile(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  file_ = H5Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (!file_.valid()) throw std::runtime_error("cannot create output file '" + path + "'");
  frames_group_ = group(file_, "frames");
  series_group_ = group(file_, "series");
  time_ = extendible(series_group_, "time", 0);
  string_attr(time_, "units", "s");
}

OutputFile::~OutputFile() {
  if (file_.valid()) H5Fflush(file_, H5F_SCOPE_GLOBAL);
}

void OutputFile::attr(const std::string& name, const std::string& value) { string_attr(file_, name, value); }
void OutputFile::attr(const std::string& name, double value) { write_attr(file_, name, H5T_NATIVE_DOUBLE, &value); }
void OutputFile::attr(const std::string& name, long value) { write_attr(file_, name, H5T_NATIVE_LONG, &value); }

void OutputFile::frame(double time, long step, std::size_t n, int cols, const std::int64_t* ids,
                       const std::int8_t* kind, const double* positions, const double* velocities,
                       const double* densities, const double* pressures) {
  H5Handle g = group(frames_group_, std::to_string(frames_));
  write_attr(g, "time", H5T_NATIVE_DOUBLE, &time);
  write_attr(g, "step", H5T_NATIVE_LONG, &step);
  dataset(g, "ids", H5T_NATIVE_INT64, n, 0, ids);
  dataset(g, "kind", H5T_NATIVE_INT8, n, 0, kind);
  dataset(g, "positions", H5T_NATIVE_DOUBLE, n, cols, positions);
  dataset(g, "velocities", H5T_NATIVE_DOUBLE, n, cols, velocities);
  dataset(g, "densities", H5T_NATIVE_DOUBLE, n, 0, densities);
  dataset(g, "pressures", H5T_NATIVE_DOUBLE, n, 0, pressures);
  last_frame_ = std::move(g);
  ++frames_;
  flush();
}

void OutputFile::frame_field(const std::string& name, std::size_t n, int cols, const double* data) {
  dataset(last_frame_, name, H5T_NATIVE_DOUBLE, n, cols, data);
  flush();
}

int OutputFile::series(const std::string& name, int cols, const std::string& units) {
  if (rows_) throw std::logic_error("series declared after the first record");
  Series s{extendible(series_group_, name, cols), cols};
  string_attr(s.ds, "units", units);
  series_.push_back(std::move(s));
  return static_cast<int>(series_.size()) - 1;
}

void OutputFile::append(H5Handle& ds, int cols, const double* row) {
  hsize_t dims[2] = {rows_ + 1, static_cast<hsize_t>(cols)};
  check(H5Dset_extent(ds, dims), "extend series");
  H5Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t start[2] = {rows_, 0}, count[2] = {1, static_cast<hsize_t>(cols)};
  const int rank = cols ? 2 : 1;
  check(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr), "select series row");
  H5Handle mem(H5Screate_simple(rank, count, nullptr), H5Sclose);
  check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, row), "write series row");
}

void OutputFile::record(double time, const std::vector<const double*>& values) {
  append(time_, 0, &time);
  for (std::size_t i = 0; i < series_.size(); ++i) append(series_[i].ds, series_[i].cols, values.at(i));
  ++rows_;
}

void OutputFile::flush() { H5Fflush(file_, H5F_SCOPE_GLOBAL); }

}  // namespace sph
