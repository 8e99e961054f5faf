#pragma once
// Mass, centre of mass and inertia of a body from its BodyDef.
#include "dynamics/validation.hpp"
#include "fulcrum/body.hpp"

namespace fulcrum::detail {

struct BodyMass {
    Real mass = 0;                     // 0 for static and kinematic bodies
    Real invMass = 0;
    Vec3 localCenterOfMass;            // in the shape's frame
    Mat3 localInertia = Mat3::zero();  // about the centre of mass, body axes
    Mat3 invLocalInertia = Mat3::zero();
};

// Rules (world.hpp, body.hpp):
//  - dynamic: mass = def.mass if > 0 (the shape's inertia scaled by mass / shapeMass),
//    else density * volume; def.inertia overrides the shape's inertia. The result
//    must have positive finite mass and a symmetric positive-definite inertia.
//  - static / kinematic: infinite mass (inverse mass and inverse inertia zero); the
//    centre of mass still comes from the shape when it has one, so a kinematic body
//    spins about its centroid.
// Throws fulcrum::Error naming `who` and the field on bad input.
BodyMass computeBodyMass(const BodyDef& def, const Subject& who);

// Sylvester's criterion on a symmetric 3x3 matrix (all leading minors > 0).
bool isSymmetricPositiveDefinite(const Mat3& m);

}  // namespace fulcrum::detail
