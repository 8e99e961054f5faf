#pragma once
// The static ground slab the thread tests build their piles on: top face y = 0.
#include "fulcrum/world.hpp"

namespace fulcrum::test {

inline BodyId addGroundSlab(World& world) {
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({40, 1, 40});
    ground.position = {0, -1, 0};
    return world.createBody(ground);
}

}  // namespace fulcrum::test
