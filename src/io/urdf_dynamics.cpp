// Inverse dynamics of a fixed-base robot tree: the recursive Newton-Euler
// algorithm (Featherstone, "Rigid Body Dynamics Algorithms", 2008, ch. 5.3),
// written with world-frame vectors. A forward pass carries each link's
// angular velocity and acceleration and its origin's linear acceleration out
// from the static root (whose acceleration is -g, so gravity needs no term of
// its own); each link's Newton-Euler force and torque follow; a backward pass
// sums them towards the root, and each joint's effort is the part along its
// axis. docs/robots.md ("Inverse dynamics") says what it is checked against.
#include <string>
#include <vector>

#include "fulcrum/urdf.hpp"

namespace fulcrum {

std::vector<Real> Robot::inverseDynamics(const World& world, std::span<const Real> q, std::span<const Real> qd,
                                         std::span<const Real> qdd) const {
    const std::vector<std::size_t> act = actuatedJoints();
    const auto requireSize = [&](std::span<const Real> v, const char* what) {
        if (v.size() != act.size()) {
            throw Error("robot '" + name + "': inverseDynamics: " + std::to_string(v.size()) + " " + what + " for " +
                        std::to_string(act.size()) + " actuated joints (one per revolute, continuous or prismatic joint, in file order)");
        }
    };
    requireSize(q, "positions");
    requireSize(qd, "velocities");
    requireSize(qdd, "accelerations");
    if (model_.size() != links.size()) {
        throw Error("robot '" + name + "': inverseDynamics needs the robot as loaded by loadUrdf (its links' inertia)");
    }

    // The tree: each link's parent joint, and an order with parents first.
    const std::size_t n = links.size();
    constexpr std::size_t kNone = ~std::size_t(0);
    std::vector<std::size_t> parentJoint(n, kNone), linkOf(joints.size(), kNone), parentLink(n, kNone);
    const auto linkIndex = [&](const std::string& link) {
        for (std::size_t i = 0; i < n; ++i) {
            if (links[i].name == link) return i;
        }
        return kNone;
    };
    for (std::size_t k = 0; k < joints.size(); ++k) {
        const RobotJoint& j = joints[k];
        if (j.type == UrdfJointType::Floating || j.type == UrdfJointType::Planar) {
            throw Error("robot '" + name + "': inverseDynamics: joint '" + j.name + "' is " + toString(j.type) +
                        " (only fixed-base trees of revolute, continuous, prismatic and fixed joints)");
        }
        const std::size_t c = linkIndex(j.child);
        linkOf[k] = c;
        parentJoint[c] = k;
        parentLink[c] = linkIndex(j.parent);
    }
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < n; ++i) {
        if (parentJoint[i] != kNone) continue;
        if (model_[i].mass > 0) {
            throw Error("robot '" + name + "': inverseDynamics: the root link '" + links[i].name +
                        "' is not static (load it with a fixed base)");
        }
        order.push_back(i);
    }
    for (std::size_t at = 0; at < order.size(); ++at) {
        for (std::size_t c = 0; c < n; ++c) {
            if (parentLink[c] == order[at]) order.push_back(c);
        }
    }
    std::vector<Real> jointQ(joints.size(), 0), jointQd(joints.size(), 0), jointQdd(joints.size(), 0);
    for (std::size_t k = 0; k < act.size(); ++k) {
        jointQ[act[k]] = q[k];
        jointQd[act[k]] = qd[k];
        jointQdd[act[k]] = qdd[k];
    }

    // Forward: poses, velocities and accelerations (world frame; `a` the link
    // origin's linear acceleration, `axis` the joint's axis in the world).
    struct State {
        Vec3 origin;
        Quat frame;
        Vec3 w, alpha, a;
        Vec3 axis;
        Vec3 force, torque;  // Newton-Euler, then summed over the subtree (torque about the origin)
    };
    std::vector<State> s(n);
    for (const std::size_t i : order) {
        State& x = s[i];
        const std::size_t k = parentJoint[i];
        if (k == kNone) {
            x.origin = model_[i].origin;
            x.frame = model_[i].frame;
            x.a = -world.settings().gravity;  // the base accelerates up at g: gravity on every link
            continue;
        }
        const State& p = s[parentLink[i]];
        const RobotJoint& j = joints[k];
        // The joint's frame in the parent's, from the pose the model was loaded in (q = 0).
        const LinkModel& mp = model_[parentLink[i]];
        const LinkModel& mc = model_[i];
        const Quat rel = conjugate(mp.frame) * mc.frame;
        const Vec3 offset = inverseRotate(mp.frame, mc.origin - mp.origin);
        const Vec3 axisChild = normalize(j.axis);  // URDF: in the joint (child) frame
        const Real qi = jointQ[k], qdi = jointQd[k], qddi = jointQdd[k];
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
        const LinkModel& m = model_[i];
        if (!(m.mass > 0)) continue;
        const Vec3 c = rotate(x.frame, m.centerOfMass);
        const Vec3 ac = x.a + cross(x.alpha, c) + cross(x.w, cross(x.w, c));
        const auto inertiaTimes = [&](const Vec3& u) { return rotate(x.frame, m.inertia * inverseRotate(x.frame, u)); };
        x.force = ac * m.mass;
        x.torque = inertiaTimes(x.alpha) + cross(x.w, inertiaTimes(x.w)) + cross(c, x.force);
    }
    // Backward: each link carries its subtree; the joint delivers the part along its axis.
    std::vector<Real> effort(joints.size(), 0);
    for (std::size_t at = order.size(); at-- > 0;) {
        const std::size_t i = order[at];
        const std::size_t k = parentJoint[i];
        if (k == kNone) continue;
        const State& x = s[i];
        const RobotJoint& j = joints[k];
        effort[k] = j.type == UrdfJointType::Prismatic ? dot(x.axis, x.force) : dot(x.axis, x.torque);
        State& p = s[parentLink[i]];
        p.force += x.force;
        p.torque += x.torque + cross(x.origin - p.origin, x.force);
    }
    std::vector<Real> out;
    out.reserve(act.size());
    for (const std::size_t k : act) out.push_back(effort[k]);
    return out;
}

}  // namespace fulcrum
