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
//
// It runs on the body store's awake set (body_store.hpp), before the records
// are written: it reads each body's pose at the step's start (startCom,
// startQ) and its pose now, and moves the pose now.
#include "fulcrum/shape.hpp"
#include "fulcrum/task_system.hpp"
#include "dynamics/body_store.hpp"

namespace fulcrum::detail {

class ContactManager;
struct JointPairFilter;

void solveContinuous(BodyStore& w, const JointPairFilter& joints, const ContactManager& manager, TaskSystem& tasks, Real dt);

// Half the thickness of the thinnest part of a shape (how far it may move
// before it could pass through something thin).
Real coreExtent(const Shape& shape);

}  // namespace fulcrum::detail
