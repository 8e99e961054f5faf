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
constexpr Real kTouchBand = 2 * kToiSlop;  // closer than this at the start counts as touching (impactRules)

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
    rules.touchBand = kTouchBand;
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

// Whether two bodies moving over the step (centres on straight lines from
// c0 by d, every point within `reach` of its centre) can come within `gap`
// of each other: the closest approach of the centres' relative path against
// the sum of the reaches. A pair it rules out never comes within the touch
// band, so its sweep could give no stop; it spares a bullet the swept boxes
// and the first distance of a non-bullet whose path passes metres away.
bool pathsMayMeet(const Vec3& a0, const Vec3& da, Real reachA, const Vec3& b0, const Vec3& db, Real reachB, Real gap) {
    const Vec3 d0 = a0 - b0, dv = da - db;
    const Real vv = lengthSquared(dv);
    const Real t = vv > 0 ? std::clamp(-dot(d0, dv) / vv, Real(0), Real(1)) : Real(0);
    const Real reach = (reachA + reachB) * Real(1 + 1e-5) + gap;
    return lengthSquared(d0 + t * dv) <= reach * reach;
}

// Where solver body i's sweep first stops, as a fraction of the step (1:
// nowhere, or not swept: not a dynamic awake body of this pass, or one whose
// points cannot have moved far enough). `bullets`: whether this pass takes
// the bullets (true) or the other bodies (false). Reads the poses of static
// bodies, of dynamic non-bullets (final once their pass is done) and, for a
// bullet, the other bullets' whole paths (their poses as the sub-steps left
// them: the bullets' pass writes no pose until every bullet's stop is known).
Real impactTimeOf(const BodyStore& w, const JointPairFilter& joints, const ContactManager& manager, std::uint32_t i,
                  bool bullets, bool onlyBulletsMove) {
    const std::uint32_t d = w.denseOfSolver[i];
    const BodyParams& p = w.params[d];
    if (p.type != BodyType::Dynamic || !p.awake || p.isSensor || p.isBullet != bullets) return 1;
    const BodyPose& m = w.pose[i];
    const Vec3 dp = m.com - w.startCom[i];
    const Shape& shape = w.cold[d].shape;
    // What the sweep may meet: the box of a ball of the body's extent (its
    // farthest point from the centre of mass) along the centre's path, grown
    // for rounding. Looser than the swept shape's own box (sweptBounds), but
    // each candidate is tested against that box first (sweptImpact), so the
    // looser query changes no result; the tight box for every swept body
    // was 11 % of Jolt's HighSpeed step (5000 tumbling bullets, a few near
    // a wall at a time), for candidates the query finds in a few tree nodes.
    const Vec3 reach = Vec3::splat(p.extent * Real(1 + 1e-5) + kTouchBand);
    const AABB swept{min(w.startCom[i], m.com) - reach, max(w.startCom[i], m.com) + reach};
    // Whether the body is swept, and its sweep, are worked out at its first
    // candidate: most of HighSpeed's bullets fly free of anything in most
    // steps, and their sweeps, turns and cores were half the time of
    // impact's instructions.
    enum class Prepared : std::uint8_t { NotYet, Swept, NotSwept };
    Prepared prepared = Prepared::NotYet;
    Sweep sweep;
    ImpactRules rules;
    const auto prepare = [&] {
        const Real core = coreExtent(shape);
        const Real half = Real(0.5) * core;
        const Quat q0 = w.startQ[i];
        // A body is swept when it may have moved more than half its thinnest
        // half extent. A bullet counts its turn too (a spinning bar's end
        // swings through a thin wall while its centre stays put), bounded
        // cheaply first: no point moved farther than the centre plus the turn
        // (at most pi sin(angle / 2)) times the farthest point. The other
        // bodies count their centre's move only, as before: a tumbling body
        // landing counts as fast by its turn and would be stopped where its
        // rim first touched, changing every such landing for no tunnelling.
        Real turnBound = 0;
        if (p.isBullet) {
            const Real cosHalf = std::min(std::fabs(dot(q0, m.q)), Real(1));
            turnBound = Real(3.14159265) * std::sqrt(1 - cosHalf * cosHalf) * p.extent;
        }
        if (length(dp) + turnBound <= half) return Prepared::NotSwept;
        sweep = sweepBetween(w.startCom[i], q0, m.com, m.q, p.localCom);
        // How far a point of the body's core moved at most: its turn does not
        // move a sphere's surface about its own centre.
        if (p.isBullet && length(dp) + length(sweep.angularVelocity) * coreReach(shape, p.localCom) <= half) {
            return Prepared::NotSwept;
        }
        rules = impactRules(core);
        return Prepared::Swept;
    };
    const std::uint32_t selfSlot = w.denseToSlot[d];
    Real best = 1;
    // false: the body is not swept (the query stops).
    const auto hit = [&](ProxyId, std::uint32_t otherSlot) {
        if (otherSlot == selfSlot) return true;
        const std::uint32_t od = w.bodySlots[otherSlot].dense;
        const BodyParams& op = w.params[od];
        if (op.isSensor || !shouldCollide(p.filter, op.filter) || !mayCollide(w, joints, selfSlot, otherSlot)) return true;
        const Shape& other = w.cold[od].shape;
        Sweep otherSweep{w.originTransform(od), op.localCom, Vec3::zero(), Vec3::zero()};
        if (op.type == BodyType::Static) {
            // any static shape
        } else if (p.isBullet && op.type == BodyType::Dynamic && canSweepAgainst(other.type())) {
            // A non-bullet along its final path, another bullet along the
            // path the sub-steps gave it (both moving: their relative motion
            // is swept, so two bullets crossing within the step stop short
            // of each other instead of meeting through speculative contacts
            // made at the step's start, which a fast turn outruns).
            const std::uint32_t oi = w.solverIndexOf(od);
            if (oi != 0) {
                if (op.isBullet) {
                    // Stops only if the sweeps end it more than 2 kToiSlop
                    // into each other (below): not when the balls of the two
                    // bodies' extents end apart, nor when their end boxes
                    // overlap by less than that along some axis (a shift by
                    // that overlap parts the boxes, so the shapes too). The
                    // boxes are shrunk by a quarter of it: rounding.
                    const Real both = (p.extent + op.extent) * Real(1 + 1e-5);
                    const BodyPose& om = w.pose[oi];
                    if (lengthSquared(m.com - om.com) > both * both) return true;
                    const Real shrink = Real(-0.5) * kToiSlop;
                    const AABB endBox = shape.bounds({m.com - rotate(m.q, p.localCom), m.q}).fattened(shrink);
                    const AABB otherEndBox = other.bounds({om.com - rotate(om.q, op.localCom), om.q}).fattened(shrink);
                    if (!overlaps(endBox, otherEndBox)) return true;
                } else {
                    const Vec3 otherDp = w.pose[oi].com - w.startCom[oi];
                    if (!pathsMayMeet(w.startCom[i], dp, p.extent, w.startCom[oi], otherDp, op.extent, kTouchBand)) return true;
                }
                otherSweep = sweepBetween(w.startCom[oi], w.startQ[oi], w.pose[oi].com, w.pose[oi].q, op.localCom);
            }
        } else {
            return true;
        }
        if (prepared == Prepared::NotYet) prepared = prepare();
        if (prepared == Prepared::NotSwept) return false;
        // Two bullets: only a pair the sweeps end overlapping, which was
        // apart at the start (ImpactRules::endOverlapOnly); what they meet
        // within the step, their speculative contact meets. A full sweep
        // of every pair of spinning bullets took eight distances each and
        // made HighSpeed's step a quarter dearer.
        ImpactRules pairRules = rules;
        pairRules.endOverlapOnly = op.isBullet && op.type == BodyType::Dynamic;
        const SweptImpact r = sweptImpact(shape, sweep, other, otherSweep, pairRules, best);
        if (r.hit) best = std::min(best, r.time);
        return true;
    };
    // Only a bullet is swept against moving bodies: the others need the
    // static tree alone (benchmark chain, no static body: the query of the
    // moving tree was 4 % of the step's instructions). When every moving
    // proxy is an awake bullet (Jolt's HighSpeed), a bullet's moving
    // partners are those of its contacts, whose fat boxes (each body's box
    // with its coming step's motion) met its own: a query of the moving
    // tree finds the same bodies at far more cost (7.5 % of the step's
    // instructions), as the fat boxes hold the paths the sweeps follow.
    if (p.isBullet && !onlyBulletsMove) {
        manager.broadPhase().query(swept, hit);
        return best;
    }
    manager.broadPhase().queryStatic(swept, hit);
    if (p.isBullet && prepared != Prepared::NotSwept && manager.contactListsBuilt()) {
        const std::vector<Contact>& contacts = manager.contacts();
        for (std::uint32_t key = manager.firstContactKey(selfSlot); key != UINT32_MAX; key = manager.nextContactKey(key)) {
            const Contact& c = contacts[key >> 1];
            const std::uint32_t otherSlot = (key & 1) == 0 ? c.slotB : c.slotA;
            // The static tree's query found the static ones.
            if (w.params[w.bodySlots[otherSlot].dense].type == BodyType::Static) continue;
            if (!hit(kNullProxy, otherSlot)) break;
        }
    }
    return best;
}

// Puts solver body i back on its sweep at `time` (a stop of impactTimeOf).
void putBack(BodyStore& w, std::uint32_t i, Real time) {
    if (time >= 1) return;
    const BodyParams& p = w.params[w.denseOfSolver[i]];
    BodyPose& m = w.pose[i];
    const Vec3 dp = m.com - w.startCom[i];
    const Sweep sweep = sweepBetween(w.startCom[i], w.startQ[i], m.com, m.q, p.localCom);
    m.com = w.startCom[i] + dp * time;
    m.q = integrateRotation(w.startQ[i], sweep.angularVelocity, time);
    const Mat3 r = toMat3(m.q);
    m.invInertiaWorld = r * p.invLocalInertia * transpose(r);
}

}  // namespace

// Two passes over the awake set, each in parallel. First the bodies that are
// not bullets: each is swept against static bodies only (which nothing here
// moves) and writes only its own pose. Then the bullets, each against static
// bodies, the dynamic non-bullets, whose poses are final after the first
// pass, and the other bullets along the paths the sub-steps gave them: every
// bullet's stop is found before any bullet is put back (impactTime), so no
// bullet reads a pose this pass writes. Either pass gives the same result
// for any thread count and any order. (A single serial loop was 31 % of the
// serial instructions of box_pile's first 120 steps, almost all of it the
// distance test of bodies that did not move far.)
void solveContinuous(BodyStore& w, const JointPairFilter& joints, const ContactManager& manager, TaskSystem& tasks, Real) {
    const auto count = static_cast<std::uint32_t>(w.denseOfSolver.size());
    if (count <= 1) return;
    std::atomic<std::uint32_t> bulletCount{0};
    tasks.parallelFor(count - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        std::uint32_t bullets = 0;
        for (std::uint32_t i = begin + 1; i <= end; ++i) {
            const BodyParams& p = w.params[w.denseOfSolver[i]];
            if (p.isBullet && p.type == BodyType::Dynamic) ++bullets;
            putBack(w, i, impactTimeOf(w, joints, manager, i, false, false));
        }
        if (bullets != 0) bulletCount.fetch_add(bullets, std::memory_order_relaxed);
    });
    const std::uint32_t bullets = bulletCount.load(std::memory_order_relaxed);
    if (bullets == 0) return;
    // Every body, awake or asleep, has one proxy; the static ones are in the static tree.
    const bool onlyBulletsMove = static_cast<std::uint32_t>(manager.broadPhase().movingTree().proxyCount()) == bullets;
    w.impactTime.resize(count);  // capacity reserved with the bodies (reserveAwakeList)
    tasks.parallelFor(count - 1, 16, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) w.impactTime[i] = impactTimeOf(w, joints, manager, i, true, onlyBulletsMove);
    });
    tasks.parallelFor(count - 1, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin + 1; i <= end; ++i) putBack(w, i, w.impactTime[i]);
    });
}

}  // namespace fulcrum::detail
