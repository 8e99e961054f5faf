// Names of the public enums, as they appear in scene files and outputs.
#include <string_view>

#include "fulcrum/body.hpp"
#include "fulcrum/joint.hpp"
#include "fulcrum/shape.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {

const char* toString(ShapeType type) {
    switch (type) {
        case ShapeType::Sphere: return "sphere";
        case ShapeType::Box: return "box";
        case ShapeType::Capsule: return "capsule";
        case ShapeType::Cylinder: return "cylinder";
        case ShapeType::ConvexHull: return "convex_hull";
        case ShapeType::Plane: return "plane";
        case ShapeType::Mesh: return "mesh";
        case ShapeType::Compound: return "compound";
        case ShapeType::HeightField: return "heightfield";
    }
    return "unknown";
}

const char* toString(BodyType type) {
    switch (type) {
        case BodyType::Static: return "static";
        case BodyType::Kinematic: return "kinematic";
        case BodyType::Dynamic: return "dynamic";
    }
    return "unknown";
}

const char* toString(JointType type) {
    switch (type) {
        case JointType::Ball: return "ball";
        case JointType::Hinge: return "hinge";
        case JointType::Slider: return "slider";
        case JointType::Distance: return "distance";
        case JointType::Fixed: return "fixed";
        case JointType::ConeTwist: return "cone_twist";
        case JointType::SixDof: return "six_dof";
    }
    return "unknown";
}

const char* toString(AxisMode mode) {
    switch (mode) {
        case AxisMode::Free: return "free";
        case AxisMode::Limited: return "limited";
        case AxisMode::Locked: return "locked";
    }
    return "unknown";
}

const char* toString(Integrator integrator) {
    switch (integrator) {
        case Integrator::ExplicitEuler: return "explicit_euler";
        case Integrator::SemiImplicitEuler: return "semi_implicit_euler";
        case Integrator::Verlet: return "verlet";
    }
    return "unknown";
}

std::optional<Integrator> integratorFromString(std::string_view name) {
    for (Integrator i : {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler, Integrator::Verlet}) {
        if (name == toString(i)) return i;
    }
    return std::nullopt;
}

}  // namespace fulcrum
