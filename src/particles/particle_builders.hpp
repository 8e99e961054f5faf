#pragma once
// Builders: turn the scene-format definitions (RopeDef, ClothDef) into
// particle systems with their constraints. They validate everything and throw
// fulcrum::Error naming the system and the field.
#include "fulcrum/particles.hpp"
#include "particles/particle_system.hpp"

namespace fulcrum {

// N + 1 particles evenly spaced from start to end; N stretch constraints
// (i, i+1), N - 1 bend constraints (i, i+2) - a distance across two segments,
// so bendCompliance 0 makes a stiff rod and a positive one a floppy rope.
// Pinned ends get inverse mass 0; attached ends keep their mass and are tied to
// the body (attachment wins over the pin flag of the same end).
ParticleSystem buildRope(const RopeDef& def);

// size[0] x size[1] particles, (i, j) at origin + spacing * (i u + j v).
// Structural constraints on grid edges, shear on both cell diagonals, bend
// across two cells along each axis; two triangles per cell for aerodynamics.
ParticleSystem buildCloth(const ClothDef& def);

// Index of cloth particle (i, j).
inline std::uint32_t clothParticle(const ParticleSystem& cloth, int i, int j) {
    return static_cast<std::uint32_t>(j * cloth.gridSize[0] + i);
}

}  // namespace fulcrum
