// A resumed run's integrated fields beyond velocity and density (the deviatoric stress of a solid, a PTT fluid's
// per-mode stresses, a solid's scalars) back from the particle file into the particles: the inverse of the frame
// writer (recorder.h), field by field as Particles::for_integrated lists them; a particle finds its row by its id
// (the solver has sorted the particles by cell; an id is its input row, or the file's `ids`).
// Called once the solver has sized the run's fields and set their starting values (a solid at T0), before the
// first step; the rates are evaluated from the restored state as at any start.
#pragma once
#include <cstdint>
#include <string>
#include <type_traits>
#include <unordered_map>

#include "input_h5.h"
#include "parameters.h"
#include "particles.h"

namespace sph {

template <int D>
void restore_fields(Particles<D>& P, const std::vector<std::int64_t>& ids) {
  if (P.saved.empty()) return;
  std::unordered_map<std::int64_t, std::size_t> row_of;
  for (std::size_t r = 0; r < P.size(); ++r) row_of[ids.empty() ? static_cast<std::int64_t>(r) : ids[r]] = r;
  for (const SavedField& saved : P.saved) {
    bool carried = false;
    P.for_integrated([&](auto& f, Integrates) {
      using T = typename std::decay_t<decltype(f.value)>::value_type;
      if constexpr (!std::is_arithmetic_v<T>) {
        if (f.output != saved.name) return;
        const int cols = T::ColsAtCompileTime == Eigen::Dynamic ? P.modes * D * D : int(T::SizeAtCompileTime);
        if (saved.cols != cols)
          throw InputError("dataset '" + saved.name + "' in the particle file has " + std::to_string(saved.cols) +
                           " columns; this run's " + saved.name + " has " + std::to_string(cols));
        carried = true;
        for (std::size_t i = 0; i < P.size(); ++i) {
          const auto found = row_of.find(P.id[i]);
          if (found == row_of.end() || (found->second + 1) * cols > saved.values.size()) continue;  // not from the file
          for (int c = 0; c < cols; ++c) {
            const double x = saved.values[found->second * cols + c];
            if constexpr (T::ColsAtCompileTime == Eigen::Dynamic) f.value[i](c % D * D + c % (D * D) / D, c / (D * D)) = x;
            else if constexpr (T::ColsAtCompileTime == 1) f.value[i](c) = x;
            else f.value[i](c / D, c % D) = x;
          }
        }
      }
    });
    if (!carried)
      throw InputError("the particle file gives '" + saved.name + "', which no material of this run carries");
  }
  P.saved.clear(), P.saved.shrink_to_fit();
}

}  // namespace sph
