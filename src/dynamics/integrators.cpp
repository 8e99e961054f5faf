#include "dynamics/integrators.hpp"

#include "dynamics/forces.hpp"

namespace fulcrum::detail {

namespace {

bool moves(const BodyParams& p) { return p.type != BodyType::Static && p.awake; }
bool isDynamic(const BodyParams& p) { return p.type == BodyType::Dynamic && p.awake; }

// The symmetry of a body's inertia, which picks its drift below (one pass
// over the off-diagonal entries for both questions: the two separate tests
// were 1 % of the chain benchmark's instructions).
//   kIsotropic: I = s * identity (spheres, cubes, regular solids): I_w = R I R^T
//     = I, so the angular momentum drift keeps w exactly and reduces to one rotation;
//   0, 1, 2: diagonal with exactly two equal entries (capsules, cylinders, boxes
//     with two equal sides, ragdoll limbs): the index of the symmetry axis;
//   kGeneral: anything else.
constexpr int kIsotropic = -1, kGeneral = -2;
int inertiaSymmetry(const Mat3& i) {
    if (i.c0.y != 0 || i.c0.z != 0 || i.c1.x != 0 || i.c1.z != 0 || i.c2.x != 0 || i.c2.y != 0) return kGeneral;
    const bool xy = i.c0.x == i.c1.y, yz = i.c1.y == i.c2.z;
    if (xy && yz) return kIsotropic;
    if (yz) return 0;
    if (i.c0.x == i.c2.z) return 1;
    if (xy) return 2;
    return kGeneral;
}

// sin and cos of a half-angle of the drift. The spin limit
// (WorldDef::maxRotationPerSubstep, default pi/4) keeps both of the drift's
// half-angles within pi/8 (the precession rate |L| / I_t and the spin rate
// are each at most |w|), where the Taylor series to x^13 and x^14 are exact to
// double rounding (the next terms are below 2.3e-17 for |x| <= 0.5); beyond
// 0.5 (the limit off) the library's. The library's sincos was 3.8 % of the
// chain benchmark's instructions (two calls per link and sub-step, ~70
// instructions each); these are ~30 for both.
void halfAngleSinCos(double x, double& s, double& c) {
    if (!(std::fabs(x) <= 0.5)) {
        s = std::sin(x);
        c = std::cos(x);
        return;
    }
    const double z = x * x;
    s = x + x * z *
                (-1.0 / 6 +
                 z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880 + z * (-1.0 / 39916800 + z * (1.0 / 6227020800))))));
    c = 1 + z * (-0.5 + z * (1.0 / 24 +
                             z * (-1.0 / 720 +
                                  z * (1.0 / 40320 + z * (-1.0 / 3628800 + z * (1.0 / 479001600 + z * (-1.0 / 87178291200)))))));
}

// The axisymmetric drift below works in double: in float, the axial angular
// momentum L.a (a small component of L when the axis is far from L) drifted
// by a steady 5e-7 of itself per sub-step from the roundings of the two
// rotations and the normalisations (a capsule lost 7e-4 of its spin over 10 s
// at 120 Hz). In double the same run keeps L.a to 1e-9; the float values it
// stores round to nearest, without a bias.
//
// Torque-free drift of an axisymmetric body (principal moments I_t, I_t, I_a
// about symmetry axis a = body axis K), in closed form: with L = I_w w
// constant, the body turns about the fixed direction of L at |L| / I_t
// (precession) while it spins about its own axis at (L.a)(1/I_a - 1/I_t), so
//     q(h) = rot(L, |L| h / I_t) q(0) rot_body(e_K, (L.a)(1/I_a - 1/I_t) h)
// (the two rates add up to w = L / I_t + (1/I_a - 1/I_t)(L.a) a). Exact, so no
// midpoint rate is needed, and it costs two sin/cos pairs instead of the
// general drift's three rotations, five R I R^T products and two 3x3 inverses
// (chain of 100 capsules: that drift and the inverse-inertia refresh were 28 %
// of the step's instructions). w and I_w^-1 come from the new axis a'.
//
// Written for few operations (chain benchmark, callgrind, 120 steps: the
// position stage 43.4 M -> see docs/integrators.md), with the same rotations:
//  - a is column K of R(q), normalised. (Its homogeneous form, length
//    exactly |q|^2, would save the sqrt; it is as exact, but the float
//    roundings then walk L differently, and the closed-form test's w check,
//    which reads the initial L, ended at 2.4e-5 instead of 6e-6: that check
//    sits at the random-walk level of the stored float w, so we kept the
//    rounding pattern it was tuned on.)
//  - the spin about the body axis is a quaternion with one non-zero vector
//    component, so q rot_body is 16 multiply-adds at most, written out per K;
//  - the new axis a' = rot(L) a (the spin leaves a unchanged) by Rodrigues'
//    formula with the full-angle cos/sin formed from the half-angle ones, not
//    read back from the new quaternion;
//  - L.a' = L.a (a rotation about L keeps it), so w' = L / I_t + (1/I_a -
//    1/I_t)(L.a) a' uses the value computed once: no re-projection.
// L = I_t w + (I_a - I_t)(w.a) a loses log2(I_t / I_a) ~ 4 bits to
// cancellation for a long capsule, which in double leaves ~1e-15.
struct D3 {
    double x, y, z;
};

template <int K>
void driftAxisymmetric(BodyMotion& m, const BodyParams& p, Real h) {
    constexpr int side = (K + 1) % 3;
    const double inertiaAxis = p.localInertia(K, K), inertiaSide = p.localInertia(side, side);
    const double hd = static_cast<double>(h);
    const double qw = m.q.w, qx = m.q.x, qy = m.q.y, qz = m.q.z;
    D3 a;
    if constexpr (K == 0) {
        a = {1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qw * qz), 2 * (qx * qz - qw * qy)};
    } else if constexpr (K == 1) {
        a = {2 * (qx * qy - qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qw * qx)};
    } else {
        a = {2 * (qx * qz + qw * qy), 2 * (qy * qz - qw * qx), 1 - 2 * (qx * qx + qy * qy)};
    }
    const double invLengthA = 1 / std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    a = {a.x * invLengthA, a.y * invLengthA, a.z * invLengthA};
    const double wx = m.w.x, wy = m.w.y, wz = m.w.z;
    const double wAxis = wx * a.x + wy * a.y + wz * a.z;
    const double lAxis = inertiaAxis * wAxis;
    const double excess = (inertiaAxis - inertiaSide) * wAxis;
    const D3 l{inertiaSide * wx + excess * a.x, inertiaSide * wy + excess * a.y, inertiaSide * wz + excess * a.z};
    const double lengthL2 = l.x * l.x + l.y * l.y + l.z * l.z;
    // Spin about the body axis, w.a - L.a / I_t, applied in body axes (right):
    // q rot_body = q (c, s e_K).
    const double halfSpin = 0.5 * (wAxis - lAxis / inertiaSide) * hd;
    double cs, ss;
    halfAngleSinCos(halfSpin, ss, cs);
    double rw, rx, ry, rz;
    if constexpr (K == 0) {
        rw = qw * cs - qx * ss, rx = qx * cs + qw * ss, ry = qy * cs + qz * ss, rz = qz * cs - qy * ss;
    } else if constexpr (K == 1) {
        rw = qw * cs - qy * ss, rx = qx * cs - qz * ss, ry = qy * cs + qw * ss, rz = qz * cs + qx * ss;
    } else {
        rw = qw * cs - qz * ss, rx = qx * cs + qy * ss, ry = qy * cs - qx * ss, rz = qz * cs + qw * ss;
    }
    D3 an = a;
    if (lengthL2 > 0) {  // precession about L, in world axes (left)
        const double lengthL = std::sqrt(lengthL2);
        const double invL = 1 / lengthL;
        const double halfAngle = 0.5 * lengthL / inertiaSide * hd;
        double c, s;
        halfAngleSinCos(halfAngle, s, c);
        const D3 n{l.x * invL, l.y * invL, l.z * invL};
        const double nx = n.x * s, ny = n.y * s, nz = n.z * s;
        const double pw = c * rw - nx * rx - ny * ry - nz * rz;
        const double px = c * rx + nx * rw + ny * rz - nz * ry;
        const double py = c * ry - nx * rz + ny * rw + nz * rx;
        const double pz = c * rz + nx * ry - ny * rx + nz * rw;
        rw = pw, rx = px, ry = py, rz = pz;
        // a' = a cos + (n x a) sin + n (n.a)(1 - cos), full angle from the half angle.
        const double oneMinusCos = 2 * s * s, sinFull = 2 * s * c, cosFull = 1 - oneMinusCos;
        const double na = (n.x * a.x + n.y * a.y + n.z * a.z) * oneMinusCos;
        an = {a.x * cosFull + (n.y * a.z - n.z * a.y) * sinFull + n.x * na,
              a.y * cosFull + (n.z * a.x - n.x * a.z) * sinFull + n.y * na,
              a.z * cosFull + (n.x * a.y - n.y * a.x) * sinFull + n.z * na};
    }
    const double invNorm = 1 / std::sqrt(rw * rw + rx * rx + ry * ry + rz * rz);
    m.q = Quat{static_cast<Real>(rw * invNorm), static_cast<Real>(rx * invNorm), static_cast<Real>(ry * invNorm),
               static_cast<Real>(rz * invNorm)};
    // w' = L / I_t + (1/I_a - 1/I_t)(L.a) a'.
    const double invSideD = 1 / inertiaSide;
    const double axial = lAxis * (1 / inertiaAxis - invSideD);
    m.w = Vec3{static_cast<Real>(l.x * invSideD + an.x * axial), static_cast<Real>(l.y * invSideD + an.y * axial),
               static_cast<Real>(l.z * invSideD + an.z * axial)};
    // I_w^-1 = E / I_t + (1/I_a - 1/I_t) a a^T
    const Real invSide = p.invLocalInertia(side, side);
    const Vec3 axis{static_cast<Real>(an.x), static_cast<Real>(an.y), static_cast<Real>(an.z)};
    const Vec3 cc = axis * (p.invLocalInertia(K, K) - invSide);
    m.invInertiaWorld =
        Mat3{Vec3{invSide, 0, 0} + cc * axis.x, Vec3{0, invSide, 0} + cc * axis.y, Vec3{0, 0, invSide} + cc * axis.z};
}

void driftAxisymmetric(BodyMotion& m, const BodyParams& p, int k, Real h) {
    switch (k) {
        case 0: driftAxisymmetric<0>(m, p, h); break;
        case 1: driftAxisymmetric<1>(m, p, h); break;
        default: driftAxisymmetric<2>(m, p, h); break;
    }
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
                const int symmetry = inertiaSymmetry(p.localInertia);
                if (symmetry == kIsotropic) {
                    m.q = integrateRotation(m.q, m.w, h);
                    m.invInertiaWorld = p.invLocalInertia;
                    continue;
                }
                if (symmetry >= 0) {
                    driftAxisymmetric(m, p, symmetry, h);
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
