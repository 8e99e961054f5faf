#pragma once
// The joint types, listed once. Each type is a class of static members in
// its own file pair, src/solver/joints/<type>.hpp and <type>.cpp (and, where
// its joints run in SIMD lanes, <type>_wide.hpp beside them):
//
//   Def                 its definition in the public API (fulcrum/joint.hpp)
//   kType               its JointType
//   kReadsOrientations  its rows read the bodies' orientations (updateFrame keeps them;
//                       frameNeedsOrientations must agree, checked below)
//   kHasFreeAxis        a hinge or slider: motor, limits and spring, also after creation
//   kHasPointBlock      its anchors meet (a 3-row point block): the tree solver may take it
//                       (a type whose joints differ also has pointBlock(j): the six-DOF)
//   kProjected          JointSolver::projectPositions pulls its anchors together
//   fromJointDef        the generic JointDef (world space) as its definition
//   setup               validates its definition (errors name the joint and the
//                       field) and makes the stored joint (JointSetup)
//   validateLimits      (free-axis types) World::setJointLimits's check
//   prepare             its constraint's fields for this step (JointSolver::prepare)
//   warmStart, solve    its rows (joint_common.hpp describes the row kinds)
//   hasRows             whether the Gauss-Seidel passes solve it
//   wideKind            which SIMD blocks take it (joint_wide.hpp)
//   addReaction         its part of the reaction force and torque (jointReaction)
//   error, position     World::jointError, World::jointPosition
//
// A new joint type: its file pair, one line in withJointType below, its
// JointType and definition in fulcrum/joint.hpp and a World::createJoint
// overload (src/world/world_joints.cpp).
#include "solver/joints/ball.hpp"
#include "solver/joints/cone_twist.hpp"
#include "solver/joints/distance.hpp"
#include "solver/joints/fixed.hpp"
#include "solver/joints/hinge.hpp"
#include "solver/joints/six_dof.hpp"
#include "solver/joints/slider.hpp"

namespace fulcrum::detail {

// f(T{}) for the class T of `type`: the one switch over the joint types.
// Always inline: a joint's kernel call through it is then the switch's direct call.
template <class F>
[[gnu::always_inline]] inline decltype(auto) withJointType(JointType type, F&& f) {
    switch (type) {
        case JointType::Ball: return f(BallJoint{});
        case JointType::Hinge: return f(HingeJoint{});
        case JointType::Slider: return f(SliderJoint{});
        case JointType::Distance: return f(DistanceJoint{});
        case JointType::Fixed: return f(FixedJoint{});
        case JointType::ConeTwist: return f(ConeTwistJoint{});
        case JointType::SixDof: return f(SixDofJoint{});
    }
    return f(BallJoint{});  // not reached: a joint's type is checked at creation
}

// The SIMD blocks that take j (joint_wide.hpp's wideKind, which the kernels
// call; this inline form for JointSolver::buildWide's sweep over every joint).
[[gnu::always_inline]] inline WideKind jointWideKind(const JointConstraint& j) {
    return withJointType(j.type, [&](auto type) { return decltype(type)::wideKind(j); });
}

// updateFrame's test of the type (joint_common.hpp) agrees with every type's trait.
template <class... T>
constexpr bool frameTestsAgree() {
    return ((frameNeedsOrientations(T::kType) == T::kReadsOrientations) && ...);
}
static_assert(frameTestsAgree<BallJoint, HingeJoint, SliderJoint, DistanceJoint, FixedJoint, ConeTwistJoint, SixDofJoint>(),
              "frameNeedsOrientations (joint_common.hpp) must match each type's kReadsOrientations");

// Whether `type` is one of the list (a JointDef's type is checked with it).
constexpr bool isJointType(JointType type) {
    switch (type) {
        case JointType::Ball:
        case JointType::Hinge:
        case JointType::Slider:
        case JointType::Distance:
        case JointType::Fixed:
        case JointType::ConeTwist:
        case JointType::SixDof: return true;
    }
    return false;
}

}  // namespace fulcrum::detail
