// The run's output file (HDF5): frames, time series and run attributes.
//
// Layout: /frames/<k>/ (attrs time, step; ids, kind, positions, velocities,
// densities, pressures), /series/time and /series/<name> (extendible, one row
// per record, attr units), root attrs (engine, status, message, n_steps, ...).
// Everything is flushed after each frame so a killed run keeps its data.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "h5_handle.h"

namespace sph {

class OutputFile {
 public:
  explicit OutputFile(const std::string& path);  // truncates; throws std::runtime_error
  ~OutputFile();

  void attr(const std::string& name, const std::string& value);
  void attr(const std::string& name, double value);
  void attr(const std::string& name, long value);

  // One frame; arrays are row-major with `cols` columns, n rows.
  void frame(double time, long step, std::size_t n, int cols, const std::int64_t* ids, const std::int8_t* kind,
             const double* positions, const double* velocities, const double* densities, const double* pressures);
  // One more dataset (n rows, `cols` columns; 0: a vector) in the frame just written.
  void frame_field(const std::string& name, std::size_t n, int cols, const double* data);
  int frames_written() const { return frames_; }

  // Declare a series of `cols` columns (0: scalar) before the first record; returns its index.
  int series(const std::string& name, int cols, const std::string& units);
  // Append one row to every series: values[i] points to series i's row.
  void record(double time, const std::vector<const double*>& values);
  void flush();

 private:
  void append(H5Handle& ds, int cols, const double* row);
  H5Handle file_, frames_group_, series_group_, last_frame_;
  struct Series {
    H5Handle ds;
    int cols;
  };
  std::vector<Series> series_;
  H5Handle time_;
  hsize_t rows_ = 0;
  int frames_ = 0;
};

}  // namespace sph
