// ZeroTailArray (src/dynamics/zero_tail_array.hpp), the body store's
// forces[], applied[] and scratch[] since branch `lw9`: an array that leaves
// an all-zero element unwritten (its calloc'd storage reads as zero already),
// so a million static bodies touch none of those pages. Its values must be a
// std::vector's in every case: checked byte for byte in lockstep with one
// over random operations, with the invariant that makes the unwritten
// elements correct (every byte past size() is zero) checked after each.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "dynamics/body_store.hpp"

using namespace fulcrum;
using fulcrum::detail::ForceTorque;
using fulcrum::detail::ZeroTailArray;

namespace {

template <class T>
void expectSame(const ZeroTailArray<T>& a, const std::vector<T>& v, int op) {
    ASSERT_EQ(a.size(), v.size()) << "operation " << op;
    ASSERT_GE(a.capacity(), a.size()) << "operation " << op;
    if (!v.empty()) {
        ASSERT_EQ(std::memcmp(a.data(), v.data(), v.size() * sizeof(T)), 0) << "operation " << op;
    }
    // The tail: every byte from size() to capacity() is zero.
    const auto* bytes = reinterpret_cast<const unsigned char*>(a.data());
    for (std::size_t i = a.size() * sizeof(T); i < a.capacity() * sizeof(T); ++i) {
        ASSERT_EQ(bytes[i], 0) << "operation " << op << ": byte " << i << " past the size";
    }
}

TEST(ZeroTailArray, MatchesAStdVectorByteForByte) {
    std::mt19937 rng(21);
    std::uniform_int_distribution<int> pick(0, 99);
    std::uniform_real_distribution<float> value(-5, 5);
    const auto element = [&] {
        ForceTorque f;
        switch (pick(rng) % 4) {
            case 0: break;                                              // all zero: not written
            case 1: f.torque.y = -0.0f; break;                          // a signed zero is not all-zero bytes
            case 2: f.force = {value(rng), 0, 0}; break;
            default: f = {{value(rng), value(rng), value(rng)}, {value(rng), value(rng), value(rng)}};
        }
        return f;
    };
    ZeroTailArray<ForceTorque> a;
    std::vector<ForceTorque> v;
    for (int op = 0; op < 20000; ++op) {
        const int r = pick(rng);
        if (r < 45) {
            const ForceTorque f = element();
            a.push_back(f);
            v.push_back(f);
        } else if (r < 65) {
            if (!v.empty()) {
                a.pop_back();
                v.pop_back();
            }
        } else if (r < 80) {
            if (!v.empty()) {  // write an element in place, as the step does
                const std::size_t i = static_cast<std::size_t>(pick(rng)) % v.size();
                const ForceTorque f = element();
                a[i] = f;
                v[i] = f;
            }
        } else if (r < 88) {
            const std::size_t n = static_cast<std::size_t>(pick(rng)) * 3;
            a.resize(n);
            v.resize(n);
        } else if (r < 93) {
            const std::size_t n = static_cast<std::size_t>(pick(rng)) * 5;
            a.reserve(n);
            v.reserve(n);
        } else if (r < 95) {
            a.clear();
            v.clear();
        } else if (r < 98) {
            ZeroTailArray<ForceTorque> copy(a);  // copies and moves keep the values and the zero tail
            expectSame(copy, v, op);
            ZeroTailArray<ForceTorque> moved(std::move(copy));
            a = moved;
        } else {
            ZeroTailArray<ForceTorque> other;
            other.push_back(element());
            other = std::move(a);
            a = std::move(other);
        }
        expectSame(a, v, op);
        if (HasFatalFailure()) return;
    }
}

TEST(ZeroTailArray, ResizeValueInitialisesLikeAStdVector) {
    // After shrinking, the dropped elements are zero again, so growing back
    // gives value-initialised elements, not the old ones.
    ZeroTailArray<ForceTorque> a;
    for (int i = 0; i < 10; ++i) a.push_back({{Real(i + 1), 2, 3}, {4, 5, Real(-0.0)}});
    a.resize(3);
    a.resize(10);
    for (std::size_t i = 3; i < 10; ++i) {
        EXPECT_TRUE(ZeroTailArray<ForceTorque>::isZero(a[i])) << i;
        EXPECT_EQ(a[i].force, Vec3{}) << i;
    }
    EXPECT_EQ(a[2].force, (Vec3{3, 2, 3}));
}

TEST(ZeroTailArray, StaticBodiesLeaveTheirForcesUnwrittenAndAUserForceStillActs) {
    // The body store's use: a thousand static tiles, then a ball pushed by a
    // user force. Its entries come after the tiles' unwritten ones; the ball
    // falls as gravity plus the force say (x'' = F / m exactly in x: no drag).
    World world;
    BodyDef tile;
    tile.type = BodyType::Static;
    tile.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    for (int i = 0; i < 1000; ++i) {
        tile.position = {Real(i % 40) - 20, -10, Real(i / 40) - 20};
        world.createBody(tile);
    }
    BodyDef ball;
    ball.shape = Shape::sphere(Real(0.5));
    ball.mass = 2;
    ball.position = {0, 5, 0};
    const BodyId b = world.createBody(ball);
    const Real dt = Real(1) / 60;
    for (int step = 0; step < 30; ++step) {
        world.applyForceAtCenter(b, {4, 0, 0});  // 2 m/s^2 along x, cleared after each step
        world.step(dt);
    }
    // Semi-implicit Euler with n sub-steps of a constant acceleration a over
    // t = 0.5 s: x = a t^2 (1 + 1 / N) / 2, N = 30 * substeps.
    const double substeps = world.settings().substeps;
    const double expected = 2 * 0.25 * (1 + 1 / (30 * substeps)) / 2;
    EXPECT_NEAR(world.position(b).x, expected, 1e-4);
    EXPECT_NEAR(world.linearVelocity(b).x, 1.0, 1e-4);
}

}  // namespace
