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
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

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
inline HullPileSpec convexPile(int countX = 8, int countZ = 8, int layers = 80) {
    HullPileSpec s;
    s.name = countX == 8 && countZ == 8 && layers == 80
                 ? "convex_pile"
                 : "convex_pile(" + std::to_string(countX) + "x" + std::to_string(countZ) + "x" + std::to_string(layers) + ")";
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

}  // namespace bench
