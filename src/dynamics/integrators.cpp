#include "dynamics/integrators.hpp"

#include "dynamics/forces.hpp"

namespace fulcrum::detail {

namespace {

bool moves(const BodyParams& p) { return p.type != BodyType::Static && p.awake; }
bool isDynamic(const BodyParams& p) { return p.type == BodyType::Dynamic && p.awake; }

// I = s * identity (spheres, cubes, regular solids): I_w = R I R^T = I, so the
// angular momentum drift below keeps w exactly and reduces to one rotation.
bool isIsotropic(const Mat3& i) {
    return i.c0.y == 0 && i.c0.z == 0 && i.c1.x == 0 && i.c1.z == 0 && i.c2.x == 0 && i.c2.y == 0 &&
           i.c0.x == i.c1.y && i.c1.y == i.c2.z;
}

// I = diag with exactly two equal entries (capsules, cylinders, boxes with two
// equal sides, ragdoll limbs): returns the index of the symmetry axis, else -1.
// Isotropic inertia is handled before this is asked.
int axisymmetricAxis(const Mat3& i) {
    if (i.c0.y != 0 || i.c0.z != 0 || i.c1.x != 0 || i.c1.z != 0 || i.c2.x != 0 || i.c2.y != 0) return -1;
    if (i.c1.y == i.c2.z) return 0;
    if (i.c0.x == i.c2.z) return 1;
    if (i.c0.x == i.c1.y) return 2;
    return -1;
}

// The axisymmetric drift below works in double: in float, the axial angular
// momentum L.a (a small component of L when the axis is far from L) drifted
// by a steady 5e-7 of itself per sub-step from the roundings of the two
// rotations and the normalisations (a capsule lost 7e-4 of its spin over 10 s
// at 120 Hz). In double the same run keeps L.a to 1e-9; the float values it
// stores round to nearest, without a bias.
struct D3 {
    double x, y, z;
    D3 operator+(const D3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    D3 operator-(const D3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    D3 operator*(double s) const { return {x * s, y * s, z * s}; }
};
struct DQ {
    double w, x, y, z;
};
double dotD(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 normalizedD(const D3& a) { return a * (1 / std::sqrt(dotD(a, a))); }
DQ mulD(const DQ& a, const DQ& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// Body axis k in world coordinates, normalised: column k of R(q).
D3 bodyAxis(const DQ& q, int k) {
    D3 a;
    switch (k) {
        case 0: a = {1 - 2 * (q.y * q.y + q.z * q.z), 2 * (q.x * q.y + q.w * q.z), 2 * (q.x * q.z - q.w * q.y)}; break;
        case 1: a = {2 * (q.x * q.y - q.w * q.z), 1 - 2 * (q.x * q.x + q.z * q.z), 2 * (q.y * q.z + q.w * q.x)}; break;
        default: a = {2 * (q.x * q.z + q.w * q.y), 2 * (q.y * q.z - q.w * q.x), 1 - 2 * (q.x * q.x + q.y * q.y)}; break;
    }
    return normalizedD(a);
}

// Torque-free drift of an axisymmetric body (principal moments I_t, I_t, I_a
// about symmetry axis a), in closed form: with L = I_w w constant, the body
// turns about the fixed direction of L at |L| / I_t (precession) while it
// spins about its own axis at (L.a)(1/I_a - 1/I_t), so
//     q(h) = rot(L, |L| h / I_t) q(0) rot_body(e_k, (L.a)(1/I_a - 1/I_t) h)
// (the two rates add up to w = L / I_t + (1/I_a - 1/I_t)(L.a) a). Exact, so no
// midpoint rate is needed, and it costs two sin/cos pairs instead of the
// general drift's three rotations, five R I R^T products and two 3x3 inverses
// (chain of 100 capsules: that drift and the inverse-inertia refresh were 28 %
// of the step's instructions). w and I_w^-1 come from the new axis a'.
// w is split into its part along a and the rest, and L's parts are divided
// back by I_a and I_t (not formed as I_t w + (I_a - I_t)(w.a) a, which cancels
// badly for a long capsule, I_a ~ I_t / 15).
void driftAxisymmetric(BodyMotion& m, const BodyParams& p, int k, Real h) {
    const int side = (k + 1) % 3;
    const double inertiaAxis = p.localInertia(k, k), inertiaSide = p.localInertia(side, side);
    const DQ q0{m.q.w, m.q.x, m.q.y, m.q.z};
    const D3 w0{m.w.x, m.w.y, m.w.z};
    const D3 a = bodyAxis(q0, k);
    const double wAxis = dotD(w0, a);
    const double lAxis = inertiaAxis * wAxis;
    const D3 angularMomentum = (w0 - a * wAxis) * inertiaSide + a * lAxis;
    const double lengthL = std::sqrt(dotD(angularMomentum, angularMomentum));
    // Spin about the body axis, w.a - L.a / I_t, applied in body axes (right).
    const double halfSpin = 0.5 * (wAxis - lAxis / inertiaSide) * static_cast<double>(h);
    DQ spin{std::cos(halfSpin), 0, 0, 0};
    (k == 0 ? spin.x : k == 1 ? spin.y : spin.z) = std::sin(halfSpin);
    DQ q = mulD(q0, spin);
    if (lengthL > 0) {  // precession about L, in world axes (left)
        const double halfAngle = 0.5 * lengthL / inertiaSide * static_cast<double>(h);
        const D3 n = angularMomentum * (std::sin(halfAngle) / lengthL);
        q = mulD(DQ{std::cos(halfAngle), n.x, n.y, n.z}, q);
    }
    const double invNorm = 1 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w * invNorm, q.x * invNorm, q.y * invNorm, q.z * invNorm};
    m.q = Quat{static_cast<Real>(q.w), static_cast<Real>(q.x), static_cast<Real>(q.y), static_cast<Real>(q.z)};
    const D3 an = bodyAxis(q, k);
    const double lAxisNew = dotD(angularMomentum, an);
    const D3 w1 = (angularMomentum - an * lAxisNew) * (1 / inertiaSide) + an * (lAxisNew / inertiaAxis);
    m.w = Vec3{static_cast<Real>(w1.x), static_cast<Real>(w1.y), static_cast<Real>(w1.z)};
    // I_w^-1 = E / I_t + (1/I_a - 1/I_t) a a^T
    const Real invSide = p.invLocalInertia(side, side);
    const Vec3 axis{static_cast<Real>(an.x), static_cast<Real>(an.y), static_cast<Real>(an.z)};
    const Vec3 c = axis * (p.invLocalInertia(k, k) - invSide);
    m.invInertiaWorld =
        Mat3{Vec3{invSide, 0, 0} + c * axis.x, Vec3{0, invSide, 0} + c * axis.y, Vec3{0, 0, invSide} + c * axis.z};
}

void applyDamping(BodyMotion& m, const BodyParams& p, Real h) {
    // Implicit (unconditionally stable) exponential decay: v *= 1 / (1 + h c).
    if (p.linearDamping > 0) m.v *= Real(1) / (1 + h * p.linearDamping);
    if (p.angularDamping > 0) m.w *= Real(1) / (1 + h * p.angularDamping);
}

}  // namespace

void integrateVelocities(WorldImpl& w, Integrator method, Real h, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        const BodyParams& p = w.params[i];
        if (!isDynamic(p)) continue;
        BodyMotion& m = w.motion[i];
        const ForceTorque& ft = w.forces[i];
        switch (method) {
            case Integrator::ExplicitEuler: {
                // a(x_n, v_n), with the gyroscopic torque -w x I_w w evaluated at the old state.
                const Vec3 v0 = m.v, w0 = m.w;
                const Vec3 lw = worldInertia(m.q, p.localInertia) * m.w;
                m.v += ft.force * (m.invMass * h);
                m.w += m.invInertiaWorld * (ft.torque - cross(m.w, lw)) * h;
                applyDamping(m, p, h);
                w.scratch[i].dv = m.v - v0;
                w.scratch[i].dw = m.w - w0;
                break;
            }
            case Integrator::SemiImplicitEuler: {
                // The gyroscopic effect is not a torque here either: the position
                // stage turns the body at constant world angular momentum (as for
                // Verlet). Catto's implicit gyroscopic step, used before, bleeds
                // |L| at high spin: the demo's tumbling box lost 13 % of |L| in
                // 10 s at 240 Hz; with the constant-L drift it keeps it to ~1e-5.
                m.v += ft.force * (m.invMass * h);
                m.w += m.invInertiaWorld * ft.torque * h;
                applyDamping(m, p, h);
                break;
            }
            case Integrator::Verlet: {
                // First half kick. The gyroscopic effect is not a torque here: in
                // world axes dL/dt = tau, and the drift below turns the body at
                // constant L, which is where w x I w comes from.
                const Real half = Real(0.5) * h;
                m.v += ft.force * (m.invMass * half);
                m.w += m.invInertiaWorld * ft.torque * half;
                applyDamping(m, p, h);
                break;
            }
        }
    }
}

void integratePositions(WorldImpl& w, Integrator method, Real h, std::size_t begin, std::size_t end) {
    const Real maxTurn = w.settings.maxRotationPerSubstep;
    for (std::size_t k = begin; k < end; ++k) {
        const std::uint32_t i = w.awakeBodies[k];
        const BodyParams& p = w.params[i];
        if (!moves(p)) continue;
        BodyMotion& m = w.motion[i];
        if (p.type == BodyType::Kinematic) {
            m.com += m.v * h;
            m.q = integrateRotation(m.q, m.w, h);
            continue;
        }
        // The spin limit (WorldDef::maxRotationPerSubstep).
        if (const Real w2 = lengthSquared(m.w); w2 * h * h > maxTurn * maxTurn) m.w *= maxTurn / (std::sqrt(w2) * h);
        switch (method) {
            case Integrator::ExplicitEuler:
                // The old velocity: the current one minus what forces added this
                // sub-step. (A solver's correction, applied after the forces, is kept.)
                m.com += (m.v - w.scratch[i].dv) * h;
                m.q = integrateRotation(m.q, m.w - w.scratch[i].dw, h);
                break;
            case Integrator::SemiImplicitEuler:
            case Integrator::Verlet: {
                m.com += m.v * h;
                // Isotropic bodies: the drift below is exactly a rotation at
                // constant w (it cost ~45 % of sphere_pile's position stage and
                // ~20 % of its step: three R I R^T and two inverses per body).
                // Its world inverse inertia is the local one (no R I^-1 R^T below).
                if (isIsotropic(p.localInertia)) {
                    m.q = integrateRotation(m.q, m.w, h);
                    m.invInertiaWorld = p.invLocalInertia;
                    continue;
                }
                if (const int axis = axisymmetricAxis(p.localInertia); axis >= 0) {
                    driftAxisymmetric(m, p, axis, h);
                    continue;
                }
                // Torque-free drift at constant world angular momentum L = I_w(q) w.
                // The rotation rate is taken at the midpoint orientation (second
                // order); afterwards w = I_w(q_new)^-1 L.
                // L and w are mapped with the same matrix I_w = R I R^T and its
                // adjugate inverse, so the round trip w -> L -> w' -> L' returns L
                // up to unbiased rounding. (Mapping back with the quaternion rotate()
                // instead leaves a ~1-ulp *bias* per sub-step from the unit-length
                // assumption: |L| drifted by 1.5e-4 over 1,920 sub-steps; now ~1e-6.)
                const Vec3 angularMomentum = worldInertia(m.q, p.localInertia) * m.w;
                const Quat qMid = integrateRotation(m.q, m.w, Real(0.5) * h);
                const Vec3 omegaMid = inverse(worldInertia(qMid, p.localInertia)) * angularMomentum;
                m.q = integrateRotation(m.q, omegaMid, h);
                m.w = inverse(worldInertia(m.q, p.localInertia)) * angularMomentum;
                break;
            }
        }
        w.updateWorldInertia(i);
    }
}

void finalizeSubstep(WorldImpl& w, Integrator method, Real h, double timeAfter) {
    if (method != Integrator::Verlet) return;
    const Real half = Real(0.5) * h;
    // Velocity-dependent forces (drag, spring damping, callbacks) at the new
    // position need a velocity there, which the second kick is about to
    // produce. Evaluate them at the predictor v_half + a_old h/2 (the velocity
    // the kick would give if the acceleration did not change): the error is
    // O(h^2) in the force, so the scheme stays second order.
    for (const std::uint32_t i : w.awakeBodies) {
        if (!isDynamic(w.params[i])) continue;
        BodyMotion& m = w.motion[i];
        w.scratch[i].dv = m.v;
        w.scratch[i].dw = m.w;
        m.v += w.forces[i].force * (m.invMass * half);
        m.w += m.invInertiaWorld * w.forces[i].torque * half;
    }
    evaluateForces(w, timeAfter);
    for (const std::uint32_t i : w.awakeBodies) {
        if (!isDynamic(w.params[i])) continue;
        BodyMotion& m = w.motion[i];
        m.v = w.scratch[i].dv + w.forces[i].force * (m.invMass * half);
        m.w = w.scratch[i].dw + m.invInertiaWorld * w.forces[i].torque * half;
    }
}

}  // namespace fulcrum::detail
