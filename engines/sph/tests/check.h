// A tiny test harness: TEST(name) { CHECK(...); CHECK_CLOSE(a, b, tol); }
#pragma once
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace check {

struct Case {
  const char* name;
  const char* file;
  void (*fn)();
};
inline std::vector<Case>& registry() {
  static std::vector<Case> cases;
  return cases;
}
inline int& failures() {
  static int n = 0;
  return n;
}
struct Register {
  Register(const char* name, const char* file, void (*fn)()) { registry().push_back({name, file, fn}); }
};
inline void fail(const char* file, int line, const std::string& what) {
  ++failures();
  std::fprintf(stderr, "  FAILED %s:%d: %s\n", file, line, what.c_str());
}
inline std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}
inline bool close(double a, double b, double rel, double abs_tol = 0.0) {
  return std::abs(a - b) <= std::max(abs_tol, rel * std::max(std::abs(a), std::abs(b)));
}

}  // namespace check

#define TEST(name)                                           \
  static void name();                                        \
  static const check::Register register_##name(#name, __FILE__, name); \
  static void name()

#define CHECK(cond) \
  do {              \
    if (!(cond)) check::fail(__FILE__, __LINE__, #cond); \
  } while (0)

// |a - b| <= rel * max(|a|, |b|) (or <= abs_tol when that is larger)
#define CHECK_CLOSE(a, b, rel, ...)                                                                     \
  do {                                                                                                  \
    const double check_a_ = (a), check_b_ = (b);                                                        \
    if (!check::close(check_a_, check_b_, rel, ##__VA_ARGS__))                                          \
      check::fail(__FILE__, __LINE__,                                                                   \
                  std::string(#a " = ") + check::num(check_a_) + " vs " #b " = " + check::num(check_b_) + \
                      " (rel tol " + check::num(rel) + ")");                                        \
  } while (0)
