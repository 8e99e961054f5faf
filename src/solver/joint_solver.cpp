#include "solver/joint_solver.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <numbers>

#include "solver/contact_solver.hpp"
#include "fulcrum/task_system.hpp"
#include "solver/graph_colouring.hpp"
#include "solver/softness.hpp"
#include "solver/joints/joint_types.hpp"

namespace fulcrum::detail {

namespace {
// A world end for the projection's check in lanes: centre 0 and the identity
// rotation (com x y z, q w x y z).
alignas(16) constexpr Real kWorldEnd[8] = {0, 0, 0, 1, 0, 0, 0, 0};
// Grain of prepare()'s record building: a record is ~500 instructions.
constexpr std::uint32_t kJointsPerBuildTask = 256;
// The projection check's groups of four joints per range (~450 instructions each).
constexpr std::uint32_t kProjectionGroupsPerTask = 16;
// refreshRotations' bodies per range (~60 instructions each where unchanged).
constexpr std::uint32_t kBodiesPerRotationTask = 512;
// store()'s joints per range (a ball joint's reaction ~200 instructions).
constexpr std::uint32_t kJointsPerStoreTask = 256;
}  // namespace

void JointSolver::reserve(std::size_t jointCount) {
    if (constraints_.capacity() < jointCount) constraints_.reserve(2 * jointCount);
    if (events_.capacity() < jointCount) events_.reserve(2 * jointCount);
    if (rowJoints_.capacity() < jointCount) rowJoints_.reserve(2 * jointCount);
    if (structure_.capacity() < jointCount) structure_.reserve(2 * jointCount);
    if (projection_.capacity() < jointCount) projection_.reserve(2 * jointCount);
    if (overBreakLimit_.capacity() < jointCount) overBreakLimit_.reserve(2 * jointCount);
    if (groupBeyond_.capacity() < jointCount / 4 + 1) groupBeyond_.reserve(2 * (jointCount / 4 + 1));
    if (active_.capacity() < jointCount) active_.reserve(2 * jointCount);
    if (placeOf_.capacity() < jointCount) placeOf_.reserve(2 * jointCount);
    if (nextStructure_.capacity() < jointCount) nextStructure_.reserve(2 * jointCount);
    const auto grow = [](auto& v, std::size_t n) {
        if (v.capacity() < n) v.reserve(2 * n);
    };
    grow(isWide_, jointCount);
    grow(wideJoints_, jointCount);
    grow(scalarJoints_, jointCount);
    grow(scalarRows_, jointCount);
    grow(wideJointStart_, kColourCount + 2);
    grow(wideBlockStart_, kColourCount + 2);
    grow(scalarJointStart_, kColourCount + 2);
    grow(scalarRowStart_, kColourCount + 2);
    reservedJoints_ = std::max(reservedJoints_, jointCount);
    if (wide_) wide_->reserve(jointCount / static_cast<std::size_t>(wide_->lanes()) + kColourCount + 1);
}

SimdPath JointSolver::setSimdPath(SimdPath path) {
    if (path == SimdPath::Avx2 && !(avx2Available() && avx2JointKernelsCompiled())) path = SimdPath::Sse2;
    simd_ = path;
    if (path != SimdPath::Scalar && (!wide_ || wide_->path() != path)) {
        wide_ = makeWideJoints(path);
        wide_->reserve(reservedJoints_ / static_cast<std::size_t>(wide_->lanes()) + kColourCount + 1);
    }
    // The joint trees' groups of four in lanes of doubles (tree_lanes.hpp): none on the scalar path.
    trees_.setLanes(path == SimdPath::Scalar ? 0 : path == SimdPath::Avx2 ? 2 : 1);
    return simd_;
}

void JointSolver::prepare(BodyStore& w, std::vector<JointData>& joints, const JointSettings& settings, TaskSystem& tasks,
                          Real h) {
    events_.clear();
    framesStale_ = true;
    refreshedSincePositions_ = false;
    // After a snapshot load the per-body joint lists start out of sync (O(1) check).
    if (!graph_.inSync(joints)) graph_.rebuild(joints);
    bodies_ = w.state.data();
    tasks_ = &tasks;
    allBodies_ = &w.state;
    ctx_.h = h;
    ctx_.invH = 1 / h;
    const Real hertz = std::min(settings.hertz, JointTuning::kMaxHertzPerSubstepRate / h);
    ctx_.soft = makeSoftness(hertz, settings.dampingRatio, h);
    projectionSlop_ = settings.projectionSlop;
    ctx_.limitSoft = ctx_.soft;

    // Which joints take part, and their bodies, first (~20 bytes each): the
    // colouring needs only that, so each constraint record (~0.6 kB) is then
    // built once, in its place in colour order. Built in creation order and
    // copied into colour order, the records were written twice and read once
    // more per step (perf, grid: colour() 6 % of the step, with the joint rows in lanes).
    active_.clear();
    std::uint32_t projectedCount = 0;
    for (std::uint32_t slot = 0; slot < joints.size(); ++slot) {
        JointData& data = joints[slot];
        if (!data.alive || !data.enabled) continue;
        const JointDef& def = data.def;
        const std::uint32_t dA = w.denseOrNone(def.bodyA), dB = w.denseOrNone(def.bodyB);
        const std::uint32_t ia = dA == kNoIndex ? 0 : w.solverIndexOf(dA);
        const std::uint32_t ib = w.solverIndexOf(dB);
        // A sleeping end (not static) sits out this step; the sleep manager wakes it.
        const auto asleep = [&](std::uint32_t d, std::uint32_t i) {
            return d != kNoIndex && i == 0 && w.params[d].type != BodyType::Static;
        };
        if (asleep(dA, ia) || asleep(dB, ib)) {
            data.reactionForce = {};
            data.reactionTorque = {};
            continue;
        }
        if (bodies_[ia].invMass == 0 && bodies_[ib].invMass == 0) continue;  // nothing can move
        // Its place in the projection's list (creation order), so the records can be built in any order.
        const bool projected = withJointType(def.type, [](auto type) { return decltype(type)::kProjected; });
        active_.push_back({slot, ia, ib, dA, dB, projected ? projectedCount++ : kNoIndex});
    }
    // The colouring and the joint trees depend only on which joints join which
    // solver bodies (sameStructureAsLastStep): in a scene whose joints and
    // sleeping don't change, the same as the last step's, so kept (chain
    // benchmark, callgrind, 120 steps: tree build 8.1 M -> 0.2 M, colouring
    // 1.6 M -> 1.1 M; docs/joints.md).
    const bool same = sameStructureAsLastStep(joints, w.state, settings.directSolve);
    colour(w.state, same);  // colourOf_, colourStart_, placeOf_
    constraints_.resize(active_.size());
    projection_.resize(projectedCount);
    groupBeyond_.resize((projection_.size() + 3) / 4);  // checkProjection's, one byte per group of four
    // Each joint's record and projection entry depend on that joint alone:
    // built in ranges across the task system (the same bits for any thread
    // count). joint_grid, 19,701 joints: this loop was ~9 M instructions of
    // serial time per step (docs/benchmarks.md).
    const auto build = [&](std::uint32_t begin, std::uint32_t end) { buildConstraints(w, joints, begin, end, h); };
    const auto activeCount = static_cast<std::uint32_t>(active_.size());
    if (tasks.workerCount() > 1 && activeCount >= 2 * kJointsPerBuildTask) {
        tasks.parallelFor(activeCount, kJointsPerBuildTask,
                          [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { build(begin, end); });
    } else {
        build(0, activeCount);
    }
    if (!settings.directSolve) {
        for (JointConstraint& j : constraints_) j.direct = false;
        if (!same) trees_.build(empty_, w.state);
    } else if (same) {
        trees_.reuse(constraints_);
    } else {
        trees_.build(constraints_, w.state);
    }
    // The joints with rows for the Gauss-Seidel passes: all but a tree's
    // frictionless ball joints, whose only rows, the point block, the tree
    // solver has (a chain's joints skip the call per pass).
    rowJoints_.clear();
    bodyHasRows_.assign(w.state.size(), 0);
    for (std::uint32_t k = 0; k < constraints_.size(); ++k) {
        const JointConstraint& j = constraints_[k];
        if (!withJointType(j.type, [&](auto type) { return decltype(type)::hasRows(j); })) continue;
        rowJoints_.push_back(k);
        // Static and kinematic ends: rows don't change their velocities.
        if (bodies_[j.bodyA].invMass > 0) bodyHasRows_[j.bodyA] = 1;
        if (bodies_[j.bodyB].invMass > 0) bodyHasRows_[j.bodyB] = 1;
    }
    if (!trees_.empty()) trees_.markWarmStartFree(constraints_, bodyHasRows_);
    // Where each colour's joints start in rowJoints_ (both are in colour order).
    const std::size_t colours = colourCount();
    rowColourStart_.resize(colours + 1);
    std::size_t row = 0;
    for (std::size_t c = 0; c <= colours; ++c) {
        const std::uint32_t start = c < colours ? colourStart_[c] : static_cast<std::uint32_t>(constraints_.size());
        while (row < rowJoints_.size() && rowJoints_[row] < start) ++row;
        rowColourStart_[c] = static_cast<std::uint32_t>(row);
    }
    buildWide();
}

void JointSolver::buildConstraints(BodyStore& w, const std::vector<JointData>& joints, std::uint32_t begin,
                                   std::uint32_t end, Real h) {
    for (std::uint32_t i = begin; i < end; ++i) {
        const ActiveJoint& e = active_[i];
        const std::uint32_t slot = e.slot, dA = e.denseA, dB = e.denseB;
        const JointData& data = joints[slot];
        const JointDef& def = data.def;
        JointConstraint& j = constraints_[placeOf_[i]];
        j = JointConstraint{};
        j.slot = slot;
        j.bodyA = e.bodyA;
        j.bodyB = e.bodyB;
        j.denseA = dA;
        j.denseB = dB;
        j.localAnchorA = data.localAnchorA;
        j.localAnchorB = data.localAnchorB;
        j.type = def.type;
        const Vec3 comA = dA == kNoIndex ? Vec3{} : w.motion[dA].com;
        j.qA0 = dA == kNoIndex ? Quat{} : w.motion[dA].q;
        j.qB0 = w.motion[dB].q;
        j.rA0 = rotate(j.qA0, data.localAnchorA);
        j.rB0 = rotate(j.qB0, data.localAnchorB);
        j.centreDelta = w.motion[dB].com - comA;
        j.relative0 = data.relativeRotation;
        j.localAxisA = data.localAxisA;
        j.localAxisB = data.localAxisB;
        j.localFrameA = data.localFrameA;
        j.record = &def;
        j.impulse = data.impulses;
        j.maxFrictionImpulse = h * def.frictionTorque;
        const StoredJoint stored{def, data.minLength, data.maxLength, data.restLength};
        // The type's own fields; it also sets to zero the impulses of rows it
        // does not have this step (a limit switched off, no friction).
        withJointType(def.type, [&](auto type) { decltype(type)::prepare(j, stored, h); });
        // Unused rows start at zero (a motor disabled, no spring).
        if (!j.motor) j.impulse.motor = 0;
        if (!j.spring) j.impulse.spring = 0;
        // A position drive's limit lowered since the last step: its warm start stays within it.
        if (j.impulse.spring > j.maxSpringImpulse) j.impulse.spring = j.maxSpringImpulse;
        if (j.impulse.spring < -j.maxSpringImpulse) j.impulse.spring = -j.maxSpringImpulse;
        // The projection's packed copy, in creation order (sliders have none).
        if (e.projection != kNoIndex) {
            // An awake end's pose is in the awake set, a static end's in its record.
            const auto pose = [&](std::uint32_t body, std::uint32_t dense) {
                return dense == kNoIndex ? kWorldEnd : body != 0 ? &w.pose[body].com.x : &w.motion[dense].com.x;
            };
            projection_[e.projection] = {j.localAnchorA, dA, j.localAnchorB, dB, j.bodyA, j.bodyB, placeOf_[i], j.type,
                                         pose(j.bodyA, dA), pose(j.bodyB, dB)};
        }
    }
}

void JointSolver::buildWide() {
    wideJoints_.clear();
    wideJointStart_.clear();
    wideBlockStart_.clear();
    scalarJoints_.clear();
    scalarJointStart_.clear();
    scalarRows_.clear();
    scalarRowStart_.clear();
    if (simd_ == SimdPath::Scalar || !wide_ || constraints_.empty()) return;
    // Per colour but the overflow colour (the last, whose joints may share a
    // body): its joints of a wide kind (wideKind: Gauss-Seidel frictionless
    // ball joints, cone-twists) in lanes, in blocks of one kind, the rest on
    // the scalar kernels. A colour's joints share no dynamic body, so solving
    // its wide joints first and its others after gives the same bits as the
    // colour in order.
    const std::size_t colours = colourCount();
    const auto lanes = static_cast<std::uint32_t>(wide_->lanes());
    isWide_.assign(constraints_.size(), 0);
    wideJointStart_.resize(colours + 1);
    wideBlockStart_.resize(colours + 1);
    scalarJointStart_.resize(colours + 1);
    scalarRowStart_.resize(colours + 1);
    wide_->clear();
    std::uint32_t blocks = 0;
    constexpr int kKinds = static_cast<int>(WideKind::NotWide);
    for (std::size_t c = 0; c < colours; ++c) {
        wideJointStart_[c] = static_cast<std::uint32_t>(wideJoints_.size());
        wideBlockStart_[c] = blocks;
        scalarJointStart_[c] = static_cast<std::uint32_t>(scalarJoints_.size());
        const bool overflow = c + 1 == colours;
        // The colour's wide joints kind by kind (a block holds one kind),
        // then its scalar ones; isWide_ holds the kind meanwhile.
        for (std::uint32_t k = colourStart_[c]; k < colourStart_[c + 1]; ++k) {
            isWide_[k] = static_cast<std::uint8_t>(overflow ? WideKind::NotWide : jointWideKind(constraints_[k]));
        }
        for (int kind = 0; kind <= kKinds; ++kind) {
            const std::size_t start = wideJoints_.size();
            for (std::uint32_t k = colourStart_[c]; k < colourStart_[c + 1]; ++k) {
                if (isWide_[k] != kind) continue;
                if (kind == kKinds) {
                    scalarJoints_.push_back(k);
                } else {
                    wideJoints_.push_back(k);
                }
            }
            for (std::size_t next = start; next < wideJoints_.size(); next += lanes) {
                const auto count = static_cast<int>(std::min<std::size_t>(lanes, wideJoints_.size() - next));
                wide_->build(constraints_.data(), wideJoints_.data() + next, count, bodies_);
                ++blocks;
            }
        }
    }
    for (std::uint8_t& kind : isWide_) kind = kind != kKinds ? 1 : 0;
    wideJointStart_[colours] = static_cast<std::uint32_t>(wideJoints_.size());
    wideBlockStart_[colours] = blocks;
    scalarJointStart_[colours] = static_cast<std::uint32_t>(scalarJoints_.size());
    for (std::size_t c = 0; c < colours; ++c) {
        scalarRowStart_[c] = static_cast<std::uint32_t>(scalarRows_.size());
        for (std::uint32_t r = rowColourStart_[c]; r < rowColourStart_[c + 1]; ++r) {
            if (!isWide_[rowJoints_[r]]) scalarRows_.push_back(rowJoints_[r]);
        }
    }
    scalarRowStart_[colours] = static_cast<std::uint32_t>(scalarRows_.size());
}

bool JointSolver::sameStructureAsLastStep(const std::vector<JointData>& joints, const std::vector<SolverBody>& bodies,
                                          bool directSolve) {
    // Each joint's key on its own: in ranges across the task system.
    nextStructure_.resize(active_.size());
    const auto keys = [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t k = begin; k < end; ++k) {
            const ActiveJoint& j = active_[k];
            std::uint32_t flags = static_cast<std::uint32_t>(joints[j.slot].def.type) << 4;
            const auto endFlags = [&](std::uint32_t i, std::uint32_t shift) {
                const SolverBody& b = bodies[i];
                if (!(b.invMass > 0)) return;
                flags |= 1u << shift;
                if (determinant(b.invI) > 0) flags |= 2u << shift;
            };
            endFlags(j.bodyA, 0);
            endFlags(j.bodyB, 2);
            nextStructure_[k] = {j.slot, j.bodyA, j.bodyB, flags};
        }
    };
    const auto count = static_cast<std::uint32_t>(active_.size());
    if (tasks_ != nullptr && tasks_->workerCount() > 1 && count >= 2 * kJointsPerBuildTask) {
        tasks_->parallelFor(count, kJointsPerBuildTask,
                            [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { keys(begin, end); });
    } else {
        keys(0, count);
    }
    const bool same = structureValid_ && structureDirect_ == directSolve && structureBodies_ == bodies.size() &&
                      structure_ == nextStructure_;
    structure_.swap(nextStructure_);
    structureBodies_ = bodies.size();
    structureDirect_ = directSolve;
    structureValid_ = true;
    return same;
}

void JointSolver::colour(const std::vector<SolverBody>& bodies, bool sameStructure) {
    // Greedy, in creation order: the first colour where neither dynamic end is
    // taken. Static and kinematic ends (never written) take no slot. Joints
    // beyond kColourCount colours go to the last, solved one after another.
    const std::size_t n = active_.size();
    if (n == 0) {
        colourStart_.clear();
        placeOf_.clear();
        return;
    }
    // The same structure as the last step's gives the same colours (kept in colourOf_).
    if (!sameStructure) {
        colourGreedily<kColourCount>(
            n, bodies.size(), [&](std::size_t i) { return constraintEnds(active_[i], bodies.data()); }, colourBits_,
            colourOf_, colourStart_);
    }
    // Each joint's place in colour order (creation order within a colour).
    std::uint32_t cursor[kColourCount + 1];
    for (std::uint32_t c = 0; c <= kColourCount; ++c) cursor[c] = colourStart_[c];
    placeOf_.resize(n);
    for (std::size_t i = 0; i < n; ++i) placeOf_[i] = cursor[colourOf_[i]]++;
}

namespace {

// The deltas a body's rotation and frames were computed from; compared bit
// for bit (a kept frame then has exactly the bits a recomputed one would).
bool sameDeltas(const SolverBody& b, const Vec3& dp, const Vec3& dtheta) {
    return std::memcmp(&b.dp, &dp, sizeof(Vec3)) == 0 && std::memcmp(&b.dtheta, &dtheta, sizeof(Vec3)) == 0;
}

}  // namespace

void JointSolver::refreshRotations() {
    // Each body's exp(dtheta), recomputed only where its deltas changed since
    // the last refresh (compared bit for bit, so a kept rotation, and a kept
    // joint frame, has exactly the bits a recomputed one would). The deltas
    // change only with the positions (the step's deltas: BodyStore::updateDeltas), so this
    // runs once per sub-step's worth of change, not once per pass. Each
    // joint's frame is then brought up to date where it is used (currentFrame:
    // recomputed if one of its bodies changed since), inside the passes'
    // own sweeps over the joints. A separate sweep over every constraint per
    // pass (first tried) adds a walk over ~50 MB of constraints in the
    // 76,560-joint grid, which is memory-bound; single runs of it read slower
    // than before by wall clock (216-266 vs 185-200 ms/step, loaded machine),
    // interleaved runs of this one are within noise of before (docs/joints.md).
    if (constraints_.empty()) return;  // contacts only: nothing to do (and nothing to allocate)
    const std::vector<SolverBody>& all = *allBodies_;
    const std::size_t n = all.size();
    frameDeltas_.resize(n);
    rotations_.resize(n);
    changedAt_.resize(n);
    ++generation_;
    // Body by body, each on its own entries: in ranges across the task
    // system when there are many (the same bits for any thread count).
    const auto refresh = [&](std::uint32_t begin, std::uint32_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const SolverBody& b = all[i];
            BodyDeltas& kept = frameDeltas_[i];
            if (!framesStale_ && sameDeltas(b, kept.dp, kept.dtheta)) continue;
            kept.dp = b.dp;
            kept.dtheta = b.dtheta;
            rotations_[i] = deltaRotation(b);
            changedAt_[i] = generation_;
        }
    };
    const auto count = static_cast<std::uint32_t>(n);
    if (tasks_ != nullptr && tasks_->workerCount() > 1 && count >= 2 * kBodiesPerRotationTask) {
        tasks_->parallelFor(count, kBodiesPerRotationTask,
                            [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { refresh(begin, end); });
    } else {
        refresh(0, count);
    }
    framesStale_ = false;
    ctx_.rotations = rotations_.data();
    ctx_.changedAt = changedAt_.data();
    ctx_.generation = generation_;
}

namespace {

// Grain of the joints' parallel loops. A joint's warm start is ~100-300
// instructions (a cone-twist's frame) and its rows ~300, so a range of 64 is
// 10-20 us of work, and a colour runs in order below 2 ranges' worth (the
// ragdoll pile's colours hold ~150 joints: joints are 63 % of its step). A
// tree is a few thousand instructions per pass (a ragdoll's 10 joints), so
// ranges of 4.
constexpr std::uint32_t kJointsPerTask = 64;
constexpr std::uint32_t kMinJointsForTasks = 2 * kJointsPerTask;
constexpr std::uint32_t kTreesPerTask = 4;

}  // namespace

template <class Kernel, class WideKernel>
void JointSolver::forEachJointByColour(const std::uint32_t* indices, const std::uint32_t* first, Kernel&& kernel,
                                       WideKernel&& wide) {
    const std::uint32_t colours = static_cast<std::uint32_t>(colourCount());
    const bool parallel = tasks_ != nullptr && tasks_->workerCount() > 1;
    // Wide blocks in ranges of the same number of joints as the scalar ones.
    const std::uint32_t blocksPerTask =
        wideActive() ? std::max<std::uint32_t>(1, kJointsPerTask / static_cast<std::uint32_t>(wide_->lanes())) : 1;
    for (std::uint32_t c = 0; c < colours; ++c) {
        if (wideActive()) {
            const std::uint32_t firstBlock = wideBlockStart_[c], blocks = wideBlockStart_[c + 1] - firstBlock;
            if (!parallel || blocks < 2 * blocksPerTask) {
                if (blocks > 0) wide(firstBlock, blocks);
            } else {
                tasks_->parallelFor(blocks, blocksPerTask, [&](std::uint32_t rangeBegin, std::uint32_t rangeEnd, std::uint32_t) {
                    wide(firstBlock + rangeBegin, rangeEnd - rangeBegin);
                });
            }
        }
        const std::uint32_t begin = first[c], count = first[c + 1] - begin;
        // The overflow colour (the last) runs in order; so does a small colour.
        if (!parallel || c + 1 == colours || count < kMinJointsForTasks) {
            for (std::uint32_t k = begin; k < begin + count; ++k) {
                JointConstraint& j = constraints_[indices != nullptr ? indices[k] : k];
                kernel(j, bodies_[j.bodyA], bodies_[j.bodyB]);
            }
            continue;
        }
        tasks_->parallelFor(count, kJointsPerTask, [&](std::uint32_t rangeBegin, std::uint32_t rangeEnd, std::uint32_t) {
            // A colour's joints share no dynamic body, but may share a static
            // or kinematic one (they take no colour slot), which the kernels
            // write back unchanged (inverse mass 0): on a copy here, so no
            // two threads write one body. Dynamic ends: the bodies themselves,
            // the same operations as in order, so the same bits.
            SolverBody copyA, copyB;
            for (std::uint32_t k = begin + rangeBegin; k < begin + rangeEnd; ++k) {
                JointConstraint& j = constraints_[indices != nullptr ? indices[k] : k];
                SolverBody& a = bodies_[j.bodyA].invMass > 0 ? bodies_[j.bodyA] : (copyA = bodies_[j.bodyA]);
                SolverBody& b = bodies_[j.bodyB].invMass > 0 ? bodies_[j.bodyB] : (copyB = bodies_[j.bodyB]);
                kernel(j, a, b);
            }
        });
    }
}

void JointSolver::warmStart() {
    // The deltas change only with the positions, and every position update
    // is followed by a relax pass, which refreshes: after one, nothing has
    // changed until the next (velocity integration and gathering leave the
    // deltas alone), so the warm start's and store()'s refreshes would find
    // every body unchanged. Skipped then (the same bits: a refresh that finds
    // nothing changed changes no rotation and no frame). Chain benchmark: 11
    // refreshes per step -> 6.
    if (framesStale_ || !refreshedSincePositions_) refreshRotations();
    // A tree of frictionless ball joints whose next biased pass is exact
    // (its factorization has this sub-step's anchors) takes its warm start
    // in that pass, in closed form (JointTreeSolver::solveTree): the same
    // result (exact in exact arithmetic) without the separate application
    // per joint. Chain benchmark: 3 of 5 sub-steps (docs/joints.md, fifth round).
    const bool fold = trees_.nextBiasedPassExact();
    trees_.newSubstep(fold);
    const bool wide = wideActive();
    forEachJointByColour(
        wide ? scalarJoints_.data() : nullptr, wide ? scalarJointStart_.data() : colourStart_.data(),
        [this, fold](JointConstraint& j, SolverBody& a, SolverBody& b) {
            if (fold && j.warmStartInTree) return;
            withJointType(j.type, [&](auto type) { decltype(type)::warmStart(j, a, b, ctx_); });
        },
        [this](std::uint32_t firstBlock, std::uint32_t blocks) {
            wide_->warmStart(firstBlock, blocks, bodies_, constraints_.data(), ctx_);
        });
}

void JointSolver::solve(bool useBias) {
    ctx_.useBias = useBias;
    // The biased pass follows this sub-step's warm start (same deltas); the
    // relax pass follows the position update.
    if (!useBias) {
        refreshRotations();
        refreshedSincePositions_ = true;
    }
    const bool wide = wideActive();
    forEachJointByColour(
        wide ? scalarRows_.data() : rowJoints_.data(), wide ? scalarRowStart_.data() : rowColourStart_.data(),
        [this](JointConstraint& j, SolverBody& a, SolverBody& b) {
            withJointType(j.type, [&](auto type) { decltype(type)::solve(j, a, b, ctx_); });
        },
        [this](std::uint32_t firstBlock, std::uint32_t blocks) {
            wide_->solve(firstBlock, blocks, bodies_, constraints_.data(), ctx_);
        });
    // The point rows of joint trees last, solved exactly, so they have the
    // final word on the anchors (the error users see).
    if (!trees_.empty()) solveTrees();
}

void JointSolver::solveTrees() {
    // Trees share no moving body, so they run side by side (the tree solver
    // never writes a static or kinematic end they may share).
    const bool refactor = trees_.beginPass(ctx_.useBias);
    const auto count = static_cast<std::uint32_t>(trees_.treeCount());
    if (tasks_ == nullptr || tasks_->workerCount() == 1 || count < 2 * kTreesPerTask) {
        trees_.solveTrees(0, count, constraints_, bodies_, ctx_, refactor);
        return;
    }
    // Ranges of whole fours of trees, so that no range cuts a group the tree
    // solver runs in lanes (tree_lanes.hpp: groups start at multiples of 4).
    const std::uint32_t fours = (count + 3) / 4;
    tasks_->parallelFor(fours, (kTreesPerTask + 3) / 4, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        trees_.solveTrees(4 * begin, std::min(4 * end, count), constraints_, bodies_, ctx_, refactor);
    });
}

namespace {

// Moves a body by the position-level impulse P at anchor r (sign -1 for body A).
void shiftBody(BodyPose& m, const SolverBody& s, const Vec3& r, const Vec3& P) {
    m.com += P * s.invMass;
    const Vec3 dtheta = s.invI * cross(r, P);
    m.q = normalize(m.q + Quat(0, dtheta.x, dtheta.y, dtheta.z) * m.q * Real(0.5));
}

}  // namespace

void JointSolver::projectPositions(BodyStore& w) {
    const Real slop = projectionSlop_;
    if (!(slop < std::numeric_limits<Real>::infinity())) return;
    // In creation order, not colour order: chains are usually made from their
    // anchor outwards, and the position pass (Gauss-Seidel) carries a
    // correction along a chain best in that order (colour order: benchmark
    // chain 1.08 -> 1.20 cm, ragdoll test 0.5 -> 1.7 cm).
    //
    // Up to kMaxProjectionPasses passes, stopping after one that moved
    // nothing: one pass leaves what a later joint's correction undid in an
    // earlier one (a ragdoll's shoulder moving the torso off its spine). Worst
    // joint error, bench_joints, 1 / 2 / 4 passes: ragdoll pile (150 steps)
    // 2.26 / 1.09 / 0.53 cm, chain 1.11 / 0.69 / 0.54 cm (Gauss-Seidel 5.3 /
    // 5.1 / 4.8 cm). Before the tree solver more passes made the chain worse
    // (docs/joints.md): they took away the error the soft rows needed to carry
    // the load; the trees now carry it exactly.
    //
    // Most sub-steps leave every joint within the slop: a first check of all
    // of them in SIMD lanes then stands for the first pass, which would move
    // nothing (firstGroupBeyondSlop: the same operations per lane as the pass's, so
    // the same decisions and the same bits).
    const std::uint32_t groups = projectionGroupCount();
    if (tasks_ != nullptr && tasks_->workerCount() > 1 && groups >= 2 * kProjectionGroupsPerTask) {
        tasks_->parallelFor(groups, kProjectionGroupsPerTask,
                            [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { checkProjection(w, begin, end); });
        projectCheckedPositions(w);
        return;
    }
    const std::size_t first = firstGroupBeyondSlop(w, slop);
    if (first == (projection_.size() + 3) / 4) return;
    runProjectionPasses(w, nullptr, first);
}

void JointSolver::runProjectionPasses(BodyStore& w, const std::uint8_t* beyond, std::size_t firstBeyond) {
    // What the check found within the slop needs no second look before a
    // body of it moves (withinAt_, movedAt_): rain, where a few ragdolls
    // touching down make every sub-step's passes run over all joints, spent
    // as much on the passes' checks again as on the check itself.
    const std::size_t joints = projection_.size();
    if (projectionClock_ > 0xF0000000u) {  // long runs: start the clock again
        std::fill(movedAt_.begin(), movedAt_.end(), 0u);
        std::fill(withinAt_.begin(), withinAt_.end(), 0u);
        projectionClock_ = 0;
    }
    projectionRunStart_ = ++projectionClock_;
    if (movedAt_.size() < w.state.size()) movedAt_.resize(w.state.size(), 0u);
    if (withinAt_.size() < joints) withinAt_.resize(joints, 0u);
    for (std::size_t g = 0, groups = (joints + 3) / 4; g < groups; ++g) {
        if (beyond != nullptr ? beyond[g] != 0 : g >= firstBeyond) continue;
        for (std::size_t k = 4 * g, end = std::min(joints, 4 * g + 4); k < end; ++k) withinAt_[k] = projectionRunStart_;
    }
    for (int pass = 0; pass < JointTuning::kMaxProjectionPasses; ++pass) {
        if (!projectionPass(w, projectionSlop_)) break;
    }
}

std::uint32_t JointSolver::projectionGroupCount() const {
    if (!(projectionSlop_ < std::numeric_limits<Real>::infinity())) return 0;  // no projection
    return static_cast<std::uint32_t>((projection_.size() + 3) / 4);
}

void JointSolver::checkProjection(const BodyStore& w, std::uint32_t beginGroup, std::uint32_t endGroup) {
    // Sized on the caller's thread before the ranges run (the stage list is
    // built after prepare(), the first range may be any thread's): each
    // range writes only its own groups' bytes.
    for (std::uint32_t g = beginGroup; g < endGroup; ++g) groupBeyond_[g] = groupBeyondSlop(w, g, projectionSlop_) ? 1 : 0;
}

void JointSolver::projectCheckedPositions(BodyStore& w) {
    // The check ran in groups across the threads (checkProjection): what
    // firstGroupBeyondSlop would have found, without its serial sweep over every
    // joint each sub-step (joint_grid: 7 % of the step's instructions, all
    // of it on one thread; docs/benchmarks.md).
    const std::uint32_t groups = projectionGroupCount();
    if (groups == 0) return;
    const auto* first = groupBeyond_.data();
    if (std::find(first, first + groups, std::uint8_t{1}) == first + groups) return;
    runProjectionPasses(w, first, 0);
}

bool JointSolver::groupBeyondSlop(const BodyStore& w, std::size_t group, Real slop) const {
#if defined(__GNUC__) && defined(__SSE2__) && !FULCRUM_DOUBLE  // float lanes; the double build checks one by one
    const std::size_t first = 4 * group;
    const std::size_t count = std::min<std::size_t>(4, projection_.size() - first);
    for (std::size_t k = 0; k < count; ++k) {
        if (projection_[first + k].type == JointType::Distance) return true;  // its own rule: the pass decides
    }
    float e2[4];
    squaredSeparations4(w, first, count, e2);
    for (std::size_t k = 0; k < count; ++k) {
        if (!(std::sqrt(e2[k]) <= slop)) return true;
    }
    return false;
#else
    (void)w;
    (void)group;
    (void)slop;
    return true;
#endif
}

std::size_t JointSolver::firstGroupBeyondSlop(const BodyStore& w, Real slop) const {
    const std::size_t groups = (projection_.size() + 3) / 4;
    for (std::size_t g = 0; g < groups; ++g) {
        if (groupBeyondSlop(w, g, slop)) return g;
    }
    return groups;
}

#if defined(__GNUC__) && defined(__SSE2__) && !FULCRUM_DOUBLE
void JointSolver::squaredSeparations4(const BodyStore& w, std::size_t first, std::size_t count, float* e2) const {
    // Four joints per round, structure of arrays: per lane exactly the
    // scalar steps of projectionPass (rotate(q, v) = (v + t q.w) + u x t with
    // t = 2 (u x v); d = (comB + rB) - (comA + rA); |d| = sqrt(x x + y y + z z)).
    // A joint to the world has the identity rotation, a zero centre and its
    // world anchor, which gives pA = anchor exactly, as the pass. Chain
    // benchmark, 600 steps, callgrind: projection 63.8 M -> 43.6 M (whole run
    // 980 M -> 960 M); grid --quick: the check ~100 instructions per joint
    // against the pass's ~166, and no pass followed it there.
    using Float4 = float __attribute__((vector_size(16)));
    // The gather: each end's centre and rotation are 7 consecutive floats of
    // BodyPose or BodyMotion (com x y z, q w x y z), its anchor 3 of the packed record; four
    // joints' ends are loaded 4 floats at a time and transposed into lanes
    // (chain benchmark, callgrind 120 steps: 7.5 M -> see docs/joints.md,
    // fifth round; it was one scalar store per float into a staging array).
    // The lanes hold the same values as before, so the same decisions.
    static_assert(offsetof(BodyMotion, q) == offsetof(BodyMotion, com) + 3 * sizeof(float));
    static_assert(offsetof(BodyPose, q) == offsetof(BodyPose, com) + 3 * sizeof(float));
    static_assert(offsetof(ProjectionJoint, localAnchorB) == offsetof(ProjectionJoint, localAnchorA) + 4 * sizeof(float));
    static_assert(sizeof(Quat) == 4 * sizeof(float) && sizeof(Vec3) == 3 * sizeof(float));
    const auto load = [](const float* p) {
        Float4 v;
        std::memcpy(&v, p, sizeof v);
        return v;
    };
    // Rows r0..r3 (one per joint) -> columns c0..c3 (one per component).
    const auto transpose = [](Float4 r0, Float4 r1, Float4 r2, Float4 r3, Float4& c0, Float4& c1, Float4& c2, Float4& c3) {
        const Float4 t0 = __builtin_shufflevector(r0, r1, 0, 4, 1, 5), t1 = __builtin_shufflevector(r2, r3, 0, 4, 1, 5);
        const Float4 t2 = __builtin_shufflevector(r0, r1, 2, 6, 3, 7), t3 = __builtin_shufflevector(r2, r3, 2, 6, 3, 7);
        c0 = __builtin_shufflevector(t0, t1, 0, 1, 4, 5);
        c1 = __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
        c2 = __builtin_shufflevector(t2, t3, 0, 1, 4, 5);
        c3 = __builtin_shufflevector(t2, t3, 2, 3, 6, 7);
    };
    // Lanes past `count` read world ends (never read back).
    const float* endA[4] = {kWorldEnd, kWorldEnd, kWorldEnd, kWorldEnd};
    const float* endB[4] = {kWorldEnd, kWorldEnd, kWorldEnd, kWorldEnd};
    const float* anchors[4] = {kWorldEnd, kWorldEnd, kWorldEnd, kWorldEnd};  // localAnchorA, denseA, B (7 floats)
    (void)w;
    for (std::size_t k = 0; k < count; ++k) {
        const ProjectionJoint& j = projection_[first + k];
        endA[k] = j.poseA;
        endB[k] = j.poseB;
        anchors[k] = &j.localAnchorA.x;
    }
    const auto end = [&](const float* const* ends, int anchorOffset, Float4& x, Float4& y, Float4& z) {
        Float4 cx, cy, cz, qw, ux, uy, uz, lx, ly, lz, unused;
        transpose(load(ends[0]), load(ends[1]), load(ends[2]), load(ends[3]), cx, cy, cz, unused);
        transpose(load(ends[0] + 3), load(ends[1] + 3), load(ends[2] + 3), load(ends[3] + 3), qw, ux, uy, uz);
        transpose(load(anchors[0] + anchorOffset), load(anchors[1] + anchorOffset), load(anchors[2] + anchorOffset),
                  load(anchors[3] + anchorOffset), lx, ly, lz, unused);
        const Float4 tx = (uy * lz - uz * ly) * 2.0f, ty = (uz * lx - ux * lz) * 2.0f, tz = (ux * ly - uy * lx) * 2.0f;
        const Float4 rx = (lx + tx * qw) + (uy * tz - uz * ty);
        const Float4 ry = (ly + ty * qw) + (uz * tx - ux * tz);
        const Float4 rz = (lz + tz * qw) + (ux * ty - uy * tx);
        x = cx + rx, y = cy + ry, z = cz + rz;
    };
    Float4 ax, ay, az, bx, by, bz;
    end(endA, 0, ax, ay, az);
    end(endB, 4, bx, by, bz);
    const Float4 dx = bx - ax, dy = by - ay, dz = bz - az;
    const Float4 squared = dx * dx + dy * dy + dz * dz;
    std::memcpy(e2, &squared, sizeof squared);
}
#endif

bool JointSolver::projectionPass(BodyStore& w, Real slop) {
    bool moved = false;
    const std::size_t joints = projection_.size();
    // Within the slop at withinAt_[k] and neither body moved since (a
    // distance joint is judged by its own rule: never skipped).
    const auto known = [&](std::size_t k) {
        const ProjectionJoint& j = projection_[k];
        const std::uint32_t at = withinAt_[k];
        return projectionMemory_ && at >= projectionRunStart_ && movedAt_[j.bodyA] <= at && movedAt_[j.bodyB] <= at &&
               j.type != JointType::Distance;
    };
    for (std::size_t i = 0; i < joints; ++i) {  // sliders left out
        if (known(i)) continue;
#if defined(__GNUC__) && defined(__SSE2__) && !FULCRUM_DOUBLE
        // Most joints are within the slop (grid, callgrind: 6.6 % of the
        // joints a pass visits move a body): the next four are checked in
        // lanes (squaredSeparations4, the steps below lane by lane, so the
        // same decisions) and skipped up to the first that moves. Nothing
        // moved between the check and the skip, and after a joint moves its
        // bodies the check starts again from the next one, so every joint is
        // judged on the positions the one-by-one pass would see.
        {
            const std::size_t count = std::min<std::size_t>(4, joints - i);
            float e2[4];
            squaredSeparations4(w, i, count, e2);
            std::size_t k = 0;
            while (k < count && projection_[i + k].type != JointType::Distance && std::sqrt(e2[k]) <= slop) {
                withinAt_[i + k] = projectionClock_;
                ++k;
            }
            if (k == count) {
                i += count - 1;
                continue;
            }
            i += k;
        }
#endif
        const ProjectionJoint& j = projection_[i];
        // An awake end's pose is in the awake set, a static end's in its record.
        const auto com = [&](std::uint32_t body, std::uint32_t dense) -> const Vec3& {
            return body != 0 ? w.pose[body].com : w.motion[dense].com;
        };
        const auto orientation = [&](std::uint32_t body, std::uint32_t dense) -> const Quat& {
            return body != 0 ? w.pose[body].q : w.motion[dense].q;
        };
        const Vec3 rA = j.denseA == kNoIndex ? Vec3{} : rotate(orientation(j.bodyA, j.denseA), j.localAnchorA);
        const Vec3 pA = j.denseA == kNoIndex ? j.localAnchorA : com(j.bodyA, j.denseA) + rA;
        const Vec3 rB = rotate(orientation(j.bodyB, j.denseB), j.localAnchorB);
        const Vec3 d = com(j.bodyB, j.denseB) + rB - pA;
        // Point joints within the slop (nearly all, every sub-step) stop here,
        // before the masses are gathered (chain benchmark, callgrind 120 steps:
        // projection 15.8 M -> see docs/joints.md).
        const Real e = length(d);
        if (j.type != JointType::Distance && e <= slop) {
            withinAt_[i] = projectionClock_;
            continue;
        }
        // Masses of the current orientations (the step's start is far off for a link spinning at 40 rad/s).
        SolverBody sa = bodies_[j.bodyA];
        SolverBody sb = bodies_[j.bodyB];
        if (sa.invMass > 0) sa.invI = w.pose[j.bodyA].invInertiaWorld;
        if (sb.invMass > 0) sb.invI = w.pose[j.bodyB].invInertiaWorld;
        BodyPose* ma = j.denseA == kNoIndex || sa.invMass == 0 ? nullptr : &w.pose[j.bodyA];
        BodyPose* mb = sb.invMass == 0 ? nullptr : &w.pose[j.bodyB];
        Vec3 P;
        if (j.type == JointType::Distance) {
            const JointConstraint& limits = constraints_[j.constraint];
            const Real len = length(d);
            if (len < Real(1e-6)) continue;
            const Real C = DistanceJoint::projectionError(limits, len, slop);
            if (C == 0) continue;
            const Vec3 n = d * (1 / len);
            const Real k = rowInverseMass(linearRow(n, rA, rB), sa, sb);
            if (k <= 0) continue;
            P = n * (-C / k);
        } else {
            const Mat3 K = pointInverseMass(sa, sb, rA, rB);
            if (!(determinant(K) > 0)) continue;
            P = -(inverse(K) * (d * ((e - slop) / e)));
        }
        if (ma) shiftBody(*ma, sa, rA, -P);
        if (mb) shiftBody(*mb, sb, rB, P);
        ++projectionClock_;
        if (ma) movedAt_[j.bodyA] = projectionClock_;
        if (mb) movedAt_[j.bodyB] = projectionClock_;
        moved = true;
    }
    return moved;
}

void JointSolver::store(BodyStore& w, std::vector<JointData>& joints) {
    // The reactions read each joint's frame: current after the last relax
    // pass (nothing is recomputed unless the deltas changed since).
    if (framesStale_ || !refreshedSincePositions_) refreshRotations();
    if (wideActive()) wide_->store(constraints_.data());  // the lanes' impulses back into their joints
    // Each joint's impulses and reaction go to its own record: in ranges
    // across the task system (joint_grid: ~2.5 M instructions a step, which
    // ran on one thread); whether it breaks is decided after, in order, so
    // the events come in the same order for any thread count.
    overBreakLimit_.resize(constraints_.size());
    const auto react = [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t k = begin; k < end; ++k) {
            JointConstraint& j = constraints_[k];
            JointData& data = joints[j.slot];
            data.impulses = j.impulse;
            // A ball joint's reaction reads no frame (jointReaction): not
            // recomputed for the joints the wide path kept no AoS frame for.
            if (j.type != JointType::Ball) currentFrame(j, bodies_[j.bodyA], bodies_[j.bodyB], ctx_);
            jointReaction(j, bodies_[j.bodyA], bodies_[j.bodyB], ctx_.invH, data.reactionForce, data.reactionTorque);
            const Real force = length(data.reactionForce), torque = length(data.reactionTorque);
            overBreakLimit_[k] = force <= data.def.breakForce && torque <= data.def.breakTorque ? 0 : 1;
        }
    };
    const auto count = static_cast<std::uint32_t>(constraints_.size());
    if (tasks_ != nullptr && tasks_->workerCount() > 1 && count >= 2 * kJointsPerStoreTask) {
        tasks_->parallelFor(count, kJointsPerStoreTask,
                            [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) { react(begin, end); });
    } else {
        react(0, count);
    }
    for (std::uint32_t k = 0; k < count; ++k) {
        if (!overBreakLimit_[k]) continue;
        const JointConstraint& j = constraints_[k];
        JointData& data = joints[j.slot];
        // Broken: disabled from the next step on, reported once. Its bodies may
        // collide again: the world re-examines their pairs (breakEvents()).
        data.enabled = false;
        data.broken = true;
        data.impulses = {};
        events_.push_back({{j.slot, data.generation}, data.def.bodyA, data.def.bodyB, data.reactionForce, data.reactionTorque});
        if (!data.def.bodyA.isNull()) w.wakeBody(w.bodySlots[data.def.bodyA.index].dense);
        w.wakeBody(w.bodySlots[data.def.bodyB.index].dense);
    }
}

void jointReaction(const JointConstraint& j, const SolverBody& a, const SolverBody& b, Real invH, Vec3& force, Vec3& torque) {
    // The point / perpendicular rows' impulse, then the type's own part:
    // friction (ball, cone-twist) and the free-axis rows (hinge, slider)
    // carry the share of the point / perpendicular / alignment rows that goes
    // with them (coupled_row.hpp, cacheFriction), which is not in those rows'
    // accumulated impulses. Torques are about B's anchor: a force at the
    // anchor adds none.
    force = j.impulse.linear;
    torque = {};
    withJointType(j.type, [&](auto type) {
        using T = decltype(type);
        if constexpr (requires { T::addReaction(j, a, b, force, torque); }) {
            T::addReaction(j, a, b, force, torque);  // rows that need the bodies to be summed (six-DOF)
        } else {
            T::addReaction(j, force, torque);
        }
    });
    force *= invH;
    torque *= invH;
}

}  // namespace fulcrum::detail
