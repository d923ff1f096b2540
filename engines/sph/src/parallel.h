// When a loop runs on several OpenMP threads, and a helper that runs it so.
#pragma once
#include <omp.h>

#include <strings.h>

#include <cstddef>
#include <cstdlib>
#include <vector>

namespace sph {

// Below these particle counts a loop runs on one thread: starting a parallel
// region costs more than it saves (and spinning threads hurt on a busy machine).
inline constexpr std::ptrdiff_t parallel_min_heavy = 512;  // a neighbour sum per particle

// Light loops (a few flops per particle: predictor, reorder, corrector) run on
// the threads from this many particles. Idle OpenMP threads that spin a
// little before sleeping (GOMP_SPINCOUNT) pick the next loop up within a
// microsecond, so 2048 pays; threads that sleep at once
// (OMP_WAIT_POLICY=passive, for shared cores) take tens of microseconds to
// wake (about 45 us measured on a 2-core VM), as long as a light loop over
// ~10^4 particles, so there the light loops stay serial below 16384.
inline std::ptrdiff_t parallel_min_light = 2048;
inline constexpr std::ptrdiff_t parallel_min_light_passive = 16384;

// Set parallel_min_light from the OpenMP wait policy of this process (call once, at start-up).
inline void configure_parallel() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  if (policy && strcasecmp(policy, "passive") == 0) parallel_min_light = parallel_min_light_passive;
}

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

// Inside a parallel region (par) or not: body() once, on one thread of the region (the others wait at its end).
template <class Body>
void on_one_thread(bool par, Body&& body) {
  if (par) {
#pragma omp single
    body();
  } else {
    body();
  }
}

// Inside a parallel region (par) or not: body(i) for i in [0, n) as a
// worksharing loop of the enclosing region (static schedule, a barrier at
// its end) when par, else as a plain loop.
template <class Body>
void for_each_index(bool par, std::ptrdiff_t n, Body&& body) {
  if (par) {
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
  } else {
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i);
  }
}

// One thread's partial result of a reduction, alone on its cache line.
template <class T>
struct alignas(64) ThreadPartial {
  T value;
};

// Inside a parallel region (par): body(i, partial) for i in [0, n), each
// thread updating its own partial in `partials` (from `init`; static
// schedule), without the loop's closing barrier and without combining them:
// after a barrier (reduce_each_index, or the region's end) the partials
// [0, threads) are combined in thread order (combine_partials). Not par:
// returns the total.
template <class T, class Body>
T partial_each_index(bool par, std::ptrdiff_t n, std::vector<ThreadPartial<T>>& partials, const T& init,
                     Body&& body) {
  T total = init;
  if (!par) {
    for (std::ptrdiff_t i = 0; i < n; ++i) body(i, total);
    return total;
  }
  T& mine = partials[omp_get_thread_num()].value;
  mine = init;
#pragma omp for schedule(static) nowait
  for (std::ptrdiff_t i = 0; i < n; ++i) body(i, mine);
  return total;
}
template <class T, class Combine>
T combine_partials(const std::vector<ThreadPartial<T>>& partials, int threads, const T& init, Combine&& combine) {
  T total = init;
  for (int t = 0; t < threads; ++t) combine(total, partials[t].value);
  return total;
}

// Inside a parallel region (par) or not: body(i, partial) for i in [0, n),
// each thread updating its own partial (from `init`; static schedule), then,
// after a barrier, the partials combined in thread order by
// combine(total, partial); every thread returns the total. For max, min and
// logical and (exact in any order) the result does not depend on the thread
// count. `partials` has a slot per thread (sized before the region); a
// region may use it once (a thread still combining would see the next loop's partials).
template <class T, class Body, class Combine>
T reduce_each_index(bool par, std::ptrdiff_t n, std::vector<ThreadPartial<T>>& partials, const T& init, Body&& body,
                    Combine&& combine) {
  const T total = partial_each_index(par, n, partials, init, body);
  if (!par) return total;
#pragma omp barrier
  return combine_partials(partials, omp_get_num_threads(), init, combine);
}

// The wall time now into `at`: by the master thread inside a parallel region
// (par; after the barrier of the previous worksharing loop), else directly.
inline void stamp_time(bool par, double& at) {
  if (!par) at = omp_get_wtime();
#pragma omp master
  if (par) at = omp_get_wtime();
}

}  // namespace sph
