#pragma once
// Deterministic parallel patterns on top of any TaskSystem.
//
// A TaskSystem only promises that every index is processed once; how [0, count)
// is cut into ranges and which worker runs which range depends on the thread
// count and on timing. Results must not. The two patterns the step needs:
//
//  * BlockReduction: a sum (or any fold) over [0, count) cut into blocks of a
//    fixed size chosen by the caller, never by the thread count. Each block is
//    folded left to right by one call, the block results are stored by block
//    index, and the caller's thread folds them in block order. Floating-point
//    sums are therefore bit-identical for 1, 2, ... N threads (and for any
//    user scheduler): the sequence of additions is a function of count and
//    blockSize only.
//
//  * WorkerBuffers: each worker appends its outputs (new pairs, contact begin
//    events, ...) to its own buffer without locks; mergeInIndexOrder then
//    concatenates them ordered by the index range that produced them, which is
//    exactly the order a single thread would have produced.
//
// Both reuse their storage: after the first call of a given size nothing
// allocates.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "fulcrum/task_system.hpp"

namespace fulcrum::detail {

template <class T>
class BlockReduction {
public:
    // Storage for a count of this size and block size, allocated ahead of time.
    void reserve(std::uint32_t count, std::uint32_t blockSize) { partials_.reserve(blockCount(count, blockSize)); }

    // Returns combine(...combine(combine(init, b0), b1)..., bn) where bk =
    // foldBlock(k * blockSize, min((k + 1) * blockSize, count)) computes block
    // k's partial result (left to right). foldBlock runs in parallel and must
    // be safe to call concurrently; combine runs on the calling thread.
    template <class FoldBlock, class Combine>
    T run(TaskSystem& tasks, std::uint32_t count, std::uint32_t blockSize, T init, FoldBlock&& foldBlock,
          Combine&& combine) {
        const std::uint32_t blocks = blockCount(count, blockSize);
        partials_.resize(blocks);
        T* partials = partials_.data();
        tasks.parallelFor(blocks, 1, [&](std::uint32_t first, std::uint32_t last, std::uint32_t) {
            for (std::uint32_t b = first; b < last; ++b) {
                const std::uint32_t begin = b * blockSize;
                const std::uint32_t end = count - begin > blockSize ? begin + blockSize : count;
                partials[b] = foldBlock(begin, end);
            }
        });
        T result = init;
        for (std::uint32_t b = 0; b < blocks; ++b) result = combine(result, partials[b]);
        return result;
    }

    static std::uint32_t blockCount(std::uint32_t count, std::uint32_t blockSize) noexcept {
        blockSize = std::max(blockSize, 1u);
        return count / blockSize + (count % blockSize != 0 ? 1u : 0u);
    }

private:
    std::vector<T> partials_;
};

template <class T>
class WorkerBuffers {
public:
    // Empties every buffer (keeping capacity) and sizes for workerCount workers.
    void reset(std::uint32_t workerCount) {
        if (workers_.size() != workerCount) workers_.resize(workerCount);
        for (Worker& w : workers_) {
            w.items.clear();
            w.segments.clear();
        }
    }

    // Call at the start of each range function, with the range's first index,
    // then append that range's outputs in index order to the returned buffer.
    // (Calling it more often, e.g. per index, is fine: keys must only be unique.)
    std::vector<T>& beginRange(std::uint32_t workerIndex, std::uint32_t rangeBegin) {
        Worker& w = workers_[workerIndex];
        w.segments.push_back({rangeBegin, workerIndex, static_cast<std::uint32_t>(w.items.size()), 0});
        return w.items;
    }

    // Replaces out's contents with every worker's outputs ordered by range
    // start: the order a single thread running [0, count) would produce.
    void mergeInIndexOrder(std::vector<T>& out) {
        merged_.clear();
        std::size_t total = 0;
        for (Worker& w : workers_) {
            for (std::size_t s = 0; s < w.segments.size(); ++s) {
                Segment seg = w.segments[s];
                seg.end = s + 1 < w.segments.size() ? w.segments[s + 1].begin : static_cast<std::uint32_t>(w.items.size());
                total += seg.end - seg.begin;
                merged_.push_back(seg);
            }
        }
        std::sort(merged_.begin(), merged_.end(),
                  [](const Segment& a, const Segment& b) { return a.rangeBegin < b.rangeBegin; });
        out.clear();
        out.reserve(total);
        for (const Segment& seg : merged_) {
            const std::vector<T>& items = workers_[seg.worker].items;
            out.insert(out.end(), items.begin() + seg.begin, items.begin() + seg.end);
        }
    }

    // Each worker's buffer grows to the largest share it has taken so far, and
    // which worker takes how much depends on timing. To allocate nothing from
    // the first call on, reserve (after reset) the worst case: every item and
    // every range of a call landing on one worker.
    void reserve(std::size_t itemsPerWorker, std::size_t rangesPerCall) {
        for (Worker& w : workers_) {
            w.items.reserve(itemsPerWorker);
            w.segments.reserve(rangesPerCall);
        }
        merged_.reserve(rangesPerCall);
    }

private:
    struct Segment {
        std::uint32_t rangeBegin;  // first index of the range that produced it
        std::uint32_t worker;
        std::uint32_t begin, end;  // in the worker's items
    };
    // One cache line per worker: the vectors' size fields change on every push.
    struct alignas(64) Worker {
        std::vector<T> items;
        std::vector<Segment> segments;
    };
    std::vector<Worker> workers_;
    std::vector<Segment> merged_;
};

}  // namespace fulcrum::detail
