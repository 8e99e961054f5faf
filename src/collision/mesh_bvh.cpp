// Binned-SAH build of the mesh BVH, and its ray and closest-point queries.
#include "collision/mesh_bvh.hpp"

#include <algorithm>
#include <cmath>

namespace fulcrum {

namespace {

constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

class BvhBuilder {
public:
    BvhBuilder(const TriangleMesh& mesh, MeshBvh& bvh, MeshBvhBinning binning) : bvh_(bvh), binning_(binning) {
        const std::size_t n = mesh.triangles.size();
        centroids_.resize(n);
        bounds_.resize(n);
        bvh.triangleOrder.resize(n);
        for (std::uint32_t t = 0; t < n; ++t) {
            bounds_[t] = triangleBounds(mesh, t);
            centroids_[t] = bounds_[t].center();
            bvh.triangleOrder[t] = t;
        }
        bvh.nodes.reserve(2 * n);
    }

    // MeshBvh::slotBounds, once the order is final.
    void fillSlotBounds() {
        bvh_.slotBounds.resize(bvh_.triangleOrder.size());
        for (std::size_t i = 0; i < bvh_.triangleOrder.size(); ++i) bvh_.slotBounds[i] = bounds_[bvh_.triangleOrder[i]];
    }

    std::uint32_t build(std::uint32_t begin, std::uint32_t end, std::uint32_t depth) {
        bvh_.depth = std::max(bvh_.depth, depth);
        const auto nodeIndex = static_cast<std::uint32_t>(bvh_.nodes.size());
        bvh_.nodes.emplace_back();
        std::uint32_t* order = bvh_.triangleOrder.data();
        AABB box, centroidBox;
        for (std::uint32_t i = begin; i < end; ++i) {
            box.grow(bounds_[order[i]]);
            centroidBox.grow(centroids_[order[i]]);
        }
        bvh_.nodes[nodeIndex].bounds = box;
        const std::uint32_t count = end - begin;
        if (count <= MeshBvh::kMaxLeafTriangles) return makeLeaf(nodeIndex, begin, count);

        std::uint32_t mid = begin;
        if (depth < MeshBvh::kSahDepthLimit) mid = sahSplit(begin, end, box, centroidBox);
        if (mid == begin || mid == end) {
            // No useful SAH split (coincident centroids, or too deep): median on the widest axis.
            const int axis = maxAxis(centroidBox.max - centroidBox.min);
            mid = begin + count / 2;
            std::nth_element(order + begin, order + mid, order + end, [&](std::uint32_t a, std::uint32_t b) {
                const Real ca = centroids_[a][static_cast<std::size_t>(axis)];
                const Real cb = centroids_[b][static_cast<std::size_t>(axis)];
                return ca < cb || (ca == cb && a < b);
            });
        } else if (mid == end + 1) {
            return makeLeaf(nodeIndex, begin, count);  // SAH says a leaf is cheaper (small ranges only)
        }
        build(begin, mid, depth + 1);
        const std::uint32_t right = build(mid, end, depth + 1);
        bvh_.nodes[nodeIndex].index = right;
        bvh_.nodes[nodeIndex].count = 0;
        return nodeIndex;
    }

private:
    std::uint32_t makeLeaf(std::uint32_t node, std::uint32_t begin, std::uint32_t count) {
        bvh_.nodes[node].index = begin;
        bvh_.nodes[node].count = count;
        return node;
    }

    // Returns the partition point of the best SAH split, begin when none is
    // found, or end + 1 when a leaf is cheaper than any split.
    std::uint32_t sahSplit(std::uint32_t begin, std::uint32_t end, const AABB& box, const AABB& centroidBox) {
        constexpr std::uint32_t kBins = MeshBvh::kSahBins;
        std::uint32_t* order = bvh_.triangleOrder.data();
        Real bestCost = std::numeric_limits<Real>::max();
        int bestAxis = -1;
        std::uint32_t bestBin = 0;
        Bins bins;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            bins.lo[axis] = centroidBox.min[axis];
            const Real extent = centroidBox.max[axis] - bins.lo[axis];
            bins.used[axis] = extent > 0;
            if (bins.used[axis]) bins.scale[axis] = Real(kBins) / extent;
        }
        if (binning_ == MeshBvhBinning::AxesTogether) {
            binAxesTogether(begin, end, bins);
        } else {
            binAxisByAxis(begin, end, bins);
        }
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (!bins.used[axis]) continue;
            const std::array<AABB, kBins>& binBox = bins.box[axis];
            const std::array<std::uint32_t, kBins>& binCount = bins.count[axis];
            // Sweep from the right to get the right-hand areas, then from the left.
            std::array<Real, kBins> rightArea{};
            std::array<std::uint32_t, kBins> rightCount{};
            AABB acc;
            std::uint32_t n = 0;
            for (std::uint32_t b = kBins - 1; b > 0; --b) {
                acc.grow(binBox[b]);
                n += binCount[b];
                rightArea[b] = n ? acc.surfaceArea() : 0;
                rightCount[b] = n;
            }
            acc = AABB();
            n = 0;
            for (std::uint32_t b = 0; b + 1 < kBins; ++b) {
                acc.grow(binBox[b]);
                n += binCount[b];
                if (n == 0 || rightCount[b + 1] == 0) continue;
                const Real cost = acc.surfaceArea() * Real(n) + rightArea[b + 1] * Real(rightCount[b + 1]);
                if (cost < bestCost) { bestCost = cost; bestAxis = static_cast<int>(axis); bestBin = b; }
            }
        }
        if (bestAxis < 0) return begin;
        // Costs relative to the parent's area: traversal 1, triangle test 1.
        const Real leafCost = Real(end - begin);
        const Real splitCost = 1 + bestCost / std::max(box.surfaceArea(), std::numeric_limits<Real>::min());
        if (splitCost >= leafCost && end - begin <= 2 * MeshBvh::kMaxLeafTriangles) return end + 1;
        const auto axis = static_cast<std::size_t>(bestAxis);
        const Real lo = centroidBox.min[axis];
        const Real scale = Real(kBins) / (centroidBox.max[axis] - lo);
        std::uint32_t* midPtr = std::partition(order + begin, order + end, [&](std::uint32_t t) {
            return binOf(centroids_[t][axis], lo, scale) <= bestBin;
        });
        return static_cast<std::uint32_t>(midPtr - order);
    }

    // Each triangle's bounds grown into its centroid's bin on each axis with
    // extent: a bin's box is the min and max of the same boxes whichever loop
    // comes first, so both orders give the same bins, bit for bit.
    struct Bins {
        std::array<std::array<AABB, MeshBvh::kSahBins>, 3> box{};
        std::array<std::array<std::uint32_t, MeshBvh::kSahBins>, 3> count{};
        std::array<Real, 3> lo{}, scale{};
        std::array<bool, 3> used{};
    };
    // One pass over the range, each triangle's centroid and bounds read once
    // for the three axes (the build's largest cost on a large mesh).
    void binAxesTogether(std::uint32_t begin, std::uint32_t end, Bins& bins) const {
        const std::uint32_t* order = bvh_.triangleOrder.data();
        for (std::uint32_t i = begin; i < end; ++i) {
            const Vec3& c = centroids_[order[i]];
            const AABB& b = bounds_[order[i]];
            for (std::size_t axis = 0; axis < 3; ++axis) {
                if (!bins.used[axis]) continue;
                const std::uint32_t bin = binOf(c[axis], bins.lo[axis], bins.scale[axis]);
                bins.box[axis][bin].grow(b);
                ++bins.count[axis][bin];
            }
        }
    }
    // The reference: a pass over the range per axis.
    void binAxisByAxis(std::uint32_t begin, std::uint32_t end, Bins& bins) const {
        const std::uint32_t* order = bvh_.triangleOrder.data();
        for (std::size_t axis = 0; axis < 3; ++axis) {
            if (!bins.used[axis]) continue;
            for (std::uint32_t i = begin; i < end; ++i) {
                const std::uint32_t bin = binOf(centroids_[order[i]][axis], bins.lo[axis], bins.scale[axis]);
                bins.box[axis][bin].grow(bounds_[order[i]]);
                ++bins.count[axis][bin];
            }
        }
    }

    static std::uint32_t binOf(Real c, Real lo, Real scale) {
        const auto b = static_cast<std::int64_t>((c - lo) * scale);
        return static_cast<std::uint32_t>(std::clamp<std::int64_t>(b, 0, MeshBvh::kSahBins - 1));
    }

    MeshBvh& bvh_;
    MeshBvhBinning binning_;
    std::vector<Vec3> centroids_;
    std::vector<AABB> bounds_;
};

Real pointBoxDistanceSquared(const AABB& b, const Vec3& p) {
    const Vec3 q = max(b.min, min(p, b.max));
    return lengthSquared(p - q);
}

}  // namespace

Real rayBox(const AABB& b, const Vec3& p, const Vec3& invD, const std::array<bool, 3>& parallel, Real maxFraction) {
    Real tmin = 0, tmax = maxFraction;
    for (std::size_t i = 0; i < 3; ++i) {
        if (parallel[i]) {
            if (p[i] < b.min[i] || p[i] > b.max[i]) return -1;
            continue;
        }
        Real t1 = (b.min[i] - p[i]) * invD[i], t2 = (b.max[i] - p[i]) * invD[i];
        if (t1 > t2) std::swap(t1, t2);
        tmin = std::max(tmin, t1);
        tmax = std::min(tmax, t2);
        if (tmin > tmax) return -1;
    }
    return tmin;
}

MeshBvh buildMeshBvh(const TriangleMesh& mesh, MeshBvhBinning binning) {
    MeshBvh bvh;
    const std::size_t nt = mesh.triangles.size();
    bvh.triangleNormals.resize(nt);
    bvh.vertexNormals.assign(mesh.vertices.size(), Vec3::zero());
    for (std::size_t t = 0; t < nt; ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3 n = normalize(cross(mesh.vertices[tri[1]] - mesh.vertices[tri[0]], mesh.vertices[tri[2]] - mesh.vertices[tri[0]]));
        bvh.triangleNormals[t] = n;
        // Angle-weighted vertex pseudo-normals.
        for (std::size_t k = 0; k < 3; ++k) {
            const Vec3& v = mesh.vertices[tri[k]];
            const Vec3 e1 = normalize(mesh.vertices[tri[(k + 1) % 3]] - v);
            const Vec3 e2 = normalize(mesh.vertices[tri[(k + 2) % 3]] - v);
            const Real angle = dmath::acos(std::clamp(dot(e1, e2), Real(-1), Real(1)));
            bvh.vertexNormals[tri[k]] += n * angle;
        }
    }
    for (Vec3& n : bvh.vertexNormals) n = normalize(n);
    BvhBuilder builder(mesh, bvh, binning);
    builder.build(0, static_cast<std::uint32_t>(nt), 0);
    builder.fillSlotBounds();
    const Vec3 size = mesh.bounds.max - mesh.bounds.min;
    bvh.rayEpsilon = Real(1e-5) * (std::fabs(size.x) + std::fabs(size.y) + std::fabs(size.z));
    return bvh;
}

std::optional<Real> rayTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Vec3& d,
                                Real maxFraction) {
    const Vec3 e1 = b - a, e2 = c - a;
    const Vec3 pv = cross(d, e2);
    const Real det = dot(e1, pv);
    // Parallel (to float precision): the sine of the angle between the ray and
    // the plane is det / (|e1 x e2| |d|).
    if (std::fabs(det) <= Real(1e-7) * length(cross(e1, e2)) * length(d)) return std::nullopt;
    const Real inv = 1 / det;
    const Vec3 s = p - a;
    const Real u = dot(s, pv) * inv;
    if (u < 0 || u > 1) return std::nullopt;
    const Vec3 q = cross(s, e1);
    const Real v = dot(d, q) * inv;
    if (v < 0 || u + v > 1) return std::nullopt;
    const Real t = dot(e2, q) * inv;
    if (t < 0 || t > maxFraction) return std::nullopt;
    return t;
}

std::optional<MeshRayHit> rayCastMesh(const TriangleMesh& mesh, const Vec3& p, const Vec3& d, Real maxFraction) {
    const MeshBvh& bvh = *mesh.bvh;
    std::array<bool, 3> parallel{};
    Vec3 invD;
    for (std::size_t i = 0; i < 3; ++i) {
        parallel[i] = std::fabs(d[i]) < Real(1e-30);
        invD[i] = parallel[i] ? 0 : 1 / d[i];
    }
    Real best = maxFraction;
    std::uint32_t bestTriangle = kNoTriangle;
    std::array<std::uint32_t, MeshBvh::kStackSize> stack;
    std::uint32_t top = 0;
    if (rayBox(bvh.nodes[0].bounds.fattened(bvh.rayEpsilon), p, invD, parallel, best) >= 0) stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const MeshBvhNode& node = bvh.nodes[index];
        if (node.isLeaf()) {
            for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
                const std::uint32_t t = bvh.triangleOrder[i];
                const auto& tri = mesh.triangles[t];
                const auto hit = rayTriangle(mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], p, d, best);
                // Ties keep the lower triangle index, so the result does not depend on the tree.
                if (hit && (*hit < best || (*hit == best && t < bestTriangle))) { best = *hit; bestTriangle = t; }
            }
            continue;
        }
        // Visit the nearer child first; skip children entered beyond the best hit.
        const std::uint32_t left = index + 1, right = node.index;
        const Real tl = rayBox(bvh.nodes[left].bounds.fattened(bvh.rayEpsilon), p, invD, parallel, best);
        const Real tr = rayBox(bvh.nodes[right].bounds.fattened(bvh.rayEpsilon), p, invD, parallel, best);
        if (tl >= 0 && tr >= 0) {
            stack[top++] = tl <= tr ? right : left;
            stack[top++] = tl <= tr ? left : right;
        } else if (tl >= 0) {
            stack[top++] = left;
        } else if (tr >= 0) {
            stack[top++] = right;
        }
    }
    if (bestTriangle == kNoTriangle) return std::nullopt;
    const Vec3 n = bvh.triangleNormals[bestTriangle];
    return MeshRayHit{best, bestTriangle, dot(n, d) <= 0 ? n : -n};
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, TriangleFeature& feature) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) { feature = TriangleFeature::Vertex0; return a; }
    const Vec3 bp = p - b;
    const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) { feature = TriangleFeature::Vertex1; return b; }
    const Real vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        feature = TriangleFeature::Edge01;
        return a + ab * (d1 / (d1 - d3));
    }
    const Vec3 cp = p - c;
    const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) { feature = TriangleFeature::Vertex2; return c; }
    const Real vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        feature = TriangleFeature::Edge20;
        return a + ac * (d2 / (d2 - d6));
    }
    const Real va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        feature = TriangleFeature::Edge12;
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    feature = TriangleFeature::Face;
    const Real denom = 1 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

MeshClosestPoint closestPointOnMesh(const TriangleMesh& mesh, const Vec3& p) {
    const MeshBvh& bvh = *mesh.bvh;
    Real bestSq = std::numeric_limits<Real>::max();
    std::uint32_t bestTriangle = kNoTriangle;
    Vec3 bestPoint;
    TriangleFeature bestFeature = TriangleFeature::Face;
    std::array<std::uint32_t, MeshBvh::kStackSize> stack;
    std::uint32_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t index = stack[--top];
        const MeshBvhNode& node = bvh.nodes[index];
        if (pointBoxDistanceSquared(node.bounds, p) > bestSq) continue;
        if (node.isLeaf()) {
            for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
                const std::uint32_t t = bvh.triangleOrder[i];
                const auto& tri = mesh.triangles[t];
                TriangleFeature feature;
                const Vec3 q = closestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], feature);
                const Real dSq = lengthSquared(p - q);
                if (dSq < bestSq || (dSq == bestSq && t < bestTriangle)) {
                    bestSq = dSq; bestTriangle = t; bestPoint = q; bestFeature = feature;
                }
            }
            continue;
        }
        const std::uint32_t left = index + 1, right = node.index;
        const Real dl = pointBoxDistanceSquared(bvh.nodes[left].bounds, p);
        const Real dr = pointBoxDistanceSquared(bvh.nodes[right].bounds, p);
        stack[top++] = dl <= dr ? right : left;  // nearer child on top
        stack[top++] = dl <= dr ? left : right;
    }
    // The sign comes from the pseudo-normal of the feature the closest point is on.
    const auto& tri = mesh.triangles[bestTriangle];
    const auto& adj = mesh.adjacency[bestTriangle];
    const Vec3 faceNormal = bvh.triangleNormals[bestTriangle];
    auto edgeNormal = [&](std::size_t k) {
        return adj[k] == kNoTriangle ? faceNormal : normalize(faceNormal + bvh.triangleNormals[adj[k]]);
    };
    Vec3 pseudo = faceNormal;
    switch (bestFeature) {
        case TriangleFeature::Face: break;
        case TriangleFeature::Vertex0: pseudo = bvh.vertexNormals[tri[0]]; break;
        case TriangleFeature::Vertex1: pseudo = bvh.vertexNormals[tri[1]]; break;
        case TriangleFeature::Vertex2: pseudo = bvh.vertexNormals[tri[2]]; break;
        case TriangleFeature::Edge01: pseudo = edgeNormal(0); break;
        case TriangleFeature::Edge12: pseudo = edgeNormal(1); break;
        case TriangleFeature::Edge20: pseudo = edgeNormal(2); break;
    }
    if (lengthSquared(pseudo) == 0) pseudo = faceNormal;  // opposite normals cancelled (a folded sheet)
    MeshClosestPoint result;
    result.point = bestPoint;
    result.triangle = bestTriangle;
    const Vec3 delta = p - bestPoint;
    const Real dist = std::sqrt(bestSq);
    const Real sign = dot(delta, pseudo) >= 0 ? Real(1) : Real(-1);
    result.distance = sign * dist;
    result.normal = dist > 0 ? delta * (sign / dist) : pseudo;
    // A point numerically on the surface: the displacement's direction is noise.
    if (dist <= std::numeric_limits<Real>::epsilon() * (1 + length(p))) result.normal = pseudo;
    return result;
}

}  // namespace fulcrum
