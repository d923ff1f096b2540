// No allocation in the time loop: a counting operator new (this test
// executable's global one) sees no allocation while a warmed-up simulation
// steps, list rebuilds included, on 1 and 2 threads, on the scalar and on the
// tensor path (PTT + Morris on walls too). (HDF5 output, outside Simulation::step, may allocate.)
#include <omp.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "check.h"
#include "fixtures.h"
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
// GCC 12 warns when it inlines a std::vector deallocation into this free(): operator new above
// takes its memory from malloc, so free is the matching call.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace sph;

namespace {

using StressCarrying = fixtures::InertStress;

constexpr unsigned kTerms = term::morris_viscosity | term::artificial_viscosity | term::body_force;

RunParameters deck() {
  RunParameters d;
  d.dimension = 2, d.terms = kTerms;
  d.rho0 = 1000.0, d.c0 = 20.0, d.gamma = 7.0, d.v_max = 2.0, d.viscosity = 1e-4, d.alpha = 0.2, d.beta = 0.1;
  d.h = 1.3e-3, d.dx = 1e-3, d.body_force = {0.0, -9.81};
  return d;
}

Particles<2> block(bool wall_points = false) {
  fixtures::Block b;
  b.columns = 40, b.rows = 30, b.seed = 3, b.jitter = 0.1, b.speed = 1.0, b.reserve = true;
  Particles<2> P = fixtures::block(b);
  if (wall_points) fixtures::wall_points_at(P, -0.4e-3);  // the no-slip extrapolated to a wall off the lattice
  return P;
}

// Allocations during 200 steps of dt after `warm_up` steps of sim, and the list builds among them.
template <class Sim>
long allocations_after_warm_up(Sim& sim, int warm_up, double dt, long& builds) {
  for (int s = 0; s < warm_up; ++s) CHECK(sim.step(dt, NoCrossings{}));
  const long before = allocations.load(), builds_before = sim.stage_times().builds;
  armed = true;
  for (int s = 0; s < 200; ++s) CHECK(sim.step(dt, NoCrossings{}));
  armed = false;
  builds = sim.stage_times().builds - builds_before;
  return allocations.load() - before;
}

// The scalar path on the block (optionally with wall points).
template <class Sim>
long allocations_while_stepping(int threads, long& builds, bool wall_points = false) {
  omp_set_num_threads(threads);
  Sim sim(deck(), block(wall_points));
  return allocations_after_warm_up(sim, 40, 2e-6, builds);
}

// The same for a PTT fluid on walls whose solvent is the Morris term (no-slip velocities and
// wall stresses, eq. W1, every evaluation).
long walled_ptt_allocations(int threads, long& builds) {
  omp_set_num_threads(threads);
  constexpr unsigned terms = term::morris_viscosity | term::body_force;
  RunParameters d = deck();
  d.terms = terms;
  MaterialSpec m;
  m.name = "melt", m.model = "ptt", m.rho0 = 1000.0, m.c0 = 20.0, m.solvent_viscosity = 0.1, m.viscosity = 1e-4;
  m.mode_lambda = {1e-3}, m.mode_eta = {0.1};
  d.materials = {m};
  Simulation<2, terms, ModelList<Ptt>> sim(d, block());
  return allocations_after_warm_up(sim, 40, 2e-6, builds);
}

// The same for two PTT modes in a Lees-Edwards cell, particles crossing the sheared faces.
long sheared_ptt_allocations(int threads, long& builds) {
  omp_set_num_threads(threads);
  RunParameters d = fixtures::shear_deck(40, 1.0, 1.0, 5.0, 1.0);
  MaterialSpec m;
  m.name = "melt", m.model = "ptt", m.rho0 = 1.0, m.c0 = 5.0, m.epsilon = 0.1;
  m.mode_lambda = {0.5, 0.05}, m.mode_eta = {0.01, 0.005};
  d.materials = {m};
  Particles<2> start = fixtures::shear_cell(40, 1.0, 1.0, 1.0, 0.1);
  for (std::size_t i = 0; i < start.size(); ++i) start.v[i][1] = 0.02 * ((i % 3) - 1.0);  // some cross the y faces (0.03 m in the run)
  Simulation<2, term::sheared, ModelList<Ptt>> sim(d, start);
  // Warm up over a strain of 1 (the sheared lattice's pair count cycles with the strain; the
  // lists keep room for 1.25 x the largest count seen so far).
  return allocations_after_warm_up(sim, 500, 2e-3, builds);
}

// The same for a Johnson-Cook solid block (plastic, artificial stress and viscosity) on the walls of the block.
long solid_allocations(int threads, long& builds) {
  omp_set_num_threads(threads);
  RunParameters d = deck();
  d.terms = term::artificial_viscosity, d.alpha = 1.0, d.beta = 1.0;
  MaterialSpec m;
  m.name = "steel", m.model = "johnson_cook", m.rho0 = 1000.0;
  m.solid.shear_modulus = 4e5, m.solid.linear = {1000.0, 1e6};
  m.solid.plastic = true, m.solid.strength = {2e3, 1e3, 0.5, 0.01, 1.0};
  m.solid.strength.melting_temperature = 1000.0;
  m.solid.heat = {1000.0, 500.0, 0.9};
  m.solid.artificial_stress = 0.3;
  m.c0 = m.solid.wave_speed();
  d.materials = {m};
  Simulation<2, term::artificial_viscosity, ModelList<JohnsonCook>> sim(d, block());
  return allocations_after_warm_up(sim, 40, 2e-6, builds);
}

}  // namespace

TEST(no_allocation_while_stepping) {
  const int saved = omp_get_max_threads();
  for (int threads : {1, 2}) {
    long builds = 0;
    const long scalar = allocations_while_stepping<Simulation<2, kTerms>>(threads, builds);
    std::fprintf(stderr, "  scalar path, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n", threads, scalar, builds);
    CHECK(scalar == 0 && builds > 0);
    const long walls = allocations_while_stepping<Simulation<2, kTerms>>(threads, builds, true);
    std::fprintf(stderr, "  scalar path with wall points, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n",
                 threads, walls, builds);
    CHECK(walls == 0 && builds > 0);
    const long tensor =
        allocations_while_stepping<Simulation<2, kTerms, ModelList<Newtonian, StressCarrying>>>(threads, builds);
    std::fprintf(stderr, "  tensor path, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n", threads, tensor, builds);
    CHECK(tensor == 0 && builds > 0);
    const long sheared = sheared_ptt_allocations(threads, builds);
    std::fprintf(stderr, "  PTT in a Lees-Edwards cell, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n",
                 threads, sheared, builds);
    CHECK(sheared == 0 && builds > 0);
    const long walled = walled_ptt_allocations(threads, builds);
    std::fprintf(stderr, "  PTT + Morris on walls, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n",
                 threads, walled, builds);
    CHECK(walled == 0 && builds > 0);
    const long solid = solid_allocations(threads, builds);
    std::fprintf(stderr, "  Johnson-Cook solid, %d thread(s): %ld allocations in 200 steps (%ld list builds)\n", threads,
                 solid, builds);
    CHECK(solid == 0 && builds > 0);
  }
  omp_set_num_threads(saved);
}
