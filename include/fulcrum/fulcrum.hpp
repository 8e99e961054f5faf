#pragma once
// Fulcrum: a 3D rigid-body physics engine. Include this for the whole public API.
#include "fulcrum/body.hpp"
#include "fulcrum/character.hpp"
#include "fulcrum/error.hpp"
#include "fulcrum/joint.hpp"
#include "fulcrum/math.hpp"
#include "fulcrum/particles.hpp"
#include "fulcrum/query.hpp"
#include "fulcrum/shape.hpp"
#include "fulcrum/spring.hpp"
#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
