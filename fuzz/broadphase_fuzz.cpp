// Fuzz target: the broad phase against brute force. The input is a program of
// proxy creates, moves, destroys, filter changes and pair updates (with and
// without a limit on new pairs); the target keeps the pair set S as the world
// does (broad_phase.hpp, "The pair contract") and checks after every update:
//   - the reported pairs are sorted, a < b, new (not in S), allowed and overlapping;
//   - after an update without a limit, S is exactly the brute-force set of
//     allowed pairs whose fat boxes overlap; with a limit, a subset of it;
//   - the trees' and records' own invariants (BroadPhase::validate).
#include <fuzzer/FuzzedDataProvider.h>

#include <cstdio>
#include <cstdlib>
#include <set>
#include <utility>
#include <vector>

#include "collision/broad_phase.hpp"

namespace {

using namespace fulcrum;

[[noreturn]] void fail(const char* what, ProxyId a, ProxyId b) {
    std::fprintf(stderr, "broad phase: %s (proxies %d, %d)\n", what, a, b);
    std::abort();
}

Real unit(FuzzedDataProvider& in) { return static_cast<Real>(in.ConsumeIntegral<std::uint16_t>()) / Real(65535); }

// Boxes in a 16 m cube, up to 3 m across, so that many of them overlap.
AABB randomBox(FuzzedDataProvider& in) {
    const Vec3 c{unit(in) * 16 - 8, unit(in) * 16 - 8, unit(in) * 16 - 8};
    const Vec3 h{unit(in) * Real(1.5), unit(in) * Real(1.5), unit(in) * Real(1.5)};
    return AABB::fromCenterHalf(c, h);
}

CollisionFilter randomFilter(FuzzedDataProvider& in) {
    CollisionFilter f;
    if (in.ConsumeBool()) {  // a few categories and groups, so the rules meet
        f.category = 1u << in.ConsumeIntegralInRange(0, 3);
        f.mask = in.ConsumeIntegralInRange<std::uint32_t>(0, 15);
        f.group = in.ConsumeIntegralInRange(-2, 2);
    }
    return f;
}

using PairSet = std::set<std::pair<ProxyId, ProxyId>>;

struct Model {
    BroadPhase& bp;
    std::vector<ProxyId> live;
    PairSet pairs;  // S

    bool allowed(ProxyId a, ProxyId b) const {
        const BodyType ta = bp.type(a), tb = bp.type(b);
        if (ta == BodyType::Static && tb == BodyType::Static) return false;
        if (bp.config().requireDynamic && ta != BodyType::Dynamic && tb != BodyType::Dynamic) return false;
        return shouldCollide(bp.filter(a), bp.filter(b));
    }
    bool overlapping(ProxyId a, ProxyId b) const { return overlaps(bp.fatAABB(a), bp.fatAABB(b)); }

    void dropPairsOf(ProxyId id) {
        for (auto it = pairs.begin(); it != pairs.end();) {
            it = (it->first == id || it->second == id) ? pairs.erase(it) : std::next(it);
        }
    }

    void update(std::uint32_t limit) {
        const auto partners = [this](ProxyId self, auto&& visit) {
            for (const auto& [a, b] : pairs) {
                if (a == self) visit(b);
                if (b == self) visit(a);
            }
        };
        const std::span<const ProxyPair> found = bp.updatePairs(AcceptAllPairs{}, partners, nullptr, limit);
        if (limit != kNoPairLimit && found.size() > limit) fail("more new pairs than the limit", -1, -1);
        for (std::size_t i = 0; i < found.size(); ++i) {
            const ProxyPair& p = found[i];
            if (!(p.a < p.b)) fail("pair not ordered a < b", p.a, p.b);
            if (i > 0 && !(std::pair(found[i - 1].a, found[i - 1].b) < std::pair(p.a, p.b))) fail("pairs not sorted or repeated", p.a, p.b);
            if (!bp.isProxy(p.a) || !bp.isProxy(p.b)) fail("pair of a destroyed proxy", p.a, p.b);
            if (p.userA != bp.userValue(p.a) || p.userB != bp.userValue(p.b)) fail("pair with wrong user values", p.a, p.b);
            if (!allowed(p.a, p.b)) fail("pair the types or filters forbid", p.a, p.b);
            if (!overlapping(p.a, p.b)) fail("pair whose fat boxes do not overlap", p.a, p.b);
            if (!pairs.insert({p.a, p.b}).second) fail("pair reported again while in S", p.a, p.b);
        }
        for (auto it = pairs.begin(); it != pairs.end();) {
            it = bp.testOverlap(it->first, it->second) ? std::next(it) : pairs.erase(it);
        }
        // Brute force over every live pair.
        for (std::size_t i = 0; i < live.size(); ++i) {
            for (std::size_t j = i + 1; j < live.size(); ++j) {
                const ProxyId a = std::min(live[i], live[j]), b = std::max(live[i], live[j]);
                const bool want = allowed(a, b) && overlapping(a, b);
                const bool have = pairs.count({a, b}) != 0;
                if (have && !want) fail("pair in S that is not allowed or not overlapping", a, b);
                if (want && !have && limit == kNoPairLimit) fail("overlapping allowed pair missing after an update", a, b);
            }
        }
        if (const std::string why = bp.validate(); !why.empty()) {
            std::fprintf(stderr, "broad phase invalid: %s\n", why.c_str());
            std::abort();
        }
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    FuzzedDataProvider in(data, size);
    BroadPhaseConfig config;
    config.requireDynamic = in.ConsumeBool();
    BroadPhase bp(config);
    Model model{bp, {}, {}};
    std::uint32_t nextUser = 0;
    // A limited update may leave pairs for later; a final update without a
    // limit must then complete S.
    for (int op = 0; op < 400 && in.remaining_bytes() > 0; ++op) {
        switch (in.ConsumeIntegralInRange(0, 9)) {
        case 0:
        case 1:
        case 2: {
            if (model.live.size() >= 128) break;
            const auto type = static_cast<BodyType>(in.ConsumeIntegralInRange(0, 2));
            const AABB box = randomBox(in);
            const CollisionFilter filter = randomFilter(in);
            model.live.push_back(bp.createProxy(box, type, filter, nextUser++));
            break;
        }
        case 3:
        case 4:
        case 5: {
            if (model.live.empty()) break;
            const ProxyId id = model.live[in.ConsumeIntegralInRange<std::size_t>(0, model.live.size() - 1)];
            const AABB box = randomBox(in);
            const Vec3 displacement{unit(in) * 2 - 1, unit(in) * 2 - 1, unit(in) * 2 - 1};
            bp.moveProxy(id, box, displacement);
            break;
        }
        case 6: {
            if (model.live.empty()) break;
            const std::size_t i = in.ConsumeIntegralInRange<std::size_t>(0, model.live.size() - 1);
            model.dropPairsOf(model.live[i]);
            bp.destroyProxy(model.live[i]);
            model.live.erase(model.live.begin() + static_cast<std::ptrdiff_t>(i));
            break;
        }
        case 7: {
            if (model.live.empty()) break;
            const ProxyId id = model.live[in.ConsumeIntegralInRange<std::size_t>(0, model.live.size() - 1)];
            model.dropPairsOf(id);
            bp.setFilter(id, randomFilter(in));
            break;
        }
        case 8:
            model.update(kNoPairLimit);
            break;
        default:
            model.update(in.ConsumeIntegralInRange<std::uint32_t>(0, 8));
            break;
        }
    }
    model.update(kNoPairLimit);
    return 0;
}
