#include "dynamics/body_mass.hpp"
#include "math/real_bits.hpp"

#include <algorithm>

namespace fulcrum::detail {

bool isSymmetricPositiveDefinite(const Mat3& m) {
    if (!isFinite(m)) return false;
    const Real scale = std::max({std::fabs(m(0, 0)), std::fabs(m(1, 1)), std::fabs(m(2, 2)), Real(1e-30)});
    const Real tol = Real(1e-5) * scale;
    if (std::fabs(m(0, 1) - m(1, 0)) > tol || std::fabs(m(0, 2) - m(2, 0)) > tol || std::fabs(m(1, 2) - m(2, 1)) > tol) {
        return false;
    }
    const Real m1 = m(0, 0);
    const Real m2 = m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0);
    return m1 > 0 && m2 > 0 && determinant(m) > 0;
}

BodyMass computeBodyMass(const BodyDef& def, const Subject& who) {
    requireFinite(who, "mass", def.mass);
    requireFinite(who, "density", def.density);
    if (def.inertia && !isFinite(*def.inertia)) fail(who, "inertia", "must be finite");
    if (def.centerOfMass) requireFinite(who, "centerOfMass", *def.centerOfMass);

    BodyMass out;
    const bool hasVolume = !def.shape.staticOnly();
    if (def.type != BodyType::Dynamic) {
        // Only the centre of mass is kept. A plain sphere, box, capsule or
        // cylinder has it at its origin (Shape::massProperties leaves it at
        // zero): no need to work out a mass and inertia nobody reads (a
        // million static boxes: ~120 instructions a body).
        const ShapeType type = def.shape.type();
        const bool centred = def.shape.convexRadius() == 0 && (type == ShapeType::Sphere || type == ShapeType::Box ||
                                                                type == ShapeType::Capsule || type == ShapeType::Cylinder);
        if (hasVolume && !centred) out.localCenterOfMass = def.shape.massProperties(Real(1)).centerOfMass;
        return out;
    }

    if (def.mass < 0) fail(who, "mass", "must be positive for a dynamic body (or 0 to use density), got " + formatReal(def.mass));
    MassProperties mp;
    if (def.mass > 0) {
        // Scale the unit-density properties: the inertia scales linearly with mass
        // for a fixed geometry, so density does not matter here.
        mp = def.shape.massProperties(Real(1));
        if (!(mp.mass > 0)) fail(who, "shape", "has no volume, so mass cannot be distributed over it");
        const Real scale = def.mass / mp.mass;
        mp.inertia = mp.inertia * scale;
        mp.mass = def.mass;
    } else {
        if (!(def.density > 0)) {
            fail(who, "density", "must be positive for a dynamic body without an explicit mass, got " + formatReal(def.density));
        }
        mp = def.shape.massProperties(def.density);
    }
    if (!std::isfinite(mp.mass) || !(mp.mass > 0)) {
        fail(who, "mass", "must come out positive and finite, got " + formatReal(mp.mass) + " (check mass, density and shape size)");
    }
    if (!def.inertia && !isSymmetricPositiveDefinite(mp.inertia) && isSymmetricPositiveDefinite(def.shape.massProperties(Real(1)).inertia)) {
        // The shape is fine, so the mass made its inertia underflow (mass 1e-45 kg):
        // blame what the user wrote, not an inertia they never gave.
        const char* field = def.mass > 0 ? "mass" : "density";
        fail(who, field,
             "is too small for " + std::string(kRealPrecision) + " numbers: the inertia it gives this shape underflows (diagonal " +
                 formatVec({mp.inertia(0, 0), mp.inertia(1, 1), mp.inertia(2, 2)}) + "), got " +
                 formatReal(def.mass > 0 ? def.mass : def.density));
    }
    if (def.inertia) mp.inertia = *def.inertia;
    if (!isSymmetricPositiveDefinite(mp.inertia)) {
        fail(who, def.inertia ? "inertia" : "shape inertia",
             "must be a symmetric positive-definite matrix, got diagonal " +
                 formatVec({mp.inertia(0, 0), mp.inertia(1, 1), mp.inertia(2, 2)}));
    }
    out.mass = mp.mass;
    out.invMass = Real(1) / mp.mass;
    out.localCenterOfMass = def.centerOfMass ? *def.centerOfMass : mp.centerOfMass;
    out.localInertia = mp.inertia;
    out.invLocalInertia = inverseSymmetric(mp.inertia);
    return out;
}

}  // namespace fulcrum::detail
