// The forces on a moving particle from outside the pair terms, added in close_rates: the body force, the penalty
// walls (wall_penalty.h, eq. 14) and the rigid impactors (impactors.h, eq. I1), each only when the deck has it.
#pragma once
#include <utility>

#include "box_policy.h"
#include "impactors.h"
#include "parameters.h"
#include "physics_terms.h"
#include "wall_penalty.h"

namespace sph {

template <int D>
class ExternalForces {
 public:
  ExternalForces(const RunParameters& deck, WallPenalty<D> walls)
      : walls_(std::move(walls)), impactors_(deck.impactors, deck.dx),
        body_on_(deck.terms & term::body_force), body_solids_(deck.body_force_solids),
        walls_on_(deck.terms & term::wall_penalty) {
    if (!deck.body_force.empty())
      for (int d = 0; d < D; ++d) body_.g[d] = deck.body_force[d];
  }

  const WallPenalty<D>& walls() const { return walls_; }
  Impactors<D>& impactors() { return impactors_; }
  const Impactors<D>& impactors() const { return impactors_; }

  // The acceleration (m/s^2) of a moving particle of mass m (kg) at x (m; wrapped into the box by `images` for
  // the walls: between list builds positions may lie up to skin/2 outside it) added to acc; a solid's particle
  // (solid true) takes the body force unless the deck's body_force_solids is false.
  template <class Images>
  void add(const Images& images, const Vec<D>& x, double m, bool solid, Vec<D>& acc) const {
    if (body_on_ && (body_solids_ || !solid)) body_.add(acc);
    if (walls_on_) {
      Vec<D> xw = x;
      images.wrap(xw);
      acc += walls_.force(xw) / m;
    }
    if (!impactors_.empty()) acc += impactors_.force(x) / m;
  }

 private:
  BodyForce<D> body_;
  WallPenalty<D> walls_;
  Impactors<D> impactors_;
  bool body_on_ = false, body_solids_ = true, walls_on_ = false;
};

}  // namespace sph
