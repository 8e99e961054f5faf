#pragma once
// Contact manifolds: what the narrow phase hands to the solver.
//
// Conventions (docs/narrow-phase.md has the long form):
// - `normal` is a world-space unit vector pointing from shape A to shape B:
//   pushing B along +normal (or A along -normal) separates them.
// - `depth` is positive when the shapes overlap; a negative depth -s means the
//   surfaces are s apart along the normal (a speculative contact, reported only
//   within the caller's speculative margin).
// - `position` is world-space, midway between the two surfaces: the point on A's
//   surface is position + normal*depth/2, the point on B's is position - normal*depth/2.
// - `localAnchorA` / `localAnchorB` are those surface points in the body frames
//   of A and B (the frames passed to collide(), so a compound's child offset is
//   already folded in).
// - `featureId` names the pair of features that made the point (reference face,
//   incident face, clipping edge or incident vertex, packed by each pair
//   function); it stays the same while the same features touch, so a contact
//   cache can match points across frames for warm starting.
// - `childA` / `childB` are the compound child index (top level) or the mesh
//   triangle index of the manifold's deepest point; 0 for plain shapes.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "fulcrum/math.hpp"

namespace fulcrum {

struct TriangleMesh;

struct ContactPoint {
    Vec3 position;
    Vec3 localAnchorA;
    Vec3 localAnchorB;
    Real depth = 0;
    std::uint32_t featureId = 0;
};

struct Manifold {
    static constexpr std::uint32_t kMaxPoints = 4;
    Vec3 normal{0, 1, 0};
    std::array<ContactPoint, kMaxPoints> points{};
    std::uint32_t pointCount = 0;
    std::uint32_t childA = 0;
    std::uint32_t childB = 0;
    // A pair function that found no contact may leave here a distance the
    // shapes are proved to be at least apart (0: none); collide() hands it on
    // through ManifoldBuffer::apartBy().
    Real apartBy = 0;

    std::span<const ContactPoint> contacts() const { return {points.data(), pointCount}; }
    // Deepest penetration among the points (most positive depth).
    Real maxDepth() const {
        Real d = -1e30f;
        for (std::uint32_t i = 0; i < pointCount; ++i) d = points[i].depth > d ? points[i].depth : d;
        return d;
    }
};

namespace detail {

// A contact candidate before reduction: world position midway between the
// surfaces, depth and feature id.
struct ContactCandidate {
    Vec3 position;
    Real depth = 0;
    std::uint32_t featureId = 0;
};

// One candidate of a mesh (or other multi-part) contact, remembered with its
// own normal so candidates can be grouped into manifolds.
struct MeshContactCandidate {
    ContactCandidate contact;
    Vec3 normal;
    std::uint32_t triangle = 0;
};

// One edge of a box or hull with the two faces that meet there (the
// triangle test's view of a polytope, collide_triangle.hpp).
struct PolytopeEdge {
    std::uint32_t from = 0, to = 0;
    std::uint32_t faces[2] = {0, 0};
};

// Four edges' two face normals a and c and their cross product a x c in
// lanes (collide_triangle.hpp, TrianglePolytope::edgeLanes): v[k][i] is
// component k (a.x, a.y, a.z, c.x, c.y, c.z, (a x c).x, .y, .z) of the
// group's edge i, zero past the polytope's last edge.
struct PolytopeEdgeLanes {
    alignas(16) float v[9][4];
};

// The edge tables of the last few hulls the triangle test prepared
// (TrianglePolytope::prepare in collide_triangle.cpp), each kept with the face
// lists it was derived from: a hull whose faces match an entry's takes that
// entry's table, where deriving it sorts every face's edges (the trees' 22
// hulls against the mesh at every step: 6 % of their step). Only the faces
// decide the table, so a hit gives what deriving it again would.
struct PolytopeEdgeCache {
    struct Entry {
        const void* hull = nullptr;                 // which hull filled it last (a hint; the faces decide)
        std::uint32_t vertexCount = 0;
        std::vector<std::uint32_t> faceRanges;      // each face's first index and count
        std::vector<std::uint32_t> faceVertices;
        std::vector<PolytopeEdge> edges;
        bool closed = false;                        // the faces close up (else no table)
        // The edges' face normals and their cross products in lanes of four
        // edges (TrianglePolytope::edgeLanes), for these face normals.
        std::vector<Vec3> faceNormals;
        std::vector<PolytopeEdgeLanes> lanes;
    };
    static constexpr std::size_t kEntries = 32;
    std::vector<Entry> entries;
    std::size_t next = 0;                           // the entry a miss fills (round robin)
};

// The mesh path's separating-axis hints (collide_triangle.cpp,
// collideTrianglePolytope): per (box or hull, mesh, triangle), the polytope
// face or edge pair that last proved the two farther apart than the margin.
// The next step tries that axis first, and a pair it still separates is
// rejected without the rest of the test. A hint is one of the test's own
// candidate axes computed by the same expressions, and any candidate beyond
// the margin rejects the pair, so a hit gives the test's own answer: the
// table only saves work, whatever it holds (entries of other pairs that hash
// to the same place included), and needs no saving in snapshots.
// A shape's triangles take consecutive slots (from a place its hash picks),
// so the hints of one piece over a mesh's rows share cache lines: with one
// slot per hash, a larger table cost more in cache misses than the hints
// saved (trees50).
struct SeparatingAxisCache {
    struct Entry {
        std::uint32_t tag = 0;   // which (shape, mesh, triangle) wrote it, hashed
        std::uint32_t axis = 0;  // collide_triangle.hpp's encoding; 0: none
    };
    static constexpr unsigned kLogEntries = 14;
    std::vector<Entry> entries;  // 1 << kLogEntries once used
};

// The per-contact triangle axis cache (collide_triangle.cpp, the "cached
// axis" path; docs/narrow-phase.md, "The triangle axis cache"): for each
// triangle a box or hull met within the margin, the axis the full
// separating-axis test chose (collide_triangle.hpp's hint encoding, or
// kTriangleFaceAxis) and its separation then. The next collide() of the pair
// builds the contact along that axis alone while its separation has moved by
// less than kAxisCacheTolerance, and runs the full test otherwise. The kept
// axis is not proven the best, so the cache changes results: it is the
// contact's own state (Contact::triangleAxes), saved in snapshots, never a
// worker's. Entries are sorted by (piece, triangle).
struct TriangleAxisEntry {
    std::uint32_t piece = 0;     // the box or hull's child index, with the mesh's (narrow_phase.cpp)
    std::uint32_t triangle = 0;
    std::uint32_t axis = 0;      // 0: none
    Real separation = 0;         // when the full test chose the axis
};
struct TriangleAxisCache {
    const TriangleAxisEntry* in = nullptr;  // the contact's entries from its last collide()
    std::size_t inCount = 0;
    std::vector<TriangleAxisEntry>* out = nullptr;  // null: no cache (the full test always)
    std::uint32_t piece = 0;                        // the piece the mesh path is colliding now
};

// A convex body's candidate triangles of a mesh (collide_mesh.cpp,
// collideMeshConvex; docs/narrow-phase.md, "The candidate triangles"):
// every triangle of `mesh` whose bounds overlap `box` (mesh-local, the
// body's query box grown when the list was made), with those bounds, in the
// BVH's order. While
// the body's query box stays inside `box`, the triangles it overlaps are
// those of the list that overlap it, in the same order as the BVH query
// would give them (queryTrianglesCached, mesh_bvh.hpp): the same answer, so
// the list is only the contact's scratch (Contact::meshCandidates), never
// saved in snapshots. Null `mesh`: no list.
struct MeshCandidateCache {
    struct Candidate {
        AABB bounds;  // the triangle's (triangleBounds, mesh_bvh.hpp)
        std::uint32_t triangle = 0;
    };
    const TriangleMesh* mesh = nullptr;
    AABB box;
    std::vector<Candidate> triangles;  // capacity kept across queries
    void clear() {
        mesh = nullptr;
        triangles.clear();
    }
};

// The GJK warm start of two hulls or a box and a hull (gjk.cpp, gjkDistance;
// docs/narrow-phase.md, "GJK's warm start"): the vertices (a hull's vertex
// index, a box's corner: bit k set for + along axis k) of the simplex the
// pair's last GJK run ended on, at most a triangle. The next run starts from
// that simplex at the shapes' new poses instead of from the line of centres;
// resting and slowly moving pairs then converge after one or two support
// searches. The answer is GJK's to its tolerance either way, but not bit for
// bit, so the start is the contact's own state (Contact::gjkWarmStart), saved
// in snapshots (format version 12).
struct GjkWarmStart {
    std::uint32_t count = 0;  // 0..3; 0: none (GJK starts cold)
    std::uint32_t indexA[3] = {0, 0, 0};
    std::uint32_t indexB[3] = {0, 0, 0};
};

// Reduces `candidates` to at most 4 points of `out` (normal already set):
// keeps the deepest point, then the point farthest from it, then the two that
// maximise the contact polygon's area (Gregorius, "Robust Contact Creation for
// Physics Simulations", GDC 2015). Near-duplicates (closer than 1e-3 of the
// span) are dropped. Candidates shallower than -margin are ignored.
void reduceContacts(std::span<const ContactCandidate> candidates, Real margin, Manifold& out);

// A candidate buffer that filled up: reduces candidates[0, count) in place to
// the points reduceContacts keeps for `normal` (at most four) and returns
// their count, so the caller can go on collecting into the same buffer.
std::uint32_t compactCandidates(ContactCandidate* candidates, std::uint32_t count, const Vec3& normal, Real margin);

}  // namespace detail

// Reusable output of collide(): cleared by the caller (or by collide), grown
// on demand, so after warm-up no call allocates. Also holds the scratch
// arrays the mesh and compound paths need.
class ManifoldBuffer {
public:
    void clear() {
        count_ = 0;
        apartBy_ = 0;
    }
    std::size_t size() const { return count_; }
    bool empty() const { return count_ == 0; }
    const Manifold& operator[](std::size_t i) const { return manifolds_[i]; }
    Manifold& operator[](std::size_t i) { return manifolds_[i]; }
    std::span<const Manifold> manifolds() const { return {manifolds_.data(), count_}; }
    const Manifold* begin() const { return manifolds_.data(); }
    const Manifold* end() const { return manifolds_.data() + count_; }

    // A fresh, empty manifold at the end of the buffer.
    Manifold& push() {
        if (count_ == manifolds_.size()) manifolds_.emplace_back();
        Manifold& m = manifolds_[count_++];
        m = Manifold{};
        return m;
    }
    // Drops the last manifold (a pair function that found nothing after all).
    void pop() { --count_; }

    // After collide() of two plain convex shapes (neither a compound nor
    // rounded) that gave no manifold: a lower bound of the shapes' distance
    // that the pair function proved on its way to rejecting the pair, or 0
    // when it proved none (the contact manager's apart cache, docs/narrow-phase.md
    // "Pairs proved apart"); after collide() with a SpeculativeReach of a
    // compound against a convex shape or a compound, the least such distance
    // over the compound's children (narrow_phase.cpp). Meaningless for any
    // other pair.
    Real apartBy() const { return apartBy_; }
    void setApartBy(Real distance) { apartBy_ = distance; }

    // Scratch for the mesh path (candidates of one shape against many triangles).
    std::vector<detail::MeshContactCandidate>& meshScratch() { return meshScratch_; }
    std::vector<std::uint32_t>& triangleScratch() { return triangleScratch_; }
    // The hulls' edges with their faces (the mesh path's triangle test).
    detail::PolytopeEdgeCache& polytopeEdgeScratch() { return polytopeEdgeScratch_; }
    // The boxes' and hulls' separating axes against triangles (a hint table).
    detail::SeparatingAxisCache& separatingAxisScratch() { return separatingAxisScratch_; }
    // The contact's triangle axis cache for this collide() (none unless the
    // contact manager sets it).
    detail::TriangleAxisCache& triangleAxes() { return triangleAxes_; }
    // The contact's GJK warm start for this collide() of two hulls or a box
    // and a hull (none unless the contact manager sets it; read and rewritten
    // by the pair's GJK).
    detail::GjkWarmStart* gjkWarmStart() const { return gjkWarmStart_; }
    void setGjkWarmStart(detail::GjkWarmStart* warm) { gjkWarmStart_ = warm; }
    // The contact's candidate triangles for this collide() of a convex shape
    // against a mesh (none unless the contact manager sets it).
    detail::MeshCandidateCache* meshCandidates() const { return meshCandidates_; }
    void setMeshCandidates(detail::MeshCandidateCache* near) { meshCandidates_ = near; }

private:
    std::vector<Manifold> manifolds_;
    std::size_t count_ = 0;
    Real apartBy_ = 0;
    std::vector<detail::MeshContactCandidate> meshScratch_;
    std::vector<std::uint32_t> triangleScratch_;
    detail::PolytopeEdgeCache polytopeEdgeScratch_;
    detail::SeparatingAxisCache separatingAxisScratch_;
    detail::TriangleAxisCache triangleAxes_;
    detail::GjkWarmStart* gjkWarmStart_ = nullptr;
    detail::MeshCandidateCache* meshCandidates_ = nullptr;
};

}  // namespace fulcrum
