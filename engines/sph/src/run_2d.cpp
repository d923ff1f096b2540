// All 2D instantiations (one per set of physics terms); kept apart from 3D to compile in parallel.
#include "run.h"
#include "run_loop.h"

namespace sph {
int run_2d(const RunParameters& deck) { return run_dimension<2>(deck); }
}  // namespace sph
