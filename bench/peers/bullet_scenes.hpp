#pragma once
// Bullet 3 (Debian's libbullet-dev) running bench/scenes.hpp: engine defaults
// (btSequentialImpulseConstraintSolver, 10 iterations), one stepSimulation(dt, 0)
// per step (exactly one internal step of dt).
#include "../scenes.hpp"

namespace bench {
RunResult runBullet(const SceneSpec& scene);
}
