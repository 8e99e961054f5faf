#pragma once
// A recycled manifold moved with its bodies (ContactManager::collideContact's
// contact recycling, and the pieces recycled against a static mesh): each
// point's two anchors placed by the poses, its depth measured along the
// manifold's normal. With ten boxes at rest this is most of the narrow
// phase: every pair recycles, 8 point transforms a pair, each two cross
// products. Where SSE2 exists (the x86-64 baseline; Emscripten's SSE2 in
// WebAssembly) the float build runs each transform with the vector's x, y
// and z in three lanes: every lane does the scalar transformPoint's
// operations in its order (no FMA: -ffp-contract=off), and the depth's dot
// product adds x, y and z in the scalar order, so the results are the
// scalar path's bits (tests/contacts/recycled_points_test.cpp). The pair's
// poses that decide whether it recycles run their three rotations the same way.
#include "contacts/contact.hpp"
#include "fulcrum/math/transform.hpp"

namespace fulcrum::detail {

// The points of `m` placed by xA and xB (position midway, depth and
// depthAfter along m.normal, which must already be in world space);
// whether any point is within kTouchSlop.
bool refreshRecycledPoints(CachedManifold& m, const Transform& xA, const Transform& xB);

// The same with the normal first turned from A's frame (m.normal =
// rotate(xA.q, m.localNormal)).
bool refreshRecycledManifold(CachedManifold& m, const Transform& xA, const Transform& xB);

// A body's pose as its record holds it: the centre of mass, the orientation
// and the centre of mass in the shape's frame (BodyParams::localCom).
struct BodyFrame {
    const Vec3& com;
    const Quat& q;
    const Vec3& localCom;
};

// What collideContact reads first for every pair: both bodies' shape-frame
// transforms (BodyStore::originTransform: com - rotate(q, localCom)) and B's
// pose in A's frame (relative(a, b)); the rotations in the same lanes.
struct PairPoses {
    Transform a, b, relative;
};
PairPoses pairPoses(const BodyFrame& a, const BodyFrame& b);

// The scalar forms, the reference the lanes must match bit for bit.
bool refreshRecycledPointsScalar(CachedManifold& m, const Transform& xA, const Transform& xB);
bool refreshRecycledManifoldScalar(CachedManifold& m, const Transform& xA, const Transform& xB);
PairPoses pairPosesScalar(const BodyFrame& a, const BodyFrame& b);

}  // namespace fulcrum::detail
