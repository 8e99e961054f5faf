#pragma once
// Collision filtering: which pairs of proxies may become contacts.
//
// Two layers, both applied by BroadPhase::updatePairs before a pair is reported:
//  1. shouldCollide(filterA, filterB): the per-body CollisionFilter of
//     include/fulcrum/body.hpp. A shared non-zero group decides alone: positive
//     always collides, negative never does. Otherwise both directions of
//     category/mask must agree: (A.category & B.mask) != 0 and
//     (B.category & A.mask) != 0.
//  2. a caller-supplied pair predicate canPair(userA, userB) on the proxies'
//     user values, for rules the broad phase cannot see, such as "bodies
//     joined by a joint without collide_connected do not collide". It must be
//     symmetric in its arguments, deterministic, and free of side effects
//     (it may later run on several threads at once).
#include <concepts>
#include <cstdint>

#include "fulcrum/body.hpp"

namespace fulcrum {

constexpr bool shouldCollide(const CollisionFilter& a, const CollisionFilter& b) {
    if (a.group == b.group && a.group != 0) return a.group > 0;
    return (a.category & b.mask) != 0 && (b.category & a.mask) != 0;
}

template <typename P>
concept PairPredicate = requires(const P& p, std::uint32_t userA, std::uint32_t userB) {
    { p(userA, userB) } -> std::convertible_to<bool>;
};

// The predicate that accepts every pair the filters let through.
struct AcceptAllPairs {
    constexpr bool operator()(std::uint32_t, std::uint32_t) const { return true; }
};

}  // namespace fulcrum
