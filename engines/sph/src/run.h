// Running a validated deck; returns the process exit code (see run_loop.h).
#pragma once
#include "parameters.h"

namespace sph {
int run_2d(const RunParameters& deck);
int run_3d(const RunParameters& deck);
inline int run_deck(const RunParameters& deck) { return deck.dimension == 2 ? run_2d(deck) : run_3d(deck); }
}  // namespace sph
