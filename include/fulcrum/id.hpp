#pragma once
// Handles to the objects a World owns (bodies, joints, springs, particle
// systems): a slot index and the slot's generation. The generation changes
// when a slot is reused, so a handle to a destroyed object is detected (World
// throws) instead of aliasing a new one. The tag only makes each kind its own
// type, so a JointId cannot be passed where a BodyId is expected.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>

namespace fulcrum {

template <class Tag>
struct Id {
    static constexpr std::uint32_t kNullIndex = std::numeric_limits<std::uint32_t>::max();

    std::uint32_t index = kNullIndex;
    std::uint32_t generation = 0;

    constexpr bool isNull() const { return index == kNullIndex; }
    constexpr bool operator==(const Id&) const = default;
};

using BodyId = Id<struct BodyTag>;
using JointId = Id<struct JointTag>;
using SpringId = Id<struct SpringTag>;
using ParticleSystemId = Id<struct ParticleSystemTag>;
using CharacterId = Id<struct CharacterTag>;

}  // namespace fulcrum

// Handles as keys of unordered containers.
template <class Tag>
struct std::hash<fulcrum::Id<Tag>> {
    std::size_t operator()(const fulcrum::Id<Tag>& id) const noexcept {
        return std::hash<std::uint64_t>{}((std::uint64_t(id.generation) << 32) | id.index);
    }
};
