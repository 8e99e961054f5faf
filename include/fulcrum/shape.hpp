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

enum class ShapeType : std::uint8_t { Sphere, Box, Capsule, Cylinder, ConvexHull, Plane, Mesh, Compound, HeightField };

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
    // Derived for the narrow phase (the hull builder and snapshots fill them
    // in; a hull built by hand without them is searched the slower way):
    // the faces around each vertex, ascending, vertexFaces[vertexFaceStart[v]]
    // up to vertexFaces[vertexFaceStart[v + 1]]; and the vertices' x
    // coordinates, then their y, then their z (8-lane support search).
    std::vector<std::uint32_t> vertexFaceStart, vertexFaces;
    std::vector<Real> vertexRows;
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

// Static heightfield (docs/terrain.md): a grid of rows x columns height
// samples; sample (row r, column c) is at shape-local (c * spacingX,
// heights[r * columns + c], r * spacingZ). Cell (r, c), r < rows - 1 and
// c < columns - 1, has index r * (columns - 1) + c and is split along its
// diagonal from sample (r, c) to sample (r + 1, c + 1) into two triangles,
// counter-clockwise seen from +y (front faces point up):
//   triangle 2 * cell     = (r, c), (r + 1, c), (r + 1, c + 1)
//   triangle 2 * cell + 1 = (r, c), (r + 1, c + 1), (r, c + 1)
// A hole is a cell without its two triangles (nothing collides there).
struct HeightField {
    std::uint32_t rows = 0;     // samples along z
    std::uint32_t columns = 0;  // samples along x
    Real spacingX = 1;
    Real spacingZ = 1;
    std::vector<Real> heights;             // rows * columns, row by row
    std::vector<std::uint32_t> holes;      // the hole cells' indices, sorted, unique
    std::vector<std::uint8_t> cellIsHole;  // per cell, 1 for a hole (empty when there are no holes)
    // Per triangle: bit k set when edge k (v0v1, v1v2, v2v0) is convex or a
    // boundary (the field's rim or a hole's), as TriangleMesh::convexEdgeMask.
    std::vector<std::uint8_t> convexEdgeMask;
    // The min/max mip-map: level 0 holds each cell's lowest and highest
    // corner, level k + 1 the extremes of 2 x 2 blocks of level k, up to a
    // single block. A hole cell (or a block of holes) has min > max.
    struct Level {
        std::uint32_t rows = 0, columns = 0;  // blocks along z and x
        std::vector<Real> minY, maxY;         // row by row
    };
    std::vector<Level> levels;
    AABB bounds;

    std::uint32_t cellRows() const { return rows - 1; }
    std::uint32_t cellColumns() const { return columns - 1; }
    Real height(std::uint32_t r, std::uint32_t c) const { return heights[std::size_t(r) * columns + c]; }
    Vec3 sample(std::uint32_t r, std::uint32_t c) const {
        return {static_cast<Real>(c) * spacingX, height(r, c), static_cast<Real>(r) * spacingZ};
    }
    bool isHole(std::uint32_t cell) const { return !cellIsHole.empty() && cellIsHole[cell] != 0; }
    // Triangle t's corners, shape-local, counter-clockwise from above.
    void triangle(std::uint32_t t, Vec3 out[3]) const {
        const std::uint32_t cell = t >> 1, r = cell / cellColumns(), c = cell % cellColumns();
        out[0] = sample(r, c);
        if ((t & 1u) == 0) {
            out[1] = sample(r + 1, c);
            out[2] = sample(r + 1, c + 1);
        } else {
            out[1] = sample(r + 1, c + 1);
            out[2] = sample(r, c + 1);
        }
    }
};

// Limits of Shape::heightField: 2 .. kMaxHeightFieldSamples samples along
// each axis (4097 x 4097 is 16.8 million samples, 64 MiB of heights).
inline constexpr std::uint32_t kMaxHeightFieldSamples = 4097;

struct CompoundChild;

// Convex decomposition (docs/shapes.md, "Convex decomposition";
// src/collision/convex_decomposition.cpp): how finely Shape::convexDecomposition
// cuts a closed mesh into convex hulls.
struct ConvexDecompositionOptions {
    // At most this many hulls (1 .. 1024).
    int maxHulls = 32;
    // A piece is kept whole once its hull exceeds the solid inside it by at
    // most this fraction of the whole mesh's volume (0 .. 1).
    Real maxConcavity = Real(0.01);
    // Columns along the mesh's longer horizontal (x or z) side of the grid
    // that estimates how much solid lies in a piece (4 .. 512).
    int resolution = 64;
};

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
    // Static heightfield of rows x columns samples (HeightField above), spacing
    // spacingX along x (between columns) and spacingZ along z (between rows);
    // `holes` lists cell indices r * (columns - 1) + c without collision.
    // Static bodies only.
    static Shape heightField(std::uint32_t rows, std::uint32_t columns, Real spacingX, Real spacingZ,
                             std::span<const Real> heights, std::span<const std::uint32_t> holes = {});
    // Several shapes rigidly joined; at least one child, no planes or meshes inside a dynamic compound;
    // compounds inside compounds at most kMaxCompoundLevels deep.
    static Shape compound(std::span<const CompoundChild> children);

    // Scaled shapes (docs/shapes.md, "Scaled shapes"; src/collision/shape_scale.cpp):
    // a new shape whose geometry is `shape`'s scaled by diag(scale) about the
    // shape's origin, baked into the result (a scaled box is a box, a scaled
    // hull a hull of the scaled points), so collision and mass properties are
    // exact and cost nothing at run time. A negative component mirrors. Each
    // component must be finite and nonzero. Spheres need a uniform |scale|,
    // capsules too, cylinders |sx| == |sz|; a compound child rotated against
    // a non-uniform scale becomes a convex hull (boxes, hulls), a mesh
    // (meshes), or is an error (spheres, capsules, cylinders, heightfields).
    static Shape scaled(const Shape& shape, const Vec3& scale);
    static Shape scaled(const Shape& shape, Real scale) { return scaled(shape, Vec3::splat(scale)); }

    // Convex decomposition: a compound of convex hulls (in the mesh's frame,
    // children at the identity) approximating the solid a closed,
    // consistently wound (counter-clockwise seen from outside) triangle mesh
    // bounds, for dynamic concave bodies, which a mesh cannot be. Recursive
    // axis-aligned cuts chosen to reduce concavity; deterministic.
    static Shape convexDecomposition(std::span<const Vec3> vertices,
                                     std::span<const std::array<std::uint32_t, 3>> triangles,
                                     const ConvexDecompositionOptions& options = {});
    // ---- Rounded shapes (docs/shapes.md, "Rounded shapes"): a box, cylinder
    // or hull whose surface is its core swept by a sphere of `convexRadius`,
    // as a capsule is a segment swept by its radius. Box and cylinder take
    // their OUTER size: the core is the outer size minus the radius, so
    // 0 <= convexRadius <= the smallest half extent (box) or min(radius,
    // halfHeight) (cylinder). A hull's points are its CORE: the rounded hull
    // reaches convexRadius beyond them. A radius of 0 is the plain shape.
    static Shape roundedBox(const Vec3& halfExtents, Real convexRadius);
    static Shape roundedCylinder(Real radius, Real halfHeight, Real convexRadius);
    static Shape roundedConvexHull(std::span<const Vec3> points, Real convexRadius);
    // The rounding radius (0 for plain shapes; spheres' and capsules' own radius is radius()).
    Real convexRadius() const { return convexRadius_; }
    // ---- end of rounded shapes

    Shape();  // a unit sphere, so a default-constructed BodyDef is valid

    ShapeType type() const { return type_; }
    Real radius() const { return radius_; }                 // sphere, capsule, cylinder
    Real halfHeight() const { return halfHeight_; }         // capsule, cylinder
    const Vec3& halfExtents() const { return halfExtents_; }  // box
    const Vec3& planeNormal() const { return halfExtents_; }  // plane (unit)
    Real planeOffset() const { return radius_; }              // plane
    const ConvexHull& hull() const;                           // convex hull only
    const TriangleMesh& mesh() const;                         // mesh only
    const HeightField& heightField() const;                   // heightfield only
    std::span<const CompoundChild> children() const;          // compound only

    // True for shapes that can only belong to static bodies (plane, mesh, heightfield, compounds holding them).
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
    std::shared_ptr<const HeightField> heightField_;
    std::shared_ptr<const std::vector<CompoundChild>> children_;
    // A compound's localBounds(), the union of its children's bounds formed
    // once with them (setChildren): continuous collision asks for it at every
    // sweep of a compound body, and a tree of 22 hulls took some 900
    // instructions a time to form it again.
    AABB childBounds_;
    void setChildren(std::shared_ptr<const std::vector<CompoundChild>> children);
    // ---- Rounded shapes: the rounding radius, and for a rounded hull the
    // polyhedron its mass properties (and drawings) come from (shape.cpp,
    // roundedHullApproximation).
    Real convexRadius_ = 0;
    std::shared_ptr<const ConvexHull> roundedHull_;
    friend const ConvexHull* roundedHullOf(const Shape& s);
    Real roundedVolume() const;
    MassProperties roundedMassProperties(Real density) const;
    AABB roundedBounds(const Transform& xf) const;
    static std::shared_ptr<const ConvexHull> roundedHullFor(const ConvexHull& core, Real convexRadius);
};

// The polyhedral stand-in of a rounded hull (its core grown by a polytope close
// to the ball of its convex radius, docs/shapes.md), or null for any other shape.
const ConvexHull* roundedHullOf(const Shape& s);

// The deepest nesting of compounds (a compound of leaves is 1 level): the
// shape code walks compounds recursively, so a depth the stack cannot hold is
// refused when the compound is made, not discovered as a crash (snapshots
// hold the same limit).
inline constexpr int kMaxCompoundLevels = 32;

// The largest size or coordinate a shape may have, in metres (10^12 m, some
// seven times the Sun's distance): far beyond any world the engine is
// accurate for, and small enough that a shape's bounds under any rotation,
// and the product of two such numbers, stay finite in float. A finite but
// larger number (a compound child at 3e38 m, a box of half extent 1e38)
// overflowed to infinity when the shape was turned, deep inside a step; every
// factory and the snapshot loader refuse it instead.
inline constexpr Real kMaxShapeCoordinate = Real(1e12);

struct CompoundChild {
    Shape shape;
    Transform transform;  // child frame in the compound's frame
};

}  // namespace fulcrum
