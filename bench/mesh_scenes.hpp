#pragma once
// The peers' triangle-mesh scenes (and Box3D's junkyard, which sits beside
// them in its suite), as engine-neutral descriptions: the parameters are
// transcribed from Box3D's shared/benchmarks.c and Jolt's
// PerformanceTest/ConvexVsMeshScene.h, the code is ours.
//
// trees25 / trees50 / trees100 (Box3D): a static wave mesh, x cells of
// 150 * scale along x and 200 * scale along z, cell width 1 / scale (scale 4,
// 2, 1: 25, 50 and 100 cm cells, 960,000 / 240,000 / 60,000 triangles),
// height 0.4 sin(2 pi 0.1 w i) sin(2 pi 0.05 w j) at column i (x) and row j
// (z), w the cell width, centred on the origin; each cell split into
// (i, j), (i, j + 1), (i + 1, j + 1) and (i + 1, j + 1), (i + 1, j), (i, j).
// 50 trees, each one body of 22 six-sided cylinder hulls (vertices on the
// circle) stacked along y: hull k has radius r_k = 0.75 * 0.95^k, height
// 1.5 + 2 r_k and its base at y_k - r_k, y_0 = 1, y_{k+1} = y_k + 1.5 + 2 r_k.
// Tree t's origin at (0, 1, -70 + 3 t), density 1, pair friction
// sqrt(0.6 * 0.9) (Box3D's mesh default and the trees'), spun about z at
// (0.5 + 0.5 t / 50) * 0.5 rad/s with alternating sign (first negative) about
// its origin, so every tree starts toppling. Sleeping on, below 0.2 m/s (the
// trees' sleep threshold; Fulcrum's linearSleepVelocity, Bullet keeps its own
// 0.8 m/s); Box3D's rolling resistance of 0.05 is not carried over (Fulcrum's
// acts on round shapes only, times their radius, so a tree of hulls would not
// feel it; Box3D's own trees with it set to 0 sleep as soon: docs/benchmarks.md,
// "Why the trees keep rocking"). 500 steps of 1/60 s, 4 sub-steps.
//
// junkyard (Box3D): a static box ground 240 x 2 x 240 m with its top at y = 0,
// four walls (half extents 1 x 8 x 50 at x = +-50 and 50 x 8 x 1 at z = +-50,
// their bases at y = -1); 24 layers of 21 x 21 rocks, each the hull of 10
// points of a Fibonacci lattice on a sphere of radius 1.5 (point i at
// z = 1 - (2 i + 1) / 10, azimuth i * 2 pi / phi), at
// (-40 + 4 X, 25 + 4 Y, -40 + 4 Z) (10,584 rocks, equal masses); a kinematic
// 16-sided cylinder (radius 4, height 24, base at y = 0) whose origin goes
// round the circle of radius 35 about the y axis at 6 degrees per second,
// from (35, 0, 0) towards -z. Friction 0.6, sleeping on, 500 steps, 4 sub-steps.
//
// convex_vs_mesh (Jolt's ConvexVsMesh): a static mesh of 100 x 100 cells of
// 3 m, height 5 sin(0.5 i) cos(0.5 j) at column i (x) and row j (z), placed
// at (-150, 5, -150); cells split into (i, j), (i, j + 1), (i + 1, j) and
// (i + 1, j), (i, j + 1), (i + 1, j + 1). 21 x 4 x 21 bodies at
// (7.5 x, 15 + 2 k, 7.5 z), x, z from -10 to 10, k picking the shape: a box
// of half extents (0.5, 0.75, 1), a sphere of radius 0.5, a capsule of radius
// 0.5 and half height 0.75, the hull of (0, 1, 0), (+-1, 0, 0), (0, 0, +-1);
// density 1000, friction 0.5, restitution 0.6; sleeping on; 500 steps of
// 1/60 s (Jolt: one collision step, 4 velocity and 1 position iteration;
// here each engine's defaults).
//
// Quality of the mesh scenes: how many bodies ended below the mesh surface
// under their origin (fell through), and the deepest overlap of the last step.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "scenes.hpp"

namespace bench {

// The hull of a `sides`-sided cylinder along y: vertices on the circle of
// `radius`, base at y = `base`.
inline std::vector<V3> cylinderHullPoints(float height, float radius, float base, int sides) {
    std::vector<V3> points;
    const float step = 2.0f * 3.14159265f / static_cast<float>(sides);
    for (int k = 0; k < sides; ++k) {
        const float angle = step * static_cast<float>(k);
        const float x = radius * std::cos(angle), z = radius * std::sin(angle);
        points.push_back({x, base, z});
        points.push_back({x, base + height, z});
    }
    return points;
}

// Box3D's tree mesh and Jolt's terrain: a grid of (columns + 1) x (rows + 1)
// vertices, vertex (i, j) at index i * (rows + 1) + j.
inline std::shared_ptr<const MeshSpec> waveMesh(int columns, int rows, double cell, double amplitude, double rowHz,
                                               double columnHz) {
    auto mesh = std::make_shared<MeshSpec>();
    const double pi = 3.14159265358979323846;
    const double omegaX = 2 * pi * columnHz * cell, omegaZ = 2 * pi * rowHz * cell;
    for (int i = 0; i <= columns; ++i) {
        for (int j = 0; j <= rows; ++j) {
            mesh->vertices.push_back({-0.5 * cell * columns + cell * i, amplitude * std::sin(omegaX * i) * std::sin(omegaZ * j),
                                      -0.5 * cell * rows + cell * j});
        }
    }
    const auto at = [rows](int i, int j) { return static_cast<std::uint32_t>(i * (rows + 1) + j); };
    for (int i = 0; i < columns; ++i) {
        for (int j = 0; j < rows; ++j) {
            mesh->triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            mesh->triangles.push_back({at(i + 1, j + 1), at(i + 1, j), at(i, j)});
        }
    }
    return mesh;
}

// Box3D's trees at mesh scale 4, 2 or 1 (trees25, trees50, trees100);
// `treeCount` 10 starts at z = -15 as Box3D's debug build.
inline std::string treesName(int scale, int treeCount) {
    return sizedName(("trees" + std::to_string(100 / scale)).c_str(), treeCount == 50, std::to_string(treeCount));
}
inline SceneSpec trees(int scale, int treeCount = 50) {
    SceneSpec s;
    s.name = treesName(scale, treeCount);
    s.steps = 500;
    s.substeps = 4;
    s.sleeping = true;
    s.friction = std::sqrt(0.6 * 0.9);
    s.sleepVelocity = 0.2;
    s.meshes.push_back(waveMesh(150 * scale, 200 * scale, 1.0 / scale, 0.4, 0.05, 0.1));
    BodySpec ground;
    ground.mesh = 0;
    ground.isStatic = true;
    s.bodies.push_back(ground);

    // The 22 hulls; mass and centre of mass of the hexagonal prisms at density 1.
    float y = 1.0f, r = 0.75f;
    const float l = 1.5f;
    double mass = 0, moment = 0;
    for (int k = 0; k < 22; ++k) {
        const float height = l + 2.0f * r;
        s.sharedCompoundHulls.push_back(cylinderHullPoints(height, r, y - r, 6));
        const double volume = 1.5 * std::sqrt(3.0) * double(r) * double(r) * double(height);
        mass += volume;
        moment += volume * (double(y) - double(r) + 0.5 * double(height));
        y += l + 2.0f * r;
        r *= 0.95f;
    }
    const double centerY = moment / mass;
    double spin = -0.5, z = treeCount == 50 ? -70.0 : -15.0;
    for (int t = 0; t < treeCount; ++t) {
        BodySpec tree;
        tree.kind = BodySpec::Kind::SharedCompound;
        tree.position = {0, 1, z};
        tree.mass = mass;
        const double omega = (0.5 + 0.5 * t / treeCount) * spin;
        tree.angularVelocity = {0, 0, omega};
        tree.linearVelocity = {-omega * centerY, 0, 0};  // omega x (centre of mass - origin)
        s.bodies.push_back(tree);
        z += 3;
        spin = -spin;
    }
    return s;
}

// Box3D's junkyard with `layers` layers of rocks (24; 2 in its debug build).
inline std::string junkyardName(int layers) { return sizedName("junkyard", layers == 24, std::to_string(layers)); }
inline SceneSpec junkyard(int layers = 24) {
    SceneSpec s;
    s.name = junkyardName(layers);
    s.steps = 500;
    s.substeps = 4;
    s.sleeping = true;
    const auto addStaticBox = [&s](V3 half, V3 center) {
        BodySpec b;
        b.isStatic = true;
        b.half = half;
        b.position = center;
        s.bodies.push_back(b);
    };
    addStaticBox({120, 1, 120}, {0, -1, 0});
    addStaticBox({1, 8, 50}, {-50, 7, 0});
    addStaticBox({1, 8, 50}, {50, 7, 0});
    addStaticBox({50, 8, 1}, {0, 7, -50});
    addStaticBox({50, 8, 1}, {0, 7, 50});
    // The rock: a Fibonacci lattice of 10 points, radius 1.5.
    const double pi = 3.14159265358979323846, phi = (1 + std::sqrt(5.0)) / 2, radius = 1.5;
    for (int i = 0; i < 10; ++i) {
        const double z = 1 - (2.0 * i + 1) / 10, rxy = std::sqrt(1 - z * z), azimuth = i * 2 * pi / phi;
        s.hullPoints.push_back({radius * rxy * std::cos(azimuth), radius * rxy * std::sin(azimuth), radius * z});
    }
    for (int y = 0; y < layers; ++y) {
        for (int x = 0; x <= 20; ++x) {
            for (int z = 0; z <= 20; ++z) {
                BodySpec rock;
                rock.kind = BodySpec::Kind::Hull;
                rock.position = {-40.0 + 4 * x, 4.0 * y + 25, -40.0 + 4 * z};
                s.bodies.push_back(rock);
            }
        }
    }
    s.sharedCompoundHulls.push_back(cylinderHullPoints(24.0f, 4.0f, 0.0f, 16));
    BodySpec pusher;
    pusher.kind = BodySpec::Kind::SharedCompound;
    pusher.isKinematic = true;
    pusher.position = {35, 0, 0};
    s.bodies.push_back(pusher);
    s.kinematicPaths.push_back({static_cast<int>(s.bodies.size()) - 1, [pi](int step) {
                                    const double angle = -6.0 * (step + 1) / 60.0 * pi / 180.0;
                                    return V3{35 * std::cos(angle), 0, 35 * std::sin(angle)};
                                }});
    return s;
}

// Jolt's ConvexVsMesh with x, z from -half to half (10: 21 x 4 x 21 bodies),
// the lowest layer at `lowest` (15).
inline std::string convexVsMeshName(int half, double lowest) {
    return sizedName("convex_vs_mesh", half == 10 && lowest == 15, std::to_string(2 * half + 1) + "x" + std::to_string(2 * half + 1));
}
inline SceneSpec convexVsMesh(int half = 10, double lowest = 15) {
    SceneSpec s;
    s.name = convexVsMeshName(half, lowest);
    s.steps = 500;
    s.sleeping = true;
    s.friction = 0.5;
    s.restitution = 0.6;
    const int n = 100;
    const double cell = 3, maxHeight = 5;
    auto mesh = std::make_shared<MeshSpec>();
    for (int z = 0; z <= n; ++z) {
        for (int x = 0; x <= n; ++x) {  // vertex (x, z) at z * (n + 1) + x
            const float height = std::sin(float(x) * 50.0f / n) * std::cos(float(z) * 50.0f / n);
            mesh->vertices.push_back({cell * x, maxHeight * height, cell * z});
        }
    }
    for (int x = 0; x < n; ++x) {
        for (int z = 0; z < n; ++z) {
            const auto start = static_cast<std::uint32_t>((n + 1) * z + x);
            mesh->triangles.push_back({start, start + n + 1, start + 1});
            mesh->triangles.push_back({start + 1, start + n + 1, start + n + 2});
        }
    }
    s.meshes.push_back(mesh);
    BodySpec ground;
    ground.mesh = 0;
    ground.isStatic = true;
    ground.position = {-0.5 * n * cell, maxHeight, -0.5 * n * cell};
    s.bodies.push_back(ground);
    s.hullPoints = {{0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    const double density = 1000, pi = 3.14159265358979323846;
    for (int x = -half; x <= half; ++x) {
        for (int k = 0; k < 4; ++k) {
            for (int z = -half; z <= half; ++z) {
                BodySpec b;
                b.position = {7.5 * x, lowest + 2.0 * k, 7.5 * z};
                switch (k) {
                    case 0: b.kind = BodySpec::Kind::Box; b.half = {0.5, 0.75, 1.0}; b.mass = density * 3; break;
                    case 1: b.kind = BodySpec::Kind::Sphere; b.half = {0.5, 0.5, 0.5}; b.mass = density * 4.0 / 3 * pi * 0.125; break;
                    case 2:
                        b.kind = BodySpec::Kind::Capsule;
                        b.half = {0.5, 0.75, 0.5};
                        b.mass = density * (pi * 0.25 * 1.5 + 4.0 / 3 * pi * 0.125);
                        break;
                    default: b.kind = BodySpec::Kind::Hull; b.mass = density * 2.0 / 3; break;  // square pyramid, base 2, height 1
                }
                s.bodies.push_back(b);
            }
        }
    }
    return s;
}

// The height of triangle t of the mesh (placed at `meshOrigin`) straight
// below or above the point (x, z) in the mesh's frame; none when the point is
// outside the triangle seen from above.
inline std::optional<double> triangleHeightAt(const MeshSpec& mesh, V3 meshOrigin, std::size_t triangle, double x, double z) {
    const auto& t = mesh.triangles[triangle];
    const V3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    if (x < std::min({a.x, b.x, c.x}) || x > std::max({a.x, b.x, c.x}) || z < std::min({a.z, b.z, c.z}) ||
        z > std::max({a.z, b.z, c.z})) {
        return std::nullopt;
    }
    // Barycentric coordinates in the x-z plane.
    const double d = (b.z - c.z) * (a.x - c.x) + (c.x - b.x) * (a.z - c.z);
    if (d == 0) return std::nullopt;
    const double u = ((b.z - c.z) * (x - c.x) + (c.x - b.x) * (z - c.z)) / d;
    const double v = ((c.z - a.z) * (x - c.x) + (a.x - c.x) * (z - c.z)) / d;
    const double w = 1 - u - v;
    if (u < -1e-9 || v < -1e-9 || w < -1e-9) return std::nullopt;
    return u * a.y + v * b.y + w * c.y + meshOrigin.y;
}

// The height of the mesh (placed at `meshOrigin`) straight below or above
// p's x and z: the highest triangle over that point; none off the mesh. Every
// triangle tested: the reference MeshColumns is checked against.
inline std::optional<double> meshSurfaceHeight(const MeshSpec& mesh, V3 meshOrigin, V3 p) {
    const double x = p.x - meshOrigin.x, z = p.z - meshOrigin.z;
    std::optional<double> best;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const std::optional<double> y = triangleHeightAt(mesh, meshOrigin, t, x, z);
        if (y && (!best || *y > *best)) best = y;
    }
    return best;
}

// meshSurfaceHeight with the triangles bucketed by their x-z bounds on a grid
// of about two triangles a cell, so a lookup tests one cell's few triangles
// where the whole mesh was tested for each body (the trees100 quality check:
// 50 x 60,000 triangles, about 0.1 billion instructions in the measured
// process). The same answer: a cell's index is a non-decreasing function of
// x (and z), so a triangle whose bounds hold x lies in every cell from its
// low x's to its high x's, x's among them; the highest of the same heights.
class MeshColumns {
public:
    MeshColumns(const MeshSpec& mesh, V3 meshOrigin) : mesh_(mesh), origin_(meshOrigin) {
        const std::size_t count = mesh.triangles.size();
        side_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::sqrt(double(count) / 2)));
        for (const V3& v : mesh.vertices) {
            lowX_ = std::min(lowX_, v.x), highX_ = std::max(highX_, v.x);
            lowZ_ = std::min(lowZ_, v.z), highZ_ = std::max(highZ_, v.z);
        }
        scaleX_ = highX_ > lowX_ ? double(side_) / (highX_ - lowX_) : 0;
        scaleZ_ = highZ_ > lowZ_ ? double(side_) / (highZ_ - lowZ_) : 0;
        // Counting sort of the triangles into the cells their x-z bounds cover, in triangle order.
        cellStart_.assign(side_ * side_ + 1, 0);
        const auto eachCell = [&](std::size_t t, auto&& visit) {
            const auto& tri = mesh.triangles[t];
            const V3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
            const std::size_t x0 = cellX(std::min({a.x, b.x, c.x})), x1 = cellX(std::max({a.x, b.x, c.x}));
            const std::size_t z0 = cellZ(std::min({a.z, b.z, c.z})), z1 = cellZ(std::max({a.z, b.z, c.z}));
            for (std::size_t i = x0; i <= x1; ++i) {
                for (std::size_t j = z0; j <= z1; ++j) visit(i * side_ + j);
            }
        };
        for (std::size_t t = 0; t < count; ++t) eachCell(t, [&](std::size_t cell) { ++cellStart_[cell + 1]; });
        for (std::size_t k = 1; k < cellStart_.size(); ++k) cellStart_[k] += cellStart_[k - 1];
        std::vector<std::size_t> next(cellStart_.begin(), cellStart_.end() - 1);
        cellTriangles_.resize(cellStart_.back());
        for (std::size_t t = 0; t < count; ++t) {
            eachCell(t, [&](std::size_t cell) { cellTriangles_[next[cell]++] = static_cast<std::uint32_t>(t); });
        }
    }

    std::optional<double> surfaceHeight(V3 p) const {
        const double x = p.x - origin_.x, z = p.z - origin_.z;
        if (std::isnan(x) || std::isnan(z)) return meshSurfaceHeight(mesh_, origin_, p);  // every bounds test passes a NaN
        if (!(x >= lowX_ && x <= highX_ && z >= lowZ_ && z <= highZ_)) return std::nullopt;  // beyond every triangle's bounds
        const std::size_t cell = cellX(x) * side_ + cellZ(z);
        std::optional<double> best;
        for (std::size_t k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) {
            const std::optional<double> y = triangleHeightAt(mesh_, origin_, cellTriangles_[k], x, z);
            if (y && (!best || *y > *best)) best = y;
        }
        return best;
    }

private:
    std::size_t cellOf(double value, double low, double scale) const {
        const double cell = std::floor((value - low) * scale);
        return static_cast<std::size_t>(std::clamp(cell, 0.0, double(side_ - 1)));
    }
    std::size_t cellX(double x) const { return cellOf(x, lowX_, scaleX_); }
    std::size_t cellZ(double z) const { return cellOf(z, lowZ_, scaleZ_); }

    const MeshSpec& mesh_;
    V3 origin_;
    std::size_t side_ = 1;
    double lowX_ = 1e300, highX_ = -1e300, lowZ_ = 1e300, highZ_ = -1e300, scaleX_ = 0, scaleZ_ = 0;
    std::vector<std::size_t> cellStart_;
    std::vector<std::uint32_t> cellTriangles_;
};

// The mesh scenes of each suite (bench/box3d_scenes.hpp's box3dScenes and
// joltScenes append them).
inline std::vector<LazyScene> box3dMeshScenes(bool quick) {
    if (quick) return {lazyScene<trees, treesName>(1, 10), lazyScene<junkyard, junkyardName>(2)};
    return {lazyScene<trees, treesName>(4, 50), lazyScene<trees, treesName>(2, 50), lazyScene<trees, treesName>(1, 50),
            lazyScene<junkyard, junkyardName>(24)};
}
inline std::vector<LazyScene> joltMeshScenes(bool quick) {
    if (quick) return {lazyScene<convexVsMesh, convexVsMeshName>(3, 15.0)};
    return {lazyScene<convexVsMesh, convexVsMeshName>(10, 15.0)};
}

}  // namespace bench
