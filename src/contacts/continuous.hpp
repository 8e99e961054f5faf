#pragma once
// Continuous collision (time of impact), run after the sub-steps.
//
// Speculative contacts stop most tunnelling: a pair gets contact points a step
// before it can touch, so the solver removes exactly the approach that would
// close the gap. They miss what the broad phase had no pair for yet, thin
// geometry crossed in one step by a small fast body, and what a fast turn
// brings into contact (the manifold's points are where the bodies met at the
// step's start). So, as in Box2D v3, every dynamic body that moved more than
// half its smallest extent this step (a bullet: any point of it, its turn
// counted) is swept from its pose at the step's start to its end pose (the
// centre on the line between them, the orientation turning at a constant
// rate: collision/swept_impact.hpp):
//   - against static bodies (any static shape);
//   - if it is a bullet, against dynamic non-bullet bodies too (both sweeps;
//     convex shapes and compounds of them).
// A pair apart at the start stops kToiSlop short of touching, if the path goes
// on more than 2 kToiSlop into it (a body its speculative contact held at the
// surface is left alone); a pair touching or overlapping at the start (a
// body sliding along a floor, or put back at a wall last step) stops only
// when a quarter of the body's thinnest half extent deeper than it started:
// it may slide along what it touches, never through it. The body is put back
// on its sweep at the first stop, its velocity kept; next step's speculative
// contact then handles the impact.
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
