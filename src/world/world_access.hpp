#pragma once
// The way from a fulcrum::World to its WorldImpl for the engine's own code
// (snapshots, io, the Python binding, tests, benchmarks). Internal: the public
// header names no accessor a user could call, and this header is not installed.
#include "fulcrum/world.hpp"
#include "world/world_impl.hpp"

namespace fulcrum::detail {

struct WorldAccess {
    static WorldImpl& impl(World& world) { return *world.impl_; }
    static const WorldImpl& impl(const World& world) { return *world.impl_; }
};

inline WorldImpl& implOf(World& world) { return WorldAccess::impl(world); }
inline const WorldImpl& implOf(const World& world) { return WorldAccess::impl(world); }

}  // namespace fulcrum::detail
