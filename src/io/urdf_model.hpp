#pragma once
// A URDF file as parsed and checked (urdf_parse.cpp), before it becomes
// bodies and joints (urdf.cpp). Everything in the file's own frames and units.
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/urdf.hpp"

namespace fulcrum::detail {

struct UrdfPose {
    Vec3 p;
    Quat q;
};

struct UrdfGeometry {
    enum class Kind { Box, Cylinder, Sphere, Capsule, Mesh };
    Kind kind = Kind::Box;
    Vec3 size;            // box: full extents
    Real radius = 0;      // cylinder, sphere, capsule
    Real length = 0;      // cylinder, capsule (along z)
    std::string filename; // mesh, as written
    Vec3 scale{1, 1, 1};  // mesh
};

struct UrdfGeometryElement {
    UrdfPose origin;
    UrdfGeometry geometry;
    int line = 0;
    // <visual>'s <material>: its colour, given inline or by the name of a
    // material defined in the file (at the robot level or in another visual).
    std::string material;                    // the name, as written ("" without one)
    bool hasColor = false;
    std::array<float, 4> rgba{1, 1, 1, 1};
};

struct UrdfLink {
    std::string name;
    int line = 0;
    bool hasInertial = false;
    UrdfPose inertialOrigin;
    Real mass = 0;
    Mat3 inertia = Mat3::zero();  // in the inertial frame
    std::vector<UrdfGeometryElement> collisions, visuals;
};

struct UrdfJoint {
    std::string name;
    int line = 0;
    UrdfJointType type = UrdfJointType::Fixed;
    std::string parent, child;
    UrdfPose origin;          // the child link's frame in the parent's
    Vec3 axis{1, 0, 0};       // unit, in the child's frame
    bool hasLimit = false, hasLower = false, hasUpper = false;
    Real lower = 0, upper = 0, effort = 0, velocity = 0;
    Real damping = 0, friction = 0;
};

struct UrdfModel {
    std::string name;
    std::string source;                  // the file, for messages
    std::vector<UrdfLink> links;         // file order
    std::vector<UrdfJoint> joints;       // file order
    std::size_t root = 0;                // index into links
    std::vector<std::size_t> parentJoint;  // per link: its joint's index (npos for the root)
    std::vector<std::size_t> order;      // links, parents before children
};

// Parses and checks a URDF document: well-formed XML with a <robot>, links
// and joints with the required attributes and numbers, unique names, one
// tree (one root, one parent per link, no loop, joints naming existing
// links), positive masses and positive-definite inertias. Throws
// fulcrum::Error "<source>: line N: <element ...>: what is wrong".
UrdfModel parseUrdf(std::string_view xml, const std::string& source);

}  // namespace fulcrum::detail
