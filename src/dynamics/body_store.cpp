#include "dynamics/body_store.hpp"

#include <algorithm>

#include "dynamics/pose_lanes.hpp"
#include "dynamics/validation.hpp"

namespace fulcrum::detail {

std::uint32_t BodyStore::resolveBody(BodyId id, const char* where) const {
    if (id.isNull()) throw Error(std::string(where) + ": null BodyId (the world body is not a body here)");
    if (id.index >= bodySlots.size()) {
        throw Error(std::string(where) + ": BodyId index " + std::to_string(id.index) + " does not exist (" +
                    std::to_string(bodySlots.size()) + " body slots)");
    }
    const BodySlot& slot = bodySlots[id.index];
    if (slot.dense == kNoIndex || slot.generation != id.generation) {
        throw Error(std::string(where) + ": stale BodyId (index " + std::to_string(id.index) + ", generation " +
                    std::to_string(id.generation) + "): that body was destroyed");
    }
    return slot.dense;
}

std::string BodyStore::describeBody(std::uint32_t dense) const {
    return Subject{"body", cold[dense].name, denseToSlot[dense]}.describe();
}

void BodyStore::wakeBody(std::uint32_t dense) {
    BodyParams& p = params[dense];
    if (p.type == BodyType::Static) return;
    p.sleepTime = 0;
    if (p.awake) return;
    const auto queue = [this](std::uint32_t d) {
        if (wokenBodies.size() >= motion.size()) {
            awakeListRebuild = true;  // (cannot happen between two refreshes; a bound, not a path)
            wokenBodies.clear();
        }
        if (!awakeListRebuild) wokenBodies.push_back(d);
    };
    const std::uint32_t island = p.sleepIsland;
    if (island == 0) {
        p.awake = true;
        queue(dense);
        return;
    }
    // The island's bodies wake together (a linear scan: waking is an event, not per step).
    for (std::uint32_t d = 0; d < params.size(); ++d) {
        BodyParams& q = params[d];
        if (q.sleepIsland != island) continue;
        q.awake = true;
        q.sleepTime = 0;
        q.sleepIsland = 0;
        queue(d);
    }
}

void BodyStore::reserveAwakeList(std::size_t bodyCount) {
    // The eleven capacities, checked on every creation, were 87 instructions
    // a body of a million static boxes: only the smallest room left is
    // compared now (the buffers only grow, and only here).
    if (bodyCount <= awakeListRoom) return;
    // Geometric growth: reserving exactly on every creation would reallocate every time.
    const auto grow = [](auto& v, std::size_t n) {
        if (v.capacity() < n) v.reserve(std::max(n, 2 * v.capacity()));
    };
    // Each buffer grows to `bodyCount + extra` and leaves room for as many bodies as it holds less `extra`.
    std::size_t room = SIZE_MAX;
    const auto growAll = [&](std::size_t extra, auto&... buffers) {
        ((grow(buffers, bodyCount + extra), room = std::min(room, buffers.capacity() - extra)), ...);
    };
    growAll(0, awakeBodies, wokenBodies, awakeMergeScratch, previousStale, solverOfDense);
    growAll(1, inAwakeList, contactDeltas, motionKind, state, pose, startCom, startQ, denseOfSolver);
    awakeListRoom = room;
}

void BodyStore::refreshAwakeList() {
    const auto count = static_cast<std::uint32_t>(motion.size());
    if (awakeListRebuild) {
        awakeBodies.clear();
        inAwakeList.assign(count, 0);
        for (std::uint32_t d = 0; d < count; ++d) {
            if (params[d].type == BodyType::Static || !params[d].awake) continue;
            awakeBodies.push_back(d);
            inAwakeList[d] = 1;
        }
        wokenBodies.clear();
        awakeListRebuild = false;
        awakeListHasSleepers = false;
        return;
    }
    if (awakeListHasSleepers) {
        std::size_t kept = 0;
        for (const std::uint32_t d : awakeBodies) {
            if (params[d].awake) {
                awakeBodies[kept++] = d;
            } else {
                inAwakeList[d] = 0;
            }
        }
        awakeBodies.resize(kept);
        awakeListHasSleepers = false;
    }
    if (wokenBodies.empty()) return;
    // The newly woken, sorted, merged into the sorted list from the back (in place, no allocation).
    awakeMergeScratch.clear();
    for (const std::uint32_t d : wokenBodies) {
        if (!params[d].awake || inAwakeList[d] != 0) continue;
        inAwakeList[d] = 1;
        awakeMergeScratch.push_back(d);
    }
    wokenBodies.clear();
    if (awakeMergeScratch.empty()) return;
    std::sort(awakeMergeScratch.begin(), awakeMergeScratch.end());
    std::size_t a = awakeBodies.size(), b = awakeMergeScratch.size();
    awakeBodies.resize(a + b);
    std::size_t out = a + b;
    while (b > 0) {
        if (a > 0 && awakeBodies[a - 1] > awakeMergeScratch[b - 1]) {
            awakeBodies[--out] = awakeBodies[--a];
        } else {
            awakeBodies[--out] = awakeMergeScratch[--b];
        }
    }
}

namespace {

// updateDeltas(i) for the solver bodies [first, last] that `wanted` keeps,
// the rotation vectors four at a time (stepRotationVectors).
template <class Wanted>
void updateDeltasInLanes(BodyStore& b, std::size_t first, std::size_t last, Wanted&& wanted) {
    const Quat* q[4];
    const Quat* start[4];
    Vec3* out[4];
    int n = 0;
    for (std::size_t i = first; i <= last; ++i) {
        if (!wanted(i)) continue;
        b.state[i].dp = b.pose[i].com - b.startCom[i];
        q[n] = &b.pose[i].q;
        start[n] = &b.startQ[i];
        out[n] = &b.state[i].dtheta;
        if (++n == 4) {
            stepRotationVectors(q, start, out, 4);
            n = 0;
        }
    }
    if (n > 0) stepRotationVectors(q, start, out, n);
}

}  // namespace

void BodyStore::updateDeltas(std::size_t begin, std::size_t end) {
    updateDeltasInLanes(*this, begin + 1, end, [](std::size_t) { return true; });
}

void BodyStore::updateContactDeltas(std::size_t begin, std::size_t end) {
    updateDeltasInLanes(*this, begin + 1, end, [this](std::size_t i) { return contactDeltas[i] != 0; });
}

void BodyStore::writeRecords(std::size_t begin, std::size_t end) {
    for (std::size_t i = begin + 1; i <= end; ++i) {
        BodyMotion& m = motion[denseOfSolver[i]];
        const BodyPose& p = pose[i];
        m.com = p.com;
        m.q = p.q;
        m.invInertiaWorld = p.invInertiaWorld;
        // A kinematic body's velocity is the user's: the kernels never change it.
        if (state[i].invMass == 0) continue;
        m.v = state[i].v;
        m.w = state[i].w;
    }
}

}  // namespace fulcrum::detail
