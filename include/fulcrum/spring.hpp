#pragma once
// Damped springs: force elements F = -k (L - L0) n - c (v_rel . n) n between
// anchor points, integrated by the world's integrator (unlike a soft distance
// joint, which the constraint solver handles).
#include <cstdint>
#include <limits>

#include "fulcrum/body.hpp"

namespace fulcrum {


struct SpringDef {
    BodyId bodyA = kWorldBody;  // null: anchored to the static world
    BodyId bodyB;
    Vec3 anchorA;               // world space at creation
    Vec3 anchorB;
    Real restLength = 0;        // >= 0; 0 is allowed (a zero-length spring)
    Real stiffness = 0;         // N/m, >= 0
    Real damping = 0;           // N s/m, >= 0
};

}  // namespace fulcrum
