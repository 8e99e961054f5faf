#pragma once
// The narrow phase dispatcher: exact contact manifolds for any pair of shapes.
#include "collision/manifold.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

// Clears `out` and fills it with the manifolds between shape a at xa and
// shape b at xb: zero or more (several for compounds and meshes), each with up
// to 4 points, normals from a to b. Points are reported while the shapes are
// within `speculativeMargin` of touching (depth >= -speculativeMargin).
// Symmetric: collide(b, a) gives the same points with the normal flipped.
// Pairs of two static-only shapes (plane/mesh against plane/mesh) give nothing.
// No heap allocation once `out` has grown to its working size.
void collide(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real speculativeMargin,
             ManifoldBuffer& out);

}  // namespace fulcrum
