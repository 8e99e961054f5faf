#pragma once
// sameMotion: body a of one world and body b of another are in the same
// state bit for bit (position, orientation, linear and angular velocity),
// the check of every "this fast path moves exactly as that one" test. On a
// difference the message gives both positions; the caller adds which run,
// body and step.
#include <gtest/gtest.h>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum::test {

inline ::testing::AssertionResult sameMotion(const World& world, BodyId a, const World& reference, BodyId b) {
    const Vec3 pa = world.position(a), pb = reference.position(b);
    const Quat qa = world.orientation(a), qb = reference.orientation(b);
    const bool same = pa == pb && qa.w == qb.w && qa.x == qb.x && qa.y == qb.y && qa.z == qb.z &&
                      world.linearVelocity(a) == reference.linearVelocity(b) &&
                      world.angularVelocity(a) == reference.angularVelocity(b);
    if (same) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "position (" << pa.x << ", " << pa.y << ", " << pa.z << ") vs (" << pb.x << ", "
                                         << pb.y << ", " << pb.z << ")";
}

}  // namespace fulcrum::test
