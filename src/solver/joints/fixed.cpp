// Fixed (weld): the anchors coincide and B keeps its rest orientation relative
// to A (3 linear + 3 angular rows, two 3x3 blocks). The angular block goes
// first so the point block, solved last, has the final word on the anchors,
// the error users see.
#include "solver/joints/joint_common.hpp"

namespace fulcrum::detail {

void warmStartFixed(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    if (!j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    applyPoint(a, b, f.rA, f.rB, j.impulse.linear);
    a.w -= a.invI * j.impulse.angular;
    b.w += b.invI * j.impulse.angular;
}

void solveFixed(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    solveAngularBlock(a, b, angularError(j, f.qA, f.qB), j.impulse.angular, ctx);
    if (!j.direct && j.pointMassValid) solvePointBlock(a, b, f.rA, f.rB, f.d, j.impulse.linear, ctx, j.pointMass);
}

}  // namespace fulcrum::detail
