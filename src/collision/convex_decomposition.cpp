// Convex decomposition of a closed triangle mesh into a compound of convex
// hulls (docs/shapes.md, "Convex decomposition"), so a concave object can be a
// dynamic body. An approximate convex decomposition in the spirit of the
// V-HACD and CoACD papers (cut the solid where a concavity measure drops most,
// recurse), written for this engine and kept simple, bounded and
// deterministic:
//
// - A piece is the solid cut by an axis-aligned box B. Its convex hull is
//   exact without ever building the cut solid: the vertices of (solid ∩ B)
//   are the mesh triangles clipped to B (which include mesh vertices in B,
//   mesh edges crossing B's faces and B's edges crossing triangles) and B's
//   corners inside the solid (oriented crossings of a vertical ray).
// - How much solid a piece holds is estimated from a grid of vertical
//   columns: each column's inside intervals along y, found once by crossing
//   every triangle, are exact; across x and z the column stands for its cell.
//   The estimate is rescaled so the whole mesh gets its exact volume.
// - concavity(piece) = hull volume - solid volume. The piece with the largest
//   concavity is cut by the axis-aligned plane (through a mesh vertex's
//   coordinate, or at one of seven evenly spaced positions) that minimises
//   the sum of its halves' concavities, until every piece is within
//   maxConcavity x the mesh volume, no cut helps, or maxHulls is reached.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "collision/mesh_bvh.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

namespace {

using Triangle = std::array<std::uint32_t, 3>;

struct Box {
    Vec3 min, max;
};

// Where the vertical line through (x, z) crosses triangle a, b, c: the
// height, and +1 entering the solid going up (the front faces down), -1
// leaving, 0 for a miss. A point on an edge belongs to one side only (a
// half-open rule on the edge's direction), so a line through an edge shared
// by two triangles crosses the surface once; a vertical triangle is grazed.
struct Crossing {
    double y = 0;
    int sign = 0;
};
Crossing verticalCrossing(const Vec3& pa, const Vec3& pb, const Vec3& pc, double px, double pz) {
    double ax = pa.x, az = pa.z, bx = pb.x, bz = pb.z, cx = pc.x, cz = pc.z;
    const double area2 = (bx - ax) * (cz - az) - (bz - az) * (cx - ax);  // > 0: the normal's y < 0
    if (area2 == 0) return {};
    double ay = pa.y, by = pb.y, cy = pc.y;
    if (area2 < 0) std::swap(bx, cx), std::swap(bz, cz), std::swap(by, cy);
    const auto includes = [](double e, double dx, double dz) { return e > 0 || (e == 0 && (dz > 0 || (dz == 0 && dx > 0))); };
    // Edge functions of the counter-clockwise (in x-z) triangle a, b, c: the barycentric weights times the area.
    const double ea = (cx - bx) * (pz - bz) - (cz - bz) * (px - bx);
    const double eb = (ax - cx) * (pz - cz) - (az - cz) * (px - cx);
    const double ec = (bx - ax) * (pz - az) - (bz - az) * (px - ax);
    if (!includes(ea, cx - bx, cz - bz) || !includes(eb, ax - cx, az - cz) || !includes(ec, bx - ax, bz - az)) return {};
    return {(ea * ay + eb * by + ec * cy) / std::fabs(area2), area2 > 0 ? 1 : -1};
}

// The inside intervals of the vertical lines through the grid's cell centres.
class Columns {
public:
    Columns(std::span<const Vec3> v, std::span<const Triangle> tris, const AABB& bounds, int resolution) {
        const Real ex = bounds.max.x - bounds.min.x, ez = bounds.max.z - bounds.min.z;
        const Real longer = std::max(ex, ez);
        nx_ = std::max(1, static_cast<int>(std::ceil(static_cast<double>(resolution) * ex / longer)));
        nz_ = std::max(1, static_cast<int>(std::ceil(static_cast<double>(resolution) * ez / longer)));
        x0_ = bounds.min.x, z0_ = bounds.min.z;
        cx_ = double(ex) / nx_, cz_ = double(ez) / nz_;
        std::vector<std::vector<std::pair<double, int>>> crossings(std::size_t(nx_) * nz_);
        for (const Triangle& t : tris) cross(v[t[0]], v[t[1]], v[t[2]], crossings);
        offsets_.push_back(0);
        for (auto& list : crossings) {
            std::sort(list.begin(), list.end());
            int winding = 0;
            double start = 0;
            for (const auto& [y, sign] : list) {
                const int before = winding;
                winding += sign;
                if (before <= 0 && winding > 0) start = y;
                if (before > 0 && winding <= 0) intervals_.push_back({start, y});
            }
            offsets_.push_back(intervals_.size());
        }
    }

    // The solid's volume inside b: each column's length inside [b.min.y,
    // b.max.y] times the part of its cell inside b's x-z rectangle.
    double volumeIn(const Box& b) const {
        const int i0 = std::max(0, static_cast<int>(std::floor((b.min.x - x0_) / cx_)));
        const int i1 = std::min(nx_ - 1, static_cast<int>(std::floor((b.max.x - x0_) / cx_)));
        const int k0 = std::max(0, static_cast<int>(std::floor((b.min.z - z0_) / cz_)));
        const int k1 = std::min(nz_ - 1, static_cast<int>(std::floor((b.max.z - z0_) / cz_)));
        double volume = 0;
        for (int i = i0; i <= i1; ++i) {
            const double lo = x0_ + i * cx_, fx = overlap(lo, lo + cx_, b.min.x, b.max.x);
            if (fx <= 0) continue;
            for (int k = k0; k <= k1; ++k) {
                const double lz = z0_ + k * cz_, fz = overlap(lz, lz + cz_, b.min.z, b.max.z);
                if (fz <= 0) continue;
                const std::size_t c = std::size_t(i) * nz_ + k;
                double length = 0;
                for (std::size_t n = offsets_[c]; n < offsets_[c + 1]; ++n) {
                    length += std::max(0.0, std::min(intervals_[n].second, double(b.max.y)) -
                                                std::max(intervals_[n].first, double(b.min.y)));
                }
                volume += fx * fz * length;
            }
        }
        return volume;
    }

private:
    static double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }

    // Adds the triangle's crossing of every column line it covers.
    void cross(const Vec3& pa, const Vec3& pb, const Vec3& pc, std::vector<std::vector<std::pair<double, int>>>& out) const {
        const double lox = std::min({pa.x, pb.x, pc.x}), hix = std::max({pa.x, pb.x, pc.x});
        const double loz = std::min({pa.z, pb.z, pc.z}), hiz = std::max({pa.z, pb.z, pc.z});
        const int i0 = std::max(0, static_cast<int>(std::floor((lox - x0_) / cx_ - 0.5)));
        const int i1 = std::min(nx_ - 1, static_cast<int>(std::ceil((hix - x0_) / cx_ - 0.5)));
        const int k0 = std::max(0, static_cast<int>(std::floor((loz - z0_) / cz_ - 0.5)));
        const int k1 = std::min(nz_ - 1, static_cast<int>(std::ceil((hiz - z0_) / cz_ - 0.5)));
        for (int i = i0; i <= i1; ++i) {
            for (int k = k0; k <= k1; ++k) {
                const Crossing c = verticalCrossing(pa, pb, pc, x0_ + (i + 0.5) * cx_, z0_ + (k + 0.5) * cz_);
                if (c.sign != 0) out[std::size_t(i) * nz_ + k].push_back({c.y, c.sign});
            }
        }
    }

    int nx_ = 1, nz_ = 1;
    double x0_ = 0, z0_ = 0, cx_ = 1, cz_ = 1;
    std::vector<std::pair<double, double>> intervals_;
    std::vector<std::size_t> offsets_;
};

// Whether p is inside the closed mesh: the crossings of the vertical ray up
// from p, with their orientation (leaving minus entering), found through the BVH.
bool insideSolid(const TriangleMesh& mesh, const Vec3& p) {
    int winding = 0;
    const AABB ray{p, {p.x, mesh.bounds.max.y, p.z}};
    queryTriangles(mesh, ray, [&](std::uint32_t t) {
        const auto& tri = mesh.triangles[t];
        const Crossing c = verticalCrossing(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], p.x, p.z);
        if (c.sign != 0 && c.y > p.y) winding -= c.sign;
    });
    return winding > 0;
}

// The vertices of the piece: the closure of (interior of the solid ∩
// interior of b), see the file comment; sorted and unique. Cuts pass through
// mesh vertices' coordinates, so surface lying exactly in a face of b is
// common: it belongs to the piece only if the solid is inside b behind it,
// and a triangle that only touches b (along an edge or at a vertex) adds
// nothing, as a corner of b on the surface adds nothing.
std::vector<Vec3> pieceVertices(const TriangleMesh& mesh, const Box& b) {
    std::vector<Vec3> points, poly, next;
    const std::vector<Vec3>& v = mesh.vertices;
    queryTriangles(mesh, AABB{b.min, b.max}, [&](std::uint32_t index) {
        const Triangle& t = mesh.triangles[index];
        const Vec3 lo = min(min(v[t[0]], v[t[1]]), v[t[2]]), hi = max(max(v[t[0]], v[t[1]]), v[t[2]]);
        const Vec3 normal = cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]);
        bool outside = false;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (lo[axis] == hi[axis] && lo[axis] == b.min[axis]) outside = outside || normal[axis] > 0;
            if (lo[axis] == hi[axis] && lo[axis] == b.max[axis]) outside = outside || normal[axis] < 0;
        }
        if (outside) return;
        poly.assign({v[t[0]], v[t[1]], v[t[2]]});
        // Sutherland-Hodgman against the six faces; points on a face stay.
        for (std::size_t axis = 0; axis < 3 && !poly.empty(); ++axis) {
            for (int side = 0; side < 2 && !poly.empty(); ++side) {
                const Real bound = side == 0 ? b.min[axis] : b.max[axis];
                const auto inside = [&](const Vec3& p) { return side == 0 ? p[axis] >= bound : p[axis] <= bound; };
                next.clear();
                for (std::size_t i = 0; i < poly.size(); ++i) {
                    const Vec3& p = poly[i];
                    const Vec3& q = poly[(i + 1) % poly.size()];
                    if (inside(p)) next.push_back(p);
                    if (inside(p) != inside(q)) {
                        Vec3 x = lerp(p, q, (bound - p[axis]) / (q[axis] - p[axis]));
                        x[axis] = bound;  // exactly on the face, whatever the rounding
                        next.push_back(x);
                    }
                }
                poly.swap(next);
            }
        }
        if (poly.size() < 3) return;
        Vec3 area2;  // Newell: twice the polygon's vector area
        for (std::size_t i = 0; i < poly.size(); ++i) area2 += cross(poly[i], poly[(i + 1) % poly.size()]);
        if (length(area2) <= Real(1e-6) * length(normal)) return;  // only touches b
        points.insert(points.end(), poly.begin(), poly.end());
    });
    // A corner is in the piece when the solid fills b's octant there: tested
    // a little way inside b, off the surface the corner may lie on.
    const Vec3 step = (b.max - b.min) * Real(1e-5);
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner{(k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z};
        const Vec3 inward{(k & 1) ? -step.x : step.x, (k & 2) ? -step.y : step.y, (k & 4) ? -step.z : step.z};
        if (insideSolid(mesh, corner + inward)) points.push_back(corner);
    }
    const auto less = [](const Vec3& a, const Vec3& c) { return a.x != c.x ? a.x < c.x : (a.y != c.y ? a.y < c.y : a.z < c.z); };
    std::sort(points.begin(), points.end(), less);
    points.erase(std::unique(points.begin(), points.end()), points.end());
    return points;
}

struct Piece {
    Box box;
    Shape hull;                // valid when hullVolume > 0
    double hullVolume = 0;
    double solidVolume = 0;
    double concavity = 0;
    bool final = false;        // no cut reduces its concavity
};

class Decomposer {
public:
    Decomposer(const TriangleMesh& mesh, const Columns& columns, double volume, double solidScale)
        : mesh_(mesh), columns_(columns), volume_(volume), solidScale_(solidScale) {}

    Piece piece(const Box& b) const {
        Piece p;
        p.box = b;
        p.solidVolume = columns_.volumeIn(b) * solidScale_;
        const std::vector<Vec3> points = pieceVertices(mesh_, b);
        if (points.size() >= 4) {
            try {
                p.hull = Shape::convexHull(points);
                p.hullVolume = p.hull.volume();
            } catch (const Error& e) {
                // A sliver flat to the hull tolerance has no volume; a piece
                // with solid in it whose hull fails (over 4096 vertices) does.
                if (p.solidVolume > 1e-6 * volume_) {
                    throw Error(std::string("convex_decomposition: a piece's hull: ") + e.what() +
                                " (simplify the mesh, or allow more hulls)");
                }
            }
        }
        p.concavity = std::max(0.0, p.hullVolume - p.solidVolume);
        return p;
    }

private:
    const TriangleMesh& mesh_;
    const Columns& columns_;
    double volume_;
    double solidScale_;
};

std::string num(double v) {
    std::string s = std::to_string(v);
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

}  // namespace

Shape Shape::convexDecomposition(std::span<const Vec3> vertices, std::span<const std::array<std::uint32_t, 3>> triangles,
                                 const ConvexDecompositionOptions& options) {
    const std::string who = "convex_decomposition: ";
    if (options.maxHulls < 1 || options.maxHulls > 1024) {
        throw Error(who + "options.maxHulls must be between 1 and 1024, got " + std::to_string(options.maxHulls));
    }
    if (!std::isfinite(options.maxConcavity) || options.maxConcavity < 0 || options.maxConcavity > 1) {
        throw Error(who + "options.maxConcavity must be between 0 and 1, got " + num(options.maxConcavity));
    }
    if (options.resolution < 4 || options.resolution > 512) {
        throw Error(who + "options.resolution must be between 4 and 512, got " + std::to_string(options.resolution));
    }
    // Shape::mesh validates the indices, finiteness and degenerate triangles and finds the neighbours.
    Shape surface;
    try {
        surface = Shape::mesh(vertices, triangles);
    } catch (const Error& e) {
        throw Error(who + e.what());
    }
    const TriangleMesh& mesh = surface.mesh();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (std::size_t k = 0; k < 3; ++k) {
            if (mesh.adjacency[t][k] == UINT32_MAX) {
                throw Error(who + "the mesh is not closed: edge " + std::to_string(k) + " of triangles[" + std::to_string(t) +
                            "] has no neighbour sharing it with the opposite winding; a decomposition needs a closed, "
                            "consistently wound surface");
            }
        }
    }
    double volume = 0;  // signed tetrahedra from the origin
    for (const Triangle& t : mesh.triangles) {
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        volume += (double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) - double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
                   double(a.z) * (double(b.x) * c.y - double(b.y) * c.x)) / 6;
    }
    const Vec3 extent = mesh.bounds.max - mesh.bounds.min;
    if (!(volume > 1e-9 * double(extent.x) * extent.y * extent.z)) {
        throw Error(who + "the mesh encloses no volume (" + num(volume) +
                    "): its triangles must be counter-clockwise seen from outside (this one may be inside out)");
    }

    const Columns columns(mesh.vertices, mesh.triangles, mesh.bounds, options.resolution);
    const Box whole{mesh.bounds.min, mesh.bounds.max};
    const double estimate = columns.volumeIn(whole);
    const Decomposer decomposer(mesh, columns, volume, estimate > 0 ? volume / estimate : 1);
    const double enough = double(options.maxConcavity) * volume;

    std::vector<Piece> pieces{decomposer.piece(whole)};
    std::vector<Real> positions;
    for (;;) {
        // The most concave piece that may still be cut (the first of equals).
        std::size_t worst = pieces.size();
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            if (!pieces[i].final && pieces[i].concavity > enough && (worst == pieces.size() || pieces[i].concavity > pieces[worst].concavity)) {
                worst = i;
            }
        }
        if (worst == pieces.size() || pieces.size() >= static_cast<std::size_t>(options.maxHulls)) break;
        const Box b = pieces[worst].box;
        double bestCost = pieces[worst].concavity;
        Piece bestLow, bestHigh;
        bool found = false;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            const Real lo = b.min[axis], hi = b.max[axis], margin = (hi - lo) * Real(1e-3);
            // Cut candidates: mesh vertices' coordinates inside the piece (at
            // most 15, evenly picked), where a concave corner sits, and seven
            // evenly spaced positions, for curved surfaces.
            positions.clear();
            for (const Vec3& p : mesh.vertices) {
                if (p[axis] > lo + margin && p[axis] < hi - margin && p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y &&
                    p.y <= b.max.y && p.z >= b.min.z && p.z <= b.max.z) {
                    positions.push_back(p[axis]);
                }
            }
            std::sort(positions.begin(), positions.end());
            positions.erase(std::unique(positions.begin(), positions.end()), positions.end());
            if (positions.size() > 15) {
                std::vector<Real> picked;
                for (std::size_t k = 0; k < 15; ++k) picked.push_back(positions[(2 * k + 1) * positions.size() / 30]);
                positions.swap(picked);
            }
            for (int k = 1; k < 8; ++k) positions.push_back(lo + (hi - lo) * static_cast<Real>(k) / 8);
            for (const Real cut : positions) {
                Box low = b, high = b;
                low.max[axis] = cut;
                high.min[axis] = cut;
                Piece a = decomposer.piece(low), c = decomposer.piece(high);
                const double cost = a.concavity + c.concavity;
                if (cost < bestCost - 1e-9 * volume) {
                    bestCost = cost;
                    bestLow = std::move(a);
                    bestHigh = std::move(c);
                    found = true;
                }
            }
        }
        if (!found) {
            pieces[worst].final = true;
            continue;
        }
        // The halves take the piece's place, in order; empty ones vanish.
        std::vector<Piece> halves;
        if (bestLow.hullVolume > 0) halves.push_back(std::move(bestLow));
        if (bestHigh.hullVolume > 0) halves.push_back(std::move(bestHigh));
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(worst));
        pieces.insert(pieces.begin() + static_cast<std::ptrdiff_t>(worst), halves.begin(), halves.end());
    }

    std::vector<CompoundChild> children;
    for (const Piece& p : pieces) {
        if (p.hullVolume > 0) children.push_back({p.hull, Transform()});
    }
    if (children.empty()) throw Error(who + "internal: no piece of the mesh has volume");
    return Shape::compound(children);
}

}  // namespace fulcrum
