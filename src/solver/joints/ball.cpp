// Ball-and-socket: the anchors of A and B coincide (3 rows, solved as a 3x3 block),
// plus optional dry friction against relative spin.
#include "solver/joints/joint_common.hpp"

namespace fulcrum::detail {

void warmStartBall(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    cacheFriction(j, a, b, f.rA, f.rB);
    if (j.frictionValid) {
        applyFriction(j, a, b, f.rA, f.rB, j.impulse.friction);
    } else {
        j.impulse.friction = {};
    }
}

void solveBall(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    // The tree solver has the point rows (JointSolver skips a tree's frictionless ball joints).
    if (j.direct && !j.frictionValid) return;
    const JointFrame& f = currentFrame(j, a, b, ctx);
    solveFrictionBlock(j, a, b, f.rA, f.rB);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, j.impulse.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail
