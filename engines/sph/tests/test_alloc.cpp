// No allocation in the time loop: a counting operator new (this test
// executable's global one) sees no allocation while a warmed-up simulation
// steps, list rebuilds included, on 1 and 2 threads, on the scalar and on the
// tensor path. (HDF5 output, outside Simulation::step, may allocate.)
#include <omp.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "check.h"
#include "simulation.h"

namespace {
std::atomic<long> allocations{0};
std::atomic<bool> armed{false};
}  // namespace
// Break here in a debugger to see where the time loop allocates.
extern "C" __attribute__((noinline)) void sph_test_allocation_in_time_loop() { asm volatile(""); }

void* operator new(std::size_t n) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (armed.load(std::memory_order_relaxed)) sph_test_allocation_in_time_loop();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace sph;

namespace {

struct StressCarrying : Newtonian {
  static constexpr const char* name = "stress_carrying";
  static constexpr bool has_stress = true;
};

constexpr unsigned kTerms = term::morris_viscosity | term::artificial_viscosity | term::body_force;

Deck deck() {
  Deck d;
  d.dimension = 2, d.terms = kTerms;
  d.rho0 = 1000.0, d.c0 = 20.0, d.gamma = 7.0, d.v_max = 2.0, d.viscosity = 1e-4, d.alpha = 0.2, d.beta = 0.1;
  d.h = 1.3e-3, d.dx = 1e-3, d.body_force = {0.0, -9.81};
  return d;
}

Particles<2> block() {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), speed(-1.0, 1.0);
  Particles<2> P;
  const int columns = 40, rows = 30;
  P.reserve(columns * (rows + 3));
  P.resize(columns * (rows + 3));
  int k = 0;
  for (int i = 0; i < columns; ++i)
    for (int j = -3; j < rows; ++j, ++k) {
      const bool wall = j < 0;
      P.x[k] = 1e-3 * Vec<2>(i + (wall ? 0.0 : jitter(rng)), j + (wall ? 0.0 : jitter(rng)));
      P.v[k] = wall ? Vec<2>::Zero() : Vec<2>(speed(rng), speed(rng));
      P.rho[k] = 1000.0, P.mass[k] = 1e-3, P.id[k] = k;
      P.kind[k] = wall ? Kind::boundary : Kind::fluid;
    }
  return P;
}

// Allocations during `steps` steps after `warm_up` steps, and the list builds among them.
template <class Sim>
long allocations_while_stepping(int threads, long& builds) {
  omp_set_num_threads(threads);
  Sim sim(deck(), block());
  for (int s = 0; s < 40; ++s) CHECK(sim.step(2e-6, NoCrossings{}));
  const long before = allocations.load(), builds_before = sim.stage_times().builds;
  armed = true;
  for (int s = 0; s < 200; ++s) CHECK(sim.step(2e-6, NoCrossings{}));
  armed = false;
  builds = sim.stage_times().builds - builds_before;
  return allocations.load() - before;
}

}  // namespace

TEST(no_allocation_while_stepping) {
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2}) {
    long builds = 0;
    const long scalar = allocations_while_stepping<Simulation<2, kTerms>>(threads, builds);
    std::fprintf(stderr, "  scalar path, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n", threads, scalar, builds);
    CHECK(scalar == 0 && builds > 0);
    const long tensor =
        allocations_while_stepping<Simulation<2, kTerms, ModelList<Newtonian, StressCarrying>>>(threads, builds);
    std::fprintf(stderr, "  tensor path, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n", threads, tensor, builds);
    CHECK(tensor == 0 && builds > 0);
  }
  omp_set_num_threads(saved);
}
