#include "contacts/contact_manager.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>

#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"
#include "contacts/recycled_points.hpp"
#include "fulcrum/task_system.hpp"
#include "solver/joint_data.hpp"

namespace fulcrum::detail {

// List keys: contact index * 2 + which end of the contact (0: slotA, 1: slotB)
// the list runs through, so walking a body's list reads links_ only, never the
// ~100-byte contacts (a cache miss each: that was 1 ms of a 10,000-sphere step).
namespace {
constexpr std::uint32_t kNoKey = UINT32_MAX;
constexpr std::uint32_t contactOfKey(std::uint32_t key) { return key >> 1; }
constexpr std::uint32_t endOfKey(std::uint32_t key) { return key & 1; }
// Below this many moved proxies a step reinserts them one by one, whatever
// their share of the moving tree (update(), step 1).
constexpr std::uint32_t kMinBulkRebuild = 256;
}  // namespace

namespace {

struct PairRule {
    const BodyStore* w;
    const JointPairFilter* joints;
    bool operator()(std::uint32_t slotA, std::uint32_t slotB) const { return mayCollide(*w, *joints, slotA, slotB); }
};

constexpr Real kMatchDistance = Real(0.02);
// Recycling thresholds: 1 mm and 0.1 degree of relative motion since the last
// collide() (a 0.5 m lever moves 1 mm per 0.1 degree).
constexpr Real kRecycleDistance = Real(0.001);
const Real kRecycleCosHalfAngle = dmath::cos(Real(0.5) * Real(0.1) * Real(3.14159265) / 180);

// Piece recycling against a static mesh (contact.hpp, PiecePose;
// docs/narrow-phase.md, "Recycling a piece's mesh contacts"). A piece whose
// manifolds were made with speculative distance m0 left out only triangles
// farther than m0 from it; having moved by at most `moved` since (its centre's
// travel plus its turn times its half diagonal), it is still farther than
// m0 - moved from them. Its step may bring it closer by its approach (the
// margin's motion part, SpeculativeReach), so its manifolds are recycled
// only while moved + approach + kPieceRecyclePad <= m0: no triangle left out
// can be reached this step, with kPieceRecyclePad to spare. Its own points
// keep their anchors and the normal stays the triangle's, so the error of a
// recycled depth (a turn bringing a point the manifold dropped lower) is
// bounded by the motion, which kPieceRecycleMax caps at 1 cm (at Box3D's 5 cm
// a rolling hex log gained 0.05 J in a step, MeshSettle.LogGainsNoEnergyWhileRolling).
// A piece the narrow phase looked at and found nothing for is proved as far
// as m0 from every triangle: the same test skips it while it would find
// nothing again.
constexpr Real kPieceRecyclePad = Real(0.005);
constexpr Real kPieceRecycleMax = Real(0.01);

bool isRecyclablePiece(ShapeType t) { return t == ShapeType::Box || t == ShapeType::ConvexHull; }

// The centre and half diagonal of bounds.
void centreAndRadius(const AABB& b, Vec3& centre, Real& radius) {
    centre = (b.min + b.max) * Real(0.5);
    radius = length(b.max - centre);
}

// The apart cache skips a pair only while it is proved this much farther
// apart than the margin: far above the narrow phase's rounding (a few
// micrometres at a few hundred metres from the origin), as GJK's early stop
// (kBeyondPad in collide_convex.cpp) for the same reason.
constexpr Real kApartPad = Real(1e-3);

// Neither a compound nor rounded: the shapes whose collide() reports a
// proved distance when it rejects the pair (ManifoldBuffer::apartBy; so
// does a compound pair's, narrow_phase.cpp).
bool isPlainConvex(const Shape& s) {
    const ShapeType t = s.type();
    return (t == ShapeType::Sphere || t == ShapeType::Box || t == ShapeType::Capsule || t == ShapeType::Cylinder ||
            t == ShapeType::ConvexHull) &&
           s.convexRadius() == 0;
}

// How far from its origin any point of the shape is (apartMotionBound's
// reach): a compound's by its local box's farthest corner.
Real shapeReach(const Shape& s) {
    if (s.type() == ShapeType::Compound) {
        const AABB b = s.localBounds();
        return length(max(abs(b.min), abs(b.max)));
    }
    return detail::makeConvex(s, Transform{}).boundingRadius();
}

bool isAwakeMover(const BodyParams& p) { return p.type != BodyType::Static && p.awake; }

bool isRound(ShapeType t) { return t == ShapeType::Sphere || t == ShapeType::Capsule; }

// A sphere whose centre of mass is its centre (the default): collideSpheres.
bool isCentredSphere(const BodyStore& w, std::uint32_t d) {
    const Vec3& c = w.params[d].localCom;
    return w.cold[d].shape.type() == ShapeType::Sphere && c.x == 0 && c.y == 0 && c.z == 0;
}

// Friction as the geometric mean, restitution as the maximum, rolling
// resistance as the larger coefficient times the larger round radius.
void mixMaterial(const BodyStore& w, Contact& c, std::uint32_t dA, std::uint32_t dB) {
    const BodyParams& pa = w.params[dA];
    const BodyParams& pb = w.params[dB];
    c.friction = std::sqrt(pa.friction * pb.friction);
    c.restitution = std::max(pa.restitution, pb.restitution);
    const Real rolling = std::max(pa.rollingResistance, pb.rollingResistance);
    c.rollingResistance = 0;
    if (rolling > 0) {
        Real radius = 0;
        if (isRound(w.cold[dA].shape.type())) radius = std::max(radius, w.cold[dA].shape.radius());
        if (isRound(w.cold[dB].shape.type())) radius = std::max(radius, w.cold[dB].shape.radius());
        c.rollingResistance = rolling * radius;
    }
}

// What the parallel pass of update() found for one contact.
constexpr std::uint8_t kTouching = 1;    // collided: the new touching state
constexpr std::uint8_t kWakeA = 2;       // collided: body A sleeps and must wake
constexpr std::uint8_t kWakeB = 4;
constexpr std::uint8_t kCollided = 8;    // collided (touching state valid)
constexpr std::uint8_t kSeparated = 16;  // fat boxes apart: destroy
constexpr std::uint8_t kTouchChanged = 32;  // collided, and the touching state flips

// A sleeping body near an awake one wakes (with its island) as soon as they
// have contact points, so the solver sees both: update() wakes the flagged ends.
std::uint8_t wakeFlags(const BodyParams& pa, const BodyParams& pb) {
    std::uint8_t flags = 0;
    if (pa.type != BodyType::Static && !pa.awake) flags |= kWakeA;
    if (pb.type != BodyType::Static && !pb.awake) flags |= kWakeB;
    return flags;
}

// A fresh narrow-phase point into a cached one: the geometry only; the
// impulses are the caller's (kept for a matched point, zero for a new one).
inline void copyGeometry(CachedPoint& dst, const ContactPoint& src) {
    dst.position = src.position;
    dst.localA = src.localAnchorA;
    dst.localB = src.localAnchorB;
    dst.depth = src.depth;
    dst.depthAfter = src.depth;
    dst.featureId = src.featureId;
}

}  // namespace

// A point y of B (|y| <= reachB) moves by |dp| + |R(q1) y - R(q0) y| and, with
// unit quaternions, R(q1) y - R(q0) y = (q1 - q0) y q1* + q0 y (q1 - q0)*, at
// most 2 |q1 - q0| |y| (q and -q are the same turn: the nearer sign). The
// quaternion difference, not 1 - dot, keeps tiny turns measurable in floats.
Real apartMotionBound(const Transform& from, const Transform& to, Real reachA, Real reachB) {
    const Quat& q0 = from.q;
    const Quat& q1 = to.q;
    const Real sign = dot(q0, q1) < 0 ? Real(-1) : Real(1);
    const Real dw = q1.w - sign * q0.w, dx = q1.x - sign * q0.x, dy = q1.y - sign * q0.y, dz = q1.z - sign * q0.z;
    const Real turn = 2 * std::sqrt(dw * dw + dx * dx + dy * dy + dz * dz);
    // The view of the shape with the smaller reach (a ground box's corners
    // swing far with the smallest turn of the body on it).
    if (reachB <= reachA) return length(to.p - from.p) + turn * reachB;
    return length(inverseRotate(to.q, to.p) - inverseRotate(from.q, from.p)) + turn * reachA;
}

bool mayCollide(const BodyStore& w, const JointPairFilter& joints, std::uint32_t slotA, std::uint32_t slotB) {
    const BodyParams& pa = w.params[w.bodySlots[slotA].dense];
    const BodyParams& pb = w.params[w.bodySlots[slotB].dense];
    if (pa.isSensor && pb.isSensor) return false;
    // Per-body joint lists (solver/joints/joint_graph.hpp): the scan of every
    // joint here was ~20 % of the ragdoll pile's step.
    return !joints.keepsApart(slotA, slotB);
}

void ContactManager::addBody(BodyStore& w, std::uint32_t dense) {
    const std::uint32_t slot = w.denseToSlot[dense];
    // A new slot is nearly always the next one: appended, not resized (the
    // fill's memset call, twice a body, was 28 M of a million static boxes'
    // creation).
    if (proxyOfSlot_.size() == slot) {
        proxyOfSlot_.push_back(kNullProxy);
    } else if (proxyOfSlot_.size() < slot) {
        proxyOfSlot_.resize(slot + 1, kNullProxy);
    }
    if (headOfSlot_.size() == slot) {
        headOfSlot_.push_back(UINT32_MAX);
    } else if (headOfSlot_.size() < slot) {
        headOfSlot_.resize(slot + 1, UINT32_MAX);
    }
    const BodyParams& p = w.params[dense];
    const AABB box = w.cold[dense].shape.bounds(w.originTransform(dense));
    proxyOfSlot_[slot] = broad_.createProxy(box, p.type, p.filter, slot);
}

void ContactManager::reserve(std::size_t bodyCount, std::int64_t maxContactPairs, std::vector<ContactReport>& reports) {
    // No more than the pair limit lets live (a small explicit limit).
    const std::size_t wantContacts =
        std::min<std::size_t>(4 * bodyCount, contactPairLimit(maxContactPairs, bodyCount));
    if (contacts_.size() < wantContacts) {
        // Geometric growth of the capacity (not of the size): reserving twice
        // the size on every body creation reallocated every time, quadratic in
        // the body count (4% of a 4000-body run was spent here).
        if (contacts_.capacity() < wantContacts) contacts_.reserve(std::max(wantContacts, 2 * contacts_.capacity()));
        while (contacts_.size() < wantContacts) {
            contacts_.emplace_back();
            Contact& c = contacts_.back();
            c.manifolds.reserve(1);
            c.nextFree = freeContact_;
            freeContact_ = static_cast<std::uint32_t>(contacts_.size() - 1);
        }
    }
    const std::size_t wantEvents = 2 * bodyCount;
    for (std::vector<ContactEvent>* v : {&beginEvents, &endEvents, &sensorBeginEvents, &sensorEndEvents}) {
        if (v->capacity() < wantEvents) v->reserve(2 * wantEvents);
    }
    broad_.reservePairs(8 * std::bit_ceil(bodyCount));
    ensureWorkers(1);
    if (movedFrom_.capacity() < bodyCount) movedFrom_.reserve(std::max(bodyCount, 2 * movedFrom_.capacity()));
    if (contactFlags_.capacity() < contacts_.size()) contactFlags_.reserve(contacts_.capacity());
    if (reportStart_.capacity() < contacts_.size() + 1) reportStart_.reserve(contacts_.capacity() + 1);
    if (links_.capacity() < contacts_.size()) links_.reserve(contacts_.capacity());
    links_.resize(contacts_.size());
    if (activeContacts_.capacity() < contacts_.size()) activeContacts_.reserve(contacts_.capacity());
    if (newContacts_.capacity() < 8 * std::bit_ceil(bodyCount)) newContacts_.reserve(8 * std::bit_ceil(bodyCount));
    const std::size_t wantMarks = contacts_.capacity() / 64 + 1;
    if (marks_.capacity() < wantMarks) marks_.reserve(wantMarks);
    marks_.resize(contacts_.size() / 64 + 1, 0);
    if (awakeMarks_.capacity() < wantMarks) awakeMarks_.reserve(wantMarks);
    awakeMarks_.resize(contacts_.size() / 64 + 1, 0);
    if (aliveBits_.capacity() < wantMarks) aliveBits_.reserve(wantMarks);
    if (flaggedWords_.capacity() < wantMarks) flaggedWords_.reserve(wantMarks);
    aliveBits_.resize(contacts_.size() / 64 + 1, 0);
    if (mayHaveManifolds_.capacity() < wantMarks) mayHaveManifolds_.reserve(wantMarks);
    mayHaveManifolds_.resize(contacts_.size() / 64 + 1, 0);
    if (proxyMoves_.capacity() < bodyCount) proxyMoves_.reserve(std::max(bodyCount, 2 * proxyMoves_.capacity()));
    const std::size_t wantReports = 2 * bodyCount;
    if (reports.size() < wantReports) {
        if (reports.capacity() < wantReports) reports.reserve(std::max(wantReports, 2 * reports.capacity()));
        while (reports.size() < wantReports) {
            reports.emplace_back();
            reports.back().points.reserve(4);
            reports.back().pointNormalImpulses.reserve(4);
        }
    }
}

void ContactManager::ensureWorkers(std::size_t workers) {
    if (narrow_.size() >= workers) return;
    narrow_.resize(workers);
    for (NarrowScratch& n : narrow_) {
        // Grow the narrow phase's output to a few manifolds now rather than in a step.
        if (n.manifolds.capacity() >= 4) continue;
        n.manifolds.reserve(4);
        for (int i = 0; i < 4; ++i) n.buffer.push();
        n.buffer.clear();
    }
}

void ContactManager::removeBody(BodyStore& w, std::uint32_t slot) {
    const auto remove = [&](std::uint32_t i) {
        Contact& c = contacts_[i];
        // The partner loses its support: wake it (Box2D does the same).
        const std::uint32_t other = c.slotA == slot ? c.slotB : c.slotA;
        if (c.touching && !c.sensor) w.wakeBody(w.bodySlots[other].dense);
        destroyContact(w, i);
    };
    if (linksRebuild_) {
        for (std::uint32_t i = 0; i < contacts_.size(); ++i) {
            const Contact& c = contacts_[i];
            if (c.alive && (c.slotA == slot || c.slotB == slot)) remove(i);
        }
    } else {
        // The body's contacts from its list, not a scan of every contact slot
        // (rain: a ragdoll's 14 bodies each scanned ~17,000 contacts, 5 % of
        // the step's instructions where a column is replaced; the `rain10`
        // block of docs/benchmarks.md). In ascending order, as the scan went,
        // so the partners wake and the free list comes out the same.
        resetScratch_.clear();
        for (std::uint32_t key = headOfSlot_[slot]; key != kNoKey; key = links_[contactOfKey(key)].next[endOfKey(key)]) {
            resetScratch_.push_back(contactOfKey(key));
        }
        std::sort(resetScratch_.begin(), resetScratch_.end());
        for (const std::uint32_t i : resetScratch_) remove(i);
    }
    broad_.destroyProxy(proxyOfSlot_[slot]);
    proxyOfSlot_[slot] = kNullProxy;
}

void ContactManager::bodyTeleported(BodyStore& w, std::uint32_t dense) {
    const std::uint32_t slot = w.denseToSlot[dense];
    const AABB box = w.cold[dense].shape.bounds(w.originTransform(dense));
    broad_.moveProxy(proxyOfSlot_[slot], box, Vec3::zero());
    // A teleported static body wakes nothing it merely left, yet its contacts
    // with sleeping bodies may now have apart fat boxes: look at every contact.
    if (w.params[dense].type == BodyType::Static) visitAll_ = true;
}

void ContactManager::resetPairs(BodyStore& w, std::uint32_t slot) {
    // The body's own contacts from its list, not a scan of every contact slot
    // (createJoint calls this once per joint: the scan made building the
    // 30^3 joint grid of bench_joints quadratic, 36 % of its run). Destroyed
    // in ascending order, as the scan did, so the free list and the indices
    // of later contacts come out the same.
    if (linksRebuild_) rebuildLinks();
    resetScratch_.clear();
    for (std::uint32_t key = headOfSlot_[slot]; key != kNoKey; key = links_[contactOfKey(key)].next[endOfKey(key)]) {
        resetScratch_.push_back(contactOfKey(key));
    }
    std::sort(resetScratch_.begin(), resetScratch_.end());
    for (const std::uint32_t i : resetScratch_) destroyContact(w, i);
    broad_.refreshProxy(proxyOfSlot_[slot]);
}

std::uint32_t ContactManager::createContact(BodyStore& w, std::uint32_t slotA, std::uint32_t slotB, ProxyId proxyA,
                                            ProxyId proxyB) {
    std::uint32_t index;
    if (freeContact_ != UINT32_MAX) {
        index = freeContact_;
        freeContact_ = contacts_[index].nextFree;
    } else {
        index = static_cast<std::uint32_t>(contacts_.size());
        contacts_.emplace_back();
        contacts_.back().manifolds.reserve(1);
        links_.resize(contacts_.size());
        marks_.resize(contacts_.size() / 64 + 1, 0);
        awakeMarks_.resize(contacts_.size() / 64 + 1, 0);
        aliveBits_.resize(contacts_.size() / 64 + 1, 0);
        mayHaveManifolds_.resize(contacts_.size() / 64 + 1, 0);
    }
    Contact& c = contacts_[index];
    // Canonical order: the smaller slot is A, so events name bodies the same way every run.
    if (slotB < slotA) {
        std::swap(slotA, slotB);
        std::swap(proxyA, proxyB);
    }
    ++liveContacts_;
    c.alive = true;
    c.slotA = slotA;
    c.slotB = slotB;
    c.proxyA = proxyA;
    c.proxyB = proxyB;
    c.touching = false;
    c.solved = false;
    c.firstTouch = FirstTouch::NotYet;
    c.nextFree = UINT32_MAX;
    c.hasPose = false;
    c.apartBy = 0;
    c.reachA = c.reachB = 0;
    c.sensor = w.params[w.bodySlots[slotA].dense].isSensor || w.params[w.bodySlots[slotB].dense].isSensor;
    c.manifolds.clear();
    c.triangleAxes.clear();
    c.gjkWarmStart = GjkWarmStart{};
    c.meshCandidates.clear();
    c.piecePoses.clear();
    if (!linksRebuild_) {
        linkContact(index);
        setAliveBit(index, true);
    }
    markContact(index);  // a new contact is visited in the update that made it
    return index;
}

void ContactManager::linkContact(std::uint32_t index) {
    const Contact& c = contacts_[index];
    ContactLinks& l = links_[index];
    const std::uint32_t slots[2] = {c.slotA, c.slotB};
    for (std::uint32_t e = 0; e < 2; ++e) {
        std::uint32_t& head = headOfSlot_[slots[e]];
        const std::uint32_t key = index * 2 + e;
        l.prev[e] = kNoKey;
        l.next[e] = head;
        if (head != kNoKey) links_[contactOfKey(head)].prev[endOfKey(head)] = key;
        head = key;
    }
}

void ContactManager::unlinkContact(std::uint32_t index) {
    const Contact& c = contacts_[index];
    ContactLinks& l = links_[index];
    const std::uint32_t slots[2] = {c.slotA, c.slotB};
    for (std::uint32_t e = 0; e < 2; ++e) {
        const std::uint32_t prev = l.prev[e], next = l.next[e];
        if (prev != kNoKey) {
            links_[contactOfKey(prev)].next[endOfKey(prev)] = next;
        } else {
            headOfSlot_[slots[e]] = next;
        }
        if (next != kNoKey) links_[contactOfKey(next)].prev[endOfKey(next)] = prev;
        l.prev[e] = l.next[e] = kNoKey;
    }
}

void ContactManager::rebuildLinks() {
    headOfSlot_.assign(proxyOfSlot_.size(), UINT32_MAX);
    links_.assign(contacts_.size(), ContactLinks{});
    marks_.resize(contacts_.size() / 64 + 1, 0);
    awakeMarks_.resize(contacts_.size() / 64 + 1, 0);
    aliveBits_.assign(contacts_.size() / 64 + 1, 0);
    mayHaveManifolds_.assign(contacts_.size() / 64 + 1, 0);
    liveContacts_ = 0;
    for (std::uint32_t i = 0; i < contacts_.size(); ++i) {
        if (contacts_[i].alive) {
            linkContact(i);
            setAliveBit(i, true);
            if (!contacts_[i].manifolds.empty()) mayHaveManifolds_[i >> 6] |= std::uint64_t{1} << (i & 63);
            ++liveContacts_;
        }
    }
    linksRebuild_ = false;
}

void ContactManager::gatherActiveContacts(const BodyStore& w) {
    activeContacts_.clear();
    // With most bodies awake, every live contact: read from the alive bitmap
    // (kept by create/destroy), not from the ~100-byte contacts (a cache miss
    // each; the pass over the contacts was 1.5 % of a 10,000-sphere pile's
    // collapse, all of it serial). The same contacts as walking the lists:
    // those whose bodies sleep are left unchanged by the update either way.
    if (visitAll_ || 2 * w.awakeBodies.size() >= w.motion.size()) {
        for (std::size_t word = 0; word < aliveBits_.size(); ++word) {
            std::uint64_t bits = aliveBits_[word];
            while (bits != 0) {
                const auto bit = static_cast<std::uint32_t>(std::countr_zero(bits));
                bits &= bits - 1;
                activeContacts_.push_back(static_cast<std::uint32_t>(word * 64 + bit));
            }
        }
        std::fill(marks_.begin(), marks_.end(), 0);
        visitAll_ = false;
        return;
    }
    collectAwakeContacts(w, marks_, activeContacts_);
}

void ContactManager::collectAwakeContacts(const BodyStore& w, std::vector<std::uint64_t>& marks,
                                          std::vector<std::uint32_t>& out) const {
    for (const std::uint32_t d : w.awakeBodies) {
        for (std::uint32_t key = headOfSlot_[w.denseToSlot[d]]; key != kNoKey;) {
            const std::uint32_t i = contactOfKey(key);
            marks[i >> 6] |= std::uint64_t(1) << (i & 63);
            key = links_[i].next[endOfKey(key)];
        }
    }
    // Ascending contact order from the bitmap (the order of a full pass), clearing it.
    for (std::size_t word = 0; word < marks.size(); ++word) {
        std::uint64_t bits = marks[word];
        if (bits == 0) continue;
        marks[word] = 0;
        bits &= aliveBits_[word];
        while (bits != 0) {
            const auto bit = static_cast<std::uint32_t>(std::countr_zero(bits));
            bits &= bits - 1;
            out.push_back(static_cast<std::uint32_t>(word * 64 + bit));
        }
    }
}

bool ContactManager::contactsOfAwakeBodies(const BodyStore& w, std::vector<std::uint32_t>& out) {
    if (linksRebuild_) return false;
    if (2 * w.awakeBodies.size() >= w.motion.size()) {
        // Most bodies awake: every live contact, from the alive bitmap, when
        // they are fewer than half the slots. The slots keep the peak's count
        // (Jolt's HighSpeed: 20,024 slots from its first steps, ~500 live
        // after), and the solver's pass over every slot read one 248-byte
        // contact each only to find it dead. The same contacts, ascending, as
        // that pass keeps (a dead one gives no constraint).
        if (!liveContactList_ || 2 * std::size_t{liveContacts_} >= contacts_.size()) return false;
        out.clear();
        for (std::size_t word = 0; word < aliveBits_.size(); ++word) {
            std::uint64_t bits = aliveBits_[word];
            while (bits != 0) {
                const auto bit = static_cast<std::uint32_t>(std::countr_zero(bits));
                bits &= bits - 1;
                out.push_back(static_cast<std::uint32_t>(word * 64 + bit));
            }
        }
        return true;
    }
    out.clear();
    collectAwakeContacts(w, awakeMarks_, out);
    return true;
}

void ContactManager::destroyContact(BodyStore& w, std::uint32_t index) {
    Contact& c = contacts_[index];
    if (!linksRebuild_) {
        unlinkContact(index);
        setAliveBit(index, false);
    }
    if (c.touching) {
        const BodyId a = {c.slotA, w.bodySlots[c.slotA].generation};
        const BodyId b = {c.slotB, w.bodySlots[c.slotB].generation};
        if (!c.sensor) {
            endEvents.push_back({a, b});
        } else {
            const bool aIsSensor = w.params[w.bodySlots[c.slotA].dense].isSensor;
            sensorEndEvents.push_back(aIsSensor ? ContactEvent{a, b} : ContactEvent{b, a});
        }
    }
    c.alive = false;
    c.touching = false;
    c.manifolds.clear();
    c.triangleAxes.clear();
    c.gjkWarmStart = GjkWarmStart{};
    c.meshCandidates.clear();
    c.nextFree = freeContact_;
    freeContact_ = index;
    --liveContacts_;
}

// Sphere against sphere (both centred), nearly every pair of a sphere pile: the exact contact
// (sphereContact, as collide() computes it: the same point and depth)
// costs less than recycling it, which moves two surface points and the
// normal with the bodies (six quaternion rotations with the relative pose).
// So these pairs are never recycled (hasPose stays false) and keep no body-frame
// points. The one point (feature 0) keeps its warm-start impulse, as the
// matching of the general path does. Measured on sphere_pile: see
// docs/solver.md ("Sphere pairs").
std::uint8_t ContactManager::collideSpheres(const BodyStore& w, Contact& c, std::uint32_t dA, std::uint32_t dB,
                                            Real margin) const {
    c.hasPose = false;
    const Vec3 ca = w.motion[dA].com, cb = w.motion[dB].com;  // centred spheres: the origin
    const Real ra = w.cold[dA].shape.radius(), rb = w.cold[dB].shape.radius();
    SphereContact sc;
    // And addContact's test: no point farther apart than the margin.
    if (!sphereContact(ca, ra, cb, rb, Vec3{0, 1, 0}, margin, sc) || sc.depth < -margin) {
        c.manifolds.clear();
        return kCollided;
    }
    const Real depth = sc.depth;
    Real impulse = 0;
    if (!c.manifolds.empty() && c.manifolds[0].childA == 0 && c.manifolds[0].childB == 0) {
        impulse = c.manifolds[0].points[0].normalImpulse;  // pointCount is 1: empty manifolds are not kept
    } else {
        c.manifolds.clear();
        c.manifolds.emplace_back();  // capacity 1 is reserved with the contact
    }
    CachedManifold& out = c.manifolds[0];
    out.normal = sc.normal;
    out.pointCount = 1;
    CachedPoint& p = out.points[0];
    p.position = (sc.pointA + sc.pointB) * Real(0.5);
    p.depth = depth;
    p.depthAfter = depth;
    p.featureId = 0;
    p.normalImpulse = impulse;
    p.maxNormalImpulse = 0;
    return static_cast<std::uint8_t>(kCollided | (depth > -kTouchSlop ? kTouching : 0) |
                                     wakeFlags(w.params[dA], w.params[dB]));
}

void ContactManager::mixMaterials(const BodyStore& w) {
    for (Contact& c : contacts_) {
        if (c.alive) mixMaterial(w, c, w.bodySlots[c.slotA].dense, w.bodySlots[c.slotB].dense);
    }
}

std::uint8_t ContactManager::collideContact(const BodyStore& w, Contact& c, Real dt, NarrowScratch& ns) const {
    ManifoldBuffer& buffer = ns.buffer;
    std::vector<CachedManifold>& scratch = ns.manifolds;
    const std::uint32_t dA = w.bodySlots[c.slotA].dense;
    const std::uint32_t dB = w.bodySlots[c.slotB].dense;
    const BodyParams& pa = w.params[dA];
    const BodyParams& pb = w.params[dB];
    const BodyMotion& ma = w.motion[dA];
    const BodyMotion& mb = w.motion[dB];
    c.grownBy = 0;  // set below by the one-manifold path only (Contact::grownBy)

    if (!c.sensor && isCentredSphere(w, dA) && isCentredSphere(w, dB)) {
        mixMaterial(w, c, dA, dB);
        // Spinning does not move a centred sphere's surface: only the linear
        // approach counts (the angular term below would add |w| r dt).
        return collideSpheres(w, c, dA, dB, speculativeMargin_ + length(mb.v - ma.v) * dt);
    }
    const PairPoses poses = pairPoses({ma.com, ma.q, pa.localCom}, {mb.com, mb.q, pb.localCom});
    const Transform& xA = poses.a;
    const Transform& xB = poses.b;
    const Transform& rel = poses.relative;
    mixMaterial(w, c, dA, dB);

    // Contact recycling (Box2D, 2026): if B hardly moved relative to A since the
    // last collide(), the manifold's features are still the right ones; move
    // the stored surface points with the bodies and recompute the depths instead
    // of running the narrow phase. Measured on pyramid20: see docs/benchmarks.md.
    if (!c.sensor && c.hasPose && lengthSquared(rel.p - c.relativePose.p) < kRecycleDistance * kRecycleDistance &&
        std::fabs(dot(rel.q, c.relativePose.q)) > kRecycleCosHalfAngle) {
        bool touching = false;
        for (CachedManifold& m : c.manifolds) {
            touching = refreshRecycledManifold(m, xA, xB) || touching;
        }
        return kCollided | (touching ? kTouching : 0);
    }
    // Speculative distance: the base margin plus how far the surfaces can
    // approach in one step, the spin's part per compound child
    // (SpeculativeReach). Recycled contacts above never need it.
    SpeculativeReach reach;
    if (!c.sensor) {
        reach.base = speculativeMargin_;
        reach.linear = length(mb.v - ma.v);
        reach.dt = dt;
        // The spin axes (reach.axisA, axisB) only for a compound pair, below:
        // no other pair reads them.
        if (pa.type != BodyType::Static) {
            reach.spinA = length(ma.w);
            reach.extentA = pa.extent;
        }
        if (pb.type != BodyType::Static) {
            reach.spinB = length(mb.w);
            reach.extentB = pb.extent;
        }
    }
    const Shape& shapeA = w.cold[dA].shape;
    const Shape& shapeB = w.cold[dB].shape;
    const bool compound = shapeA.type() == ShapeType::Compound || shapeB.type() == ShapeType::Compound;
    const Real margin = reach.margin(reach.extentA, reach.extentB);  // the whole bodies' (the same sums as before)
    // The apart cache: the last narrow phase proved the shapes at least
    // c.apartBy apart at c.relativePose, and since then B has moved in A's
    // frame (or A in B's) by at most `moved`. While what is left exceeds the
    // margin by kApartPad, the narrow phase would reject the pair again (its
    // own rounding is far below the pad): the same answer, without it. The
    // bound moves on to this pose, as relativePose does when the narrow phase
    // runs, so the recycling above decides as it did without the cache. Only
    // plain convex pairs and compound pairs ever hold a bound (a compound's
    // children's margins are at most the whole body's, so the test holds for each).
    if (!c.sensor && c.apartBy > 0) {
        const Real moved = apartMotionBound(c.relativePose, rel, c.reachA, c.reachB);
        if (c.apartBy - moved > margin + kApartPad) {
            c.apartBy -= moved;
            c.relativePose = rel;
            return kCollided;
        }
    }
    c.hasPose = true;
    c.relativePose = rel;
    std::uint8_t flags = 0;
    // A box or hull against a mesh reads and rewrites the pair's triangle
    // axis cache (TriangleAxisCache, collision/manifold.hpp).
    const bool meshPair = !c.sensor && (shapeA.type() == ShapeType::Mesh || shapeB.type() == ShapeType::Mesh || compound);
    TriangleAxisCache& axes = buffer.triangleAxes();
    if (meshPair) {
        ns.triangleAxes.clear();
        axes = {c.triangleAxes.data(), c.triangleAxes.size(), &ns.triangleAxes, 0};
    }
    // Two hulls, or a box and a hull, start GJK from their last run's
    // simplex (GjkWarmStart, collision/manifold.hpp), the contact's own state.
    const ShapeType typeA = shapeA.type(), typeB = shapeB.type();
    const bool hullPair = !c.sensor && (typeA == ShapeType::ConvexHull || typeB == ShapeType::ConvexHull) &&
                          (typeA == ShapeType::ConvexHull || typeA == ShapeType::Box) &&
                          (typeB == ShapeType::ConvexHull || typeB == ShapeType::Box);
    if (hullPair) buffer.setGjkWarmStart(&c.gjkWarmStart);
    // A plain convex shape against a mesh keeps its candidate triangles
    // (MeshCandidateCache, collision/manifold.hpp; the same answer as the query).
    const bool nearList = meshPair && !compound;
    if (nearList) buffer.setMeshCandidates(&c.meshCandidates);
    if (compound) {
        if (reach.spinA > 0) reach.axisA = ma.w / reach.spinA;
        if (reach.spinB > 0) reach.axisB = mb.w / reach.spinB;
        reach.centreA = ma.com;
        reach.centreB = mb.com;
        reach.childrenA = knownChildren(dA);
        reach.childrenB = knownChildren(dB);
    }
    // Piece recycling against a static mesh (PiecePose, kPieceRecyclePad):
    // which pieces the narrow phase skips, their manifolds set aside with
    // their depths refreshed.
    const bool meshIsA = typeA == ShapeType::Mesh && pa.type == BodyType::Static;
    const bool meshIsB = typeB == ShapeType::Mesh && pb.type == BodyType::Static;
    const ShapeType pieceType = meshIsA ? typeB : typeA;
    const bool pieceCompound = pieceType == ShapeType::Compound;
    const bool pieces = pieceRecycling_ && !c.sensor && meshIsA != meshIsB && (isRecyclablePiece(pieceType) || pieceCompound);
    const Shape& pieceShape = meshIsA ? shapeB : shapeA;
    const ChildReach* pieceChildren = meshIsA ? reach.childrenB : reach.childrenA;
    if (pieces && pieceCompound && pieceChildren == nullptr) {
        // Not in the pool this update (a world just loaded, or no room): the
        // same entries computed here, so the decision never depends on the pool.
        ns.children.resize(pieceShape.children().size());
        if (meshIsA) {
            compoundChildReaches(pieceShape, xB, reach.centreB, reach.extentB, reach.axisB, ns.children.data());
            reach.childrenB = ns.children.data();
        } else {
            compoundChildReaches(pieceShape, xA, reach.centreA, reach.extentA, reach.axisA, ns.children.data());
            reach.childrenA = ns.children.data();
        }
        pieceChildren = ns.children.data();
    }
    const Real pieceExtent = meshIsA ? reach.extentB : reach.extentA;
    Transform toPiece;  // the piece body's frame in the mesh's
    std::vector<std::uint8_t>& skip = ns.skip;
    std::vector<CachedManifold>& recycled = ns.recycled;
    recycled.clear();
    std::size_t skipped = 0;
    if (pieces) {
        toPiece = meshIsA ? rel : relative(xB, xA);
        skip.assign(pieceCompound ? pieceShape.children().size() : 1, 0);
        for (const PiecePose& r : c.piecePoses) {
            if (r.piece >= skip.size()) continue;  // not this body's (a bad file): collided
            const Real rc = pieceCompound ? pieceChildren[r.piece].reach : pieceExtent;
            const Real approach = (meshIsA ? reach.margin(0, rc) : reach.margin(rc, 0)) - reach.base;
            const Quat turn = conjugate(r.rotation) * toPiece.q;
            const Real moved = length(transformPoint(toPiece, r.localCentre) - r.centre) +
                               2 * length(Vec3{turn.x, turn.y, turn.z}) * r.radius;
            if (moved <= kPieceRecycleMax && moved + approach + kPieceRecyclePad <= r.margin) {
                skip[r.piece] = 1;
                ++skipped;
            }
        }
        ns.recycledPieces += skipped;
        if (skipped > 0) {
            std::size_t kept = 0;
            for (std::size_t i = 0; i < c.manifolds.size(); ++i) {
                CachedManifold& m = c.manifolds[i];
                const std::uint32_t piece = meshIsA ? m.childB : m.childA;
                if (piece < skip.size() && skip[piece] != 0) {
                    recycled.push_back(m);
                    CachedManifold& r = recycled.back();
                    // The mesh is static: the triangles' normal stays put.
                    r.localNormal = inverseRotate(xA.q, r.normal);
                    refreshRecycledPoints(r, xA, xB);  // touching is decided after the narrow phase
                } else {
                    if (kept != i) c.manifolds[kept] = m;
                    ++kept;
                }
            }
            c.manifolds.resize(kept);
        }
        // Which pieces the narrow phase will look at: the box test of
        // collideRecursive (a plain piece always).
        ns.near.assign(skip.size(), 1);
        if (pieceCompound) {
            const AABB meshBounds = (meshIsA ? shapeA : shapeB).bounds(meshIsA ? xA : xB);
            for (std::size_t i = 0; i < skip.size(); ++i) {
                const Real rc = pieceChildren[i].reach;
                const Real mc = meshIsA ? reach.margin(0, rc) : reach.margin(rc, 0);
                ns.near[i] = skip[i] == 0 && overlaps(pieceChildren[i].bounds, meshBounds.fattened(mc)) ? 1 : 0;
            }
        }
        if (pieceCompound) {
            if (meshIsA) {
                reach.skipB = skip.data();
            } else {
                reach.skipA = skip.data();
            }
        }
    }
    if (pieces && !pieceCompound && skipped > 0) {
        buffer.clear();  // the one piece is recycled
    } else if (compound) {
        collide(shapeA, xA, shapeB, xB, reach, buffer);
    } else {
        collide(shapeA, xA, shapeB, xB, pieces ? reach.margin(reach.extentA, reach.extentB) : margin, buffer);
    }
    if (hullPair) buffer.setGjkWarmStart(nullptr);
    if (nearList) buffer.setMeshCandidates(nullptr);
    if (meshPair) {
        axes = TriangleAxisCache{};
        std::vector<TriangleAxisEntry>& fresh = ns.triangleAxes;
        if (skipped > 0) {  // the recycled pieces keep theirs (the cache's piece is the top-level child)
            for (const TriangleAxisEntry& e : c.triangleAxes) {
                if (e.piece < skip.size() && skip[e.piece] != 0) fresh.push_back(e);
            }
        }
        const auto before = [](const TriangleAxisEntry& x, const TriangleAxisEntry& y) {
            return x.piece != y.piece ? x.piece < y.piece : x.triangle < y.triangle;
        };
        if (!std::is_sorted(fresh.begin(), fresh.end(), before)) std::sort(fresh.begin(), fresh.end(), before);
        c.triangleAxes.assign(fresh.begin(), fresh.end());
    }
    c.apartBy = 0;
    // A compound pair's collide() proves a distance too (the least over its
    // children, narrow_phase.cpp): the bodies with nothing near a spinning
    // drum skip it while they cannot have come within the margin.
    if (buffer.empty() && buffer.apartBy() > 0 && (compound || (isPlainConvex(shapeA) && isPlainConvex(shapeB)))) {
        c.apartBy = buffer.apartBy();
        if (c.reachA == 0) {  // once per contact: the shapes never change
            c.reachA = shapeReach(shapeA);
            c.reachB = shapeReach(shapeB);
        }
    }

    bool touching = false;
    if (c.sensor) {
        for (const Manifold& m : buffer) touching = touching || (m.pointCount > 0 && m.maxDepth() >= 0);
        c.manifolds.clear();
    } else if (buffer.size() == 1 && c.manifolds.size() <= 1) {
        // One manifold in, at most one before (every convex pair): rebuilt in
        // place from a copy of the old points' ids, positions and impulses,
        // without the scratch manifold and its copy back (~290 bytes zeroed
        // and copied twice per pair; the same results as the general path).
        const Manifold& m = buffer[0];
        if (m.pointCount == 0) {
            c.manifolds.clear();
        } else {
            std::uint32_t oldCount = 0;
            std::uint32_t oldFeature[4];
            Vec3 oldPosition[4];
            Real oldImpulse[4];
            if (!c.manifolds.empty() && c.manifolds[0].childA == m.childA && c.manifolds[0].childB == m.childB) {
                const CachedManifold& o = c.manifolds[0];
                oldCount = o.pointCount;
                Real oldDeepest = -std::numeric_limits<Real>::infinity();
                for (std::uint32_t j = 0; j < oldCount; ++j) {
                    oldFeature[j] = o.points[j].featureId;
                    oldPosition[j] = o.points[j].position;
                    oldImpulse[j] = o.points[j].normalImpulse;
                    oldDeepest = std::max(oldDeepest, o.points[j].depthAfter);
                }
                if (oldCount > 0) c.grownBy = m.maxDepth() - oldDeepest;
            } else {
                c.manifolds.clear();
            }
            const bool hasOld = !c.manifolds.empty();
            if (!hasOld) c.manifolds.emplace_back();  // capacity 1 is reserved with the contact
            CachedManifold& out = c.manifolds[0];
            if (!hasOld) out = CachedManifold{};
            out.normal = m.normal;
            out.localNormal = inverseRotate(xA.q, m.normal);
            out.childA = m.childA;
            out.childB = m.childB;
            out.pointCount = m.pointCount;
            for (std::uint32_t k = 0; k < 4; ++k) {
                CachedPoint& dst = out.points[k];
                if (k >= m.pointCount) {
                    dst = CachedPoint{};
                    continue;
                }
                const ContactPoint& src = m.points[k];
                copyGeometry(dst, src);
                dst.normalImpulse = 0;
                dst.maxNormalImpulse = 0;
                touching = touching || src.depth > -kTouchSlop;
                // The same matching as the general path below.
                std::uint32_t match = UINT32_MAX;
                Real bestDist2 = kMatchDistance * kMatchDistance;
                for (std::uint32_t j = 0; j < oldCount; ++j) {
                    if (oldFeature[j] == src.featureId) {
                        match = j;
                        break;
                    }
                    const Real d2 = lengthSquared(oldPosition[j] - src.position);
                    if (d2 < bestDist2) {
                        bestDist2 = d2;
                        match = j;
                    }
                }
                if (match != UINT32_MAX) dst.normalImpulse = oldImpulse[match];
            }
            flags |= wakeFlags(pa, pb);
        }
    } else {
        scratch.clear();
        for (const Manifold& m : buffer) {
            if (m.pointCount == 0) continue;
            scratch.emplace_back();
            CachedManifold& out = scratch.back();
            out.normal = m.normal;
            out.localNormal = inverseRotate(xA.q, m.normal);
            out.childA = m.childA;
            out.childB = m.childB;
            out.pointCount = m.pointCount;
            const CachedManifold* old = nullptr;
            for (const CachedManifold& o : c.manifolds) {
                if (o.childA == m.childA && o.childB == m.childB) {
                    old = &o;
                    break;
                }
            }
            if (old != nullptr) {
                out.frictionImpulse = old->frictionImpulse;
                out.twistImpulse = old->twistImpulse;
                out.rollingImpulse = old->rollingImpulse;
            }
            for (std::uint32_t k = 0; k < m.pointCount; ++k) {
                const ContactPoint& src = m.points[k];
                CachedPoint& dst = out.points[k];
                copyGeometry(dst, src);
                touching = touching || src.depth > -kTouchSlop;
                if (old == nullptr) continue;
                // Match by feature id; failing that (a box-box manifold may swap its
                // reference face between frames, renaming every point), by the
                // nearest old point within kMatchDistance.
                std::uint32_t match = UINT32_MAX;
                Real bestDist2 = kMatchDistance * kMatchDistance;
                for (std::uint32_t j = 0; j < old->pointCount; ++j) {
                    if (old->points[j].featureId == src.featureId) {
                        match = j;
                        break;
                    }
                    const Real d2 = lengthSquared(old->points[j].position - src.position);
                    if (d2 < bestDist2) {
                        bestDist2 = d2;
                        match = j;
                    }
                }
                if (match != UINT32_MAX) {
                    dst.normalImpulse = old->points[match].normalImpulse;
                }
            }
        }
        c.manifolds.resize(scratch.size());
        std::copy(scratch.begin(), scratch.end(), c.manifolds.begin());
        if (!c.manifolds.empty()) flags |= wakeFlags(pa, pb);
    }
    if (pieces) touching = recordPieces(c, ns, meshIsA, pieceShape, toPiece, reach, pieceChildren) || touching;
    if (!recycled.empty()) flags |= wakeFlags(pa, pb);
    return flags | kCollided | (touching ? kTouching : 0);
}

std::uint64_t ContactManager::recycledPieceCount() const {
    std::uint64_t n = 0;
    for (const NarrowScratch& s : narrow_) n += s.recycledPieces;
    return n;
}

// After a mesh pair's narrow phase: the recycled manifolds merged back in
// piece order, and the poses of the pieces with manifolds or that the narrow
// phase looked at (the skipped ones keep theirs). Returns whether a recycled point touches.
bool ContactManager::recordPieces(Contact& c, NarrowScratch& ns, bool meshIsA, const Shape& pieceShape,
                                  const Transform& toPiece, const SpeculativeReach& reach,
                                  const ChildReach* pieceChildren) const {
    const auto pieceOf = [meshIsA](const CachedManifold& m) { return meshIsA ? m.childB : m.childA; };
    const std::vector<CachedManifold>& recycled = ns.recycled;
    bool touching = false;
    if (!recycled.empty()) {
        for (const CachedManifold& m : recycled) {
            for (std::uint32_t k = 0; k < m.pointCount; ++k) touching = touching || m.points[k].depth > -kTouchSlop;
        }
        std::vector<CachedManifold>& merged = ns.manifolds;
        merged.clear();
        std::size_t i = 0, j = 0;
        while (i < c.manifolds.size() || j < recycled.size()) {
            if (j == recycled.size() || (i < c.manifolds.size() && pieceOf(c.manifolds[i]) < pieceOf(recycled[j]))) {
                merged.push_back(c.manifolds[i++]);
            } else {
                merged.push_back(recycled[j++]);
            }
        }
        c.manifolds.resize(merged.size());
        std::copy(merged.begin(), merged.end(), c.manifolds.begin());
    }
    const bool pieceCompound = pieceShape.type() == ShapeType::Compound;
    std::vector<PiecePose>& poses = ns.piecePoses;
    poses.clear();
    std::size_t old = 0, next = 0;
    const auto count = static_cast<std::uint32_t>(ns.skip.size());
    for (std::uint32_t piece = 0; piece < count; ++piece) {
        bool has = false;  // manifolds (the narrow phase's or recycled)
        while (next < c.manifolds.size() && pieceOf(c.manifolds[next]) <= piece) has = pieceOf(c.manifolds[next++]) == piece || has;
        while (old < c.piecePoses.size() && c.piecePoses[old].piece < piece) ++old;
        const PiecePose* before = old < c.piecePoses.size() && c.piecePoses[old].piece == piece ? &c.piecePoses[old] : nullptr;
        if (ns.skip[piece] != 0) {  // recycled: only pieces with a pose are
            if (before != nullptr) poses.push_back(*before);
            continue;
        }
        // Without manifolds, a piece the narrow phase looked at (ns.near) is
        // proved as far from every triangle as its margin: the same bound
        // lets it skip the narrow phase, which would find nothing again.
        if (!has && ns.near[piece] == 0) continue;
        PiecePose r;
        r.piece = piece;
        if (before != nullptr) {  // a piece's bounds in its body never change
            r.localCentre = before->localCentre;
            r.radius = before->radius;
        } else {
            const Shape* s = &pieceShape;
            AABB local;
            if (pieceCompound) {
                const auto children = pieceShape.children();
                s = &children[piece].shape;
                local = s->bounds(children[piece].transform);
            } else {
                local = s->localBounds();
            }
            if (!isRecyclablePiece(s->type())) continue;
            centreAndRadius(local, r.localCentre, r.radius);
        }
        r.centre = transformPoint(toPiece, r.localCentre);
        r.rotation = toPiece.q;
        const Real rc = pieceCompound ? pieceChildren[piece].reach : (meshIsA ? reach.extentB : reach.extentA);
        r.margin = meshIsA ? reach.margin(0, rc) : reach.margin(rc, 0);
        poses.push_back(r);
    }
    c.piecePoses.assign(poses.begin(), poses.end());
    return touching;
}

void ContactManager::updateTouching(BodyStore& w, Contact& c, bool touching) {
    if (touching == c.touching) return;
    const BodyId a = {c.slotA, w.bodySlots[c.slotA].generation};
    const BodyId b = {c.slotB, w.bodySlots[c.slotB].generation};
    if (!c.sensor) {
        (touching ? beginEvents : endEvents).push_back({a, b});
    } else {
        const ContactEvent e = w.params[w.bodySlots[c.slotA].dense].isSensor ? ContactEvent{a, b} : ContactEvent{b, a};
        (touching ? sensorBeginEvents : sensorEndEvents).push_back(e);
    }
    c.touching = touching;
}

// Prefetching ahead of the contact loop of update() (Box3D's collide task
// prefetches its contacts too). With thousands of contacts the loop waited on
// cache misses more than it computed: at the washer's full size (8000 cubes)
// the end test's reads of the contact, its proxies' records and their leaf
// boxes were most of update()'s own time, and collideContact's own time was
// mostly the bodies' records (the shapes' types in the cold record) and the
// old manifold's points. Each is requested a few contacts ahead, in the order
// the reads depend on each other: the contact, then what it points to, then
// what those point to. Hints only: no result depends on them.
constexpr std::uint32_t kAheadContact = 16, kAheadRecords = 8, kAheadBoxes = 4;

namespace {

inline void prefetchLine(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

// The contact's fields up to its manifolds' vector (the end test, the
// recycling and the apart cache read them).
inline void prefetchContact(const Contact& c) {
    const char* p = reinterpret_cast<const char*>(&c);
    prefetchLine(p);
    prefetchLine(p + 64);
    prefetchLine(reinterpret_cast<const char*>(&c.manifolds) + sizeof(c.manifolds) - 1);
}

void prefetchBody(const BodyStore& w, std::uint32_t slot) {
    const std::uint32_t d = w.bodySlots[slot].dense;
    prefetchLine(&w.params[d]);
    const char* motion = reinterpret_cast<const char*>(&w.motion[d]);
    prefetchLine(motion);
    prefetchLine(motion + sizeof(BodyMotion) - 1);
    const char* shape = reinterpret_cast<const char*>(&w.cold[d].shape);
    prefetchLine(shape);
    prefetchLine(shape + 64);
}

}  // namespace

// What the contact points to: its proxies' records, its bodies' records and
// its first manifold.
void ContactManager::prefetchRecords(const BodyStore& w, const Contact& c) const {
    broad_.prefetchRecord(c.proxyA);
    broad_.prefetchRecord(c.proxyB);
    prefetchBody(w, c.slotA);
    prefetchBody(w, c.slotB);
    if (!c.manifolds.empty()) {
        const char* m = reinterpret_cast<const char*>(c.manifolds.data());
        for (std::size_t at = 0; at < sizeof(CachedManifold); at += 64) prefetchLine(m + at);
    }
}

void ContactManager::update(BodyStore& w, const CollisionSettings& settings, const JointPairFilter& joints,
                            TaskSystem& tasks, Real dt) {
    speculativeMargin_ = settings.speculativeMargin;
    beginEvents.clear();
    endEvents.clear();
    sensorBeginEvents.clear();
    sensorEndEvents.clear();

    ensureWorkers(tasks.workerCount());
    if (linksRebuild_) rebuildLinks();

    // 1. Proxies follow the awake bodies (fattened by the coming step's motion).
    // In parallel: the tight boxes, and whether each proxy must move (that
    // depends only on its own leaf's box, which no other proxy's move changes).
    // A mover gets its new fat box there too (its own leaf's box; the box it
    // replaced is kept for the move buffer). Then serially, in body order,
    // only the movers (a few % of the proxies) get their move-buffer entry;
    // the tree itself is restructured in step 2, next to the narrow phase.
    // (The fat boxes were set in the serial pass until that pass, reading the
    // boxes the other core had just computed, cost box_pile's fall 0.029 ms a
    // step on 2 threads against 0.0125 on one.)
    // w.awakeBodies is the ascending list of awake non-static bodies (refreshed by the step).
    const std::vector<std::uint32_t>& awake = w.awakeBodies;
    const auto awakeCount = static_cast<std::uint32_t>(awake.size());
    if (proxyMoves_.size() < awakeCount) proxyMoves_.resize(awakeCount);
    if (movedFrom_.size() < awakeCount) movedFrom_.resize(awakeCount);
    // A compound's tight box is the union of its children's bounds: kept per
    // child (with its r) for this update's narrow phase, in the pool's room
    // (claimed atomically: any order gives the same entries). Without room
    // the narrow phase computes them per pair as before, and the pool grows
    // for the next update.
    if (++updateCount_ == 0) {  // wrapped: no stale entry may match
        std::fill(childrenOfDense_.begin(), childrenOfDense_.end(), ChildrenRef{});
        updateCount_ = 1;
    }
    if (childrenOfDense_.size() < w.motion.size()) childrenOfDense_.resize(w.motion.size());
    std::atomic<std::uint32_t> childCursor{0};
    const auto poolSize = static_cast<std::uint32_t>(childPool_.size());
    tasks.parallelFor(awakeCount, 64, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t k = begin; k < end; ++k) {
            const std::uint32_t d = awake[k];
            const ProxyId proxy = proxyOfSlot_[w.denseToSlot[d]];
            const Shape& shape = w.cold[d].shape;
            const Transform xf = w.originTransform(d);
            w.previous[d] = xf;  // the step's start (WorldImpl::refreshPrevious leaves the awake bodies to this pass)
            AABB tight;
            if (shape.type() == ShapeType::Compound) {
                const auto count = static_cast<std::uint32_t>(shape.children().size());
                const std::uint32_t at = childCursor.fetch_add(count, std::memory_order_relaxed);
                if (count <= poolSize && at <= poolSize - count) {
                    // The spin axis as collideContact forms it (reach.axisA), so the same r.
                    const Vec3& spin = w.motion[d].w;
                    const Real spinRate = length(spin);
                    const Vec3 axis = spinRate > 0 ? spin / spinRate : Vec3{};
                    tight = compoundChildReaches(shape, xf, w.motion[d].com, w.params[d].extent, axis, childPool_.data() + at);
                    childrenOfDense_[d] = {updateCount_, at};
                } else {
                    tight = shape.bounds(xf);
                }
            } else {
                tight = shape.bounds(xf);
            }
            const Vec3 displacement = w.motion[d].v * dt;
            proxyMoves_[k] = broad_.proxyMustMove(proxy, tight, displacement);
            if (proxyMoves_[k] != 0) movedFrom_[k] = broad_.writeFatBox(proxy, tight, displacement);
        }
    });
    if (childCursor.load(std::memory_order_relaxed) > poolSize) childPool_.resize(childCursor.load(std::memory_order_relaxed));
    bool anyMoved = false;
    std::uint32_t movedCount = 0;
    for (std::uint32_t k = 0; k < awakeCount; ++k) {
        if (proxyMoves_[k] == 0) continue;
        broad_.noteMoved(proxyOfSlot_[w.denseToSlot[awake[k]]], movedFrom_[k]);
        anyMoved = true;
        ++movedCount;
    }
    // When most moving proxies left their fat boxes (fast bodies everywhere:
    // Jolt's HighSpeed scene), one bulk update of the moving tree replaces
    // the reinsertions (a refit of its boxes, or a rebuild once the refitted
    // tree has loosened: DynamicTree::refitOrRebuild): one by one, with the
    // ancestors' boxes stale while the others are still to come, the
    // in-place refits let the tree's boxes grow until every query visited
    // most of it.
    const bool rebuildMoving =
        movedCount > kMinBulkRebuild && 2 * movedCount > static_cast<std::uint32_t>(broad_.movingTree().proxyCount());

    // 2. The existing contacts: end those whose fat boxes separated, collide
    // the rest that can have moved. In parallel, each contact writing only
    // itself and its flag slot. Index 0 of the same call re-inserts the moved
    // proxies into the tree, serially in body order, while the other ranges
    // collide: the tree update was the largest serial part of the collapse of
    // a 10,000-sphere pile (7 % of the one-thread step). Nothing here reads
    // the tree's structure: the end test reads only the leaves' fat boxes,
    // final since step 1, and the pool is not reallocated by reinsertion.
    gatherActiveContacts(w);
    const auto activeCount = static_cast<std::uint32_t>(activeContacts_.size());
    if (contactFlags_.size() < activeCount) contactFlags_.resize(activeCount);
    // Which active contacts got a flag, one bit each: the serial pass (step 4)
    // then visits those only, not every contact (an OR is order-independent).
    const std::size_t flaggedWordCount = (std::size_t{activeCount} + 63) / 64;
    if (flaggedWords_.size() < flaggedWordCount) flaggedWords_.resize(flaggedWordCount);
    std::fill(flaggedWords_.begin(), flaggedWords_.begin() + static_cast<std::ptrdiff_t>(flaggedWordCount), 0);
    const auto collideRange = [&](const std::uint32_t* indices, std::uint8_t* flagsOut, std::uint64_t* flaggedOut,
                                  std::uint32_t begin, std::uint32_t end, NarrowScratch& ns) {
        std::uint64_t flagged = 0;  // bits of the current word, ORed in once per word
        const auto flushFlagged = [&](std::uint32_t k) {
            if (flagged != 0) {
                std::atomic_ref<std::uint64_t>(flaggedOut[k >> 6]).fetch_or(flagged, std::memory_order_relaxed);
                flagged = 0;
            }
        };
        for (std::uint32_t k = begin; k < end; ++k) {
            if (k + kAheadContact < end) prefetchContact(contacts_[indices[k + kAheadContact]]);
            if (k + kAheadRecords < end) prefetchRecords(w, contacts_[indices[k + kAheadRecords]]);
            if (k + kAheadBoxes < end) {
                const Contact& ahead = contacts_[indices[k + kAheadBoxes]];
                broad_.prefetchFatBox(ahead.proxyA);
                broad_.prefetchFatBox(ahead.proxyB);
            }
            Contact& c = contacts_[indices[k]];
            std::uint8_t flags = 0;
            if (!broad_.testOverlap(c.proxyA, c.proxyB)) {
                flags = kSeparated;
            } else if (isAwakeMover(w.params[w.bodySlots[c.slotA].dense]) ||
                       isAwakeMover(w.params[w.bodySlots[c.slotB].dense])) {
                // Both asleep (or asleep on a static body): nothing moved, the manifolds still hold.
                flags = collideContact(w, c, dt, ns);
                if (!c.manifolds.empty()) {
                    // mayHaveManifoldBits: set (atomically: another range may
                    // share the word) unless already set, as it mostly is.
                    const std::uint32_t i = indices[k];
                    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
                    std::atomic_ref<std::uint64_t> word(mayHaveManifolds_[i >> 6]);
                    if ((word.load(std::memory_order_relaxed) & bit) == 0) word.fetch_or(bit, std::memory_order_relaxed);
                }
                // Only a change of the touching state is left for the serial
                // pass (it reads c.touching, which only that pass writes): most
                // contacts then need no serial work at all (updateTouching on
                // every collided contact was 1.4 % of a sphere pile's collapse).
                const bool touching = (flags & kTouching) != 0;
                flags &= static_cast<std::uint8_t>(~(kTouching | kCollided));
                if (touching != c.touching) flags |= kTouchChanged;
            }
            flagsOut[k] = flags;
            if (flaggedOut != nullptr) {
                if (flags != 0) flagged |= std::uint64_t{1} << (k & 63);
                if ((k & 63) == 63) flushFlagged(k);
            }
        }
        if (flaggedOut != nullptr && end > begin) flushFlagged(end - 1);
    };
    tasks.parallelFor(activeCount + 1, 32, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
        if (begin == 0) {
            if (rebuildMoving) {
                broad_.refitMovingTree();
            } else if (anyMoved) {
                for (std::uint32_t k = 0; k < awakeCount; ++k) {
                    if (proxyMoves_[k] != 0) broad_.reinsertProxy(proxyOfSlot_[w.denseToSlot[awake[k]]]);
                }
            }
            ++begin;
        }
        if (begin < end) {
            collideRange(activeContacts_.data(), contactFlags_.data(), flaggedWords_.data(), begin - 1, end - 1,
                         narrow_[worker]);
        }
    });

    // 3. New pairs, sorted by proxy ids: a deterministic order, and no more
    // than the pair limit leaves room for (WorldDef::maxContactPairs: the
    // broad phase keeps the rest for later updates, docs/solver.md "Contact
    // pair limit"; the pairs this update separates make room from the next
    // one on). Then their narrow phase (the same test as step 2's, in parallel).
    lastPairLimit_ = contactPairLimit(settings.maxContactPairs, w.motion.size());
    const std::uint32_t room = liveContacts_ < lastPairLimit_ ? lastPairLimit_ - liveContacts_ : 0;
    newContacts_.clear();
    for (const ProxyPair& pair : broad_.updatePairs(PairRule{&w, &joints}, KnownPartners{this}, &tasks, room)) {
        newContacts_.push_back(createContact(w, pair.userA, pair.userB, pair.a, pair.b));
    }
    // Ascending, like the active list; made in this update, so not visited by the next one.
    std::sort(newContacts_.begin(), newContacts_.end());
    for (const std::uint32_t i : newContacts_) marks_[i >> 6] &= ~(std::uint64_t(1) << (i & 63));
    const auto newCount = static_cast<std::uint32_t>(newContacts_.size());
    if (contactFlags_.size() < activeCount + newCount) contactFlags_.resize(activeCount + newCount);
    std::uint8_t* newFlags = contactFlags_.data() + activeCount;
    tasks.parallelFor(newCount, 32, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t worker) {
        collideRange(newContacts_.data(), newFlags, nullptr, begin, end, narrow_[worker]);
    });

    // 4. In contact order over both lists (new contacts took free slots, so
    // the lists are disjoint): the destructions, wakes and events, so the
    // result is the same for any thread count. (A body woken here gets its
    // contacts with other sleeping bodies collided next step: they have not
    // moved, so their manifolds still hold.)
    // The active contacts with a flag come from the bitmap (ascending), the
    // new ones are few: merged by contact index, the order of one list.
    std::uint32_t kn = 0;
    const auto apply = [&](std::uint32_t i, std::uint8_t flags) {
        if (flags == 0) return;
        Contact& c = contacts_[i];
        if ((flags & kSeparated) != 0) {
            destroyContact(w, i);
            return;
        }
        if ((flags & kWakeA) != 0 && !w.params[w.bodySlots[c.slotA].dense].awake) w.wakeBody(w.bodySlots[c.slotA].dense);
        if ((flags & kWakeB) != 0 && !w.params[w.bodySlots[c.slotB].dense].awake) w.wakeBody(w.bodySlots[c.slotB].dense);
        if ((flags & kTouchChanged) != 0) updateTouching(w, c, !c.touching);
    };
    for (std::size_t word = 0; word < flaggedWordCount; ++word) {
        std::uint64_t bits = flaggedWords_[word];
        while (bits != 0) {
            const auto ka = static_cast<std::uint32_t>(word * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
            bits &= bits - 1;
            const std::uint32_t i = activeContacts_[ka];
            for (; kn < newCount && newContacts_[kn] < i; ++kn) apply(newContacts_[kn], newFlags[kn]);
            apply(i, contactFlags_[ka]);
        }
    }
    for (; kn < newCount; ++kn) apply(newContacts_[kn], newFlags[kn]);
}

void ContactManager::appendHitEvent(const BodyStore& w, const Contact& c, const CachedManifold& m, Real threshold,
                                    std::vector<ContactHitEvent>& out) {
    Real fastest = 0;
    std::uint32_t at = UINT32_MAX;
    for (std::uint32_t k = 0; k < m.pointCount; ++k) {
        const CachedPoint& p = m.points[k];
        // Only points that pushed in the step; approachVelocity is the normal
        // velocity when they first did (negative: approaching).
        const Real approach = -p.approachVelocity;
        if (p.maxNormalImpulse > 0 && approach > threshold && approach > fastest) {
            fastest = approach;
            at = k;
        }
    }
    if (at == UINT32_MAX) return;
    out.push_back({{c.slotA, w.bodySlots[c.slotA].generation}, {c.slotB, w.bodySlots[c.slotB].generation},
                   m.points[at].position, m.normal, fastest});
}

namespace {

// Whether a manifold is reported (a point within kTouchSlop), and its deepest point.
bool reportable(const CachedManifold& m, Real& deepest) {
    deepest = -1e30f;
    for (std::uint32_t k = 0; k < m.pointCount; ++k) deepest = std::max(deepest, m.points[k].depthAfter);
    return m.pointCount > 0 && deepest > -kTouchSlop;
}

}  // namespace

void ContactManager::report(const BodyStore& w, std::vector<ContactReport>& out, std::size_t& reportCount, Real dt,
                            TaskSystem& tasks) const {
    const Real invDt = dt > 0 ? Real(1) / dt : Real(0);
    // In parallel and in contact order: count each contact's reports, place
    // them by prefix sums (serial), then fill each contact's slots.
    const auto contactCount = static_cast<std::uint32_t>(contacts_.size());
    if (reportStart_.size() < contactCount + 1) reportStart_.resize(contactCount + 1);
    tasks.parallelFor(contactCount, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin; i < end; ++i) {
            const Contact& c = contacts_[i];
            std::uint32_t count = 0;
            Real deepest = 0;
            if (c.alive && !c.sensor)
                for (const CachedManifold& m : c.manifolds) count += reportable(m, deepest) ? 1u : 0u;
            reportStart_[i + 1] = count;
        }
    });
    reportStart_[0] = 0;
    for (std::uint32_t i = 0; i < contactCount; ++i) reportStart_[i + 1] += reportStart_[i];
    const std::size_t n = reportStart_[contactCount];
    while (out.size() < n) out.emplace_back();
    tasks.parallelFor(contactCount, 256, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin; i < end; ++i) {
            const Contact& c = contacts_[i];
            if (reportStart_[i + 1] == reportStart_[i]) continue;
            std::size_t r = reportStart_[i];
            for (const CachedManifold& m : c.manifolds) {
                Real deepest = 0;
                if (!reportable(m, deepest)) continue;
                ContactReport& rep = out[r++];
                rep.bodyA = {c.slotA, w.bodySlots[c.slotA].generation};
                rep.bodyB = {c.slotB, w.bodySlots[c.slotB].generation};
                rep.normal = m.normal;
                rep.depth = deepest;
                rep.points.resize(m.pointCount);
                rep.pointNormalImpulses.resize(m.pointCount);
                // A pair without a dynamic body is never solved: its stored impulses mean nothing.
                const bool solved = w.params[w.bodySlots[c.slotA].dense].type == BodyType::Dynamic ||
                                    w.params[w.bodySlots[c.slotB].dense].type == BodyType::Dynamic;
                Real total = 0;
                for (std::uint32_t k = 0; k < m.pointCount; ++k) {
                    rep.points[k] = m.points[k].position;
                    rep.pointNormalImpulses[k] = solved ? m.points[k].stepNormalImpulse : Real(0);
                    total += rep.pointNormalImpulses[k];
                }
                rep.normalImpulse = total;
                rep.frictionImpulse = solved ? m.stepFrictionImpulse : Vec3{};
                rep.force = (m.normal * total + rep.frictionImpulse) * invDt;
            }
        }
    });
    reportCount = n;
}

}  // namespace fulcrum::detail
