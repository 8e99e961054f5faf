#include "contacts/continuous.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "collision/shape_cast.hpp"
#include "fulcrum/task_system.hpp"
#include "contacts/contact_manager.hpp"
#include "solver/joint_data.hpp"

namespace fulcrum::detail {

namespace {

constexpr Real kToiSlop = Real(0.005);  // stop this far before the hit, so the next step sees a speculative gap

bool isConvexShape(ShapeType t) {
    return t == ShapeType::Sphere || t == ShapeType::Box || t == ShapeType::Capsule || t == ShapeType::Cylinder ||
           t == ShapeType::ConvexHull;
}

}  // namespace

Real coreExtent(const Shape& shape) {
    switch (shape.type()) {
        case ShapeType::Sphere:
        case ShapeType::Capsule: return shape.radius();
        case ShapeType::Box: return minComponent(shape.halfExtents());
        case ShapeType::Cylinder: return std::min(shape.radius(), shape.halfHeight());
        default: {
            const AABB b = shape.localBounds();
            return Real(0.5) * minComponent(b.max - b.min) * Real(0.5);
        }
    }
}

namespace {

// Sweeps solver body i (if it is a dynamic body that moved far enough) and
// puts it back at its first time of impact, in the awake set. `bullets`:
// whether this pass takes the bullets (true) or the other bodies (false).
void sweepBody(BodyStore& w, const JointPairFilter& joints, const BroadPhase& broad, Real dt, std::uint32_t i,
               bool bullets) {
    const std::uint32_t d = w.denseOfSolver[i];
    const BodyParams& p = w.params[d];
    if (p.type != BodyType::Dynamic || !p.awake || p.isSensor || p.isBullet != bullets) return;
    BodyPose& m = w.pose[i];
    const Vec3 dp = m.com - w.startCom[i];
    const Shape& shape = w.cold[d].shape;
    const Real core = coreExtent(shape);
    if (lengthSquared(dp) <= Real(0.25) * core * core) return;

    const Quat q0 = w.startQ[i];
    const Transform x0{w.startCom[i] - rotate(q0, p.localCom), q0};
    const Transform x1{m.com - rotate(m.q, p.localCom), m.q};
    const Vec3 translation = x1.p - x0.p;
    const AABB swept = merge(shape.bounds(x0), shape.bounds(x1));
    const std::uint32_t selfSlot = w.denseToSlot[d];
    Real best = 1;
    const auto hit = [&](ProxyId, std::uint32_t otherSlot) {
        if (otherSlot == selfSlot) return true;
        const std::uint32_t od = w.bodySlots[otherSlot].dense;
        const BodyParams& op = w.params[od];
        if (op.isSensor || !shouldCollide(p.filter, op.filter) || !mayCollide(w, joints, selfSlot, otherSlot)) return true;
        const Shape& other = w.cold[od].shape;
        if (op.type == BodyType::Static) {
            const ShapeCastResult r = shapeCast(shape, x0, translation, other, w.originTransform(od));
            if (r.hit && r.fraction > 0 && r.fraction < best) best = r.fraction;
        } else if (p.isBullet && op.type == BodyType::Dynamic && !op.isBullet && isConvexShape(shape.type()) &&
                   isConvexShape(other.type())) {
            const std::uint32_t oi = w.solverIndexOf(od);
            Sweep sa{x0, p.localCom, dp / dt, w.state[i].w};
            Sweep sb{w.originTransform(od), op.localCom, Vec3::zero(), Vec3::zero()};
            if (oi != 0) {
                const Quat oq0 = w.startQ[oi];
                sb.start = {w.startCom[oi] - rotate(oq0, op.localCom), oq0};
                sb.linearVelocity = (w.pose[oi].com - w.startCom[oi]) / dt;
                sb.angularVelocity = w.state[oi].w;
            }
            const ToiResult r = timeOfImpact(shape, sa, other, sb, dt);
            if (r.state == ToiResult::State::Hit && r.time > 0 && r.time / dt < best) best = r.time / dt;
        }
        return true;
    };
    // Only a bullet is swept against moving bodies: the others need the
    // static tree alone (benchmark chain, no static body: the query of the
    // moving tree was 4 % of the step's instructions).
    if (p.isBullet) {
        broad.query(swept, hit);
    } else {
        broad.queryStatic(swept, hit);
    }
    if (best >= 1) return;
    // A body the solver already stopped at the surface (the speculative
    // contact worked) hits at the very end of its path: leave it there.
    const Real travel = length(translation);
    if ((1 - best) * travel < 2 * kToiSlop) return;
    const Real back = kToiSlop / travel;
    const Real t = std::max(Real(0), best - back);
    m.com = w.startCom[i] + dp * t;
    m.q = normalize(slerp(q0, m.q, t));
    const Mat3 r = toMat3(m.q);
    m.invInertiaWorld = r * p.invLocalInertia * transpose(r);
}

}  // namespace

// The bodies that are not bullets in parallel: each is swept against static
// bodies only (which nothing here moves) and writes only its own state, so
// the result is the same for any thread count. Then the bullets, which read
// the dynamic bodies' final poses, on this thread in solver order (after every
// other body's put-back, whatever the thread count). The single serial loop
// was 31 % of the serial instructions of box_pile's first 120 steps (39 M of
// 127 M, callgrind), almost all of it the distance test of bodies that did
// not move far.
void solveContinuous(BodyStore& w, const JointPairFilter& joints, const ContactManager& manager, TaskSystem& tasks, Real dt) {
    const auto count = static_cast<std::uint32_t>(w.denseOfSolver.size());
    if (count <= 1) return;
    const BroadPhase& broad = manager.broadPhase();
    std::atomic<bool> anyBullet{false};
    tasks.parallelFor(count - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        bool bullet = false;
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            bullet = bullet || w.params[w.denseOfSolver[i]].isBullet;
            sweepBody(w, joints, broad, dt, i, false);
        }
        if (bullet) anyBullet.store(true, std::memory_order_relaxed);
    });
    if (!anyBullet.load(std::memory_order_relaxed)) return;
    for (std::uint32_t i = 1; i < count; ++i) sweepBody(w, joints, broad, dt, i, true);
}

}  // namespace fulcrum::detail
