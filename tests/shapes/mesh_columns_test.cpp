// The benchmark harness's mesh quality check (bench/mesh_scenes.hpp): the
// height under a body from the triangles of one grid cell (MeshColumns) is the
// height from every triangle of the mesh (meshSurfaceHeight), exactly, on
// the trees' and ConvexVsMesh's meshes: points scattered over and beyond the
// mesh, on its vertices and edge midpoints (where triangles meet and the
// cells' borders fall), and not a number.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "../../bench/mesh_scenes.hpp"

namespace {

bool sameAnswer(const std::optional<double>& a, const std::optional<double>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || std::memcmp(&*a, &*b, sizeof(double)) == 0;
}

TEST(MeshColumns, SurfaceHeightIsEveryTrianglesAnswerExactly) {
    const std::vector<bench::SceneSpec> scenes{bench::trees(1, 10), bench::convexVsMesh(3)};
    for (const bench::SceneSpec& scene : scenes) {
        const bench::MeshSpec& mesh = *scene.meshes.at(0);
        bench::V3 origin;
        for (const bench::BodySpec& b : scene.bodies) {
            if (b.mesh == 0) origin = b.position;
        }
        const bench::MeshColumns columns(mesh, origin);
        double lowX = 1e300, highX = -1e300, lowZ = 1e300, highZ = -1e300;
        for (const bench::V3& v : mesh.vertices) {
            lowX = std::min(lowX, v.x), highX = std::max(highX, v.x);
            lowZ = std::min(lowZ, v.z), highZ = std::max(highZ, v.z);
        }
        std::vector<bench::V3> points;
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> unit(-0.05, 1.05);
        for (int i = 0; i < 1000; ++i) {
            points.push_back({origin.x + lowX + unit(rng) * (highX - lowX), 0, origin.z + lowZ + unit(rng) * (highZ - lowZ)});
        }
        for (std::size_t k = 0; k < mesh.vertices.size(); k += 61) {
            const bench::V3 v = mesh.vertices[k];
            points.push_back({origin.x + v.x, 0, origin.z + v.z});
        }
        for (std::size_t k = 0; k < mesh.triangles.size(); k += 67) {
            const bench::V3 a = mesh.vertices[mesh.triangles[k][0]], b = mesh.vertices[mesh.triangles[k][1]];
            points.push_back({origin.x + 0.5 * (a.x + b.x), 0, origin.z + 0.5 * (a.z + b.z)});
        }
        points.push_back({origin.x + lowX, 0, origin.z + lowZ});
        points.push_back({origin.x + highX, 0, origin.z + highZ});
        points.push_back({std::numeric_limits<double>::quiet_NaN(), 0, origin.z});
        int over = 0;
        for (const bench::V3& p : points) {
            const std::optional<double> expected = bench::meshSurfaceHeight(mesh, origin, p);
            const std::optional<double> got = columns.surfaceHeight(p);
            over += expected.has_value() && !std::isnan(*expected);
            if (expected && std::isnan(*expected)) {
                ASSERT_TRUE(got && std::isnan(*got)) << scene.name;
                continue;
            }
            ASSERT_TRUE(sameAnswer(got, expected)) << scene.name << " at x " << p.x << ", z " << p.z;
        }
        EXPECT_GT(over, 900) << scene.name;  // most points are over the mesh, some beyond it
    }
}

}  // namespace
