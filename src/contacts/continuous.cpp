#include "contacts/continuous.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "collision/swept_impact.hpp"
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

// How continuous collision stops a body (collision/swept_impact.hpp): kToiSlop
// short of what it was apart from at the start, so the next step's
// speculative contact sees a gap, once its path goes on 2 kToiSlop into it (a
// body the solver held at the surface, its speculative contact working, goes
// no deeper than the solver's slop and is left where it is); at most a quarter
// of its thinnest half extent deeper than it started in what it touched at
// the start.
ImpactRules impactRules(Real core) {
    ImpactRules rules;
    rules.touchBand = 2 * kToiSlop;
    rules.stopGap = kToiSlop;
    rules.passDepth = 2 * kToiSlop;
    rules.sinkAllowance = std::max(kToiSlop, Real(0.25) * core);
    rules.tolerance = Real(0.1) * kToiSlop;
    // A compound's piece is swept only when it moved as far as a whole body
    // must before it is (sweepBody), its own turn counted: of a toppling
    // tree's 22 pieces those near its foot then stay out of the sweep.
    rules.pieceThickness = coreExtent;
    rules.slowPieceFraction = Real(0.5);
    return rules;
}

bool canSweepAgainst(ShapeType t) { return isConvexShape(t) || t == ShapeType::Compound; }

// Sweeps solver body i (if it is a dynamic body whose points may have moved
// far enough) and puts it back at its first time of impact, in the awake set.
// `bullets`: whether this pass takes the bullets (true) or the other bodies
// (false). Writes only body i's pose; reads the poses of dynamic non-bullets
// (final once their pass is done) and of static bodies.
void sweepBody(BodyStore& w, const JointPairFilter& joints, const BroadPhase& broad, std::uint32_t i, bool bullets,
               bool onlyBulletsMove) {
    const std::uint32_t d = w.denseOfSolver[i];
    const BodyParams& p = w.params[d];
    if (p.type != BodyType::Dynamic || !p.awake || p.isSensor || p.isBullet != bullets) return;
    BodyPose& m = w.pose[i];
    const Vec3 dp = m.com - w.startCom[i];
    const Shape& shape = w.cold[d].shape;
    // Half the core's extent (coreExtent: a compound's local bounds, a loop
    // over its children), formed when a test needs it. It is at most half
    // the body's extent (p.extent, the farthest point of its bounds from the
    // centre of mass, is at least every half side of those bounds, and
    // coreExtent at most the least of them), so a motion beyond that passes
    // the tests below without it: the same results, and 1.8 % of Jolt's
    // HighSpeed step less.
    Real core = 0;
    bool coreFormed = false;
    const auto halfCore = [&] {
        if (!coreFormed) {
            core = coreExtent(shape);
            coreFormed = true;
        }
        return Real(0.5) * core;
    };
    const Real halfExtent = Real(0.5) * p.extent;
    const Quat q0 = w.startQ[i];
    // A body is swept when it may have moved more than half its thinnest half
    // extent. A bullet counts its turn too (a spinning bar's end swings
    // through a thin wall while its centre stays put), bounded cheaply first:
    // no point moved farther than the centre plus the turn (at most
    // pi sin(angle / 2)) times the farthest point. The other bodies count
    // their centre's move only, as before: a tumbling body landing counts as
    // fast by its turn and would be stopped where its rim first touched,
    // changing every such landing for no tunnelling.
    Real turnBound = 0;
    if (p.isBullet) {
        const Real cosHalf = std::min(std::fabs(dot(q0, m.q)), Real(1));
        turnBound = Real(3.14159265) * std::sqrt(1 - cosHalf * cosHalf) * p.extent;
    }
    const Real motion = length(dp) + turnBound;
    if (motion <= halfExtent && motion <= halfCore()) return;
    // The sweep (its rotation vector an atan2) is formed when something needs
    // it: most bullets of Jolt's HighSpeed meet no candidate (2.4 % of its step).
    Sweep sweep;
    bool sweepFormed = false;
    const auto sweepOf = [&]() -> const Sweep& {
        if (!sweepFormed) {
            sweep = sweepBetween(w.startCom[i], q0, m.com, m.q, p.localCom);
            sweepFormed = true;
        }
        return sweep;
    };
    // How far a point of the body's core moved at most: its turn does not
    // move a sphere's surface about its own centre. (Only when the centre
    // alone moved no farther: the sum is never less than length(dp), and
    // the core's reach, a loop over a compound's children, was 1.2 % of Jolt's
    // HighSpeed step, whose bullets move metres.)
    const Real moved = length(dp);
    if (p.isBullet && moved <= halfExtent && moved <= halfCore() && moved + length(sweepOf().angularVelocity) * coreReach(shape, p.localCom) <= halfCore()) return;
    // What the sweep may meet: the box of a ball of the body's extent (its
    // farthest point from the centre of mass) along the centre's path, grown
    // for rounding. Looser than the swept shape's own box (sweptBounds), but
    // each candidate is tested against that box first (sweptImpact), so the
    // looser query changes no result; the tight box for every swept body
    // was 11 % of Jolt's HighSpeed step (5000 tumbling bullets, a few near
    // a wall at a time), for candidates the query finds in a few tree nodes.
    const Vec3 reach = Vec3::splat(p.extent * Real(1 + 1e-5) + impactRules(0).touchBand);
    const AABB swept{min(w.startCom[i], m.com) - reach, max(w.startCom[i], m.com) + reach};
    const std::uint32_t selfSlot = w.denseToSlot[d];
    Real best = 1;
    const auto hit = [&](ProxyId, std::uint32_t otherSlot) {
        if (otherSlot == selfSlot) return true;
        const std::uint32_t od = w.bodySlots[otherSlot].dense;
        const BodyParams& op = w.params[od];
        if (op.isSensor || !shouldCollide(p.filter, op.filter) || !mayCollide(w, joints, selfSlot, otherSlot)) return true;
        const Shape& other = w.cold[od].shape;
        Sweep otherSweep{w.originTransform(od), op.localCom, Vec3::zero(), Vec3::zero()};
        if (op.type == BodyType::Static) {
            // any static shape
        } else if (p.isBullet && op.type == BodyType::Dynamic && !op.isBullet && canSweepAgainst(other.type())) {
            const std::uint32_t oi = w.solverIndexOf(od);
            if (oi != 0) otherSweep = sweepBetween(w.startCom[oi], w.startQ[oi], w.pose[oi].com, w.pose[oi].q, op.localCom);
        } else {
            return true;
        }
        halfCore();
        const SweptImpact r = sweptImpact(shape, sweepOf(), other, otherSweep, impactRules(core), best);
        if (r.hit) best = std::min(best, r.time);
        return true;
    };
    // Only a bullet is swept against moving bodies: the others need the
    // static tree alone (benchmark chain, no static body: the query of the
    // moving tree was 4 % of the step's instructions), and so do the bullets
    // when every moving proxy is an awake bullet (Jolt's HighSpeed: the
    // queries of its moving tree, which give nothing a bullet is swept
    // against, were 7.5 % of the step's instructions).
    if (p.isBullet && !onlyBulletsMove) {
        broad.query(swept, hit);
    } else {
        broad.queryStatic(swept, hit);
    }
    if (best >= 1) return;
    m.com = w.startCom[i] + dp * best;
    m.q = integrateRotation(q0, sweepOf().angularVelocity, best);
    const Mat3 r = toMat3(m.q);
    m.invInertiaWorld = r * p.invLocalInertia * transpose(r);
}

}  // namespace

// Two passes over the awake set, each in parallel. First the bodies that are
// not bullets: each is swept against static bodies only (which nothing here
// moves) and writes only its own pose. Then the bullets, each against static
// bodies and the dynamic non-bullets, whose poses are final after the first
// pass; a bullet is never swept against another bullet, so no bullet reads a
// pose this pass writes. Either pass gives the same result for any thread
// count and any order. (A single serial loop was 31 % of the serial
// instructions of box_pile's first 120 steps, almost all of it the distance
// test of bodies that did not move far.)
void solveContinuous(BodyStore& w, const JointPairFilter& joints, const ContactManager& manager, TaskSystem& tasks, Real) {
    const auto count = static_cast<std::uint32_t>(w.denseOfSolver.size());
    if (count <= 1) return;
    const BroadPhase& broad = manager.broadPhase();
    std::atomic<std::uint32_t> bulletCount{0};
    tasks.parallelFor(count - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        std::uint32_t bullets = 0;
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const BodyParams& p = w.params[w.denseOfSolver[i]];
            if (p.isBullet && p.type == BodyType::Dynamic) ++bullets;
            sweepBody(w, joints, broad, i, false, false);
        }
        if (bullets != 0) bulletCount.fetch_add(bullets, std::memory_order_relaxed);
    });
    const std::uint32_t bullets = bulletCount.load(std::memory_order_relaxed);
    if (bullets == 0) return;
    // Every body, awake or asleep, has one proxy; the static ones are in the static tree.
    const bool onlyBulletsMove = static_cast<std::uint32_t>(broad.movingTree().proxyCount()) == bullets;
    tasks.parallelFor(count - 1, 16, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) sweepBody(w, joints, broad, i, true, onlyBulletsMove);
    });
}

}  // namespace fulcrum::detail
