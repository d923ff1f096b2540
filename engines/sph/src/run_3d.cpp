// All 3D instantiations (one per set of physics terms); kept apart from 2D to compile in parallel.
#include "run.h"
#include "run_loop.h"

namespace sph {
int run_3d(const RunParameters& deck) { return run_dimension<3>(deck); }
}  // namespace sph
