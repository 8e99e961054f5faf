#pragma once
// Box3D's own benchmark scenes (its shared/benchmarks.c), as engine-neutral
// descriptions: the parameters are transcribed (bodies, shapes, sizes,
// densities, step, sub-steps, sleep settings), the code is ours. Each engine
// builds the description its own way (bench/scenes.hpp's engines, the tests).
//
// convexPile: "a huge pile of large convexes, ported from PEEL". Every body is
// the convex hull of the same 32 points on a sphere of radius 2, drawn with a
// fixed linear congruential generator (state * 2147001325 + 715136305, seed
// 42; a coordinate is (state & 0xffff) / 65535 - 0.5, the point rejected when
// outside the ball of radius 0.5, then normalised and scaled by 2; float
// arithmetic, as in Box3D). 8 x 8 columns 4 m apart at x, z = (i - 4) * 4,
// 80 layers 4 m apart from y = 2; a static box of half extents 250 x 1 x 250
// centred at y = -1 (top face at y = 0). Density 1000, friction 0.6,
// restitution 0, sleeping on; 500 steps of 1/60 s with 4 sub-steps.
//
// box3dScenes() turns these descriptions into the harness's SceneSpecs
// (bench/scenes.hpp), with the rest of Box3D's suite that the shared
// description can hold: joint_grid, large_pyramid, many_pyramids. Every scene
// runs at Box3D's 1/60 s with 4 sub-steps. Masses follow Box3D's densities
// where the shape's volume is plain (boxes, spheres); a hull body gets mass 1
// (all dynamic bodies of a scene share one mass and the ground is static, so
// the motion does not depend on its value).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_scenes.hpp"
#include "scenes.hpp"

namespace bench {

struct HullPileSpec {
    std::string name;
    std::vector<V3> hullPoints;  // the one hull every dynamic body uses, in its body frame
    V3 groundHalf;               // static box
    V3 groundPosition;
    std::vector<V3> positions;   // the dynamic bodies' origins (identity orientation, at rest)
    double density = 1000;
    double friction = 0.6;
    double restitution = 0;
    bool sleeping = true;
    int steps = 500;
    double dt = 1.0 / 60;
    int substeps = 4;
    V3 gravity{0, -9.81, 0};
};

// The 32 points of the convex pile's hull (radius `amplitude`), in Box3D's order.
inline std::vector<V3> convexPileHullPoints(int pointCount = 32, float amplitude = 2.0f) {
    std::uint32_t state = 42;
    const auto coordinate = [&state] {
        state = state * 2147001325u + 715136305u;
        return static_cast<float>(state & 0xffffu) / 65535.0f - 0.5f;
    };
    std::vector<V3> points;
    points.reserve(static_cast<std::size_t>(pointCount));
    for (int i = 0; i < pointCount; ++i) {
        float x, y, z, length2;
        do {
            x = coordinate();
            y = coordinate();
            z = coordinate();
            length2 = x * x + y * y + z * z;
        } while (length2 > 0.25f);
        const float inverse = 1.0f / std::sqrt(length2);
        points.push_back({amplitude * (inverse * x), amplitude * (inverse * y), amplitude * (inverse * z)});
    }
    return points;
}

// Box3D's convex_pile: countX x countZ columns, `layers` layers (80 in Box3D's
// release benchmark, 10 in its debug one). Smaller piles keep the same hull,
// spacing and ground, for tests.
inline std::string convexPileName(int countX, int countZ, int layers) {
    return sizedName("convex_pile", countX == 8 && countZ == 8 && layers == 80,
                     std::to_string(countX) + "x" + std::to_string(countZ) + "x" + std::to_string(layers));
}
inline HullPileSpec convexPile(int countX = 8, int countZ = 8, int layers = 80) {
    HullPileSpec s;
    s.name = convexPileName(countX, countZ, layers);
    const double amplitude = 2, scatter = 2 * amplitude;
    s.hullPoints = convexPileHullPoints(32, static_cast<float>(amplitude));
    s.groundHalf = {250, 1, 250};
    s.groundPosition = {0, -1, 0};
    for (int layer = 0; layer < layers; ++layer) {
        for (int z = 0; z < countZ; ++z) {
            for (int x = 0; x < countX; ++x) {
                // Box3D's float expressions: (x - 0.5 countX) * scatter etc.
                const float px = (static_cast<float>(x) - 0.5f * static_cast<float>(countX)) * static_cast<float>(scatter);
                const float pz = (static_cast<float>(z) - 0.5f * static_cast<float>(countZ)) * static_cast<float>(scatter);
                const float py = static_cast<float>(amplitude) + 2.0f * static_cast<float>(amplitude) * static_cast<float>(layer);
                s.positions.push_back({px, py, pz});
            }
        }
    }
    return s;
}

// The harness's description of a hull pile (bench_benchmark_scenes --suite box3d).
inline SceneSpec hullPileScene(const HullPileSpec& pile) {
    SceneSpec s;
    s.name = pile.name;
    s.steps = pile.steps;
    s.dt = pile.dt;
    s.substeps = pile.substeps;
    s.gravity = pile.gravity;
    s.friction = pile.friction;
    s.sleeping = pile.sleeping;
    s.hullPoints = pile.hullPoints;
    BodySpec ground;
    ground.isStatic = true;
    ground.half = pile.groundHalf;
    ground.position = pile.groundPosition;
    s.bodies.push_back(ground);
    for (const V3& p : pile.positions) {
        BodySpec b;
        b.kind = BodySpec::Kind::Hull;
        b.position = p;
        s.bodies.push_back(b);
    }
    return s;
}
// Box3D's convex_pile as a harness scene.
inline SceneSpec convexPileScene(int countX, int countZ, int layers) { return hullPileScene(convexPile(countX, countZ, layers)); }

// Box3D's joint_grid: n x n spheres of radius 0.4 (density 1) 1 m apart in
// the x-y plane, column k at x = k, row i at y = -i; row 0 static; each sphere
// tied by a ball joint to the one above (anchor midway) and to the one on its
// left. Nothing collides (Box3D's filter: category 2, mask ~2). Sleeping off;
// 100 steps.
inline std::string jointGridName(int n) { return sizedName("joint_grid", n == 100, std::to_string(n)); }
inline SceneSpec jointGrid(int n = 100) {
    SceneSpec s;
    s.name = jointGridName(n);
    s.kind = SceneSpec::Kind::Jointed;
    s.steps = 100;
    s.substeps = 4;
    s.sleeping = false;
    s.bodyCollisions = false;
    const double radius = 0.4, density = 1;
    const double mass = density * 4.0 / 3.0 * 3.14159265358979323846 * radius * radius * radius;
    for (int k = 0; k < n; ++k) {
        for (int i = 0; i < n; ++i) {
            const int index = k * n + i;
            BodySpec b;
            b.kind = BodySpec::Kind::Sphere;
            b.half = {radius, radius, radius};
            b.position = {double(k), -double(i), 0};
            b.isStatic = i == 0;
            b.mass = mass;
            s.bodies.push_back(b);
            if (i > 0) s.joints.push_back({index - 1, index, {double(k), 0.5 - i, 0}});
            if (k > 0) s.joints.push_back({index - n, index, {k - 0.5, -double(i), 0}});
        }
    }
    return s;
}

// Box3D's pyramid of boxes (half extent `extent`, density 100) with `base`
// boxes in its bottom row, in the plane z = `z`: row i, box j (i <= j < base)
// at x = (i + 1) extent + 2 (j - i) extent + offsetX, y = (2 i + 1) extent.
inline void addBox3dPyramid(SceneSpec& s, int base, double extent, double offsetX, double z) {
    const double mass = 100 * 8 * extent * extent * extent;
    for (int i = 0; i < base; ++i) {
        const double y = (2.0 * i + 1.0) * extent;
        for (int j = i; j < base; ++j) {
            BodySpec b;
            b.half = {extent, extent, extent};
            b.position = {(i + 1.0) * extent + 2.0 * (j - i) * extent + offsetX, y, z};
            b.mass = mass;
            s.bodies.push_back(b);
        }
    }
}

inline void addBox3dGround(SceneSpec& s, double halfExtent) {
    BodySpec g;
    g.isStatic = true;
    g.half = {halfExtent, 1, halfExtent};
    g.position = {0, -1, 0};
    s.bodies.push_back(g);
}

// Box3D's large_pyramid: one pyramid with 100 boxes at its base (5050 boxes),
// ground 800 x 800 m; sleeping off; 200 steps. Quality: it stands.
inline std::string largePyramidName(int base) { return sizedName("large_pyramid", base == 100, std::to_string(base)); }
inline SceneSpec largePyramid(int base = 100) {
    SceneSpec s;
    s.name = largePyramidName(base);
    s.steps = 200;
    s.substeps = 4;
    s.sleeping = false;
    s.pyramid = true;
    addBox3dGround(s, 400);
    addBox3dPyramid(s, base, 0.5, -0.5 * base, 0);  // Box3D's offset: -h base
    s.topIndex = static_cast<int>(s.bodies.size()) - 1;
    return s;
}

// Box3D's many_pyramids: rows x columns pyramids of 10-box bases (55 boxes
// each; 14 x 14 = 10,780 boxes), spread over a ground of half extent
// 0.5 * columns * 11; bodies never sleep; 100 steps.
inline std::string manyPyramidsName(int rows, int columns) {
    return sizedName("many_pyramids", rows == 14 && columns == 14, std::to_string(rows) + "x" + std::to_string(columns));
}
inline SceneSpec manyPyramids(int rows = 14, int columns = 14) {
    SceneSpec s;
    s.name = manyPyramidsName(rows, columns);
    s.steps = 100;
    s.substeps = 4;
    s.sleeping = false;
    s.pyramid = true;
    const int base = 10;
    const double extent = 0.5;
    const double groundExtent = extent * columns * (base + 1.0);
    addBox3dGround(s, groundExtent);
    const double baseWidth = 2 * extent * base;
    double z = -groundExtent + 2 * extent;
    const double deltaZ = rows > 1 ? 2 * (groundExtent - 2 * extent) / (rows - 1.0) : 0;
    for (int i = 0; i < rows; ++i) {
        for (int j = 0; j < columns; ++j) {
            const double centerX = -groundExtent + j * (baseWidth + 2 * extent) + 2 * extent;
            addBox3dPyramid(s, base, extent, centerX - 0.5, z);
        }
        z += deltaZ;
    }
    s.topIndex = static_cast<int>(s.bodies.size()) - 1;
    return s;
}

// Jolt's PerformanceTest "Pyramid" (its PyramidScene.h): boxes of half
// extent 1 with no convex radius, 15 layers; layer i is a square of n x n
// boxes, n = 15 - floor(i / 2) - floor((i + 1) / 2) (1240 boxes in all): j, k
// from floor(i / 2) to 15 - floor((i + 1) / 2) - 1, at
// (-15 + 2 j + (i odd ? 1 : 0), 1 + 2.5 i, -15 + 2 k + (i odd ? 1 : 0)),
// so each layer starts 0.5 m above the one below and drops onto it; a
// static floor box of half extents (50, 1, 50) centred at y = -1. Sleeping
// off; 500 steps of 1/60 s (Jolt: one collision step, its own iterations;
// here each engine's default sub-steps). Quality: the deepest overlap.
inline std::string joltPyramidName(int height) { return sizedName("jolt_pyramid", height == 15, std::to_string(height)); }
inline SceneSpec joltPyramid(int height = 15) {
    SceneSpec s;
    s.name = joltPyramidName(height);
    s.steps = 500;
    s.sleeping = false;
    BodySpec floor;
    floor.isStatic = true;
    floor.half = {50, 1, 50};
    floor.position = {0, -1, 0};
    s.bodies.push_back(floor);
    const double size = 2, separation = 0.5, half = 0.5 * size;
    for (int i = 0; i < height; ++i) {
        const double shift = (i & 1) != 0 ? half : 0.0;
        for (int j = i / 2; j < height - (i + 1) / 2; ++j) {
            for (int k = i / 2; k < height - (i + 1) / 2; ++k) {
                BodySpec b;
                b.half = {half, half, half};
                b.mass = 8 * half * half * half * 1000;  // Jolt's default density, 1000 kg/m^3
                b.position = {-height + size * j + shift, 1 + (size + separation) * i, -height + size * k + shift};
                s.bodies.push_back(b);
            }
        }
    }
    return s;
}

// The part of Box3D's suite the harness runs (--suite box3d). Its rain,
// washer and large_world are in bench/churn_scenes.hpp (--suite churn).
inline std::vector<LazyScene> box3dScenes(bool quick) {
    std::vector<LazyScene> scenes =
        quick ? std::vector<LazyScene>{lazyScene<jointGrid, jointGridName>(30), lazyScene<largePyramid, largePyramidName>(40),
                                       lazyScene<manyPyramids, manyPyramidsName>(4, 4),
                                       lazyScene<convexPileScene, convexPileName>(4, 4, 20)}
              : std::vector<LazyScene>{lazyScene<jointGrid, jointGridName>(100), lazyScene<largePyramid, largePyramidName>(100),
                                       lazyScene<manyPyramids, manyPyramidsName>(14, 14),
                                       lazyScene<convexPileScene, convexPileName>(8, 8, 80)};
    for (LazyScene& s : box3dMeshScenes(quick)) scenes.push_back(std::move(s));  // trees, junkyard (mesh_scenes.hpp)
    return scenes;
}

// The part of Jolt's PerformanceTest the harness runs (--suite jolt). Not
// yet: Ragdoll. Its HighSpeed is in bench/churn_scenes.hpp (--suite churn).
inline std::vector<LazyScene> joltScenes(bool quick) {
    std::vector<LazyScene> scenes{lazyScene<joltPyramid, joltPyramidName>(quick ? 8 : 15)};
    for (LazyScene& s : joltMeshScenes(quick)) scenes.push_back(std::move(s));  // ConvexVsMesh (mesh_scenes.hpp)
    return scenes;
}

}  // namespace bench
