// Shape::convexHull: quickhull (Barber, Dobkin & Huhdanpaa 1996, "The
// Quickhull Algorithm for Convex Hulls"), organised the way Dirk Gregorius
// presents it in "Implementing Quickhull" (GDC 2014): an initial tetrahedron,
// one conflict list per face, the horizon found by a depth-first walk over the
// faces the eye point sees, and a fan of new faces from the horizon to the eye.
//
// Robustness choices (why):
// - Everything runs in double on coordinates re-centred on the cloud's bounds
//   centre. Inputs are float, so double predicates are ~1e9 times finer than
//   the input's own rounding and the topological decisions below never hinge
//   on a rounding error.
// - One distance tolerance `tol`, relative to the cloud's extent (see
//   hullTolerance): a point within tol of a face is "on" the hull and is never
//   added, a face is "visible" only when the eye is more than tol above it.
//   Duplicates, points on faces and edges, and nearly coplanar noise are
//   therefore absorbed instead of creating slivers.
// - Coplanar merging is a separate pass on the finished triangle hull: faces
//   are grown from the largest triangle over neighbours whose three vertices
//   lie within tol of the seed's plane (distance to one fixed plane, so the
//   merge cannot drift around a finely tessellated curved surface). A vertex
//   survives only if three or more merged faces meet at it; a vertex where only
//   two faces meet lies on their common edge (a point on a cube's edge) and is
//   dropped from both faces, which keeps the topology consistent (V-E+F = 2).
// - Mass properties by the divergence theorem over signed tetrahedra from an
//   interior reference point (Mirtich 1996, Eberly "Polyhedral Mass
//   Properties"), the covariance form of Blow & Binstock ("How to find the
//   inertia tensor (or other mass properties) of a 3D solid body represented by
//   a triangle mesh", 2004).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <vector>

#include "collision/support.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

namespace {

// Hulls larger than this are rejected: collision cost of SAT and support
// mapping grows with the vertex count, and a body with thousands of hull
// vertices is almost certainly an unsimplified render mesh.
constexpr std::size_t kMaxHullVertices = 4096;

struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double length(const D3& a) { return std::sqrt(dot(a, a)); }

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct Face {
    std::array<std::uint32_t, 3> v{};    // point indices, counter-clockwise seen from outside
    std::array<std::uint32_t, 3> nb{};   // neighbour across edge (v[i], v[i+1])
    D3 n;                                // outward unit normal
    double d = 0;                        // n . p = d on the face
    std::vector<std::uint32_t> conflict; // points more than tol above this face
    bool alive = true;
    bool visited = false;
};

struct HorizonEdge {
    std::uint32_t a, b;   // directed as in the removed (visible) face
    std::uint32_t outer;  // the face that stays, across the edge
};

class Quickhull {
public:
    Quickhull(std::vector<D3> pts, double tol) : p_(std::move(pts)), tol_(tol) {}

    // Returns false with `why` set when the cloud has no volume.
    bool build(std::string& why);
    const std::vector<Face>& faces() const { return faces_; }

private:
    double distance(const Face& f, std::uint32_t i) const { return dot(f.n, p_[i]) - f.d; }
    std::uint32_t addFace(std::uint32_t a, std::uint32_t b, std::uint32_t c);
    void assign(std::uint32_t point, const std::vector<std::uint32_t>& candidates);
    bool findHorizon(std::uint32_t start, std::uint32_t eye);
    void addPoint(std::uint32_t face, std::uint32_t eye);

    std::vector<D3> p_;
    double tol_;
    std::vector<Face> faces_;
    std::vector<std::uint32_t> pending_;  // faces that may have a non-empty conflict list
    std::vector<std::uint32_t> visible_;
    std::vector<HorizonEdge> horizon_;
    std::vector<std::uint32_t> newFaces_;

public:
    std::uint32_t droppedEyes_ = 0;  // diagnostics
};

std::uint32_t Quickhull::addFace(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    Face f;
    f.v = {a, b, c};
    f.nb = {kNone, kNone, kNone};
    const D3 n = cross(p_[b] - p_[a], p_[c] - p_[a]);
    const double len = length(n);
    f.n = len > 0 ? n * (1 / len) : D3{0, 0, 0};
    f.d = dot(f.n, (p_[a] + p_[b] + p_[c]) * (1.0 / 3.0));
    faces_.push_back(std::move(f));
    return static_cast<std::uint32_t>(faces_.size() - 1);
}

void Quickhull::assign(std::uint32_t point, const std::vector<std::uint32_t>& candidates) {
    double best = tol_;
    std::uint32_t bestFace = kNone;
    for (std::uint32_t f : candidates) {
        const double dist = distance(faces_[f], point);
        if (dist > best) { best = dist; bestFace = f; }
    }
    if (bestFace != kNone) faces_[bestFace].conflict.push_back(point);  // else: inside or on the hull, dropped
}

bool Quickhull::build(std::string& why) {
    const std::uint32_t n = static_cast<std::uint32_t>(p_.size());
    // Initial simplex: the two most distant of the six axis-extreme points,
    // then the point farthest from their line, then the farthest from that plane.
    std::array<std::uint32_t, 6> extreme{};
    for (std::uint32_t i = 1; i < n; ++i) {
        if (p_[i].x < p_[extreme[0]].x) extreme[0] = i;
        if (p_[i].x > p_[extreme[1]].x) extreme[1] = i;
        if (p_[i].y < p_[extreme[2]].y) extreme[2] = i;
        if (p_[i].y > p_[extreme[3]].y) extreme[3] = i;
        if (p_[i].z < p_[extreme[4]].z) extreme[4] = i;
        if (p_[i].z > p_[extreme[5]].z) extreme[5] = i;
    }
    std::uint32_t i0 = 0, i1 = 0;
    double best = -1;
    for (std::size_t a = 0; a < 6; ++a) {
        for (std::size_t b = a + 1; b < 6; ++b) {
            const D3 d = p_[extreme[b]] - p_[extreme[a]];
            if (dot(d, d) > best) { best = dot(d, d); i0 = extreme[a]; i1 = extreme[b]; }
        }
    }
    if (std::sqrt(best) <= tol_) { why = "points are coplanar (they all coincide); a hull needs volume"; return false; }
    const D3 axis = (p_[i1] - p_[i0]) * (1 / std::sqrt(best));
    std::uint32_t i2 = kNone;
    best = tol_;
    for (std::uint32_t i = 0; i < n; ++i) {
        const D3 d = p_[i] - p_[i0];
        const double dist = length(d - axis * dot(d, axis));
        if (dist > best) { best = dist; i2 = i; }
    }
    if (i2 == kNone) { why = "points are coplanar (they all lie on a line); a hull needs volume"; return false; }
    const D3 normal = [&] { const D3 c = cross(p_[i1] - p_[i0], p_[i2] - p_[i0]); return c * (1 / length(c)); }();
    std::uint32_t i3 = kNone;
    best = tol_;
    for (std::uint32_t i = 0; i < n; ++i) {
        const double dist = std::fabs(dot(normal, p_[i] - p_[i0]));
        if (dist > best) { best = dist; i3 = i; }
    }
    if (i3 == kNone) { why = "points are coplanar; a hull needs volume"; return false; }
    if (dot(normal, p_[i3] - p_[i0]) > 0) std::swap(i1, i2);  // the apex must lie behind face (i0, i1, i2)

    faces_.reserve(4 * std::size_t(n));
    const std::uint32_t f0 = addFace(i0, i1, i2), f1 = addFace(i0, i3, i1);
    const std::uint32_t f2 = addFace(i1, i3, i2), f3 = addFace(i2, i3, i0);
    // Neighbours by matching each directed edge with its reverse.
    for (std::uint32_t f : {f0, f1, f2, f3}) {
        for (std::size_t e = 0; e < 3; ++e) {
            const std::uint32_t a = faces_[f].v[e], b = faces_[f].v[(e + 1) % 3];
            for (std::uint32_t g : {f0, f1, f2, f3}) {
                for (std::size_t k = 0; k < 3; ++k) {
                    if (faces_[g].v[k] == b && faces_[g].v[(k + 1) % 3] == a) faces_[f].nb[e] = g;
                }
            }
        }
    }
    const std::vector<std::uint32_t> initial{f0, f1, f2, f3};
    for (std::uint32_t i = 0; i < n; ++i) {
        if (i != i0 && i != i1 && i != i2 && i != i3) assign(i, initial);
    }
    pending_ = initial;

    while (!pending_.empty()) {
        const std::uint32_t f = pending_.back();
        if (!faces_[f].alive || faces_[f].conflict.empty()) { pending_.pop_back(); continue; }
        // The eye is the conflict point farthest above the face: always a vertex
        // of the final hull.
        std::uint32_t eye = faces_[f].conflict[0];
        double far = distance(faces_[f], eye);
        for (std::uint32_t c : faces_[f].conflict) {
            const double dist = distance(faces_[f], c);
            if (dist > far) { far = dist; eye = c; }
        }
        addPoint(f, eye);
    }
    return true;
}

// Depth-first walk over the faces the eye sees; the horizon comes out as a
// closed loop of edges, counter-clockwise seen from the eye (Gregorius).
// Returns false if the walk does not produce a simple closed loop.
bool Quickhull::findHorizon(std::uint32_t start, std::uint32_t eye) {
    visible_.clear();
    horizon_.clear();
    struct Frame { std::uint32_t face; std::uint32_t edge; std::uint32_t step; };
    std::vector<Frame> stack;
    faces_[start].visited = true;
    visible_.push_back(start);
    stack.push_back({start, 0, 0});
    while (!stack.empty()) {
        Frame& fr = stack.back();
        if (fr.step == 3) { stack.pop_back(); continue; }
        const std::uint32_t e = (fr.edge + fr.step) % 3;
        ++fr.step;
        const Face& face = faces_[fr.face];
        const std::uint32_t nb = face.nb[e];
        if (faces_[nb].visited) continue;
        if (distance(faces_[nb], eye) > 0) {
            faces_[nb].visited = true;
            visible_.push_back(nb);
            // Continue in the neighbour just after the edge we crossed.
            std::uint32_t back = 0;
            while (faces_[nb].nb[back] != fr.face) ++back;
            stack.push_back({nb, (back + 1) % 3, 0});
        } else {
            horizon_.push_back({face.v[e], face.v[(e + 1) % 3], nb});
        }
    }
    if (horizon_.size() < 3) return false;
    for (std::size_t i = 0; i < horizon_.size(); ++i) {
        if (horizon_[i].b != horizon_[(i + 1) % horizon_.size()].a) return false;
    }
    // A vertex visited twice would make the new fan non-manifold.
    std::vector<std::uint32_t> starts;
    for (const HorizonEdge& h : horizon_) starts.push_back(h.a);
    std::sort(starts.begin(), starts.end());
    return std::adjacent_find(starts.begin(), starts.end()) == starts.end();
}

void Quickhull::addPoint(std::uint32_t face, std::uint32_t eye) {
    // Visibility is the exact predicate (eye strictly above the plane, in
    // double): with a positive tolerance here, an eye slightly above a nearly
    // coplanar neighbour that is declared hidden creates a new face folded
    // back over it (observed on noisy cube clouds). The exact predicate's own
    // weakness, an eye almost on the line of a horizon edge, yields a sliver
    // triangle of almost no area; mergeFaces absorbs those into a neighbour.
    const bool ok = findHorizon(face, eye);
    if (!ok) {
        // No simple horizon (never observed in double on the test clouds):
        // drop the eye rather than corrupt the mesh.
        for (std::uint32_t v : visible_) faces_[v].visited = false;
        auto& list = faces_[face].conflict;
        list.erase(std::find(list.begin(), list.end(), eye));
        ++droppedEyes_;
        return;
    }
    newFaces_.clear();
    for (const HorizonEdge& h : horizon_) {
        const std::uint32_t nf = addFace(h.a, h.b, eye);
        newFaces_.push_back(nf);
        faces_[nf].nb[0] = h.outer;
        Face& outer = faces_[h.outer];
        for (std::size_t k = 0; k < 3; ++k) {
            if (outer.v[k] == h.b && outer.v[(k + 1) % 3] == h.a) outer.nb[k] = nf;
        }
    }
    const std::size_t m = newFaces_.size();
    for (std::size_t i = 0; i < m; ++i) {
        faces_[newFaces_[i]].nb[1] = newFaces_[(i + 1) % m];
        faces_[newFaces_[i]].nb[2] = newFaces_[(i + m - 1) % m];
    }
    for (std::uint32_t v : visible_) {
        Face& dead = faces_[v];
        dead.alive = false;
        std::vector<std::uint32_t> orphans = std::move(dead.conflict);
        dead.conflict.clear();
        for (std::uint32_t c : orphans) {
            if (c != eye) assign(c, newFaces_);
        }
    }
    for (std::uint32_t nf : newFaces_) {
        if (!faces_[nf].conflict.empty()) pending_.push_back(nf);
    }
}

double hullTolerance(std::span<const Vec3> points, D3& center) {
    D3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    D3 hi = lo * -1.0;
    double maxAbs = 0;
    for (const Vec3& v : points) {
        lo = {std::min(lo.x, double(v.x)), std::min(lo.y, double(v.y)), std::min(lo.z, double(v.z))};
        hi = {std::max(hi.x, double(v.x)), std::max(hi.y, double(v.y)), std::max(hi.z, double(v.z))};
        maxAbs = std::max({maxAbs, std::fabs(double(v.x)), std::fabs(double(v.y)), std::fabs(double(v.z))});
    }
    center = (lo + hi) * 0.5;
    const D3 half = (hi - lo) * 0.5;
    // 2e-6 of the sum of half extents (a unit cube: 3e-6) absorbs coplanar
    // noise a few times larger than float rounding while still accepting a
    // plate 1e-5 times thinner than it is wide; far from the origin the
    // float resolution of the input itself dominates.
    return std::max(2e-6 * (half.x + half.y + half.z),
                    2.0 * double(std::numeric_limits<Real>::epsilon()) * maxAbs);
}

// A triangle of the finished quickhull, compacted.
struct Tri {
    std::array<std::uint32_t, 3> v;
    std::array<std::uint32_t, 3> nb;
    D3 n;
    double d;
    double area;
    bool sliver;  // narrower than the tolerance: its normal means nothing
};

// Merges coplanar triangles into polygons; returns false when some merged face
// degenerates (then the caller retries keeping every boundary vertex).
bool mergeFaces(const std::vector<Tri>& tris, const std::vector<D3>& p, double tol, bool dropEdgeVertices,
                std::vector<std::vector<std::uint32_t>>& polygons) {
    const std::size_t nt = tris.size();
    std::vector<std::uint32_t> order(nt);
    std::iota(order.begin(), order.end(), 0u);
    // Seeds: proper triangles by decreasing area, slivers last.
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        if (tris[a].sliver != tris[b].sliver) return !tris[a].sliver;
        return tris[a].area > tris[b].area;
    });
    std::vector<std::uint32_t> cluster(nt, kNone);
    std::uint32_t clusterCount = 0;
    std::vector<std::uint32_t> queue;
    std::vector<std::vector<std::uint32_t>> members;
    for (std::uint32_t seed : order) {
        if (cluster[seed] != kNone) continue;
        const std::uint32_t c = clusterCount++;
        members.emplace_back();
        const D3 n = tris[seed].n;
        const double d = tris[seed].d;
        cluster[seed] = c;
        queue.assign(1, seed);
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::uint32_t t = queue[q];
            members[c].push_back(t);
            for (std::uint32_t u : tris[t].nb) {
                if (cluster[u] != kNone || (!tris[u].sliver && dot(tris[u].n, n) <= 0)) continue;
                bool coplanar = true;
                for (std::uint32_t vi : tris[u].v) coplanar = coplanar && std::fabs(dot(n, p[vi]) - d) <= tol;
                if (coplanar) { cluster[u] = c; queue.push_back(u); }
            }
        }
    }
    // Boundary loop of each merged face; a face whose boundary is not one
    // simple loop is split back into its triangles.
    std::vector<std::vector<std::uint32_t>> loops(clusterCount);
    for (std::uint32_t c = 0; c < clusterCount; ++c) {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // (from, to)
        for (std::uint32_t t : members[c]) {
            for (std::size_t e = 0; e < 3; ++e) {
                if (cluster[tris[t].nb[e]] != c) edges.emplace_back(tris[t].v[e], tris[t].v[(e + 1) % 3]);
            }
        }
        std::sort(edges.begin(), edges.end());
        bool simple = std::adjacent_find(edges.begin(), edges.end(), [](const auto& a, const auto& b) { return a.first == b.first; }) == edges.end();
        std::vector<std::uint32_t> loop;
        if (simple) {
            std::uint32_t v = edges[0].first;
            for (std::size_t k = 0; k < edges.size(); ++k) {
                loop.push_back(v);
                auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(v, 0u));
                if (it == edges.end() || it->first != v) { simple = false; break; }
                v = it->second;
            }
            simple = simple && v == edges[0].first;
        }
        if (simple || members[c].size() == 1) {
            loops[c] = std::move(loop);
            continue;
        }
        // Split: the first triangle keeps id c, the others get new ids.
        for (std::size_t k = 0; k < members[c].size(); ++k) {
            const std::uint32_t t = members[c][k];
            std::uint32_t id = c;
            if (k > 0) {
                id = static_cast<std::uint32_t>(loops.size());
                loops.emplace_back();
            }
            cluster[t] = id;
            loops[id] = {tris[t].v[0], tris[t].v[1], tris[t].v[2]};
        }
    }
    // Number of distinct faces meeting at each vertex.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> incidence;
    for (std::uint32_t t = 0; t < nt; ++t) {
        for (std::uint32_t v : tris[t].v) incidence.emplace_back(v, cluster[t]);
    }
    std::sort(incidence.begin(), incidence.end());
    incidence.erase(std::unique(incidence.begin(), incidence.end()), incidence.end());
    std::vector<std::uint32_t> faceCount(p.size(), 0);
    for (const auto& [v, c] : incidence) ++faceCount[v];

    polygons.clear();
    for (const std::vector<std::uint32_t>& loop : loops) {
        std::vector<std::uint32_t> poly;
        for (std::uint32_t v : loop) {
            if (!dropEdgeVertices || faceCount[v] >= 3) poly.push_back(v);
        }
        if (poly.size() < 3) return false;
        polygons.push_back(std::move(poly));
    }
    return true;
}

std::string indexString(std::size_t i) { return std::to_string(i); }

}  // namespace

Shape Shape::convexHull(std::span<const Vec3> points) {
    if (points.size() < 4) {
        throw Error("convex_hull: needs at least 4 points, got " + std::to_string(points.size()));
    }
    if (points.size() > std::size_t(std::numeric_limits<std::uint32_t>::max() / 8)) {
        throw Error("convex_hull: too many points (" + std::to_string(points.size()) + ")");
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!isFinite(points[i])) throw Error("convex_hull: points[" + indexString(i) + "] is not finite (NaN or infinity)");
        if (maxComponent(abs(points[i])) > kMaxShapeCoordinate) {
            throw Error("convex_hull: points[" + indexString(i) + "] has a coordinate beyond the limit of 1e12 m (kMaxShapeCoordinate)");
        }
    }
    D3 center;
    const double tol = hullTolerance(points, center);
    std::vector<D3> p;
    p.reserve(points.size());
    for (const Vec3& v : points) p.push_back(D3{v.x, v.y, v.z} - center);

    Quickhull qh(p, tol);
    std::string why;
    if (!qh.build(why)) throw Error("convex_hull: " + why);

    // Compact the surviving triangles.
    const std::vector<Face>& faces = qh.faces();
    std::vector<std::uint32_t> remap(faces.size(), kNone);
    std::vector<Tri> tris;
    for (std::size_t f = 0; f < faces.size(); ++f) {
        if (!faces[f].alive) continue;
        remap[f] = static_cast<std::uint32_t>(tris.size());
        const Face& face = faces[f];
        const D3 &a = p[face.v[0]], &b = p[face.v[1]], &c = p[face.v[2]];
        const double area = 0.5 * length(cross(b - a, c - a));
        const double longest = std::max({length(b - a), length(c - b), length(a - c)});
        tris.push_back({face.v, face.nb, face.n, face.d, area, 2 * area <= tol * longest});
    }
    for (Tri& t : tris) {
        for (std::uint32_t& nb : t.nb) nb = remap[nb];
    }

    std::vector<std::vector<std::uint32_t>> polygons;
    if (!mergeFaces(tris, p, tol, true, polygons)) mergeFaces(tris, p, tol, false, polygons);

    // Unique hull vertices in order of first use.
    std::vector<std::uint32_t> vertexId(p.size(), kNone);
    std::vector<D3> verts;
    std::vector<std::uint32_t> vertexSource;  // each one's index in points
    for (auto& poly : polygons) {
        for (std::uint32_t& v : poly) {
            if (vertexId[v] == kNone) {
                vertexId[v] = static_cast<std::uint32_t>(verts.size());
                verts.push_back(p[v]);
                vertexSource.push_back(v);
            }
            v = vertexId[v];
        }
    }
    if (verts.size() > kMaxHullVertices) {
        throw Error("convex_hull: the hull has " + std::to_string(verts.size()) + " vertices, more than the limit of " +
                    std::to_string(kMaxHullVertices) + "; simplify the point cloud");
    }

    auto hull = std::make_shared<ConvexHull>();
    // The input points themselves: un-centring (p + center) gives them back
    // exactly only when Real is float; in the double build it may be off by an ulp.
    for (const std::uint32_t v : vertexSource) {
        hull->vertices.push_back(points[v]);
        hull->bounds.grow(hull->vertices.back());
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    // Mass properties about the mean vertex (inside the hull, so the signed
    // tetrahedra are mostly positive and cancellation is small).
    D3 ref;
    for (const D3& v : verts) ref = ref + v;
    ref = ref * (1.0 / double(verts.size()));
    double volume6 = 0;  // 6 x volume
    D3 firstMoment;      // sum of 6V_i * centroid_i * 4  (divided at the end)
    double cov[3][3] = {};
    for (const auto& poly : polygons) {
        // Newell's normal: the least-squares plane of a polygon whose vertices
        // are coplanar only within tolerance.
        D3 nn;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const D3& a = verts[poly[i]];
            const D3& b = verts[poly[(i + 1) % poly.size()]];
            nn = nn + D3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
        }
        nn = nn * (1 / length(nn));
        double offset = -std::numeric_limits<double>::max();
        for (std::uint32_t v : poly) offset = std::max(offset, dot(nn, verts[v]));
        HullFace hf;
        hf.normal = {static_cast<Real>(nn.x), static_cast<Real>(nn.y), static_cast<Real>(nn.z)};
        hf.offset = static_cast<Real>(offset + dot(nn, center));
        hf.firstIndex = static_cast<std::uint32_t>(hull->faceVertices.size());
        hf.indexCount = static_cast<std::uint32_t>(poly.size());
        hull->faces.push_back(hf);
        for (std::size_t i = 0; i < poly.size(); ++i) {
            hull->faceVertices.push_back(poly[i]);
            const std::uint32_t a = poly[i], b = poly[(i + 1) % poly.size()];
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
        // Signed tetrahedra (ref, v0, vi, vi+1) of the fan.
        const D3 a = verts[poly[0]] - ref;
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
            const D3 b = verts[poly[i]] - ref, c = verts[poly[i + 1]] - ref;
            const double det = dot(a, cross(b, c));  // 6 x signed volume
            volume6 += det;
            const D3 s = a + b + c;
            firstMoment = firstMoment + s * det;
            // Covariance of a tetrahedron with a vertex at the origin:
            // det/120 (a a^T + b b^T + c c^T + s s^T).
            const std::array<double, 3> av{a.x, a.y, a.z}, bv{b.x, b.y, b.z}, cv{c.x, c.y, c.z}, sv{s.x, s.y, s.z};
            for (std::size_t r = 0; r < 3; ++r) {
                for (std::size_t k = 0; k < 3; ++k) {
                    cov[r][k] += det / 120.0 * (av[r] * av[k] + bv[r] * bv[k] + cv[r] * cv[k] + sv[r] * sv[k]);
                }
            }
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& [a, b] : edges) hull->edges.push_back({a, b});
    detail::deriveHullTables(*hull);

    const double volume = volume6 / 6;
    if (!(volume > 0)) throw Error("convex_hull: points are coplanar; a hull needs volume");
    const D3 centroidRel = firstMoment * (1.0 / (4.0 * volume6));  // sum(V_i s_i/4) / V
    // Covariance about the centroid (parallel-axis), then I = tr(C) E - C.
    const std::array<double, 3> g{centroidRel.x, centroidRel.y, centroidRel.z};
    for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t k = 0; k < 3; ++k) cov[r][k] -= volume * g[r] * g[k];
    }
    const double tr = cov[0][0] + cov[1][1] + cov[2][2];
    auto inertia = [&](std::size_t r, std::size_t k) {
        return static_cast<Real>((r == k ? tr : 0.0) - cov[r][k]);
    };
    hull->unitDensityInertia = Mat3::fromRows({inertia(0, 0), inertia(0, 1), inertia(0, 2)},
                                              {inertia(1, 0), inertia(1, 1), inertia(1, 2)},
                                              {inertia(2, 0), inertia(2, 1), inertia(2, 2)});
    hull->volume = static_cast<Real>(volume);
    const D3 centroid = centroidRel + ref + center;
    hull->centroid = {static_cast<Real>(centroid.x), static_cast<Real>(centroid.y), static_cast<Real>(centroid.z)};

    Shape s;
    s.type_ = ShapeType::ConvexHull;
    s.radius_ = 0;
    s.hull_ = std::move(hull);
    return s;
}

}  // namespace fulcrum
