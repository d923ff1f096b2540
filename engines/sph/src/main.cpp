// sph deck.json: run a weakly compressible SPH simulation described by a JSON deck.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "deck.h"
#include "run.h"
#include "run_loop.h"

namespace {
const char* usage =
    "usage: sph DECK.json     run the simulation described by the deck (see README.md)\n"
    "       sph --version     print the engine version\n"
    "exit codes: 0 ok, 1 failed, 2 input rejected, 3 numerically unstable, 4 stopped by a signal\n";

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && (!std::strcmp(argv[1], "--version") || !std::strcmp(argv[1], "-V"))) {
    std::printf("sph %s\n", SPH_VERSION);
    return 0;
  }
  if (argc == 2 && (!std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h"))) {
    std::fputs(usage, stdout);
    return 0;
  }
  if (argc != 2) {
    std::fputs("error: expected exactly one argument, the deck file (sph DECK.json)\n", stderr);
    std::fputs(usage, stderr);
    return sph::exit_bad_input;
  }
  try {
    const sph::RunParameters deck = sph::load_deck(argv[1]);
    return sph::run_deck(deck);
  } catch (const sph::InputError& e) {
    std::fprintf(stderr, "error: %s\n", one_line(e.what()).c_str());
    return sph::exit_bad_input;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", one_line(e.what()).c_str());
    return sph::exit_failed;
  }
}
