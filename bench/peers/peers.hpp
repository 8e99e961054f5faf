#pragma once
// The peer engines of the side-by-side benchmark, each compiled in when its
// Debian package is installed (bench/peers/CMakeLists.txt defines
// FULCRUM_HAVE_<ENGINE>). Each builds bench/scenes.hpp's scenes at its own
// default settings; Engine::settings() says which.
#include <memory>

#include "../scenes.hpp"

namespace bench {
#ifdef FULCRUM_HAVE_BULLET
std::unique_ptr<Engine> makeBullet();  // bullet_scenes.cpp
#endif
#ifdef FULCRUM_HAVE_ODE
std::unique_ptr<Engine> makeOde();     // ode_scenes.cpp
#endif
#ifdef FULCRUM_HAVE_MUJOCO
std::unique_ptr<Engine> makeMujoco();  // mujoco_scenes.cpp
#endif
}  // namespace bench
