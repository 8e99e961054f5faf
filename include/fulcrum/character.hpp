#pragma once
// Character controllers (docs/characters.md): a kinematic capsule the World
// moves by a desired velocity, in the manner of Jolt's CharacterVirtual. It
// is not simulated by the solver: at the end of every World::step it moves
// itself with shape casts against the bodies (collide and slide), stands on
// walkable ground, slides down steeper ground, steps up stairs, sticks to the
// ground going down, rides the body it stands on, pushes dynamic bodies with
// a bounded force and jumps under gravity.
//
// The capsule stands along +y: "up" is +y and its segment is vertical.
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/id.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum {

// The collision category of a character's capsule body (World::characterBody):
// it collides only with other characters' capsules, so dynamic bodies never
// meet it in the solver (the character pushes them itself, with a bounded
// force); queries see it as any body, so characters block each other and
// ray casts hit them. Bodies of a user's own that use this category bit
// count as characters.
inline constexpr std::uint32_t kCharacterCategory = 1u << 30;

// A scripted input: from `time` (world time, s) on, until the next entry's time.
struct CharacterInput {
    Real time = 0;
    Vec3 velocity;      // m/s, desired; the y component is ignored (walking is horizontal)
    bool jump = false;  // held: jumps whenever on walkable ground
};

struct CharacterDef {
    std::string name;               // used in errors and outputs; also the capsule body's name
    Vec3 position;                  // capsule centre, world space
    Real radius = Real(0.3);        // m, > 0
    Real height = Real(1.8);        // m, the capsule's total height, >= 2 radius
    Real mass = 80;                 // kg, > 0: what a push shares with the body pushed
    Real maxSlope = Real(0.7853981633974483);  // rad, in (0, pi/2): steeper ground is not walkable
    Real stepHeight = Real(0.3);    // m, >= 0: the highest step climbed without jumping
    Real jumpSpeed = 5;             // m/s, >= 0: the upward speed a jump starts with
    Real maxPushForce = 500;        // N, >= 0: the most the character pushes a dynamic body with
    Real stickDistance = Real(0.5); // m, >= 0: walking off an edge this high or less keeps to the ground (stairs, slopes)
    // Optional script (World::setCharacterInput sets the held input in code).
    // Times finite and non-decreasing.
    std::vector<CharacterInput> inputs;
};

enum class GroundState : std::uint8_t {
    OnGround,       // standing on walkable ground (its slope at most maxSlope)
    OnSteepGround,  // touching ground too steep to stand on: slides down it
    InAir,          // nothing below within reach
};
const char* toString(GroundState state);  // "on_ground", "on_steep_ground", "in_air"

// What World::characterState reports, as of the end of the last step.
struct CharacterState {
    Vec3 position;                 // capsule centre
    Vec3 velocity;                 // m/s over the last step: its own motion plus the ground's
    GroundState ground = GroundState::InAir;
    Vec3 groundNormal;             // unit, of the supporting surface; zero in the air
    Vec3 groundVelocity;           // m/s of the ground body at the character; zero in the air
    BodyId groundBody;             // null in the air
};

}  // namespace fulcrum
