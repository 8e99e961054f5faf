#pragma once
// All of Fulcrum's math types: Vec3, Mat3, Quat, Transform, AABB.
#include "fulcrum/math/aabb.hpp"
#include "fulcrum/math/mat3.hpp"
#include "fulcrum/math/quat.hpp"
#include "fulcrum/math/transform.hpp"
#include "fulcrum/math/vec3.hpp"
