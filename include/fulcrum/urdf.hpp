#pragma once
// Robot models from URDF files (docs/robots.md): links become bodies and
// joints joints, named as in the file, and a Robot keeps their handles by
// name, with bulk drive targets and read-outs for the whole robot. Part of
// the fulcrum::io library (it parses XML with Debian's tinyxml2); the engine
// core knows nothing of URDF.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {

// A drive on a hinge (revolute, continuous) or slider (prismatic) joint: an
// implicit PD towards `position` (the joint's JointSpring: stiffness, damping),
// and/or a velocity target (its JointMotor), each with at most `maxForce`
// (PyBullet's `force`; default: the URDF effort limit).
struct JointDrive {
    Real position = 0;   // rad or m, from the pose the model was built in (all joint positions 0)
    Real stiffness = 0;  // N m/rad or N/m; 0 with damping 0: no position drive
    Real damping = 0;    // N m s/rad or N s/m, added to the URDF's <dynamics damping>
    bool velocityDrive = false;
    Real velocity = 0;   // rad/s or m/s
    // N m or N, > 0: caps the position drive (JointSpring::maxForce) and the
    // velocity drive (JointMotor::maxForce), each row on its own; inf: the URDF
    // effort limit (none: the position drive unlimited, the velocity drive 1e9).
    Real maxForce = std::numeric_limits<Real>::infinity();
};

struct UrdfOptions {
    Vec3 position;        // of the root link's frame, world
    Quat orientation;     // of the root link's frame
    bool fixedBase = false;  // the root link static (also when it is named "world" and has no <inertial>); links fixed to a static link are static too
    // Folders that `package://NAME/...` and relative mesh paths are looked up in
    // (after the URDF file's own folder, for relative paths).
    std::vector<std::filesystem::path> searchPath;
    // false: no two links of the robot collide (a negative collision group,
    // PyBullet's default); true: all pairs except joint-connected ones.
    bool selfCollision = false;
    // The collision group when selfCollision is false; 0: one below the lowest
    // group of the bodies already in the world (or of the scene), so each robot has its own.
    std::int32_t collisionGroup = 0;
    // Links without <inertial>: this mass (kg), spread as a solid sphere of
    // radius defaultRadius about the link origin.
    Real defaultMass = Real(0.1);
    Real defaultRadius = Real(0.05);
    // Warnings (a missing mesh, an approximation); default: printed to stderr
    // as "fulcrum: warning: ...". Every warning also lands in Robot::warnings.
    std::function<void(const std::string&)> warn;
};

enum class UrdfJointType : std::uint8_t { Revolute, Continuous, Prismatic, Fixed, Floating, Planar };
const char* toString(UrdfJointType type);

struct RobotLink {
    std::string name;
    BodyId body;
    Real mass = 0;                 // kg (0: static)
    bool collides = false;         // has at least one collider
    // Its <visual> elements, in the link frame (docs/robots.md), for a
    // recording: Recorder::setVisuals(link.body, link.visuals).
    std::vector<BodyVisual> visuals{};
};

struct RobotJoint {
    std::string name;
    UrdfJointType type = UrdfJointType::Fixed;
    std::string parent, child;     // link names
    JointId joint;                 // null for a fixed joint between static links (floating and planar: six-DOF joints)
    Vec3 axis{1, 0, 0};            // in the joint frame (the child link's)
    Real lower = -std::numeric_limits<Real>::infinity(), upper = std::numeric_limits<Real>::infinity();
    Real effortLimit = std::numeric_limits<Real>::infinity();    // N m or N (0 in the file: none)
    Real velocityLimit = std::numeric_limits<Real>::infinity();  // rad/s or m/s (kept, not enforced)
    Real damping = 0, friction = 0;  // <dynamics>
    bool actuated() const {
        return type == UrdfJointType::Revolute || type == UrdfJointType::Continuous || type == UrdfJointType::Prismatic;
    }
};

// One degree of freedom of the robot's "dof" bulk calls: an actuated joint's
// axis (axis -1), or one free or limited axis of a six-DOF joint (a URDF
// floating or planar joint; axis: SixDofAxisIndex, in its joint frame).
struct RobotDof {
    std::size_t joint = 0;  // index into Robot::joints
    int axis = -1;
};

// What Robot::inverseDynamics adds to the rigid tree's efforts.
struct InverseDynamicsOptions {
    bool damping = true;   // d qd, d the URDF <dynamics damping>
    // f sgn(qd), f the URDF <dynamics friction> (Coulomb); at qd = 0 the
    // friction opposes the acceleration, f sgn(qdd) (the joint breaks away),
    // and is 0 with qdd = 0 too (holding relies on no static friction).
    bool friction = true;
};

// The root link's state for floating-base inverse dynamics (world frame);
// Robot::baseState reads it from the world.
struct RobotBaseState {
    Vec3 position;          // the root link's frame origin, m
    Quat orientation;       // the root link's frame
    Vec3 angularVelocity;   // rad/s (its linear velocity does not enter the efforts)
};

// Floating-base inverse dynamics' answer (Robot::freeBaseInverseDynamics,
// prescribedBaseInverseDynamics).
struct FloatingBaseDynamics {
    std::vector<Real> efforts;         // per actuated joint (N m or N), the order of jointPositions
    // The root link's frame origin's linear acceleration (m/s^2, world) and
    // its angular acceleration (rad/s^2): free base, what the tree takes;
    // prescribed base, as given.
    Vec3 linearAcceleration, angularAcceleration;
    // The wrench on the root link, besides gravity, that the motion needs
    // (N, and N m about the root link's frame origin; world): zero for a free base.
    Vec3 force, torque;
};

// A specific-force IMU reading in the body's axes.
struct ImuReading {
    Vec3 specificForce;     // m/s^2: linear acceleration of the centre of mass minus gravity (at rest: -g, "up")
    Vec3 angularVelocity;   // rad/s
};

struct UrdfSceneParts;

// A loaded robot: handles by name, and bulk drives and read-outs over its
// actuated joints (revolute, continuous, prismatic), in file order.
class Robot {
public:
    std::string name;
    std::vector<RobotLink> links;    // file order
    std::vector<RobotJoint> joints;  // file order
    std::vector<std::string> warnings;

    BodyId body(std::string_view link) const;         // throws fulcrum::Error naming a missing link
    JointId joint(std::string_view joint) const;      // throws for a missing or floating joint
    const RobotJoint& jointInfo(std::string_view joint) const;
    // The actuated joints, in the order of every bulk call below.
    std::vector<std::size_t> actuatedJoints() const;
    std::vector<std::string> actuatedJointNames() const;

    // One joint's drive (validated as World::setJointSpring / setJointMotor),
    // or one six-DOF axis's, named "joint/x" ... "joint/rz" (as dofNames).
    void setDrive(World& world, std::string_view joint, const JointDrive& drive) const;
    // Bulk, one value per actuated joint: position targets keep each drive's
    // gains; gains set stiffness and damping; velocity targets turn the
    // velocity drive on (maxForce: the effort limit, or unlimited).
    void setPositionTargets(World& world, std::span<const Real> positions) const;
    void setDriveGains(World& world, std::span<const Real> stiffness, std::span<const Real> damping) const;
    void setVelocityTargets(World& world, std::span<const Real> velocities) const;
    // The position drives' force limits (N m or N, >= 0; +infinity: none),
    // kept by the calls above and by disableDrives. Loading sets them to the
    // URDF effort limits (docs/robots.md, "Drives").
    void setDriveMaxForces(World& world, std::span<const Real> maxForces) const;
    void disableDrives(World& world) const;  // springs and motors off (URDF damping and friction stay), six-DOF axes' too

    // Every degree of freedom (docs/robots.md, "Six-DOF drives"): the actuated
    // joints and the free or limited axes of floating and planar joints, in
    // file order (a six-DOF joint's axes x, y, z, rx, ry, rz in turn). Named
    // as the joint, a six-DOF axis as "joint/x" ... "joint/rz" (setDrive
    // takes these names too). The dof calls below take and give one value
    // per entry; on a robot without floating or planar joints they are the
    // joint calls. Six-DOF velocity targets are unlimited (maxForce 1e9).
    std::vector<RobotDof> dofs() const;
    std::vector<std::string> dofNames() const;
    void setDofPositionTargets(World& world, std::span<const Real> positions) const;
    void setDofDriveGains(World& world, std::span<const Real> stiffness, std::span<const Real> damping) const;
    void setDofVelocityTargets(World& world, std::span<const Real> velocities) const;
    void setDofDriveMaxForces(World& world, std::span<const Real> maxForces) const;  // as setDriveMaxForces
    std::vector<Real> dofPositions(const World& world) const;
    std::vector<Real> dofVelocities(const World& world) const;
    std::vector<Real> dofEfforts(const World& world) const;  // six-DOF axes: World::sixDofReading's efforts

    std::vector<Real> jointPositions(const World& world) const;
    std::vector<Real> jointVelocities(const World& world) const;
    std::vector<Real> jointEfforts(const World& world) const;  // World::jointEffort
    // The contact force on every link over the last step (N, world, file
    // order; World::contactForces), zero for a link without a body.
    std::vector<Vec3> contactForces(const World& world) const;

    // IMU readings of every link (file order). Call once after each step: the
    // acceleration is the change of each link's velocity since the previous
    // call over the time between them (the first call reads it as zero).
    std::vector<ImuReading> sampleImu(const World& world);

    // Inverse dynamics of a fixed-base tree (recursive Newton-Euler, as
    // Featherstone's "Rigid Body Dynamics Algorithms", ch. 5): the effort at
    // each actuated joint (N m or N, the order of jointPositions) that moves
    // the robot through positions q, velocities qd and accelerations qdd under
    // the world's gravity, from the links' mass, centre of mass and inertia
    // and the model's geometry (the pose it was loaded in is q = 0), plus the
    // URDF damping and friction (options). With qd and qdd zero: the
    // gravity-holding efforts. Joint limits are not part of it. Throws for a
    // robot whose root is not static, or with floating or planar joints.
    std::vector<Real> inverseDynamics(const World& world, std::span<const Real> q, std::span<const Real> qd,
                                      std::span<const Real> qdd, const InverseDynamicsOptions& options = {}) const;
    // Floating base (a root link that is not static; Featherstone ch. 9.5):
    // the free tree, no wrench on its root but gravity, moving its joints
    // through q, qd, qdd from the base state: the base's acceleration and the
    // joint efforts. Throws for a static root, or floating or planar joints.
    FloatingBaseDynamics freeBaseInverseDynamics(const World& world, const RobotBaseState& base, std::span<const Real> q,
                                                 std::span<const Real> qd, std::span<const Real> qdd,
                                                 const InverseDynamicsOptions& options = {}) const;
    // The same with the base's accelerations given (its frame origin's linear
    // one and the angular one, world): the wrench on the base and the joint
    // efforts that make that motion (the base as a sixth actuated joint).
    FloatingBaseDynamics prescribedBaseInverseDynamics(const World& world, const RobotBaseState& base,
                                                       const Vec3& linearAcceleration, const Vec3& angularAcceleration,
                                                       std::span<const Real> q, std::span<const Real> qd,
                                                       std::span<const Real> qdd,
                                                       const InverseDynamicsOptions& options = {}) const;
    // The root link's pose and angular velocity now (its body's).
    RobotBaseState baseState(const World& world) const;

private:
    friend Robot createUrdfParts(World& world, const UrdfSceneParts& parts, const std::string& sourceName);
    // Each link's frame as loaded (q = 0) and inertia in it (inverseDynamics).
    struct LinkModel {
        Vec3 origin;
        Quat frame;
        Vec3 centerOfMass;  // link frame
        Mat3 inertia;       // about the centre of mass, link axes
        Real mass = 0;      // 0: static
    };
    std::vector<LinkModel> model_;
    struct Dynamics;  // the recursive Newton-Euler passes (urdf_dynamics.cpp)
    std::vector<Vec3> lastVelocity_;
    Real lastTime_ = 0;
    bool sampled_ = false;
};

// One IMU on one body (see Robot::sampleImu): update() after each step.
class Imu {
public:
    explicit Imu(BodyId body) : body_(body) {}
    ImuReading update(const World& world);

private:
    BodyId body_;
    Vec3 lastVelocity_;
    Real lastTime_ = 0;
    bool sampled_ = false;
};

// Loads a URDF file into the world. Throws fulcrum::Error naming the file
// (and line and element) for malformed XML, a broken tree or bad inertia.
// Floating and planar joints become six-DOF joints (docs/robots.md).
Robot loadUrdf(World& world, const std::filesystem::path& file, const UrdfOptions& options = {});
// The same from text in memory; `sourceName` names it in errors and its
// folder resolves relative mesh paths (fuzzing, tests).
Robot loadUrdfFromString(World& world, std::string_view xml, const std::string& sourceName,
                         const UrdfOptions& options = {});

// The robot as scene bodies and joints (what a scene file's "urdf" entry
// adds): bodies and joints named as in the file, joint anchors in world
// space, `drives` (by joint name) as the joints' springs. Robot::links and
// joints are filled with names and types only (no handles yet).
struct UrdfSceneParts {
    std::vector<SceneBody> bodies;
    std::vector<SceneJoint> joints;
    std::vector<std::size_t> jointIndex;  // per scene joint: its index in robot.joints
    Robot robot;
};
UrdfSceneParts urdfSceneParts(std::string_view xml, const std::string& sourceName, const UrdfOptions& options,
                              const std::vector<std::pair<std::string, JointDrive>>& drives = {});
// The parts' bodies and joints created in the world (what loadUrdf does
// after urdfSceneParts); the Robot with their handles.
Robot createUrdfParts(World& world, const UrdfSceneParts& parts, const std::string& sourceName);
std::string readUrdfText(const std::filesystem::path& file);

}  // namespace fulcrum
