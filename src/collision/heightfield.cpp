// Shape::heightField: validation, convex-edge flags, the min/max mip-map;
// and the heightfield's ray cast, closest point and surface height.
//
// Internal edges: every triangle edge inside the field is shared by exactly
// one neighbour triangle, known from the grid (no adjacency search), and is
// flagged convex with the same rule as a mesh's (isConvexEdge, mesh.cpp). The
// field's rim and the rims of holes are boundaries, which may collide.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "collision/heightfield.hpp"

namespace fulcrum {

namespace {

constexpr Real kEmptyMin = std::numeric_limits<Real>::max();
constexpr Real kEmptyMax = -std::numeric_limits<Real>::max();

std::string number(double v) {
    std::string s = std::to_string(v);
    s.erase(s.find_last_not_of('0') + 1);
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

// Flags of triangle t (HeightField's layout): for each edge the far vertex of
// the neighbour across it, or none on the rim or next to a hole.
std::uint8_t triangleEdgeFlags(const HeightField& hf, std::uint32_t t) {
    const std::uint32_t cell = t >> 1, r = cell / hf.cellColumns(), c = cell % hf.cellColumns();
    Vec3 v[3];
    hf.triangle(t, v);
    const Vec3 n = normalize(cross(v[1] - v[0], v[2] - v[0]));
    // Per edge: the neighbouring cell (row, column) and the neighbour's far sample.
    struct Across {
        bool inside;
        std::uint32_t cellRow, cellColumn, farRow, farColumn;
    };
    const bool first = (t & 1u) == 0;
    const std::uint32_t lastRow = hf.cellRows() - 1, lastColumn = hf.cellColumns() - 1;
    Across across[3];
    if (first) {  // (r, c), (r + 1, c), (r + 1, c + 1)
        across[0] = {c > 0, r, c - 1, r, c - 1};            // x = c side: cell (r, c - 1)'s second triangle
        across[1] = {r < lastRow, r + 1, c, r + 2, c + 1};  // z = r + 1 side: cell (r + 1, c)'s second
        across[2] = {true, r, c, r, c + 1};                 // the diagonal: this cell's second
    } else {  // (r, c), (r + 1, c + 1), (r, c + 1)
        across[0] = {true, r, c, r + 1, c};                         // the diagonal: this cell's first
        across[1] = {c < lastColumn, r, c + 1, r + 1, c + 2};       // x = c + 1 side: cell (r, c + 1)'s first
        across[2] = {r > 0, r - 1, c, r - 1, c};                    // z = r side: cell (r - 1, c)'s first
    }
    std::uint8_t mask = 0;
    for (std::uint32_t k = 0; k < 3; ++k) {
        const Across& a = across[k];
        const bool boundary = !a.inside || hf.isHole(a.cellRow * hf.cellColumns() + a.cellColumn);
        if (boundary || isConvexEdge(n, v[k], v[(k + 1) % 3], hf.sample(a.farRow, a.farColumn))) {
            mask = static_cast<std::uint8_t>(mask | (1u << k));
        }
    }
    return mask;
}

void buildLevels(HeightField& hf) {
    HeightField::Level base;
    base.rows = hf.cellRows();
    base.columns = hf.cellColumns();
    const std::size_t cells = std::size_t(base.rows) * base.columns;
    base.minY.resize(cells);
    base.maxY.resize(cells);
    for (std::uint32_t r = 0; r < base.rows; ++r) {
        for (std::uint32_t c = 0; c < base.columns; ++c) {
            const std::size_t cell = std::size_t(r) * base.columns + c;
            if (hf.isHole(static_cast<std::uint32_t>(cell))) {
                base.minY[cell] = kEmptyMin;
                base.maxY[cell] = kEmptyMax;
                continue;
            }
            const Real h[4] = {hf.height(r, c), hf.height(r, c + 1), hf.height(r + 1, c), hf.height(r + 1, c + 1)};
            base.minY[cell] = std::min({h[0], h[1], h[2], h[3]});
            base.maxY[cell] = std::max({h[0], h[1], h[2], h[3]});
        }
    }
    hf.levels.push_back(std::move(base));
    while (hf.levels.back().rows > 1 || hf.levels.back().columns > 1) {
        const HeightField::Level& below = hf.levels.back();
        HeightField::Level up;
        up.rows = (below.rows + 1) / 2;
        up.columns = (below.columns + 1) / 2;
        up.minY.assign(std::size_t(up.rows) * up.columns, kEmptyMin);
        up.maxY.assign(std::size_t(up.rows) * up.columns, kEmptyMax);
        for (std::uint32_t r = 0; r < below.rows; ++r) {
            for (std::uint32_t c = 0; c < below.columns; ++c) {
                const std::size_t from = std::size_t(r) * below.columns + c, to = std::size_t(r / 2) * up.columns + c / 2;
                up.minY[to] = std::min(up.minY[to], below.minY[from]);
                up.maxY[to] = std::max(up.maxY[to], below.maxY[from]);
            }
        }
        hf.levels.push_back(std::move(up));
    }
}

}  // namespace

Shape Shape::heightField(std::uint32_t rows, std::uint32_t columns, Real spacingX, Real spacingZ,
                         std::span<const Real> heights, std::span<const std::uint32_t> holes) {
    const auto requireSamples = [](std::uint32_t n, const char* what) {
        if (n < 2 || n > kMaxHeightFieldSamples) {
            throw Error(std::string("heightfield: ") + what + " must be between 2 and " + std::to_string(kMaxHeightFieldSamples) +
                        ", got " + std::to_string(n));
        }
    };
    requireSamples(rows, "rows");
    requireSamples(columns, "columns");
    const auto requireSpacing = [](Real s, const char* what) {
        if (!std::isfinite(s) || !(s > 0)) {
            throw Error(std::string("heightfield: ") + what + " must be a positive finite number, got " + number(s));
        }
    };
    requireSpacing(spacingX, "spacing x");
    requireSpacing(spacingZ, "spacing z");
    if (!std::isfinite(spacingX * static_cast<Real>(columns - 1)) || !std::isfinite(spacingZ * static_cast<Real>(rows - 1))) {
        throw Error("heightfield: spacing times the number of cells overflows");
    }
    if (spacingX * static_cast<Real>(columns - 1) > kMaxShapeCoordinate || spacingZ * static_cast<Real>(rows - 1) > kMaxShapeCoordinate) {
        throw Error("heightfield: spacing times the number of cells is beyond the limit of 1e12 m (kMaxShapeCoordinate)");
    }
    const std::size_t samples = std::size_t(rows) * columns;
    if (heights.size() != samples) {
        throw Error("heightfield: heights has " + std::to_string(heights.size()) + " values, rows * columns = " +
                    std::to_string(rows) + " * " + std::to_string(columns) + " = " + std::to_string(samples));
    }
    for (std::size_t i = 0; i < samples; ++i) {
        if (!std::isfinite(heights[i])) {
            throw Error("heightfield: heights[" + std::to_string(i) + "] (row " + std::to_string(i / columns) + ", column " +
                        std::to_string(i % columns) + ") is not finite (NaN or infinity)");
        }
        if (std::abs(heights[i]) > kMaxShapeCoordinate) {
            throw Error("heightfield: heights[" + std::to_string(i) + "] is beyond the limit of 1e12 m (kMaxShapeCoordinate)");
        }
    }
    auto hf = std::make_shared<HeightField>();
    hf->rows = rows;
    hf->columns = columns;
    hf->spacingX = spacingX;
    hf->spacingZ = spacingZ;
    hf->heights.assign(heights.begin(), heights.end());
    const std::size_t cells = std::size_t(rows - 1) * (columns - 1);
    if (!holes.empty()) {
        hf->cellIsHole.assign(cells, 0);
        for (std::size_t i = 0; i < holes.size(); ++i) {
            if (holes[i] >= cells) {
                throw Error("heightfield: holes[" + std::to_string(i) + "] = " + std::to_string(holes[i]) +
                            " is not a cell index (the field has " + std::to_string(cells) + " cells)");
            }
            hf->cellIsHole[holes[i]] = 1;
        }
        for (std::uint32_t cell = 0; cell < cells; ++cell) {
            if (hf->cellIsHole[cell]) hf->holes.push_back(cell);
        }
        if (hf->holes.size() == cells) throw Error("heightfield: every cell is a hole");
    }
    const std::uint32_t triangles = static_cast<std::uint32_t>(2 * cells);
    hf->convexEdgeMask.resize(triangles);
    for (std::uint32_t t = 0; t < triangles; ++t) hf->convexEdgeMask[t] = triangleEdgeFlags(*hf, t);
    buildLevels(*hf);
    const HeightField::Level& top = hf->levels.back();
    hf->bounds = {{0, top.minY[0], 0},
                  {spacingX * static_cast<Real>(columns - 1), top.maxY[0], spacingZ * static_cast<Real>(rows - 1)}};
    Shape s;
    s.type_ = ShapeType::HeightField;
    s.radius_ = 0;
    s.heightField_ = std::move(hf);
    return s;
}

namespace detail {

bool heightFieldSurface(const HeightField& hf, Real x, Real z, Real& height) {
    const Real fx = x / hf.spacingX, fz = z / hf.spacingZ;
    if (!(fx >= 0 && fz >= 0 && fx <= static_cast<Real>(hf.cellColumns()) && fz <= static_cast<Real>(hf.cellRows()))) return false;
    const std::uint32_t c = std::min(static_cast<std::uint32_t>(fx), hf.cellColumns() - 1);
    const std::uint32_t r = std::min(static_cast<std::uint32_t>(fz), hf.cellRows() - 1);
    if (hf.isHole(r * hf.cellColumns() + c)) return false;
    const Real u = fx - static_cast<Real>(c), w = fz - static_cast<Real>(r);
    const Real h00 = hf.height(r, c), h01 = hf.height(r, c + 1), h10 = hf.height(r + 1, c), h11 = hf.height(r + 1, c + 1);
    // The diagonal from (r, c) to (r + 1, c + 1): the first triangle where w >= u.
    height = w >= u ? h00 + w * (h10 - h00) + u * (h11 - h10) : h00 + u * (h01 - h00) + w * (h11 - h01);
    return true;
}

std::optional<MeshRayHit> rayCastHeightField(const HeightField& hf, const Vec3& p, const Vec3& d, Real maxFraction) {
    std::array<bool, 3> parallel{};
    Vec3 invD;
    for (std::size_t i = 0; i < 3; ++i) {
        parallel[i] = std::fabs(d[i]) < Real(1e-30);
        invD[i] = parallel[i] ? 0 : 1 / d[i];
    }
    const Vec3 size = hf.bounds.max - hf.bounds.min;
    const Real epsilon = Real(1e-5) * (std::fabs(size.x) + std::fabs(size.y) + std::fabs(size.z));
    Real best = maxFraction;
    std::uint32_t bestTriangle = std::numeric_limits<std::uint32_t>::max();
    const std::uint32_t top = static_cast<std::uint32_t>(hf.levels.size() - 1);
    visitHeightFieldCells(
        hf, top, 0, hf.levels[top].rows - 1, 0, hf.levels[top].columns - 1,
        [&](const AABB& b) { return rayBox(b.fattened(epsilon), p, invD, parallel, best) >= 0; },
        [&](std::uint32_t cell) {
            for (std::uint32_t t = 2 * cell; t < 2 * cell + 2; ++t) {
                Vec3 v[3];
                hf.triangle(t, v);
                const auto hit = rayTriangle(v[0], v[1], v[2], p, d, best);
                if (hit && (*hit < best || (*hit == best && t < bestTriangle))) {
                    best = *hit;
                    bestTriangle = t;
                }
            }
            return true;
        });
    if (bestTriangle == std::numeric_limits<std::uint32_t>::max()) return std::nullopt;
    Vec3 v[3];
    hf.triangle(bestTriangle, v);
    const Vec3 n = normalize(cross(v[1] - v[0], v[2] - v[0]));
    return MeshRayHit{best, bestTriangle, dot(n, d) <= 0 ? n : -n};
}

MeshClosestPoint closestPointOnHeightField(const HeightField& hf, const Vec3& p) {
    // Search a box around p that grows until the best point found lies inside
    // it (a closer triangle would overlap the box), or the box holds the field.
    Real reach = std::max(hf.spacingX, hf.spacingZ);
    Real bestSq = std::numeric_limits<Real>::max();
    std::uint32_t bestTriangle = std::numeric_limits<std::uint32_t>::max();
    Vec3 bestPoint;
    for (;;) {
        const AABB box = AABB::fromCenterHalf(p, Vec3::splat(reach));
        forEachHeightFieldTriangle(hf, box, [&](std::uint32_t t) {
            Vec3 v[3];
            hf.triangle(t, v);
            TriangleFeature feature;
            const Vec3 q = closestPointOnTriangle(p, v[0], v[1], v[2], feature);
            const Real dSq = lengthSquared(p - q);
            if (dSq < bestSq || (dSq == bestSq && t < bestTriangle)) {
                bestSq = dSq;
                bestTriangle = t;
                bestPoint = q;
            }
        });
        const bool holdsField = box.min.x <= hf.bounds.min.x && box.min.y <= hf.bounds.min.y && box.min.z <= hf.bounds.min.z &&
                                box.max.x >= hf.bounds.max.x && box.max.y >= hf.bounds.max.y && box.max.z >= hf.bounds.max.z;
        if (bestSq <= reach * reach || holdsField || !std::isfinite(reach)) break;
        reach *= 4;
    }
    MeshClosestPoint result;
    if (bestTriangle == std::numeric_limits<std::uint32_t>::max()) {  // only for a non-finite p
        result.distance = std::numeric_limits<Real>::max();
        result.normal = {0, 1, 0};
        return result;
    }
    Vec3 v[3];
    hf.triangle(bestTriangle, v);
    const Vec3 faceNormal = normalize(cross(v[1] - v[0], v[2] - v[0]));
    Real surface = 0;
    const bool below = heightFieldSurface(hf, p.x, p.z, surface) && p.y < surface;
    const Real sign = below ? Real(-1) : Real(1);
    const Vec3 delta = p - bestPoint;
    const Real dist = std::sqrt(bestSq);
    result.point = bestPoint;
    result.triangle = bestTriangle;
    result.distance = sign * dist;
    result.normal = dist > std::numeric_limits<Real>::epsilon() * (1 + length(p)) ? delta * (sign / dist) : faceNormal;
    return result;
}

}  // namespace detail

}  // namespace fulcrum
