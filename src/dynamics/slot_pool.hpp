#pragma once
// SlotPool: the objects a World hands out handles to (joints, springs,
// particle systems) in slots that are reused. Each slot carries a generation
// that changes when its object is destroyed, so a handle {index, generation}
// to a destroyed object is told apart from the object that reuses the slot.
// Free slots are kept on a stack: the slot freed last is filled first.
//
// The entries keep their own `alive` flag and `generation` (they derive from
// PoolSlot): the step walks every slot and skips the dead ones (the objects
// are few, so holes cost little), and snapshots save the slots as they are.
// A destroyed entry keeps its data (and its capacity) until the slot is
// filled again; callers reset what they need when they fill it.
//
// The generation wraps after 2^32 reuses of one slot; a handle kept that long
// would alias the new object, which no run comes near.
//
// Bodies are not pooled here: their slots map to dense arrays (world_impl.hpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/error.hpp"

namespace fulcrum::detail {

struct PoolSlot {
    bool alive = false;
    std::uint32_t generation = 0;
};

// What a handle points at (SlotPool::lookup).
enum class HandleState : std::uint8_t { Live, Null, OutOfRange, Stale };

template <class Entry, class Handle>
class SlotPool {
public:
    // All slots, live or not (skip `!alive`), in slot order.
    std::size_t size() const { return slots_.size(); }
    bool empty() const { return slots_.empty(); }
    Entry& operator[](std::size_t slot) { return slots_[slot]; }
    const Entry& operator[](std::size_t slot) const { return slots_[slot]; }
    auto begin() { return slots_.begin(); }
    auto end() { return slots_.end(); }
    auto begin() const { return slots_.begin(); }
    auto end() const { return slots_.end(); }

    std::size_t liveCount() const { return slots_.size() - free_.size(); }

    // The slot the next add() fills (messages name an object by its slot
    // before it is added).
    std::uint32_t nextSlot() const {
        return free_.empty() ? static_cast<std::uint32_t>(slots_.size()) : free_.back();
    }
    // Marks the next slot live and returns it; its other fields are as the
    // last object in it left them (or default-constructed for a new slot).
    Entry& add() {
        const std::uint32_t slot = nextSlot();
        if (slot == slots_.size()) {
            slots_.emplace_back();
        } else {
            free_.pop_back();
        }
        slots_[slot].alive = true;
        return slots_[slot];
    }
    Handle handleOf(std::uint32_t slot) const { return {slot, slots_[slot].generation}; }
    // Frees a live slot: its handles go stale.
    void remove(std::uint32_t slot) {
        slots_[slot].alive = false;
        ++slots_[slot].generation;
        free_.push_back(slot);
    }

    HandleState lookup(Handle id) const {
        if (id.isNull()) return HandleState::Null;
        if (id.index >= slots_.size()) return HandleState::OutOfRange;
        const Entry& e = slots_[id.index];
        return e.alive && e.generation == id.generation ? HandleState::Live : HandleState::Stale;
    }
    bool isLive(Handle id) const { return lookup(id) == HandleState::Live; }

    // The slots and the free stack as they are, for snapshots; check
    // consistent() after loading them.
    std::vector<Entry>& slots() { return slots_; }
    const std::vector<Entry>& slots() const { return slots_; }
    std::vector<std::uint32_t>& freeSlots() { return free_; }
    // Every free slot in range, dead and listed once, and every dead slot listed.
    bool consistent() const {
        std::vector<bool> listed(slots_.size(), false);
        for (std::uint32_t f : free_) {
            if (f >= slots_.size() || slots_[f].alive || listed[f]) return false;
            listed[f] = true;
        }
        for (std::size_t i = 0; i < slots_.size(); ++i) {
            if (!slots_[i].alive && !listed[i]) return false;
        }
        return true;
    }

private:
    std::vector<Entry> slots_;
    std::vector<std::uint32_t> free_;
};

// The live entry a handle names, or fulcrum::Error in the World's words:
// "<where>: null SpringId", "<where>: SpringId index 7 does not exist",
// "<where>: stale SpringId (index 3): that spring was destroyed (or one of its bodies was)".
template <class Entry, class Handle>
const Entry& resolveHandle(const SlotPool<Entry, Handle>& pool, Handle id, const char* where, const char* handleName,
                           const char* objectName) {
    switch (pool.lookup(id)) {
        case HandleState::Live: return pool[id.index];
        case HandleState::Null: throw Error(std::string(where) + ": null " + handleName);
        case HandleState::OutOfRange:
            throw Error(std::string(where) + ": " + handleName + " index " + std::to_string(id.index) + " does not exist");
        case HandleState::Stale: break;
    }
    throw Error(std::string(where) + ": stale " + handleName + " (index " + std::to_string(id.index) + "): that " +
                objectName + " was destroyed (or one of its bodies was)");
}

}  // namespace fulcrum::detail
