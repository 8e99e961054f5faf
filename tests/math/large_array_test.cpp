// LargeArrayAllocator (src/math/large_array.hpp): the per-body and per-node
// arrays of a large world, aligned to 2 MiB and advised to use huge pages.
// Bad sizes give a clear error, the memory goes back when an array goes, the
// advice is on the mapping only when asked for, a world steps to the same bits
// with and without it, and a steady step allocates no array.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/world.hpp"
#include "math/large_array.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;
using fulcrum::detail::kHugePageBytes;
using fulcrum::detail::kLargeArrayBytes;
using fulcrum::detail::LargeArray;
using fulcrum::detail::LargeArrayAllocator;

namespace {

// Restores the process-wide advice switch when a test ends.
class HugePagesSetting {
public:
    explicit HugePagesSetting(bool on) : before_(detail::largeArrayHugePages()) { detail::setLargeArrayHugePages(on); }
    ~HugePagesSetting() { detail::setLargeArrayHugePages(before_); }
    HugePagesSetting(const HugePagesSetting&) = delete;
    HugePagesSetting& operator=(const HugePagesSetting&) = delete;

private:
    bool before_;
};

// The VmFlags line of the mapping that holds `p` in /proc/self/smaps ("" when
// there is none: not Linux). "hg" in it is the MADV_HUGEPAGE advice.
std::string vmFlagsOf(const void* p) {
    std::ifstream smaps("/proc/self/smaps");
    const auto address = reinterpret_cast<std::uintptr_t>(p);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        // A mapping's first line: "begin-end perms ...", both hexadecimal.
        if (const std::size_t space = line.find(' '); space != std::string::npos && line.find('-') < space) {
            try {
                begin = std::stoull(line.substr(0, line.find('-')), nullptr, 16);
                end = std::stoull(line.substr(line.find('-') + 1, space - line.find('-') - 1), nullptr, 16);
                dash = '-';
            } catch (const std::exception&) {
                dash = 0;
            }
            if (dash == '-') {
                inside = begin <= address && address < end;
                continue;
            }
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return "";
}

bool kernelHasHugePages() { return std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled").good(); }

bool hasFlag(const std::string& vmFlags, const std::string& flag) { return (vmFlags + " ").find(" " + flag + " ") != std::string::npos; }

// A grid of static boxes large enough that the body store's records, the
// static tree's nodes and the proxy records take the large path, and spheres
// dropped onto it at different heights (some landing, some still falling at
// the end, a few sleeping).
std::uint64_t stepGridWorld(int side, int steps) {
    World world;
    world.reserveBodies(static_cast<std::size_t>(side * side + 40));
    BodyDef tile;
    tile.type = BodyType::Static;
    tile.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    for (int i = 0; i < side; ++i) {
        for (int j = 0; j < side; ++j) {
            tile.position = {Real(i) - Real(0.5) * Real(side), 0, Real(j) - Real(0.5) * Real(side)};
            world.createBody(tile);
        }
    }
    BodyDef ball;
    ball.shape = Shape::sphere(Real(0.3));
    ball.mass = 2;
    for (int k = 0; k < 40; ++k) {
        ball.position = {Real(k % 8) * Real(1.7) - 6, Real(1) + Real(k % 5) * Real(0.9), Real(k / 8) * Real(1.3) - 3};
        ball.linearVelocity = {Real(k % 3) - 1, 0, Real(k % 4) * Real(0.5) - Real(0.75)};
        world.createBody(ball);
    }
    for (int s = 0; s < steps; ++s) world.step(Real(1) / 60);
    return test::stateHash(world);
}

}  // namespace

TEST(LargeArray, BadSizesGiveAClearError) {
    LargeArrayAllocator<double> alloc;
    // More elements than bytes can count: an error before any allocation.
    EXPECT_THROW((void)alloc.allocate(std::numeric_limits<std::size_t>::max() / 4), std::bad_array_new_length);
    // Representable but more memory than any machine has: bad_alloc, not a crash.
    EXPECT_THROW((void)alloc.allocate(std::size_t{1} << 60), std::bad_alloc);
    LargeArray<double> v;
    EXPECT_THROW(v.reserve(v.max_size() + 1), std::length_error);
    EXPECT_TRUE(v.empty());
}

TEST(LargeArray, LargeArraysAreAlignedAndReleased) {
    const HugePagesSetting on(true);
    test::HeapBudget heap;
    const std::size_t before = detail::largeArrayAllocationCount();
    {
        // 48 MiB: over glibc's largest mmap threshold, so its own mapping.
        LargeArray<std::uint32_t> big(std::size_t{12} << 20, 7u);
        if (detail::kLargeArraysAligned) {
            EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % kHugePageBytes, 0u);
        }
        EXPECT_EQ(detail::largeArrayAllocationCount(), before + 1);
        EXPECT_EQ(big.front(), 7u);
        EXPECT_EQ(big.back(), 7u);
        EXPECT_GE(heap.growth(), static_cast<long long>(big.size() * sizeof(std::uint32_t)));
        // A small array takes the plain path.
        LargeArray<std::uint32_t> small(kLargeArrayBytes / sizeof(std::uint32_t) - 1, 1u);
        EXPECT_EQ(detail::largeArrayAllocationCount(), before + 1);
    }
    EXPECT_LE(heap.growth(), 0);
    EXPECT_GE(heap.peakGrowth(), static_cast<long long>((std::size_t{12} << 20) * sizeof(std::uint32_t)));
}

TEST(LargeArray, TheAdviceIsOnTheMappingOnlyWhenAsked) {
    static const int anything = 0;
    if (!kernelHasHugePages() || vmFlagsOf(&anything).empty()) {
        GTEST_SKIP() << "no transparent huge pages or no /proc/self/smaps here";
    }
    for (const bool on : {true, false}) {
        const HugePagesSetting setting(on);
        LargeArray<std::uint8_t> big(std::size_t{40} << 20, std::uint8_t{1});
        const std::string flags = vmFlagsOf(big.data());
        ASSERT_FALSE(flags.empty());
        EXPECT_EQ(hasFlag(flags, "hg"), on) << flags;
    }
}

TEST(LargeArray, AWorldStepsToTheSameBitsWithAndWithoutHugePages) {
    // 200 x 200 tiles: the records (152 bytes of parameters a body) pass kLargeArrayBytes.
    constexpr int kSide = 200, kSteps = 90;
    std::uint64_t advised = 0, plain = 0;
    const std::size_t before = detail::largeArrayAllocationCount();
    {
        const HugePagesSetting on(true);
        advised = stepGridWorld(kSide, kSteps);
    }
    EXPECT_GT(detail::largeArrayAllocationCount(), before) << "the world took no large array: the test proves nothing";
    {
        const HugePagesSetting off(false);
        plain = stepGridWorld(kSide, kSteps);
    }
    EXPECT_EQ(advised, plain);
}

TEST(LargeArray, ASteadyStepAllocatesNothing) {
    const HugePagesSetting on(true);
    World world;
    BodyDef tile;
    tile.type = BodyType::Static;
    tile.shape = Shape::box({Real(0.5), Real(0.25), Real(0.5)});
    for (int i = 0; i < 200; ++i) {
        for (int j = 0; j < 200; ++j) {
            tile.position = {Real(i) - 100, 0, Real(j) - 100};
            world.createBody(tile);
        }
    }
    BodyDef ball;
    ball.shape = Shape::sphere(Real(0.3));
    ball.mass = 2;
    for (int k = 0; k < 20; ++k) {
        ball.position = {Real(k % 5) * Real(1.5), Real(0.6), Real(k / 5) * Real(1.5)};
        world.createBody(ball);
    }
    for (int s = 0; s < 120; ++s) world.step(Real(1) / 60);  // settles; every buffer sized
    const std::size_t large = detail::largeArrayAllocationCount();
    test::CountAllocations count;
    for (int s = 0; s < 60; ++s) world.step(Real(1) / 60);
    EXPECT_EQ(count.stop(), 0);
    EXPECT_EQ(detail::largeArrayAllocationCount(), large);
}
