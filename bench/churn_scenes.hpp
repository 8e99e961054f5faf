#pragma once
// The churn and scale scenes of the peers' own suites, as engine-neutral
// descriptions (bench/scenes.hpp's SceneSpec, Kind::Churn): Box3D's rain,
// washer and large_world (its shared/benchmarks.c and, for the ragdoll,
// shared/human.c) and Jolt's PerformanceTest HighSpeed (its
// PerformanceTest/HighSpeedScene.h). The parameters are transcribed; the
// code is ours. Box3D's scenes run at its 1/60 s with 4 sub-steps; a
// script event at step s runs before step s (0-based), as Box3D's
// benchmark program calls its step function before each step, and the
// harness times it with the step.
//
// Quality (bench/benchmark_scenes.cpp): how many dynamic bodies are alive,
// how many escaped the scene's bounds (fell through a floor, left the drum
// or the box: the continuous collision's and the mesh's test), the deepest
// overlap, and for large_world how far the spheres rest from where they should.
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "scenes.hpp"

namespace bench {

namespace churn_detail {

constexpr double kPi = 3.14159265358979323846;

// The rotation taking +y to the unit vector d (a capsule's axis).
inline Q yTo(V3 d) {
    const V3 y{0, 1, 0};
    const double c = dot(y, d);
    if (c < -0.999999) return {0, 1, 0, 0};  // half turn about x
    const V3 axis = cross(y, d);
    Q q{1 + c, axis.x, axis.y, axis.z};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// Box3D's capsule (two centres and a radius, in the body frame) as a part.
inline ShapePart capsulePart(V3 c1, V3 c2, double radius) {
    ShapePart p;
    p.kind = ShapePart::Kind::Capsule;
    p.position = (c1 + c2) * 0.5;
    const V3 d = c2 - c1;
    const double l = length(d);
    p.orientation = yTo(d * (1 / l));
    p.half = {radius, 0.5 * l, radius};
    return p;
}

inline double capsuleMass(const ShapePart& p, double density) {
    const double r = p.half.x, h = p.half.y;
    return density * (kPi * r * r * 2 * h + 4.0 / 3.0 * kPi * r * r * r);
}

inline Q quatXyzw(double x, double y, double z, double w) {
    const double n = std::sqrt(x * x + y * y + z * z + w * w);
    return {w / n, x / n, y / n, z / n};
}

}  // namespace churn_detail

// ---- Box3D's ragdoll (shared/human.c) ------------------------------------------------
// 14 capsule bones (density 1000), each body at its reference frame offset
// by `position`; 13 joints to the parent bone: spherical (here cone-twist:
// cone on frame A's z axis, twist about frame B's z) or revolute (here a
// hinge about frame A's z), limits as given, joint friction 5 N m times the
// bone's factor (Box3D: a motor at speed 0 with that much torque). Box3D
// also gives each joint a 1 Hz spring (damping ratio 0.7) to the rest pose
// and the capsules a rolling resistance of 0.2, which the description leaves
// out. spine_01 and the thighs are in filter group -groupIndex (they never
// collide within a group); the thighs never collide with each other (Box3D's
// filter joint; here the same group does it whenever groupIndex > 0).
inline void addHuman(BodyGroup& g, V3 position, int groupIndex) {
    using namespace churn_detail;
    struct Bone {
        int parent;
        V3 p;
        Q q;
        V3 c1, c2;
        double radius;
        bool grouped;
        bool hinge;
        V3 aP;
        Q aQ;
        V3 bP;
        Q bQ;
        double swingDeg, lowerDeg, upperDeg, friction;
    };
    const Bone bones[14] = {
        // pelvis
        {-1, {0, 0.932087, -0.051708}, quatXyzw(0.739169, 0, 0, 0.673520), {0.07, 0, -0.08}, {-0.07, 0, -0.08}, 0.13, false, false,
         {}, {}, {}, {}, 0, 0, 0, 1},
        // spine_01
        {0, {0, 1.113505, -0.03481}, quatXyzw(0.739973, 0, 0, 0.672637), {0.06, 0, -0.052264}, {-0.06, 0, -0.052264}, 0.12, true,
         false, {0, 0, -0.182204}, quatXyzw(-0.999999, 0, 0, 0.001194), {0, 0, -0.007736}, quatXyzw(-1, 0, 0, 0), 25, -15, 15, 1},
        // spine_02
        {1, {0, 1.194336, -0.027087}, quatXyzw(0.703611, 0, 0, 0.710586), {0.08, -0.015133, -0.091801}, {-0.08, -0.015133, -0.091801},
         0.10, false, false, {0, 0, -0.088935}, quatXyzw(-0.998619, 0, 0, -0.052540), {0, 0, -0.008199}, quatXyzw(-1, 0, 0, 0), 25,
         -15, 15, 1},
        // spine_03
        {2, {0, 1.31043, -0.028232}, quatXyzw(0.669856, 0.000001, -0.000001, 0.742491), {0.11, -0.039753, -0.13},
         {-0.11, -0.039753, -0.13}, 0.145, false, false, {0, 0, -0.124298}, quatXyzw(-0.998921, 0.000001, -0.000001, -0.046434), {},
         quatXyzw(-1, 0, -0.000001, 0), 15, -10, 10, 1},
        // neck
        {3, {0, 1.575582, -0.055837}, quatXyzw(0.879922, 0, 0, 0.475118), {-0.000001, 0, -0.02}, {0, -0.005, -0.08}, 0.07, false, false,
         {0.000001, -0.000259, -0.266585}, quatXyzw(-0.942192, -0.000001, 0, 0.335074), {}, quatXyzw(-1, 0, -0.000001, 0), 45, -15, 15,
         0.8},
        // head
        {4, {0, 1.653348, -0.003241}, quatXyzw(0.750288, 0, 0, 0.661111), {-0.000001, 0.016892, -0.05869}, {0, -0.003629, -0.115072},
         0.0975, false, false, {0, 0.001321, -0.093873}, quatXyzw(-0.974301, 0, 0, -0.225251), {0, 0.001268, -0.005104},
         quatXyzw(-1, 0, 0, 0), 15, -15, 15, 0.4},
        // thigh_l
        {0, {0.090416, 0.986104, -0.035090}, quatXyzw(-0.703287, -0.070715, 0.053866, 0.705327), {0.023719, 0.006008, -0.039068},
         {-0.064492, -0.004664, -0.424718}, 0.09, true, false, {0.05, 0.011537, -0.055325},
         quatXyzw(-0.714896, -0.022305, -0.698361, -0.026790), {}, quatXyzw(-0.002064, 0.758987, 0.017046, 0.650880), 10, -60, 40, 1},
        // calf_l
        {6, {0.101198, 0.527027, -0.037374}, quatXyzw(-0.653328, -0.066860, 0.058582, 0.751838), {0.001778, 0, 0.009841},
         {-0.078577, 0.014707, -0.41816}, 0.075, false, true, {-0.069989, 0.000253, -0.453844},
         quatXyzw(-0.000677, 0.760087, 0.105674, 0.641171), {}, quatXyzw(-0.044589, 0.765540, 0.053368, 0.639619), 0, -5, 45, 1},
        // thigh_r
        {0, {-0.090416, 0.986104, -0.03509}, quatXyzw(-0.703287, 0.070715, -0.053865, 0.705326), {-0.023719, 0.006008, -0.039068},
         {0.064492, -0.004664, -0.424718}, 0.09, true, false, {-0.05, 0.011537, -0.055326},
         quatXyzw(-0.039089, -0.714094, 0.043177, 0.697623), {}, quatXyzw(0.758805, -0.019886, -0.651012, -0.001759), 10, -30, 60, 1},
        // calf_r
        {8, {-0.101198, 0.527027, -0.037373}, quatXyzw(-0.653327, 0.06686, -0.058582, 0.751839), {-0.001820, 0, 0.010071},
         {0.077883, 0.014825, -0.418047}, 0.075, false, true, {0.069988, 0.000253, -0.453844},
         quatXyzw(0.760086, -0.000675, -0.641171, -0.105676), {}, quatXyzw(0.765540, -0.044589, -0.639619, -0.053368), 0, -45, 5, 1},
        // upper_arm_l
        {3, {0.20378, 1.484275, -0.115897}, quatXyzw(0.143082, 0.695980, -0.690130, 0.13733), {}, {-0.091118, 0.037775, 0.229719},
         0.075, false, false, {0.203780, -0.069369, -0.181921}, quatXyzw(-0.278486, 0.445600, -0.097014, 0.845266), {},
         quatXyzw(-0.201396, -0.001586, 0.901850, 0.382234), 60, -5, 5, 1},
        // lower_arm_l
        {10, {0.305614, 1.242908, -0.117599}, quatXyzw(0.165048, 0.563437, -0.802002, 0.109959), {}, {-0.142406, 0.039392, 0.261092},
         0.05, false, true, {-0.095482, 0.039584, 0.240723}, quatXyzw(0.512487, -0.180629, 0.839474, 0.003742), {},
         quatXyzw(0.503803, -0.029831, 0.858168, 0.094017), 0, -5, 60, 1},
        // upper_arm_r
        {3, {-0.20378, 1.484276, -0.115899}, quatXyzw(0.143083, -0.695978, 0.690132, 0.137329), {}, {0.091118, 0.037775, 0.229718},
         0.075, false, false, {-0.203779, -0.069371, -0.181922}, quatXyzw(-0.253621, -0.414842, 0.106962, 0.867261), {},
         quatXyzw(-0.201397, 0.001587, -0.901850, 0.382233), 60, -5, 5, 1},
        // lower_arm_r
        {12, {-0.305614, 1.242907, -0.117599}, quatXyzw(0.165048, -0.563437, 0.802002, 0.109959), {}, {0.142406, 0.039392, 0.261092},
         0.05, false, true, {0.095484, 0.039585, 0.240723}, quatXyzw(-0.180627, 0.512487, -0.003744, -0.839474), {},
         quatXyzw(-0.029831, 0.503803, -0.094017, -0.858169), 0, -60, 5, 1},
    };
    const double frictionTorque = 5, toRadians = kPi / 180;
    const int first = static_cast<int>(g.bodies.size());
    for (const Bone& bone : bones) {
        BodySpec b;
        b.position = position + bone.p;
        b.orientation = bone.q;
        b.parts.push_back(capsulePart(bone.c1, bone.c2, bone.radius));
        b.mass = capsuleMass(b.parts.back(), 1000);
        b.filterGroup = bone.grouped ? -groupIndex : 0;
        g.bodies.push_back(b);
    }
    for (int i = 1; i < 14; ++i) {
        const Bone& bone = bones[i];
        JointSpec j;
        j.a = first + bone.parent;
        j.b = first + i;
        j.type = bone.hinge ? JointSpec::Type::Hinge : JointSpec::Type::ConeTwist;
        j.localFrames = true;
        j.localA = bone.aP;
        j.frameA = bone.aQ;
        j.localB = bone.bP;
        j.frameB = bone.bQ;
        j.swing = bone.swingDeg * toRadians;
        j.lower = bone.lowerDeg * toRadians;
        j.upper = bone.upperDeg * toRadians;
        j.frictionTorque = bone.friction * frictionTorque;
        g.joints.push_back(j);
    }
}

// ---- Box3D's rain ---------------------------------------------------------------------------
// A gridCount x gridCount floor of 15 m cells (Box3D: 10 x 10), each a static
// body at the cell's centre (y = 0) holding a flat grid mesh (8 x 8 squares
// of 1.875 m, two triangles each) and a torus mesh standing in the x-y plane
// (16 x 16 segments, radius 3.75 m, tube 1 m). Group (row, column) is three
// ragdolls dropped from y = 20 at the cell's centre, 0.75 m apart along x.
// Every step s with (s & 0x2F) == 0 (Box3D's release delay) either adds the
// next column's groups (one per row) or, once all columns are in, destroys
// and re-creates one column's, cycling through the columns. Sleeping on;
// 400 steps.
inline std::string rainName(int gridCount, int groupSize, int /*steps*/) {
    return sizedName("rain", gridCount == 10 && groupSize == 3, std::to_string(gridCount) + "x" + std::to_string(groupSize));
}
inline SceneSpec rain(int gridCount = 10, int groupSize = 3, int steps = 400) {
    using namespace churn_detail;
    SceneSpec s;
    s.name = rainName(gridCount, groupSize, steps);
    s.kind = SceneSpec::Kind::Churn;
    s.steps = steps;
    s.substeps = 4;
    const double cell = 15, span = cell * gridCount;
    auto mesh = std::make_shared<MeshSpec>();
    const auto index = [](int i) { return static_cast<std::uint32_t>(i); };
    const int rows = 8;
    const double width = cell / rows;
    for (int ix = 0; ix <= rows; ++ix) {
        for (int iz = 0; iz <= rows; ++iz) mesh->vertices.push_back({-0.5 * cell + ix * width, 0, -0.5 * cell + iz * width});
    }
    for (int ix = 0; ix < rows; ++ix) {
        for (int iz = 0; iz < rows; ++iz) {
            const int i1 = iz + (rows + 1) * ix, i2 = i1 + 1, i3 = i2 + (rows + 1), i4 = i3 - 1;
            mesh->triangles.push_back({index(i1), index(i2), index(i3)});
            mesh->triangles.push_back({index(i3), index(i4), index(i1)});
        }
    }
    const int torusBase = static_cast<int>(mesh->vertices.size()), segments = 16;
    const double radius = 0.25 * cell, thickness = 1;
    for (int r = 0; r < segments; ++r) {
        for (int t = 0; t < segments; ++t) {
            const double u = 2 * kPi * t / segments, v = 2 * kPi * r / segments;
            mesh->vertices.push_back({(radius + thickness * std::cos(v)) * std::cos(u), (radius + thickness * std::cos(v)) * std::sin(u),
                                      thickness * std::sin(v)});
        }
    }
    for (int r1 = 0; r1 < segments; ++r1) {
        const int r2 = (r1 + 1) % segments;
        for (int t1 = 0; t1 < segments; ++t1) {
            const int t2 = (t1 + 1) % segments;
            const int i1 = torusBase + r1 * segments + t1, i2 = torusBase + r1 * segments + t2;
            const int i3 = torusBase + r2 * segments + t2, i4 = torusBase + r2 * segments + t1;
            mesh->triangles.push_back({index(i1), index(i2), index(i3)});
            mesh->triangles.push_back({index(i3), index(i4), index(i1)});
        }
    }
    s.meshes.push_back(std::move(mesh));
    for (int i = 0; i < gridCount; ++i) {
        for (int j = 0; j < gridCount; ++j) {
            BodySpec ground;
            ground.isStatic = true;
            ground.mesh = 0;
            ground.position = {-0.5 * span + 0.5 * cell + i * cell, 0, -0.5 * span + 0.5 * cell + j * cell};
            s.bodies.push_back(ground);
        }
    }
    // Groups: row * gridCount + column.
    for (int row = 0; row < gridCount; ++row) {
        for (int column = 0; column < gridCount; ++column) {
            BodyGroup g;
            V3 p{-0.5 * span + cell * (column + 0.5), 20, -0.5 * span + cell * (row + 0.5)};
            for (int k = 0; k < groupSize; ++k) {
                addHuman(g, p, row * gridCount + column);
                p.x += 0.75;
            }
            s.groups.push_back(std::move(g));
        }
    }
    int columnCount = 0, columnIndex = 0;
    for (int step = 0; step < steps; ++step) {
        if ((step & 0x2F) != 0) continue;
        if (columnCount < gridCount) {
            for (int row = 0; row < gridCount; ++row) s.script.push_back({step, true, row * gridCount + columnCount});
            ++columnCount;
        } else {
            for (int row = 0; row < gridCount; ++row) {
                s.script.push_back({step, false, row * gridCount + columnIndex});
                s.script.push_back({step, true, row * gridCount + columnIndex});
            }
            columnIndex = (columnIndex + 1) % gridCount;
        }
    }
    s.boundsMin = {-0.5 * span - 5, -1, -0.5 * span - 5};  // below y = -1: fell through the floor
    s.boundsMax = {0.5 * span + 5, 1e30, 0.5 * span + 5};
    return s;
}

// ---- Box3D's washer ---------------------------------------------------------------------------
// A kinematic drum at (0, 21, 0) turning at 25 degrees/s about z (and
// drifting at (0.001, -0.002, 0) m/s, as Box3D's does): 36 wall segments
// (hulls of 8 points between radii 16 and 18, z from -10 to 10, each
// spanning 10 degrees less a tenth of that at each end) and 4 paddles
// (radii 14 to 16, 10 degrees wide, at segments 0, 9, 18, 27). Inside,
// n x n x n cubes of half extent 0.2 (density 1000; Box3D: 20^3 = 8000)
// 0.8 m apart, the first at (-8, 13, -8). A static box of half extents
// 60 x 1 x 60 under it (top at y = 0); the drum is open at both ends.
// Sleeping on; 1000 steps.
inline std::string washerName(int n, int /*steps*/) { return sizedName("washer", n == 20, std::to_string(n)); }
inline SceneSpec washer(int n = 20, int steps = 1000) {
    using namespace churn_detail;
    SceneSpec s;
    s.name = washerName(n, steps);
    s.kind = SceneSpec::Kind::Churn;
    s.steps = steps;
    s.substeps = 4;
    BodySpec ground;
    ground.isStatic = true;
    ground.half = {60, 1, 60};
    ground.position = {0, -1, 0};
    s.bodies.push_back(ground);

    BodySpec drum;
    drum.isKinematic = true;
    drum.position = {0, 21, 0};
    drum.angularVelocity = {0, 0, kPi / 180 * 25};
    drum.linearVelocity = {0.001, -0.002, 0};
    const double r0 = 14, r1 = 16, r2 = 18;
    const V3 nd{0, 0, -10}, pd{0, 0, 10};
    const double angle = kPi / 18;
    const Q q = axisAngle({0, 0, 1}, angle), qo = axisAngle({0, 0, 1}, 0.1 * angle);
    const auto hull = [](std::vector<V3> points) {
        ShapePart p;
        p.kind = ShapePart::Kind::Hull;
        p.points = std::move(points);
        return p;
    };
    V3 u1{1, 0, 0};
    for (int i = 0; i < 36; ++i) {
        const V3 u2 = i == 35 ? V3{1, 0, 0} : rotate(q, u1);
        const V3 a1 = rotate(conjugate(qo), u1), a2 = rotate(qo, u2);
        drum.parts.push_back(hull({nd + a1 * r1, nd + a1 * r2, nd + a2 * r1, nd + a2 * r2, pd + a1 * r1, pd + a1 * r2, pd + a2 * r1,
                                   pd + a2 * r2}));
        if (i % 9 == 0) {
            drum.parts.push_back(hull({nd + u1 * r0, nd + u1 * r1, nd + u2 * r0, nd + u2 * r1, pd + u1 * r0, pd + u1 * r1, pd + u2 * r0,
                                       pd + u2 * r1}));
        }
        u1 = u2;
    }
    s.bodies.push_back(std::move(drum));

    const double a = 0.2;
    double x = -2 * a * 20;  // Box3D's start stays at its 20-cube offsets for smaller n (tests)
    for (int i = 0; i < n; ++i) {
        double y = -2 * a * 20 + 21;
        for (int j = 0; j < n; ++j) {
            double z = -2 * a * 20;
            for (int k = 0; k < n; ++k) {
                BodySpec b;
                b.half = {a, a, a};
                b.position = {x, y, z};
                b.mass = 1000 * 8 * a * a * a;
                s.bodies.push_back(b);
                z += 4 * a;
            }
            y += 4 * a;
        }
        x += 4 * a;
    }
    // The drum has no end walls (nor has Box3D's): cubes spill out of both
    // ends onto the ground. Escaped: through the ground or off its edge.
    s.boundsMin = {-60, -1, -60};
    s.boundsMax = {60, 1e30, 60};
    return s;
}

// ---- Box3D's large_world ----------------------------------------------------------------------
// n x n static boxes (Box3D: 1000 x 1000 = a million) of half extents 5 x
// 0.25 x 5 tiling the plane y = 0, 10 m apart; one sphere of radius 0.5
// (density 1000) dropped from y = 1.5 every 5 steps from step 5 until 100
// are out (99 within the 500 steps), on a 10 x 10 grid over the inner 80 %
// of the floor. Sleeping on; 500 steps. They rest at y = 0.75.
inline std::string largeWorldName(int n, int /*steps*/) { return sizedName("large_world", n == 1000, std::to_string(n)); }
inline SceneSpec largeWorld(int n = 1000, int steps = 500) {
    SceneSpec s;
    s.name = largeWorldName(n, steps);
    s.kind = SceneSpec::Kind::Churn;
    s.steps = steps;
    s.substeps = 4;
    const double cell = 10, halfSpan = 0.5 * cell * n;
    s.staticGrid = {n, n, cell, 0, {0.5 * cell, 0.25, 0.5 * cell}};
    const int spheres = 100, side = 10;
    const double inset = 0.1 * 2 * halfSpan, usable = 2 * halfSpan - 2 * inset;
    for (int k = 0; k < spheres; ++k) {
        const int step = 5 * (k + 1);
        if (step >= steps) break;
        BodyGroup g;
        BodySpec b;
        b.kind = BodySpec::Kind::Sphere;
        b.half = {0.5, 0.5, 0.5};
        b.mass = 1000 * 4.0 / 3.0 * churn_detail::kPi * 0.125;
        b.position = {-halfSpan + inset + (k % side + 0.5) * (usable / side), 1.5, -halfSpan + inset + (k / side + 0.5) * (usable / side)};
        g.bodies.push_back(b);
        s.groups.push_back(std::move(g));
        s.script.push_back({step, true, k});
    }
    s.boundsMin = {-halfSpan, -1, -halfSpan};
    s.boundsMax = {halfSpan, 1e30, halfSpan};
    s.restHeight = 0.75;
    return s;
}

// ---- Jolt's PerformanceTest HighSpeed -------------------------------------------------------------
// A closed box of six static walls (boxes of half extents 50 x 0.2 x 50 at
// 50 m from the centre, restitution 1, friction 1) holding `count` (Jolt:
// 5000) dynamic bodies with continuous collision (Jolt's LinearCast motion
// quality, against every body), cycling through three shapes: a sphere of
// radius 0.5, a box of half extents 0.25 x 0.5 x 0.5 and a compound (a
// capsule of radius 0.125 and cylinder half height 0.5 at (0, 0.5, 0), a box
// of half extents 0.5 x 0.125 x 0.125 at (0.5, 0, 0)); density 1000. Drawn
// from std::mt19937 with its default seed, Jolt's way and order: position
// in [-45, 45]^3, a uniform random rotation (Shoemake), friction in
// [0.5, 1], restitution in [0.9, 1], velocity 250 m/s in a uniform random
// direction. Sleeping on (Jolt's default); 500 steps of 1/60 s, Jolt with
// its one collision step, Fulcrum with 2 sub-steps: nothing here stacks, so
// its default 5 (for stacking quality) would integrate positions five times
// where Jolt does once; 2 keep every body in the box (with more, not much
// deeper, overlaps with the walls at a step's end), 1 gives seven times
// as many (docs/benchmarks.md, branch hsccd).
inline std::string joltHighSpeedName(int count, int /*steps*/) {
    return sizedName("jolt_high_speed", count == 5000, std::to_string(count));
}
inline SceneSpec joltHighSpeed(int count = 5000, int steps = 500) {
    using namespace churn_detail;
    SceneSpec s;
    s.name = joltHighSpeedName(count, steps);
    s.kind = SceneSpec::Kind::Churn;
    s.steps = steps;
    const double half = 50, wall = 0.2, range = 0.9 * half, speed = 250;
    const V3 positions[6] = {{0, -half, 0}, {0, half, 0}, {0, 0, -half}, {0, 0, half}, {-half, 0, 0}, {half, 0, 0}};
    for (int i = 0; i < 6; ++i) {
        BodySpec w;
        w.isStatic = true;
        w.position = positions[i];
        // Jolt rotates the y-thin box a quarter turn about x (z walls) or z (x walls): the same as a thin z or x box.
        w.half = i < 2 ? V3{half, wall, half} : i < 4 ? V3{half, half, wall} : V3{wall, half, half};
        w.friction = 1;
        w.restitution = 1;
        s.bodies.push_back(w);
    }
    std::mt19937 rnd;
    const float rangeF = static_cast<float>(std::mt19937::max() - std::mt19937::min());
    const auto unit = [&] { return static_cast<float>(rnd() - std::mt19937::min()) / rangeF; };
    const auto between = [&](float lo, float hi) {
        return lo + static_cast<float>(rnd() - std::mt19937::min()) * (hi - lo) / rangeF;
    };
    const float twoPi = static_cast<float>(2 * kPi);
    for (int i = 0; i < count; ++i) {
        BodySpec b;
        const float x = between(float(-range), float(range));
        const float y = between(float(-range), float(range));
        const float z = between(float(-range), float(range));
        b.position = {x, y, z};
        const float x0 = unit();
        const float r1 = std::sqrt(1 - x0), r2 = std::sqrt(x0);
        const float theta1 = twoPi * unit();
        const float theta2 = twoPi * unit();
        b.orientation = quatXyzw(std::sin(theta1) * r1, std::cos(theta1) * r1, std::sin(theta2) * r2, std::cos(theta2) * r2);
        b.friction = between(0.5f, 1.0f);
        b.restitution = between(0.9f, 1.0f);
        const float vz = -1 + 2 * unit();
        const float vr = std::sqrt(1 - vz * vz);
        const float theta = twoPi * unit();
        b.linearVelocity = V3{vr * std::sin(theta), vr * std::cos(theta), vz} * speed;
        b.isBullet = true;
        const double size = 0.5;
        switch (i % 3) {
            case 0:
                b.kind = BodySpec::Kind::Sphere;
                b.half = {size, size, size};
                b.mass = 1000 * 4.0 / 3.0 * kPi * size * size * size;
                break;
            case 1:
                b.half = {0.5 * size, size, size};
                b.mass = 1000 * 8 * b.half.x * b.half.y * b.half.z;
                break;
            default: {
                ShapePart capsule;
                capsule.kind = ShapePart::Kind::Capsule;
                capsule.position = {0, size, 0};
                capsule.half = {0.25 * size, size, 0.25 * size};
                ShapePart bar;
                bar.position = {size, 0, 0};
                bar.half = {size, 0.25 * size, 0.25 * size};
                b.parts = {capsule, bar};
                b.mass = capsuleMass(capsule, 1000) + 1000 * 8 * bar.half.x * bar.half.y * bar.half.z;
                break;
            }
        }
        s.bodies.push_back(b);
    }
    s.substeps = 2;
    s.boundsMin = {-half, -half, -half};
    s.boundsMax = {half, half, half};
    return s;
}

// The churn and scale scenes of both suites (--suite churn): Box3D's rain,
// washer and large_world, Jolt's HighSpeed; --quick makes them small.
inline std::vector<LazyScene> churnScenes(bool quick) {
    if (quick) {
        return {lazyScene<rain, rainName>(4, 2, 200), lazyScene<washer, washerName>(8, 300),
                lazyScene<largeWorld, largeWorldName>(100, 200), lazyScene<joltHighSpeed, joltHighSpeedName>(500, 200)};
    }
    return {lazyScene<rain, rainName>(10, 3, 400), lazyScene<washer, washerName>(20, 1000),
            lazyScene<largeWorld, largeWorldName>(1000, 500), lazyScene<joltHighSpeed, joltHighSpeedName>(5000, 500)};
}

}  // namespace bench
