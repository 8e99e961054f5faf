#include "solver/contact_solver.hpp"
#include "solver/graph_colouring.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "fulcrum/task_system.hpp"
#include "contacts/contact.hpp"
#include "contacts/contact_manager.hpp"
#include "solver/joints/joint_common.hpp"
#include "threads/staged_parallel.hpp"

namespace fulcrum::detail {

namespace {

// Colours tried before a constraint goes to the overflow colour (solved last).
// Box2D uses 24 in 2D; 3D piles have more neighbours per body, 32 fits one
// uint32 mask of used colours per body if we ever need it.
constexpr std::uint32_t kColourCount = 32;

// Fewest blocks per task when a colour is spread over threads: a block is
// ~0.2-0.5 us of work, a hand-off to a spinning worker about as much.
// Was 8 (colours of 16 blocks and more split): 4 splits box_pile's colours of
// ~60 blocks (its ~950 still-awake bodies) into 15 ranges instead of 7.
constexpr std::uint32_t kBlocksPerTask = 4;

// Ranges for the loops spread over threads: building a block (four
// constraints) is ~0.3-0.6 us and storing one ~0.1 us, so these sizes keep
// a range above the pool's hand-off cost (~0.1-0.2 us).
constexpr std::uint32_t kBlocksPerBuildTask = 16;
constexpr std::uint32_t kConstraintsPerTask = 64;
// The pending-constraint list is built over fixed blocks of contact slots (a
// constant, so the block sums do not depend on the thread count); a block is
// ~1-2 us of work.
constexpr std::size_t kContactsPerBlock = 256;
constexpr std::uint32_t kContactBlocksPerTask = 2;
// The colour-ordered slots are placed per fixed block of constraints (a block
// counts its colours, ~0.3 us): colour().
constexpr std::size_t kSlotsPerBlock = 256;

// How far ahead the constraint build and the store prefetch their contacts
// (manifolds half as far): a block takes ~0.5 us, a miss to memory ~0.1 us.
constexpr std::size_t kPrefetchBlocks = 8;

// Overlaps deeper than this share contactPushMaxVelocity among a body's
// contacts (pushLimit). Resting contacts (a few millimetres deep, up to ~3 cm
// under a heavy load: docs/solver.md, "Mass ratios") keep the whole push
// speed: a light box between two 100x heavier ones rests ~2 cm into each and
// needs ~1.5 m/s of bias from both; at a 1 cm threshold the two shared 3 m/s
// and the 1:100 stack collapsed.
constexpr Real kPushShareDepth = Real(0.05);

// A pair that got deeper by more than this, either unseen (the narrow phase
// finds it deeper than the solver had predicted for the end of the last
// step: Contact::grownBy) or within this step (its predicted end depth less
// its step-start depth, or less zero if it started apart), is pushed apart by
// position after the sub-steps (pushOutGrown) down to kGrowthPushOutKeep.
// Resting contacts change their depth by far less from step to step; a hull
// struck within a step into a neighbour whose step-start manifold held other
// features grows 10-20 cm unseen, and one struck by a hull landing at 15-25
// m/s is driven several centimetres into the next within the step
// (docs/benchmarks.md, `pile8`: 1 cm against 0.5 cm there).
constexpr Real kGrowthPushOut = Real(0.005);
constexpr Real kGrowthPushOutKeep = Real(0.005);
// Gauss-Seidel passes of pushOutGrown at most (a pass moves a body into its
// next neighbour, which the next pass sees grown), and the least move.
constexpr std::uint32_t kPushOutPasses = 8;
constexpr Real kPushOutTolerance = Real(1e-3);
// pushOutGrown leaves the pairs of a body touching a dynamic body more than
// this many times heavier to the soft contact.
constexpr Real kPushOutMassRatio = 10;

// The largest |depth| of a contact's points (pushOutGrown's gate: its
// PairReach). Out of line: the prepare's loop stays as small as without the
// push-out.
[[gnu::noinline]] Real largestDepth(const Contact& c, std::uint32_t manifolds) {
    Real farthest = 0;
    for (std::uint32_t mi = 0; mi < manifolds; ++mi) {
        const CachedManifold& m = c.manifolds[mi];
        for (std::uint32_t i = 0; i < m.pointCount; ++i) farthest = std::max(farthest, std::abs(m.points[i].depth));
    }
    return farthest;
}

// The pending-list pass reads each contact's manifolds (their own heap
// blocks, scattered): requested this many contacts ahead. A hint only.
constexpr std::size_t kManifoldsAhead = 16;

void prefetchFirstManifold(const Contact& c) {
#if defined(__GNUC__) || defined(__clang__)
    if (c.manifolds.empty()) return;
    const char* m = reinterpret_cast<const char*>(c.manifolds.data());
    for (std::size_t at = 0; at < sizeof(CachedManifold); at += 64) __builtin_prefetch(m + at);
#else
    (void)c;
#endif
}

// The lines of a contact the solver reads after the pending-list pass: its
// material and first touch, and its manifolds' vector (a 248-byte contact
// spans four or five lines; its first and last, which this prefetched before,
// hold neither: the store then waited on each lane's contact, 70 % of its
// samples on ConvexVsMesh, and the staging in packWide on each manifold).
void prefetchContact(const Contact& c) {
    __builtin_prefetch(&c.friction);
    __builtin_prefetch(reinterpret_cast<const char*>(&c.manifolds) + sizeof(c.manifolds) - 1);
}

// The lines of a manifold the build and store use: the normal and first
// point at the start, the friction state at the end (a one-point manifold
// leaves the middle alone).
void prefetchManifold(const CachedManifold* m) {
    const char* p = reinterpret_cast<const char*>(m);
    __builtin_prefetch(p);
    __builtin_prefetch(p + 64);
    __builtin_prefetch(p + sizeof(CachedManifold) - 1);
}

// The wide blocks' lanes are placed by a key within each colour
// (placeInLanes): the constraints of more points first, and among those of
// one point count, the ones whose end A is the static world (solver body 0)
// first. A block runs its points up to its lanes' largest count and gathers
// end A unless every lane's is the static world (WideContactBlock), so
// blocks of like lanes do the least work: on Jolt's ConvexVsMesh 73 % of
// the constraints have one point, but with the lanes in slot order 80 % of
// the blocks had a lane of two or more (docs/benchmarks.md, cvm9).
constexpr std::uint32_t kLaneKeys = 8;

// A manifold's point count less one, in 0-3 (a manifold of no points, which
// the narrow phase does not keep, as one of one point: the key only orders).
std::uint32_t lanePoints(const CachedManifold& m) { return std::min(std::max(m.pointCount, 1u), 4u) - 1; }

std::uint8_t laneKey(std::uint32_t pointsLessOne, std::uint32_t bodyA) {
    return static_cast<std::uint8_t>((3 - pointsLessOne) * 2 + (bodyA != 0 ? 1 : 0));
}

}  // namespace

ContactSolver::ContactSolver() { setSimdPath(initialSimdPath()); }
ContactSolver::~ContactSolver() = default;
ContactSolver::ContactSolver(ContactSolver&&) noexcept = default;
ContactSolver& ContactSolver::operator=(ContactSolver&&) noexcept = default;

void ContactSolver::reserve(std::size_t bodyCount) {
    const auto grow = [](auto& v, std::size_t n) {
        if (v.capacity() < n) v.reserve(2 * n);
    };
    grow(constraints_, 4 * bodyCount);
    grow(pending_, 4 * bodyCount);
    grow(overlapping_, 4 * bodyCount);
    grow(laneKeys_, 4 * bodyCount);
    grow(laneOfSlot_, 4 * bodyCount);
    grow(overlapCount_, bodyCount + 1);
    grow(pushedPass_, bodyCount + 1);
    grow(loaded_, bodyCount + 1);
    grow(jointed_, bodyCount + 1);
    grow(still_, 4 * bodyCount);
    grow(pairReach_, 4 * bodyCount);
    grow(contactEnds_, 4 * bodyCount);
    grow(contactReach_, 4 * bodyCount);
    grow(candidates_, 4 * bodyCount);
    grow(pendingBlockStart_, 4 * bodyCount / kContactsPerBlock + 2);
    grow(slotOf_, 4 * bodyCount);
    grow(slotCursor_, (kColourCount + 1) * (4 * bodyCount / kSlotsPerBlock + 2));
    grow(pendingOfSlot_, 4 * bodyCount);
    grow(laneSources_, 4 * bodyCount);
    grow(blockColour_, bodyCount + kColourCount + 1);  // 4 constraints per body, 4 lanes (the narrowest)
    grow(colourOf_, 4 * bodyCount);
    grow(colouredEnds_, 4 * bodyCount);
    grow(colourBits_, bodyCount + 1);
    grow(colourStart_, kColourCount + 2);
    if (blocks_) blocks_->reserve(4 * bodyCount / static_cast<std::size_t>(blocks_->lanes()) + kColourCount + 1);
    grow(blockStart_, kColourCount + 2);
    grow(lastPassStages_, kColourCount + 4);
}

SimdPath ContactSolver::setSimdPath(SimdPath path) {
    if (path == SimdPath::Avx2 && !avx2Available()) path = SimdPath::Sse2;
    simd_ = path;
    wide_ = path != SimdPath::Scalar;
    if (wide_ && (!blocks_ || blocks_->path() != path)) {
        const std::size_t capacity = blocks_ ? blocks_->size() * static_cast<std::size_t>(blocks_->lanes()) : 0;
        blocks_ = makeWideBlocks(path);
        blocks_->setStaticAKernels(staticAKernels_);
        blocks_->reserve(capacity / static_cast<std::size_t>(blocks_->lanes()) + kColourCount + 1);
    }
    return simd_;
}

void ContactSolver::prepareConstraintList(BodyStore& w, ContactManager& manager, const SolverSettings& s, Real h) {
    store_ = &w;
    invH_ = 1 / h;
    pushMax_ = s.pushMaxVelocity;
    restitutionThreshold_ = s.restitutionThreshold;
    // Contact stiffness between two dynamic bodies capped at a sixth of the
    // sub-step rate (h omega <= 1.05). At a quarter (h omega = pi/2) one
    // Gauss-Seidel pass per sub-step has a limit cycle in deep stacks:
    // pyramid_large (60 rows) kept ringing vertically at 0.05-0.1 m/s for all
    // 10 s and its top rows slid 0.22 m; at a sixth the ringing decays to
    // ~1 mm/s (docs/solver.md, "pyramid_large"). Static contacts twice as stiff
    // (so stacks don't sink into the ground) under a quarter of the sub-step
    // rate: at half the rate (Box2D's limit for static contacts) a stack of
    // three unit boxes jittered at 0.1 m/s; capped, below 1e-4 m/s.
    const Real hertz = std::min(s.contactHertz, Real(1) / (6 * h));
    contactSoftness_ = makeSoftness(hertz, s.dampingRatio, h);
    staticSoftness_ = makeSoftness(std::min(2 * s.contactHertz, Real(0.25) / h), s.dampingRatio, h);

    // The solver bodies are the body store's awake set (body_store.hpp),
    // filled by the step just before: solver body i is w.awakeBodies[i - 1].
    const auto& solverOfDense_ = w.solverOfDense;

    // ---- constraints, one per manifold of every contact with an awake body.
    // First the list of (contact, manifold, bodies), coloured; then each
    // constraint is built in place at its colour's position (no copies of the
    // ~600-byte constraints: measured -5 % on sphere_pile).
    // The list is built in parallel over fixed blocks of contacts: each block
    // finds its contacts' solver bodies and manifold counts (contactEnds_,
    // per contact), the block totals are summed in block order, and each block
    // writes its entries from its own offset: the list one thread builds.
    // The candidates are every contact, or, with fewer than half the bodies
    // awake, only the awake bodies' contacts (ascending, so the same list):
    // scanning every contact cost a sleeping box_pile 11 us per step, all of
    // its step (World::lastStepProfile; 4,000 boxes, 12,000 contacts).
    ContactArray& contacts = manager.contacts();
    const bool sparse = manager.contactsOfAwakeBodies(w, candidates_);
    const std::size_t candidateCount = sparse ? candidates_.size() : contacts.size();
    const std::uint32_t* candidate = sparse ? candidates_.data() : nullptr;
    const auto contactAt = [candidate](std::size_t k) {
        return candidate != nullptr ? std::size_t{candidate[k]} : k;
    };
    const bool pushOut = pushOut_;  // pushOutGrown's gate needs the pairs' reach
    // Walking every slot: the contacts that may hold manifolds, one bit each
    // (ContactManager::mayHaveManifoldBits). A slot with its bit clear has no
    // manifold and a zero grownBy, so it gives no constraint and its
    // contactEnds_ entry is what reading it would give; the pass reads only
    // the others (ConvexVsMesh: about half of its live contacts have none),
    // and clears the bits of those it finds without. A block's words are its
    // own (kContactsPerBlock is a multiple of 64): no two tasks share one.
    static_assert(kContactsPerBlock % 64 == 0);
    std::uint64_t* const maybe = sparse ? nullptr : manager.mayHaveManifoldBits();
    const std::size_t contactBlocks = (candidateCount + kContactsPerBlock - 1) / kContactsPerBlock;
    contactEnds_.resize(candidateCount);
    if (pushOut) contactReach_.resize(candidateCount);
    pendingBlockStart_.resize(contactBlocks + 1);
    // One candidate: its contactEnds_ entry (ends.manifolds already 0), and
    // the constraints it gives.
    const auto visit = [&](std::size_t k, ContactEnds& ends) {
        Contact& c = contacts[contactAt(k)];
        // Read and zeroed here (Contact::grownBy: 0 between steps).
        ends.grown = c.grownBy > kGrowthPushOut;
        c.grownBy = 0;
        if (maybe != nullptr && (!c.alive || c.manifolds.empty())) maybe[k >> 6] &= ~(std::uint64_t{1} << (k & 63));
        if (!c.alive || c.sensor || c.manifolds.empty()) return std::uint32_t{0};
        const std::uint32_t dA = w.bodySlots[c.slotA].dense;
        const std::uint32_t dB = w.bodySlots[c.slotB].dense;
        const std::uint32_t ia = solverOfDense_[dA], ib = solverOfDense_[dB];
        // Both static or asleep: not part of this step.
        if (ia == 0 && ib == 0) return std::uint32_t{0};
        // A sleeping body paired with an awake one was woken by the contact manager.
        if ((ia == 0 && w.params[dA].type != BodyType::Static) ||
            (ib == 0 && w.params[dB].type != BodyType::Static))
            return std::uint32_t{0};
        if (store_->state[ia].invMass == 0 && store_->state[ib].invMass == 0) return std::uint32_t{0};
        ends.bodyA = ia;
        ends.bodyB = ib;
        ends.manifolds = static_cast<std::uint32_t>(c.manifolds.size());
        // Which manifolds overlap deeply, and how the pair came
        // together (pushLimit), read here while the contact is in
        // the cache: the pass below then reads no contact and no
        // manifold (it missed the cache on both again: 45 % of this
        // function's time at the washer's full size). Only this
        // block writes this contact, so the flag is the same for
        // any thread count.
        bool anyOverlaps = false;
        std::uint32_t overlapping = 0, points = 0;
        for (std::uint32_t mi = 0; mi < ends.manifolds; ++mi) {
            const CachedManifold& m = c.manifolds[mi];
            bool overlaps = false;
            for (std::uint32_t i = 0; i < m.pointCount; ++i) overlaps = overlaps || m.points[i].depth > kPushShareDepth;
            anyOverlaps = anyOverlaps || overlaps;
            if (overlaps && mi < 32) overlapping |= std::uint32_t{1} << mi;
            if (mi < 16) points |= lanePoints(m) << (2 * mi);
        }
        ends.overlapping = overlapping;
        ends.points = points;
        // The points' reach from each body's step-start centre
        // (pushOutGrown's gate): a point lies midway between the
        // two surface points, each within its body's extent of its
        // centre, |depth| apart along the normal, so |p - comA| <=
        // extentA + |depth|; the largest |depth| here (no distance
        // computed a point). The slack covers a surface point's
        // offset across the normal and the rounding.
        // Only with the push-out on (WorldDef::pushOutGrownOverlaps),
        // out of line: off, this loop is the one without it.
        if (pushOut) {
            const Real farthest = largestDepth(c, ends.manifolds);
            contactReach_[k] = {Real(1.01) * (w.params[dA].extent + 2 * farthest) + Real(1e-3),
                                Real(1.01) * (w.params[dB].extent + 2 * farthest) + Real(1e-3)};
        }
        if (c.firstTouch == FirstTouch::NotYet) {
            c.firstTouch = anyOverlaps ? FirstTouch::Deep : FirstTouch::Shallow;
        }
        return ends.manifolds;
    };
    forRanges(contactBlocks, kContactBlocksPerTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t block = begin; block < end; ++block) {
            const std::size_t first = block * kContactsPerBlock;
            const std::size_t last = std::min(first + kContactsPerBlock, candidateCount);
            std::uint32_t total = 0;
            if (maybe == nullptr) {
                for (std::size_t k = first; k < last; ++k) {
                    // The contact twice as far ahead, so that reading its
                    // manifolds' address for the prefetch below does not wait
                    // (it did: 30 % of this function's samples on ConvexVsMesh).
                    if (k + 2 * kManifoldsAhead < last) {
                        __builtin_prefetch(&contacts[contactAt(k + 2 * kManifoldsAhead)].manifolds);
                    }
                    if (k + kManifoldsAhead < last) prefetchFirstManifold(contacts[contactAt(k + kManifoldsAhead)]);
                    ContactEnds& ends = contactEnds_[k];
                    ends.manifolds = 0;
                    total += visit(k, ends);
                }
            } else {
                // The slots whose bit is set, in order (the prefetches run
                // ahead over them); the others have no manifold and a zero
                // grownBy: their entries as reading them would write.
                std::uint16_t read[kContactsPerBlock];
                std::size_t count = 0;
                for (std::size_t word = first >> 6; word < (last + 63) >> 6; ++word) {
                    std::uint64_t bits = maybe[word];
                    while (bits != 0) {
                        const std::size_t k = word * 64 + static_cast<std::size_t>(std::countr_zero(bits));
                        bits &= bits - 1;
                        if (k < last) read[count++] = static_cast<std::uint16_t>(k - first);
                    }
                }
                std::size_t j = 0;
                for (std::size_t k = first; k < last; ++k) {
                    ContactEnds& ends = contactEnds_[k];
                    ends.manifolds = 0;
                    if (j == count || first + read[j] != k) {
                        ends.grown = false;
                        continue;
                    }
                    if (j + 2 * kManifoldsAhead < count) __builtin_prefetch(&contacts[first + read[j + 2 * kManifoldsAhead]].manifolds);
                    if (j + kManifoldsAhead < count) prefetchFirstManifold(contacts[first + read[j + kManifoldsAhead]]);
                    ++j;
                    total += visit(k, ends);
                }
            }
            pendingBlockStart_[block + 1] = total;
        }
    });
    pendingBlockStart_[0] = 0;
    for (std::size_t block = 0; block < contactBlocks; ++block) pendingBlockStart_[block + 1] += pendingBlockStart_[block];
    pending_.resize(pendingBlockStart_[contactBlocks]);
    overlapping_.resize(pending_.size());
    laneKeys_.resize(pending_.size());
    if (pushOut) pairReach_.resize(pending_.size());
    forRanges(contactBlocks, kContactBlocksPerTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t block = begin; block < end; ++block) {
            const std::size_t first = block * kContactsPerBlock;
            const std::size_t last = std::min(first + kContactsPerBlock, candidateCount);
            std::uint32_t out = pendingBlockStart_[block];
            if (out == pendingBlockStart_[block + 1]) continue;  // nothing solved here (a sleeping part of the world)
            for (std::size_t k = first; k < last; ++k) {
                const ContactEnds& ends = contactEnds_[k];
                if (ends.manifolds == 0) continue;
                const std::size_t ci = contactAt(k);
                for (std::uint32_t mi = 0; mi < ends.manifolds; ++mi) {
                    bool overlaps = ((ends.overlapping >> (mi & 31)) & 1) != 0;
                    if (mi >= 32) {  // past the mask (a compound or mesh pair with many manifolds)
                        const CachedManifold& m = contacts[ci].manifolds[mi];
                        overlaps = false;
                        for (std::uint32_t i = 0; i < m.pointCount; ++i) overlaps = overlaps || m.points[i].depth > kPushShareDepth;
                    }
                    overlapping_[out] = static_cast<std::uint8_t>((overlaps ? 1 : 0) | (ends.grown ? 2 : 0));
                    if (pushOut) pairReach_[out] = contactReach_[k];
                    const std::uint32_t points = mi < 16 ? (ends.points >> (2 * mi)) & 3 : lanePoints(contacts[ci].manifolds[mi]);
                    laneKeys_[out] = laneKey(points, ends.bodyA);
                    pending_[out++] = {static_cast<std::uint32_t>(ci), mi, ends.bodyA, ends.bodyB};
                }
            }
        }
    });
    // The bodies whose deltas the kernels read (BodyStore::contactDeltas).
    for (const PendingConstraint& p : pending_) {
        w.contactDeltas[p.bodyA] = 1;
        w.contactDeltas[p.bodyB] = 1;
    }
}

void ContactSolver::finishPrepare(ContactManager& manager) {
    const ContactArray& contacts = manager.contacts();
    placeInColourSlots();
    if (wide_) {
        packWide(contacts);
        return;
    }
    constraints_.resize(pending_.size());
    forRanges(pending_.size(), kConstraintsPerTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t pi = begin; pi < end; ++pi) {
            const PendingConstraint& pc = pending_[pi];
            buildConstraint(contacts[pc.contact], pc, constraints_[slotOf_[pi]]);
        }
    });
}

// The coloured constraints into blocks of kWideLanes, colour by colour (a
// block never mixes colours, so its lanes share no dynamic body). Each block
// is built kWideLanes constraints at a time (buildBlock, contact_wide.cpp:
// the twin of buildConstraint, the same bits); the wide path keeps
// no scalar copy (that copy, written and read back once per step, was 5 % of
// sphere_pile). The overflow colour stays scalar in constraints_: its
// constraints may share bodies.
//
// Blocks are built in parallel, one block per index: a block's lanes, its
// lane count and its flags are written by one call only, and every constraint
// depends only on its contact and the solver bodies, so the blocks are the
// same bits for any thread count. (Building per pending constraint instead
// would have two threads writing lanes of the same block: false sharing, and
// the block-wide flags would need a second pass.)
void ContactSolver::packWide(const ContactArray& contacts) {
    WideBlocks& wideBlocks = *blocks_;
    const auto kWideLanes = static_cast<std::uint32_t>(wideBlocks.lanes());
    blockStart_.assign(kColourCount + 1, 0);
    std::size_t blocks = 0;
    // The colours past the last one with blocks add no stage: addPassStages
    // stops there (a ten-body step has one colour of 32, and walked all 32 in
    // each of its 15 passes: 4.8 % of its instructions).
    colourEnd_ = 0;
    for (std::uint32_t c = 0; c < kColourCount; ++c) {
        blockStart_[c] = static_cast<std::uint32_t>(blocks);
        const std::uint32_t n = colourStart_[c + 1] - colourStart_[c];
        blocks += (n + kWideLanes - 1) / kWideLanes;
        if (n != 0) colourEnd_ = c + 1;
    }
    blockStart_[kColourCount] = static_cast<std::uint32_t>(blocks);
    wideBlocks.resize(blocks);
    blockColour_.resize(blocks);
    for (std::uint32_t c = 0; c < kColourCount; ++c) {
        for (std::uint32_t b = blockStart_[c]; b < blockStart_[c + 1]; ++b) blockColour_[b] = c;
    }

    // The lanes' inputs staged in colour order first, in pending (contact)
    // order: the contacts are read one after another and the manifold reads
    // are independent, so many are in flight at once. Built straight from the
    // manifolds in colour order, the block build waited on the first read of
    // each lane's manifold for ~40 % of its time (perf, 10,000-sphere pile).
    const std::uint32_t colouredCount = colourStart_[kColourCount];
    placeInLanes();
    laneSources_.resize(colouredCount);
    forRanges(pending_.size(), kConstraintsPerTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t pi = begin; pi < end; ++pi) {
            // The contacts and manifolds ahead (random in memory: the manifold
            // reads below were most of this loop's samples on ConvexVsMesh).
            if (pi + 2 * kManifoldsAhead < end) prefetchContact(contacts[pending_[pi + 2 * kManifoldsAhead].contact]);
            if (pi + kManifoldsAhead < end) {
                const PendingConstraint& ahead = pending_[pi + kManifoldsAhead];
                prefetchManifold(contacts[ahead.contact].manifolds.data() + ahead.manifold);
            }
            const std::uint32_t slot = slotOf_[pi];
            if (slot >= colouredCount) continue;
            const PendingConstraint& pc = pending_[pi];
            const Contact& contact = contacts[pc.contact];
            const CachedManifold& m = contact.manifolds[pc.manifold];
            LaneSource& lane = laneSources_[laneOfSlot_[slot]];
            lane.normal = m.normal;
            lane.pointCount = m.pointCount;
            lane.frictionImpulse = m.frictionImpulse;
            lane.twistImpulse = m.twistImpulse;
            lane.rollingImpulse = m.rollingImpulse;
            lane.bodyA = pc.bodyA;
            lane.bodyB = pc.bodyB;
            lane.contact = pc.contact;
            lane.manifoldIndex = pc.manifold;
            lane.friction = contact.friction;
            lane.restitution = contact.restitution;
            lane.rollingResistance = contact.rollingResistance;
            lane.pushMax = pushLimit(pc, contact);
            for (std::uint32_t i = 0; i < m.pointCount; ++i) {
                lane.points[i].position = m.points[i].position;
                lane.points[i].depth = m.points[i].depth;
                lane.points[i].normalImpulse = m.points[i].normalImpulse;
            }
            const Softness soft = softnessOf(pc);
            lane.biasRate = soft.biasRate;
            lane.massScale = soft.massScale;
            lane.impulseScale = soft.impulseScale;
        }
    });
    forRanges(blocks, kBlocksPerBuildTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t bi = begin; bi < end; ++bi) {
            const std::uint32_t c = blockColour_[bi];
            const std::uint32_t first = colourStart_[c] + (static_cast<std::uint32_t>(bi) - blockStart_[c]) * kWideLanes;
            const std::uint32_t last = std::min<std::uint32_t>(first + kWideLanes, colourStart_[c + 1]);
            wideBlocks.build(bi, laneSources_.data() + first, static_cast<int>(last - first), store_->state.data(),
                             store_->startCom.data());
        }
    });

    const std::uint32_t overflow = colourStart_[kColourCount];
    constraints_.resize(pending_.size() - overflow);
    forRanges(constraints_.size(), kConstraintsPerTask, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const PendingConstraint& pc = pending_[pendingOfSlot_[overflow + i]];
            buildConstraint(contacts[pc.contact], pc, constraints_[i]);
        }
    });
}

// Each coloured slot's lane: the colour's slots ordered by their lane key
// (kLaneKeys), in slot order among equal keys. A colour's constraints share
// no dynamic body, so the order of its lanes, and how they are cut into
// blocks, does not change a bit of the results (contact_wide.hpp); only the
// blocks' work. Serial: two counting passes over the slots, ~15 instructions
// a constraint.
void ContactSolver::placeInLanes() {
    laneOfSlot_.resize(colourStart_[kColourCount]);
    if (!laneOrder_) {  // the slots' own order (setLaneOrder(false): the tests' reference)
        for (std::uint32_t s = 0; s < colourStart_[kColourCount]; ++s) laneOfSlot_[s] = s;
        return;
    }
    for (std::uint32_t c = 0; c < kColourCount; ++c) {
        const std::uint32_t first = colourStart_[c], last = colourStart_[c + 1];
        std::uint32_t cursor[kLaneKeys] = {};
        for (std::uint32_t s = first; s < last; ++s) ++cursor[laneKeys_[pendingOfSlot_[s]]];
        std::uint32_t at = first;
        for (std::uint32_t& k : cursor) {
            const std::uint32_t count = k;
            k = at;
            at += count;
        }
        for (std::uint32_t s = first; s < last; ++s) laneOfSlot_[s] = cursor[laneKeys_[pendingOfSlot_[s]]]++;
    }
}

std::size_t ContactSolver::largestColourBlocks() const {
    std::size_t largest = 0;
    for (std::size_t c = 0; c + 1 < blockStart_.size(); ++c) {
        largest = std::max<std::size_t>(largest, blockStart_[c + 1] - blockStart_[c]);
    }
    return largest;
}

void ContactSolver::buildConstraint(const Contact& c, const PendingConstraint& pc, ContactConstraint& k) const {
    // Only the contact and the solver's own arrays: a static body is the zero
    // body 0 with a zero centre (its anchor rB is then only ever multiplied by
    // its zero velocity and zero inverse inertia).
    const std::uint32_t ia = pc.bodyA, ib = pc.bodyB, ci = pc.contact, mi = pc.manifold;
    const SolverBody& ba = store_->state[ia];
    const SolverBody& bb = store_->state[ib];
    const Vec3 comA = store_->startCom[ia], comB = store_->startCom[ib];
    const Real friction = c.friction;
    const Real restitution = c.restitution;
    const Real rolling = c.rollingResistance;
    {
            const CachedManifold& m = c.manifolds[mi];
            k.bodyA = ia;
            k.bodyB = ib;
            k.contact = ci;
            k.manifold = mi;
            k.pointCount = m.pointCount;
            k.friction = friction;
            k.restitution = restitution;
            k.rollingResistance = rolling;
            k.pushMax = pushLimit(pc, c);
            k.softness = softnessOf(pc);
            const Vec3 n = m.normal;
            k.normal = n;
            orthonormalBasis(n, k.tangent1, k.tangent2);

            Vec3 centre;
            for (std::uint32_t pi = 0; pi < m.pointCount; ++pi) {
                const CachedPoint& src = m.points[pi];
                ConstraintPoint& cp = k.points[pi];
                cp.rA = src.position - comA;
                cp.rB = src.position - comB;
                cp.rAxn = cross(cp.rA, n);
                cp.rBxn = cross(cp.rB, n);
                cp.angA = ba.invI * cp.rAxn;
                cp.angB = bb.invI * cp.rBxn;
                cp.baseSeparation = -src.depth;
                const Real kn = ba.invMass + bb.invMass + dot(cp.rAxn, cp.angA) + dot(cp.rBxn, cp.angB);
                cp.normalMass = kn > 0 ? 1 / kn : 0;
                cp.normalImpulse = src.normalImpulse;
                cp.maxNormalImpulse = 0;
                cp.stepImpulse = 0;
                const Vec3 dv = bb.v + cross(bb.w, cp.rB) - ba.v - cross(ba.w, cp.rA);
                cp.relativeVelocity = dot(n, dv);
                cp.approachVelocity = cp.relativeVelocity;
                centre += src.position;
            }
            centre *= Real(1) / static_cast<Real>(m.pointCount);
            const Vec3 rAc = centre - comA;
            const Vec3 rBc = centre - comB;
            Real radius = 0;
            for (std::uint32_t pi = 0; pi < m.pointCount; ++pi) radius += length(m.points[pi].position - centre);
            k.twistRadius = radius / static_cast<Real>(m.pointCount);

            // 2x2 tangent effective mass at the centre, inverted.
            k.rAc1 = cross(rAc, k.tangent1);
            k.rAc2 = cross(rAc, k.tangent2);
            k.rBc1 = cross(rBc, k.tangent1);
            k.rBc2 = cross(rBc, k.tangent2);
            k.angA1 = ba.invI * k.rAc1;
            k.angA2 = ba.invI * k.rAc2;
            k.angB1 = bb.invI * k.rBc1;
            k.angB2 = bb.invI * k.rBc2;
            const Real mSum = ba.invMass + bb.invMass;
            const Real t11 = mSum + dot(k.rAc1, k.angA1) + dot(k.rBc1, k.angB1);
            const Real t12 = dot(k.rAc1, k.angA2) + dot(k.rBc1, k.angB2);
            const Real t22 = mSum + dot(k.rAc2, k.angA2) + dot(k.rBc2, k.angB2);
            const Real det = t11 * t22 - t12 * t12;
            k.k11 = k.k12 = k.k22 = 0;
            if (det > 0) {
                const Real inv = 1 / det;
                k.k11 = t22 * inv;
                k.k12 = -t12 * inv;
                k.k22 = t11 * inv;
            }
            k.twistA = ba.invI * n;
            k.twistB = bb.invI * n;
            const Real kt = dot(n, k.twistA) + dot(n, k.twistB);
            k.twistMass = kt > 0 ? 1 / kt : 0;
            k.tangentImpulse1 = dot(m.frictionImpulse, k.tangent1);
            k.tangentImpulse2 = dot(m.frictionImpulse, k.tangent2);
            k.stepTangent1 = 0;
            k.stepTangent2 = 0;
            k.twistImpulse = m.twistImpulse;
            if (rolling > 0) {
                const Mat3 kr = ba.invI + bb.invI;
                k.rollingMass = std::fabs(determinant(kr)) > 0 ? inverse(kr) : Mat3::zero();
                k.rollingImpulse = m.rollingImpulse;
            } else {
                k.rollingMass = Mat3::zero();
                k.rollingImpulse = {};
            }
    }
}

void ContactSolver::colourGreedy() {
    // The colours, and the slots placeInColourSlots gives them, are a function
    // of the constraints' ends alone: a step whose list has the ends of the
    // last one's (a scene at rest, the same contacts step after step) keeps
    // them. (Colouring and placing were 1,500 of a ten-body step's 87,000
    // instructions.)
    const SolverBody* bodies = store_->state.data();
    const std::size_t n = pending_.size();
    bool same = colourStart_.size() == kColourCount + 2 && colouredEnds_.size() == n;
    for (std::size_t i = 0; i < n && same; ++i) same = colouredEnds_[i] == constraintEnds(pending_[i], bodies);
    coloursKept_ = same;
    if (!same) {
        colourGreedily<kColourCount>(
            n, store_->state.size(), [&](std::size_t i) { return constraintEnds(pending_[i], bodies); }, colourBits_,
            colourOf_, colourStart_);
        colouredEnds_.resize(n);
        for (std::size_t i = 0; i < n; ++i) colouredEnds_[i] = constraintEnds(pending_[i], bodies);
    }
    // Each body's deep overlaps, for pushLimit (serial here, beside the
    // first force evaluation, like the colouring).
    overlapCount_.assign(store_->state.size(), 0);
    for (std::size_t i = 0; i < pending_.size(); ++i) {
        if ((overlapping_[i] & 1) == 0) continue;
        ++overlapCount_[pending_[i].bodyA];
        ++overlapCount_[pending_[i].bodyB];
    }
}

[[gnu::always_inline]] inline Softness ContactSolver::softnessOf(const PendingConstraint& pc) const {
    // Against static (and kinematic: infinite mass) bodies the stiffer softness.
    const bool stiff = store_->state[pc.bodyA].invMass == 0 || store_->state[pc.bodyB].invMass == 0;
    return stiff ? staticSoftness_ : contactSoftness_;
}

// Why shared: each overlapping contact asks its pair to separate at up to
// pushMax, and those demands add up through the bodies. N boxes created at one
// spot form N(N-1)/2 contacts whose demands, chained through the bodies, threw
// them apart (100 boxes: 50 m/s, 110x the energy of every box moving at
// pushMax): the relax pass, one Gauss-Seidel sweep, cannot take that back out
// of so coupled a system. With each contact's limit divided by the number of
// deep overlaps (deeper than kPushShareDepth) of its busier dynamic end, the
// demands on any body sum to at most pushMax. Resting contacts do not count.
// Why only pairs born deep (Contact::firstTouch): bodies driven into each
// other (the rocks a kinematic pusher jams together, fast landings) touched
// first at a resting depth. Shared, their push-out fell behind the drive: in
// the junkyard two rocks squeezed from five sides were pushed out at 1.5 m/s
// while the jam moved at 3.7, went deeper, shared more, and stayed 0.9 m into
// each other to the end. Their overlaps are the solver's own lag, not a heap
// to open, so they keep the whole speed (as every Box2D-style solver does).
[[gnu::always_inline]] inline Real ContactSolver::pushLimit(const PendingConstraint& pc, const Contact& c) const {
    if (c.firstTouch != FirstTouch::Deep) return pushMax_;
    const auto countOf = [&](std::uint32_t body) {
        return store_->state[body].invMass > 0 ? overlapCount_[body] : 0u;  // static and kinematic ends are never pushed
    };
    const std::uint32_t count = std::max(countOf(pc.bodyA), countOf(pc.bodyB));
    return count > 1 ? pushMax_ / static_cast<Real>(count) : pushMax_;
}

void ContactSolver::placeInColourSlots() {
    if (coloursKept_) return;  // the same colours: the same slots (colourGreedy)
    const std::size_t n = pending_.size();
    // Constraint i goes to slot colourStart[c] + (how many constraints before i
    // have colour c), and pendingOfSlot_ is the inverse. In parallel over fixed
    // blocks of constraints: each block counts its colours, the counts are
    // summed in block order into each block's cursors, and each block fills its
    // own slots: the slots of one pass in constraint order.
    const std::size_t blocks = (n + kSlotsPerBlock - 1) / kSlotsPerBlock;
    slotCursor_.resize(blocks * (kColourCount + 1));
    forRanges(blocks, 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t block = begin; block < end; ++block) {
            std::uint32_t* counts = slotCursor_.data() + block * (kColourCount + 1);
            std::fill(counts, counts + kColourCount + 1, 0u);
            const std::size_t last = std::min(n, (block + 1) * kSlotsPerBlock);
            for (std::size_t i = block * kSlotsPerBlock; i < last; ++i) ++counts[colourOf_[i]];
        }
    });
    for (std::uint32_t c = 0; c <= kColourCount; ++c) {
        std::uint32_t cursor = colourStart_[c];
        for (std::size_t block = 0; block < blocks; ++block) {
            std::uint32_t& slot = slotCursor_[block * (kColourCount + 1) + c];
            const std::uint32_t count = slot;
            slot = cursor;
            cursor += count;
        }
    }
    slotOf_.resize(n);
    pendingOfSlot_.resize(n);
    forRanges(blocks, 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t block = begin; block < end; ++block) {
            std::uint32_t* cursor = slotCursor_.data() + block * (kColourCount + 1);
            const std::size_t last = std::min(n, (block + 1) * kSlotsPerBlock);
            for (std::size_t i = block * kSlotsPerBlock; i < last; ++i) {
                const std::uint32_t slot = cursor[colourOf_[i]]++;
                slotOf_[i] = slot;
                pendingOfSlot_[slot] = static_cast<std::uint32_t>(i);
            }
        }
    });
}

// The per-body loops below run in ranges of bodies (solver index - 1) across
// the task system: each body is read and written by one call only.
template <class Fn>
void ContactSolver::forRanges(std::size_t count, std::uint32_t minRange, Fn&& fn) const {
    if (count == 0) return;
    if (tasks_ == nullptr || tasks_->workerCount() == 1 || count < 2 * std::size_t{minRange}) {
        fn(std::size_t{0}, count);
        return;
    }
    tasks_->parallelFor(static_cast<std::uint32_t>(count), minRange,
                        [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
                            fn(std::size_t{begin}, std::size_t{end});
                        });
}

// A stage's arg: the pass (bits 0-1) and whether it is the overflow/scalar part (bit 2).
constexpr std::uint32_t kOverflowStage = 4;

std::uint32_t ContactSolver::maxPassStages() { return kColourCount + 1; }

void ContactSolver::addPassStages(StagedParallel& stages, std::uint32_t kind, Pass pass) const {
    const auto p = static_cast<std::uint32_t>(pass);
    if (wide_) {
        for (std::uint32_t c = 0; c < colourEnd_; ++c) {
            const std::uint32_t first = blockStart_[c], count = blockStart_[c + 1] - first;
            stages.add(kind, p, first, count, kBlocksPerTask);
        }
    }
    if (!constraints_.empty()) stages.add(kind, p | kOverflowStage, 0, 1, 1);
}

bool ContactSolver::takePassStagesChanged() {
    // [wide, overflow, colour end, blockStart_[0 .. colour end]]: addPassStages reads nothing else.
    const std::uint32_t colours = wide_ ? colourEnd_ : 0;
    const std::size_t size = 3 + (wide_ ? std::size_t{colours} + 1 : 0);
    const std::uint32_t head[3] = {wide_ ? 1u : 0u, constraints_.empty() ? 0u : 1u, colours};
    bool changed = lastPassStages_.size() != size;
    for (std::size_t i = 0; i < 3 && !changed; ++i) changed = lastPassStages_[i] != head[i];
    for (std::size_t i = 3; i < size && !changed; ++i) changed = lastPassStages_[i] != blockStart_[i - 3];
    if (changed) {
        lastPassStages_.assign(head, head + 3);
        if (wide_) lastPassStages_.insert(lastPassStages_.end(), blockStart_.begin(), blockStart_.begin() + colours + 1);
    }
    return changed;
}

void ContactSolver::runPassStage(std::uint32_t arg, std::uint32_t first, std::uint32_t last) {
    const auto pass = static_cast<Pass>(arg & 3);
    if ((arg & kOverflowStage) != 0) {
        if (pass == Pass::WarmStart) {
            warmStartRange(0, constraints_.size());
        } else if (pass == Pass::Solve) {
            solvePass<true>(0, constraints_.size());
        } else {
            solvePass<false>(0, constraints_.size());
        }
        return;
    }
    if (pass == Pass::WarmStart) {
        blocks_->warmStart(first, last - first, store_->state.data());
    } else {
        blocks_->solve(first, last - first, store_->state.data(), pass == Pass::Solve, invH_);
    }
}

void ContactSolver::warmStartRange(std::size_t begin, std::size_t end) {
    for (std::size_t ki = begin; ki < end; ++ki) {
        ContactConstraint& k = constraints_[ki];
        SolverBody& a = store_->state[k.bodyA];
        SolverBody& b = store_->state[k.bodyB];
        Vec3 vA = a.v, wA = a.w, vB = b.v, wB = b.w;
        Real total = 0;
        for (std::uint32_t i = 0; i < k.pointCount; ++i) {
            const ConstraintPoint& cp = k.points[i];
            total += cp.normalImpulse;
            wA -= cp.angA * cp.normalImpulse;
            wB += cp.angB * cp.normalImpulse;
        }
        const Vec3 P = k.normal * total + k.tangent1 * k.tangentImpulse1 + k.tangent2 * k.tangentImpulse2;
        vA -= P * a.invMass;
        vB += P * b.invMass;
        wA -= k.angA1 * k.tangentImpulse1 + k.angA2 * k.tangentImpulse2 + k.twistA * k.twistImpulse +
              a.invI * k.rollingImpulse;
        wB += k.angB1 * k.tangentImpulse1 + k.angB2 * k.tangentImpulse2 + k.twistB * k.twistImpulse +
              b.invI * k.rollingImpulse;
        a.v = vA;
        a.w = wA;
        b.v = vB;
        b.w = wB;
    }
}

template <bool useBias>
void ContactSolver::solvePass(std::size_t begin, std::size_t end) {
    for (std::size_t ki = begin; ki < end; ++ki) {
        ContactConstraint& k = constraints_[ki];
        SolverBody& a = store_->state[k.bodyA];
        SolverBody& b = store_->state[k.bodyB];
        Vec3 vA = a.v, wA = a.w, vB = b.v, wB = b.w;
        const Real mA = a.invMass, mB = b.invMass;
        const Vec3 dp = b.dp - a.dp;
        const Vec3 n = k.normal;
        const Softness soft = useBias ? k.softness : Softness{0, 1, 0};
        Real totalNormal = 0;
        for (std::uint32_t i = 0; i < k.pointCount; ++i) {
            ConstraintPoint& cp = k.points[i];
            // Separation now, from the bodies' motion since the step's start:
            // s = s0 + n.(dpB + (RB - I) rB - dpA - (RA - I) rA), with the rotations
            // to first order, (R - I) r = theta x r, and n.(theta x r) = theta.(r x n):
            // four dot products on precomputed data instead of two rotations per
            // point (the error is theta^2 |r| / 2: 0.25 mm for a half-metre lever
            // turning 0.03 rad in a step). Measured in docs/benchmarks.md.
            const Real s = cp.baseSeparation + dot(n, dp) + dot(b.dtheta, cp.rBxn) - dot(a.dtheta, cp.rAxn);
            Real bias = 0, massScale = 1, impulseScale = 0;
            if (s > 0) {
                bias = s * invH_;  // speculative: allow exactly the approach that closes the gap
            } else if constexpr (useBias) {
                bias = std::max(soft.biasRate * s, -k.pushMax);
                massScale = soft.massScale;
                impulseScale = soft.impulseScale;
            }
            const Real vn = dot(n, vB - vA) + dot(wB, cp.rBxn) - dot(wA, cp.rAxn);
            Real impulse = -cp.normalMass * massScale * (vn + bias) - impulseScale * cp.normalImpulse;
            const Real newImpulse = std::max(cp.normalImpulse + impulse, Real(0));
            impulse = newImpulse - cp.normalImpulse;
            // The approach speed for restitution: the speed when the point first
            // pushes, which includes the gravity of the sub-steps before the
            // impact (the speed at the step's start misses up to g dt: a ball
            // with e = 1 lost ~7 % of its height per bounce; now ~1.5 %).
            if (impulse > 0 && cp.maxNormalImpulse == 0) {
                if constexpr (useBias) cp.relativeVelocity = std::min(cp.relativeVelocity, vn);
                cp.approachVelocity = std::min(cp.approachVelocity, vn);
            }
            cp.normalImpulse = newImpulse;
            cp.maxNormalImpulse = std::max(cp.maxNormalImpulse, impulse);
            // The relax pass is a sub-step's last: what its warm start, solve and
            // relax applied adds up to the accumulated impulse now.
            if constexpr (!useBias) cp.stepImpulse += newImpulse;
            totalNormal += newImpulse;
            const Vec3 P = n * impulse;
            vA -= P * mA;
            wA -= cp.angA * impulse;
            vB += P * mB;
            wB += cp.angB * impulse;
        }

        // Tangent friction at the manifold's centre, clamped to the friction disc.
        {
            const Vec3 dv = vB - vA;
            const Real v1 = dot(dv, k.tangent1) + dot(wB, k.rBc1) - dot(wA, k.rAc1);
            const Real v2 = dot(dv, k.tangent2) + dot(wB, k.rBc2) - dot(wA, k.rAc2);
            const Real old1 = k.tangentImpulse1, old2 = k.tangentImpulse2;
            Real new1 = old1 - (k.k11 * v1 + k.k12 * v2);
            Real new2 = old2 - (k.k12 * v1 + k.k22 * v2);
            const Real maxFriction = k.friction * totalNormal;
            const Real mag2 = new1 * new1 + new2 * new2;
            if (mag2 > maxFriction * maxFriction) {
                const Real scale = maxFriction / std::sqrt(mag2);
                new1 *= scale;
                new2 *= scale;
            }
            k.tangentImpulse1 = new1;
            k.tangentImpulse2 = new2;
            if constexpr (!useBias) {
                k.stepTangent1 += new1;
                k.stepTangent2 += new2;
            }
            const Real d1 = new1 - old1, d2 = new2 - old2;
            const Vec3 P = k.tangent1 * d1 + k.tangent2 * d2;
            vA -= P * mA;
            wA -= k.angA1 * d1 + k.angA2 * d2;
            vB += P * mB;
            wB += k.angB1 * d1 + k.angB2 * d2;

            // Twist friction about the normal, clamped by mu N times the points' mean lever arm.
            const Real maxTwist = maxFriction * k.twistRadius;
            const Real wn = dot(wB - wA, n);
            const Real oldT = k.twistImpulse;
            const Real newT = std::clamp(oldT - k.twistMass * wn, -maxTwist, maxTwist);
            k.twistImpulse = newT;
            const Real dT = newT - oldT;
            wA -= k.twistA * dT;
            wB += k.twistB * dT;
        }

        // Rolling resistance: an angular velocity constraint clamped by rr * radius * N.
        if (k.rollingResistance > 0) {
            const Real maxRolling = k.rollingResistance * totalNormal;
            const Vec3 oldR = k.rollingImpulse;
            Vec3 newR = oldR - k.rollingMass * (wB - wA);
            const Real mag2 = lengthSquared(newR);
            if (mag2 > maxRolling * maxRolling) newR *= maxRolling / std::sqrt(mag2);
            k.rollingImpulse = newR;
            const Vec3 T = newR - oldR;
            wA -= a.invI * T;
            wB += b.invI * T;
        }

        a.v = vA;
        a.w = wA;
        b.v = vB;
        b.w = wB;
    }
}

void ContactSolver::applyRestitution() {
    if (wide_) blocks_->restitution(store_->state.data(), restitutionThreshold_);
    for (ContactConstraint& k : constraints_) {
        if (k.restitution == 0) continue;
        SolverBody& a = store_->state[k.bodyA];
        SolverBody& b = store_->state[k.bodyB];
        Vec3 vA = a.v, wA = a.w, vB = b.v, wB = b.w;
        for (std::uint32_t i = 0; i < k.pointCount; ++i) {
            ConstraintPoint& cp = k.points[i];
            // Only points that approached fast enough and actually pushed.
            if (cp.relativeVelocity > -restitutionThreshold_ || cp.maxNormalImpulse == 0) continue;
            const Real vn = dot(k.normal, vB - vA) + dot(wB, cp.rBxn) - dot(wA, cp.rAxn);
            Real impulse = -cp.normalMass * (vn + k.restitution * cp.relativeVelocity);
            const Real newImpulse = std::max(cp.normalImpulse + impulse, Real(0));
            impulse = newImpulse - cp.normalImpulse;
            cp.normalImpulse = newImpulse;
            cp.maxNormalImpulse = std::max(cp.maxNormalImpulse, impulse);
            cp.stepImpulse += impulse;
            const Vec3 P = k.normal * impulse;
            vA -= P * a.invMass;
            wA -= cp.angA * impulse;
            vB += P * b.invMass;
            wB += cp.angB * impulse;
        }
        a.v = vA;
        a.w = wA;
        b.v = vB;
        b.w = wB;
    }
}

// Why by position: the soft contact pushes an overlap out at up to
// contactPushMaxVelocity (3 m/s, 5 cm a step at 60 Hz), and what it pushes
// stays in the bodies as separating velocity (the relax pass removes only
// approach). A faster push bounced: two free boxes pushed out of a 10 cm
// overlap by a push limit growing with the depth left each other at 1.9 m/s
// (docs/benchmarks.md, `pile`). Moving the positions leaves the velocities
// alone, like a split impulse's pseudo-velocity. Why only grown pairs:
// resting contacts under a load (a heavy box on a light one rests 1-3 cm
// deep; a 1:10^6 stack sinks on by design: docs/solver.md, "Mass ratios")
// keep their depth from step to step and stay the soft spring's; a pair
// that gets 10-20 cm deeper within one step (a hull struck into a
// neighbour, a landing the solver did not hold) is the solver's or the
// narrow phase's lag, not a load.
void ContactSolver::pushOutGrown(BodyStore& w, const ContactManager& manager, std::span<const JointConstraint> joints) {
    if (!pushOut_) return;
    const ContactArray& contacts = manager.contacts();
    // The gate: a point's predicted depth changes within the step by
    // -dot(n, dpB - dpA) - dot(dthetaB, cross(rB, n)) + dot(dthetaA, cross(rA, n)),
    // at most |dpB - dpA| + |dthetaA| reachA + |dthetaB| reachB (|n| = 1;
    // reach: a bound on the contact's points' |r|, from prepare). Under the
    // trigger, the deepest point grew by no more than that from its start
    // depth, nor from zero if it started apart, so `within` is false; with no
    // `unseen` bit the pair is skipped and its manifold not read. The bound
    // is compared with 0.9 of the trigger: the rounding of the depths (a few
    // ulps of centimetres and metres) never reaches the 0.5 mm left.
    constexpr Real kGateGrowth = Real(0.9) * kGrowthPushOut;
    const auto provablyStill = [&](std::size_t i) {
        const PendingConstraint& pc = pending_[i];
        if ((overlapping_[i] & 2) != 0) return false;
        // |dtheta| bounded by its 1-norm (no square root).
        const auto turned = [](const Vec3& t) { return std::abs(t.x) + std::abs(t.y) + std::abs(t.z); };
        const SolverBody& a = w.state[pc.bodyA];
        const SolverBody& b = w.state[pc.bodyB];
        const Real room = kGateGrowth - (turned(a.dtheta) * pairReach_[i].a + turned(b.dtheta) * pairReach_[i].b);
        // NaN anywhere: false, the full test decides.
        return room > 0 && lengthSquared(b.dp - a.dp) < room * room;
    };
    // Every pair's answer before any move (pass 1 reuses it until a body
    // moves); none to push: nothing else to do (the passes below would skip
    // every pair).
    if (pushOutGate_) {
        still_.resize(pending_.size());
        bool any = false;
        for (std::size_t i = 0; i < pending_.size(); ++i) {
            still_[i] = provablyStill(i) ? 1 : 0;
            any = any || still_[i] == 0;
        }
        if (!any) return;
    }
    // Per solver body: the last pass (from 1) that moved it. A later pass
    // revisits only the pairs with a body moved in the pass before or this one.
    pushedPass_.assign(w.state.size(), 0);
    // Per solver body: it touches a dynamic body more than kPushOutMassRatio
    // times heavier (the pass below leaves its pairs alone).
    loaded_.assign(w.state.size(), 0);
    for (const PendingConstraint& pc : pending_) {
        const Real ia = w.state[pc.bodyA].invMass, ib = w.state[pc.bodyB].invMass;
        if (ia > 0 && ib > 0 && std::max(ia, ib) > kPushOutMassRatio * std::min(ia, ib)) {
            loaded_[ia > ib ? pc.bodyA : pc.bodyB] = 1;
        }
    }
    // Per solver body: an end of a joint. It is held as a static end is (its
    // pair's other body takes the whole move and the whole stop; two such
    // ends: the pair is left to the soft contact). Moved by position, a
    // jointed body opened its joint until the next step's solve, and the
    // approach impulse changed a velocity the joint solve had just made
    // consistent (docs/solver.md, "Grown overlaps").
    const bool anyJoint = !joints.empty();
    if (anyJoint) {
        jointed_.assign(w.state.size(), 0);
        for (const JointConstraint& j : joints) {
            jointed_[j.bodyA] = 1;
            jointed_[j.bodyB] = 1;
        }
    }
    for (std::uint32_t pass = 1; pass <= kPushOutPasses; ++pass) {
        bool moved = false;
        for (std::size_t i = 0; i < pending_.size(); ++i) {
            // The first pass reads every manifold the gate lets through
            // (random in memory, as in store): their lines requested ahead
            // (the contacts further ahead when the gate is off). Without it
            // the misses were 70 % of this function's time.
            bool still = false;  // pass 1 with the gate: provablyStill(i)
            if (pass == 1 && pushOutGate_) {
                // Valid while neither body has moved in this pass.
                const PendingConstraint& here = pending_[i];
                still = still_[i] != 0 && (!moved || (pushedPass_[here.bodyA] != pass && pushedPass_[here.bodyB] != pass));
                if (!still && moved && still_[i] != 0) still = provablyStill(i);
                if (i + kManifoldsAhead < pending_.size() && still_[i + kManifoldsAhead] == 0) {
                    const PendingConstraint& ahead = pending_[i + kManifoldsAhead];
                    prefetchContact(contacts[ahead.contact]);
                    prefetchManifold(contacts[ahead.contact].manifolds.data() + ahead.manifold);
                }
            } else if (pass == 1) {
                if (i + 2 * kManifoldsAhead < pending_.size()) prefetchContact(contacts[pending_[i + 2 * kManifoldsAhead].contact]);
                if (i + kManifoldsAhead < pending_.size()) {
                    const PendingConstraint& ahead = pending_[i + kManifoldsAhead];
                    prefetchManifold(contacts[ahead.contact].manifolds.data() + ahead.manifold);
                }
            }
            const PendingConstraint& pc = pending_[i];
            if (pass > 1 && pushedPass_[pc.bodyA] + 1 < pass && pushedPass_[pc.bodyB] + 1 < pass) continue;
            SolverBody& a = w.state[pc.bodyA];
            SolverBody& b = w.state[pc.bodyB];
            // Pairs of dynamic bodies of very different masses, and any pair
            // of a body touching a much heavier one, are left to the soft
            // contact (loaded_). A move shared by inverse mass puts nearly
            // all of it on the light body, which it drives into whatever is
            // under it, and the passes shuttle the overlap between the two
            // pairs (a 300 kg box on a 1 kg one on the ground went through
            // both); a light box held on the ground by position while a 10^6
            // times heavier one sank into it was passed through whole (the
            // two boxes ended in one place, where no contact reports a depth).
            if (loaded_[pc.bodyA] != 0 || loaded_[pc.bodyB] != 0) continue;
            const Real invMassA = anyJoint && jointed_[pc.bodyA] != 0 ? Real(0) : a.invMass;
            const Real invMassB = anyJoint && jointed_[pc.bodyB] != 0 ? Real(0) : b.invMass;
            const Real invMass = invMassA + invMassB;
            if (!(invMass > 0)) continue;
            if (pushOutGate_ && (pass == 1 ? still : provablyStill(i))) continue;
            const CachedManifold& m = contacts[pc.contact].manifolds[pc.manifold];
            // The deepest point now, to first order in the bodies' motion since
            // the step's start (as store's depthAfter), and at the step's start.
            const Vec3 n = m.normal;
            const Vec3 dp = b.dp - a.dp;
            Real deepest = -std::numeric_limits<Real>::infinity();
            Real deepestStart = -std::numeric_limits<Real>::infinity();
            for (std::uint32_t k = 0; k < m.pointCount; ++k) {
                const CachedPoint& p = m.points[k];
                const Vec3 rA = p.position - w.startCom[pc.bodyA];
                const Vec3 rB = p.position - w.startCom[pc.bodyB];
                const Real depth = p.depth - dot(n, dp) - dot(b.dtheta, cross(rB, n)) + dot(a.dtheta, cross(rA, n));
                deepest = std::max(deepest, depth);
                deepestStart = std::max(deepestStart, p.depth);
            }
            // Grown unseen (this step's narrow phase found it: grownBy) or
            // within this step (from its start, or from touching if it
            // started apart).
            const bool unseen = (overlapping_[i] & 2) != 0;
            const bool within = deepest - std::max(deepestStart, Real(0)) > kGrowthPushOut;
            if (!unseen && !within) continue;
            const Real excess = deepest - kGrowthPushOutKeep;
            if (!(excess > kPushOutTolerance)) continue;
            // Along the normal, shared by the inverse masses (a static or
            // kinematic end does not move): every point's depth falls by excess.
            // And the centres' approach along the normal taken out by an
            // equal and opposite impulse (never a separating one): moved
            // back without it, a body sinking under a load the soft contact
            // had not yet taken kept its speed, sank again the next step,
            // and gained speed step after step (a 300 kg box on a 1 kg one
            // went through it).
            const Real approach = dot(n, b.v - a.v);
            const Real stop = approach < 0 ? approach : Real(0);
            if (invMassA > 0) {
                const Real share = invMassA / invMass;
                const Vec3 move = n * (-excess * share);
                w.pose[pc.bodyA].com += move;
                a.dp += move;
                a.v += n * (stop * share);
                pushedPass_[pc.bodyA] = pass;
            }
            if (invMassB > 0) {
                const Real share = invMassB / invMass;
                const Vec3 move = n * (excess * share);
                w.pose[pc.bodyB].com += move;
                b.dp += move;
                b.v -= n * (stop * share);
                pushedPass_[pc.bodyB] = pass;
            }
            moved = true;
        }
        if (!moved) break;
    }
}

void ContactSolver::store(ContactManager& manager) {
    ContactArray& contacts = manager.contacts();
    // Every lane and constraint writes its own manifold: in parallel.
    if (wide_) {
        const WideBlocks& wideBlocks = *blocks_;
        forRanges(wideBlocks.size(), kBlocksPerBuildTask, [&](std::size_t begin, std::size_t end) {
            // One block at a time with its manifolds prefetched (random in memory, as in packWide).
            for (std::size_t bi = begin; bi < end; ++bi) {
                for (std::size_t ahead : {bi + kPrefetchBlocks, bi + kPrefetchBlocks / 2}) {
                    if (ahead >= wideBlocks.size()) continue;
                    const std::uint32_t *contact = nullptr, *manifold = nullptr;
                    std::uint32_t laneCount = 0;
                    wideBlocks.laneTargets(ahead, contact, manifold, laneCount);
                    for (std::uint32_t l = 0; l < laneCount; ++l) {
                        if (ahead == bi + kPrefetchBlocks) {
                            prefetchContact(contacts[contact[l]]);
                        } else {
                            prefetchManifold(contacts[contact[l]].manifolds.data() + manifold[l]);
                        }
                    }
                }
                wideBlocks.store(bi, 1, store_->state.data(), contacts.data());
            }
        });
    }
    forRanges(constraints_.size(), kConstraintsPerTask,
              [&](std::size_t begin, std::size_t end) { storeRange(contacts, begin, end); });
}

void ContactSolver::storeRange(ContactArray& contacts, std::size_t begin, std::size_t end) const {
    for (std::size_t ki = begin; ki < end; ++ki) {
        const ContactConstraint& k = constraints_[ki];
        CachedManifold& m = contacts[k.contact].manifolds[k.manifold];
        const SolverBody& a = store_->state[k.bodyA];
        const SolverBody& b = store_->state[k.bodyB];
        const Vec3 dp = b.dp - a.dp;
        for (std::uint32_t i = 0; i < k.pointCount; ++i) {
            const ConstraintPoint& cp = k.points[i];
            CachedPoint& dst = m.points[i];
            dst.normalImpulse = cp.normalImpulse;
            dst.maxNormalImpulse = cp.maxNormalImpulse;
            dst.stepNormalImpulse = cp.stepImpulse;
            dst.approachVelocity = cp.approachVelocity;
            dst.depthAfter = -(cp.baseSeparation + dot(k.normal, dp) + dot(b.dtheta, cp.rBxn) - dot(a.dtheta, cp.rAxn));
        }
        m.frictionImpulse = k.tangent1 * k.tangentImpulse1 + k.tangent2 * k.tangentImpulse2;
        m.twistImpulse = k.twistImpulse;
        m.rollingImpulse = k.rollingImpulse;
        m.stepFrictionImpulse = k.tangent1 * k.stepTangent1 + k.tangent2 * k.stepTangent2;
    }
}

}  // namespace fulcrum::detail
