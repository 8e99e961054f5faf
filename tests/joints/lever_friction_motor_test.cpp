// Joint friction, motors and reaction forces on a lever: a body whose centre
// is r from its joint, so the joint's torque turns it about the joint
// (inertia I_cm + m r^2), not about its centre (I_cm). Checked for a rod
// (I_cm = m L^2 / 12) and a small sphere (I_cm << m r^2, the hard case), with
// the tree solver on and off (WorldDef::jointDirectSolve).
#include <algorithm>
#include <cmath>
#include <string>

#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

constexpr double kMass = 1;
constexpr double kLever = 0.5;  // m, joint to centre

// A horizontal lever along +x with its joint at the origin: a 1 m rod
// (centre at 0.5 m) or a 5 cm sphere at 0.5 m. Inertia about the joint's z axis.
struct Lever {
    BodyDef body;
    double inertiaAboutJoint = 0;
};

Lever rod() {
    Lever l{boxBody(Real(kMass), {Real(kLever), 0, 0}, {Real(kLever), Real(0.02), Real(0.02)}), 0};
    const double L = 2 * kLever, t = 0.04;
    l.inertiaAboutJoint = kMass * (L * L + t * t) / 12 + kMass * kLever * kLever;
    return l;
}

Lever sphere() {
    Lever l{sphereBody(Real(kMass), {Real(kLever), 0, 0}, Real(0.05)), 0};
    l.inertiaAboutJoint = 0.4 * kMass * 0.05 * 0.05 + kMass * kLever * kLever;
    return l;
}

WorldDef world(bool direct) {
    WorldDef d = worldDef();
    d.jointDirectSolve = direct;
    return d;
}

// The lever's angle about z from horizontal (its centre's position about the joint).
double angleOf(const World& w, BodyId b) {
    const Vec3 p = w.position(b);
    return std::atan2(double(p.y), double(p.x));
}

constexpr double kGravityTorque = kMass * kG * kLever;  // 4.905 N m

// Steps 1 s and checks that the joint reports the static load it carries:
// force m g up and torque m g r about z (1 %), nothing across.
void expectReportsStaticLoad(World& w, JointId id, const std::string& what) {
    for (int i = 0; i < 60; ++i) w.step(kDt);
    const Vec3 f = w.jointReactionForce(id), t = w.jointReactionTorque(id);
    EXPECT_NEAR(f.y / (kMass * kG), 1, 0.01) << what;
    EXPECT_LT(std::hypot(f.x, f.z), 0.01 * kMass * kG) << what;
    EXPECT_NEAR(t.z / kGravityTorque, 1, 0.01) << what;
    EXPECT_LT(std::hypot(t.x, t.y), 0.01 * kGravityTorque) << what;
}

}  // namespace

// Dry friction T > m g r holds the lever (the angle moves < 1 mrad in 5 s; measured 0.3 mrad, the soft point rows' sag);
// T < m g r lets it fall with alpha = (m g r - T) / (I_cm + m r^2) at the
// start (3 %, from the first step's spin). Hinge (axis z), ball and
// cone-twist joints (twist axis along the lever, no cone), both solver paths.
TEST(LeverFriction, HoldsAboveAndSlipsBelowTheGravityTorque) {
    for (const JointType type : {JointType::Hinge, JointType::Ball, JointType::ConeTwist}) {
        for (const bool direct : {true, false}) {
            for (const Lever& lever : {rod(), sphere()}) {
                for (const double factor : {1.2, 0.8}) {
                    World w(world(direct));
                    const BodyId b = w.createBody(lever.body);
                    JointDef j = jointDef(type, kWorldBody, b, {0, 0, 0}, type == JointType::ConeTwist ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
                    j.swingLimit = Real(kPi);
                    j.frictionTorque = Real(factor * kGravityTorque);
                    w.createJoint(j);
                    const std::string what = std::string(toString(type)) + (direct ? " tree" : " gauss-seidel") +
                                             " I_joint " + std::to_string(lever.inertiaAboutJoint) + " factor " +
                                             std::to_string(factor);
                    if (factor > 1) {
                        double drift = 0;
                        for (int i = 0; i < 300; ++i) {
                            w.step(kDt);
                            drift = std::max(drift, std::fabs(angleOf(w, b)));
                        }
                        EXPECT_LT(drift, 1e-3) << what;
                    } else {
                        w.step(kDt);
                        const double alpha = -double(w.angularVelocity(b).z) / double(kDt);
                        const double expected = (kGravityTorque - j.frictionTorque) / lever.inertiaAboutJoint;
                        EXPECT_NEAR(alpha / expected, 1, 0.03) << what << " alpha " << alpha;
                    }
                }
            }
        }
    }
}

// A hinge motor lifting the lever at 1 rad/s with max torque 2 m g r reaches
// its target speed (1 %) and keeps it; with max torque 0.8 m g r it can't
// lift: the lever falls with alpha = (m g r - T) / (I_cm + m r^2) (3 %).
TEST(LeverMotor, LiftsAtTargetSpeedWithinItsTorque) {
    for (const bool direct : {true, false}) {
        for (const Lever& lever : {rod(), sphere()}) {
            for (const double factor : {2.0, 0.8}) {
                World w(world(direct));
                const BodyId b = w.createBody(lever.body);
                JointDef j = jointDef(JointType::Hinge, kWorldBody, b, {0, 0, 0}, {0, 0, 1});
                j.motor = {true, 1, Real(factor * kGravityTorque)};
                w.createJoint(j);
                const std::string what = std::string(direct ? "tree" : "gauss-seidel") + " I_joint " +
                                         std::to_string(lever.inertiaAboutJoint) + " factor " + std::to_string(factor);
                if (factor > 1) {
                    // Full torque: (2 - 1) m g r / I reaches 1 rad/s within 0.06 s (rod) / 0.05 s (sphere).
                    for (int i = 0; i < 15; ++i) w.step(kDt);
                    EXPECT_NEAR(w.angularVelocity(b).z, 1, 0.01) << what;
                    for (int i = 0; i < 30; ++i) w.step(kDt);
                    EXPECT_NEAR(w.angularVelocity(b).z, 1, 0.01) << what;
                } else {
                    w.step(kDt);
                    const double alpha = -double(w.angularVelocity(b).z) / double(kDt);
                    const double expected = (kGravityTorque - factor * kGravityTorque) / lever.inertiaAboutJoint;
                    EXPECT_NEAR(alpha / expected, 1, 0.03) << what << " alpha " << alpha;
                }
            }
        }
    }
}

// A slider whose anchor is 0.5 m beside the block's centre (vertical axis):
// the motor, limited to 2 m g, lifts the block at 0.5 m/s (1 %); the angular
// lock keeps it from tipping, so the motor moves the block's whole mass.
TEST(LeverMotor, OffsetSliderMotorLifts) {
    for (const bool direct : {true, false}) {
        World w(world(direct));
        const BodyId b = w.createBody(boxBody(Real(kMass), {Real(kLever), 0, 0}, {Real(0.05), Real(0.05), Real(0.05)}));
        JointDef j = jointDef(JointType::Slider, kWorldBody, b, {0, 0, 0}, {0, 1, 0});
        j.motor = {true, Real(0.5), Real(2 * kMass * kG)};
        w.createJoint(j);
        for (int i = 0; i < 15; ++i) w.step(kDt);
        EXPECT_NEAR(w.linearVelocity(b).y, 0.5, 0.005) << direct;
        EXPECT_LT(length(w.angularVelocity(b)), 1e-3) << direct;
    }
}

// Reaction of a hinge (axis z) holding the static lever by friction or by a
// stalled motor: force m g up, torque m g r about z (1 %) — the torque the
// joint applies to the lever about its anchor.
TEST(LeverReaction, HingeHoldingALoadReportsMgAndMgr) {
    for (const bool direct : {true, false}) {
        for (const bool motor : {false, true}) {
            World w(world(direct));
            const BodyId b = w.createBody(rod().body);
            JointDef j = jointDef(JointType::Hinge, kWorldBody, b, {0, 0, 0}, {0, 0, 1});
            if (motor) {
                j.motor = {true, 0, Real(3 * kGravityTorque)};
            } else {
                j.frictionTorque = Real(3 * kGravityTorque);
            }
            const JointId id = w.createJoint(j);
            expectReportsStaticLoad(w, id, std::to_string(direct) + std::to_string(motor));
        }
    }
}

// The same for a ball and a cone-twist joint held by friction, and a hinge
// resting on its lower limit (the limit carries the torque).
TEST(LeverReaction, FrictionAndLimitLoadsAreReported) {
    for (const bool direct : {true, false}) {
        for (const JointType type : {JointType::Ball, JointType::ConeTwist, JointType::Hinge}) {
            World w(world(direct));
            const BodyId b = w.createBody(rod().body);
            JointDef j = jointDef(type, kWorldBody, b, {0, 0, 0}, type == JointType::ConeTwist ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
            j.swingLimit = Real(kPi);
            if (type == JointType::Hinge) {
                j.hasLimits = true;
                j.lowerLimit = 0;
                j.upperLimit = 1;
            } else {
                j.frictionTorque = Real(3 * kGravityTorque);
            }
            const JointId id = w.createJoint(j);
            expectReportsStaticLoad(w, id, std::string(toString(type)) + (direct ? " tree" : " gauss-seidel"));
        }
    }
}

// A block 0.5 m beside its vertical slider's anchor, held by a stalled motor
// (speed 0) or resting on the lower limit: the slider reports m g up and,
// from its angular lock, the moment m g r about z (1 %).
TEST(LeverReaction, OffsetSliderHoldingALoad) {
    for (const bool direct : {true, false}) {
        for (const bool motor : {true, false}) {
            World w(world(direct));
            const BodyId b = w.createBody(boxBody(Real(kMass), {Real(kLever), 0, 0}, {Real(0.05), Real(0.05), Real(0.05)}));
            JointDef j = jointDef(JointType::Slider, kWorldBody, b, {0, 0, 0}, {0, 1, 0});
            if (motor) {
                j.motor = {true, 0, Real(3 * kMass * kG)};
            } else {
                j.hasLimits = true;
                j.lowerLimit = 0;
                j.upperLimit = 1;
            }
            const JointId id = w.createJoint(j);
            expectReportsStaticLoad(w, id, std::to_string(direct) + std::to_string(motor));
        }
    }
}

// A lever spinning about a vertical hinge under its weight (the point and
// alignment rows carry m g and m g r) with dry friction T: the friction row,
// coupled to those rows, slows it at the constant rate T / (I_cm + m r^2), so
// the spin is w(t) = w0 - T t / I_joint until it stops. Bounded at every step
// of the run, not only at its end (the worst error over the run): the
// coupled row is kept from the step's start while the lever turns less than
// the guard (coupled_row.hpp) and coupled again at every position update
// past it, so each speed exercises another share of kept and fresh rows
// (0.2 rad/s: 0.0008 rad a sub-step, kept for the step; 2 rad/s: past the
// guard at the third sub-step; 20 rad/s: 0.08 rad a sub-step). Stopping
// in 1 s; the rate is checked from 0.1 s (the lever has taken its weight)
// to 0.75 s. Tolerance 1 % of w0 (measured worst: 0.5 %, at 20 rad/s; see
// docs/joints.md, "The hinge's coupled row once per step"). The rod only:
// a 5 cm sphere spinning on its lever is off by 1-80 % with the coupling
// redone every sub-step too (an open issue of the soft point rows, not of
// the coupling's reuse).
TEST(LeverFriction, SpinningHingeUnderLoadSlowsAtTheFrictionRate) {
    for (const bool direct : {true, false}) {
        {
            const Lever lever = rod();
            for (const double w0 : {0.2, 2.0, 20.0}) {
                World w(world(direct));
                const BodyId b = w.createBody(lever.body);
                JointDef j = jointDef(JointType::Hinge, kWorldBody, b, {0, 0, 0}, {0, 1, 0});
                const double rate = w0;  // rad/s^2: stops in 1 s
                j.frictionTorque = Real(rate * lever.inertiaAboutJoint);
                w.createJoint(j);
                // Spinning about the joint: v = w x r with r = (r, 0, 0).
                w.setAngularVelocity(b, {0, Real(w0), 0});
                w.setLinearVelocity(b, {0, 0, Real(-w0 * kLever)});
                const std::string what = std::string(direct ? "tree" : "gauss-seidel") + " I_joint " +
                                         std::to_string(lever.inertiaAboutJoint) + " w0 " + std::to_string(w0);
                // The first 0.1 s: the lever takes its weight (the soft rows' sag).
                constexpr int kSettle = 6;
                for (int i = 0; i < kSettle; ++i) w.step(kDt);
                const double start = double(w.angularVelocity(b).y);
                double worst = 0;
                for (int i = 1; i <= 39; ++i) {
                    w.step(kDt);
                    const double expected = start - rate * i * double(kDt);
                    worst = std::max(worst, std::fabs(double(w.angularVelocity(b).y) - expected) / w0);
                }
                EXPECT_LT(worst, 0.01) << what;
            }
        }
    }
}
