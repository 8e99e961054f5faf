#pragma once
// Queries on a heightfield's cells through its min/max mip-map (the
// HeightField struct in include/fulcrum/shape.hpp; docs/terrain.md).
//
// Every query walks the mip-map depth first from the coarsest level that is
// still small for it: a box query starts at the level where its cell range
// spans at most 2 x 2 blocks, so its cost depends on the cells it covers, not
// on the field's size; a ray starts at the top and only descends into blocks
// its segment crosses. The visiting order is fixed (rows, then columns, of
// each block's children), so results never depend on anything but the input.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>

#include "collision/mesh_bvh.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum::detail {

// Shape-local bounds of block (row, column) of mip level `level`; a block of
// holes has min.y > max.y.
inline AABB heightFieldBlockBounds(const HeightField& hf, std::uint32_t level, std::uint32_t row, std::uint32_t column) {
    const HeightField::Level& l = hf.levels[level];
    const std::size_t at = std::size_t(row) * l.columns + column;
    const std::uint32_t c0 = column << level, r0 = row << level;
    const std::uint32_t c1 = std::min((column + 1) << level, hf.cellColumns());
    const std::uint32_t r1 = std::min((row + 1) << level, hf.cellRows());
    return {{static_cast<Real>(c0) * hf.spacingX, l.minY[at], static_cast<Real>(r0) * hf.spacingZ},
            {static_cast<Real>(c1) * hf.spacingX, l.maxY[at], static_cast<Real>(r1) * hf.spacingZ}};
}

// Visits the cells (index r * cellColumns + c, holes never) under blocks
// [r0, r1] x [c0, c1] of mip level `level` whose bounds pass test(AABB), and
// calls cell(index), which returns false to stop. Returns false when stopped.
template <class Test, class Cell>
bool visitHeightFieldCells(const HeightField& hf, std::uint32_t level, std::uint32_t r0, std::uint32_t r1, std::uint32_t c0,
                           std::uint32_t c1, Test&& test, Cell&& cell) {
    struct Block {
        std::uint32_t level, row, column;
    };
    // At most 4 start blocks, then each level replaces one block by at most 4.
    std::array<Block, 4 + 3 * 32> stack;
    std::uint32_t top = 0;
    for (std::uint32_t r = r1 + 1; r-- > r0;) {
        for (std::uint32_t c = c1 + 1; c-- > c0;) stack[top++] = {level, r, c};
    }
    while (top > 0) {
        const Block b = stack[--top];
        const AABB bounds = heightFieldBlockBounds(hf, b.level, b.row, b.column);
        if (bounds.min.y > bounds.max.y || !test(bounds)) continue;
        if (b.level == 0) {
            if (!cell(b.row * hf.cellColumns() + b.column)) return false;
            continue;
        }
        const HeightField::Level& below = hf.levels[b.level - 1];
        const std::uint32_t rEnd = std::min(2 * b.row + 2, below.rows), cEnd = std::min(2 * b.column + 2, below.columns);
        for (std::uint32_t r = rEnd; r-- > 2 * b.row;) {
            for (std::uint32_t c = cEnd; c-- > 2 * b.column;) stack[top++] = {b.level - 1, r, c};
        }
    }
    return true;
}

// Calls fn(triangleIndex) for every triangle (not in a hole) whose bounds
// overlap `box` (shape-local). fn may return void, or bool where false stops.
template <class Fn>
void forEachHeightFieldTriangle(const HeightField& hf, const AABB& box, Fn&& fn) {
    if (!overlaps(hf.bounds, box)) return;
    // The cell range, clamped in double so a huge box cannot overflow.
    const auto cellOf = [](Real v, Real spacing, std::uint32_t count) {
        const double f = std::floor(double(v) / double(spacing));
        return static_cast<std::uint32_t>(std::clamp(f, 0.0, double(count - 1)));
    };
    const std::uint32_t c0 = cellOf(box.min.x, hf.spacingX, hf.cellColumns()), c1 = cellOf(box.max.x, hf.spacingX, hf.cellColumns());
    const std::uint32_t r0 = cellOf(box.min.z, hf.spacingZ, hf.cellRows()), r1 = cellOf(box.max.z, hf.spacingZ, hf.cellRows());
    std::uint32_t level = 0;
    while (level + 1 < hf.levels.size() && ((c1 >> level) - (c0 >> level) > 1 || (r1 >> level) - (r0 >> level) > 1)) ++level;
    visitHeightFieldCells(
        hf, level, r0 >> level, r1 >> level, c0 >> level, c1 >> level, [&](const AABB& b) { return overlaps(b, box); },
        [&](std::uint32_t cell) {
            for (std::uint32_t t = 2 * cell; t < 2 * cell + 2; ++t) {
                Vec3 v[3];
                hf.triangle(t, v);
                AABB tb;
                tb.grow(v[0]), tb.grow(v[1]), tb.grow(v[2]);
                if (!overlaps(tb, box)) continue;
                if constexpr (std::is_same_v<std::invoke_result_t<Fn&, std::uint32_t>, bool>) {
                    if (!fn(t)) return false;
                } else {
                    fn(t);
                }
            }
            return true;
        });
}

// The surface height under shape-local (x, z): false outside the grid or
// over a hole.
bool heightFieldSurface(const HeightField& hf, Real x, Real z, Real& height);

// Closest hit of the ray p + t d, t in [0, maxFraction] (shape-local), with
// the field's triangles (both sides, as meshes: the normal faces the ray).
std::optional<MeshRayHit> rayCastHeightField(const HeightField& hf, const Vec3& p, const Vec3& d, Real maxFraction);

// The nearest point of the field's surface to p (shape-local); the distance
// is negative under the surface (inside the grid, not over a hole).
MeshClosestPoint closestPointOnHeightField(const HeightField& hf, const Vec3& p);

}  // namespace fulcrum::detail
