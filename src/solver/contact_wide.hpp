#pragma once
// The wide (SIMD) contact solver: kSimdLanes constraints of one graph colour
// solved at once (4 with SSE2, the x86-64 default build; 8 when the library is
// built with -mavx2), with the constraint data in structure-of-arrays blocks
// and the bodies gathered and scattered per lane.
//
// Why it is correct: constraints of one colour share no dynamic body (the
// colouring in contact_solver.cpp), so the lanes of a block never write the
// same body and a block's result does not depend on the order of its lanes.
// Static bodies are solver body 0 (all zeros) and kinematic bodies have
// infinite mass: they are gathered (a kinematic body has a velocity) but
// never scattered (writeA/writeB hold kEmptyLane), so lanes may share them.
//
// Why it is the scalar solver, bit for bit: every kernel does the same float
// operations in the same order as its scalar twin in contact_solver.cpp, and
// src/math/simd.hpp's operations are lane-wise the scalar ones. std::max(a, b)
// is (a < b) ? b : a, which is the wide max(b, a); std::min(a, b) is the wide
// min(b, a); std::clamp is two selects in its own order. The scalar branches
// become selects whose untaken side changes nothing; a lane beyond a
// manifold's point count has zero mass and zero impulse, so it adds exactly
// zero. The only freedom left is the sign of a zero (x - 0 vs x - (-0) when x
// is itself zero), which no later operation turns into a different non-zero
// value (there is no division by a velocity). tests/solver/simd_solver_test.cpp
// checks positions and velocities for equality over a pile's whole fall.
#include <cstdint>

#include "math/simd.hpp"

namespace fulcrum::detail {

struct SolverBody;
struct ContactConstraint;
struct Contact;
struct CachedManifold;
struct Softness;

inline constexpr int kWideLanes = simd::kSimdLanes;

struct WidePoint {
    simd::Vec3W rAxn, rBxn, angA, angB;
    simd::FloatW baseSeparation, normalMass, normalImpulse, maxNormalImpulse, relativeVelocity;
};

// What a block needs only when a lane has more than one point or rolling
// resistance, kept out of the block so that blocks of one-point contacts
// (sphere piles) are dense: measured on sphere_pile, see docs/solver.md.
struct WideBlockExtra {
    WidePoint points[3];                                   // points 1-3
    simd::Vec3W rollingMass0, rollingMass1, rollingMass2;  // columns
    simd::Vec3W rollingImpulse;
};

// kWideLanes constraints of one colour. Lanes past laneCount are empty: no
// bodies, zero masses and impulses. Points past a lane's count are zero.
struct WideContactBlock {
    std::uint32_t bodyA[kWideLanes], bodyB[kWideLanes];    // gather: solver body (0: static)
    std::uint32_t writeA[kWideLanes], writeB[kWideLanes];  // scatter: the body if dynamic, else kEmptyLane
    std::uint32_t laneCount = 0, pointCount = 0;           // pointCount: the largest of the lanes
    bool rolling = false;                                  // a lane has rolling resistance
    bool bouncy = false;                                   // a lane has restitution
    WideBlockExtra* extra = nullptr;                       // points 1-3 and rolling; set iff pointCount > 1 or rolling
    simd::Vec3W normal, tangent1, tangent2;
    simd::FloatW friction, biasRate, massScale, impulseScale;
    WidePoint point0;
    simd::Vec3W rAc1, rAc2, rBc1, rBc2, angA1, angA2, angB1, angB2, twistA, twistB;
    simd::FloatW k11, k12, k22, tangentImpulse1, tangentImpulse2, twistMass, twistImpulse, twistRadius;
    // Cold: restitution and store only.
    simd::FloatW rollingResistance, restitution;
    std::uint32_t contact[kWideLanes], manifold[kWideLanes];  // where store() writes each lane's results
    std::uint32_t lanePoints[kWideLanes];                  // each lane's point count

    WidePoint& point(std::uint32_t i) { return i == 0 ? point0 : extra->points[i - 1]; }
    const WidePoint& point(std::uint32_t i) const { return i == 0 ? point0 : extra->points[i - 1]; }
};

// An empty block: every lane without bodies, masses or impulses.
void clearBlock(WideContactBlock& block);

// What ContactSolver::buildConstraint reads for one constraint, copied out of
// its contact and manifold (prepare stages these in colour order, so the block
// build reads them sequentially instead of chasing one manifold allocation
// per lane).
struct LaneSource {
    Vec3 normal;
    std::uint32_t pointCount = 0;
    Vec3 frictionImpulse;
    Real twistImpulse = 0;
    Vec3 rollingImpulse;
    std::uint32_t bodyA = 0, bodyB = 0, contact = 0, manifoldIndex = 0;
    Real friction = 0, restitution = 0, rollingResistance = 0;
    struct Point {
        Vec3 position;
        Real depth = 0, normalImpulse = 0;
    } points[4];
};
// A whole block built kWideLanes constraints at a time: lanes [0, laneCount)
// from `lanes`, the rest empty. The same operations in the same order as
// buildConstraint (the scalar reference), so the same bits:
// tests/solver/simd_solver_test.cpp compares the two solvers step by step.
// startCom: each solver body's centre of mass at the step's start. `extra`
// is this block's own side storage, used (and then attached) only when a
// lane has several points or rolling resistance.
void buildBlock(WideContactBlock& block, WideBlockExtra& extra, const LaneSource* lanes, int laneCount,
                const SolverBody* bodies, const Vec3* startCom, const Softness& dynamicSoftness,
                const Softness& stiffSoftness);

void warmStartWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies);
void solveWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, bool useBias, Real invH,
               Real pushMax);
// Twins of ContactSolver::applyRestitution and store.
void restitutionWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, Real threshold);
void storeWide(const WideContactBlock* blocks, std::size_t count, const SolverBody* bodies, Contact* contacts);

}  // namespace fulcrum::detail
