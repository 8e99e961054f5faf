// The soak (issue 26; docs/reliability.md, "Soak"): a world that never
// settles into a steady set of objects, run on two threads for a while, must
// keep its memory flat after a warm-up, its energy bounded and its state
// finite. Every step creates and destroys bodies; joints break and are
// mended; a cloth lies on a moving kinematic paddle and on the falling
// bodies; a rope hangs from bodies that come and go; a stack falls asleep and
// is woken; and the world is saved to a snapshot and continued from the
// loaded copy, mid-run, over and over.
//
// The test runs it for 25 s of wall time (whatever that is in steps on the
// build at hand). By hand, for as long as you like:
//     FULCRUM_SOAK_SECONDS=3600 build/release/tests/test_soak
// prints the same figures at the end (and every FULCRUM_SOAK_REPORT seconds).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum/snapshot.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;

namespace {

constexpr Real kDt = Real(1) / Real(60);
constexpr std::size_t kMaxSpawned = 120;     // live falling bodies; the oldest go first
constexpr int kChainLinks = 6;
// Periods, in steps, of the events; short, so that a 25 s run under the
// sanitizers still goes through each several times before the warm-up ends.
constexpr std::uint64_t kKickChainEvery = 90;   // an impulse that breaks a chain joint
constexpr std::uint64_t kMendAfter = 45;        // steps a broken joint stays broken
constexpr std::uint64_t kWakeStackEvery = 170;  // the sleeping stack is pushed
constexpr std::uint64_t kNewRopeEvery = 130;    // the rope is replaced (tied to a newer body)
constexpr std::uint64_t kNewClothEvery = 400;   // the cloth is replaced
constexpr std::uint64_t kSnapshotEvery = 110;   // save, load, continue from the copy
// The bounds of "energy stays bounded": bodies fall from at most 10 m
// (14 m/s) and the paddle moves at under 3 m/s, so a body faster than this
// gained energy the scene never gave it.
constexpr Real kMaxSpeed = 40;        // m/s
constexpr Real kMaxSpin = 300;        // rad/s (a small capsule hit on its end spins fast)

BodyDef bodyDef(const Shape& shape, BodyType type, const Vec3& position, Real mass = 0) {
    BodyDef def;
    def.shape = shape;
    def.type = type;
    def.position = position;
    def.mass = mass;
    return def;
}

// AddressSanitizer keeps freed blocks in a quarantine (256 MB by default)
// before reusing them, so under it the resident size grows by design and the
// steps are many times slower: the RSS check is left out and the warm-up is
// shorter there (the live-heap check stays).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

long residentBytes() {  // from /proc/self/statm (pages)
    std::ifstream statm("/proc/self/statm");
    long size = 0, resident = 0;
    statm >> size >> resident;
    return resident * 4096;
}

struct Figures {
    std::uint64_t steps = 0, created = 0, destroyed = 0, breaks = 0, mends = 0, wakes = 0, snapshots = 0;
    std::uint64_t sleepingSeen = 0;  // steps that ended with the stack asleep
    std::uint64_t ropes = 0, cloths = 0;
    Real maxSpeed = 0, maxSpin = 0;
    double maxKinetic = 0;
};

class Churn {
public:
    Churn() : world_(makeDef()), rng_(2026) {
        world_.createBody(bodyDef(Shape::plane({0, 1, 0}, 0), BodyType::Static, {}));
        paddle_ = world_.createBody(bodyDef(Shape::box({Real(1.5), Real(0.1), Real(1.5)}), BodyType::Kinematic, {0, 2, 0}));
        // A chain hanging from the static world, its joints breakable.
        BodyId previous = kWorldBody;
        for (int i = 0; i < kChainLinks; ++i) {
            const Vec3 at{8, Real(8) - Real(0.5) * static_cast<Real>(i), 0};
            const BodyId link = world_.createBody(bodyDef(Shape::capsule(Real(0.08), Real(0.15)), BodyType::Dynamic, at, 1));
            BallJointDef def = BallJointDef::fromWorld(world_, previous, link, at + Vec3{0, Real(0.25), 0});
            def.breakForce = 150;  // N: the chain's weight is 59 N; a kick breaks it
            chain_.push_back(world_.createJoint(def));
            links_.push_back(link);
            linkHome_.push_back(at);
            previous = link;
        }
        chainEnd_ = previous;
        // A stack away from the rain, to fall asleep and be woken.
        for (int i = 0; i < 3; ++i) {
            stack_.push_back(world_.createBody(bodyDef(Shape::box({Real(0.4), Real(0.2), Real(0.4)}), BodyType::Dynamic,
                                                {-8, Real(0.2) + Real(0.41) * static_cast<Real>(i), 0}, 2)));
        }
        shapes_ = {Shape::sphere(Real(0.2)), Shape::box({Real(0.2), Real(0.15), Real(0.25)}), Shape::capsule(Real(0.1), Real(0.2)),
                   Shape::convexHull(std::vector<Vec3>{{0, Real(0.3), 0}, {Real(0.25), -Real(0.1), 0}, {-Real(0.2), -Real(0.1), Real(0.2)},
                                                       {-Real(0.1), -Real(0.1), -Real(0.25)}})};
        newCloth();
    }

    void step() {
        const std::uint64_t k = world_.stepCount();
        spawn();
        despawn();
        // The paddle sweeps under the cloth: a kinematic target every step.
        const Real t = static_cast<Real>(k) * kDt;
        world_.moveKinematic(paddle_, {{std::sin(t) * Real(1.5), 2, 0}, Quat::fromAxisAngle({0, 1, 0}, Real(0.5) * t)}, kDt);
        if (k % kKickChainEvery == kKickChainEvery / 2) world_.applyLinearImpulseAtCenter(chainEnd_, {12, 4, 0});
        mendChain(k);
        if (k % kWakeStackEvery == 0) {
            world_.applyLinearImpulseAtCenter(stack_[0], {0, 0, 3});
            ++figures_.wakes;
        }
        if (k % kNewRopeEvery == 0) newRope();
        if (k % kNewClothEvery == kNewClothEvery / 2) newCloth();

        world_.step(kDt);
        ++figures_.steps;
        figures_.breaks += world_.jointBreakEvents().size();
        if (!world_.isAwake(stack_[2])) ++figures_.sleepingSeen;
        check();
        if (world_.stepCount() % kSnapshotEvery == 0) restartFromSnapshot();
    }

    const Figures& figures() const { return figures_; }
    World& world() { return world_; }

private:
    static WorldDef makeDef() {
        WorldDef def;
        def.threads = 2;
        def.parallelMinBodies = 0;  // the two threads on every step, however small
        return def;
    }

    // A while after a joint broke, the chain is put back together: every link
    // back home, at rest, and the broken joints enabled again (which mends
    // them). Mending without bringing the links back would ask the solver to
    // close a gap of metres in one step (docs/reliability.md, "Soak").
    void mendChain(std::uint64_t k) {
        bool broken = false;
        for (const JointId j : chain_) broken = broken || world_.isJointBroken(j);
        if (!broken) {
            brokenSince_ = 0;
            return;
        }
        if (brokenSince_ == 0) brokenSince_ = k;
        if (k - brokenSince_ < kMendAfter) return;
        for (std::size_t i = 0; i < links_.size(); ++i) {
            world_.setTransform(links_[i], linkHome_[i], Quat::identity());
            world_.setLinearVelocity(links_[i], Vec3::zero());
            world_.setAngularVelocity(links_[i], Vec3::zero());
        }
        for (const JointId j : chain_) {
            if (!world_.isJointBroken(j)) continue;
            world_.setJointEnabled(j, true);
            ++figures_.mends;
        }
        brokenSince_ = 0;
    }

    void spawn() {
        std::uniform_real_distribution<Real> across(-3, 3), height(6, 10);
        for (int i = 0; i < 2; ++i) {
            BodyDef def;
            def.shape = shapes_[rng_() % shapes_.size()];
            def.position = {across(rng_), height(rng_), across(rng_)};
            def.angularVelocity = {across(rng_), across(rng_), across(rng_)};
            spawned_.push_back(world_.createBody(def));
            ++figures_.created;
        }
    }

    void despawn() {
        while (spawned_.size() > kMaxSpawned) {
            world_.destroyBody(spawned_.front());  // the rope tied to it lets go
            spawned_.pop_front();
            ++figures_.destroyed;
        }
    }

    void newRope() {
        if (!rope_.isNull() && world_.isValid(rope_)) world_.destroyParticleSystem(rope_);
        RopeDef def;
        def.start = {4, 9, 0};
        def.end = {4, 6, 0};
        def.segments = 12;
        def.attachEnd = spawned_.empty() ? kWorldBody : spawned_.back();
        if (!def.attachEnd.isNull()) def.end = world_.position(def.attachEnd);
        rope_ = world_.createRope(def);
        ++figures_.ropes;
    }

    void newCloth() {
        if (!cloth_.isNull() && world_.isValid(cloth_)) world_.destroyParticleSystem(cloth_);
        ClothDef def;
        def.origin = {-Real(0.9), Real(2.6), -Real(0.9)};
        def.size = {10, 10};
        def.spacing = Real(0.2);
        def.bendCompliance = Real(0.1);
        cloth_ = world_.createCloth(def);
        ++figures_.cloths;
    }

    void check() {
        double kinetic = world_.energy().kinetic;
        ASSERT_TRUE(std::isfinite(kinetic)) << "step " << world_.stepCount();
        figures_.maxKinetic = std::max(figures_.maxKinetic, kinetic);
        for (const BodyId id : world_.bodies()) {
            if (world_.bodyType(id) != BodyType::Dynamic) continue;
            const Real v = length(world_.linearVelocity(id)), w = length(world_.angularVelocity(id));
            ASSERT_TRUE(std::isfinite(v) && std::isfinite(w))
                << "step " << world_.stepCount() << ": body " << id.index << " velocity " << world_.linearVelocity(id).x << " "
                << world_.linearVelocity(id).y << " " << world_.linearVelocity(id).z << " spin " << world_.angularVelocity(id).x
                << " position " << world_.position(id).x << " " << world_.position(id).y << " mass " << world_.mass(id);
            figures_.maxSpeed = std::max(figures_.maxSpeed, v);
            figures_.maxSpin = std::max(figures_.maxSpin, w);
        }
        for (const ParticleSystemId p : world_.particleSystems()) {
            for (const Vec3& x : world_.particlePositions(p)) {
                ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z)) << "step " << world_.stepCount();
            }
        }
    }

    // Saves the world, then steps the original once and the loaded copy once:
    // they must agree bit for bit (snapshots resume exactly); the run goes on
    // with the copy, so the next steps run on a world that was loaded.
    void restartFromSnapshot() {
        const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world_);
        World copy = loadSnapshotFromMemory(bytes);
        copy.setThreadCount(2);
        world_.step(kDt);
        copy.step(kDt);
        ++figures_.steps;
        for (const BodyId id : world_.bodies()) {
            const Transform a = world_.transform(id), b = copy.transform(id);
            ASSERT_TRUE(a.p.x == b.p.x && a.p.y == b.p.y && a.p.z == b.p.z && a.q.x == b.q.x && a.q.w == b.q.w)
                << "the loaded snapshot went another way at step " << world_.stepCount();
        }
        world_ = std::move(copy);
        ++figures_.snapshots;
    }

    World world_;
    std::mt19937 rng_;
    std::vector<Shape> shapes_;
    std::deque<BodyId> spawned_;
    BodyId paddle_, chainEnd_;
    std::vector<JointId> chain_;
    std::vector<BodyId> links_;
    std::vector<Vec3> linkHome_;
    std::uint64_t brokenSince_ = 0;
    std::vector<BodyId> stack_;
    ParticleSystemId rope_, cloth_;
    Figures figures_;
};

double envSeconds(const char* name, double fallback) {
    const char* v = std::getenv(name);
    return v != nullptr ? std::atof(v) : fallback;
}

}  // namespace

TEST(Soak, ChurnOnTwoThreadsKeepsMemoryFlatEnergyBoundedAndNoNaN) {
    const double seconds = envSeconds("FULCRUM_SOAK_SECONDS", 25);
    const double reportEvery = envSeconds("FULCRUM_SOAK_REPORT", 0);
    // Warm-up: the first quarter of the run, and at least every event twice
    // (once under AddressSanitizer), so that the buffers have grown to their
    // working size: the most bodies, contacts, particles and snapshot bytes
    // the churn reaches.
    const std::uint64_t minWarmupSteps = kAddressSanitizer ? kNewClothEvery : 2 * kNewClothEvery;
    using Clock = std::chrono::steady_clock;
    const Clock::time_point start = Clock::now();
    const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

    test::HeapBudget heap;  // measures only
    Churn churn;
    long long heapAfterWarmup = -1, heapMax = 0, heapWarmupPeak = 0;  // heapAfterWarmup: the warm-up's peak
    long rssAfterWarmup = 0, rssMax = 0, rssWarmupPeak = 0;
    double nextReport = reportEvery;
    while (elapsed() < seconds || churn.figures().steps < 2 * minWarmupSteps) {
        churn.step();
        if (::testing::Test::HasFatalFailure()) return;
        const Figures& f = churn.figures();
        // The live heap swings by about 0.3 MB in the double build within the
        // warm-up and after it (a cloth or rope replaced, a snapshot's bytes,
        // the contacts' count), so "flat" compares peaks: the highest value
        // after the warm-up against the highest during it. Comparing against
        // the value at the warm-up's last step failed when that step fell in
        // a trough (a loaded machine ends the warm-up at other steps).
        if (heapAfterWarmup < 0) {
            heapWarmupPeak = std::max(heapWarmupPeak, heap.growth());
            rssWarmupPeak = std::max(rssWarmupPeak, residentBytes());
            if (elapsed() >= seconds / 4 && f.steps >= minWarmupSteps) {
                heapAfterWarmup = heapWarmupPeak;
                rssAfterWarmup = rssWarmupPeak;
            }
        } else {
            heapMax = std::max(heapMax, heap.growth());
            rssMax = std::max(rssMax, residentBytes());
        }
        if (reportEvery > 0 && elapsed() >= nextReport) {
            const double heapNow = static_cast<double>(heap.growth()) / 1e6;
            std::printf("soak: %.0f s, %llu steps, bodies created %llu, joint breaks %llu, snapshots %llu, max speed %.2f m/s, "
                        "max spin %.1f rad/s; heap %.2f MB (after the warm-up %.2f MB), RSS %.1f MB (after the warm-up %.1f MB)\n",
                        elapsed(), static_cast<unsigned long long>(f.steps), static_cast<unsigned long long>(f.created),
                        static_cast<unsigned long long>(f.breaks), static_cast<unsigned long long>(f.snapshots),
                        static_cast<double>(f.maxSpeed), static_cast<double>(f.maxSpin), heapNow,
                        static_cast<double>(heapAfterWarmup) / 1e6, static_cast<double>(residentBytes()) / 1e6,
                        static_cast<double>(rssAfterWarmup) / 1e6);
            std::fflush(stdout);
            nextReport += reportEvery;
        }
    }
    const Figures& f = churn.figures();
    std::printf("soak: %.1f s, %llu steps (%.2f ms each), bodies created %llu, destroyed %llu, joint breaks %llu, mends %llu, "
                "stack woken %llu times (asleep at the end of %llu steps), ropes %llu, cloths %llu, snapshots %llu; "
                "max speed %.2f m/s, max spin %.1f rad/s, max kinetic energy %.1f J; heap after warm-up %.2f MB, "
                "max later %.2f MB (%+.3f MB); RSS after warm-up %.1f MB, max later %.1f MB (%+.2f MB) (after the warm-up: its peak)\n",
                elapsed(), static_cast<unsigned long long>(f.steps), 1e3 * elapsed() / static_cast<double>(f.steps),
                static_cast<unsigned long long>(f.created), static_cast<unsigned long long>(f.destroyed),
                static_cast<unsigned long long>(f.breaks), static_cast<unsigned long long>(f.mends),
                static_cast<unsigned long long>(f.wakes), static_cast<unsigned long long>(f.sleepingSeen),
                static_cast<unsigned long long>(f.ropes), static_cast<unsigned long long>(f.cloths),
                static_cast<unsigned long long>(f.snapshots), static_cast<double>(f.maxSpeed), static_cast<double>(f.maxSpin),
                f.maxKinetic, static_cast<double>(heapAfterWarmup) / 1e6, static_cast<double>(heapMax) / 1e6,
                static_cast<double>(heapMax - heapAfterWarmup) / 1e6, static_cast<double>(rssAfterWarmup) / 1e6,
                static_cast<double>(rssMax) / 1e6, static_cast<double>(rssMax - rssAfterWarmup) / 1e6);

    // The churn did churn.
    EXPECT_GT(f.breaks, 0u);
    EXPECT_GT(f.mends, 0u);
    EXPECT_GT(f.sleepingSeen, 0u);
    EXPECT_GT(f.snapshots, 0u);
    EXPECT_EQ(f.created - f.destroyed, kMaxSpawned);
    // Energy bounded (the bounds' reasons are at their definitions).
    EXPECT_LT(f.maxSpeed, kMaxSpeed);
    EXPECT_LT(f.maxSpin, kMaxSpin);
    // Memory flat: after the warm-up the live heap never grows by more than
    // 256 KB (buffers that grow by doubling when a rare peak of contacts or
    // particles is reached), and the resident size by more than 8 MB (the
    // allocator's own caching and fragmentation on top).
    EXPECT_LE(heapMax - heapAfterWarmup, 256 * 1024);
    if (!kAddressSanitizer) {
        EXPECT_LE(rssMax - rssAfterWarmup, 8L * 1024 * 1024);
    }
}
