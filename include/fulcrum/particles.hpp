#pragma once
// Verlet particle systems: ropes and cloths. The definitions below are what the
// scene format's `ropes` and `cloths` sections describe (docs/scene-format.md).
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "fulcrum/body.hpp"

namespace fulcrum {

// The most particles one rope or cloth may have (docs/reliability.md, "Bad
// input"): beyond any real system, it makes a typo an error instead of an
// allocation that the system's memory cannot hold.
inline constexpr std::int64_t kMaxParticlesPerSystem = 100000000;

// N segments, N + 1 particles evenly spaced from start to end.
struct RopeDef {
    std::string name;
    Vec3 start;
    Vec3 end{1, 0, 0};
    int segments = 10;
    Real particleMass = Real(0.1);
    Real radius = Real(0.02);
    bool pinStart = true;
    bool pinEnd = false;
    BodyId attachStart = kWorldBody;  // tie an end to a rigid body (null: not attached)
    BodyId attachEnd = kWorldBody;
    Real stretchCompliance = 0;       // m/N (XPBD): 0 is inextensible
    Real bendCompliance = 0;

    // Extensions (not in the scene contract; defaults keep the contract's behaviour).
    Real damping = 0;                 // 1/s: velocity *= 1 / (1 + h c) each sub-step
    Real friction = Real(0.5);        // against rigid shapes; combined with the body's by geometric mean
    Real attachCompliance = 0;        // m/N of the attachments to bodies (0: rigid tie)
    bool tethers = false;             // long-range tethers from pinned ends (Kim et al. 2012)
};

// Particle (i, j) starts at origin + spacing * (i * uAxis + j * vAxis), 0 <= i < size[0], 0 <= j < size[1].
struct ClothDef {
    std::string name;
    Vec3 origin;
    Vec3 uAxis{1, 0, 0};
    Vec3 vAxis{0, 0, 1};
    std::array<int, 2> size{16, 16};
    Real spacing = Real(0.1);
    Real particleMass = Real(0.01);
    Real radius = Real(0.02);
    std::vector<std::array<int, 2>> pinned;
    Real stretchCompliance = 0;       // m/N (XPBD) of structural (grid-edge) constraints
    Real bendCompliance = 0;          // m/N of the bend constraints ((i,j)-(i+2,j), (i,j)-(i,j+2)); 0 is a stiff plate

    // Extensions (not in the scene contract; defaults keep the contract's behaviour).
    std::optional<Real> shearCompliance;  // m/N of the diagonal constraints; empty: stretchCompliance
    Real damping = 0;                 // 1/s: velocity *= 1 / (1 + h c) each sub-step
    Real friction = Real(0.5);        // against rigid shapes; combined with the body's by geometric mean
    bool selfCollision = true;        // particle-particle contacts between non-neighbouring particles
    bool tethers = false;             // long-range tethers to the nearest pin (Kim et al. 2012)
    Real dragCoefficient = 0;         // aerodynamic drag of each triangle (flat plate: about 1)
    Real liftCoefficient = 0;         // aerodynamic lift of each triangle
};

// The figures of one rope or cloth (the `particle_systems` entry of `--json`;
// World::particleReport).
struct ParticleReport {
    std::string name;
    std::size_t particles = 0;
    Vec3 centroid;                 // mean particle position, m
    Real maxStretch = 0;           // max over structural constraints of (length - rest) / rest
    Real meanStretch = 0;          // mean of the same (signed: compression counts negative)
    Real maxPenetration = 0;       // m: deepest any particle sphere sits inside a rigid shape (0 if none)
};

}  // namespace fulcrum
