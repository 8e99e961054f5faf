// Inverse dynamics of a robot tree: the recursive Newton-Euler algorithm
// (Featherstone, "Rigid Body Dynamics Algorithms", 2008, ch. 5.3), written
// with world-frame vectors. A forward pass carries each link's angular
// velocity and acceleration and its origin's linear acceleration out from
// the root (whose acceleration has -g added, so gravity needs no term of its
// own); each link's Newton-Euler force and torque follow; a backward pass
// sums them towards the root, and each joint's effort is the part along its
// axis. What reaches the root is the wrench its motion needs.
//
// A floating base (ch. 9.5): that wrench is linear in the base's
// acceleration a0, W(a0) = W(0) + I_c a0, with I_c the whole tree's
// composite inertia at the root. A free base takes no wrench but gravity, so
// a0 = -I_c^-1 W(0); the efforts follow from one more pass with that a0.
// I_c's columns are the wrenches of unit base accelerations in a pass with
// no velocity and no gravity (exact: the passes are linear in a0).
// docs/robots.md ("Inverse dynamics") says what it is checked against.
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "fulcrum/urdf.hpp"

namespace fulcrum {

struct Robot::Dynamics {
    static constexpr std::size_t kNone = ~std::size_t(0);

    // The root's motion: its frame, angular velocity and acceleration, and
    // its origin's linear acceleration minus gravity.
    struct Base {
        Vec3 origin;
        Quat frame;
        Vec3 w, alpha, a;
    };
    // Per robot joint: the effort; and the wrench the root needs (torque about its origin).
    struct Pass {
        std::vector<Real> effort;
        Vec3 force, torque;
    };

    const Robot& robot;
    std::vector<std::size_t> act, parentJoint, parentLink, order;
    std::size_t root = kNone;
    std::vector<Real> q, qd, qdd;  // per robot joint (0 for the unactuated)

    Dynamics(const Robot& r, const char* caller, std::span<const Real> qa, std::span<const Real> qda,
             std::span<const Real> qdda, bool staticRoot)
        : robot(r), act(r.actuatedJoints()) {
        const auto fail = [&](const std::string& what) { throw Error("robot '" + r.name + "': " + caller + ": " + what); };
        const auto requireSize = [&](std::span<const Real> v, const char* what) {
            if (v.size() != act.size()) {
                fail(std::to_string(v.size()) + " " + what + " for " + std::to_string(act.size()) +
                     " actuated joints (one per revolute, continuous or prismatic joint, in file order)");
            }
        };
        requireSize(qa, "positions");
        requireSize(qda, "velocities");
        requireSize(qdda, "accelerations");
        if (r.model_.size() != r.links.size()) fail("needs the robot as loaded by loadUrdf (its links' inertia)");
        // The tree: each link's parent joint, and an order with parents first.
        const std::size_t n = r.links.size();
        parentJoint.assign(n, kNone);
        parentLink.assign(n, kNone);
        const auto linkIndex = [&](const std::string& link) {
            for (std::size_t i = 0; i < n; ++i) {
                if (r.links[i].name == link) return i;
            }
            return kNone;
        };
        for (std::size_t k = 0; k < r.joints.size(); ++k) {
            const RobotJoint& j = r.joints[k];
            if (j.type == UrdfJointType::Floating || j.type == UrdfJointType::Planar) {
                fail("joint '" + j.name + "' is " + toString(j.type) +
                     " (only trees of revolute, continuous, prismatic and fixed joints; a floating base is a root "
                     "link loaded without a fixed base)");
            }
            const std::size_t c = linkIndex(j.child);
            parentJoint[c] = k;
            parentLink[c] = linkIndex(j.parent);
        }
        for (std::size_t i = 0; i < n; ++i) {
            if (parentJoint[i] != kNone) continue;
            const bool isStatic = !(r.model_[i].mass > 0);
            if (staticRoot && !isStatic) {
                fail("the root link '" + r.links[i].name +
                     "' is not static (load it with a fixed base, or use the floating-base inverse dynamics)");
            }
            if (!staticRoot && isStatic) {
                fail("the root link '" + r.links[i].name + "' is static (a fixed base: use inverseDynamics)");
            }
            root = i;
            order.push_back(i);
        }
        for (std::size_t at = 0; at < order.size(); ++at) {
            for (std::size_t c = 0; c < n; ++c) {
                if (parentLink[c] == order[at]) order.push_back(c);
            }
        }
        q.assign(r.joints.size(), 0);
        qd.assign(r.joints.size(), 0);
        qdd.assign(r.joints.size(), 0);
        for (std::size_t k = 0; k < act.size(); ++k) {
            q[act[k]] = qa[k];
            qd[act[k]] = qda[k];
            qdd[act[k]] = qdda[k];
        }
    }

    // One Newton-Euler pass from the base's motion; `moving` false: the
    // joints' velocities and accelerations taken as zero (the base's own
    // velocity and acceleration are as given).
    Pass run(const Base& base, bool moving) const {
        struct State {
            Vec3 origin;
            Quat frame;
            Vec3 w, alpha, a;     // `a`: the origin's linear acceleration
            Vec3 axis;            // the joint's axis in the world
            Vec3 force, torque;   // Newton-Euler, then summed over the subtree (torque about the origin)
        };
        const std::size_t n = robot.links.size();
        std::vector<State> s(n);
        for (const std::size_t i : order) {
            State& x = s[i];
            const std::size_t k = parentJoint[i];
            if (k == kNone) {
                x.origin = base.origin;
                x.frame = base.frame;
                x.w = base.w;
                x.alpha = base.alpha;
                x.a = base.a;
                continue;
            }
            const State& p = s[parentLink[i]];
            const RobotJoint& j = robot.joints[k];
            // The joint's frame in the parent's, from the pose the model was loaded in (q = 0).
            const LinkModel& mp = robot.model_[parentLink[i]];
            const LinkModel& mc = robot.model_[i];
            const Quat rel = conjugate(mp.frame) * mc.frame;
            const Vec3 offset = inverseRotate(mp.frame, mc.origin - mp.origin);
            const Vec3 axisChild = normalize(j.axis);  // URDF: in the joint (child) frame
            const Real qi = q[k], qdi = moving ? qd[k] : Real(0), qddi = moving ? qdd[k] : Real(0);
            const bool revolute = j.type == UrdfJointType::Revolute || j.type == UrdfJointType::Continuous;
            const bool prismatic = j.type == UrdfJointType::Prismatic;
            const Quat jointFrame = p.frame * rel;
            x.axis = rotate(jointFrame, axisChild);
            x.frame = revolute ? jointFrame * Quat::fromAxisAngle(axisChild, qi) : jointFrame;
            const Vec3 r = rotate(p.frame, offset) + (prismatic ? x.axis * qi : Vec3{});
            x.origin = p.origin + r;
            // The origin's acceleration through the parent (rigid lever r) and,
            // for a slider, its own motion along the axis (with its Coriolis term).
            x.a = p.a + cross(p.alpha, r) + cross(p.w, cross(p.w, r));
            x.w = p.w;
            x.alpha = p.alpha;
            if (revolute) {
                x.w = p.w + x.axis * qdi;
                x.alpha = p.alpha + x.axis * qddi + cross(p.w, x.axis * qdi);
            } else if (prismatic) {
                x.a += x.axis * qddi + cross(p.w, x.axis * qdi) * 2;
            }
        }
        // Each link's own Newton-Euler force and torque (about its origin).
        for (const std::size_t i : order) {
            State& x = s[i];
            const LinkModel& m = robot.model_[i];
            if (!(m.mass > 0)) continue;
            const Vec3 c = rotate(x.frame, m.centerOfMass);
            const Vec3 ac = x.a + cross(x.alpha, c) + cross(x.w, cross(x.w, c));
            const auto inertiaTimes = [&](const Vec3& u) { return rotate(x.frame, m.inertia * inverseRotate(x.frame, u)); };
            x.force = ac * m.mass;
            x.torque = inertiaTimes(x.alpha) + cross(x.w, inertiaTimes(x.w)) + cross(c, x.force);
        }
        // Backward: each link carries its subtree; the joint delivers the part along its axis.
        Pass out;
        out.effort.assign(robot.joints.size(), 0);
        for (std::size_t at = order.size(); at-- > 0;) {
            const std::size_t i = order[at];
            const std::size_t k = parentJoint[i];
            if (k == kNone) continue;
            const State& x = s[i];
            const RobotJoint& j = robot.joints[k];
            out.effort[k] = j.type == UrdfJointType::Prismatic ? dot(x.axis, x.force) : dot(x.axis, x.torque);
            State& p = s[parentLink[i]];
            p.force += x.force;
            p.torque += x.torque + cross(x.origin - p.origin, x.force);
        }
        out.force = s[root].force;
        out.torque = s[root].torque;
        return out;
    }

    // The actuated joints' efforts with the URDF damping and friction added.
    std::vector<Real> efforts(const std::vector<Real>& effort, const InverseDynamicsOptions& options) const {
        std::vector<Real> out;
        out.reserve(act.size());
        for (const std::size_t k : act) {
            const RobotJoint& j = robot.joints[k];
            Real tau = effort[k];
            if (options.damping) tau += j.damping * qd[k];
            if (options.friction && j.friction > 0) {
                const Real towards = qd[k] != 0 ? qd[k] : qdd[k];  // at rest: the way it breaks away
                tau += towards > 0 ? j.friction : (towards < 0 ? -j.friction : Real(0));
            }
            out.push_back(tau);
        }
        return out;
    }

    Base floatingBase(const World& world, const RobotBaseState& state, const Vec3& linear, const Vec3& angular) const {
        return {state.position, normalize(state.orientation), state.angularVelocity, angular, linear - world.settings().gravity};
    }
};

std::vector<Real> Robot::inverseDynamics(const World& world, std::span<const Real> q, std::span<const Real> qd,
                                         std::span<const Real> qdd, const InverseDynamicsOptions& options) const {
    const Dynamics d(*this, "inverseDynamics", q, qd, qdd, true);
    // The static root accelerates up at g: gravity on every link.
    const Dynamics::Base base{model_[d.root].origin, model_[d.root].frame, {}, {}, -world.settings().gravity};
    return d.efforts(d.run(base, true).effort, options);
}

FloatingBaseDynamics Robot::prescribedBaseInverseDynamics(const World& world, const RobotBaseState& state,
                                                          const Vec3& linearAcceleration, const Vec3& angularAcceleration,
                                                          std::span<const Real> q, std::span<const Real> qd,
                                                          std::span<const Real> qdd,
                                                          const InverseDynamicsOptions& options) const {
    const Dynamics d(*this, "prescribedBaseInverseDynamics", q, qd, qdd, false);
    const Dynamics::Pass pass = d.run(d.floatingBase(world, state, linearAcceleration, angularAcceleration), true);
    FloatingBaseDynamics out;
    out.efforts = d.efforts(pass.effort, options);
    out.linearAcceleration = linearAcceleration;
    out.angularAcceleration = angularAcceleration;
    out.force = pass.force;
    out.torque = pass.torque;
    return out;
}

FloatingBaseDynamics Robot::freeBaseInverseDynamics(const World& world, const RobotBaseState& state, std::span<const Real> q,
                                                    std::span<const Real> qd, std::span<const Real> qdd,
                                                    const InverseDynamicsOptions& options) const {
    const Dynamics d(*this, "freeBaseInverseDynamics", q, qd, qdd, false);
    // W(0): the wrench with the base not accelerating (gravity as an upward acceleration).
    const Dynamics::Pass still = d.run(d.floatingBase(world, state, {}, {}), true);
    // I_c column by column: the wrench of a unit base acceleration, nothing else moving.
    std::array<std::array<double, 6>, 6> Ic{};
    for (int c = 0; c < 6; ++c) {
        Dynamics::Base unit{state.position, normalize(state.orientation), {}, {}, {}};
        Vec3& axis = c < 3 ? unit.a : unit.alpha;
        (c % 3 == 0 ? axis.x : c % 3 == 1 ? axis.y : axis.z) = 1;
        const Dynamics::Pass p = d.run(unit, false);
        const Real column[6] = {p.force.x, p.force.y, p.force.z, p.torque.x, p.torque.y, p.torque.z};
        for (int r = 0; r < 6; ++r) Ic[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = double(column[r]);
    }
    // Solve I_c a0 = -W(0) (symmetric positive definite: Gaussian elimination with partial pivoting, double).
    std::array<double, 6> rhs = {-double(still.force.x), -double(still.force.y), -double(still.force.z),
                                 -double(still.torque.x), -double(still.torque.y), -double(still.torque.z)};
    for (std::size_t col = 0; col < 6; ++col) {
        std::size_t pivot = col;
        for (std::size_t r = col + 1; r < 6; ++r) {
            if (std::fabs(Ic[r][col]) > std::fabs(Ic[pivot][col])) pivot = r;
        }
        if (!(std::fabs(Ic[pivot][col]) > 0)) throw Error("robot '" + name + "': freeBaseInverseDynamics: the tree's inertia is singular");
        std::swap(Ic[pivot], Ic[col]);
        std::swap(rhs[pivot], rhs[col]);
        for (std::size_t r = col + 1; r < 6; ++r) {
            const double f = Ic[r][col] / Ic[col][col];
            for (std::size_t k = col; k < 6; ++k) Ic[r][k] -= f * Ic[col][k];
            rhs[r] -= f * rhs[col];
        }
    }
    std::array<double, 6> a0{};
    for (std::size_t r = 6; r-- > 0;) {
        double t = rhs[r];
        for (std::size_t k = r + 1; k < 6; ++k) t -= Ic[r][k] * a0[k];
        a0[r] = t / Ic[r][r];
    }
    const Vec3 linear{Real(a0[0]), Real(a0[1]), Real(a0[2])}, angular{Real(a0[3]), Real(a0[4]), Real(a0[5])};
    FloatingBaseDynamics out = prescribedBaseInverseDynamics(world, state, linear, angular, q, qd, qdd, options);
    // The wrench left is the solve's rounding; the answer's is zero by definition.
    out.force = {};
    out.torque = {};
    return out;
}

RobotBaseState Robot::baseState(const World& world) const {
    for (std::size_t i = 0; i < links.size(); ++i) {
        bool isRoot = true;
        for (const RobotJoint& j : joints) isRoot = isRoot && j.child != links[i].name;
        if (!isRoot) continue;
        const BodyId body = links[i].body;
        if (body.isNull()) break;
        return {world.position(body), world.orientation(body), world.angularVelocity(body)};
    }
    throw Error("robot '" + name + "': baseState: the root link has no body");
}

}  // namespace fulcrum
