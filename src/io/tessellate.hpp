#pragma once
// Render meshes for collision shapes: triangle lists with per-vertex normals,
// counter-clockwise seen from outside, in the shape's local frame. Shared by
// the glTF writer and the HTML replay page, so both show the same geometry.
//
// Curved shapes are tessellated (a sphere, capsule or cylinder becomes a
// polyhedron inscribed in it); hulls use their faces (flat shaded); meshes are
// emitted as they are (flat shaded); heightfields as their grid (smooth); an infinite plane becomes a finite quad
// centred on the point of the plane nearest to a given centre; compounds
// become one part per leaf child with the child's frame.
#include <cstdint>
#include <vector>

#include "fulcrum/shape.hpp"

namespace fulcrum::io {

struct RenderMesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;                 // unit, one per position
    std::vector<std::uint32_t> indices;        // triangles
    bool doubleSided = false;                  // planes: seen from both sides
};

struct RenderPart {
    Transform local;                           // part frame in the body frame
    RenderMesh mesh;
};

struct TessellationOptions {
    int segments = 32;                         // around the axis (>= 3)
    int rings = 16;                            // pole to pole on a sphere (>= 2)
    Vec3 planeCenter;                          // body-local point the plane quad is centred near
    Real planeHalfSize = 20;                   // half the side of the plane quad, metres
};

RenderMesh tessellateSphere(Real radius, const TessellationOptions& options = {});
RenderMesh tessellateBox(const Vec3& halfExtents);
RenderMesh tessellateCapsule(Real radius, Real halfHeight, const TessellationOptions& options = {});
RenderMesh tessellateCylinder(Real radius, Real halfHeight, const TessellationOptions& options = {});
RenderMesh tessellateHull(const ConvexHull& hull);
RenderMesh tessellateTriangleMesh(const TriangleMesh& mesh);
// A heightfield with smooth normals; fields of more than maxCells cells along
// an axis are drawn from every k-th sample (the replay page stays small).
RenderMesh tessellateHeightField(const HeightField& field, std::uint32_t maxCells = 256);
RenderMesh tessellatePlane(const Vec3& normal, Real offset, const TessellationOptions& options = {});

// Every shape type; a compound yields one part per leaf (nested compounds flattened).
std::vector<RenderPart> tessellate(const Shape& shape, const TessellationOptions& options = {});

// Signed volume enclosed by the triangles (divergence theorem); positive for a
// closed mesh wound counter-clockwise seen from outside.
double enclosedVolume(const RenderMesh& mesh);

}  // namespace fulcrum::io
