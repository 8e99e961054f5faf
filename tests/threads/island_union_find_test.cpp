// The islands' concurrent union-find (src/islands/sleep.hpp): linked from
// several threads at once, in any order, it must give every element the
// smallest index of its connected component, which is what the serial
// union-find gives (and what a breadth-first search finds), for every thread
// count and scheduler. The sleep manager relies on that for bit-identical
// islands, tags and island sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "islands/sleep.hpp"
#include "threads/reverse_scheduler.hpp"
#include "threads/thread_pool.hpp"

using namespace fulcrum;

namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;

// Chains of neighbours (like towers and rows of a pile), a few long random
// links that merge them into larger islands, and isolated elements.
std::vector<Edge> pileLikeGraph(std::uint32_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::uint32_t> any(0, n - 1);
    std::uniform_int_distribution<int> percent(0, 99);
    std::vector<Edge> edges;
    for (std::uint32_t i = 0; i + 1 < n; ++i) {
        if (percent(rng) < 70) edges.emplace_back(i + 1, i);  // either order: the link picks the smaller root
    }
    for (std::uint32_t k = 0; k < n / 50; ++k) {
        const std::uint32_t b = any(rng), a = any(rng);  // drawn last argument first, as GCC evaluated the call: the same cases with every compiler
        edges.emplace_back(a, b);
    }
    std::shuffle(edges.begin(), edges.end(), rng);
    return edges;
}

// Every element's component labelled by its smallest element, by breadth-first search.
std::vector<std::uint32_t> smallestOfComponent(std::uint32_t n, const std::vector<Edge>& edges) {
    std::vector<std::vector<std::uint32_t>> adjacent(n);
    for (const auto& [a, b] : edges) {
        adjacent[a].push_back(b);
        adjacent[b].push_back(a);
    }
    std::vector<std::uint32_t> label(n, UINT32_MAX), queue;
    for (std::uint32_t s = 0; s < n; ++s) {  // ascending: s is its component's smallest element
        if (label[s] != UINT32_MAX) continue;
        label[s] = s;
        queue.assign(1, s);
        for (std::size_t q = 0; q < queue.size(); ++q) {
            for (const std::uint32_t o : adjacent[queue[q]]) {
                if (label[o] == UINT32_MAX) {
                    label[o] = s;
                    queue.push_back(o);
                }
            }
        }
    }
    return label;
}

// The sleep manager's two passes: unions over the edges, then each element's root.
std::vector<std::uint32_t> rootsInParallel(TaskSystem& tasks, std::uint32_t n, const std::vector<Edge>& edges) {
    std::vector<std::uint32_t> parent(n), root(n);
    for (std::uint32_t i = 0; i < n; ++i) parent[i] = i;
    tasks.parallelFor(static_cast<std::uint32_t>(edges.size()), 16, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t k = begin; k < end; ++k) detail::uniteConcurrently(parent.data(), edges[k].first, edges[k].second);
    });
    tasks.parallelFor(n, 16, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t i = begin; i < end; ++i) root[i] = detail::findRootConcurrently(parent.data(), i);
    });
    return root;
}

std::vector<std::unique_ptr<TaskSystem>> allSchedulers() {
    std::vector<std::unique_ptr<TaskSystem>> s;
    s.push_back(std::make_unique<InlineTaskSystem>());
    s.push_back(std::make_unique<test::ReverseScheduler>());
    for (std::uint32_t threads : {2u, 3u, 4u, 8u}) s.push_back(makeThreadPool(ThreadPoolDef{threads, 2000, 4}));
    return s;
}

// A broken scheduler: runs every range but the last (to show the comparison catches a lost range).
class DropLastRange final : public TaskSystem {
public:
    std::uint32_t workerCount() const noexcept override { return 2; }
    void parallelFor(std::uint32_t count, std::uint32_t minRange, RangeFn fn) override {
        const std::uint32_t step = minRange == 0 ? 1 : minRange;
        for (std::uint32_t begin = 0; begin + step < count; begin += step) fn(begin, begin + step, 0);
    }
};

}  // namespace

TEST(IslandUnionFind, RootsAreEachComponentsSmallestElementForEveryScheduler) {
    constexpr std::uint32_t n = 20000;
    for (const std::uint32_t seed : {1u, 2u, 3u}) {
        const std::vector<Edge> edges = pileLikeGraph(n, seed);
        const std::vector<std::uint32_t> expected = smallestOfComponent(n, edges);
        for (const auto& tasks : allSchedulers()) {
            // Repeated: the pool's interleavings differ from run to run.
            for (int repeat = 0; repeat < 3; ++repeat) {
                const std::vector<std::uint32_t> roots = rootsInParallel(*tasks, n, edges);
                std::uint32_t mismatches = 0;
                for (std::uint32_t i = 0; i < n; ++i) mismatches += roots[i] != expected[i] ? 1u : 0u;
                EXPECT_EQ(mismatches, 0u) << "seed " << seed << ", " << tasks->workerCount() << " workers";
            }
        }
    }
}

TEST(IslandUnionFind, OneHubLinkedFromAllThreadsAtOnce) {
    // Every element joined to element n - 1 and to a neighbour: all threads
    // race on the same few roots (the CAS retries), and the whole set must end
    // as one island rooted at 0.
    constexpr std::uint32_t n = 4096;
    std::vector<Edge> edges;
    for (std::uint32_t i = 0; i + 1 < n; ++i) {
        edges.emplace_back(n - 1, i);
        edges.emplace_back(i, (i * 2654435761u) % n);
    }
    for (const auto& tasks : allSchedulers()) {
        const std::vector<std::uint32_t> roots = rootsInParallel(*tasks, n, edges);
        std::uint32_t notZero = 0;
        for (const std::uint32_t r : roots) notZero += r != 0 ? 1u : 0u;
        EXPECT_EQ(notZero, 0u) << tasks->workerCount() << " workers";
    }
}

TEST(IslandUnionFind, ALostRangeOfUnionsIsCaught) {
    constexpr std::uint32_t n = 2000;
    const std::vector<Edge> edges = pileLikeGraph(n, 7);
    const std::vector<std::uint32_t> expected = smallestOfComponent(n, edges);
    DropLastRange broken;
    EXPECT_NE(rootsInParallel(broken, n, edges), expected);
}
