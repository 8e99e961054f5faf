// BroadPhase::updatePairs with a limit on the new pairs (broad_phase.hpp, "A
// limit on new pairs"), against brute force: a crowd of proxies, most of them
// overlapping each other, moved at random, the caller's set S kept through
// the contract with a limit on its size. After every update:
//   (1) no reported pair is in S already (the entries that waited report
//       again only the pairs S lacks), and S never exceeds the limit;
//   (2) S holds allowed overlapping pairs only;
//   (3) the reports are the same on one thread and on a pool of three;
// and once the limit is lifted, one update brings S to exactly the allowed
// overlapping pairs (nothing was lost while it waited).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "collision/broad_phase.hpp"
#include "fulcrum/task_system.hpp"

namespace fulcrum {
namespace {

struct OddPairsOnly {  // a caller rule, as the joint rule: symmetric and pure
    bool operator()(std::uint32_t a, std::uint32_t b) const { return (a * 7 + b * 7) % 5 != 0; }
};

class Crowd {
public:
    Crowd(std::uint32_t seed, TaskSystem* tasks) : rng_(seed), tasks_(tasks) {
        // A static floor under 400 moving boxes packed into a 6 m cube.
        floor_ = bp_.createProxy(AABB{{-10, -2, -10}, {10, -1, 10}}, BodyType::Static, {}, 0);
        grow(floor_);
        for (std::uint32_t i = 1; i <= 400; ++i) {
            const Vec3 c{uniform(-3, 3), uniform(-1, 5), uniform(-3, 3)};
            const AABB box = AABB::fromCenterHalf(c, Vec3::splat(Real(0.6)));
            const ProxyId id = bp_.createProxy(box, BodyType::Dynamic, {}, i);
            grow(id);
            tight_[static_cast<std::size_t>(id)] = box;
        }
        tight_[static_cast<std::size_t>(floor_)] = AABB{{-10, -2, -10}, {10, -1, 10}};
    }

    std::vector<ProxyPair> step(std::uint32_t limit) {
        for (ProxyId id = 0; id < static_cast<ProxyId>(tight_.size()); ++id) {
            if (id == floor_ || uniform(0, 1) < Real(0.3)) continue;  // some rest
            const Vec3 d{uniform(-0.3f, 0.3f), uniform(-0.3f, 0.3f), uniform(-0.3f, 0.3f)};
            AABB& t = tight_[static_cast<std::size_t>(id)];
            t = {t.min + d, t.max + d};
            bp_.moveProxy(id, t, d);
        }
        const std::uint32_t room =
            limit == kNoPairLimit ? kNoPairLimit : (pairs_.size() < limit ? limit - static_cast<std::uint32_t>(pairs_.size()) : 0);
        const auto partners = [this](ProxyId id, auto&& visit) {
            for (const ProxyId other : adjacent_[static_cast<std::size_t>(id)]) visit(other);
        };
        const std::span<const ProxyPair> reported = bp_.updatePairs(OddPairsOnly{}, partners, tasks_, room);
        std::vector<ProxyPair> out(reported.begin(), reported.end());
        EXPECT_LE(out.size(), room);
        for (const ProxyPair& p : out) {
            EXPECT_TRUE(pairs_.insert({p.a, p.b}).second) << "pair (" << p.a << ", " << p.b << ") reported twice";
            adjacent_[static_cast<std::size_t>(p.a)].insert(p.b);
            adjacent_[static_cast<std::size_t>(p.b)].insert(p.a);
        }
        for (auto it = pairs_.begin(); it != pairs_.end();) {
            if (bp_.testOverlap(it->first, it->second)) {
                ++it;
                continue;
            }
            adjacent_[static_cast<std::size_t>(it->first)].erase(it->second);
            adjacent_[static_cast<std::size_t>(it->second)].erase(it->first);
            it = pairs_.erase(it);
        }
        if (limit != kNoPairLimit) {
            EXPECT_LE(pairs_.size(), limit);
        }
        return out;
    }

    // The allowed pairs whose fat boxes overlap now.
    std::set<std::pair<ProxyId, ProxyId>> bruteForce() const {
        std::set<std::pair<ProxyId, ProxyId>> all;
        const auto n = static_cast<ProxyId>(tight_.size());
        for (ProxyId a = 0; a < n; ++a) {
            for (ProxyId b = a + 1; b < n; ++b) {
                if (!overlaps(bp_.fatAABB(a), bp_.fatAABB(b))) continue;
                if (!OddPairsOnly{}(bp_.userValue(a), bp_.userValue(b))) continue;
                all.insert({a, b});
            }
        }
        return all;
    }
    const std::set<std::pair<ProxyId, ProxyId>>& pairs() const { return pairs_; }
    const BroadPhase& broadPhase() const { return bp_; }

private:
    Real uniform(Real lo, Real hi) { return std::uniform_real_distribution<Real>(lo, hi)(rng_); }
    void grow(ProxyId id) {
        if (tight_.size() <= static_cast<std::size_t>(id)) tight_.resize(static_cast<std::size_t>(id) + 1);
        if (adjacent_.size() <= static_cast<std::size_t>(id)) adjacent_.resize(static_cast<std::size_t>(id) + 1);
    }

    std::mt19937 rng_;
    TaskSystem* tasks_;
    BroadPhase bp_;
    ProxyId floor_ = kNullProxy;
    std::vector<AABB> tight_;
    std::vector<std::set<ProxyId>> adjacent_;
    std::set<std::pair<ProxyId, ProxyId>> pairs_;
};

TEST(BroadPhasePairLimit, CrowdKeepsUnderTheLimitAndLosesNothing) {
    std::unique_ptr<TaskSystem> pool = makeThreadPool(ThreadPoolDef{3});
    Crowd serial(5, nullptr), parallel(5, pool.get());
    // The crowd has thousands of overlapping pairs; the limit lets 1,500 live.
    constexpr std::uint32_t kLimit = 1500;
    std::uint32_t mostWaiting = 0;
    for (int step = 0; step < 40 && !::testing::Test::HasFailure(); ++step) {
        const std::vector<ProxyPair> a = serial.step(kLimit);
        const std::vector<ProxyPair> b = parallel.step(kLimit);
        ASSERT_EQ(a, b) << "step " << step << ": the thread count changed the pairs kept";
        ASSERT_EQ(serial.broadPhase().lastUpdate().deferred, parallel.broadPhase().lastUpdate().deferred);
        mostWaiting = std::max(mostWaiting, serial.broadPhase().lastUpdate().deferred);
        const auto all = serial.bruteForce();
        ASSERT_GT(all.size(), 2 * kLimit) << "the crowd must be over the limit";
        ASSERT_TRUE(std::includes(all.begin(), all.end(), serial.pairs().begin(), serial.pairs().end()))
            << "a pair that does not overlap is held";
        ASSERT_EQ(serial.broadPhase().validate(), "");
    }
    EXPECT_GT(mostWaiting, 100u);
    // Lifted: the entries that waited report everything S lacks, once.
    serial.step(kNoPairLimit);
    EXPECT_EQ(serial.pairs(), serial.bruteForce());
    EXPECT_EQ(serial.broadPhase().lastUpdate().deferred, 0u);
}

TEST(BroadPhasePairLimit, NoRoomReportsNothingAndEveryMoverWaits) {
    Crowd crowd(9, nullptr);
    EXPECT_TRUE(crowd.step(0).empty());
    EXPECT_GT(crowd.broadPhase().lastUpdate().deferred, 300u);  // every proxy was fresh
    EXPECT_TRUE(crowd.pairs().empty());
    crowd.step(kNoPairLimit);
    EXPECT_EQ(crowd.pairs(), crowd.bruteForce());
}

}  // namespace
}  // namespace fulcrum
