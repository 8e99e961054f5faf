#pragma once
// ParticleSystem: the data of one rope, cloth or free particle set.
//
// Particles are stored as a structure of arrays: the solver streams through
// positions, displacements and inverse masses, and only those. The velocity
// is implicit in position Verlet, v = (x - x_prev) / h_prev; it is kept as
// the displacement d = x - x_prev over the last sub-step (not as x_prev),
// because in float the tiny per-sub-step change of d (g h^2 ~ 1.1e-5 m at
// 16 sub-steps of 1/60 s) is lost to rounding when it is added to a position
// far from the origin: with x_prev stored, a particle falling from y = 10
// gained only 98.55 % of g t (particle_integration.hpp).
//
// Constraints are arrays of small structs grouped by kind, each group with one
// XPBD compliance (m/N, the inverse of a stiffness): the solver reads a
// constraint's two indices and rest length together, so they sit together.
//
// Nothing here allocates during a step: every array is sized when the system
// is built, and the scratch buffers (Lagrange multipliers, self-collision
// pairs, the spatial hash) keep their capacity from step to step.
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/math.hpp"

namespace fulcrum {

// |x_a - x_b| = restLength, solved with the group's compliance.
struct DistanceConstraint {
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    Real restLength = 0;
};

struct DistanceConstraintGroup {
    std::vector<DistanceConstraint> constraints;
    // XPBD Lagrange multipliers (N s^2). Kept for source compatibility: the
    // solver keeps its own, in colour order (xpbd_distance.hpp); must match constraints' length.
    std::vector<Real> lambda;
    Real compliance = 0;       // m/N; 0 is rigid
    // Unilateral groups only pull (C = |x_a - x_b| - L <= 0 is allowed): tethers.
    bool unilateral = false;

    void add(std::uint32_t a, std::uint32_t b, Real restLength) {
        constraints.push_back({a, b, restLength});
        lambda.push_back(0);
    }
    std::size_t size() const { return constraints.size(); }
};

// A particle held at a world point (inverse mass 0). Move the target to drag it.
struct ParticlePin {
    std::uint32_t particle = 0;
    Vec3 target;
};

// A particle tied to a rigid body: |x - (body transform * localAnchor)| = 0,
// solved with `compliance`, pulling both ways.
struct ParticleAttachment {
    std::uint32_t particle = 0;
    std::uint32_t body = 0;     // body index in the RigidCollider
    Vec3 localAnchor;           // in the body's frame (resolved when the system joins a ParticleWorld)
    Real compliance = 0;        // m/N
    Real lambda = 0;            // scratch
    bool resolved = false;      // localAnchor computed from the particle's position
    const char* field = "attach";  // for error messages ("attach_start", ...)
};

// Damped spring force element between two particles:
// F = -k (L - L0) n - c (v_rel . n) n (the same law as the rigid-body springs).
struct ParticleSpring {
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    Real restLength = 0;  // m
    Real stiffness = 0;   // N/m
    Real damping = 0;     // N s/m
};

struct ParticleTriangle {
    std::uint32_t a = 0, b = 0, c = 0;
};

enum class ParticleSystemKind : std::uint8_t { Rope, Cloth, Particles };
const char* toString(ParticleSystemKind kind);  // "rope", "cloth", "particles"

struct ParticleSystem {
    std::string name;
    ParticleSystemKind kind = ParticleSystemKind::Particles;
    int gridSize[2] = {0, 0};  // cloth: particle (i, j) has index j * gridSize[0] + i

    // ---- particles (structure of arrays, one entry per particle)
    std::vector<Vec3> position;          // x_n
    std::vector<Vec3> displacement;      // x_n - x_{n-1}, m over the last sub-step (previousSubstep)
    std::vector<Vec3> restPosition;      // as built: defines rest distances for self-collision
    std::vector<Vec3> force;             // user forces, N; cleared after each step
    std::vector<Real> inverseMass;       // 1/kg; 0 = pinned or infinitely heavy
    std::vector<Real> radius;            // m: collision sphere of each particle

    // ---- constraints
    DistanceConstraintGroup stretch;     // structural: the stretch metric is measured on these
    DistanceConstraintGroup shear;
    DistanceConstraintGroup bend;
    DistanceConstraintGroup tethers;     // unilateral long-range attachments (Kim, Chentanez, Müller 2012)
    std::vector<ParticlePin> pins;
    std::vector<ParticleAttachment> attachments;
    std::vector<ParticleSpring> springs;
    std::vector<ParticleTriangle> triangles;  // cloth surface, for aerodynamics

    // ---- material
    Real damping = 0;          // 1/s
    Real linearDrag = 0;       // N s/m per particle: F = -b v
    Real friction = Real(0.5); // Coulomb coefficient against rigid shapes
    Real dragCoefficient = 0;  // aerodynamic, per triangle
    Real liftCoefficient = 0;
    bool selfCollision = false;
    // Pairs whose rest distance is below this never self-collide: they are
    // neighbours in the rest mesh, held apart by the distance constraints.
    Real selfCollisionExclusion = 0;

    // ---- state kept between steps
    Real previousSubstep = 0;  // h of the last sub-step (0 before the first): Verlet's time-step ratio

    std::size_t particleCount() const { return position.size(); }
    // Velocity over the last sub-step, (x - x_prev) / h_prev; zero before the first step.
    Vec3 velocity(std::size_t i) const {
        return previousSubstep > 0 ? displacement[i] / previousSubstep : Vec3::zero();
    }
    Real mass(std::size_t i) const { return inverseMass[i] > 0 ? 1 / inverseMass[i] : 0; }
};

// Appends one free particle (mass 0 pins it in place); returns its index.
std::uint32_t addParticle(ParticleSystem& system, const Vec3& position, Real mass, Real radius);
// Changes a particle's mass (> 0, finite) - e.g. a heavy bob at the end of a rope. Throws fulcrum::Error.
void setParticleMass(ParticleSystem& system, std::uint32_t particle, Real mass);
// Teleports a particle, at rest (zero displacement).
void setParticlePosition(ParticleSystem& system, std::uint32_t particle, const Vec3& position);
// Sets a particle's velocity as the displacement velocity * h (h: the sub-step it will be read with).
void setParticleVelocity(ParticleSystem& system, std::uint32_t particle, const Vec3& velocity, Real substep);
// Pins a particle at its current position (inverse mass 0); throws if the index is outside the system.
void pinParticle(ParticleSystem& system, std::uint32_t particle);
// Adds a spring force element between two particles; validated, throws fulcrum::Error.
void addParticleSpring(ParticleSystem& system, const ParticleSpring& spring);
// Ties a particle to rigid body `bodyIndex`; the local anchor is computed from
// the particle's position when the system joins a ParticleWorld.
void attachParticle(ParticleSystem& system, std::uint32_t particle, std::uint32_t bodyIndex, Real compliance,
                    const char* field = "attach");
// Adds tethers from every free particle to the nearest pinned particle, with
// rest length (1 + slack) times their rest distance.
void addTethers(ParticleSystem& system, Real slack = 0);

}  // namespace fulcrum
