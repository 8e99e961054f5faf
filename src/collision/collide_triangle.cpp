// A box or convex hull against one triangle: the separating-axis test.
//
// The general path (GJK, EPA when the shapes overlap, then face clipping
// along EPA's normal) was 57 % of a mesh scene's step (docs/benchmarks.md,
// "Mesh scenes"): each of the 10-30 triangles under a hull ran it. A triangle
// and a polytope are both polyhedra, so the axes that can separate them, and
// the direction of least overlap when they do overlap, are among a short
// list (the Minkowski difference's face normals):
// - the triangle's normal, both ways (the triangle is flat: its two faces);
// - the polytope's face normals;
// - for an edge of the polytope and an edge of the triangle, the common
//   perpendicular, when it is a face of the Minkowski difference: on the
//   Gauss map, the arc of the polytope's edge (between its two face normals)
//   crosses the arc of the triangle's edge reflected through the centre (the
//   half great circle from n to -n through the edge's outward side
//   direction). Every other pair of edges is skipped, as in Gregorius's SAT
//   for hulls (GDC 2013); a box is a hull whose 12 edges are known.
// Each axis's separation is exact and a lower bound of the distance; the
// largest is the overlap's depth (negated) when the shapes overlap, and a
// lower bound of their distance when they do not (a speculative contact that
// says the shapes are closer than they are is safe). Any axis that separates
// by more than the margin ends the test.
//
// The contact along the chosen axis: a face axis clips the other shape's
// supporting feature against the reference face (buildFaceManifold, as the
// general path does after EPA), an edge axis is the closest points of the two
// edges (one point). The triangle's normal is preferred to a polytope face,
// unless the latter separates the pair better by more than kAxisBias, and,
// while the shapes overlap, to an edge pair unless that is better by 5 mm and
// 5 % (kEdgeBias, as box-box): ties (a box lying flat on a triangle) keep the
// triangle's own normal, and the choice does not flip between steps.
// Everything the mesh path does afterwards (internal edges, points over the
// triangle only, grouping by normal) is collide_mesh.cpp's, unchanged.
#include "collision/collide_triangle.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
#include <xmmintrin.h>
#endif

#include "collision/collide_mesh.hpp"
#include "collision/collide_pairs.hpp"

namespace fulcrum::detail {

namespace {

// The triangle's face axis stands unless a polytope face separates the pair
// better by more than this: the general path's preference for a box or hull
// face over EPA's normal (kFaceAxisTolerance in collide_convex.cpp).
constexpr Real kAxisBias = Real(1e-4);
// Where the shapes overlap along every face axis, a face axis stands unless
// an edge pair separates the pair better by more than this plus
// kEdgeBiasRelative of the separation, as box-box does
// (collide_box.cpp). With kAxisBias here, a box resting on a gently curved
// heightfield (bench/heightfield.cpp's hills, 0.25 m boxes on 0.25 m cells)
// flipped between a face manifold and a one-point edge contact at the
// slightly convex edges under it and never came to rest (6 mm/s after
// settling, against 0 with the general path).
constexpr Real kEdgeBias = Real(0.005);
constexpr Real kEdgeBiasRelative = Real(0.05);
// Edges this close to parallel (sine of their angle) make no edge axis: their
// common perpendicular is not defined, and the faces on either side of the
// two edges are the axes of such a contact.
constexpr Real kParallelSine = Real(1e-3);

// A box's 12 edges: vertex i has coordinate +h along axis k when bit k of i
// is set; face 2k is +k, face 2k+1 is -k. The edge along k from vertex i (bit
// k clear) lies on the faces of the other two axes on i's sides.
constexpr PolytopeEdge boxEdge(std::uint32_t k, std::uint32_t i) {
    const std::uint32_t u = (k + 1) % 3, v = (k + 2) % 3;
    PolytopeEdge e;
    e.from = i;
    e.to = i | (1u << k);
    e.faces[0] = 2 * u + ((i >> u) & 1u ? 0u : 1u);
    e.faces[1] = 2 * v + ((i >> v) & 1u ? 0u : 1u);
    return e;
}
constexpr PolytopeEdge kBoxEdges[12] = {
    boxEdge(0, 0), boxEdge(0, 2), boxEdge(0, 4), boxEdge(0, 6),  // along x
    boxEdge(1, 0), boxEdge(1, 1), boxEdge(1, 4), boxEdge(1, 5),  // along y
    boxEdge(2, 0), boxEdge(2, 1), boxEdge(2, 2), boxEdge(2, 3),  // along z
};

// The feature id of an edge-edge contact (before the mesh path hashes in the
// triangle): its own high bits, the triangle's edge, the polytope's edge.
std::uint32_t edgeFeature(std::uint32_t triangleEdge, std::uint32_t polytopeEdge) {
    return 0x80400000u | (triangleEdge << 20) | (polytopeEdge & 0xFFFFFu);
}

// How far a point may lie outside a face's other planes and still count as
// over the face (rounding).
constexpr Real kOverTolerance = Real(1e-5);

// Polytopes with at most this many faces (every box, the hulls of the bench
// scenes) get their face-edge dots tabled on the stack.
constexpr std::uint32_t kMaxTabledFaces = 64;

// How far a cached axis's separation may move from the one the full test
// found before the full test runs again (TriangleAxisCache, manifold.hpp):
// Box3D's linear slop, as its mesh contacts use it.
constexpr Real kAxisCacheTolerance = Real(0.005);

#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
// The edges' face normals and their cross products in lanes of four edges,
// zero past the last edge.
void fillEdgeLanes(const HullFace* faces, const PolytopeEdge* edges, std::uint32_t edgeCount, PolytopeEdgeLanes* lanes) {
    const std::uint32_t groups = (edgeCount + 3) / 4;
    for (std::uint32_t g = 0; g < groups; ++g) lanes[g] = PolytopeEdgeLanes{};
    for (std::uint32_t e = 0; e < edgeCount; ++e) {
        const Vec3 a = faces[edges[e].faces[0]].normal, c = faces[edges[e].faces[1]].normal, ac = cross(a, c);
        float(*v)[4] = lanes[e / 4].v;
        const std::uint32_t i = e % 4;
        v[0][i] = a.x;
        v[1][i] = a.y;
        v[2][i] = a.z;
        v[3][i] = c.x;
        v[4][i] = c.y;
        v[5][i] = c.z;
        v[6][i] = ac.x;
        v[7][i] = ac.y;
        v[8][i] = ac.z;
    }
}

// Every box's lanes: its face normals are the axes whatever its size.
const PolytopeEdgeLanes* boxEdgeLanes() {
    static const std::array<PolytopeEdgeLanes, 3> lanes = [] {
        std::array<HullFace, 6> faces{};
        for (std::size_t k = 0; k < 3; ++k) {
            Vec3 axis;
            axis[k] = 1;
            faces[2 * k].normal = axis;
            faces[2 * k + 1].normal = -axis;
        }
        std::array<PolytopeEdgeLanes, 3> l{};
        fillEdgeLanes(faces.data(), kBoxEdges, 12, l.data());
        return l;
    }();
    return lanes.data();
}
#else
const PolytopeEdgeLanes* boxEdgeLanes() { return nullptr; }
#endif

}  // namespace

void TrianglePolytope::setFrame(const ConvexShape& b) {
    shape = &b;
    rotation = toMat3(b.xf.q);
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
    const Vec3 columns[3] = {rotation.c0, rotation.c1, rotation.c2};
    for (std::size_t k = 0; k < 3; ++k) {
        for (std::size_t i = 0; i < 3; ++i) {
            for (float& lane : frameLanes[3 * k + i]) lane = columns[k][i];
        }
        frameLanes[9 + k][0] = frameLanes[9 + k][1] = frameLanes[9 + k][2] = b.xf.p[k];
        frameLanes[9 + k][3] = 0.0f;
    }
#endif
}

bool TrianglePolytope::prepare(const ConvexShape& b, std::vector<PolytopeEdge>& edgeScratch) {
    setFrame(b);
    if (b.radius != 0) return false;
    if (b.kind == ConvexKind::Box) {
        const Vec3 h = b.halfExtents;
        for (std::uint32_t i = 0; i < 8; ++i) {
            boxVertices_[i] = {(i & 1u) ? h.x : -h.x, (i & 2u) ? h.y : -h.y, (i & 4u) ? h.z : -h.z};
        }
        for (std::size_t k = 0; k < 3; ++k) {
            Vec3 axis;
            axis[k] = 1;
            boxFaces_[2 * k].normal = axis;
            boxFaces_[2 * k + 1].normal = -axis;
            boxFaces_[2 * k].offset = boxFaces_[2 * k + 1].offset = h[k];
        }
        vertices = boxVertices_.data();
        vertexCount = 8;
        faces = boxFaces_.data();
        faceCount = 6;
        edges = kBoxEdges;
        edgeCount = 12;
        edgeLanes = boxEdgeLanes();
        edgeLaneGroups = edgeLanes != nullptr ? 3 : 0;
        return true;
    }
    if (b.kind != ConvexKind::Hull || b.hull == nullptr) return false;
    const ConvexHull& h = *b.hull;
    if (h.vertices.size() < 4 || h.faces.size() < 4) return false;
    // Every face's edges, keyed by (lower vertex, higher vertex), faces[1]
    // holding the way round (0: lower to higher in the face's loop).
    edgeScratch.clear();
    for (std::uint32_t f = 0; f < h.faces.size(); ++f) {
        const HullFace& face = h.faces[f];
        if (std::uint64_t(face.firstIndex) + face.indexCount > h.faceVertices.size() || face.indexCount < 3) return false;
        for (std::uint32_t i = 0; i < face.indexCount; ++i) {
            const std::uint32_t a = h.faceVertices[face.firstIndex + i];
            const std::uint32_t c = h.faceVertices[face.firstIndex + (i + 1) % face.indexCount];
            if (a >= h.vertices.size() || c >= h.vertices.size()) return false;
            PolytopeEdge e;
            e.from = std::min(a, c);
            e.to = std::max(a, c);
            e.faces[0] = f;
            e.faces[1] = a < c ? 0u : 1u;
            edgeScratch.push_back(e);
        }
    }
    std::sort(edgeScratch.begin(), edgeScratch.end(), [](const PolytopeEdge& x, const PolytopeEdge& y) {
        if (x.from != y.from) return x.from < y.from;
        if (x.to != y.to) return x.to < y.to;
        return x.faces[1] < y.faces[1];
    });
    // A closed surface has each edge twice, once each way round.
    const std::size_t n = edgeScratch.size();
    if (n % 2 != 0) return false;
    for (std::size_t k = 0; 2 * k < n; ++k) {
        const PolytopeEdge x = edgeScratch[2 * k], y = edgeScratch[2 * k + 1];
        if (x.from != y.from || x.to != y.to || x.faces[1] != 0 || y.faces[1] != 1) return false;
        if (k > 0 && edgeScratch[k - 1].from == x.from && edgeScratch[k - 1].to == x.to) return false;
        edgeScratch[k] = {x.from, x.to, {x.faces[0], y.faces[0]}};
    }
    edgeScratch.resize(n / 2);
    vertices = h.vertices.data();
    vertexCount = static_cast<std::uint32_t>(h.vertices.size());
    faces = h.faces.data();
    faceCount = static_cast<std::uint32_t>(h.faces.size());
    edges = edgeScratch.data();
    edgeCount = static_cast<std::uint32_t>(edgeScratch.size());
    edgeLanes = nullptr;
    edgeLaneGroups = 0;
    return true;
}

bool TrianglePolytope::prepare(const ConvexShape& b, PolytopeEdgeCache& cache) {
    static std::vector<PolytopeEdge> unused;  // boxes and the shapes without a table never touch it
    if (b.radius != 0 || b.kind != ConvexKind::Hull || b.hull == nullptr) return prepare(b, unused);
    const ConvexHull& h = *b.hull;
    if (cache.entries.empty()) cache.entries.resize(PolytopeEdgeCache::kEntries);
    // The entry this hull filled last, if its faces are still these.
    PolytopeEdgeCache::Entry* entry = nullptr;
    for (PolytopeEdgeCache::Entry& e : cache.entries) {
        if (e.hull == &h) {
            entry = &e;
            break;
        }
    }
    bool same = entry != nullptr && entry->vertexCount == h.vertices.size() && entry->faceRanges.size() == 2 * h.faces.size() &&
                entry->faceVertices == h.faceVertices;
    for (std::size_t f = 0; same && f < h.faces.size(); ++f) {
        same = entry->faceRanges[2 * f] == h.faces[f].firstIndex && entry->faceRanges[2 * f + 1] == h.faces[f].indexCount;
    }
    if (!same) {
        if (entry == nullptr) {
            entry = &cache.entries[cache.next];
            cache.next = (cache.next + 1) % PolytopeEdgeCache::kEntries;
        }
        entry->hull = &h;
        entry->vertexCount = static_cast<std::uint32_t>(h.vertices.size());
        entry->faceRanges.clear();
        for (const HullFace& face : h.faces) {
            entry->faceRanges.push_back(face.firstIndex);
            entry->faceRanges.push_back(face.indexCount);
        }
        entry->faceVertices = h.faceVertices;
        entry->closed = prepare(b, entry->edges);
        entry->faceNormals.clear();
        entry->lanes.clear();
        if (!entry->closed) return false;
    }
    setFrame(b);
    if (!entry->closed) return false;
    vertices = h.vertices.data();
    vertexCount = static_cast<std::uint32_t>(h.vertices.size());
    faces = h.faces.data();
    faceCount = static_cast<std::uint32_t>(h.faces.size());
    edges = entry->edges.data();
    edgeCount = static_cast<std::uint32_t>(entry->edges.size());
    edgeLanes = nullptr;
    edgeLaneGroups = 0;
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
    if (edgeCount <= kMaxLaneEdges) {
        // The lanes, unless the entry's were made from these face normals.
        bool sameNormals = entry->faceNormals.size() == faceCount;
        for (std::uint32_t f = 0; sameNormals && f < faceCount; ++f) {
            const Vec3 &x = entry->faceNormals[f], &y = faces[f].normal;
            sameNormals = x.x == y.x && x.y == y.y && x.z == y.z;
        }
        if (!sameNormals) {
            entry->faceNormals.resize(faceCount);
            for (std::uint32_t f = 0; f < faceCount; ++f) entry->faceNormals[f] = faces[f].normal;
            entry->lanes.resize((edgeCount + 3) / 4);
            fillEdgeLanes(faces, edges, edgeCount, entry->lanes.data());
        }
        edgeLanes = entry->lanes.data();
        edgeLaneGroups = static_cast<std::uint32_t>(entry->lanes.size());
    }
#endif
    return true;
}

// The triangle's vertices and normal in the polytope's frame by its rotation
// matrix, taken once per pair (TrianglePolytope::rotation): v = R^T (w - p),
// n = R^T faceN. Three dots a point where the quaternion per point took two
// cross products and their sums (branch trees11); the results differ from
// the quaternion's by rounding only.
void toPieceFrame(const TrianglePolytope& p, const Vec3 w[3], const Vec3& faceN, Vec3 v[3], Vec3& n) {
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
    // Three points and the normal a lane each, the matrix and the position
    // as prepare left them in lanes (p.frameLanes: r and o).
    const float(*lanes)[4] = p.frameLanes;
    const __m128 x = _mm_sub_ps(_mm_setr_ps(w[0].x, w[1].x, w[2].x, faceN.x), _mm_load_ps(lanes[9]));
    const __m128 y = _mm_sub_ps(_mm_setr_ps(w[0].y, w[1].y, w[2].y, faceN.y), _mm_load_ps(lanes[10]));
    const __m128 z = _mm_sub_ps(_mm_setr_ps(w[0].z, w[1].z, w[2].z, faceN.z), _mm_load_ps(lanes[11]));
    // Row k of R^T: column k's x, y and z entries times the lanes' x, y and z.
    const auto row = [&](std::size_t k) {
        return _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_load_ps(lanes[3 * k]), x), _mm_mul_ps(_mm_load_ps(lanes[3 * k + 1]), y)),
                          _mm_mul_ps(_mm_load_ps(lanes[3 * k + 2]), z));
    };
    alignas(16) float ox[4], oy[4], oz[4];
    _mm_store_ps(ox, row(0));
    _mm_store_ps(oy, row(1));
    _mm_store_ps(oz, row(2));
    for (std::size_t i = 0; i < 3; ++i) v[i] = {ox[i], oy[i], oz[i]};
    n = {ox[3], oy[3], oz[3]};
#else
    const Mat3& r = p.rotation;
    const Vec3& o = p.shape->xf.p;
    for (std::size_t i = 0; i < 3; ++i) v[i] = transposeMul(r, w[i] - o);
    n = transposeMul(r, faceN);
#endif
}

namespace {
// A point of the polytope's frame in the world, by the same matrix.
inline Vec3 pieceToWorld(const TrianglePolytope& p, const Vec3& q) { return p.rotation * q + p.shape->xf.p; }

}  // namespace

// The polytope's supporting face along l (its own frame), as supportingFace
// gives it in the world but left in the polytope's frame: a box's face of
// the axis nearest l (the same corners in the same order), a hull's face
// most aligned with l among the faces at vertex `top` (the vertex furthest
// along l, which the caller's scan found).
void pieceSupportingFace(const TrianglePolytope& p, const Vec3& l, std::uint32_t top, SupportFace& out) {
    const ConvexShape& s = *p.shape;
    if (s.kind == ConvexKind::Box) {
        const int axis = maxAxis(abs(l));
        const Real sign = l[static_cast<std::size_t>(axis)] >= 0 ? Real(1) : Real(-1);
        const Vec3 e = s.halfExtents;
        boxFaceCorners(e, axis, sign, out.points);
        out.count = 4;
        out.id = static_cast<std::uint32_t>(2 * axis + (sign > 0 ? 0 : 1));
        out.normal = p.faces[out.id].normal;
        return;
    }
    const ConvexHull& h = *s.hull;
    const std::uint32_t best = hullFaceAtVertex(h, top, l);
    const HullFace& face = h.faces[best];
    const std::uint32_t count = face.indexCount < kMaxFacePoints ? face.indexCount : kMaxFacePoints;
    for (std::uint32_t i = 0; i < count; ++i) out.points[i] = h.vertices[h.faceVertices[face.firstIndex + i]];
    out.count = count;
    out.id = best;
    out.normal = face.normal;
}

namespace {

// The polytope's face f in its own frame (the reference face of a polytope
// face axis): a box's by its axis and sign, a hull's as stored.
void pieceFace(const TrianglePolytope& p, std::uint32_t f, SupportFace& out) {
    if (p.shape->kind == ConvexKind::Box) {
        pieceSupportingFace(p, p.faces[f].normal, 0, out);
        return;
    }
    const ConvexHull& h = *p.shape->hull;
    const HullFace& face = h.faces[f];
    const std::uint32_t count = face.indexCount < kMaxFacePoints ? face.indexCount : kMaxFacePoints;
    for (std::uint32_t i = 0; i < count; ++i) out.points[i] = h.vertices[h.faceVertices[face.firstIndex + i]];
    out.count = count;
    out.id = f;
    out.normal = face.normal;
}

// True when the triangle's edge j and the polytope's edge e cross, seen along
// their common perpendicular: the closest points of their lines lie inside
// both segments. In the polytope's frame (v, the triangle there).
// `s` is the closest point's parameter on the triangle's edge, as the edge
// contact (buildAlong) takes it from the same call.
bool edgesCross(const Vec3 v[3], std::uint32_t j, const TrianglePolytope& p, std::uint32_t e, Real& s) {
    const Vec3 a0 = v[j], a1 = v[(j + 1) % 3];
    const Vec3 b0 = p.vertices[p.edges[e].from];
    const Vec3 b1 = p.vertices[p.edges[e].to];
    Real u;
    closestSegmentSegment(a0, a1, b0, b1, s, u);
    return s > 0 && s < 1 && u > 0 && u < 1;
}

// The separation along polytope face f's axis (from the triangle to the
// polytope): the triangle's lowest vertex under the face's plane, `vertex`
// that vertex. The full test and the hint compute it alike (the same bits).
[[gnu::always_inline]] inline Real faceAxisSeparation(const TrianglePolytope& p, std::uint32_t f, const Vec3 v[3],
                                                      std::uint32_t& vertex) {
    const Vec3 nf = p.faces[f].normal;
    const Real d[3] = {dot(nf, v[0]), dot(nf, v[1]), dot(nf, v[2])};
    vertex = d[0] <= d[1] ? (d[0] <= d[2] ? 0u : 2u) : (d[1] <= d[2] ? 1u : 2u);
    return d[vertex] - p.faces[f].offset;
}

// The axis of the polytope's edge with face normals a and c against a
// triangle edge (its side direction `side`, squared length tt, the faces'
// dots with it ca and cc), when the pair makes a face of the Minkowski
// difference (collideTrianglePolytope): false when it does not.
[[gnu::always_inline]] inline bool edgePairAxis(const Vec3& a, const Vec3& c, Real ca, Real cc, const Vec3& side, Real tt,
                                                Vec3& axis) {
    if (!(ca * cc < 0)) return false;
    if (std::max(ca * ca, cc * cc) < kParallelSine * kParallelSine * tt) return false;
    const Vec3 mid = a + (c - a) * (ca / (ca - cc));
    if (!(dot(mid, side) < 0)) return false;
    axis = -normalize(mid);
    return true;
}

// True when the hinted axis (a polytope face, or an edge pair that is still
// a candidate) separates the triangle (v, normal n, in the polytope's frame)
// from the polytope by more than the margin: then the full test rejects the
// pair too, on that axis if on no other.
bool hintSeparates(std::uint32_t hint, const TrianglePolytope& p, const Vec3 v[3], const Vec3& n, Real margin) {
    const std::uint32_t index = hint & kAxisHintIndex;
    const std::uint32_t kind = hint & ~kAxisHintIndex;
    if (kind == kFaceAxisHint) {
        if (index >= p.faceCount) return false;
        std::uint32_t vertex;
        return faceAxisSeparation(p, index, v, vertex) > margin;
    }
    if (kind != kEdgeAxisHint) return false;
    const std::uint32_t e = index / 3, j = index % 3;
    if (e >= p.edgeCount) return false;
    const Vec3 t = v[(j + 1) % 3] - v[j];
    const Vec3 side = cross(t, n);
    const Real tt = dot(t, t);
    const PolytopeEdge& edge = p.edges[e];
    const Vec3 a = p.faces[edge.faces[0]].normal, c = p.faces[edge.faces[1]].normal;
    const Real ca = dot(a, t);
    if (p.edgeLaneGroups != 0) {
        // The lanes' filter as the full test applies it (the same products
        // and sums): a pair it skips is no candidate there either.
        const float(*lanes)[4] = p.edgeLanes[e / 4].v;
        const Vec3 ac{lanes[6][e % 4], lanes[7][e % 4], lanes[8][e % 4]};
        if (!(ca * dot(ac, n) > 0)) return false;
    }
    Vec3 axis;
    if (!edgePairAxis(a, c, ca, dot(c, t), side, tt, axis)) return false;
    return dot(axis, p.vertices[edge.from] - v[j]) > margin;
}

// The axis a triangle test settled on, with what building its contact needs
// (collideTrianglePolytope: the full search fills every field, the cached
// axis only its own).
enum class Axis { TriangleFace, BackFace, PolytopeFace, Edges };
struct Choice {
    Axis axis = Axis::TriangleFace;
    Real separation = 0;  // along `axis` (the cache's)
    Real faceSeparation = 0;
    std::uint32_t lowest = 0;  // the polytope's vertex lowest along the triangle's normal
    std::uint32_t bestFace = 0, bestVertex = 0;
    Real polytopeSeparation = 0;
    std::uint32_t bestEdge = 0, bestTriangleEdge = 0;
    Vec3 bestEdgeAxis;
    Real edgeSeparation = 0;
    bool edgeBetter = false;  // a triangle face kept against a better edge pair (within kEdgeBias)
    bool realized = true;     // apart, the features the axis names meet across it
    // The edges' closest point parameter on the triangle's edge, when
    // axisRealized found it for this bestEdge and bestTriangleEdge.
    bool edgeParameterKnown = false;
    Real edgeParameter = 0;
};

// Apart, an axis's separation is the distance only when the features it
// names meet across it: the polytope's nearest vertex over the triangle,
// the triangle's nearest vertex over the polytope's face, the two edges
// crossing (collideTrianglePolytope).
bool axisRealized(Choice& c, const TrianglePolytope& p, const Vec3 v[3]) {
    if (c.axis == Axis::Edges) {
        c.edgeParameterKnown = true;
        return edgesCross(v, c.bestTriangleEdge, p, c.bestEdge, c.edgeParameter);
    }
    if (c.axis == Axis::PolytopeFace) {
        // The triangle's vertex, moved onto the face's plane, inside every other face.
        const Vec3 q = v[c.bestVertex] - p.faces[c.bestFace].normal * c.polytopeSeparation;
        bool realized = true;
        for (std::uint32_t f = 0; f < p.faceCount && realized; ++f) {
            realized = f == c.bestFace || dot(p.faces[f].normal, q) <= p.faces[f].offset + kOverTolerance;
        }
        return realized;
    }
    return overTriangle(v, p.vertices[c.lowest]);
}

// The triangle's supporting face along n, as supportingFace(makeTriangle(w),
// n) gives it, without the square root again: its unit normal faceN (in the
// polytope's frame, the triangle v and its normal moved there).
void triangleFace(const Vec3 w[3], const Vec3& faceN, const Vec3& n, SupportFace& out) {
    out.count = 3;
    out.points[0] = w[0];
    if (dot(faceN, n) >= 0) {
        out.points[1] = w[1];
        out.points[2] = w[2];
        out.normal = faceN;
        out.id = 0;
    } else {
        out.points[1] = w[2];
        out.points[2] = w[1];
        out.normal = -faceN;
        out.id = 1;
    }
}

// The contact along c's axis (collideTrianglePolytope's second half): false
// when it gives no point. c.axis ends naming the axis the contact took (a
// face kept against a better edge pair may fall back to the pair).
bool buildAlong(Choice& c, const Vec3 w[3], const Vec3& faceN, const Vec3 v[3], const Vec3& n, const TrianglePolytope& p,
                Real margin, Manifold& m) {
    const ConvexShape& b = *p.shape;
    const bool realized = c.realized;
    // True when m holds nothing but buildFaceManifold's stand-in (pa, pb).
    const auto onlyStandIn = [&m](const Vec3& pa, const Vec3& pb) {
        return m.pointCount == 1 && m.points[0].position == (pa + pb) * Real(0.5);
    };

    // A face's manifold is built and clipped in the polytope's frame (v and
    // n, the triangle there; the polytope's faces as stored, not moved into
    // the world point by point), and its points alone moved back. Both
    // faces are handed to buildFaceManifold, which then reads neither shape
    // (b stands for both).
    switch (c.axis) {
        case Axis::TriangleFace:
        case Axis::BackFace: {
            // The back face (the shape reaching further below the triangle's
            // plane than above it, its centre above) is not a contact a
            // one-sided triangle keeps: the mesh path rebuilds such a normal
            // along the front face (edgeNormalAllowed), exactly as here,
            // without the polytope's deepest point joining the clipped ones.
            const Vec3 pb = p.vertices[c.lowest];
            const Real depth = -c.faceSeparation;
            // The polytope's supporting face from the vertex the axis search
            // found lowest along the triangle's normal (for a hull, the vertex
            // its own support search along -n returns).
            SupportFace pieceFaceB;
            pieceSupportingFace(p, -n, c.lowest, pieceFaceB);
            SupportFace triangle;
            triangleFace(v, n, n, triangle);
            buildFaceManifold(b, b, n, pb + n * depth, pb, margin, m, 1, c.axis == Axis::TriangleFace && realized, &triangle,
                              &pieceFaceB);
            // Kept against a better edge pair (within kEdgeBias), the face
            // must hold a point over the triangle, the only points the mesh
            // path keeps along its normal: a hull sunk across the triangle's
            // edge, its deepest part beyond it, otherwise lost its contact.
            if (c.edgeBetter) {
                bool over = false;
                for (std::uint32_t i = 0; i < m.pointCount && !over; ++i) {
                    over = overTriangle(v, m.points[i].position + n * (Real(0.5) * m.points[i].depth));
                }
                if (!over) c.axis = Axis::Edges;
            }
            if (c.axis != Axis::Edges) {
                // Along the triangle's own normal: faceN itself, as the mesh
                // path compares and groups it.
                m.normal = faceN;
                for (std::uint32_t i = 0; i < m.pointCount; ++i) m.points[i].position = pieceToWorld(p, m.points[i].position);
            }
            break;
        }
        case Axis::PolytopeFace: {
            const Vec3 normal = -p.faces[c.bestFace].normal;
            const Vec3 pa = v[c.bestVertex];
            SupportFace pieceFaceB;
            pieceFace(p, c.bestFace, pieceFaceB);
            SupportFace triangle;
            triangleFace(v, n, normal, triangle);
            buildFaceManifold(b, b, normal, pa, pa + normal * c.polytopeSeparation, margin, m, 2, realized, &triangle, &pieceFaceB);
            if (!realized && onlyStandIn(pa, pa + normal * c.polytopeSeparation)) return false;
            if (c.edgeBetter && m.pointCount == 0) c.axis = Axis::Edges;
            if (c.axis != Axis::Edges) {
                m.normal = p.rotation * m.normal;
                for (std::uint32_t i = 0; i < m.pointCount; ++i) m.points[i].position = pieceToWorld(p, m.points[i].position);
            }
            break;
        }
        case Axis::Edges: break;
    }
    if (c.axis == Axis::Edges) {
        const PolytopeEdge& edge = p.edges[c.bestEdge];
        const std::uint32_t j = c.bestTriangleEdge, k = (j + 1) % 3;
        Real s = c.edgeParameter;
        if (!c.edgeParameterKnown) {
            Real u;
            closestSegmentSegment(v[j], v[k], p.vertices[edge.from], p.vertices[edge.to], s, u);
        }
        // The point on the triangle's edge, and the polytope's surface
        // along the axis from it: the edges' closest points when the two
        // edges cross (seen along the axis). When they do not (shapes
        // apart, their nearest features a vertex and an edge), the point
        // stays on the triangle's edge, where the mesh path looks for the
        // feature it touches, and the depth is the axis's separation, a
        // lower bound of the distance. The parameter is the polytope
        // frame's, the point the world triangle's.
        const Vec3 normal = p.rotation * c.bestEdgeAxis;
        const Vec3 pa = w[j] + (w[k] - w[j]) * s;
        m.normal = normal;
        m.pointCount = 0;
        addContact(m, pa, pa + normal * c.edgeSeparation, -c.edgeSeparation, edgeFeature(c.bestTriangleEdge, c.bestEdge), margin);
    }
    return m.pointCount > 0;
}

// What the cached axis gives at this pose.
// The polytope's lowest vertex along n, the first of equals (its support
// along -n), as the full test's scan finds it; `lo` gets its height.
std::uint32_t lowestVertexAlong(const TrianglePolytope& p, const Vec3& n, Real& lo) {
    lo = dot(n, p.vertices[0]);
    std::uint32_t lowest = 0;
    for (std::uint32_t i = 1; i < p.vertexCount; ++i) {
        const Real d = dot(n, p.vertices[i]);
        if (d < lo) {
            lo = d;
            lowest = i;
        }
    }
    return lowest;
}

enum class CachedAxis { Invalid, Apart, Valid };
CachedAxis cachedAxisSeparation(std::uint32_t code, const TrianglePolytope& p, const Vec3 v[3], const Vec3& n, Real margin,
                                Choice& c) {
    const std::uint32_t index = code & kAxisHintIndex;
    const std::uint32_t kind = code & ~kAxisHintIndex;
    if (kind == kTriangleFaceAxis) {
        Real lo;
        const std::uint32_t lowest = lowestVertexAlong(p, n, lo);
        c.axis = Axis::TriangleFace;
        c.lowest = lowest;
        c.faceSeparation = c.separation = lo - dot(n, v[0]);
    } else if (kind == kFaceAxisHint) {
        if (index >= p.faceCount) return CachedAxis::Invalid;
        c.axis = Axis::PolytopeFace;
        c.bestFace = index;
        c.polytopeSeparation = c.separation = faceAxisSeparation(p, index, v, c.bestVertex);
    } else if (kind == kEdgeAxisHint) {
        const std::uint32_t e = index / 3, j = index % 3;
        if (e >= p.edgeCount) return CachedAxis::Invalid;
        const Vec3 t = v[(j + 1) % 3] - v[j];
        const Vec3 side = cross(t, n);
        const PolytopeEdge& edge = p.edges[e];
        const Vec3 a = p.faces[edge.faces[0]].normal, cn = p.faces[edge.faces[1]].normal;
        if (!edgePairAxis(a, cn, dot(a, t), dot(cn, t), side, dot(t, t), c.bestEdgeAxis)) return CachedAxis::Invalid;
        c.axis = Axis::Edges;
        c.bestEdge = e;
        c.bestTriangleEdge = j;
        c.edgeSeparation = c.separation = dot(c.bestEdgeAxis, p.vertices[edge.from] - v[j]);
    } else {
        return CachedAxis::Invalid;
    }
    return c.separation > margin ? CachedAxis::Apart : CachedAxis::Valid;
}

// The cache's code of the axis a contact took.
std::uint32_t axisCode(const Choice& c) {
    switch (c.axis) {
        case Axis::TriangleFace: return kTriangleFaceAxis;
        case Axis::PolytopeFace: return kFaceAxisHint | c.bestFace;
        case Axis::Edges: return c.bestEdge <= kAxisHintIndex / 3 ? kEdgeAxisHint | (3 * c.bestEdge + c.bestTriangleEdge) : 0u;
        case Axis::BackFace: break;
    }
    return 0;
}

}  // namespace

bool collideTrianglePolytope(const Vec3 w[3], const Vec3& faceN, const TrianglePolytope& p, Real margin, Manifold& m,
                             std::uint32_t* axisHint, TriangleAxisEntry* cached) {
    // In the polytope's frame: its vertices and face planes as stored.
    Vec3 v[3], n;
    toPieceFrame(p, w, faceN, v, n);
    Choice ch;
    // The contact's cached axis (TriangleAxisCache, manifold.hpp): the axis
    // the full test chose when it last ran for this pair, taken again alone
    // while its separation is within kAxisCacheTolerance of what it was then
    // and it still gives a point. Beyond the margin along it, the pair is
    // apart whatever the other axes say.
    const std::uint32_t cachedAxis = cached != nullptr ? cached->axis : 0u;
    if (cachedAxis != 0) {
        switch (cachedAxisSeparation(cachedAxis, p, v, n, margin, ch)) {
            case CachedAxis::Apart:
                cached->axis = 0;
                return false;
            case CachedAxis::Valid:
                if (std::fabs(ch.separation - cached->separation) < kAxisCacheTolerance) {
                    ch.realized = ch.separation <= 0 || axisRealized(ch, p, v);
                    if (buildAlong(ch, w, faceN, v, n, p, margin, m)) return true;
                    m = Manifold{};
                }
                break;
            case CachedAxis::Invalid: break;
        }
        ch = Choice{};
    }
    if (cached != nullptr) cached->axis = 0;

    // The axis that rejected the pair last time: a piece resting or rolling
    // slowly beside a triangle is still beyond the margin along it. It comes
    // after the contact's cached axis, never before: the hint table is a
    // worker's (SeparatingAxisCache), shared by every piece of the same hull
    // over the triangle, so what it holds depends on which contacts the
    // worker collided before. Tried first, a hint that rejected the pair
    // kept the contact's cached axis alive where the cached axis alone would
    // have given a point or been dropped, and the result followed the
    // thread count (two copies of one world at three threads parted, about
    // one run in thirty). Here its rejection is the full test's own answer,
    // the cached axis already cleared as the full test clears it.
    std::uint32_t unusedHint = 0;
    std::uint32_t& hint = axisHint != nullptr ? *axisHint : unusedHint;
    if (hint != 0 && hintSeparates(hint, p, v, n, margin)) return false;
    hint = 0;

    // The triangle's normal, both ways: one pass over the vertices.
    const Real plane = dot(n, v[0]);
    Real lo = dot(n, p.vertices[0]), hi = lo;
    std::uint32_t lowest = 0;
    for (std::uint32_t i = 1; i < p.vertexCount; ++i) {
        const Real d = dot(n, p.vertices[i]);
        if (d < lo) {
            lo = d;
            lowest = i;
        }
        hi = std::max(hi, d);
    }
    const Real faceSeparation = lo - plane, backSeparation = plane - hi;
    if (faceSeparation > margin || backSeparation > margin) return false;

    // The polytope's faces (axis -normal, from the triangle to the polytope):
    // the triangle's lowest vertex under each face's plane.
    Real polytopeSeparation = -1e30f;
    std::uint32_t bestFace = 0, bestVertex = 0;
    for (std::uint32_t f = 0; f < p.faceCount; ++f) {
        std::uint32_t k;
        const Real separation = faceAxisSeparation(p, f, v, k);
        if (separation > margin) {
            hint = kFaceAxisHint | f;
            return false;
        }
        if (separation > polytopeSeparation) {
            polytopeSeparation = separation;
            bestFace = f;
            bestVertex = k;
        }
    }

    // Edge pairs that make a face of the Minkowski difference. For the
    // polytope's edge with face normals a and c and the triangle's edge t
    // (outward side direction s = t x n), the arc from a to c crosses the
    // great circle perpendicular to t where a.t and c.t change sign, at
    // mid = a + (c - a) (a.t) / (a.t - c.t): the polytope's outward
    // direction there. The axis from the triangle to the polytope is -mid,
    // which must point out of the triangle's edge (-mid . s > 0). Both
    // supports along it are then the two edges, so the separation is one dot.
    Vec3 t[3], side[3];
    Real tt[3];
    for (std::uint32_t j = 0; j < 3; ++j) {
        t[j] = v[(j + 1) % 3] - v[j];
        side[j] = cross(t[j], n);
        tt[j] = dot(t[j], t[j]);
    }
    Real edgeSeparation = -1e30f;
    std::uint32_t bestEdge = 0, bestTriangleEdge = 0;
    Vec3 bestEdgeAxis;
    // One edge pair's axis, from either loop below: true when it separates
    // the shapes by more than the margin (its index kept as the next call's
    // hint), else kept if it is the shallowest edge axis so far.
    const auto separatedByEdgeAxis = [&](std::uint32_t e, std::uint32_t j, const Vec3& axis) {
        const Real separation = dot(axis, p.vertices[p.edges[e].from] - v[j]);
        if (separation > margin) {
            if (e <= kAxisHintIndex / 3) hint = kEdgeAxisHint | (3 * e + j);
            return true;
        }
        if (separation > edgeSeparation) {
            edgeSeparation = separation;
            bestEdge = e;
            bestTriangleEdge = j;
            bestEdgeAxis = axis;
        }
        return false;
    };
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
    if (p.edgeLaneGroups != 0) {
        // Four polytope edges at a time (TrianglePolytope::edgeLanes): the
        // faces' dots with each triangle edge, ca and cc, in lanes, by
        // dot()'s products and sums in its order (the same bits), and the
        // Gauss-map filter as two signs: the arc from a to c crosses the
        // plane perpendicular to t (ca cc < 0), and on the side where -mid
        // points out of the triangle's edge. As mid = -(t x (a x c)) / (ca -
        // cc) and t . n = 0, mid . s = -(t . t) ((a x c) . n) / (ca - cc),
        // so the second sign is ca ((a x c) . n) > 0: one dot per edge
        // instead of mid per pair (Box3D's test). Where a triangle edge has
        // pairs both signs pass, edgePairAxis's further tests (not too near
        // parallel, the exact mid . s) and its axis -mid / |mid| run in the
        // lanes too, by its operations in its order (each product, sum,
        // quotient and square root rounded as the scalar one is: the same
        // bits); the pairs every test passes are then taken in the scalar
        // loop's order, edge-major, the triangle's edges within, each
        // separation one dot. (One pair at a time, edgePairAxis and the
        // separation cost about 115 instructions a pair, some 2.3 pairs a
        // group on trees100(10): the largest share of the test; branch
        // trees12.) The pair-at-a-time form (TrianglePolytope::
        // edgePairsInLanes false) is a separate instance, chosen once per
        // test, kept for the tests to compare against. True when an edge
        // pair separates the two by more than the margin.
        const auto laneEdgeStage = [&]<bool kPairsInLanes>() {
            static constexpr std::uint16_t kSpread[16] = {0x000, 0x001, 0x008, 0x009, 0x040, 0x041, 0x048, 0x049,
                                                          0x200, 0x201, 0x208, 0x209, 0x240, 0x241, 0x248, 0x249};
            const __m128 zero = _mm_setzero_ps();
            const __m128 signBit = _mm_set1_ps(-0.0f);
            const __m128 nx = _mm_set1_ps(n.x), ny = _mm_set1_ps(n.y), nz = _mm_set1_ps(n.z);
            __m128 tx[3], ty[3], tz[3], sx[3], sy[3], sz[3], parallel[3];
            for (std::uint32_t j = 0; j < 3; ++j) {
                tx[j] = _mm_set1_ps(t[j].x);
                ty[j] = _mm_set1_ps(t[j].y);
                tz[j] = _mm_set1_ps(t[j].z);
                sx[j] = _mm_set1_ps(side[j].x);
                sy[j] = _mm_set1_ps(side[j].y);
                sz[j] = _mm_set1_ps(side[j].z);
                parallel[j] = _mm_set1_ps(kParallelSine * kParallelSine * tt[j]);
            }
            // Per triangle edge j and lane: the pair's axis.
            alignas(16) float axisLanes[3][3][4];
            // The signs' ca and cc, when the pairs run edgePairAxis one at a time.
            alignas(16) float caLanes[3][4], ccLanes[3][4];
            for (std::uint32_t g = 0; g < p.edgeLaneGroups; ++g) {
                const float(*lanes)[4] = p.edgeLanes[g].v;
                const __m128 ax = _mm_load_ps(lanes[0]), ay = _mm_load_ps(lanes[1]), az = _mm_load_ps(lanes[2]);
                const __m128 cx = _mm_load_ps(lanes[3]), cy = _mm_load_ps(lanes[4]), cz = _mm_load_ps(lanes[5]);
                const __m128 en = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_load_ps(lanes[6]), nx), _mm_mul_ps(_mm_load_ps(lanes[7]), ny)),
                                             _mm_mul_ps(_mm_load_ps(lanes[8]), nz));
                unsigned pairs = 0;
                for (std::uint32_t j = 0; j < 3; ++j) {
                    const __m128 ca = _mm_add_ps(_mm_add_ps(_mm_mul_ps(ax, tx[j]), _mm_mul_ps(ay, ty[j])), _mm_mul_ps(az, tz[j]));
                    const __m128 cc = _mm_add_ps(_mm_add_ps(_mm_mul_ps(cx, tx[j]), _mm_mul_ps(cy, ty[j])), _mm_mul_ps(cz, tz[j]));
                    __m128 pass = _mm_and_ps(_mm_cmplt_ps(_mm_mul_ps(ca, cc), zero), _mm_cmpgt_ps(_mm_mul_ps(ca, en), zero));
                    if (_mm_movemask_ps(pass) == 0) continue;
                    if constexpr (!kPairsInLanes) {
                        _mm_store_ps(caLanes[j], ca);
                        _mm_store_ps(ccLanes[j], cc);
                        pairs |= unsigned(kSpread[_mm_movemask_ps(pass)]) << j;
                        continue;
                    }
                    // edgePairAxis: not parallel (!(max(ca ca, cc cc) < k^2 tt)),
                    // mid = a + (c - a) (ca / (ca - cc)), mid . s < 0, axis
                    // -mid / |mid| (zero when |mid| is not positive); the lanes
                    // that fail are never read. (max_ps and std::max part only
                    // on a NaN, whose lane the signs already failed.)
                    pass = _mm_and_ps(pass, _mm_cmpnlt_ps(_mm_max_ps(_mm_mul_ps(ca, ca), _mm_mul_ps(cc, cc)), parallel[j]));
                    const __m128 u = _mm_div_ps(ca, _mm_sub_ps(ca, cc));
                    const __m128 mx = _mm_add_ps(ax, _mm_mul_ps(_mm_sub_ps(cx, ax), u));
                    const __m128 my = _mm_add_ps(ay, _mm_mul_ps(_mm_sub_ps(cy, ay), u));
                    const __m128 mz = _mm_add_ps(az, _mm_mul_ps(_mm_sub_ps(cz, az), u));
                    const __m128 ms = _mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, sx[j]), _mm_mul_ps(my, sy[j])), _mm_mul_ps(mz, sz[j]));
                    pass = _mm_and_ps(pass, _mm_cmplt_ps(ms, zero));
                    pairs |= unsigned(kSpread[_mm_movemask_ps(pass)]) << j;
                    const __m128 length = _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(mx, mx), _mm_mul_ps(my, my)), _mm_mul_ps(mz, mz)));
                    const __m128 positive = _mm_cmpgt_ps(length, zero);
                    const __m128 axisX = _mm_xor_ps(_mm_and_ps(_mm_div_ps(mx, length), positive), signBit);
                    const __m128 axisY = _mm_xor_ps(_mm_and_ps(_mm_div_ps(my, length), positive), signBit);
                    const __m128 axisZ = _mm_xor_ps(_mm_and_ps(_mm_div_ps(mz, length), positive), signBit);
                    _mm_store_ps(axisLanes[j][0], axisX);
                    _mm_store_ps(axisLanes[j][1], axisY);
                    _mm_store_ps(axisLanes[j][2], axisZ);
                }
                while (pairs != 0) {
                    const unsigned bit = static_cast<unsigned>(std::countr_zero(pairs));
                    pairs &= pairs - 1;
                    const std::uint32_t i = (bit * 11u) >> 5, j = bit - 3 * i, e = 4 * g + i;  // bit = 3 i + j, i < 4
                    if constexpr (kPairsInLanes) {
                        const Vec3 axis{axisLanes[j][0][i], axisLanes[j][1][i], axisLanes[j][2][i]};
                        if (separatedByEdgeAxis(e, j, axis)) return true;
                        continue;
                    }
                    const PolytopeEdge& edge = p.edges[e];
                    Vec3 axis;
                    if (!edgePairAxis(p.faces[edge.faces[0]].normal, p.faces[edge.faces[1]].normal, caLanes[j][i], ccLanes[j][i],
                                      side[j], tt[j], axis)) {
                        continue;
                    }
                    if (separatedByEdgeAxis(e, j, axis)) return true;
                }
            }
            return false;
        };
        if (p.edgePairsInLanes ? laneEdgeStage.template operator()<true>() : laneEdgeStage.template operator()<false>()) return false;
    } else
#endif
    {
        // Each face normal's dot with each triangle edge, once: every edge of
        // the polytope reads the two of its faces (an edge per pair of faces
        // would compute them 2E / F >= 3 times over). The same dots as before,
        // so the same bits; a hull with more faces than the table computes them
        // per edge as before.
        Real faceDots[kMaxTabledFaces][3];
        const bool tabled = p.faceCount <= kMaxTabledFaces;
        if (tabled) {
            for (std::uint32_t f = 0; f < p.faceCount; ++f) {
                for (std::uint32_t j = 0; j < 3; ++j) faceDots[f][j] = dot(p.faces[f].normal, t[j]);
            }
        }
        for (std::uint32_t e = 0; e < p.edgeCount; ++e) {
            const PolytopeEdge& edge = p.edges[e];
            const Vec3& a = p.faces[edge.faces[0]].normal;
            const Vec3& c = p.faces[edge.faces[1]].normal;
            for (std::uint32_t j = 0; j < 3; ++j) {
                const Real ca = tabled ? faceDots[edge.faces[0]][j] : dot(a, t[j]);
                const Real cc = tabled ? faceDots[edge.faces[1]][j] : dot(c, t[j]);
                Vec3 axis;
                if (!edgePairAxis(a, c, ca, cc, side[j], tt[j], axis)) continue;
                if (separatedByEdgeAxis(e, j, axis)) return false;
            }
        }
    }

    ch.axis = Axis::TriangleFace;
    Real best = faceSeparation;
    if (backSeparation > best + kAxisBias) {
        ch.axis = Axis::BackFace;
        best = backSeparation;
    }
    if (polytopeSeparation > best + kAxisBias) {
        ch.axis = Axis::PolytopeFace;
        best = polytopeSeparation;
    }
    // Apart, the better axis is taken as it is: it is the nearer bound of the
    // distance, and nothing rests there to flip. The triangle's own normal
    // is what the mesh path keeps best (over the triangle, grouped with its
    // neighbours'); a polytope face against an edge pair takes the better of
    // the two, as the general path does.
    const Real edgeBias = ch.axis != Axis::TriangleFace || best > 0 || edgeSeparation > 0
                              ? kAxisBias
                              : kEdgeBias + kEdgeBiasRelative * std::fabs(best);
    ch.edgeBetter = edgeSeparation > best + kAxisBias;
    if (edgeSeparation > best + edgeBias) ch.axis = Axis::Edges;
    ch.faceSeparation = faceSeparation;
    ch.lowest = lowest;
    ch.bestFace = bestFace;
    ch.bestVertex = bestVertex;
    ch.polytopeSeparation = polytopeSeparation;
    ch.bestEdge = bestEdge;
    ch.bestTriangleEdge = bestTriangleEdge;
    ch.bestEdgeAxis = bestEdgeAxis;
    ch.edgeSeparation = edgeSeparation;

    // Apart, the best axis's separation is the distance only when the
    // features it names meet across it (axisRealized). Otherwise the shapes
    // are farther apart than it says. A face's clipped points are still
    // honest (each one's own gap along the normal), but the deepest-point
    // stand-in is not: a box's side face "0.2 mm" from a triangle passing
    // under the box's bottom edge caged a box resting on hills from both
    // sides, came and went, and the box never came to rest
    // (bench/heightfield.cpp). So, apart and not met, a face keeps its
    // clipped points only; a polytope face with none gives no contact (the
    // triangle's face: the mesh path keeps only points over the triangle
    // along its normal, which the stand-in is not). An edge pair that does
    // not cross keeps its point on the triangle's edge and the axis's
    // separation, a lower bound of the distance. (Handing every unmet axis
    // to the general path, GJK, made trees100(10) slower than the general
    // path alone: docs/benchmarks.md, "Mesh scenes".)
    ch.realized = !(std::max(best, edgeSeparation) > 0) || axisRealized(ch, p, v);
    if (!buildAlong(ch, w, faceN, v, n, p, margin, m)) return false;
    if (cached != nullptr) {
        cached->axis = axisCode(ch);
        cached->separation = ch.axis == Axis::Edges          ? edgeSeparation
                             : ch.axis == Axis::PolytopeFace ? polytopeSeparation
                                                            : faceSeparation;
    }
    return true;
}

bool collideTrianglePolytopeAlongFace(const Vec3 w[3], const Vec3& faceN, const TrianglePolytope& p, Real margin, Manifold& m) {
    Vec3 v[3], n;
    toPieceFrame(p, w, faceN, v, n);
    Real lo;
    const std::uint32_t lowest = lowestVertexAlong(p, n, lo);
    Choice c;
    c.axis = Axis::TriangleFace;
    c.lowest = lowest;
    c.faceSeparation = lo - dot(n, v[0]);
    if (c.faceSeparation > margin) return false;
    // Not the deepest point's contact: the clipped points, or the stand-in
    // when none is within the margin (as the rebuild always was).
    c.realized = false;
    return buildAlong(c, w, faceN, v, n, p, margin, m);
}

}  // namespace fulcrum::detail
