// Six degrees of freedom: every linear and angular axis of the joint frame
// free, limited or locked, each with a motor and a spring.
//
// Coordinates. The joint frame is fixed in A (localFrameA) and, through the
// rest pose, in B: at creation the two coincide. The linear coordinates are
// B's anchor from A's along A's frame axes (the slider's rows: they act at
// B's anchor and on A at the point under it, lever rA + d, exact for any
// separation). The angles are B's frame against A's as intrinsic x-y-z Euler
// angles, R = Rx(a) Ry(b) Rz(c): each axis has its own angle with its own
// range, which a swing-twist split (one cone for two axes) would not give,
// and a planar or hinge-like joint locks angles that stay at 0, far from
// the decomposition's one singularity.
//
// Rates. The relative spin is w = a' g1 + b' g2 + c' g3 over the gimbal
// axes g1 = A's x, g2 = the turned y = (zB x xA) / |zB x xA|, g3 = B's z. The
// rows' axes are their dual basis (dot(d_i, g_j) = delta_ij): d2 = g2,
// d1 = (g2 x g3) / cos b, d3 = (g1 x g2) / cos b, so dot(d_i, w) is exactly
// the i-th angle's rate, and a torque's share along g_i is the effort of
// angle i (its power).
//
// Singularity. At b = +-pi/2 (A's x parallel to B's z: gimbal lock) a and c
// are not separately defined. A limited y angle must stay within
// (-pi/2, pi/2) (setup checks), the rows divide by cos b clamped at
// kMinCosine (near the lock the x and z rows weaken instead of blowing up),
// and at the lock itself g2 falls back to B's y axis and the read-out puts
// the whole turn into a (c = 0).
//
// Rows, in order: drives (spring, motor) and limits of the angular axes, the
// angular locks (one 3x3 block when all three are locked, as the fixed
// joint), then the linear axes' drives, limits and locks; when all three
// linear axes are locked the anchors meet and their point block is solved
// last (or by the tree solver: pointBlock). A limited axis has one signed
// impulse: the lower limit's row while its position is nearer the lower
// bound, the upper's otherwise (the impulse of the other side is dropped
// when it switches, which only happens when the axis is far from both).
#include "solver/joints/six_dof.hpp"

#include "solver/joints/coupled_row.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace fulcrum::detail {

namespace {

constexpr Real kMinCosine = Real(1e-3);
constexpr const char* kAxisNames[kSixDofAxes] = {"x", "y", "z", "rx", "ry", "rz"};

std::string axisField(int axis, const char* field) { return std::string("axes[") + kAxisNames[axis] + "]." + field; }

// The rows that hold the joint's locked directions now: the point block's
// three (all linear axes locked) or each locked linear axis's, the angular
// block's three (all angles locked) or each locked angle's. At most 5 when
// some axis is not locked (the only time they are asked for).
struct HeldRows {
    JointRow rows[kMaxHeldRows];
    int count = 0;
};

HeldRows heldRows(const JointConstraint& j, const SixDofAxes& axes, const SixDofGeometry& g, const JointFrame& f) {
    HeldRows h;
    const auto add = [&](const JointRow& r) {
        if (h.count < kMaxHeldRows) h.rows[h.count++] = r;
    };
    const Vec3 leverA = f.rA + f.d;
    for (std::size_t k = 0; k < 3; ++k) {
        Vec3 e;
        e[k] = 1;
        if (j.pointLocked) {
            add(linearRow(e, f.rA, f.rB));
        } else if (axes[k].mode == AxisMode::Locked) {
            add(linearRow(g.linearAxis[k], leverA, f.rB));
        }
    }
    for (std::size_t k = 0; k < 3; ++k) {
        Vec3 e;
        e[k] = 1;
        if (j.rotationLocked) {
            add(angularRow(e));
        } else if (axes[3 + k].mode == AxisMode::Locked) {
            add(angularRow(g.angularRow[k]));
        }
    }
    return h;
}

// The row of axis k (0-2 linear, 3-5 angular).
JointRow axisRow(std::size_t k, const SixDofGeometry& g, const JointFrame& f) {
    return k < 3 ? linearRow(g.linearAxis[k], f.rA + f.d, f.rB) : angularRow(g.angularRow[k - 3]);
}

// A free or limited axis's row solved with the held rows' share
// (coupled_row.hpp: the hinge's and slider's free-axis rows): a lever's
// limit, motor and spring see its inertia about the joint, not about its
// centre (with the free body's, a ball on a lever swung 0.14 rad through an
// angle limit).
CoupledRow coupledAxisRow(const SolverBody& a, const SolverBody& b, const HeldRows& held, const JointRow& measure) {
    CoupledRow r;
    r.measure = measure;
    coupleRow(a, b, held.rows, held.count, measure, r.apply, r.invMass);  // false: the plain row
    return r;
}

bool hasAxisRows(const SixDofAxis& s) {
    return s.mode != AxisMode::Free || s.motor.enabled || (s.spring.enabled && (s.spring.stiffness > 0 || s.spring.damping > 0));
}

// The limit row of a limited axis (position x in [lower, upper]) with its signed impulse.
void solveAxisLimit(const CoupledRow& row, SolverBody& a, SolverBody& b, Real x, Real lower, Real upper, Real& lambda,
                    const JointContext& ctx) {
    const bool lowerSide = x - lower <= upper - x;
    if (lowerSide ? lambda < 0 : lambda > 0) {  // the other side's impulse: dropped
        applyRow(row.apply, a, b, -lambda);
        lambda = 0;
    }
    if (lowerSide) {
        solveCoupledLimit(row, 1, a, b, x - lower, lambda, ctx);
        return;
    }
    Real up = -lambda;
    solveCoupledLimit(row, -1, a, b, upper - x, up, ctx);
    lambda = -up;
}

// A free or limited axis's spring, motor and limit, in that order (the limit wins).
void solveAxis(const SixDofAxis& s, const CoupledRow& row, SolverBody& a, SolverBody& b, Real x, Real& limit, Real& motor,
               Real& spring, const JointContext& ctx) {
    if (s.spring.enabled && (s.spring.stiffness > 0 || s.spring.damping > 0)) {
        Real bias = 0, gamma = 0;
        springCoefficients(s.spring.stiffness, s.spring.damping, ctx.h, bias, gamma);
        solveCoupledSpring(row, a, b, x - s.spring.target, bias, gamma, ctx.h * s.spring.maxForce, spring);
    }
    if (s.motor.enabled) solveCoupledMotor(row, a, b, s.motor.speed, ctx.h * s.motor.maxForce, motor);
    if (s.mode == AxisMode::Limited) solveAxisLimit(row, a, b, x, s.lower, s.upper, limit, ctx);
}

// Axis k's accumulated impulses: its lock or limit, motor and spring.
Real axisImpulse(const JointImpulses& i, std::size_t k) {
    const std::size_t c = k % 3;
    return k < 3 ? i.linear[c] + i.axisMotorLinear[c] + i.axisSpringLinear[c]
                 : i.angular[c] + i.axisMotorAngular[c] + i.axisSpringAngular[c];
}

// f(row, impulse) for every per-axis row with its accumulated impulse (the
// coupled row for a free or limited axis), then the blocks' world impulses
// as (linear, angular) on B: what the warm start applies and the reaction sums.
template <class RowFn, class BlockFn>
void forEachImpulse(const JointConstraint& j, const SolverBody& a, const SolverBody& b, const SixDofGeometry& g,
                    const JointFrame& f, RowFn&& row, BlockFn&& block) {
    const SixDofAxes& axes = j.record->axes;
    const HeldRows held = heldRows(j, axes, g, f);
    for (std::size_t k = 0; k < kSixDofAxes; ++k) {
        if (k < 3 ? j.pointLocked : j.rotationLocked) continue;
        const SixDofAxis& s = axes[k];
        if (!hasAxisRows(s)) continue;
        const JointRow measure = axisRow(k, g, f);
        const Real impulse = axisImpulse(j.impulse, k);
        if (s.mode == AxisMode::Locked) {
            row(measure, impulse);
        } else {
            row(coupledAxisRow(a, b, held, measure).apply, impulse);
        }
    }
    block(j.pointLocked ? j.impulse.linear : Vec3{}, j.rotationLocked ? j.impulse.angular : Vec3{});
}

SixDofGeometry geometryOf(const JointConstraint& j, const JointFrame& f) {
    return sixDofGeometry(f.qA, f.qB, j.relative0, j.localFrameA, f.d);
}

}  // namespace

SixDofGeometry sixDofGeometry(const Quat& qA, const Quat& qB, const Quat& relative0, const Quat& localFrameA, const Vec3& d) {
    SixDofGeometry g;
    const Quat frameA = qA * localFrameA;
    const Quat frameB = qB * conjugate(relative0) * localFrameA;
    for (std::size_t k = 0; k < 3; ++k) {
        Vec3 e;
        e[k] = 1;
        g.linearAxis[k] = rotate(frameA, e);
        g.linear[k] = dot(d, g.linearAxis[k]);
    }
    // B's frame in A's, R = Rx(a) Ry(b) Rz(c), as a matrix's entries.
    const Quat r = conjugate(frameA) * frameB;
    const Real m00 = 1 - 2 * (r.y * r.y + r.z * r.z), m01 = 2 * (r.x * r.y - r.w * r.z), m02 = 2 * (r.x * r.z + r.w * r.y);
    const Real m12 = 2 * (r.y * r.z - r.w * r.x), m22 = 1 - 2 * (r.x * r.x + r.y * r.y);
    const Real cosB = std::sqrt(m00 * m00 + m01 * m01);
    g.angle[1] = dmath::atan2(m02, cosB);
    if (cosB > Real(1e-6)) {
        g.angle[0] = dmath::atan2(-m12, m22);
        g.angle[2] = dmath::atan2(-m01, m00);
    } else {
        // Gimbal lock: a and c turn about the same axis (m10, m11 are the sin
        // and cos of a + c at b = pi/2, of c - a at -pi/2); all of it is read as a.
        const Real m10 = 2 * (r.x * r.y + r.w * r.z), m11 = 1 - 2 * (r.x * r.x + r.z * r.z);
        const Real turn = dmath::atan2(m10, m11);
        g.angle[0] = m02 > 0 ? turn : -turn;
        g.angle[2] = 0;
    }
    const Vec3 xA = g.linearAxis[0];
    const Vec3 zB = rotate(frameB, Vec3{0, 0, 1});
    Vec3 y = cross(zB, xA);
    const Real len = length(y);
    y = len > Real(1e-6) ? y * (1 / len) : rotate(frameB, Vec3{0, 1, 0});
    g.gimbal[0] = xA;
    g.gimbal[1] = y;
    g.gimbal[2] = zB;
    const Real c = cosB > kMinCosine ? cosB : kMinCosine;
    g.angularRow[0] = cross(y, zB) * (1 / c);
    g.angularRow[1] = y;
    g.angularRow[2] = cross(xA, y) * (1 / c);
    return g;
}

// ---- definition

SixDofJointDef SixDofJoint::fromJointDef(const JointDef& def, const JointEnds& ends) {
    SixDofJointDef d;
    static_cast<JointDefBase&>(d) = baseOf(def);
    d.localAnchorA = ends.a.localPoint(def.anchor);
    d.localAnchorB = ends.b.localPoint(def.anchor);
    const Subject who{"joint", def.name};
    const Vec3 x = requireDirection(who, "axis", def.axis);
    requireFinite(who, "axisY", def.axisY);
    // y: axisY made perpendicular to x; without one (or along x), world y
    // (world z when x is near y), so the default frame is the world's.
    Vec3 y = def.axisY - x * dot(def.axisY, x);
    if (!(length(y) > Real(1e-6))) {
        const Vec3 fallback = std::abs(x.y) < Real(0.9) ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
        y = fallback - x * dot(fallback, x);
    }
    y = normalize(y);
    const Quat frame = Quat::fromMatrix(Mat3(x, y, cross(x, y)));
    d.localFrameA = ends.a.world ? frame : conjugate(ends.a.q) * frame;
    d.axes = def.axes;
    return d;
}

void SixDofJoint::validateAxis(const Subject& who, int axis, const SixDofAxis& s) {
    constexpr Real kPi = std::numbers::pi_v<Real>;
    if (s.mode != AxisMode::Free && s.mode != AxisMode::Limited && s.mode != AxisMode::Locked) {
        fail(who, axisField(axis, "mode"), "is not free, limited or locked");
    }
    requireFinite(who, axisField(axis, "lower"), s.lower);
    requireFinite(who, axisField(axis, "upper"), s.upper);
    if (s.mode == AxisMode::Limited) {
        if (s.lower > s.upper) {
            fail(who, axisField(axis, "lower"), "(" + formatReal(s.lower) + ") is above upper (" + formatReal(s.upper) + ")");
        }
        const Real bound = axis == kAxisRotY ? kPi / 2 : kPi;
        if (axis >= kAxisRotX && (s.lower < -bound || s.upper > bound || (axis == kAxisRotY && (s.lower <= -bound || s.upper >= bound)))) {
            fail(who, axisField(axis, s.lower < -bound || (axis == kAxisRotY && s.lower <= -bound) ? "lower" : "upper"),
                 std::string("must be within ") + (axis == kAxisRotY ? "(-pi/2, pi/2)" : "[-pi, pi]") +
                     " radians for the " + kAxisNames[axis] + " angle, got [" + formatReal(s.lower) + ", " +
                     formatReal(s.upper) + "]");
        }
    }
    requireFinite(who, axisField(axis, "motor.speed"), s.motor.speed);
    requireNonNegative(who, axisField(axis, "motor.maxForce"), s.motor.maxForce);
    requireFinite(who, axisField(axis, "spring.target"), s.spring.target);
    requireNonNegative(who, axisField(axis, "spring.stiffness"), s.spring.stiffness);
    requireNonNegative(who, axisField(axis, "spring.damping"), s.spring.damping);
    requireForceLimit(who, axisField(axis, "spring.maxForce"), s.spring.maxForce);
}

JointSetup SixDofJoint::setup(const Def& def, const Subject& who, const JointEnds& ends) {
    requireFinite(who, "localAnchorA", def.localAnchorA);
    requireFinite(who, "localAnchorB", def.localAnchorB);
    requireFinite(who, "localFrameA", def.localFrameA);
    const Real n = length(def.localFrameA);
    if (!(std::abs(n - 1) <= Real(1e-4))) {
        fail(who, "localFrameA", "must be a unit quaternion, got length " + formatReal(n));
    }
    for (int k = 0; k < kSixDofAxes; ++k) validateAxis(who, k, def.axes[static_cast<std::size_t>(k)]);
    JointSetup s;
    s.record = baseRecord(def, kType);
    setPointAnchors(s, ends, def.localAnchorA, def.localAnchorB);
    const Quat frame = normalize(def.localFrameA);
    s.localFrameA = frame;
    const Quat world = ends.a.world ? frame : ends.a.q * frame;
    s.localAxisA = rotate(frame, Vec3{1, 0, 0});
    s.localAxisB = ends.b.localAxis(rotate(world, Vec3{1, 0, 0}));
    s.record.axis = rotate(world, Vec3{1, 0, 0});
    s.record.axisY = rotate(world, Vec3{0, 1, 0});
    s.record.axes = def.axes;
    return s;
}

// ---- solver

void SixDofJoint::warmStart(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const SixDofGeometry g = geometryOf(j, f);
    if (j.pointLocked && !j.direct) cachePointMass(j, a, b, f.rA, f.rB);
    // The rows' directions from the bodies before any impulse (as the solve's
    // coupled rows would see them), applied after.
    JointRow rows[kSixDofAxes];
    Real impulses[kSixDofAxes];
    int n = 0;
    Vec3 P, T;
    forEachImpulse(
        j, a, b, g, f,
        [&](const JointRow& r, Real impulse) {
            rows[n] = r;
            impulses[n++] = impulse;
        },
        [&](const Vec3& linear, const Vec3& angular) {
            P = linear;
            T = angular;
        });
    for (int k = 0; k < n; ++k) applyRow(rows[k], a, b, impulses[k]);
    applyPoint(a, b, f.rA, f.rB, P);
    a.w -= a.invI * T;
    b.w += b.invI * T;
}

void SixDofJoint::solve(JointConstraint& j, SolverBody& a, SolverBody& b, const JointContext& ctx) {
    const JointFrame& f = currentFrame(j, a, b, ctx);
    const SixDofGeometry g = geometryOf(j, f);
    JointImpulses& i = j.impulse;
    const SixDofAxes& axes = j.record->axes;
    const HeldRows held = heldRows(j, axes, g, f);
    // Free and limited axes first (drives, then limits), the locks after: they carry the joint's error.
    for (std::size_t k = 0; k < kSixDofAxes; ++k) {
        const SixDofAxis& s = axes[k];
        if (s.mode == AxisMode::Locked || !hasAxisRows(s)) continue;
        const std::size_t c = k % 3;
        const CoupledRow row = coupledAxisRow(a, b, held, axisRow(k, g, f));
        if (k < 3) {
            solveAxis(s, row, a, b, g.linear[c], i.linear[c], i.axisMotorLinear[c], i.axisSpringLinear[c], ctx);
        } else {
            solveAxis(s, row, a, b, g.angle[c], i.angular[c], i.axisMotorAngular[c], i.axisSpringAngular[c], ctx);
        }
    }
    if (j.rotationLocked) {
        solveAngularBlock(a, b, angularError(j, f.qA, f.qB), i.angular, ctx);
    } else {
        for (std::size_t c = 0; c < 3; ++c) {
            if (axes[3 + c].mode == AxisMode::Locked) solveEqualityRow(angularRow(g.angularRow[c]), a, b, g.angle[c], i.angular[c], ctx);
        }
    }
    if (!j.pointLocked) {
        for (std::size_t c = 0; c < 3; ++c) {
            if (axes[c].mode == AxisMode::Locked) solveEqualityRow(axisRow(c, g, f), a, b, g.linear[c], i.linear[c], ctx);
        }
    } else if (!j.direct && j.pointMassValid) {
        solvePointBlock(a, b, f.rA, f.rB, f.d, i.linear, ctx, j.pointMass);
    }
}

void SixDofJoint::addReaction(const JointConstraint& j, const SolverBody& a, const SolverBody& b, Vec3& force, Vec3& torque) {
    // Every row's impulse on B (the coupled rows with their held rows'
    // share), as force and torque about B's centre; then about B's anchor.
    // jointReaction starts from `linear` as a world impulse, which only the
    // point block's is: replaced.
    const SixDofGeometry g = geometryOf(j, j.frame);
    Vec3 F, Tcom;
    forEachImpulse(
        j, a, b, g, j.frame,
        [&](const JointRow& r, Real impulse) {
            F += r.linear * impulse;
            Tcom += r.angularB * impulse;
        },
        [&](const Vec3& linear, const Vec3& angular) {
            F += linear;
            Tcom += cross(j.frame.rB, linear) + angular;
        });
    force = F;
    torque += Tcom - cross(j.frame.rB, F);
}

Real SixDofJoint::error(const JointPose& pose) {
    // The locked linear axes' separation and the limited ones' overshoot (m).
    const SixDofGeometry g =
        sixDofGeometry(pose.orientationA(), *pose.qB, *pose.relativeRotation, *pose.localFrameA, pose.d);
    Real e2 = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        const SixDofAxis& s = (*pose.sixDofAxes)[k];
        Real e = 0;
        if (s.mode == AxisMode::Locked) e = g.linear[k];
        if (s.mode == AxisMode::Limited) e = g.linear[k] < s.lower ? s.lower - g.linear[k] : (g.linear[k] > s.upper ? g.linear[k] - s.upper : 0);
        e2 += e * e;
    }
    return std::sqrt(e2);
}

}  // namespace fulcrum::detail

namespace fulcrum {

SixDofJointDef SixDofJointDef::fromWorld(const World& world, BodyId a, BodyId b, Vec3 anchor, Vec3 axis, Vec3 axisY) {
    const detail::JointEnds ends = detail::jointEnds(world, a, b, "SixDofJointDef::fromWorld");
    JointDef def;
    def.bodyA = a;
    def.bodyB = b;
    def.anchor = anchor;
    def.axis = detail::worldAxisArgument(axis, "SixDofJointDef::fromWorld");
    def.axisY = axisY;
    SixDofJointDef d = detail::SixDofJoint::fromJointDef(def, ends);
    return d;
}

}  // namespace fulcrum
