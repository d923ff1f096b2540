// When a loop runs on several OpenMP threads, and a helper that runs it so.
#pragma once
#include <omp.h>

#include <cstddef>

namespace sph {

// Below these particle counts a loop runs on one thread: starting a parallel
// region costs more than it saves (and spinning threads hurt on a busy machine).
inline constexpr std::ptrdiff_t parallel_min_light = 16384;  // a few flops per particle
inline constexpr std::ptrdiff_t parallel_min_heavy = 512;    // a neighbour sum per particle

// Whether a loop over n items opens a parallel region: enough work to pay for
// waking the threads, and more than one thread. Otherwise no region is
// entered at all: libgomp allocates a team for every region it starts (even
// one of a single thread, or with a false `if` clause), and the time loop
// must not allocate.
inline bool go_parallel(std::ptrdiff_t n, std::ptrdiff_t min_items) {
  return n >= min_items && omp_get_max_threads() > 1;
}

// body(i) for i in [0, n): on the threads (static schedule) when go_parallel(n, min_items).
template <class Body>
void parallel_for(std::ptrdiff_t n, std::ptrdiff_t min_items, Body&& body) {
  if (go_parallel(n, min_items)) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
  } else {
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
  }
}

}  // namespace sph
