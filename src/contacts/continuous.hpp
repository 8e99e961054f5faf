#pragma once
// Continuous collision (time of impact), run after the sub-steps.
//
// Speculative contacts stop most tunnelling: a pair gets contact points a step
// before it can touch, so the solver removes exactly the approach that would
// close the gap. They miss what the broad phase had no pair for yet and thin
// geometry crossed in one step by a small fast body. So, as in Box2D v3, every
// dynamic body that moved more than half its smallest extent this step is
// swept from its pose at the step's start to its end pose:
//   - against static bodies (shapeCast along its displacement; any static shape);
//   - if it is a bullet, against dynamic non-bullet bodies too (timeOfImpact on
//     both bodies' sweeps; convex shapes).
// The body is put back at the first time of impact (less a small slop) with
// its velocity kept; next step's speculative contact then handles the impact.
// Hits at fraction 0 (already touching at the start) are ignored so a body
// sliding fast along the floor is not stopped.
#include "fulcrum/shape.hpp"

namespace fulcrum {
struct WorldImpl;
}

namespace fulcrum::detail {

class ContactSolver;
class ContactManager;

void solveContinuous(WorldImpl& w, const ContactSolver& solver, const ContactManager& manager, Real dt);

// Half the thickness of the thinnest part of a shape (how far it may move
// before it could pass through something thin).
Real coreExtent(const Shape& shape);

}  // namespace fulcrum::detail
