// Distance joint between two anchors: a rod (min == max, one rigid-in-the-limit
// equality row), a rope (min 0, max L: one limit row that only pulls, so it
// goes slack), or a soft spring (stiffness / damping, implicit, towards the
// rest length) with its min / max still enforced as limit rows.
#include <limits>

#include "solver/joints/joint_common.hpp"

namespace fulcrum::detail {

namespace {

// Unit direction A -> B and length; a degenerate (coincident) pair has no direction.
bool direction(const JointFrame& f, Vec3& n, Real& len) {
    len = length(f.d);
    if (len < Real(1e-6)) return false;
    n = f.d * (1 / len);
    return true;
}

}  // namespace

void warmStartDistance(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    Vec3 n;
    Real len = 0;
    if (!direction(f, n, len)) return;
    const JointImpulses& i = j.impulse;
    applyPoint(a, b, f.rA, f.rB, n * (i.axial + i.spring + i.lower - i.upper));
}

void solveDistance(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    Vec3 n;
    Real len = 0;
    if (!direction(f, n, len)) return;
    const JointRow row = linearRow(n, f.rA, f.rB);
    JointImpulses& i = j.impulse;
    if (j.rigidDistance) {
        solveEqualityRow(row, a, b, len - j.restLength, i.axial, ctx);
        return;
    }
    if (j.spring) solveSpringRow(row, a, b, len - j.restLength, j.springBias, j.springGamma, i.spring);
    if (j.lower > 0) solveLimitRow(row, a, b, len - j.lower, i.lower, ctx);
    if (j.upper < std::numeric_limits<Real>::infinity()) {
        const JointRow pull{-row.linear, -row.angularA, -row.angularB};
        solveLimitRow(pull, a, b, j.upper - len, i.upper, ctx);
    }
}

}  // namespace fulcrum::detail
