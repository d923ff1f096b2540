// Reading the particle and mesh input files (HDF5).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace sph {

// Rows of the particle file: positions (n,D) m, velocities (n,D) m/s,
// masses (n) kg, densities (n) kg/m^3, kind (n) 0 fluid / 1 boundary / 4 a grain's particle,
// optionally material (n) integer index into the deck's `materials` (default 0)
// and wall_point (n,D) m: the nearest point of the true wall surface of a fixed
// boundary particle (NaN row: none; ignored for fluid; boundary_particles.h).
// An integrated field of a resumed run's frame, as the frame holds it: dataset `name` (n, cols) row-major, rows in
// the particle file's order (restore_fields.h puts it back into the particles).
struct SavedField {
  std::string name;
  int cols = 0;
  std::vector<double> values;
};

struct ParticleInput {
  std::size_t n = 0;
  int dimension = 0;
  std::vector<double> positions, velocities, masses, densities;  // row-major
  std::vector<std::int8_t> kind;
  std::vector<std::int32_t> material;  // optional dataset `material` (n): index into the deck's materials
  std::vector<double> wall_point;      // optional dataset `wall_point` (n,D) m, row-major; NaN rows: none
  std::vector<std::int64_t> ids;       // optional dataset `ids` (n): a resumed run's particle ids (default: row)
  std::vector<std::int32_t> grain;     // optional dataset `grain` (n): a body particle's (kind 4) index into the deck's grains
  bool has_buffers = false;            // kind 2 (inlet) or 3 (outlet) rows: a resumed run's open-boundary buffers
  std::vector<SavedField> saved;       // optional datasets stress, mode_stress, solid_state: a resumed run's state
};

// A mesh group: vertices (nv,D) m, faces (nf,D) vertex indices (triangles in 3D, segments in 2D).
struct MeshInput {
  std::vector<double> vertices;
  std::vector<long> faces;
};

// Throw InputError naming the file and dataset when something is missing or malformed.
ParticleInput read_particles(const std::string& path, int dimension);
MeshInput read_mesh(const std::string& path, const std::string& group, int dimension);

}  // namespace sph
