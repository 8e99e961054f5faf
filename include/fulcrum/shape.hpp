#pragma once
// Collision shapes. A Shape is a small immutable value: primitives keep their
// dimensions inline, while hulls, meshes and compounds share their (validated,
// preprocessed) geometry through a shared_ptr, so copying a Shape into many
// bodies is cheap. Every factory validates its input and throws fulcrum::Error.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fulcrum/error.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum {

enum class ShapeType : std::uint8_t { Sphere, Box, Capsule, Cylinder, ConvexHull, Plane, Mesh, Compound };

const char* toString(ShapeType type);

// Mass, centre of mass (shape-local) and inertia tensor about the centre of
// mass, in shape-local axes.
struct MassProperties {
    Real mass = 0;
    Vec3 centerOfMass;
    Mat3 inertia = Mat3::zero();
};

// A face of a convex hull: outward unit normal, plane offset (n . p = offset for
// points on the face) and its vertices, counter-clockwise seen from outside,
// as a range of ConvexHull::faceVertices.
struct HullFace {
    Vec3 normal;
    Real offset = 0;
    std::uint32_t firstIndex = 0;
    std::uint32_t indexCount = 0;
};

// Convex hull geometry built by quickhull: unique vertices, faces with
// coplanar triangles merged into polygons, and unique edges (for SAT).
struct ConvexHull {
    std::vector<Vec3> vertices;
    std::vector<HullFace> faces;
    std::vector<std::uint32_t> faceVertices;                  // indices into vertices
    std::vector<std::array<std::uint32_t, 2>> edges;          // unique undirected edges
    Vec3 centroid;                                            // of the solid (volume centroid)
    Real volume = 0;
    Mat3 unitDensityInertia = Mat3::zero();                   // about the centroid, density 1
    AABB bounds;
};

struct MeshBvh;  // the mesh's bounding volume hierarchy (src/collision/mesh_bvh.hpp)

// Static triangle mesh: vertices, triangles (counter-clockwise = front face),
// per-triangle adjacency for internal-edge handling, and a BVH.
struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    // For each triangle edge (v0v1, v1v2, v2v0): the adjacent triangle, or UINT32_MAX on a boundary.
    std::vector<std::array<std::uint32_t, 3>> adjacency;
    // Bit k set when edge k is convex (or a boundary): only then may a contact use that edge's normal.
    std::vector<std::uint8_t> convexEdgeMask;
    AABB bounds;
    std::shared_ptr<const MeshBvh> bvh;
};

struct CompoundChild;

struct SnapshotAccess;  // src/world/snapshot.cpp: saves and restores private state

class Shape {
public:
    static Shape sphere(Real radius);
    static Shape box(const Vec3& halfExtents);
    // Capsule: segment from (0,-halfHeight,0) to (0,halfHeight,0) swept by a sphere of `radius`.
    static Shape capsule(Real radius, Real halfHeight);
    // Cylinder: axis along local y, from -halfHeight to +halfHeight.
    static Shape cylinder(Real radius, Real halfHeight);
    // Quickhull of a point cloud; needs at least 4 points that are not coplanar.
    static Shape convexHull(std::span<const Vec3> points);
    // Infinite plane {p : n . p = offset}, solid on the side opposite to n. Static bodies only.
    static Shape plane(const Vec3& normal, Real offset);
    // Static triangle mesh. Triangles index into vertices; degenerate (zero-area) triangles are an error.
    static Shape mesh(std::span<const Vec3> vertices, std::span<const std::array<std::uint32_t, 3>> triangles);
    // Several shapes rigidly joined; at least one child, no planes or meshes inside a dynamic compound;
    // compounds inside compounds at most kMaxCompoundLevels deep.
    static Shape compound(std::span<const CompoundChild> children);

    Shape();  // a unit sphere, so a default-constructed BodyDef is valid

    ShapeType type() const { return type_; }
    Real radius() const { return radius_; }                 // sphere, capsule, cylinder
    Real halfHeight() const { return halfHeight_; }         // capsule, cylinder
    const Vec3& halfExtents() const { return halfExtents_; }  // box
    const Vec3& planeNormal() const { return halfExtents_; }  // plane (unit)
    Real planeOffset() const { return radius_; }              // plane
    const ConvexHull& hull() const;                           // convex hull only
    const TriangleMesh& mesh() const;                         // mesh only
    std::span<const CompoundChild> children() const;          // compound only

    // True for shapes that can only belong to static bodies (plane, mesh, compounds holding them).
    bool staticOnly() const;
    // Mass properties at the given density; throws for shapes without volume (plane, mesh).
    MassProperties massProperties(Real density) const;
    Real volume() const;
    // Bounds in shape-local coordinates; a plane reports a huge box.
    AABB localBounds() const;
    AABB bounds(const Transform& xf) const;

private:
    friend struct fulcrum::SnapshotAccess;
    ShapeType type_ = ShapeType::Sphere;
    Real radius_ = 1;
    Real halfHeight_ = 0;
    Vec3 halfExtents_;
    std::shared_ptr<const ConvexHull> hull_;
    std::shared_ptr<const TriangleMesh> mesh_;
    std::shared_ptr<const std::vector<CompoundChild>> children_;
};

// The deepest nesting of compounds (a compound of leaves is 1 level): the
// shape code walks compounds recursively, so a depth the stack cannot hold is
// refused when the compound is made, not discovered as a crash (snapshots
// hold the same limit).
inline constexpr int kMaxCompoundLevels = 32;

struct CompoundChild {
    Shape shape;
    Transform transform;  // child frame in the compound's frame
};

}  // namespace fulcrum
