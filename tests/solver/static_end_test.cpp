// The wide kernels for blocks whose end A is the static world in every lane
// (staticAKernels in src/solver/contact_wide_kernels.hpp): they read none of
// end A's rows and subtract the stored signed zero dot(+0, rAxn) where the
// general kernel subtracts the dot, a claim of the same bits, signs of zero
// included. Held here against the general kernel on every block
// (ContactSolver::setStaticAKernels(false)) and against the scalar reference:
// every body's position, orientation and velocities bit for bit every step,
// at one thread and at three, at 8 lanes (where the CPU has AVX2) and at 4.
// The scenes make exact zeros on purpose: boxes set down square on the
// ground with no sideways motion (velocity components exactly zero, the
// sums where a -0 from A's term would turn a -0 into +0), beside a heap of
// spheres, capsules, boxes and hulls with restitution and rolling
// resistance, and bodies dropped on a wavy mesh (ConvexVsMesh in small).
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "contacts/helpers.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"
#include "solver/contact_wide.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// A heap on the ground box (as tests/solver/lane_order_test.cpp) and a row
// of boxes set down square, at rest, a millimetre above the ground.
std::vector<BodyId> buildGroundScene(World& world) {
    addGround(world, Real(0.6), Real(0.1));
    const Vec3 pyramid[] = {{0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1}};
    std::vector<BodyId> ids;
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j < 4; ++j) {
                BodyDef d;
                d.position = {Real(1.6) * static_cast<Real>(i - 2) + Real(0.3) * static_cast<Real>(k % 2),
                              Real(0.8) + Real(1.5) * static_cast<Real>(k),
                              Real(1.6) * static_cast<Real>(j - 2) - Real(0.2) * static_cast<Real>(k % 3)};
                d.orientation = Quat::fromAxisAngle(normalize(Vec3{3, 1, 2}), Real(0.15) * static_cast<Real>(i + 2 * j + k));
                switch ((i + j + k) % 4) {
                    case 0:
                        d.shape = Shape::sphere(Real(0.5));
                        d.restitution = Real(0.5);
                        d.rollingResistance = Real(0.05);
                        break;
                    case 1:
                        d.shape = Shape::capsule(Real(0.35), Real(0.6));
                        d.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5)) * d.orientation;
                        break;
                    case 2:
                        d.shape = Shape::box({Real(0.5), Real(0.35), Real(0.6)});
                        d.mass = 3;
                        break;
                    default:
                        d.shape = Shape::convexHull(pyramid);
                        d.friction = Real(0.4);
                        break;
                }
                ids.push_back(world.createBody(d));
            }
        }
    }
    for (int i = 0; i < 12; ++i) {
        ids.push_back(addBox(world, {Real(12) + Real(1.5) * static_cast<Real>(i), Real(0.501), Real(-6) + static_cast<Real>(i)},
                             {Real(0.5), Real(0.5), Real(0.5)}, Real(1) + static_cast<Real>(i % 3)));
    }
    return ids;
}

// Boxes, spheres, capsules and hulls dropped on a wavy static mesh (as
// tests/contacts/manifold_bits_test.cpp, fewer).
std::vector<BodyId> buildMeshScene(World& world) {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    const int n = 12;
    for (int z = 0; z <= n; ++z) {
        for (int x = 0; x <= n; ++x) {
            const Real h = Real(0.6) * std::sin(Real(0.7) * Real(x)) * std::cos(Real(0.6) * Real(z));
            vertices.push_back({Real(x) - Real(n) / 2, h, Real(z) - Real(n) / 2});
        }
    }
    for (int x = 0; x < n; ++x) {
        for (int z = 0; z < n; ++z) {
            const auto s = static_cast<std::uint32_t>((n + 1) * z + x);
            triangles.push_back({s, s + n + 1, s + 1});
            triangles.push_back({s + 1, s + n + 1, s + n + 2});
        }
    }
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::mesh(vertices, triangles);
    ground.friction = Real(0.5);
    world.createBody(ground);
    const std::array<Vec3, 5> pyramid = {Vec3{0, Real(0.5), 0}, Vec3{Real(0.5), 0, 0}, Vec3{Real(-0.5), 0, 0},
                                         Vec3{0, 0, Real(0.5)}, Vec3{0, 0, Real(-0.5)}};
    std::vector<BodyId> bodies;
    for (int x = -2; x <= 2; ++x) {
        for (int z = -2; z <= 2; ++z) {
            for (int k = 0; k < 3; ++k) {
                BodyDef d;
                d.position = {Real(1.3) * Real(x), Real(1.6) + Real(1.15) * Real(k), Real(1.3) * Real(z)};
                d.friction = Real(0.5);
                d.restitution = Real(0.3);
                switch ((k + x + z + 12) % 4) {
                    case 0: d.shape = Shape::box({Real(0.25), Real(0.4), Real(0.5)}); break;
                    case 1: d.shape = Shape::sphere(Real(0.3)); break;
                    case 2: d.shape = Shape::capsule(Real(0.25), Real(0.35)); break;
                    default: d.shape = Shape::convexHull(pyramid); break;
                }
                d.mass = 1;
                d.angularVelocity = {Real(0.1) * Real(x), 0, Real(0.1) * Real(z)};
                bodies.push_back(world.createBody(d));
            }
        }
    }
    return bodies;
}

using RealBits = std::conditional_t<sizeof(Real) == 4, std::uint32_t, std::uint64_t>;
bool sameBits(Real a, Real b) { return std::bit_cast<RealBits>(a) == std::bit_cast<RealBits>(b); }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

::testing::AssertionResult sameState(const World& world, BodyId a, const World& reference, BodyId b) {
    const Quat qa = world.orientation(a), qb = reference.orientation(b);
    const Vec3 va = world.linearVelocity(a), vb = reference.linearVelocity(b);
    const Vec3 wa = world.angularVelocity(a), wb = reference.angularVelocity(b);
    const bool same = sameBits(world.position(a), reference.position(b)) &&
                      sameBits(Vec3{qa.x, qa.y, qa.z}, Vec3{qb.x, qb.y, qb.z}) && sameBits(qa.w, qb.w) &&
                      sameBits(va, vb) && sameBits(wa, wb);
    if (same) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "v (" << va.x << ", " << va.y << ", " << va.z << ") vs (" << vb.x << ", "
                                         << vb.y << ", " << vb.z << "), w (" << wa.x << ", " << wa.y << ", " << wa.z
                                         << ") vs (" << wb.x << ", " << wb.y << ", " << wb.z << ")";
}

template <class Build>
void runTriple(Build build, detail::SimdPath path, int threads, int steps) {
    WorldDef def;
    def.threads = threads;
    def.sleeping = false;
    World fast(def), general(def), scalar(def);
    for (World* w : {&fast, &general, &scalar}) w->setParallelMinBodies(1);
    detail::ContactSolver& solver = detail::implOf(fast).contactSolver;
    if (solver.setSimdPath(path) != path) GTEST_SKIP() << "this CPU has no " << detail::simdPathName(path);
    detail::ContactSolver& reference = detail::implOf(general).contactSolver;
    reference.setSimdPath(path);
    reference.setStaticAKernels(false);
    detail::implOf(scalar).contactSolver.setSimdPath(detail::SimdPath::Scalar);
    const std::vector<BodyId> a = build(fast), b = build(general), c = build(scalar);
    std::size_t staticBlocks = 0, referenceStatic = 0, exactZeros = 0;
    for (int step = 0; step < steps; ++step) {
        fast.step(kDt);
        general.step(kDt);
        scalar.step(kDt);
        staticBlocks += solver.staticABlocks();
        referenceStatic += reference.staticABlocks();
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(sameState(fast, a[i], general, b[i])) << "threads " << threads << ", body " << i << ", step " << step;
            ASSERT_TRUE(sameState(fast, a[i], scalar, c[i])) << "scalar, threads " << threads << ", body " << i << ", step " << step;
            const Vec3 v = fast.linearVelocity(a[i]), w = fast.angularVelocity(a[i]);
            for (Real x : {v.x, v.z, w.x, w.y, w.z}) exactZeros += x == 0 ? 1 : 0;
        }
    }
    // The fast kernels ran (and the reference never did), on a scene with
    // exact zeros in the bodies' velocities to get their signs wrong on.
    EXPECT_GT(staticBlocks, static_cast<std::size_t>(steps)) << staticBlocks;
    EXPECT_EQ(referenceStatic, 0u);
    EXPECT_GT(exactZeros, 1000u) << exactZeros;
}

TEST(StaticEndKernels, GroundSameBitsOneThread8Lanes) { runTriple(buildGroundScene, detail::SimdPath::Avx2, 1, 150); }
TEST(StaticEndKernels, GroundSameBitsThreeThreads8Lanes) { runTriple(buildGroundScene, detail::SimdPath::Avx2, 3, 150); }
TEST(StaticEndKernels, GroundSameBitsOneThread4Lanes) { runTriple(buildGroundScene, detail::SimdPath::Sse2, 1, 150); }
TEST(StaticEndKernels, GroundSameBitsThreeThreads4Lanes) { runTriple(buildGroundScene, detail::SimdPath::Sse2, 3, 150); }
TEST(StaticEndKernels, MeshSameBitsOneThread8Lanes) { runTriple(buildMeshScene, detail::SimdPath::Avx2, 1, 150); }
TEST(StaticEndKernels, MeshSameBitsThreeThreads4Lanes) { runTriple(buildMeshScene, detail::SimdPath::Sse2, 3, 150); }

}  // namespace

// The kernels themselves on blocks built from drawn inputs full of signed
// zeros (velocities, deltas, contact points and normals along the axes, the
// static end's centre of mass), where A's dot(+0, r) term is -0 and the rest
// of a sum is -0 often enough: the body rows after a warm start, a solve
// with and without bias and a restitution pass, bit for bit, the fast
// kernels against the general one. (Dropping the stored signed zeros, the
// obvious shortcut, fails here; the scene tests above do not reach it.)
namespace kernels {

struct Draw {
    std::uint32_t state;
    std::uint32_t next() {
        state = state * 1664525u + 1013904223u;
        return state >> 8;
    }
    // +0, -0, or a value of either sign, small or near 1.
    Real value() {
        switch (next() % 6) {
            case 0: return Real(0);
            case 1: return -Real(0);
            case 2: return Real(0.25) + Real(next() % 1000) / 1000;
            case 3: return -Real(0.25) - Real(next() % 1000) / 1000;
            case 4: return Real(1e-3) * Real(next() % 100);
            default: return -Real(1e-3) * Real(next() % 100);
        }
    }
    Vec3 vec() { return {value(), value(), value()}; }
    Real zero() { return next() % 2 == 0 ? Real(0) : -Real(0); }
    Vec3 zeros() { return {zero(), zero(), zero()}; }
    // An axis (either sign) or a drawn direction.
    Vec3 normal() {
        const Real s = next() % 2 == 0 ? Real(1) : Real(-1);
        switch (next() % 6) {
            case 0: return {0, s, 0};
            case 1: return {s, 0, -Real(0)};
            case 2: return {-Real(0), 0, s};
            default: {
                Vec3 n{value(), Real(0.5) + Real(next() % 100) / 100, value()};
                return normalize(n);
            }
        }
    }
};

void runKernels(detail::SimdPath path) {
    std::unique_ptr<detail::WideBlocks> fast = detail::makeWideBlocks(path);
    std::unique_ptr<detail::WideBlocks> general = detail::makeWideBlocks(path);
    if (!fast || !general) GTEST_SKIP() << "this CPU has no " << detail::simdPathName(path);
    general->setStaticAKernels(false);
    const int lanes = fast->lanes();
    Draw draw{12345};
    std::size_t differ = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        // Half the blocks at rest to the bit: every velocity, delta, impulse
        // and depth a signed zero (where a -0 from A's term is not absorbed
        // by a later sum).
        const bool still = trial % 2 == 0;
        const auto vec = [&] { return still ? draw.zeros() : draw.vec(); };
        const auto value = [&] { return still ? draw.zero() : draw.value(); };
        std::vector<detail::SolverBody> bodies(static_cast<std::size_t>(lanes) + 1);
        std::vector<Vec3> startCom(bodies.size());
        startCom[0] = draw.vec();
        for (std::size_t i = 1; i < bodies.size(); ++i) {
            detail::SolverBody& b = bodies[i];
            b.v = vec();
            b.w = vec();
            b.dp = vec();
            b.dtheta = vec();
            b.invMass = Real(0.5) + Real(draw.next() % 100) / 100;
            const Real d = Real(0.5) + Real(draw.next() % 100) / 100;
            b.invI = Mat3{{d, 0, 0}, {0, d, 0}, {0, 0, d}};
            startCom[i] = draw.vec();
        }
        std::vector<detail::LaneSource> src(static_cast<std::size_t>(lanes));
        const int laneCount = 1 + static_cast<int>(draw.next() % static_cast<std::uint32_t>(lanes));
        for (int l = 0; l < laneCount; ++l) {
            detail::LaneSource& s = src[static_cast<std::size_t>(l)];
            s.normal = draw.normal();
            s.pointCount = 1 + draw.next() % 4;
            s.frictionImpulse = vec();
            s.twistImpulse = value();
            s.rollingImpulse = vec();
            s.bodyA = 0;
            s.bodyB = static_cast<std::uint32_t>(l + 1);
            s.friction = Real(0.5);
            s.restitution = draw.next() % 3 == 0 ? Real(0.5) : Real(0);
            s.rollingResistance = draw.next() % 4 == 0 ? Real(0.05) : Real(0);
            s.pushMax = 3;
            s.biasRate = 30;
            s.massScale = Real(0.8);
            s.impulseScale = Real(0.2);
            for (std::uint32_t i = 0; i < s.pointCount; ++i) {
                s.points[i].position = draw.vec();
                s.points[i].depth = value() * Real(0.01);
                s.points[i].normalImpulse = still ? draw.zero() : std::abs(draw.value());  // an impulse of -0 is reachable
            }
        }
        std::vector<detail::SolverBody> a = bodies, b = bodies;
        fast->resize(1);
        general->resize(1);
        fast->build(0, src.data(), laneCount, a.data(), startCom.data());
        general->build(0, src.data(), laneCount, b.data(), startCom.data());
        ASSERT_EQ(fast->staticABlocks(), 1u);
        for (detail::WideBlocks* blocks : {fast.get(), general.get()}) {
            detail::SolverBody* rows = blocks == fast.get() ? a.data() : b.data();
            blocks->warmStart(0, 1, rows);
            blocks->solve(0, 1, rows, true, Real(240));
            blocks->solve(0, 1, rows, false, Real(240));
            blocks->restitution(rows, Real(1e-3));
        }
        bool same = true;
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            same = same && sameBits(a[i].v, b[i].v) && sameBits(a[i].w, b[i].w) && sameBits(a[i].invMass, b[i].invMass);
        }
        differ += same ? 0 : 1;
    }
    EXPECT_EQ(differ, 0u) << "of 4000 drawn blocks at " << detail::simdPathName(path);
}

}  // namespace kernels

TEST(StaticEndKernels, DrawnBlocksSameBits8Lanes) { kernels::runKernels(detail::SimdPath::Avx2); }
TEST(StaticEndKernels, DrawnBlocksSameBits4Lanes) { kernels::runKernels(detail::SimdPath::Sse2); }
