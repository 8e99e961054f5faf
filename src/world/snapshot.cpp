// Snapshots: saving and restoring the whole World (include/fulcrum/snapshot.hpp,
// docs/snapshots.md).
//
// How bit-identical resumption is achieved
// ----------------------------------------
// A resumed run must take every branch and round every number exactly as the
// uninterrupted one. Anything that orders work therefore comes back exactly,
// not just "equivalently":
//   - the dense body arrays in their order (every per-body loop, the solver's
//     body list and graph colouring follow it) and the slot tables;
//   - the contact array *with its free slots and free-list order*: a new
//     contact takes the head of the free list, and contacts are prepared in
//     array order;
//   - the broad phase node for node: proxy ids order new pairs, fat boxes
//     decide when pairs begin and end and when a proxy is reinserted, and the
//     tree shape orders the particle coupling's shape queries;
//   - the sleep manager's next island tag (tags only need to be distinct, but
//     a restarted counter could reuse the tag of an island that still sleeps,
//     and waking one would wake the other);
//   - hull geometry as stored (faces and vertices in their order), not
//     recomputed: quickhull over the hull's own vertices need not give the
//     same face order. Meshes are rebuilt from their vertices and triangles,
//     which the mesh factory keeps as given, so the BVH comes out the same.
// Scratch that every step rebuilds before reading (solver constraints,
// islands, narrow-phase buffers, particle coupling proxies) is not saved.
//
// One description of each struct serves both directions: `io(archive, x)`
// overloads list the fields once, and the Writer and the Reader give them
// meaning, so a field cannot be saved and forgotten on load. The Writer only
// reads its argument (the const_cast at the entry point is for this sharing).
#include "fulcrum/snapshot.hpp"

#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <type_traits>

#include "collision/support.hpp"
#include "world/input_file.hpp"
#include "world/snapshot_versions.hpp"
#include "world/world_access.hpp"

namespace fulcrum::detail {

namespace {

constexpr char kMagic[8] = {'F', 'U', 'L', 'C', 'S', 'N', 'A', 'P'};
constexpr std::size_t kHeaderSize = 32;  // magic 8, version 4, sizeof(Real) 4, payload size 8, checksum 8
constexpr std::size_t kNoIndexSize = std::numeric_limits<std::size_t>::max();

// FNV-1a, 64 bit: simple, byte order independent, good enough to catch
// corruption (not an integrity guarantee against tampering).
std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size) {
    std::uint64_t h = 14695981039346656037ull;
    for (std::size_t i = 0; i < size; ++i) {
        h ^= data[i];
        h *= 1099511628211ull;
    }
    return h;
}

template <typename T>
std::uint64_t bitsOf(T v) {
    if constexpr (std::is_same_v<T, bool>) {
        return v ? 1u : 0u;
    } else if constexpr (std::is_floating_point_v<T>) {
        if constexpr (sizeof(T) == 4) {
            std::uint32_t u;
            std::memcpy(&u, &v, 4);
            return u;
        } else {
            std::uint64_t u;
            std::memcpy(&u, &v, 8);
            return u;
        }
    } else {
        return static_cast<std::uint64_t>(static_cast<std::make_unsigned_t<T>>(v));
    }
}

template <typename T>
T fromBits(std::uint64_t u) {
    if constexpr (std::is_same_v<T, bool>) {
        return u != 0;
    } else if constexpr (std::is_floating_point_v<T>) {
        T v;
        if constexpr (sizeof(T) == 4) {
            const auto w = static_cast<std::uint32_t>(u);
            std::memcpy(&v, &w, 4);
        } else {
            std::memcpy(&v, &u, 8);
        }
        return v;
    } else {
        return static_cast<T>(static_cast<std::make_unsigned_t<T>>(u));
    }
}

// ---------------------------------------------------------------- archives

class Writer {
public:
    static constexpr bool kReading = false;
    std::vector<std::uint8_t> out;
    // The format version written: fields added in a later version are left
    // out of an older one (tests write version 2 to prove it still loads).
    std::uint32_t version = kSnapshotVersion;

    void at(const char*, std::size_t = kNoIndexSize) {}
    template <typename T>
    void primitive(T& v) {
        put(bitsOf(v), sizeof(T));
    }
    // Element count of a container (read: checked against the remaining bytes).
    void count(std::size_t& n, std::size_t) { put(n, 8); }
    template <typename E>
    void enumeration(E& e, E) {
        put(static_cast<std::uint64_t>(e), 1);
    }
    [[noreturn]] void fail(const std::string& what) const { throw Error("saving a snapshot: " + what); }
    void put(std::uint64_t v, std::size_t bytes) {
        for (std::size_t i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    }
};

class Reader {
public:
    static constexpr bool kReading = true;

    Reader(std::span<const std::uint8_t> payload, std::string source, bool truncated, std::uint32_t fileVersion)
        : version(fileVersion), data_(payload), source_(std::move(source)), truncated_(truncated) {}

    // The file's format version: fields added later keep their defaults when reading an older file.
    const std::uint32_t version;

    void at(const char* section, std::size_t index = kNoIndexSize) {
        section_ = section;
        index_ = index;
    }
    template <typename T>
    void primitive(T& v) {
        v = fromBits<T>(get(sizeof(T)));
    }
    // A count must fit the remaining bytes (each element takes at least
    // `minBytes`), so a corrupt count never triggers a huge allocation.
    void count(std::size_t& n, std::size_t minBytes) {
        const std::uint64_t c = get(8);
        const std::size_t remaining = data_.size() - pos_;
        if (c > remaining / (minBytes == 0 ? 1 : minBytes)) {
            if (truncated_) fail("truncated");
            fail("corrupt element count " + std::to_string(c));
        }
        n = static_cast<std::size_t>(c);
    }
    template <typename E>
    void enumeration(E& e, E maxValue) {
        const std::uint64_t u = get(1);
        if (u > static_cast<std::uint64_t>(maxValue)) fail("invalid value " + std::to_string(u));
        e = static_cast<E>(u);
    }
    [[noreturn]] void fail(const std::string& what) const {
        // Offsets are reported in the file, header included.
        std::string where = section_;
        if (index_ != kNoIndexSize) where += "[" + std::to_string(index_) + "]";
        throw Error(source_ + ": " + what + " at byte " + std::to_string(kHeaderSize + pos_) + " (" + where + ")");
    }
    bool atEnd() const { return pos_ == data_.size(); }
    std::size_t position() const { return pos_; }
    const std::string& source() const { return source_; }

private:
    std::uint64_t get(std::size_t bytes) {
        if (data_.size() - pos_ < bytes) fail(truncated_ ? "truncated" : "corrupt: unexpected end of data");
        std::uint64_t v = 0;
        for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(data_[pos_ + i]) << (8 * i);
        pos_ += bytes;
        return v;
    }

    std::span<const std::uint8_t> data_;
    std::size_t pos_ = 0;
    std::string source_;
    bool truncated_;
    const char* section_ = "header";
    std::size_t index_ = kNoIndexSize;
};

// ---------------------------------------------------------------- field lists

template <typename A, typename T>
    requires std::is_arithmetic_v<T>
void io(A& a, T& v) {
    a.primitive(v);
}
template <typename A>
void io(A& a, Vec3& v) {
    io(a, v.x), io(a, v.y), io(a, v.z);
}
template <typename A>
void io(A& a, Quat& q) {
    io(a, q.w), io(a, q.x), io(a, q.y), io(a, q.z);
}
template <typename A>
void io(A& a, Mat3& m) {
    io(a, m.c0), io(a, m.c1), io(a, m.c2);
}
template <typename A>
void io(A& a, AABB& b) {
    io(a, b.min), io(a, b.max);
}
template <typename A>
void io(A& a, Transform& t) {
    io(a, t.p), io(a, t.q);
}
template <typename A>
void io(A& a, std::string& s) {
    std::size_t n = s.size();
    a.count(n, 1);
    if constexpr (A::kReading) s.resize(n);
    for (char& c : s) io(a, c);
}
template <typename A, typename T, typename Alloc>
void io(A& a, std::vector<T, Alloc>& v) {
    std::size_t n = v.size();
    a.count(n, 1);
    if constexpr (A::kReading) v.resize(n);
    for (auto& e : v) io(a, e);
}
template <typename A, typename T, std::size_t N>
void io(A& a, std::array<T, N>& v) {
    for (T& e : v) io(a, e);
}
template <typename A>
void io(A& a, BodyId& id) {
    io(a, id.index), io(a, id.generation);
}
template <typename A>
void io(A& a, ParticleSystemId& id) {
    io(a, id.index), io(a, id.generation);
}
template <typename A>
void io(A& a, CollisionFilter& f) {
    io(a, f.category), io(a, f.mask), io(a, f.group);
}
template <typename A>
void io(A& a, ContactEvent& e) {
    io(a, e.bodyA), io(a, e.bodyB);
}

template <typename A>
void io(A& a, WorldDef& s) {
    io(a, s.gravity);
    a.enumeration(s.integrator, Integrator::Verlet);
    io(a, s.substeps), io(a, s.solverIterations), io(a, s.sleeping), io(a, s.threads);
    io(a, s.contactHertz), io(a, s.contactDampingRatio), io(a, s.contactPushMaxVelocity), io(a, s.speculativeMargin);
    io(a, s.restitutionThreshold);
    io(a, s.linearSleepVelocity), io(a, s.angularSleepVelocity), io(a, s.timeToSleep);
    io(a, s.continuousCollision);
    if (a.version >= 3) {
        // Joint solver tuning (version 3). A version-2 file was written when
        // these were constants equal to today's defaults, so the defaults it
        // keeps on reading reproduce its run.
        io(a, s.jointHertz), io(a, s.jointDampingRatio), io(a, s.jointProjectionSlop), io(a, s.jointDirectSolve);
    }
    // The contact pair limit (version 4); older files ran without one, and
    // the automatic limit it gets leaves every scene that fit in memory alone.
    if (a.version >= 4) io(a, s.maxContactPairs);
    if (a.version >= 5) io(a, s.hitEventThreshold);  // version 5 (older: the default, 1 m/s)
    // Version 14: the push-out of grown overlaps; older files were written
    // by builds without it (the default, off, resumes them as they ran).
    if (a.version >= 14) io(a, s.pushOutGrownOverlaps);
}

// ---- bodies
template <typename A>
void io(A& a, BodySlot& s) {
    io(a, s.dense), io(a, s.generation);
}
template <typename A>
void io(A& a, BodyMotion& m) {
    io(a, m.com), io(a, m.q), io(a, m.v), io(a, m.w), io(a, m.invMass), io(a, m.invInertiaWorld);
}
template <typename A>
void io(A& a, ForceTorque& f) {
    io(a, f.force), io(a, f.torque);
}
template <typename A>
void io(A& a, BodyParams& p) {
    a.enumeration(p.type, BodyType::Dynamic);
    io(a, p.awake), io(a, p.allowSleep), io(a, p.isSensor), io(a, p.isBullet);
    io(a, p.mass), io(a, p.localCom), io(a, p.localInertia), io(a, p.invLocalInertia);
    io(a, p.linearDamping), io(a, p.angularDamping), io(a, p.linearDrag), io(a, p.quadraticDrag), io(a, p.gravityScale);
    io(a, p.friction), io(a, p.restitution), io(a, p.rollingResistance);
    io(a, p.filter), io(a, p.extent), io(a, p.sleepTime), io(a, p.sleepIsland);
}
template <typename A>
void io(A& a, IntegratorScratch& s) {
    io(a, s.dv), io(a, s.dw);
}

// ---- springs and joints
template <typename A>
void io(A& a, SpringData& s) {
    io(a, s.alive), io(a, s.generation), io(a, s.bodyA), io(a, s.bodyB), io(a, s.localA), io(a, s.localB);
    io(a, s.restLength), io(a, s.stiffness), io(a, s.damping);
}
template <typename A>
void io(A& a, JointDef& d) {
    io(a, d.name);
    if constexpr (!A::kReading) {
        if (a.version < 7 && d.type == JointType::SixDof) a.fail("six-DOF joints need format version 7 or later");
    }
    a.enumeration(d.type, a.version >= 7 ? JointType::SixDof : JointType::ConeTwist);
    io(a, d.bodyA), io(a, d.bodyB), io(a, d.anchor), io(a, d.anchorB), io(a, d.axis);
    io(a, d.hasLimits), io(a, d.lowerLimit), io(a, d.upperLimit);
    io(a, d.motor.enabled), io(a, d.motor.speed), io(a, d.motor.maxForce);
    io(a, d.spring.enabled), io(a, d.spring.target), io(a, d.spring.stiffness), io(a, d.spring.damping);
    io(a, d.minLength), io(a, d.maxLength), io(a, d.stiffness), io(a, d.damping);
    io(a, d.swingLimit), io(a, d.twistLower), io(a, d.twistUpper);
    io(a, d.breakForce), io(a, d.breakTorque), io(a, d.collideConnected);
    if (a.version >= 3) io(a, d.frictionTorque);  // version 3 (version 2: frictionless, 0)
    if (a.version >= 7) {  // version 7: the six-DOF joint's frame and axes, the cone-twist drive
        io(a, d.coneDrive.enabled), io(a, d.coneDrive.target), io(a, d.coneDrive.stiffness), io(a, d.coneDrive.damping);
        io(a, d.coneDrive.maxTorque);
        io(a, d.axisY);
        for (SixDofAxis& s : d.axes) {
            a.enumeration(s.mode, AxisMode::Locked);
            io(a, s.lower), io(a, s.upper);
            io(a, s.motor.enabled), io(a, s.motor.speed), io(a, s.motor.maxForce);
            io(a, s.spring.enabled), io(a, s.spring.target), io(a, s.spring.stiffness), io(a, s.spring.damping);
        }
    }
    if (a.version >= 9) {  // version 9: the position drives' force limits (older: unlimited)
        io(a, d.spring.maxForce);
        for (SixDofAxis& s : d.axes) io(a, s.spring.maxForce);
    }
}
template <typename A>
void io(A& a, JointData& j) {
    io(a, j.alive), io(a, j.generation), io(a, j.def);
    io(a, j.localAnchorA), io(a, j.localAnchorB), io(a, j.localAxisA), io(a, j.localAxisB);
    io(a, j.minLength), io(a, j.maxLength);
    // Joint solver runtime that carries over between steps: the rest pose,
    // the soft distance joint's rest length, enable/broken flags, the
    // accumulated sub-step impulses (warm starting) and the last reactions.
    // (Added in snapshot version 2.)
    io(a, j.relativeRotation), io(a, j.restLength), io(a, j.enabled), io(a, j.broken);
    io(a, j.impulses.linear), io(a, j.impulses.angular), io(a, j.impulses.axial), io(a, j.impulses.spring);
    io(a, j.impulses.motor), io(a, j.impulses.lower), io(a, j.impulses.upper), io(a, j.impulses.swing);
    io(a, j.reactionForce), io(a, j.reactionTorque);
    // Version 3: the ball / cone-twist friction impulse (warm started like the
    // others; hinge friction rides on the motor impulse above). The tree
    // solver keeps nothing between steps: it finds the trees in every
    // prepare() and factors again every sub-step.
    if (a.version >= 3) io(a, j.impulses.friction);
    if (a.version >= 7) {  // version 7: the six-DOF joint's frame and its axes' drive impulses
        io(a, j.localFrameA);
        io(a, j.impulses.axisMotorLinear), io(a, j.impulses.axisMotorAngular);
        io(a, j.impulses.axisSpringLinear), io(a, j.impulses.axisSpringAngular), io(a, j.impulses.drive);
    }
}

// ---- contacts
template <typename A>
void io(A& a, CachedPoint& p) {
    io(a, p.localA), io(a, p.localB), io(a, p.position), io(a, p.depth), io(a, p.depthAfter), io(a, p.featureId);
    io(a, p.normalImpulse), io(a, p.maxNormalImpulse);
    if (a.version >= 5) io(a, p.stepNormalImpulse), io(a, p.approachVelocity);  // contact forces (version 5)
}
template <typename A>
void io(A& a, CachedManifold& m) {
    io(a, m.normal), io(a, m.localNormal), io(a, m.childA), io(a, m.childB), io(a, m.pointCount);
    if (m.pointCount > 4) {
        if constexpr (A::kReading) a.fail("manifold point count " + std::to_string(m.pointCount) + " is over 4");
    }
    for (CachedPoint& p : m.points) io(a, p);
    io(a, m.frictionImpulse), io(a, m.twistImpulse), io(a, m.rollingImpulse);
    if (a.version >= 5) io(a, m.stepFrictionImpulse);
}
template <typename A>
void io(A& a, TriangleAxisEntry& e) {
    io(a, e.piece), io(a, e.triangle), io(a, e.axis), io(a, e.separation);
}
template <typename A>
void io(A& a, PiecePose& r) {
    io(a, r.piece), io(a, r.localCentre), io(a, r.radius), io(a, r.centre), io(a, r.rotation), io(a, r.margin);
}
template <typename A>
void io(A& a, Contact& c) {
    io(a, c.alive), io(a, c.sensor), io(a, c.touching), io(a, c.solved), io(a, c.slotA), io(a, c.slotB);
    io(a, c.proxyA), io(a, c.proxyB), io(a, c.nextFree), io(a, c.hasPose), io(a, c.relativePose);
    if constexpr (A::kReading) {  // the apart cache is not saved: the narrow phase runs again
        c.apartBy = 0;
        c.reachA = c.reachB = 0;
        c.meshCandidates.clear();  // nor the candidate triangles: the query runs again
    }
    // Version 9: the pair's mixed material. The step reads it before the
    // narrow phase mixes it again, so a file without it (older) gets it mixed
    // from the bodies on load (ContactManager::mixMaterials).
    if (a.version >= 9) io(a, c.friction), io(a, c.restitution), io(a, c.rollingResistance);
    io(a, c.manifolds);
    // Version 10: how the pair first touched (the solver's push-out sharing).
    // A file before it was written by a build that shared every deep overlap
    // of a body, as for pairs born deep: its touching pairs load so and resume
    // as they ran.
    if (a.version >= 10) {
        a.enumeration(c.firstTouch, FirstTouch::Deep);
    } else if constexpr (A::kReading) {
        c.firstTouch = c.manifolds.empty() ? FirstTouch::NotYet : FirstTouch::Deep;
    }
    // Version 11: the triangle axis cache of a box or hull against a mesh
    // (collision/manifold.hpp, TriangleAxisCache), which decides the next
    // contacts. A file before it was written by a build without the cache:
    // its pairs load with none and run the full test.
    if (a.version >= 11) {
        io(a, c.triangleAxes);
        if constexpr (A::kReading) {
            for (std::size_t i = 1; i < c.triangleAxes.size(); ++i) {
                const TriangleAxisEntry& x = c.triangleAxes[i - 1];
                const TriangleAxisEntry& y = c.triangleAxes[i];
                if (!(x.piece < y.piece || (x.piece == y.piece && x.triangle < y.triangle))) {
                    a.fail("a contact's triangle axis cache is not sorted by piece and triangle");
                }
            }
        }
    } else if constexpr (A::kReading) {
        c.triangleAxes.clear();
    }
    // Version 12: the GJK warm start of two hulls or a box and a hull (collision/manifold.hpp,
    // GjkWarmStart), where the pair's next GJK run starts. A file before it
    // was written by a build that started every run cold: its pairs load
    // with none. Indices beyond the shapes are not an error (the run then
    // starts cold); a count beyond a triangle is.
    if (a.version >= 12) {
        GjkWarmStart& g = c.gjkWarmStart;
        io(a, g.count);
        if constexpr (A::kReading) {
            if (g.count > 3) a.fail("a contact's GJK warm start holds more than three vertices");
        }
        for (std::uint32_t i = 0; i < 3; ++i) io(a, g.indexA[i]), io(a, g.indexB[i]);
    } else if constexpr (A::kReading) {
        c.gjkWarmStart = GjkWarmStart{};
    }
    // Version 13: piece recycling against a static mesh (contact.hpp,
    // PiecePose), which decides which pieces the next narrow phase skips. A
    // file before it was written by a build that collided every piece: its
    // pairs load with none and collide them all once.
    if (a.version >= 13) {
        io(a, c.piecePoses);
        if constexpr (A::kReading) {
            for (std::size_t i = 1; i < c.piecePoses.size(); ++i) {
                if (!(c.piecePoses[i - 1].piece < c.piecePoses[i].piece)) {
                    a.fail("a contact's piece poses are not in ascending piece order");
                }
            }
        }
    } else if constexpr (A::kReading) {
        c.piecePoses.clear();
    }
}
template <typename A>
void io(A& a, ContactReport& r) {
    io(a, r.bodyA), io(a, r.bodyB), io(a, r.normal), io(a, r.depth), io(a, r.points);
    if (a.version >= 5) {
        io(a, r.normalImpulse), io(a, r.frictionImpulse), io(a, r.force), io(a, r.pointNormalImpulses);
    } else if constexpr (A::kReading) {
        r.pointNormalImpulses.assign(r.points.size(), Real(0));  // written before forces were reported
    }
}

// ---- particles
template <typename A>
void io(A& a, DistanceConstraint& c) {
    io(a, c.a), io(a, c.b), io(a, c.restLength);
}
template <typename A>
void io(A& a, DistanceConstraintGroup& g) {
    io(a, g.constraints), io(a, g.lambda), io(a, g.compliance), io(a, g.unilateral);
}
template <typename A>
void io(A& a, ParticlePin& p) {
    io(a, p.particle), io(a, p.target);
}
// The error-message field name of an attachment is a pointer to a literal: it
// travels as text and comes back as one of the literals the builders use.
const char* attachmentField(const std::string& s) {
    for (const char* known : {"attach_start", "attach_end"}) {
        if (s == known) return known;
    }
    return "attach";
}
template <typename A>
void io(A& a, ParticleAttachment& p) {
    io(a, p.particle), io(a, p.body), io(a, p.localAnchor), io(a, p.compliance), io(a, p.lambda), io(a, p.resolved);
    std::string field = p.field;
    io(a, field);
    if constexpr (A::kReading) p.field = attachmentField(field);
}
template <typename A>
void io(A& a, ParticleSpring& s) {
    io(a, s.a), io(a, s.b), io(a, s.restLength), io(a, s.stiffness), io(a, s.damping);
}
template <typename A>
void io(A& a, ParticleTriangle& t) {
    io(a, t.a), io(a, t.b), io(a, t.c);
}
template <typename A>
void io(A& a, ParticleSystem& s) {
    io(a, s.name);
    a.enumeration(s.kind, ParticleSystemKind::Particles);
    io(a, s.gridSize[0]), io(a, s.gridSize[1]);
    io(a, s.position), io(a, s.displacement), io(a, s.restPosition), io(a, s.force), io(a, s.inverseMass),
        io(a, s.radius);
    io(a, s.stretch), io(a, s.shear), io(a, s.bend), io(a, s.tethers);
    io(a, s.pins), io(a, s.attachments), io(a, s.springs), io(a, s.triangles);
    io(a, s.damping), io(a, s.linearDrag), io(a, s.friction), io(a, s.dragCoefficient), io(a, s.liftCoefficient);
    io(a, s.selfCollision), io(a, s.selfCollisionExclusion), io(a, s.previousSubstep);
}

// ---- characters and vehicles (version 6)
template <typename A>
void io(A& a, CharacterInput& in) {
    io(a, in.time), io(a, in.velocity), io(a, in.jump);
}
template <typename A>
void io(A& a, CharacterDef& d) {
    io(a, d.name), io(a, d.position), io(a, d.radius), io(a, d.height), io(a, d.mass), io(a, d.maxSlope),
        io(a, d.stepHeight), io(a, d.jumpSpeed), io(a, d.maxPushForce), io(a, d.stickDistance), io(a, d.inputs);
}
template <typename A>
void io(A& a, CharacterData& c) {
    io(a, c.alive), io(a, c.generation), io(a, c.def), io(a, c.cosMaxSlope), io(a, c.body), io(a, c.position), io(a, c.velocity),
        io(a, c.airVelocity), io(a, c.reportedVelocity);
    a.enumeration(c.ground, GroundState::InAir);
    io(a, c.groundNormal), io(a, c.groundVelocity), io(a, c.groundBody), io(a, c.groundLocal), io(a, c.groundPoint),
        io(a, c.inputVelocity), io(a, c.inputJump), io(a, c.nextInput);
}
template <typename A>
void io(A& a, WheelDef& d) {
    io(a, d.position), io(a, d.radius), io(a, d.width), io(a, d.suspension.restLength), io(a, d.suspension.stiffness),
        io(a, d.suspension.damping), io(a, d.steering), io(a, d.driven), io(a, d.handBrake), io(a, d.friction),
        io(a, d.inertia);
}
template <typename A>
void io(A& a, VehicleInput& in) {
    io(a, in.time), io(a, in.throttle), io(a, in.brake), io(a, in.steering), io(a, in.handBrake);
}
template <typename A>
void io(A& a, AntiRollBar& b) {
    io(a, b.left), io(a, b.right), io(a, b.stiffness);
}
template <typename A>
void io(A& a, VehicleDef& d) {
    io(a, d.name), io(a, d.chassis), io(a, d.wheels), io(a, d.engine.maxTorque), io(a, d.engine.maxRpm),
        io(a, d.engine.minRpm), io(a, d.engine.torqueCurve), io(a, d.gearbox.ratios), io(a, d.gearbox.differentialRatio),
        io(a, d.gearbox.shiftUpRpm), io(a, d.gearbox.shiftDownRpm), io(a, d.maxBrakeTorque), io(a, d.maxHandBrakeTorque),
        io(a, d.maxSteeringAngle), io(a, d.antiRollBars), io(a, d.inputs);
}
template <typename A>
void io(A& a, WheelState& s) {
    io(a, s.inContact), io(a, s.suspensionLength), io(a, s.suspensionForce), io(a, s.angularVelocity), io(a, s.rotation),
        io(a, s.steerAngle), io(a, s.longitudinalSlip), io(a, s.lateralSlip), io(a, s.contactPoint), io(a, s.contactNormal),
        io(a, s.contactBody);
}
template <typename A>
void io(A& a, WheelData& wh) {
    // The tyre solve's scratch is rebuilt every step; only what carries over is kept.
    io(a, wh.mountLocal), io(a, wh.state), io(a, wh.sinSteer), io(a, wh.cosSteer);
}
template <typename A>
void io(A& a, VehicleData& v) {
    io(a, v.alive), io(a, v.generation), io(a, v.def), io(a, v.wheels), io(a, v.input), io(a, v.nextInput), io(a, v.gear),
        io(a, v.engineRpm);
}

}  // namespace
}  // namespace fulcrum::detail

namespace fulcrum {

using detail::ContactManager;
using detail::SleepManager;

// ---------------------------------------------------------------- private state (friend of the classes it saves)

struct SnapshotAccess {
    // ---- shapes: the private fields as they are; hulls with their full
    // geometry, meshes from vertices and triangles (see the top comment).
    template <typename A>
    static void shape(A& a, Shape& s, int depth) {
        if (depth > kMaxCompoundLevels) a.fail("compound shapes nested deeper than " + std::to_string(kMaxCompoundLevels));
        a.enumeration(s.type_, ShapeType::HeightField);
        io(a, s.radius_), io(a, s.halfHeight_), io(a, s.halfExtents_);
        // Version 8: rounded shapes' convex radius (older files: plain shapes).
        if constexpr (!A::kReading) {
            if (a.version < 8 && s.convexRadius_ > 0) a.fail("rounded shapes need format version 8 or later");
        }
        if (a.version >= 8) io(a, s.convexRadius_);
        if constexpr (A::kReading) {
            // The factories' size limit (kMaxShapeCoordinate, fulcrum/shape.hpp):
            // a finite but larger size overflows when the shape is turned.
            const auto within = [](Real x) { return std::isfinite(x) && std::fabs(x) <= kMaxShapeCoordinate; };
            if (!within(s.radius_) || !within(s.halfHeight_) || !within(s.halfExtents_.x) || !within(s.halfExtents_.y) ||
                !within(s.halfExtents_.z)) {
                a.fail("a shape's size is not finite or beyond the limit of 1e12 m");
            }
            const Real r = s.convexRadius_;
            const bool roundable = s.type_ == ShapeType::Box || s.type_ == ShapeType::Cylinder || s.type_ == ShapeType::ConvexHull;
            Real limit = r;  // hulls: any finite radius
            if (s.type_ == ShapeType::Box) limit = minComponent(s.halfExtents_);
            if (s.type_ == ShapeType::Cylinder) limit = std::min(s.radius_, s.halfHeight_);
            if (!std::isfinite(r) || r < 0 || (r > 0 && !roundable) || r > limit) a.fail("invalid convex radius");
        }
        switch (s.type_) {
            case ShapeType::ConvexHull: {
                ConvexHull h = A::kReading ? ConvexHull{} : *s.hull_;
                std::vector<std::uint32_t> faceData;  // normal, offset, range per face
                std::size_t faceCount = h.faces.size();
                io(a, h.vertices);
                a.count(faceCount, 20);
                if constexpr (A::kReading) h.faces.resize(faceCount);
                for (HullFace& f : h.faces) io(a, f.normal), io(a, f.offset), io(a, f.firstIndex), io(a, f.indexCount);
                io(a, h.faceVertices), io(a, h.edges), io(a, h.centroid), io(a, h.volume), io(a, h.unitDensityInertia);
                io(a, h.bounds);
                if constexpr (A::kReading) {
                    for (const HullFace& f : h.faces) {
                        if (std::uint64_t(f.firstIndex) + f.indexCount > h.faceVertices.size()) a.fail("hull face out of range");
                    }
                    for (std::uint32_t v : h.faceVertices) {
                        if (v >= h.vertices.size()) a.fail("hull vertex index out of range");
                    }
                    for (const auto& e : h.edges) {
                        if (e[0] >= h.vertices.size() || e[1] >= h.vertices.size()) a.fail("hull edge out of range");
                    }
                    for (const Vec3& v : h.vertices) {
                        if (!isFinite(v) || maxComponent(abs(v)) > kMaxShapeCoordinate) {
                            a.fail("hull vertex not finite or beyond the limit of 1e12 m");
                        }
                    }
                    detail::deriveHullTables(h);  // derived, not saved
                    s.hull_ = std::make_shared<const ConvexHull>(std::move(h));
                    if (s.convexRadius_ > 0) {  // the rounded hull's stand-in is derived, not saved
                        try {
                            s.roundedHull_ = Shape::roundedHullFor(*s.hull_, s.convexRadius_);
                        } catch (const Error& e) {
                            a.fail(std::string("invalid rounded hull: ") + e.what());
                        }
                    }
                }
                break;
            }
            case ShapeType::Mesh: {
                std::vector<Vec3> vertices = A::kReading ? std::vector<Vec3>{} : s.mesh_->vertices;
                std::vector<std::array<std::uint32_t, 3>> triangles = A::kReading ? decltype(triangles){} : s.mesh_->triangles;
                io(a, vertices), io(a, triangles);
                if constexpr (A::kReading) {
                    try {
                        s.mesh_ = Shape::mesh(vertices, triangles).mesh_;
                    } catch (const Error& e) {
                        a.fail(std::string("invalid mesh: ") + e.what());
                    }
                }
                break;
            }
            case ShapeType::HeightField: {
                // From its definition, rebuilt (and validated again) on load, as a mesh.
                HeightField h;
                if constexpr (!A::kReading) {
                    const HeightField& f = *s.heightField_;
                    h.rows = f.rows, h.columns = f.columns, h.spacingX = f.spacingX, h.spacingZ = f.spacingZ;
                    h.heights = f.heights, h.holes = f.holes;
                }
                io(a, h.rows), io(a, h.columns), io(a, h.spacingX), io(a, h.spacingZ), io(a, h.heights), io(a, h.holes);
                if constexpr (A::kReading) {
                    try {
                        s.heightField_ = Shape::heightField(h.rows, h.columns, h.spacingX, h.spacingZ, h.heights, h.holes).heightField_;
                    } catch (const Error& e) {
                        a.fail(std::string("invalid heightfield: ") + e.what());
                    }
                }
                break;
            }
            case ShapeType::Compound: {
                std::vector<CompoundChild> children = A::kReading ? std::vector<CompoundChild>{} : *s.children_;
                std::size_t n = children.size();
                a.count(n, 2);
                if (n == 0) a.fail("compound without children");
                if constexpr (A::kReading) children.resize(n);
                for (CompoundChild& c : children) {
                    shape(a, c.shape, depth + 1);
                    io(a, c.transform);
                    // As Shape::compound makes them: a finite position within
                    // the size limit and a unit orientation.
                    if constexpr (A::kReading) {
                        const Transform& t = c.transform;
                        if (!isFinite(t.p) || maxComponent(abs(t.p)) > kMaxShapeCoordinate || !isFinite(t.q) ||
                            !(std::fabs(length(t.q) - 1) <= Real(1e-3))) {
                            a.fail("a compound child's position is not finite or beyond the limit of 1e12 m, or its orientation is not a unit quaternion");
                        }
                    }
                }
                if constexpr (A::kReading) s.setChildren(std::make_shared<const std::vector<CompoundChild>>(std::move(children)));
                break;
            }
            default: break;
        }
    }

    // ---- broad phase and its trees
    template <typename A>
    static void tree(A& a, DynamicTree& t) {
        std::size_t n = t.nodes_.size();
        a.count(n, 8);
        if constexpr (A::kReading) t.nodes_.resize(n);
        for (TreeNode& node : t.nodes_) {
            io(a, node.box), io(a, node.parent), io(a, node.child1), io(a, node.child2), io(a, node.userValue);
            io(a, node.height);
        }
        io(a, t.root_), io(a, t.freeList_), io(a, t.proxyCount_);
        if constexpr (A::kReading) t.descentValid_ = false;  // the depth-first copy is derived, not saved
    }
    template <typename A>
    static void broadPhase(A& a, BroadPhase& b) {
        // Written with every static proxy in its tree (none waiting), read into one with none waiting.
        b.settleStaticTree();
        b.restoreSkippedMoves();  // every entry in the buffer, as written before they could be skipped
        a.at("broad phase: static tree");
        tree(a, b.staticTree_);
        a.at("broad phase: moving tree");
        tree(a, b.movingTree_);
        a.at("broad phase: proxies");
        std::size_t n = b.records_.size();
        a.count(n, 8);
        if constexpr (A::kReading) b.records_.resize(n);
        for (auto& r : b.records_) {
            io(a, r.leaf), io(a, r.moveIndex), io(a, r.nextFree), io(a, r.userValue), io(a, r.filter);
            a.enumeration(r.type, BodyType::Dynamic);
            io(a, r.alive);
        }
        io(a, b.freeRecord_);
        a.at("broad phase: moves");
        std::size_t m = b.moveBuffer_.size();
        a.count(m, 8);
        if constexpr (A::kReading) b.moveBuffer_.resize(m);
        for (auto& e : b.moveBuffer_) io(a, e.proxy), io(a, e.fresh), io(a, e.oldFat);
    }

    template <typename A>
    static void contactManager(A& a, ContactManager& c) {
        broadPhase(a, c.broad_);
        a.at("contacts");
        io(a, c.proxyOfSlot_);
        std::size_t n = c.contacts_.size();
        a.count(n, 8);
        if constexpr (A::kReading) c.contacts_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            a.at("contacts", i);
            io(a, c.contacts_[i]);
        }
        a.at("contacts");
        io(a, c.freeContact_);
        a.at("contact events");
        io(a, c.beginEvents), io(a, c.endEvents), io(a, c.sensorBeginEvents), io(a, c.sensorEndEvents);
    }

    template <typename A>
    static void sleep(A& a, SleepManager& s) {
        io(a, s.nextIsland_);
    }

    template <typename A>
    static void particles(A& a, ParticleWorld& p) {
        a.at("particle settings");
        io(a, p.settings_.gravity), io(a, p.settings_.substeps), io(a, p.settings_.iterations), io(a, p.settings_.wind);
        io(a, p.settings_.airDensity);
        std::size_t n = p.slots_.size();
        a.count(n, 13);
        if constexpr (A::kReading) p.slots_.slots().resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            a.at("particle systems", i);
            auto& slot = p.slots_[i];
            io(a, slot.alive), io(a, slot.generation), io(a, slot.order);
            if (slot.alive) {
                if constexpr (A::kReading) slot.system = std::make_unique<ParticleSystem>();
                io(a, *slot.system);
            }
        }
        a.at("particle systems");
        io(a, p.slots_.freeSlots()), io(a, p.nextOrder_);
        if (!p.slots_.consistent()) a.fail("free particle system slot list");
    }

    static std::size_t contactCount(const ContactManager& c) { return c.contacts_.size(); }
    static std::string validateBroadPhase(const ContactManager& c) { return c.broad_.validate(); }
    static const detail::LargeArray<ProxyId>& proxyOfSlot(const ContactManager& c) { return c.proxyOfSlot_; }
};

}  // namespace fulcrum

namespace fulcrum::detail {
namespace {

// Shapes shared between bodies (hulls, meshes, compounds hold their geometry
// through a shared_ptr) are written once and shared again on load.
const void* sharedGeometry(const Shape& s) {
    switch (s.type()) {
        case ShapeType::ConvexHull: return &s.hull();
        case ShapeType::Mesh: return &s.mesh();
        case ShapeType::HeightField: return &s.heightField();
        case ShapeType::Compound: return s.children().data();
        default: return nullptr;
    }
}

// The whole world, in file order.
template <typename A>
void worldState(A& a, WorldImpl& w, std::string& userData) {
    a.at("user data");
    io(a, userData);
    a.at("settings");
    io(a, w.settings);
    a.at("world");
    io(a, w.time), io(a, w.stepCount), io(a, w.nextBodySerial), io(a, w.wasSleeping);
    if (a.version >= 5) io(a, w.lastStepDt);

    // ---- shape table, then bodies referring to it
    a.at("shapes");
    std::vector<Shape> shapes;
    std::vector<std::uint32_t> shapeOfBody;
    if constexpr (!A::kReading) {
        std::map<const void*, std::uint32_t> seen;
        for (const BodyCold& c : w.cold) {
            const void* key = sharedGeometry(c.shape);
            if (key != nullptr) {
                const auto [it, inserted] = seen.try_emplace(key, static_cast<std::uint32_t>(shapes.size()));
                if (inserted) shapes.push_back(c.shape);
                shapeOfBody.push_back(it->second);
            } else {
                shapeOfBody.push_back(static_cast<std::uint32_t>(shapes.size()));
                shapes.push_back(c.shape);
            }
        }
    }
    std::size_t shapeCount = shapes.size();
    a.count(shapeCount, 13);
    if constexpr (A::kReading) shapes.resize(shapeCount);
    for (std::size_t i = 0; i < shapeCount; ++i) {
        a.at("shapes", i);
        SnapshotAccess::shape(a, shapes[i], 0);
    }

    a.at("body slots");
    io(a, w.bodySlots), io(a, w.freeBodySlots);
    std::size_t n = w.motion.size();
    a.at("bodies");
    a.count(n, 100);
    if constexpr (A::kReading) {
        w.motion.resize(n), w.forces.resize(n), w.applied.resize(n), w.params.resize(n), w.cold.resize(n);
        w.previous.resize(n), w.denseToSlot.resize(n), w.scratch.resize(n);
        shapeOfBody.resize(n);
    }
    for (std::size_t i = 0; i < n; ++i) {
        a.at("bodies", i);
        io(a, w.motion[i]), io(a, w.forces[i]), io(a, w.applied[i]), io(a, w.params[i]);
        io(a, w.cold[i].name), io(a, w.cold[i].creationSerial), io(a, shapeOfBody[i]);
        io(a, w.previous[i]), io(a, w.denseToSlot[i]), io(a, w.scratch[i]);
        if constexpr (A::kReading) {
            if (shapeOfBody[i] >= shapes.size()) a.fail("shape index out of range");
            w.cold[i].shape = shapes[shapeOfBody[i]];
        }
    }

    a.at("springs");
    io(a, w.springs.slots()), io(a, w.springs.freeSlots());
    std::uint64_t liveSprings = w.springs.liveCount();  // kept in the format; the pool counts for itself
    io(a, liveSprings);
    if (liveSprings != w.springs.liveCount()) a.fail("live spring count");
    a.at("joints");
    std::size_t jointCount = w.joints.size();
    a.count(jointCount, 16);
    if constexpr (A::kReading) w.joints.slots().resize(jointCount);
    for (std::size_t i = 0; i < jointCount; ++i) {
        a.at("joints", i);
        io(a, w.joints[i]);
    }
    a.at("joints");
    io(a, w.joints.freeSlots());

    SnapshotAccess::contactManager(a, w.contactManager);
    a.at("contact reports");
    std::size_t reports = w.contactReportCount;
    a.count(reports, 8);
    if constexpr (A::kReading) w.contacts.resize(reports);
    for (std::size_t i = 0; i < reports; ++i) io(a, w.contacts[i]);
    w.contactReportCount = reports;
    a.at("sleep");
    SnapshotAccess::sleep(a, w.sleepManager);

    SnapshotAccess::particles(a, w.particles.world);
    a.at("particle systems");
    io(a, w.particles.live);

    // Version 6: characters and vehicles (docs/characters.md, docs/vehicles.md).
    if (a.version >= 6) {
        a.at("characters");
        io(a, w.characters.pool.slots()), io(a, w.characters.pool.freeSlots()), io(a, w.characters.order);
        a.at("vehicles");
        io(a, w.vehicles.pool.slots()), io(a, w.vehicles.pool.freeSlots()), io(a, w.vehicles.order);
    } else if (!w.characters.empty() || !w.vehicles.empty()) {
        a.fail("characters and vehicles need format version 6 or later");
    }
}

// ---------------------------------------------------------------- checks after loading

// Structural consistency of what was read: every index points where it must,
// so no later step reads out of range. (The checksum already caught random
// corruption; this guards against a file written by a buggy or hostile tool.)
void validateLoaded(const Reader& r, WorldImpl& w) {
    const auto fail = [&](const std::string& what) { throw Error(r.source() + ": inconsistent snapshot: " + what); };
    const std::size_t n = w.motion.size();
    for (std::size_t d = 0; d < n; ++d) {
        const std::uint32_t slot = w.denseToSlot[d];
        if (slot >= w.bodySlots.size() || w.bodySlots[slot].dense != d) fail("bodies[" + std::to_string(d) + "] slot table");
        const Shape& s = w.cold[d].shape;
        if (w.params[d].type != BodyType::Static && s.staticOnly()) fail("bodies[" + std::to_string(d) + "] moving body with a static-only shape");
        // The state the step reads without checking (found by
        // fuzz/snapshot_fuzz.cpp: a NaN pose reached the broad phase's
        // assertion on the box it moves to).
        const BodyMotion& m = w.motion[d];
        const Real qq = dot(m.q, m.q);
        if (!isFinite(m.com) || !isFinite(m.q) || !isFinite(m.v) || !isFinite(m.w) || !std::isfinite(m.invMass) ||
            !isFinite(m.invInertiaWorld) || !isFinite(w.forces[d].force) || !isFinite(w.forces[d].torque) ||
            !(std::fabs(qq - 1) < Real(1e-3))) {
            fail("bodies[" + std::to_string(d) + "] pose, velocity or force not finite (or orientation not unit)");
        }
        const BodyParams& bp = w.params[d];
        const Real numbers[] = {bp.mass, bp.linearDamping, bp.angularDamping, bp.linearDrag, bp.quadraticDrag, bp.gravityScale,
                                bp.friction, bp.restitution, bp.rollingResistance, bp.extent, bp.sleepTime};
        bool finiteNumbers = isFinite(bp.localCom) && isFinite(bp.localInertia) && isFinite(bp.invLocalInertia) &&
                             isFinite(w.applied[d].force) && isFinite(w.applied[d].torque);
        for (const Real x : numbers) finiteNumbers = finiteNumbers && std::isfinite(x);
        if (!finiteNumbers) fail("bodies[" + std::to_string(d) + "] mass, material or damping not finite");
        const AABB box = s.bounds(Transform{m.com, m.q});
        if (!isFinite(box.min) || !isFinite(box.max) || box.isEmpty()) fail("bodies[" + std::to_string(d) + "] shape bounds not finite");
    }
    std::size_t liveSlots = 0;
    for (const BodySlot& s : w.bodySlots) {
        if (s.dense != kNoIndex) {
            if (s.dense >= n) fail("body slot refers to a missing body");
            ++liveSlots;
        }
    }
    if (liveSlots != n) fail("body slot count");
    for (std::uint32_t f : w.freeBodySlots) {
        if (f >= w.bodySlots.size() || w.bodySlots[f].dense != kNoIndex) fail("free body slot list");
    }
    const auto bodyOk = [&](BodyId id) { return id.isNull() || w.isLive(id); };
    for (std::size_t i = 0; i < w.springs.size(); ++i) {
        const SpringData& s = w.springs[i];
        if (s.alive && (!bodyOk(s.bodyA) || !bodyOk(s.bodyB))) fail("springs[" + std::to_string(i) + "] body handle");
    }
    if (!w.springs.consistent()) fail("free spring slot list");
    for (std::size_t i = 0; i < w.joints.size(); ++i) {
        const JointData& j = w.joints[i];
        if (j.alive && (!bodyOk(j.def.bodyA) || !bodyOk(j.def.bodyB))) fail("joints[" + std::to_string(i) + "] body handle");
    }
    if (!w.joints.consistent()) fail("free joint slot list");
    if (!w.characters.pool.consistent()) fail("free character slot list");
    for (const std::uint32_t slot : w.characters.order) {
        if (slot >= w.characters.pool.size() || !w.characters.pool[slot].alive) fail("character order");
        const CharacterData& c = w.characters.pool[slot];
        if (!w.isLive(c.body) || w.params[w.resolveBody(c.body, "snapshot")].type != BodyType::Kinematic ||
            w.cold[w.resolveBody(c.body, "snapshot")].shape.type() != ShapeType::Capsule) {
            fail("characters[" + std::to_string(slot) + "] capsule body");
        }
        if (!bodyOk(c.groundBody)) fail("characters[" + std::to_string(slot) + "] ground body");
    }
    if (w.characters.order.size() != w.characters.pool.liveCount()) fail("character count");
    if (!w.vehicles.pool.consistent()) fail("free vehicle slot list");
    for (const std::uint32_t slot : w.vehicles.order) {
        if (slot >= w.vehicles.pool.size() || !w.vehicles.pool[slot].alive) fail("vehicle order");
        const VehicleData& v = w.vehicles.pool[slot];
        if (!bodyOk(v.def.chassis) || v.wheels.size() != v.def.wheels.size() || v.def.wheels.empty() ||
            v.def.gearbox.ratios.empty() || v.def.engine.torqueCurve.empty() || (v.gear < 1 && v.gear != -1) ||
            v.gear > static_cast<int>(v.def.gearbox.ratios.size())) {
            fail("vehicles[" + std::to_string(slot) + "] definition");
        }
        for (const AntiRollBar& b : v.def.antiRollBars) {
            if (b.left >= v.wheels.size() || b.right >= v.wheels.size()) fail("vehicles[" + std::to_string(slot) + "] anti-roll bar");
        }
        for (const WheelData& wh : v.wheels) {
            if (!bodyOk(wh.state.contactBody)) fail("vehicles[" + std::to_string(slot) + "] wheel contact body");
        }
    }
    if (w.vehicles.order.size() != w.vehicles.pool.liveCount()) fail("vehicle count");

    // Broad phase: the trees' and records' own invariants, then the links to bodies.
    if (const std::string why = SnapshotAccess::validateBroadPhase(w.contactManager); !why.empty()) fail("broad phase: " + why);
    const BroadPhase& bp = w.contactManager.broadPhase();
    const auto& proxies = SnapshotAccess::proxyOfSlot(w.contactManager);
    if (proxies.size() < w.bodySlots.size()) fail("proxy table shorter than the body slots");
    for (std::uint32_t slot = 0; slot < w.bodySlots.size(); ++slot) {
        if (w.bodySlots[slot].dense == kNoIndex) continue;
        const ProxyId p = proxies[slot];
        if (!bp.isProxy(p) || bp.userValue(p) != slot) fail("body slot " + std::to_string(slot) + " has no broad-phase proxy");
    }
    const std::size_t slotCount = w.bodySlots.size();
    const std::size_t contactCount = SnapshotAccess::contactCount(w.contactManager);
    const auto& contacts = w.contactManager.contacts();
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const Contact& c = contacts[i];
        if (c.nextFree != UINT32_MAX && c.nextFree >= contactCount) fail("contacts[" + std::to_string(i) + "] free link");
        if (!c.alive) continue;
        if (c.slotA >= slotCount || c.slotB >= slotCount || w.bodySlots[c.slotA].dense == kNoIndex ||
            w.bodySlots[c.slotB].dense == kNoIndex || !bp.isProxy(c.proxyA) || !bp.isProxy(c.proxyB)) {
            fail("contacts[" + std::to_string(i) + "] refers to a missing body or proxy");
        }
        for (const CachedManifold& m : c.manifolds) {
            if (m.pointCount > 4) fail("contacts[" + std::to_string(i) + "] manifold point count");
        }
        const auto coefficient = [](Real x) { return x >= 0 && x < std::numeric_limits<Real>::infinity(); };
        if (!coefficient(c.friction) || !coefficient(c.restitution) || !coefficient(c.rollingResistance)) {
            fail("contacts[" + std::to_string(i) + "] material is negative or not finite");
        }
    }
    // The free list: in range, dead entries only, no cycle (found by
    // fuzz/snapshot_fuzz.cpp: a head past the end made the next new contact
    // write outside the table).
    std::size_t freeSteps = 0;
    for (std::uint32_t f = w.contactManager.firstFreeContact(); f != UINT32_MAX; f = contacts[f].nextFree) {
        if (f >= contactCount || contacts[f].alive || ++freeSteps > contactCount) fail("free contact list");
    }

    // Particles: the particle world's settings (its sub-steps and sweeps
    // too: found by fuzz/snapshot_fuzz.cpp, a count of 2e9 ran for ever),
    // then array lengths and indices.
    const ParticleWorld& pw = w.particles.world;
    try {
        ParticleWorld check;
        check.setSettings(pw.settings());
    } catch (const Error& e) {
        fail(std::string("particle settings: ") + e.what());
    }
    if (pw.settings().substeps > kMaxSubsteps || pw.settings().iterations > kMaxSolverIterations) {
        fail("particle settings: substeps " + std::to_string(pw.settings().substeps) + " and iterations " +
             std::to_string(pw.settings().iterations) + " must be at most " + std::to_string(kMaxSubsteps) + " and " +
             std::to_string(kMaxSolverIterations));
    }
    // The checks below walk the live list; the particle step walks every
    // live slot. So the list must name each live slot exactly once (found by
    // fuzz/snapshot_fuzz.cpp: a live system missing from the list went
    // unchecked, and its constraint indices ran past its particles).
    if (w.particles.live.size() != pw.systemCount()) fail("live particle system list");
    std::vector<bool> listedSystem;
    for (const ParticleSystemId id : w.particles.live) {
        if (!pw.isValid(id)) fail("live particle system handle");
        if (id.index >= listedSystem.size()) listedSystem.resize(id.index + std::size_t{1}, false);
        if (listedSystem[id.index]) fail("live particle system listed twice");
        listedSystem[id.index] = true;
        const ParticleSystem& s = pw.system(id);
        const std::size_t np = s.position.size();
        if (s.displacement.size() != np || s.restPosition.size() != np || s.force.size() != np ||
            s.inverseMass.size() != np || s.radius.size() != np) {
            fail("particle system '" + s.name + "' array lengths");
        }
        // Numbers the particle step reads unchecked (found by
        // fuzz/snapshot_fuzz.cpp: a bad position sent the self-collision
        // grid's cell index out of its table).
        bool finiteNumbers = std::isfinite(s.damping) && std::isfinite(s.linearDrag) && std::isfinite(s.friction) &&
                             std::isfinite(s.dragCoefficient) && std::isfinite(s.liftCoefficient) &&
                             std::isfinite(s.selfCollisionExclusion) && std::isfinite(s.previousSubstep);
        for (std::size_t i = 0; i < np && finiteNumbers; ++i) {
            finiteNumbers = isFinite(s.position[i]) && isFinite(s.displacement[i]) && isFinite(s.restPosition[i]) &&
                            isFinite(s.force[i]) && std::isfinite(s.inverseMass[i]) && s.inverseMass[i] >= 0 &&
                            std::isfinite(s.radius[i]) && s.radius[i] > 0;
        }
        if (!finiteNumbers) fail("particle system '" + s.name + "' positions, masses, radii or material not finite");
        for (const DistanceConstraintGroup* g : {&s.stretch, &s.shear, &s.bend, &s.tethers}) {
            if (g->lambda.size() != g->constraints.size()) fail("particle system '" + s.name + "' multipliers");
            if (!std::isfinite(g->compliance) || g->compliance < 0) fail("particle system '" + s.name + "' compliance");
            for (const DistanceConstraint& c : g->constraints) {
                if (c.a >= np || c.b >= np) fail("particle system '" + s.name + "' constraint index");
                if (!std::isfinite(c.restLength) || c.restLength < 0) fail("particle system '" + s.name + "' rest length");
            }
        }
        for (const ParticlePin& p : s.pins) {
            if (p.particle >= np) fail("particle system '" + s.name + "' pin index");
            if (!isFinite(p.target)) fail("particle system '" + s.name + "' pin target");
        }
        for (const ParticleAttachment& at : s.attachments) {
            if (at.particle >= np || at.body >= slotCount || w.bodySlots[at.body].dense == kNoIndex) {
                fail("particle system '" + s.name + "' attachment");
            }
        }
        for (const ParticleSpring& sp : s.springs) {
            if (sp.a >= np || sp.b >= np) fail("particle system '" + s.name + "' spring index");
        }
        for (const ParticleTriangle& t : s.triangles) {
            if (t.a >= np || t.b >= np || t.c >= np) fail("particle system '" + s.name + "' triangle index");
        }
        if (s.kind == ParticleSystemKind::Cloth && static_cast<std::size_t>(s.gridSize[0]) * static_cast<std::size_t>(s.gridSize[1]) != np) {
            fail("particle system '" + s.name + "' cloth grid");
        }
    }
}

std::string fileLabel(const std::filesystem::path& path) { return path.string(); }

}  // namespace
}  // namespace fulcrum::detail

namespace fulcrum {

std::vector<std::uint8_t> detail::saveSnapshotAsVersion(const World& world, std::uint32_t version, std::string_view userData) {
    if (version < kOldestSnapshotVersion || version > kSnapshotVersion) {
        throw Error("saving a snapshot: cannot write format version " + std::to_string(version) + " (this build writes " +
                    std::to_string(kOldestSnapshotVersion) + " to " + std::to_string(kSnapshotVersion) + ")");
    }
    detail::Writer w;
    w.version = version;
    w.out.resize(detail::kHeaderSize);
    std::string data(userData);
    // The contact report is built when read (world_impl.hpp): the snapshot holds it.
    const_cast<WorldImpl&>(detail::implOf(world)).ensureContactReport();
    // The field lists serve reading and writing alike; writing only reads.
    detail::worldState(w, const_cast<WorldImpl&>(detail::implOf(world)), data);

    const std::uint64_t payload = w.out.size() - detail::kHeaderSize;
    const std::uint64_t checksum = detail::fnv1a(w.out.data() + detail::kHeaderSize, w.out.size() - detail::kHeaderSize);
    detail::Writer header;
    for (char c : detail::kMagic) header.put(static_cast<std::uint8_t>(c), 1);
    header.put(version, 4);
    header.put(sizeof(Real), 4);
    header.put(payload, 8);
    header.put(checksum, 8);
    std::copy(header.out.begin(), header.out.end(), w.out.begin());
    return std::move(w.out);
}

std::vector<std::uint8_t> saveSnapshotToMemory(const World& world, std::string_view userData) {
    return detail::saveSnapshotAsVersion(world, kSnapshotVersion, userData);
}

void saveSnapshot(const World& world, const std::filesystem::path& path, std::string_view userData) {
    const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world, userData);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(detail::fileLabel(path) + ": cannot open the file for writing");
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw Error(detail::fileLabel(path) + ": error while writing the snapshot");
}

World loadSnapshotFromMemory(std::span<const std::uint8_t> bytes, std::string* userData, std::string_view sourceName) {
    const std::string source(sourceName);
    using detail::kHeaderSize;
    const auto le = [&](std::size_t at, std::size_t count) {
        std::uint64_t v = 0;
        for (std::size_t i = 0; i < count; ++i) v |= static_cast<std::uint64_t>(bytes[at + i]) << (8 * i);
        return v;
    };
    if (bytes.size() < 8 || std::memcmp(bytes.data(), detail::kMagic, 8) != 0) {
        throw Error(source + ": not a Fulcrum snapshot (the file does not start with \"FULCSNAP\")");
    }
    if (bytes.size() < kHeaderSize) {
        throw Error(source + ": truncated at byte " + std::to_string(bytes.size()) + " (header, " +
                    std::to_string(kHeaderSize) + " bytes)");
    }
    const std::uint64_t version = le(8, 4);
    if (version < detail::kOldestSnapshotVersion || version > kSnapshotVersion) {
        throw Error(source + ": unsupported snapshot version " + std::to_string(version) + " (this build reads versions " +
                    std::to_string(detail::kOldestSnapshotVersion) + " to " + std::to_string(kSnapshotVersion) + ")");
    }
    const std::uint64_t realSize = le(12, 4);
    if (realSize != sizeof(Real)) {
        throw Error(source + ": written with " + std::to_string(realSize * 8) + "-bit reals, this build uses " +
                    std::to_string(sizeof(Real) * 8) + "-bit reals");
    }
    const std::uint64_t payloadSize = le(16, 8);
    const std::uint64_t checksum = le(24, 8);
    const std::size_t available = bytes.size() - kHeaderSize;
    const bool truncated = available < payloadSize;
    if (available > payloadSize) {
        throw Error(source + ": corrupt: " + std::to_string(available - payloadSize) +
                    " bytes after the end of the snapshot (the header declares " + std::to_string(kHeaderSize + payloadSize) +
                    " bytes)");
    }
    const std::span<const std::uint8_t> payload = bytes.subspan(kHeaderSize);
    if (!truncated && detail::fnv1a(payload.data(), payload.size()) != checksum) {
        throw Error(source + ": corrupt: checksum mismatch (the data was changed after it was written)");
    }

    // A truncated file is still parsed, to say in which part it ends.
    detail::Reader reader(payload, source, truncated, static_cast<std::uint32_t>(version));
    std::string data;
    World world;
    WorldImpl& w = detail::implOf(world);
    detail::worldState(reader, w, data);
    if (truncated) {
        throw Error(source + ": truncated at byte " + std::to_string(bytes.size()) + " (the header declares " +
                    std::to_string(kHeaderSize + payloadSize) + " bytes)");
    }
    if (!reader.atEnd()) reader.fail("corrupt: data left over");
    try {
        World check(w.settings);  // the settings' validation, as World's constructor does it
    } catch (const Error& e) {
        throw Error(source + ": invalid settings: " + e.what());
    }
    detail::validateLoaded(reader, w);
    if (reader.version < 9) w.contactManager.mixMaterials(w);

    // Grow the per-step buffers as body creation would have (no allocation in the next step).
    const std::size_t bufferBodies = w.contactManager.bufferBodyCount();
    w.contactManager.reserve(bufferBodies, w.settings.maxContactPairs, w.contacts);
    w.contactSolver.reserve(bufferBodies);
    w.sleepManager.reserve(bufferBodies);
    if (userData != nullptr) *userData = std::move(data);
    return world;
}

World loadSnapshot(const std::filesystem::path& path, std::string* userData) {
    // The magic first: a large file that is no snapshot is refused without reading it all.
    const std::vector<std::uint8_t> magic = detail::readInputFilePrefix(path, "snapshot", sizeof detail::kMagic);
    if (magic.size() < sizeof detail::kMagic || std::memcmp(magic.data(), detail::kMagic, sizeof detail::kMagic) != 0) {
        return loadSnapshotFromMemory(magic, userData, detail::fileLabel(path));  // throws: not a Fulcrum snapshot
    }
    return loadSnapshotFromMemory(detail::readInputFile(path, "snapshot"), userData, detail::fileLabel(path));
}

}  // namespace fulcrum
