// BroadPhase: the pair contract against brute force, filtering, type rules and
// determinism.
//
// What the randomized test proves, after every step of a run with thousands of
// proxies (static, kinematic, dynamic; small and large), random jitters,
// steady motion, teleports, sleeping proxies, static moves, creations,
// destructions and filter changes:
//   (1) the caller-side set S, maintained only through the documented contract
//       (add every pair updatePairs reports; drop pairs whose testOverlap is
//       false; drop a proxy's pairs when destroying or re-filtering it), equals
//       exactly the brute-force O(n^2) set of allowed pairs whose fat boxes
//       overlap;
//   (2) every reported pair is new (not already in S), has a < b, carries the
//       right user values, and the list is strictly sorted by (a, b);
//   (3) every allowed pair whose tight boxes overlap is in S;
//   (4) both trees and the proxy records pass validate().
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"

namespace fulcrum {
namespace {

using PairSet = std::set<std::pair<ProxyId, ProxyId>>;

// Stand-in for "bodies joined by a joint do not collide": symmetric and pure.
struct NoJointPairs {
    bool operator()(std::uint32_t userA, std::uint32_t userB) const { return (userA + userB) % 13 != 0; }
};

struct SimBody {
    ProxyId proxy = kNullProxy;
    BodyType type = BodyType::Dynamic;
    CollisionFilter filter;
    std::uint32_t user = 0;
    AABB tight;
    Vec3 velocity;
};

class Scenario {
public:
    Scenario(std::uint32_t seed, int staticCount, int kinematicCount, int dynamicCount, bool requireDynamic)
        : rng_(seed), bp_(makeConfig(requireDynamic)) {
        for (int i = 0; i < staticCount; ++i) create(BodyType::Static);
        for (int i = 0; i < kinematicCount; ++i) create(BodyType::Kinematic);
        for (int i = 0; i < dynamicCount; ++i) create(BodyType::Dynamic);
    }

    // One step of random changes, then the pair update. Returns the reported pairs.
    std::vector<ProxyPair> step() {
        // Destroy and create about 0.5% each.
        const std::size_t churn = bodies_.size() / 200 + 1;
        for (std::size_t k = 0; k < churn; ++k) destroy(static_cast<std::size_t>(index(static_cast<int>(bodies_.size()))));
        for (std::size_t k = 0; k < churn; ++k) create(static_cast<BodyType>(index(3)));
        for (SimBody& b : bodies_) {
            const Real r = uniform(0, 1);
            if (b.type == BodyType::Static) {
                if (r < Real(0.003)) move(b, randomPoint() - b.tight.center(), Vec3::zero());  // level editing
                continue;
            }
            if (r < Real(0.55)) {
                const Vec3 d{uniform(Real(-0.03), Real(0.03)), uniform(Real(-0.03), Real(0.03)), uniform(Real(-0.03), Real(0.03))};
                move(b, d, d);                                        // resting jitter
            } else if (r < Real(0.9)) {
                move(b, b.velocity, b.velocity);                      // steady motion
            } else if (r < Real(0.98)) {
                // asleep: not moved at all
            } else {
                move(b, randomPoint() - b.tight.center(), Vec3::zero());  // teleport
            }
        }
        // Re-filter about 0.3%: the caller drops the proxy's pairs first.
        for (SimBody& b : bodies_) {
            if (uniform(0, 1) < Real(0.003)) {
                dropPairsOf(b.proxy);
                b.filter = randomFilter();
                bp_.setFilter(b.proxy, b.filter);
            }
        }

        const std::span<const ProxyPair> reported = bp_.updatePairs(NoJointPairs{});
        std::vector<ProxyPair> out(reported.begin(), reported.end());
        for (std::size_t i = 0; i < out.size(); ++i) {
            const ProxyPair& p = out[i];
            EXPECT_LT(p.a, p.b);
            if (i > 0) {
                EXPECT_TRUE(out[i - 1].a < p.a || (out[i - 1].a == p.a && out[i - 1].b < p.b)) << "not strictly sorted";
            }
            EXPECT_EQ(p.userA, bp_.userValue(p.a));
            EXPECT_EQ(p.userB, bp_.userValue(p.b));
            EXPECT_TRUE(pairs_.insert({p.a, p.b}).second) << "pair (" << p.a << ", " << p.b << ") reported twice";
        }
        for (auto it = pairs_.begin(); it != pairs_.end();) {
            it = bp_.testOverlap(it->first, it->second) ? std::next(it) : pairs_.erase(it);
        }
        return out;
    }

    // Checks (1), (3) and (4) of the file comment.
    void checkAgainstBruteForce() const {
        ASSERT_EQ(bp_.validate(), "");
        std::vector<const SimBody*> byProxy;
        for (const SimBody& b : bodies_) byProxy.push_back(&b);
        std::sort(byProxy.begin(), byProxy.end(), [](const SimBody* l, const SimBody* r) { return l->proxy < r->proxy; });
        std::vector<AABB> fat;
        for (const SimBody* b : byProxy) {
            fat.push_back(bp_.fatAABB(b->proxy));
            ASSERT_TRUE(fat.back().contains(b->tight));
        }
        PairSet expected;
        std::size_t tightPairs = 0;
        for (std::size_t i = 0; i < byProxy.size(); ++i) {
            const SimBody& a = *byProxy[i];
            for (std::size_t j = i + 1; j < byProxy.size(); ++j) {
                if (!overlaps(fat[i], fat[j])) continue;  // a fat box contains its tight box
                const SimBody& b = *byProxy[j];
                if (!allowed(a, b)) continue;
                expected.insert({a.proxy, b.proxy});
                if (overlaps(a.tight, b.tight)) {
                    ++tightPairs;
                    ASSERT_TRUE(pairs_.count({a.proxy, b.proxy})) << "tight overlap missing: " << a.proxy << ", " << b.proxy;
                }
            }
        }
        ASSERT_EQ(pairs_.size(), expected.size());
        ASSERT_TRUE(pairs_ == expected);
        tightPairsSeen_ += tightPairs;
    }

    std::size_t pairCount() const { return pairs_.size(); }
    std::size_t tightPairsSeen() const { return tightPairsSeen_; }

private:
    static BroadPhaseConfig makeConfig(bool requireDynamic) {
        BroadPhaseConfig c;
        c.requireDynamic = requireDynamic;
        return c;
    }
    bool allowed(const SimBody& a, const SimBody& b) const {
        if (a.type == BodyType::Static && b.type == BodyType::Static) return false;
        if (bp_.config().requireDynamic && a.type != BodyType::Dynamic && b.type != BodyType::Dynamic) return false;
        return shouldCollide(a.filter, b.filter) && NoJointPairs{}(a.user, b.user);
    }
    Real uniform(Real lo, Real hi) { return std::uniform_real_distribution<Real>(lo, hi)(rng_); }
    int index(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }
    Vec3 randomPoint() { return {uniform(-kHalfWorld, kHalfWorld), uniform(-kHalfWorld, kHalfWorld), uniform(-kHalfWorld, kHalfWorld)}; }
    CollisionFilter randomFilter() {
        CollisionFilter f;
        f.category = 1u << index(3);
        const std::uint32_t masks[] = {0xFFFFFFFFu, 0xFFFFFFFFu, ~2u, 1u | 4u};
        f.mask = masks[index(4)];
        const std::int32_t groups[] = {0, 0, 0, 0, 1, -1, 2};
        f.group = groups[index(7)];
        return f;
    }
    void create(BodyType type) {
        SimBody b;
        b.type = type;
        const bool large = index(20) == 0;
        const Real lo = large ? Real(2) : Real(0.2), hi = large ? Real(5) : Real(1.2);
        b.tight = AABB::fromCenterHalf(randomPoint(), {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)});
        b.velocity = {uniform(Real(-0.4), Real(0.4)), uniform(Real(-0.4), Real(0.4)), uniform(Real(-0.4), Real(0.4))};
        b.filter = randomFilter();
        b.user = nextUser_++;
        b.proxy = bp_.createProxy(b.tight, b.type, b.filter, b.user);
        bodies_.push_back(b);
    }
    void destroy(std::size_t k) {
        dropPairsOf(bodies_[k].proxy);
        bp_.destroyProxy(bodies_[k].proxy);
        bodies_[k] = bodies_.back();
        bodies_.pop_back();
    }
    void move(SimBody& b, const Vec3& delta, const Vec3& displacement) {
        b.tight = {b.tight.min + delta, b.tight.max + delta};
        // Bounce off the walls of the world so the density stays constant.
        for (std::size_t i = 0; i < 3; ++i) {
            if (b.tight.center()[i] > kHalfWorld && b.velocity[i] > 0) b.velocity[i] = -b.velocity[i];
            if (b.tight.center()[i] < -kHalfWorld && b.velocity[i] < 0) b.velocity[i] = -b.velocity[i];
        }
        bp_.moveProxy(b.proxy, b.tight, displacement);
    }
    void dropPairsOf(ProxyId id) {
        for (auto it = pairs_.begin(); it != pairs_.end();) {
            it = (it->first == id || it->second == id) ? pairs_.erase(it) : std::next(it);
        }
    }

    static constexpr Real kHalfWorld = 14;
    std::mt19937 rng_;
    BroadPhase bp_;
    std::vector<SimBody> bodies_;
    PairSet pairs_;
    std::uint32_t nextUser_ = 0;
    mutable std::size_t tightPairsSeen_ = 0;
};

TEST(BroadPhase, TrackedPairsEqualBruteForceOverRandomSteps) {
    Scenario s(11, 300, 200, 1500, true);
    s.step();
    s.checkAgainstBruteForce();
    std::size_t reported = 0;
    for (int step = 0; step < 60 && !::testing::Test::HasFatalFailure(); ++step) {
        reported += s.step().size();
        s.checkAgainstBruteForce();
    }
    // Make sure the scene is dense enough to mean something.
    EXPECT_GT(s.pairCount(), 1000u);
    EXPECT_GT(reported, 1000u);
    EXPECT_GT(s.tightPairsSeen(), 10000u);
}

TEST(BroadPhase, TrackedPairsEqualBruteForceWithKinematicPairs) {
    Scenario s(12, 200, 400, 600, false);
    for (int step = 0; step < 40 && !::testing::Test::HasFatalFailure(); ++step) {
        s.step();
        s.checkAgainstBruteForce();
    }
    EXPECT_GT(s.pairCount(), 200u);
}

TEST(BroadPhase, SameOperationsGiveIdenticalPairLists) {
    Scenario first(21, 100, 100, 800, true), second(21, 100, 100, 800, true);
    for (int step = 0; step < 30; ++step) {
        const std::vector<ProxyPair> a = first.step();
        const std::vector<ProxyPair> b = second.step();
        ASSERT_EQ(a, b) << "step " << step;
    }
}

AABB unitBoxAt(Real x) { return AABB::fromCenterHalf({x, 0, 0}, Vec3::splat(Real(0.5))); }

TEST(BroadPhase, NeverReportsStaticStaticOrSelfPairs) {
    BroadPhase bp;
    const ProxyId s1 = bp.createProxy(unitBoxAt(0), BodyType::Static, {}, 10);
    const ProxyId s2 = bp.createProxy(unitBoxAt(Real(0.5)), BodyType::Static, {}, 11);
    const ProxyId d = bp.createProxy(unitBoxAt(Real(0.3)), BodyType::Dynamic, {}, 12);
    const std::span<const ProxyPair> pairs = bp.updatePairs();
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0], (ProxyPair{s1, d, 10, 12}));
    EXPECT_EQ(pairs[1], (ProxyPair{s2, d, 11, 12}));
    EXPECT_TRUE(bp.updatePairs().empty()) << "nothing moved: nothing new";
}

TEST(BroadPhase, KinematicPairsOnlyWithADynamicUnlessAskedFor) {
    for (const bool requireDynamic : {true, false}) {
        BroadPhaseConfig config;
        config.requireDynamic = requireDynamic;
        BroadPhase bp(config);
        bp.createProxy(unitBoxAt(0), BodyType::Static, {}, 0);
        bp.createProxy(unitBoxAt(Real(0.2)), BodyType::Kinematic, {}, 1);
        bp.createProxy(unitBoxAt(Real(0.4)), BodyType::Kinematic, {}, 2);
        bp.createProxy(unitBoxAt(Real(0.6)), BodyType::Dynamic, {}, 3);
        // Dynamic pairs with all three; kinematic-static (2) and
        // kinematic-kinematic (1) only when asked for.
        EXPECT_EQ(bp.updatePairs().size(), requireDynamic ? 3u : 6u);
    }
}

TEST(BroadPhase, PairsAppearOnceAndEndWhenFatBoxesSeparate) {
    BroadPhase bp;
    const ProxyId a = bp.createProxy(unitBoxAt(0), BodyType::Dynamic, {}, 0);
    const ProxyId b = bp.createProxy(unitBoxAt(5), BodyType::Dynamic, {}, 1);
    EXPECT_TRUE(bp.updatePairs().empty());
    // Both move towards each other in the same step: one report, not two.
    bp.moveProxy(a, unitBoxAt(2), {2, 0, 0});
    bp.moveProxy(b, unitBoxAt(Real(2.5)), {Real(-2.5), 0, 0});
    const std::span<const ProxyPair> met = bp.updatePairs();
    ASSERT_EQ(met.size(), 1u);
    EXPECT_EQ(met[0].a, a);
    EXPECT_EQ(met[0].b, b);
    EXPECT_TRUE(bp.testOverlap(a, b));
    // Still overlapping after a further move: not new.
    bp.moveProxy(a, unitBoxAt(Real(2.2)), {Real(0.2), 0, 0});
    EXPECT_TRUE(bp.updatePairs().empty());
    // Apart: the caller sees testOverlap turn false.
    bp.moveProxy(a, unitBoxAt(-10), Vec3::zero());
    EXPECT_TRUE(bp.updatePairs().empty());
    EXPECT_FALSE(bp.testOverlap(a, b));
}

TEST(BroadPhase, FiltersAndPredicateExcludePairsUntilRefreshed) {
    BroadPhase bp;
    CollisionFilter ragdoll;
    ragdoll.group = -1;
    const ProxyId a = bp.createProxy(unitBoxAt(0), BodyType::Dynamic, ragdoll, 100);
    const ProxyId b = bp.createProxy(unitBoxAt(Real(0.5)), BodyType::Dynamic, ragdoll, 200);
    const ProxyId c = bp.createProxy(unitBoxAt(Real(0.9)), BodyType::Dynamic, {}, 300);
    // a-b share a negative group; b-c are "jointed" per the predicate.
    bool jointBC = true;
    const auto noJoint = [&](std::uint32_t u, std::uint32_t v) {
        return !(jointBC && ((u == 200 && v == 300) || (u == 300 && v == 200)));
    };
    std::span<const ProxyPair> pairs = bp.updatePairs(noJoint);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0], (ProxyPair{a, c, 100, 300}));
    // The joint goes away: the world refreshes one body, the pair appears.
    jointBC = false;
    bp.refreshProxy(b);
    pairs = bp.updatePairs(noJoint);
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0], (ProxyPair{b, c, 200, 300}));
    // a leaves the ragdoll group: after the caller drops a's pairs, setFilter
    // reports all of a's current pairs, including the one with b.
    bp.setFilter(a, CollisionFilter{});
    pairs = bp.updatePairs(noJoint);
    ASSERT_EQ(pairs.size(), 2u);
    EXPECT_EQ(pairs[0], (ProxyPair{a, b, 100, 200}));
    EXPECT_EQ(pairs[1], (ProxyPair{a, c, 100, 300}));
}

TEST(BroadPhase, DestroyedProxiesLeaveNoTrace) {
    BroadPhase bp;
    const ProxyId a = bp.createProxy(unitBoxAt(0), BodyType::Dynamic, {}, 0);
    const ProxyId b = bp.createProxy(unitBoxAt(Real(0.5)), BodyType::Dynamic, {}, 1);
    bp.destroyProxy(b);  // destroyed while in the move buffer
    EXPECT_EQ(bp.validate(), "");
    EXPECT_TRUE(bp.updatePairs().empty());
    const ProxyId c = bp.createProxy(unitBoxAt(Real(0.5)), BodyType::Static, {}, 2);
    EXPECT_EQ(c, b) << "ids are reused";
    const std::span<const ProxyPair> pairs = bp.updatePairs();
    ASSERT_EQ(pairs.size(), 1u);
    EXPECT_EQ(pairs[0], (ProxyPair{a, c, 0, 2}));
    EXPECT_EQ(bp.validate(), "");
}

TEST(BroadPhase, QueriesAndRayCastsCoverBothTrees) {
    BroadPhase bp;
    const ProxyId ground = bp.createProxy(AABB{{-10, -1, -10}, {10, 0, 10}}, BodyType::Static, {}, 1);
    const ProxyId box = bp.createProxy(AABB{{-1, 1, -1}, {1, 3, 1}}, BodyType::Dynamic, {}, 2);
    std::vector<ProxyId> found;
    bp.query(AABB{{-2, -Real(0.5), -2}, {2, 2, 2}}, [&](ProxyId id, std::uint32_t) { return found.push_back(id), true; });
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, (std::vector<ProxyId>{ground, box}));
    // Closest hit straight down from y = 10: the dynamic box's fat top at
    // y = 3.1 (10 cm margin) comes before the ground's top at y = 0.
    const RayCastInput down{{0, 10, 0}, {0, -20, 0}, 1};
    ProxyId hit = kNullProxy;
    Real hitFraction = 1;
    bp.rayCast(down, [&](const RayCastInput& in, ProxyId id, std::uint32_t) {
        const Real t = RaySlab(in).entry(bp.fatAABB(id), in.maxFraction);
        if (t < 0) return Real(-1);
        hit = id;
        hitFraction = t;
        return t;
    });
    EXPECT_EQ(hit, box);
    EXPECT_NEAR(hitFraction, (10 - Real(3.1)) / 20, 1e-6);
    // Static rebuild keeps everything valid and findable.
    bp.rebuildStaticTree();
    EXPECT_EQ(bp.validate(), "");
}

}  // namespace
}  // namespace fulcrum
