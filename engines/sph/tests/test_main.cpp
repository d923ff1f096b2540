// sph_tests [FILTER...]: run the tests whose name or source file contains a filter (all without one).
#include <cstdio>
#include <string>

#include "check.h"
#include "test_files.h"

int main(int argc, char** argv) {
  int failed_cases = 0, ran = 0;
  for (const auto& c : check::registry()) {
    bool selected = argc < 2;
    for (int i = 1; i < argc; ++i)
      selected = selected || std::string(c.name).find(argv[i]) != std::string::npos ||
                 std::string(c.file).find(argv[i]) != std::string::npos;
    if (!selected) continue;
    const int before = check::failures();
    std::fprintf(stderr, "[ RUN  ] %s\n", c.name);
    c.fn();
    const bool ok = check::failures() == before;
    failed_cases += !ok;
    ++ran;
    std::fprintf(stderr, "[ %s ] %s\n", ok ? " OK " : "FAIL", c.name);
  }
  std::fprintf(stderr, "%d tests, %d failed\n", ran, failed_cases);
  std::error_code ignored;
  if (!failed_cases) std::filesystem::remove_all(testfiles::scratch_root(), ignored);  // keep files of failures
  return failed_cases || ran == 0 ? 1 : 0;
}
