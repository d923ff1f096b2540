// Running a validated deck; returns the process exit code (see run_loop.h).
#pragma once
#include "deck.h"

namespace sph {
int run_2d(const Deck& deck);
int run_3d(const Deck& deck);
inline int run_deck(const Deck& deck) { return deck.dimension == 2 ? run_2d(deck) : run_3d(deck); }
}  // namespace sph
