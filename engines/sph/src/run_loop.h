// A run: the deck's configuration chosen from the closed list, its inputs read, its time loop (time_loop.h) run.
#pragma once
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "configurations.h"
#include "open_boundaries.h"
#include "output_h5.h"
#include "recorder.h"
#include "restore_fields.h"
#include "setup.h"
#include "simulation.h"
#include "time_loop.h"

namespace sph {

// Run the deck's particles, walls and open boundaries with the solver of one configuration (Terms, Models).
template <int D, unsigned Terms, class Models>
int run_simulation(const RunParameters& deck, Particles<D> particles, WallPenalty<D> walls, OpenBoundaries<D> open) {
  const std::vector<std::int64_t> input_ids = particles.id;  // in the particle file's row order
  using Sim = Simulation<D, Terms, Models>;
  const auto started = TimeLoop<D, Sim>::Clock::now();
  std::int64_t next_id = 0;
  for (auto id : particles.id) next_id = std::max(next_id, id + 1);
  Sim sim(deck, std::move(particles), std::move(walls));
  restore_fields(sim.particles(), input_ids);  // a resumed run's stresses and solid scalars (restore_fields.h)
  OutputFile out(deck.output_file);
  Recorder<D, Sim> rec(deck, sim, open, out);
  std::signal(SIGTERM, request_stop);
  std::signal(SIGINT, request_stop);
  TimeLoop<D, Sim> loop(deck, sim, rec, open, next_id, started);
  const int code = loop.run();
  loop.write_summary(out);
  out.flush();
  if (code == exit_unstable) std::fprintf(stderr, "error: numerically %s\n", loop.message().c_str());
  return code;
}

// The pair terms and the material models of a deck, as the closed list of
// configurations (configurations.h) names them.
struct Wanted {
  unsigned terms;                   // pair terms (| several_materials)
  std::vector<std::string> models;  // distinct model names of the deck's materials
};
inline Wanted wanted_by(const RunParameters& deck) {
  Wanted w{deck.terms & term::pair_terms, {}};
  const auto materials = deck.material_list();
  for (const auto& m : materials)
    if (std::find(w.models.begin(), w.models.end(), m.model) == w.models.end()) w.models.push_back(m.model);
  if (materials.size() > 1 && (w.terms & term::morris_viscosity)) w.terms |= term::several_materials;
  if (deck.lees_edwards.on) w.terms |= term::sheared;
  if (deck.viscosity_correction) w.terms |= term::viscosity_correction;
  if (deck.smagorinsky_cs > 0) w.terms |= term::eddy_viscosity;
  if (!deck.grains.empty()) w.terms |= term::grains;
  for (const auto& m : materials)
    if (m.stress_diffusion > 0) w.terms |= term::stress_diffusion;
  return w;
}
template <class Models>
bool same_models(const std::vector<std::string>& names) {
  if (static_cast<int>(names.size()) != Models::size) return false;
  for (const auto& n : names)
    if (Models::index(n) < 0) return false;
  return true;
}

// Run the configuration of the closed list that matches the deck exactly.
template <int D, std::size_t I = 0>
int dispatch(const Wanted& w, const RunParameters& deck, Particles<D> P, WallPenalty<D> walls, OpenBoundaries<D> open) {
  if constexpr (I == std::tuple_size_v<Configurations>) {
    std::string models;
    for (const auto& m : w.models) models += (models.empty() ? "" : ", ") + m;
    throw InputError("no compiled configuration runs materials of model(s) " + models + " with physics '" +
                     deck.terms_string() + "'; add one to src/configurations.h");
  } else {
    using C = std::tuple_element_t<I, Configurations>;
    if (C::terms == w.terms && same_models<typename C::models>(w.models))
      return run_simulation<D, C::terms, typename C::models>(deck, std::move(P), std::move(walls), std::move(open));
    return dispatch<D, I + 1>(w, deck, std::move(P), std::move(walls), std::move(open));
  }
}

// Read the inputs of a deck of dimension D and run it.
template <int D>
int run_dimension(const RunParameters& deck) {
  if (deck.threads > 0) omp_set_num_threads(deck.threads);
  configure_parallel();
  const ParticleInput in = read_particles(deck.particles_file, D);
  OpenBoundaries<D> open(deck);
  Particles<D> P = make_particles<D>(deck, in, open.extra_capacity(deck.t_end - deck.t_start));
  if (in.has_buffers) {  // a resumed run: its frame holds the buffers as they were
    for (std::size_t i = 0; i < in.n; ++i)
      if ((in.kind[i] == 2 && deck.inlets.empty()) || (in.kind[i] == 3 && deck.outlets.empty()))
        throw InputError("particle " + std::to_string(i) + " is an " + (in.kind[i] == 2 ? "inlet" : "outlet") +
                         " particle (kind " + std::to_string(in.kind[i]) + ") but the deck has no " +
                         (in.kind[i] == 2 ? "inlets" : "outlets"));
    open.start_at(deck.t_start);
  } else {
    open.fill(P, static_cast<std::int64_t>(in.n));
  }
  open.classify_initial(P);
  WallPenalty<D> walls = make_walls<D>(deck);
  return dispatch<D>(wanted_by(deck), deck, std::move(P), std::move(walls), std::move(open));
}

}  // namespace sph
