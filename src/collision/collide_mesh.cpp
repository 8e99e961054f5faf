// Convex shapes against triangle meshes.
//
// Each candidate triangle is collided as a one-sided convex shape (triangles
// facing away from the shape's centre are skipped): boxes and hulls by the
// separating-axis test of collide_triangle.cpp, spheres by their closest
// point (collideTriangleSphere), capsules by their core segment's closest
// points and the general path's clipping (collideTriangleCapsule), the other
// shapes by the general convex path (GJK, EPA, face clipping). Then the internal-edge
// fix: a contact whose normal is not the triangle's face normal is only
// allowed when it touches the triangle at a *convex* edge (or at a vertex with
// a convex edge); at a flat or concave edge the normal is replaced by the face
// normal and the contact is rebuilt along it. This removes the "ghost bumps"
// of a box sliding over the seams of a flat mesh, where the neighbouring
// triangle's edge would otherwise push sideways (the same idea as Bullet's
// btAdjustInternalEdgeContacts and Jolt's active-edge flags, using
// TriangleMesh::convexEdgeMask computed by the mesh builder).
//
// A contact along the triangle's face normal is kept only where it lies over
// the triangle: a point beyond its edges was measured against the extended
// plane, not the surface under it (the neighbouring triangle measures it).
//
// The contacts of all triangles are then grouped by normal (cosine > 0.999)
// and each group is reduced to one manifold of at most four points, so a box
// lying across many triangles gets one manifold, not one per triangle. Only
// the points within kReductionBand of the group's deepest (or, a centimetre
// deep, at least half as deep) take part; a box's or hull's group then gives
// two of its places to speculative points where they widen it much more
// (kTouchingPreference), as a box ground's clipped face would hold them.
// Heightfields (collide_heightfield.cpp) run the same two halves on the
// triangles of their cells.
#include "collision/collide_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <new>
#include <type_traits>

#include "collision/collide_pairs.hpp"
#include "collision/collide_triangle.hpp"

namespace fulcrum::detail {

namespace {

constexpr Real kFaceNormalCos = Real(1) - Real(1e-4);
constexpr Real kGroupCos = Real(0.999);
constexpr Real kBaryTol = Real(1e-3);
// The reduction keeps the group's deepest point and then the widest spread;
// with every speculative point of the group (up to the margin, centimetres
// away) in the choice, far speculative points displaced the touching ones, and
// which touching point survived flipped with sub-millimetre depth changes: a
// cylinder's cap or a hull across a curved field's seams then rocked between
// supports and never came to rest (tests/contacts/heightfield_test.cpp,
// EveryConvexShapeRestsOnBumpyField). Points further than this behind the
// deepest one are left out; a falling body's group is led by its nearest point,
// so its speculative contact stays.
constexpr Real kReductionBand = Real(1e-3);
// A group led by a point this deep is a body sunk into the surface, not one
// resting on it (groupTriangleContacts).
constexpr Real kDeepSeed = Real(0.01);
// A box's or hull's group also keeps its speculative points (those behind the
// band, up to the margin) where they widen the manifold: the touching pair
// stays, and the other two places go to the widest of the touching points
// and the speculative ones. On a box ground the clipped face manifold holds
// the corners of a face swinging down; on a mesh, without them, a log
// pivoting on one edge (the trees' trunks) had no point under the face coming
// down, landed a step late, sunk, and was pushed out: a bounce that kept it
// rocking about twice as long (tests/contacts/mesh_settle_test.cpp). A
// touching point counts this many times its width, so it keeps its place
// unless a speculative point is clearly wider: on a fine mesh the points a
// millimetre from the pivot edge, centimetres off it, otherwise took those
// places; with a preference of 1 a hull on the bumpy field kept rocking
// between them, with 2 another did in the double-precision build. (Taking as
// speculative only points 5 mm or more from touching was tried as well: the
// log then rocked longer.) Round shapes (cylinders, capsules) keep only their touching points:
// a cylinder's cap across a curved field's seams rocked with its rim's
// speculative points in (tests/contacts/heightfield_test.cpp).
constexpr Real kTouchingPreference = Real(3);

// How far beyond the margin the face plane must put the shape before the
// triangle is skipped without GJK: GJK's distance is exact to far less than
// this, so a triangle skipped here is one GJK would have found apart as well
// (the results keep their bits).
constexpr Real kSeparationSlack = Real(1e-3);

// How far a contact's candidate list (MeshCandidateCache) reaches beyond the
// body's query box when it is made, as a fraction of the box's largest half
// extent: a larger box is made again less often and filters more triangles.
constexpr Real kCandidateGrowth = Real(0.5);

// Room for N objects of T, left unset: every field read is written first.
// (Arrays of ContactCandidate zeroed their 1.4 kB at every group: 3 % of
// convex_vs_mesh(7x7)'s mesh narrow phase; a Manifold zeroes its four points,
// 32 instructions, at every triangle test.) T is an aggregate, so the bytes'
// storage creates its objects implicitly.
template <class T, std::size_t N>
struct Unset {
    static_assert(std::is_aggregate_v<T> && std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
    alignas(T) std::byte bytes[N * sizeof(T)];
    T* data() { return std::launder(reinterpret_cast<T*>(bytes)); }
};

// True when the triangle's plane separates b from it by more than the margin
// (b wholly above it, or wholly behind it): one extent, a pass over a hull's
// vertices, where GJK takes several supports and simplex steps. On a hilly
// mesh many triangles under a body's bounding box lie below it like this.
// Tried and measured (callgrind, docs/benchmarks.md "Mesh scenes"): the three
// in-plane edge normals as further axes, and b's bounding box instead of b
// (alone, or before b's extent for all but hulls). On convex_vs_mesh(7x7)
// this one saves most (7.5 %); on trees100(10), whose hulls lie near most
// triangles under them, every variant costs more than it saves, this one
// 2.5 % more than the grouping alone, the box 0.5 %.
bool separatedByTrianglePlane(const Vec3 w[3], const Vec3& faceN, const ConvexShape& b, Real margin) {
    const Real reach = margin + kSeparationSlack;
    Real lo, hi;
    if (b.kind == ConvexKind::Point || b.kind == ConvexKind::Segment) {
        // A sphere or capsule: its centre's height over the plane, give or
        // take the radius and the segment's half span along the (unit)
        // normal. ConvexShape::extent goes through two rounded supports,
        // each normalising the direction: some 280 instructions a triangle
        // (1.7 % of convex_vs_mesh(7x7)'s step). The rounding differs from
        // theirs only far below kSeparationSlack.
        const Real centre = dot(faceN, b.xf.p);
        Real reachOfB = b.radius;
        if (b.kind == ConvexKind::Segment) reachOfB += std::fabs(dot(faceN, rotate(b.xf.q, Vec3{0, b.halfHeight, 0})));
        lo = centre - reachOfB;
        hi = centre + reachOfB;
    } else {
        b.extent(faceN, lo, hi);
    }
    const Real plane = dot(faceN, w[0]);
    return lo - plane > reach || plane - hi > reach;
}

std::uint32_t meshFeature(std::uint32_t triangle, std::uint32_t local) {
    return (triangle * 0x9E3779B1u) ^ (local * 0x85EBCA77u);
}

// True when the contact at triangle point p (normal n from the triangle) is
// allowed to keep a normal other than the face normal.
bool edgeNormalAllowed(const Vec3 w[3], std::uint8_t convexMask, const Vec3& p, const Vec3& n, const Vec3& faceN) {
    // In the triangle's plane is still on its front side: a shape beside a
    // convex edge, level with the surface, is pushed away along the plane.
    // (GJK's normal there used to carry a few 1e-6 of rounding upwards; exact,
    // it was refused and rebuilt along the face normal.)
    if (dot(n, faceN) < 0) return false;
    // Barycentric coordinates of p projected on the triangle.
    const Vec3 e0 = w[1] - w[0], e1 = w[2] - w[0], ep = p - w[0];
    const Real d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(ep, e0), d21 = dot(ep, e1);
    const Real den = d00 * d11 - d01 * d01;
    if (!(den > 0)) return false;
    const Real bv = (d11 * d20 - d01 * d21) / den, bw = (d00 * d21 - d01 * d20) / den;
    const Real bu = 1 - bv - bw;
    const bool onEdge[3] = {bw <= kBaryTol, bu <= kBaryTol, bv <= kBaryTol};  // edges v0v1, v1v2, v2v0
    const int count = int(onEdge[0]) + int(onEdge[1]) + int(onEdge[2]);
    if (count == 0) return false;  // interior: only the face normal makes sense for a one-sided surface
    bool convex = false;
    for (std::uint32_t k = 0; k < 3; ++k) {
        if (onEdge[k] && (convexMask & (1u << k))) convex = true;
    }
    return convex;
}

}  // namespace

// True when p, projected along the triangle's normal, falls on the triangle
// (within kBaryTol of its edges).
bool overTriangle(const Vec3 w[3], const Vec3& p) {
    const Vec3 e0 = w[1] - w[0], e1 = w[2] - w[0], ep = p - w[0];
    const Real d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(ep, e0), d21 = dot(ep, e1);
    const Real den = d00 * d11 - d01 * d01;
    if (!(den > 0)) return false;
    const Real bv = (d11 * d20 - d01 * d21) / den, bw = (d00 * d21 - d01 * d20) / den;
    return bv >= -kBaryTol && bw >= -kBaryTol && bv + bw <= 1 + kBaryTol;
}

bool collideTriangleWithConvex(const Vec3 w[3], std::uint8_t convexMask, std::uint32_t t, const ConvexShape& b, Real margin,
                               std::vector<MeshContactCandidate>& scratch, const TrianglePolytope* polytope,
                               std::uint32_t* axisHint, const Vec3* bCentre, TriangleAxisEntry* cachedAxis) {
    const Vec3 faceN = normalize(cross(w[1] - w[0], w[2] - w[0]));
    if (dot(faceN, (bCentre != nullptr ? *bCentre : b.center()) - w[0]) < 0) return false;  // one-sided: behind the triangle
    // Unset: the separating-axis test writes the normal, the count and each
    // point's position, depth and id before it gives a contact (and nothing
    // below reads more); the general path's pair functions get a fresh one.
    Unset<Manifold, 1> manifoldSlot;
    Manifold& tm = *manifoldSlot.data();
    if (polytope != nullptr && lengthSquared(faceN) > Real(0.5)) {
        // A box or hull: the separating-axis test (collide_triangle.cpp),
        // which also tests the triangle's plane.
        if (!collideTrianglePolytope(w, faceN, *polytope, margin, tm, axisHint, cachedAxis)) return false;
    } else {
        tm = Manifold{};
        if (separatedByTrianglePlane(w, faceN, b, margin)) return false;
        const ConvexShape tri = makeTriangle(w[0], w[1], w[2]);
        const bool hit = b.kind == ConvexKind::Point     ? collideTriangleSphere(tri, b, margin, tm)
                         : b.kind == ConvexKind::Segment ? collideTriangleCapsule(tri, b, margin, tm)
                                                         : collideConvexConvex(tri, b, margin, tm);
        if (!hit) return false;
    }
    if (dot(tm.normal, faceN) < kFaceNormalCos) {
        // Where the deepest point touches the triangle.
        std::uint32_t deepest = 0;
        for (std::uint32_t i = 1; i < tm.pointCount; ++i) {
            if (tm.points[i].depth > tm.points[deepest].depth) deepest = i;
        }
        const Vec3 onTri = tm.points[deepest].position + tm.normal * (Real(0.5) * tm.points[deepest].depth);
        const bool allowed = edgeNormalAllowed(w, convexMask, onTri, tm.normal, faceN);
        if (!allowed && polytope != nullptr && lengthSquared(faceN) > Real(0.5)) {
            // Rebuild the contact along the face normal, a box or hull in its
            // own frame as the separating-axis test builds its face contacts.
            if (!collideTrianglePolytopeAlongFace(w, faceN, *polytope, margin, tm)) return false;
        } else if (!allowed) {
            // Rebuild the contact along the face normal.
            // A hull's support vertex is kept: its supporting face along -faceN
            // starts from it (the search buildFaceManifold would repeat).
            std::uint32_t hullVertex = kNoVertex;
            const Vec3 pb = b.support(-faceN, hullVertex);
            const Real depth = dot(w[0] - pb, faceN);
            if (depth < -margin) return false;
            if (b.kind == ConvexKind::Point) {
                tm.normal = faceN;
                tm.pointCount = 0;
                addContact(tm, pb + faceN * depth, pb, depth, 7, margin);
            } else {
                SupportFace faceB;
                const SupportFace* knownB = nullptr;
                if (hullVertex != kNoVertex) {
                    supportingFace(b, -faceN, faceB, hullVertex);
                    knownB = &faceB;
                }
                buildFaceManifold(makeTriangle(w[0], w[1], w[2]), b, faceN, pb + faceN * depth, pb, margin, tm, 1, false, nullptr,
                                  knownB);
            }
            if (tm.pointCount == 0) return false;
        }
    }
    if (dot(tm.normal, faceN) >= kFaceNormalCos) {
        // Along the face normal: only the points over this triangle. (A hull
        // vertex beyond the edge, measured against the extended plane, came and
        // went with its depth from step to step, the same feature id handed to
        // two vertices 0.5 m apart, and the hull rocked between them.)
        std::uint32_t kept = 0;
        for (std::uint32_t i = 0; i < tm.pointCount; ++i) {
            const Vec3 onTriangle = tm.points[i].position + tm.normal * (Real(0.5) * tm.points[i].depth);
            if (!overTriangle(w, onTriangle)) continue;
            // The fields the test wrote (the anchors are left unset).
            ContactPoint& keptPoint = tm.points[kept++];
            keptPoint.position = tm.points[i].position;
            keptPoint.depth = tm.points[i].depth;
            keptPoint.featureId = tm.points[i].featureId;
        }
        tm.pointCount = kept;
        if (kept == 0) return false;
    }
    for (std::uint32_t i = 0; i < tm.pointCount; ++i) {
        MeshContactCandidate c;
        c.contact = {tm.points[i].position, tm.points[i].depth, meshFeature(t, tm.points[i].featureId)};
        c.normal = tm.normal;
        c.triangle = t;
        scratch.push_back(c);
    }
    return true;
}

namespace {

// How much candidate q would widen manifold m: the squared distance from a
// lone point, the area of the triangle with a pair (about the normal), the
// area the edges of a triangle see q outside them (0 or less inside).
// Compared only within one stage.
Real wideningBy(const Manifold& m, const Vec3& q) {
    const Vec3& a = m.points[0].position;
    if (m.pointCount == 1) return lengthSquared(q - a);
    const Vec3& b = m.points[1].position;
    if (m.pointCount == 2) return std::fabs(dot(cross(b - a, q - a), m.normal));
    const Vec3& c = m.points[2].position;
    const Real winding = dot(cross(b - a, c - a), m.normal) < 0 ? Real(-1) : Real(1);
    const Real ab = winding * dot(cross(b - a, q - a), m.normal);
    const Real bc = winding * dot(cross(c - b, q - b), m.normal);
    const Real ca = winding * dot(cross(a - c, q - c), m.normal);
    return -std::min(ab, std::min(bc, ca));
}

// Fills the free places of m (its touching pair chosen) with the candidates
// that widen it most, one stage at a time as reduceContacts does, the first
// of near-equals; the first `touching` candidates are touching points and
// count kTouchingPreference times their width. Candidates beyond the margin
// are skipped, and so is a widening no larger than the reduction's duplicate
// tolerance (1 mm from a lone point, 1e-3 of the span so far).
void addWideningPoints(Manifold& m, const ContactCandidate* candidates, std::uint32_t count, std::uint32_t touching, Real margin) {
    const auto score = [&](std::uint32_t i) {
        const Real w = wideningBy(m, candidates[i].position);
        return i < touching ? kTouchingPreference * w : w;
    };
    while (m.pointCount > 0 && m.pointCount < Manifold::kMaxPoints) {
        Real best = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
            if (candidates[i].depth >= -margin) best = std::max(best, score(i));
        }
        Real span2 = 0;
        for (std::uint32_t k = 1; k < m.pointCount; ++k) {
            span2 = std::max(span2, lengthSquared(m.points[k].position - m.points[0].position));
        }
        const Real floor = m.pointCount == 1 ? Real(1e-6) : Real(1e-3) * std::sqrt(span2);
        if (!(best > floor)) return;
        const Real threshold = best - Real(1e-3) * best;
        std::uint32_t pick = 0;
        while (!(candidates[pick].depth >= -margin && score(pick) >= threshold)) ++pick;
        ContactPoint& p = m.points[m.pointCount++];
        p.position = candidates[pick].position;
        p.depth = candidates[pick].depth;
        p.featureId = candidates[pick].featureId;
    }
}

}  // namespace

void groupTriangleContacts(std::vector<MeshContactCandidate>& scratch, Real margin, ManifoldBuffer& out, bool flatFaces) {
    // Group by normal, deepest first. Each pass takes the deepest candidate
    // left (the first of equals) as the seed, consumes its group in index
    // order and moves the rest, in order, to the front of `scratch`, finding
    // the next seed on the way: one pass over what is left per group, where
    // marking candidates used and searching all of them again for the next
    // seed cost two passes over every candidate per group (a lying tree's
    // hull on a curved mesh makes a group of nearly every triangle; 14 % of
    // trees100's step). The same groups in the same order as that did.
    constexpr Real kUsed = -1e30f;  // a depth at or below it never seeds a group (as a consumed candidate did)
    constexpr std::size_t kNone = ~std::size_t(0);
    const auto deeperSeed = [&scratch](std::size_t i, std::size_t seed) {
        return scratch[i].contact.depth > kUsed && (seed == kNone || scratch[i].contact.depth > scratch[seed].contact.depth);
    };
    std::size_t live = scratch.size();
    std::size_t seed = kNone;
    for (std::size_t i = 0; i < live; ++i) {
        if (deeperSeed(i, seed)) seed = i;
    }
    while (seed != kNone) {
        const Vec3 n = scratch[seed].normal;
        // The seed is the group's deepest. When it is sunk deeper than any
        // resting contact (kDeepSeed), every point at least half as deep
        // takes part as well: a pyramid hit hard on a hill of convex_vs_mesh,
        // 0.1-0.2 m into two triangles, otherwise kept only its deepest
        // point, was pushed out at that one corner, tipped and had another
        // corner deepest the next step, and rocked there sunk for hundreds of
        // steps. (Every overlapping point, or every point half as deep at any
        // depth, was tried: a resting cylinder then rocked between its rim
        // points again, EveryConvexShapeRestsOnBumpyField.)
        const Real seedDepth = scratch[seed].contact.depth;
        const Real bandFloor =
            seedDepth > kDeepSeed ? std::min(seedDepth - kReductionBand, Real(0.5) * seedDepth) : seedDepth - kReductionBand;
        Manifold& m = out.push();
        m.normal = n;
        m.childA = scratch[seed].triangle;
        constexpr std::uint32_t kBatch = 64;
        Unset<ContactCandidate, kBatch + Manifold::kMaxPoints> batchSlots, speculativeSlots;
        ContactCandidate* batch = batchSlots.data();
        ContactCandidate* speculative = speculativeSlots.data();
        std::uint32_t count = 0, speculativeCount = 0;
        std::size_t kept = 0, nextSeed = kNone;
        for (std::size_t i = 0; i < live; ++i) {
            // The seed always joins its own group, so every pass consumes at
            // least one candidate: a seed whose normal lost its unit length
            // (a body 1e13 m across, found by fuzz/snapshot_fuzz.cpp) failed
            // its own test, stayed unused and was picked again for ever.
            if (i != seed && (scratch[i].contact.depth <= kUsed || dot(scratch[i].normal, n) < kGroupCos)) {
                if (kept != i) scratch[kept] = scratch[i];
                if (deeperSeed(kept, nextSeed)) nextSeed = kept;
                ++kept;
                continue;
            }
            if (scratch[i].contact.depth >= bandFloor) {
                batch[count++] = scratch[i].contact;
            } else if (flatFaces && scratch[i].contact.depth >= -margin) {
                speculative[speculativeCount++] = scratch[i].contact;
                if (speculativeCount == kBatch + Manifold::kMaxPoints) {
                    // Bounded as well: the four that reduce them best.
                    speculativeCount = compactCandidates(speculative, speculativeCount, n, margin);
                }
            }
            if (count == kBatch + Manifold::kMaxPoints) {
                // Keep the batch bounded: reduce to 4 and continue.
                count = compactCandidates(batch, count, n, margin);
            }
        }
        reduceContacts({batch, count}, margin, m);
        if (flatFaces && speculativeCount > 0) {
            // The touching pair (the deepest and the farthest from it) stays;
            // the other places go to the widest of the touching points the
            // reduction chose for them and the speculative ones, a touching
            // point counting kTouchingPreference times its width.
            Unset<ContactCandidate, kBatch + 2 * Manifold::kMaxPoints> widenSlots;
            ContactCandidate* widen = widenSlots.data();
            std::uint32_t widenCount = 0;
            for (std::uint32_t k = 2; k < m.pointCount; ++k) {
                widen[widenCount++] = {m.points[k].position, m.points[k].depth, m.points[k].featureId};
            }
            const std::uint32_t touching = widenCount;
            for (std::uint32_t k = 0; k < speculativeCount; ++k) widen[widenCount++] = speculative[k];
            m.pointCount = std::min(m.pointCount, 2u);
            addWideningPoints(m, widen, widenCount, touching, margin);
        }
        if (m.pointCount == 0) out.pop();
        live = kept;
        seed = nextSeed;
    }
}

namespace {

// Which box or hull a separating-axis hint belongs to, with the mesh: a
// hull by its shared data (a compound's child, as every body built from the
// same hulls: two bodies' pieces over one triangle share a slot and only
// cost each other a miss), a box by its size. Any value is safe (the hints
// are only tried, SeparatingAxisCache), a distinct one is merely faster.
std::uint64_t polytopeKey(const TriangleMesh& mesh, const ConvexShape& b) {
    std::uint64_t key = reinterpret_cast<std::uintptr_t>(&mesh);
    if (b.kind == ConvexKind::Hull) {
        key ^= reinterpret_cast<std::uintptr_t>(b.hull) * 0x9E3779B97F4A7C15ull;
    } else {
        for (std::size_t k = 0; k < 3; ++k) {
            const Real h = b.halfExtents[k];
            std::uint64_t bits = 0;
            std::memcpy(&bits, &h, sizeof(Real));
            key = (key ^ bits) * 0xBF58476D1CE4E5B9ull;
        }
    }
    key *= 0xBF58476D1CE4E5B9ull;
    return key ^ (key >> 29);
}

// The hint table's slot for triangle t of the pair `pairKey` (the pair's
// run of slots from a place its hash picks), and the tag that names the
// triangle's pair there.
SeparatingAxisCache::Entry& hintSlot(SeparatingAxisCache& cache, std::uint64_t pairKey, std::uint32_t t, std::uint32_t& tag) {
    const std::uint64_t mixed = (pairKey ^ (std::uint64_t(t) * 0xC2B2AE3D27D4EB4Full)) * 0x94D049BB133111EBull;
    tag = static_cast<std::uint32_t>(mixed >> 32);
    constexpr std::uint64_t kMask = (std::uint64_t(1) << SeparatingAxisCache::kLogEntries) - 1;
    return cache.entries[((pairKey >> 40) + t) & kMask];
}

}  // namespace

void collideMeshConvex(const TriangleMesh& mesh, const Transform& meshXf, const ConvexShape& b, const AABB& bBounds,
                       Real margin, ManifoldBuffer& out) {
    std::vector<MeshContactCandidate>& scratch = out.meshScratch();
    scratch.clear();
    TrianglePolytope polytope;
    const TrianglePolytope* sat = polytope.prepare(b, out.polytopeEdgeScratch()) ? &polytope : nullptr;
    SeparatingAxisCache& hints = out.separatingAxisScratch();
    if (sat != nullptr && hints.entries.empty()) hints.entries.resize(std::size_t(1) << SeparatingAxisCache::kLogEntries);
    const std::uint64_t pairKey = sat != nullptr ? polytopeKey(mesh, b) : 0;
    const Vec3 centre = b.center();  // the one-sided test's, once for every triangle
    // The contact's triangle axis cache (TriangleAxisCache, manifold.hpp):
    // this piece's entries from the last collide(), and where this one's go.
    TriangleAxisCache& axes = out.triangleAxes();
    std::vector<TriangleAxisEntry>* axisOut = sat != nullptr ? axes.out : nullptr;
    const TriangleAxisEntry* pieceFirst = nullptr;
    const TriangleAxisEntry* pieceLast = nullptr;
    std::size_t outFirst = 0;
    if (axisOut != nullptr) {
        const TriangleAxisEntry* end = axes.in + axes.inCount;
        pieceFirst = std::lower_bound(axes.in, end, axes.piece, [](const TriangleAxisEntry& e, std::uint32_t x) { return e.piece < x; });
        pieceLast = std::upper_bound(pieceFirst, end, axes.piece, [](std::uint32_t x, const TriangleAxisEntry& e) { return x < e.piece; });
        outFirst = axisOut->size();
    }
    // The triangle's test with its hint, the hint stored back when it changed.
    const auto collideTriangle = [&](const Vec3 w[3], std::uint8_t mask, std::uint32_t t) {
        if (sat == nullptr) {
            collideTriangleWithConvex(w, mask, t, b, margin, scratch, nullptr, nullptr, &centre);
            return;
        }
        std::uint32_t tag;
        SeparatingAxisCache::Entry& slot = hintSlot(hints, pairKey, t, tag);
        std::uint32_t hint = slot.tag == tag ? slot.axis : 0;
        const std::uint32_t before = hint;
        if (axisOut == nullptr) {
            collideTriangleWithConvex(w, mask, t, b, margin, scratch, sat, &hint, &centre);
        } else {
            // The contact's entry for this triangle, if its last collide() kept one.
            TriangleAxisEntry entry{axes.piece, t, 0, 0};
            const TriangleAxisEntry* found = std::lower_bound(pieceFirst, pieceLast, t, [](const TriangleAxisEntry& e, std::uint32_t x) {
                return e.triangle < x;
            });
            if (found != pieceLast && found->triangle == t) entry = *found;
            collideTriangleWithConvex(w, mask, t, b, margin, scratch, sat, &hint, &centre, &entry);
            if (entry.axis != 0) axisOut->push_back(entry);
        }
        if (hint != before) slot = {tag, hint};
    };
    const AABB localBox = transformBounds(inverse(meshXf), bBounds.fattened(margin));
    // A mesh placed at the origin unturned (a ground, the usual case) takes
    // its vertices as they are: the identity transform changes no bit of them.
    const bool placed = !(meshXf.p.x == 0 && meshXf.p.y == 0 && meshXf.p.z == 0 && meshXf.q.x == 0 && meshXf.q.y == 0 &&
                          meshXf.q.z == 0 && meshXf.q.w == 1);
    // Moved but not turned, with no coordinate of the move zero (Jolt's
    // ConvexVsMesh terrain at (-150, 5, -150)): transformPoint's rotation by
    // the identity gives each vertex back up to the sign of a zero
    // coordinate, which the non-zero move's sum then drops, so the sum alone
    // gives the same bits.
    const bool shifted = placed && meshXf.q.x == 0 && meshXf.q.y == 0 && meshXf.q.z == 0 && meshXf.q.w == 1 &&
                         meshXf.p.x != 0 && meshXf.p.y != 0 && meshXf.p.z != 0;
    const auto visit = [&](std::uint32_t t) {
        const auto& idx = mesh.triangles[t];
        const std::uint8_t mask = t < mesh.convexEdgeMask.size() ? mesh.convexEdgeMask[t] : std::uint8_t(7);
        if (!placed) {
            const Vec3 w[3] = {mesh.vertices[idx[0]], mesh.vertices[idx[1]], mesh.vertices[idx[2]]};
            collideTriangle(w, mask, t);
            return;
        }
        if (shifted) {
            const Vec3 w[3] = {mesh.vertices[idx[0]] + meshXf.p, mesh.vertices[idx[1]] + meshXf.p,
                               mesh.vertices[idx[2]] + meshXf.p};
            collideTriangle(w, mask, t);
            return;
        }
        const Vec3 w[3] = {transformPoint(meshXf, mesh.vertices[idx[0]]), transformPoint(meshXf, mesh.vertices[idx[1]]),
                           transformPoint(meshXf, mesh.vertices[idx[2]])};
        collideTriangle(w, mask, t);
    };
    // The contact's candidate triangles (MeshCandidateCache, manifold.hpp),
    // when the contact manager keeps them: the BVH query's own triangles in
    // its order, so the same bits.
    MeshCandidateCache* near = out.meshCandidates();
    if (near != nullptr && mesh.bvh) {
        const Vec3 h = localBox.halfExtents();
        queryTrianglesCached(mesh, localBox, kCandidateGrowth * std::max(h.x, std::max(h.y, h.z)), *near, visit);
    } else {
        forEachTriangleOverlapping(mesh, localBox, visit);
    }
    if (axisOut != nullptr) {
        // In triangle order, for the next collide()'s search.
        std::sort(axisOut->begin() + static_cast<std::ptrdiff_t>(outFirst), axisOut->end(),
                  [](const TriangleAxisEntry& x, const TriangleAxisEntry& y) { return x.triangle < y.triangle; });
    }
    groupTriangleContacts(scratch, margin, out, sat != nullptr);
}

}  // namespace fulcrum::detail
