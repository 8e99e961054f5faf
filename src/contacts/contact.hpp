#pragma once
// Persistent contacts: one per pair of bodies whose fat boxes overlap, holding
// the manifolds of the last narrow-phase update and the accumulated impulses
// that warm-start the solver next step.
//
// Bodies are referred to by *slot* index (stable while the body lives), not by
// dense index, because destroying another body swap-removes the dense arrays.
#include <cstdint>
#include <vector>

#include "collision/broad_phase.hpp"
#include "collision/manifold.hpp"
#include "fulcrum/math.hpp"
#include "math/large_array.hpp"

namespace fulcrum::detail {

struct CachedPoint {
    Vec3 localA, localB;         // the surface points in A's and B's body frames (for recycling)
    Vec3 position;               // world, midway between the surfaces, at the step's start
    Real depth = 0;              // at the step's start (positive: overlap)
    Real depthAfter = 0;         // at the step's end, from the bodies' motion (reported to users)
    std::uint32_t featureId = 0;
    Real normalImpulse = 0;      // accumulated over a sub-step (warm start)
    Real maxNormalImpulse = 0;   // largest sub-step impulse of the last step (restitution, events)
    // What the solver applied over the whole last step (ContactSolver::store):
    // the sum over its sub-steps of the accumulated impulse after the relax
    // pass, plus restitution's (N s; the contact report's forces).
    Real stepNormalImpulse = 0;
    Real approachVelocity = 0;   // normal velocity when the point first pushed in the last step (hit events)
};

struct CachedManifold {
    Vec3 normal{0, 1, 0};        // from A to B
    Vec3 localNormal{0, 1, 0};   // the normal in A's body frame (for recycling)
    std::uint32_t childA = 0, childB = 0;
    std::uint32_t pointCount = 0;
    CachedPoint points[4];
    // Manifold-level friction state (bepu / Box3D style), world space so a new
    // tangent basis can pick it up: tangent impulse vector, twist impulse about
    // the normal, rolling-resistance angular impulse.
    Vec3 frictionImpulse;
    Real twistImpulse = 0;
    Vec3 rollingImpulse;
    Vec3 stepFrictionImpulse;    // tangent impulse on B over the last step, as stepNormalImpulse (world)
};

// Piece recycling against a static mesh (docs/narrow-phase.md, "Recycling a
// piece's mesh contacts"): for each box or hull piece of a body (a compound's
// top-level child, or the body's own shape as piece 0) that the narrow phase
// last looked at against the mesh, where the piece was then. While it has
// moved so little since that no triangle its manifolds left out can be
// reached this step, the narrow phase skips it and its points (if any) keep
// their anchors with refreshed depths.
struct PiecePose {
    std::uint32_t piece = 0;     // the top-level child (0: a plain body)
    Vec3 localCentre;            // the centre of the piece's bounds, in its body's frame
    Real radius = 0;             // the half diagonal of those bounds
    Vec3 centre;                 // localCentre in the mesh's frame when the manifolds were made
    Quat rotation;               // the body's rotation in the mesh's frame then
    Real margin = 0;             // the speculative distance they were made with (at most the one used)
};

// How a pair first touched, for the contact solver's push-out limit
// (ContactSolver::pushLimit; docs/solver.md, "Born deep, driven deep").
// Bodies created (or moved) inside one another touch first already deep: their
// deep overlaps share contactPushMaxVelocity, so a heap of them opens gently.
// Bodies that touched first at a resting depth and were driven in since (a
// kinematic pusher, a jam, a fast landing the speculative margin saw coming)
// keep the whole push-out speed.
enum class FirstTouch : std::uint8_t {
    NotYet = 0,   // no manifold has reached the solver yet
    Shallow = 1,  // the first manifold the solver saw had no point deeper than its sharing depth
    Deep = 2,     // it had one: the pair was born inside each other
};

struct Contact {
    bool alive = false;
    bool sensor = false;         // one body is a sensor: overlap tracking only
    bool touching = false;       // as of the last update (sensor: overlapping)
    // Unused (always false since the solver stopped visiting sleeping
    // contacts); kept so the snapshot format stays the same.
    bool solved = false;
    std::uint32_t slotA = 0, slotB = 0;  // slotA's proxy id < slotB's proxy id
    ProxyId proxyA = kNullProxy, proxyB = kNullProxy;
    std::uint32_t nextFree = UINT32_MAX;
    bool hasPose = false;        // relativePose holds the pose of the last collide()
    Transform relativePose;      // B's body frame in A's, when collide() last ran
    // The apart cache (docs/narrow-phase.md, "Pairs proved apart"): a distance
    // the two shapes are proved to be at least apart at relativePose (0: none
    // known), and each shape's reach (its farthest point from its body
    // origin) that bounds how far a turn moves it. Not saved in snapshots:
    // a pair without it runs the narrow phase, which gives the same answer.
    Real apartBy = 0;
    Real reachA = 0, reachB = 0;
    // The pair's material, mixed at every collideContact() (so setFriction and
    // setRestitution take effect next step): the solver's prepare then reads
    // only the contact and its own compact body arrays, not the world's body
    // records (measured: buildConstraint was the top function of sphere_pile,
    // 11 % of its time, mostly cache misses on those records).
    Real friction = 0, restitution = 0, rollingResistance = 0;  // rolling: times the round shape's radius
    // Set by the solver's prepare from the first manifold it sees, kept for
    // the contact's life (saved in snapshots from format version 10).
    FirstTouch firstTouch = FirstTouch::NotYet;
    // How much deeper the narrow phase found the pair than the solver had
    // predicted for the end of the last step (the fresh manifold's deepest
    // point less the old one's depthAfter; 0 when there was no old manifold
    // or the narrow phase did not run): an overlap made within the last step
    // that its step-start manifold could not see (a hull struck into this
    // one). Set by collideContact, read and zeroed by the solver's prepare in
    // the same step (ContactSolver::pushOutGrown), so it is always 0 between
    // steps and snapshots need not hold it.
    Real grownBy = 0;
    std::vector<CachedManifold> manifolds;  // capacity kept across reuse: no allocation in steady state
    // The triangle axis cache of a box or hull against a mesh (TriangleAxisCache,
    // collision/manifold.hpp): per (piece, triangle) the axis of the last full
    // test that gave a contact, sorted. It changes results, so it is saved in
    // snapshots (format version 11); capacity kept across reuse.
    std::vector<TriangleAxisEntry> triangleAxes;
    // The GJK warm start of two hulls or a box and a hull (GjkWarmStart,
    // collision/manifold.hpp): the vertices of the simplex the pair's last
    // GJK run ended on. It
    // changes results, so it is saved in snapshots (format version 12).
    GjkWarmStart gjkWarmStart;
    // The candidate triangles of a plain convex shape against a mesh
    // (MeshCandidateCache, collision/manifold.hpp): the BVH query's answer
    // while the body stays in a grown box. It gives the query's own
    // triangles in its order, so it is scratch: not saved in snapshots.
    MeshCandidateCache meshCandidates;
    // The pieces' poses for piece recycling against a static mesh (PiecePose),
    // ascending by piece. They decide which pieces the next narrow phase
    // skips, so they are saved in snapshots (format version 13); capacity kept.
    std::vector<PiecePose> piecePoses;
};

// The contact pool: a large array (math/large_array.hpp), since a world
// reserves about four contacts a moving body (5000 bullets: 5 MB).
using ContactArray = LargeArray<Contact>;

}  // namespace fulcrum::detail
