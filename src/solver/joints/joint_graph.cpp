// Per-body joint lists: see joint_graph.hpp.
#include "solver/joints/joint_graph.hpp"

#include "solver/joint_data.hpp"

namespace fulcrum::detail {

namespace {

// The body slot at end 0 (A) or 1 (B) of a joint; UINT32_MAX for the static world.
std::uint32_t endOf(const JointDef& d, int end) {
    const BodyId id = end == 0 ? d.bodyA : d.bodyB;
    return id.isNull() ? UINT32_MAX : id.index;
}

}  // namespace

void JointGraph::link(std::uint32_t body, std::uint32_t jointSlot, int end) {
    if (head_.size() <= body) {
        head_.resize(body + 1, kNone);
        degree_.resize(body + 1, 0);
    }
    next_[2 * jointSlot + static_cast<std::uint32_t>(end)] = head_[body];
    head_[body] = jointSlot;
    ++degree_[body];
}

std::uint32_t& JointGraph::nextOf(const Joints& w, std::uint32_t jointSlot, std::uint32_t body) {
    return next_[2 * jointSlot + (endOf(w[jointSlot].def, 0) == body ? 0u : 1u)];
}

void JointGraph::add(const Joints& w, std::uint32_t jointSlot) {
    // In sync before this joint: it reused a free slot, or it was appended.
    const bool reused = jointSlots_ == w.size() && jointSlot < jointSlots_;
    const bool appended = jointSlots_ + 1 == w.size() && jointSlot == jointSlots_;
    if (!reused && !appended) {
        rebuild(w);  // out of sync (a snapshot load): start over, the new joint included
        return;
    }
    jointSlots_ = w.size();
    if (next_.size() < 2 * jointSlots_) next_.resize(2 * jointSlots_, kNone);
    const JointDef& d = w[jointSlot].def;
    for (int end = 0; end < 2; ++end) {
        const std::uint32_t body = endOf(d, end);
        if (body != UINT32_MAX) link(body, jointSlot, end);
    }
}

void JointGraph::remove(const Joints& w, std::uint32_t jointSlot) {
    if (!inSync(w)) return;  // the next rebuild leaves it out
    const JointDef& d = w[jointSlot].def;
    for (int end = 0; end < 2; ++end) {
        const std::uint32_t body = endOf(d, end);
        if (body == UINT32_MAX) continue;
        // Unlink: the lists are a body's few joints.
        std::uint32_t* at = &head_[body];
        while (*at != kNone && *at != jointSlot) at = &nextOf(w, *at, body);
        if (*at == kNone) continue;
        *at = next_[2 * jointSlot + static_cast<std::uint32_t>(end)];
        --degree_[body];
    }
}

void JointGraph::rebuild(const Joints& w) {
    head_.assign(head_.size(), kNone);
    degree_.assign(degree_.size(), 0);
    jointSlots_ = w.size();
    next_.assign(2 * jointSlots_, kNone);
    for (std::uint32_t k = 0; k < jointSlots_; ++k) {
        if (!w[k].alive) continue;
        const JointDef& d = w[k].def;
        for (int end = 0; end < 2; ++end) {
            const std::uint32_t body = endOf(d, end);
            if (body != UINT32_MAX) link(body, k, end);
        }
    }
}

bool JointGraph::inSync(const Joints& w) const { return jointSlots_ == w.size(); }

bool JointGraph::keepsApart(const Joints& w, std::uint32_t slotA, std::uint32_t slotB) const {
    const auto blocks = [&](const JointData& j, std::uint32_t a, std::uint32_t b) {
        if (!j.alive || !j.enabled || j.def.collideConnected) return false;
        const std::uint32_t ja = endOf(j.def, 0), jb = endOf(j.def, 1);
        return (ja == a && jb == b) || (ja == b && jb == a);
    };
    if (!inSync(w)) {
        for (const JointData& j : w) {
            if (blocks(j, slotA, slotB)) return true;
        }
        return false;
    }
    // Walk the shorter list.
    const std::uint32_t degreeA = slotA < degree_.size() ? degree_[slotA] : 0;
    const std::uint32_t degreeB = slotB < degree_.size() ? degree_[slotB] : 0;
    const std::uint32_t body = degreeA <= degreeB ? slotA : slotB;
    if (body >= head_.size()) return false;
    for (std::uint32_t k = head_[body]; k != kNone;) {
        const JointData& j = w[k];
        if (blocks(j, slotA, slotB)) return true;
        k = next_[2 * k + (endOf(j.def, 0) == body ? 0u : 1u)];
    }
    return false;
}

bool JointPairFilter::keepsApart(std::uint32_t slotA, std::uint32_t slotB) const {
    return graph != nullptr && graph->keepsApart(*joints, slotA, slotB);
}

}  // namespace fulcrum::detail
