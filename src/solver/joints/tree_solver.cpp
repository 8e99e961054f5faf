// Direct (linear-time) solve of the point rows of joint trees: see tree_solver.hpp.
#include "solver/joints/tree_solver.hpp"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "math/simd.hpp"
#include "solver/joints/joint_types.hpp"

// solveGroupInLanes' residuals and impulses in SSE float lanes
// (JointTreeSolver::setWideEnds): where the build's Real is a float and SSE2
// is there (the double build, WebAssembly and others: tree by tree).
#if FULCRUM_SIMD_HAS_SSE2 && !defined(FULCRUM_SIMD_PORTABLE)
#define FULCRUM_TREE_WIDE_ENDS 1
#else
#define FULCRUM_TREE_WIDE_ENDS 0
#endif
// Their bodies are inlined into two entry points each; the second is compiled
// for AVX2 (the function's target only: the file keeps the baseline, and
// inline functions it calls but does not inline stay baseline copies), run
// only on the AVX2 path. Elsewhere (MSVC, and WebAssembly, whose SSE2 is
// SIMD128 with no AVX2 target) both entry points are baseline.
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
#define FULCRUM_TREE_WIDE_INLINE inline __attribute__((always_inline))
#define FULCRUM_TREE_WIDE_VEX __attribute__((target("avx2")))
#else
#define FULCRUM_TREE_WIDE_INLINE inline
#define FULCRUM_TREE_WIDE_VEX
#endif

namespace fulcrum::detail {

namespace {

bool hasPointBlock(const JointConstraint& j) {
    return withJointType(j.type, [&](auto type) {
        using T = decltype(type);
        if constexpr (requires { T::pointBlock(j); }) {
            return T::pointBlock(j);  // per joint (a six-DOF's point rows: all three linear axes locked)
        } else {
            return T::kHasPointBlock;
        }
    });
}

// In-place Cholesky of the N x N symmetric matrix a (lower triangle used).
// The diagonal keeps the factor's reciprocal: the solves multiply instead of
// dividing (chain scene: 0.82 -> 0.66 ms/step median, side by side).
template <int N>
bool cholesky(double a[6][6]) {
    for (int j = 0; j < N; ++j) {
        double s = a[j][j];
        for (int k = 0; k < j; ++k) s -= a[j][k] * a[j][k];
        if (!(s > 1e-300)) return false;
        const double inv = 1 / std::sqrt(s);
        a[j][j] = inv;
        for (int i = j + 1; i < N; ++i) {
            double t = a[i][j];
            for (int k = 0; k < j; ++k) t -= a[i][k] * a[j][k];
            a[i][j] = t * inv;
        }
    }
    return true;
}

// x <- (L L^T)^-1 x.
template <int N>
void applyCholeskyInverse(const double L[6][6], double* x) {
    for (int i = 0; i < N; ++i) {
        double t = x[i];
        for (int k = 0; k < i; ++k) t -= L[i][k] * x[k];
        x[i] = t * L[i][i];
    }
    for (int i = N - 1; i >= 0; --i) {
        double t = x[i];
        for (int k = i + 1; k < N; ++k) t -= L[k][i] * x[k];
        x[i] = t * L[i][i];
    }
}

// The inverse of a negative definite 3x3 block D (lower triangle read): the
// adjugate of -D, whose Sylvester minors say whether it is definite; false
// if not. Shared by invertInPlace<3> and eliminateChainJoint (same bits).
struct SymmetricInverse3 {
    double i00, i11, i22, i10, i20, i21;
    // D^-1 z as the chain sweeps sum it (eliminateChainJoint, forwardChainJoint).
    void times(double z0, double z1, double z2, double y[3]) const {
        y[0] = i00 * z0 + i10 * z1 + i20 * z2;
        y[1] = i10 * z0 + i11 * z1 + i21 * z2;
        y[2] = i20 * z0 + i21 * z1 + i22 * z2;
    }
    // The root's D^-1 z as multiplyInPlace<3> sums it (from 0.0, so a -0 term gives +0).
    void timesFromZero(double z0, double z1, double z2, double y[3]) const {
        y[0] = ((0.0 + i00 * z0) + i10 * z1) + i20 * z2;
        y[1] = ((0.0 + i10 * z0) + i11 * z1) + i21 * z2;
        y[2] = ((0.0 + i20 * z0) + i21 * z1) + i22 * z2;
    }
    void store(double a[6][6]) const {
        a[0][0] = i00, a[1][1] = i11, a[2][2] = i22;
        a[0][1] = a[1][0] = i10;
        a[0][2] = a[2][0] = i20;
        a[1][2] = a[2][1] = i21;
    }
};

inline bool invertNegativeDefinite3(const double a[6][6], SymmetricInverse3& out) {
    const double m00 = -a[0][0], m10 = -a[1][0], m11 = -a[1][1], m20 = -a[2][0], m21 = -a[2][1], m22 = -a[2][2];
    const double c00 = m11 * m22 - m21 * m21;
    const double c10 = m21 * m20 - m10 * m22;
    const double c20 = m10 * m21 - m11 * m20;
    const double det = m00 * c00 + m10 * c10 + m20 * c20;
    const double minor2 = m00 * m11 - m10 * m10;
    if (!(m00 > 1e-300) || !(minor2 > 1e-300) || !(det > 1e-300)) return false;
    const double s = -1 / det;  // D^-1 = -(-D)^-1
    const double c11 = m00 * m22 - m20 * m20;
    const double c21 = m20 * m10 - m00 * m21;
    out = {c00 * s, c11 * s, minor2 * s, c10 * s, c20 * s, c21 * s};
    return true;
}

// a <- a^-1 in place (a symmetric; the lower triangle is read, the whole
// inverse written). Joints' blocks are negative definite, bodies' positive
// definite; false if singular. Every later use of the block is then a dense
// mat-vec of independent multiply-adds instead of two dependent triangular
// solves (the solver's other passes apply D^-1 about 5 times per node).
template <int N>
bool invertInPlace(double a[6][6]) {
    if constexpr (N == 3) {
        SymmetricInverse3 inv;
        if (!invertNegativeDefinite3(a, inv)) return false;
        inv.store(a);
        return true;
    } else {
        double L[6][6];
        for (int r = 0; r < N; ++r) {
            for (int c = 0; c <= r; ++c) L[r][c] = a[r][c];
        }
        if (!cholesky<N>(L)) return false;
        for (int c = 0; c < N; ++c) {
            double e[6] = {};
            e[c] = 1;
            applyCholeskyInverse<N>(L, e);
            for (int r = 0; r < N; ++r) a[r][c] = e[r];
        }
        return true;
    }
}

// x <- A x for the N x N block A (a factored block, stored inverted).
template <int N>
void multiplyInPlace(const double a[6][6], double* x) {
    double y[6];
    for (int r = 0; r < N; ++r) {
        double t = 0;
        for (int k = 0; k < N; ++k) t += a[r][k] * x[k];
        y[r] = t;
    }
    for (int r = 0; r < N; ++r) x[r] = y[r];
}

// The 3 x 6 Jacobian block of a point row on one body: [s I, -s [r]x] with
// s = +1 on B, -1 on A (J v = s (v - r x w)).
void jacobian(double out[3][6], const Vec3& r, double s) {
    const double rx = r.x, ry = r.y, rz = r.z;
    const double skew[3][3] = {{0, -rz, ry}, {rz, 0, -rx}, {-ry, rx, 0}};
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            out[i][k] = i == k ? s : 0;
            out[i][3 + k] = -s * skew[i][k];
        }
    }
}

// The point rows' couplings through one body, J_p M^-1 J_c^T for two anchors
// p, c with signs sp, sc (+1 on B, -1 on A):
//     sp sc (invMass I - [p]x invI [c]x)      (J = s [I, -[r]x], [r]x^T = -[r]x).
// With p = c and sp = sc, the body's share of the joint's K = J M^-1 J^T.
struct BodyCoupling {
    double invMass;
    double invI[3][3];
    explicit BodyCoupling(const SolverBody& b) : invMass(static_cast<double>(b.invMass)) {
        for (int r = 0; r < 3; ++r) {
            for (int k = 0; k < 3; ++k) invI[r][k] = static_cast<double>(b.invI(r, k));
        }
    }
    // T = invI [c]x: row r of T is (row r of invI) x c.
    void rightSkew(double T[3][3], const Vec3& c) const {
        const double cx = c.x, cy = c.y, cz = c.z;
        for (int r = 0; r < 3; ++r) {
            T[r][0] = invI[r][1] * cz - invI[r][2] * cy;
            T[r][1] = invI[r][2] * cx - invI[r][0] * cz;
            T[r][2] = invI[r][0] * cy - invI[r][1] * cx;
        }
    }
    // D -= invMass I - [c]x T with T = invI [c]x: the body's share of the K
    // of a joint anchored at c on it (D = minus the joint's K). Symmetric, so
    // only the lower triangle, which is all the elimination reads (the same
    // bits as adding couple(c, T, -1) there, with 6 entries instead of 9).
    void subtractShare(double D[][6], const Vec3& c, const double T[3][3]) const {
        const double cx = c.x, cy = c.y, cz = c.z;
        D[0][0] += (cy * T[2][0] - cz * T[1][0]) - invMass;
        D[1][0] += cz * T[0][0] - cx * T[2][0];
        D[1][1] += (cz * T[0][1] - cx * T[2][1]) - invMass;
        D[2][0] += cx * T[1][0] - cy * T[0][0];
        D[2][1] += cx * T[1][1] - cy * T[0][1];
        D[2][2] += (cx * T[1][2] - cy * T[0][2]) - invMass;
    }
    // The terms subtractShare adds, lower triangle in the order
    // (0,0), (1,0), (1,1), (2,0), (2,1), (2,2): added later with the same
    // bits (solveChain carries a body's share to the parent joint's block).
    void shareTerms(double out[6], const Vec3& c, const double T[3][3]) const {
        const double cx = c.x, cy = c.y, cz = c.z;
        out[0] = (cy * T[2][0] - cz * T[1][0]) - invMass;
        out[1] = cz * T[0][0] - cx * T[2][0];
        out[2] = (cz * T[0][1] - cx * T[2][1]) - invMass;
        out[3] = cx * T[1][0] - cy * T[0][0];
        out[4] = cx * T[1][1] - cy * T[0][1];
        out[5] = (cx * T[1][2] - cy * T[0][2]) - invMass;
    }
    // out = s (invMass I - [p]x T), T = invI [c]x: the coupling of anchors p and c.
    void couple(double out[][6], const Vec3& p, const double T[3][3], double s) const {
        const double px = p.x, py = p.y, pz = p.z;
        for (int k = 0; k < 3; ++k) {
            const double t0 = T[0][k], t1 = T[1][k], t2 = T[2][k];
            double col[3] = {-s * (py * t2 - pz * t1), -s * (pz * t0 - px * t2), -s * (px * t1 - py * t0)};
            col[k] += s * invMass;
            for (int r = 0; r < 3; ++r) out[r][k] = col[r];
        }
    }
};

}  // namespace

void JointTreeSolver::build(std::vector<JointConstraint>& joints, const std::vector<SolverBody>& bodies) {
    findTrees(joints, bodies);
    direct_.resize(joints.size());
    for (std::size_t k = 0; k < joints.size(); ++k) direct_[k] = joints[k].direct ? 1 : 0;
}

void JointTreeSolver::reuse(std::vector<JointConstraint>& joints) {
    for (std::size_t k = 0; k < joints.size(); ++k) joints[k].direct = direct_[k] != 0;
    valid_.assign(trees_, 1);
    factored_ = false;
}

void JointTreeSolver::markWarmStartFree(std::vector<JointConstraint>& joints, const std::vector<std::uint8_t>& bodyHasRows) {
    warmFree_.assign(trees_, 0);
    for (std::size_t t = 0; t < trees_; ++t) {
        bool free = true;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1] && free; ++i) {
            if (!nodes_[i].joint) continue;
            const JointConstraint& j = joints[nodes_[i].ref];
            free = j.type == JointType::Ball && !(j.maxFrictionImpulse > 0) && !bodyHasRows[j.bodyA] && !bodyHasRows[j.bodyB];
        }
        warmFree_[t] = free ? 1 : 0;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            if (nodes_[i].joint) joints[nodes_[i].ref].warmStartInTree = free;
        }
    }
}

void JointTreeSolver::findTrees(std::vector<JointConstraint>& joints, const std::vector<SolverBody>& bodies) {
    nodes_.clear();
    trees_ = 0;
    groupOf_.clear();
    lanePassesOf_.clear();
    laneFactorPassesOf_.clear();
    laneFactorChecksOf_.clear();
    laneFactorMismatchesOf_.clear();
    laneOnly_.clear();
    treeStart_.clear();
    const std::size_t nb = bodies.size(), nj = joints.size();
    const auto dynamic = [&](std::uint32_t i) { return i != 0 && bodies[i].invMass > 0; };
    const auto eligible = [&](const JointConstraint& j) {
        return hasPointBlock(j) && (dynamic(j.bodyA) || dynamic(j.bodyB));
    };
    bool any = false;
    for (JointConstraint& j : joints) {
        j.direct = false;
        any = any || eligible(j);
    }
    valid_.clear();
    if (!any) return;

    // Components of dynamic bodies over eligible joints (union-find).
    parentOf_.resize(nb);
    for (std::uint32_t i = 0; i < nb; ++i) parentOf_[i] = i;
    const auto find = [&](std::uint32_t i) {
        while (parentOf_[i] != i) {
            parentOf_[i] = parentOf_[parentOf_[i]];
            i = parentOf_[i];
        }
        return i;
    };
    for (const JointConstraint& j : joints) {
        if (!eligible(j)) continue;
        if (dynamic(j.bodyA) && dynamic(j.bodyB)) {
            const std::uint32_t ra = find(j.bodyA), rb = find(j.bodyB);
            if (ra != rb) parentOf_[ra > rb ? ra : rb] = ra < rb ? ra : rb;
        }
    }

    // A body whose inertia can't be inverted (locked rotation) makes the
    // elimination singular: its whole group stays on Gauss-Seidel.
    singular_.assign(nb, 0);
    visited_.assign(nb + nj, 0);  // bodies [0, nb), joints [nb, nb + nj)
    contracted_.assign(nb, 0);
    for (const JointConstraint& j : joints) {
        if (!eligible(j)) continue;
        for (const std::uint32_t b : {j.bodyA, j.bodyB}) {
            if (!dynamic(b) || visited_[b]) continue;
            visited_[b] = 1;
            if (!(determinant(bodies[b].invI) > 0)) singular_[find(b)] = 1;
        }
    }
    const auto usable = [&](const JointConstraint& j) {
        return eligible(j) && !singular_[find(dynamic(j.bodyA) ? j.bodyA : j.bodyB)];
    };

    // Adjacency: body -> its usable joints (CSR).
    adjStart_.assign(nb + 1, 0);
    for (const JointConstraint& j : joints) {
        if (!usable(j)) continue;
        if (dynamic(j.bodyA)) ++adjStart_[j.bodyA + 1];
        if (dynamic(j.bodyB)) ++adjStart_[j.bodyB + 1];
    }
    for (std::size_t i = 0; i < nb; ++i) adjStart_[i + 1] += adjStart_[i];
    adj_.resize(adjStart_[nb]);
    order_.assign(adjStart_.begin(), adjStart_.end() - 1);  // fill cursors
    for (std::uint32_t k = 0; k < nj; ++k) {
        const JointConstraint& j = joints[k];
        if (!usable(j)) continue;
        if (dynamic(j.bodyA)) adj_[order_[j.bodyA]++] = k;
        if (dynamic(j.bodyB)) adj_[order_[j.bodyB]++] = k;
    }

    // The spanning forest: which joints are tree edges (solved exactly) and
    // which close a loop (they stay Gauss-Seidel rows). Every joint to a
    // static or kinematic end roots a tree of its own, unless its body was
    // claimed by an earlier one (a second anchor to the world closes a loop
    // through it); the trees then grow breadth first side by side, each body
    // joining the first tree to reach it. A group that is a tree keeps all its
    // joints; a grid hung from a row of anchors becomes one chain per column
    // (the joints that carry the load), its cross joints loop edges. A group
    // with no joint to the world is rooted at its first joint's body A.
    // Deterministic: sources in joint order, adjacency in joint order.
    treeEdge_.assign(nj, 0);
    rootOf_.assign(nb, kNone);  // per claimed body: its tree's root joint (to the world), or kBodyRoot | root body
    std::vector<std::uint32_t>& frontier = frontier_;
    frontier.clear();
    std::fill(visited_.begin(), visited_.end(), 0);  // here: bodies claimed
    const auto grow = [&](std::size_t from) {
        for (std::size_t head = from; head < frontier.size(); ++head) {
            const std::uint32_t u = frontier[head];
            for (std::uint32_t e = adjStart_[u]; e < adjStart_[u + 1]; ++e) {
                const std::uint32_t k = adj_[e];
                const JointConstraint& j = joints[k];
                const std::uint32_t o = j.bodyA == u ? j.bodyB : j.bodyA;
                if (!dynamic(o) || visited_[o]) continue;  // to the world, or closing a loop
                visited_[o] = 1;
                treeEdge_[k] = 1;
                rootOf_[o] = rootOf_[u];
                frontier.push_back(o);
            }
        }
    };
    for (std::uint32_t k = 0; k < nj; ++k) {
        const JointConstraint& j = joints[k];
        if (!usable(j) || (dynamic(j.bodyA) && dynamic(j.bodyB))) continue;
        const std::uint32_t b = dynamic(j.bodyA) ? j.bodyA : j.bodyB;
        if (visited_[b]) continue;
        visited_[b] = 1;
        treeEdge_[k] = 1;
        rootOf_[b] = k;
        frontier.push_back(b);
    }
    grow(0);
    for (std::uint32_t k = 0; k < nj; ++k) {
        const JointConstraint& j = joints[k];
        if (!usable(j) || visited_[j.bodyA] || !dynamic(j.bodyA)) continue;
        visited_[j.bodyA] = 1;
        rootOf_[j.bodyA] = kBodyRoot | j.bodyA;
        const std::size_t from = frontier.size();
        frontier.push_back(j.bodyA);
        grow(from);
    }

    // Breadth-first from each tree's root (its joint to the world if it has
    // one, else its root body) over the tree edges, then stored reversed so
    // that children come before parents. Trees start in joint order: deterministic.
    std::fill(visited_.begin(), visited_.end(), 0);
    std::vector<Pending>& queue = queue_;
    for (std::uint32_t k = 0; k < nj; ++k) {
        const JointConstraint& first = joints[k];
        if (!treeEdge_[k] || visited_[nb + k]) continue;
        const std::uint32_t root = rootOf_[dynamic(first.bodyA) ? first.bodyA : first.bodyB];
        queue.clear();
        if ((root & kBodyRoot) == 0) {
            queue.push_back({root, kNone, true, false});
            visited_[nb + root] = 1;
        } else {
            queue.push_back({root & ~kBodyRoot, kNone, false, false});
            visited_[root & ~kBodyRoot] = 1;
        }
        for (std::uint32_t head = 0; head < queue.size(); ++head) {
            const Pending p = queue[head];
            if (p.joint) {
                const JointConstraint& j = joints[p.ref];
                for (const std::uint32_t b : {j.bodyA, j.bodyB}) {
                    if (!dynamic(b) || visited_[b]) continue;
                    visited_[b] = 1;
                    queue.push_back({b, head, false, b == j.bodyA});
                }
            } else {
                for (std::uint32_t e = adjStart_[p.ref]; e < adjStart_[p.ref + 1]; ++e) {
                    const std::uint32_t k2 = adj_[e];
                    if (!treeEdge_[k2] || visited_[nb + k2]) continue;
                    visited_[nb + k2] = 1;
                    queue.push_back({k2, head, true, joints[k2].bodyA == p.ref});
                }
            }
        }
        // Contraction: a body with at most one child joint (every link of a
        // chain, a ragdoll's limbs and head) is eliminated first, while its D is
        // still its mass M, whose inverse the solver body already holds. Its
        // parent joint q and child joint c then couple directly through the 3x3
        // block -J_q M^-1 J_c^T, so a chain becomes a block-tridiagonal system of
        // 3x3 joint blocks (the joint-space K = J M^-1 J^T) and the 6x6 body
        // blocks remain only at branch points (a ragdoll's torso and pelvis) and
        // at a free tree's root. Same exact solution, no fill-in. Measured with
        // the inverted blocks (side by side, bench_joints): chain 0.65-0.72 ->
        // 0.26-0.27 ms/step, worst joint error unchanged (0.54 cm); callgrind
        // (120 chain steps) 491 M -> 369 M instructions; ragdoll pile (first 60
        // steps) 4,343 M -> 3,722 M.
        const std::uint32_t count = static_cast<std::uint32_t>(queue.size());
        children_.assign(count, 0);
        for (std::uint32_t q = 0; q < count; ++q) {
            if (queue[q].parentPos != kNone) ++children_[queue[q].parentPos];
        }
        const auto isContracted = [&](std::uint32_t q) {
            return !queue[q].joint && queue[q].parentPos != kNone && children_[q] <= 1;
        };
        for (std::uint32_t q = 0; q < count; ++q) {
            if (!queue[q].joint) contracted_[queue[q].ref] = isContracted(q) ? (children_[q] == 0 ? 1 : 2) : 0;
        }
        const std::uint32_t base = static_cast<std::uint32_t>(nodes_.size());
        nodeOf_.assign(count, kNone);
        std::uint32_t next = base;
        for (std::uint32_t q = count; q-- > 0;) {
            if (!isContracted(q)) nodeOf_[q] = next++;
        }
        treeStart_.push_back(base);
        for (std::uint32_t q = count; q-- > 0;) {
            if (isContracted(q)) continue;
            const Pending& p = queue[q];
            Node n;
            n.ref = p.ref;
            n.joint = p.joint;
            n.bodyIsA = p.bodyIsA;
            if (p.parentPos != kNone) {
                if (p.joint && isContracted(p.parentPos)) {
                    const Pending& via = queue[p.parentPos];  // a body; its parent is a joint
                    n.parent = nodeOf_[via.parentPos];
                    n.via = via.ref;
                    n.viaIsA = p.bodyIsA;
                    n.viaIsParentA = via.bodyIsA;
                } else {
                    n.parent = nodeOf_[p.parentPos];
                }
            }
            if (p.joint) {
                const JointConstraint& j = joints[p.ref];
                // A contracted leaf's share goes to its one joint; a contracted
                // body with a child joint is handled by that child (its share
                // of both joints and the coupling, from one copy of its inertia).
                n.ownA = dynamic(j.bodyA) && contracted_[j.bodyA] == 1;
                n.ownB = dynamic(j.bodyB) && contracted_[j.bodyB] == 1;
                joints[p.ref].direct = true;
            }
            nodes_.push_back(n);
        }
        ++trees_;
    }
    treeStart_.push_back(static_cast<std::uint32_t>(nodes_.size()));
    if (factors_.size() < nodes_.size()) factors_.resize(nodes_.size());
    valid_.assign(trees_, 1);
    for (const std::uint64_t k : guardTripsOf_) guardTripsPast_ += k;
    guardTripsOf_.assign(trees_, 0);
    kind_.resize(nodes_.size());
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const Node& n = nodes_[i];
        kind_[i] = !n.joint ? kBodyNode : n.parent != kNone && nodes_[n.parent].joint ? kJointBelowJoint : kJointBelowBody;
    }
    chain_.assign(trees_, 0);
    for (std::size_t t = 0; t < trees_; ++t) {
        bool chain = true;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            const Node& n = nodes_[i];
            const bool root = i + 1 == treeStart_[t + 1];
            chain = chain && n.joint && (root ? n.parent == kNone : n.parent == i + 1 && n.via != kNone);
        }
        chain_[t] = chain ? 1 : 0;
        if (!chain) continue;
        if (links_.size() < nodes_.size()) links_.resize(nodes_.size());
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            const Node& n = nodes_[i];
            ChainLink& link = links_[i];
            link.via = n.via;
            link.viaIsA = n.viaIsA;
            link.viaIsParentA = n.viaIsParentA;
            link.ownA = n.ownA;
            link.ownB = n.ownB;
        }
    }
    groupTrees();
    factored_ = false;
}

// Inlined into solveTree (called once or twice per joint and pass).
inline void JointTreeSolver::forwardChainJoint(std::uint32_t i) {
    Factor& f = factors_[i];
    Factor& pf = factors_[nodes_[i].parent];
    const double z0 = f.z[0], z1 = f.z[1], z2 = f.z[2];
    const double y0 = f.D[0][0] * z0 + f.D[0][1] * z1 + f.D[0][2] * z2;
    const double y1 = f.D[1][0] * z0 + f.D[1][1] * z1 + f.D[1][2] * z2;
    const double y2 = f.D[2][0] * z0 + f.D[2][1] * z1 + f.D[2][2] * z2;
    f.z[0] = y0, f.z[1] = y1, f.z[2] = y2;
    for (int r = 0; r < 3; ++r) pf.z[r] -= f.Hp[r][0] * y0 + f.Hp[r][1] * y1 + f.Hp[r][2] * y2;
}

inline void JointTreeSolver::backSubstituteChainJoint(std::uint32_t i) {
    Factor& f = factors_[i];
    const Factor& pf = factors_[nodes_[i].parent];
    const double p0 = pf.y[0], p1 = pf.y[1], p2 = pf.y[2];
    for (int k = 0; k < 3; ++k) f.y[k] = ((f.z[k] - f.X[0][k] * p0) - f.X[1][k] * p1) - f.X[2][k] * p2;
}

namespace {

// Whether anchor r has moved from its factorization's value rf by more than
// kGuardTurn of its length (a turn of that angle, to first order).
inline bool turnedTooFar(const Vec3& r, const Vec3& rf, Real turn2) {
    return lengthSquared(r - rf) > turn2 * lengthSquared(rf);
}

// applyPoint on the ends that move. A static or kinematic end (inverse mass 0)
// is unchanged by the impulse but may be shared by trees that other threads
// solve at the same time (JointTreeSolver::solveTrees): even writing its
// unchanged value would be a data race, so it is not written at all. The
// dynamic ends get exactly applyPoint's operations.
inline void applyPointToMovingEnds(SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& P) {
    if (a.invMass > 0) {
        a.v -= P * a.invMass;
        a.w -= a.invI * cross(rA, P);
    }
    if (b.invMass > 0) {
        b.v += P * b.invMass;
        b.w += b.invI * cross(rB, P);
    }
}

// The chain's per-joint 3-vector work (solveChain), written out per
// component: exactly the operations of Vec3's operators in their order
// (rotate(), the residual of solveTree, applyPointToMovingEnds with the
// mat-vec as (c0 x + c1 y) + c2 z), so the same bits, without the Vec3
// temporaries the compiler shuffles through the stack: applyPointToMovingEnds
// was 123 instructions per joint, these 104 (callgrind, chain). An SSE
// version (a 3-vector per register, shuffles for the cross products) took
// more instructions than this, not fewer (173.1 M against 171.6 M, 120 steps).
// A hint to load the line holding p (no effect on results).
inline void prefetch(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

// applyPointToMovingEnds for one end: v -= P m, w -= I^-1 (r x P) on A; += on B.
template <bool onB>
inline void pushEnd(SolverBody& s, const Vec3& r, Real px, Real py, Real pz) {
    const Real m = s.invMass;
    const Real cx = r.y * pz - r.z * py, cy = r.z * px - r.x * pz, cz = r.x * py - r.y * px;
    const Mat3& I = s.invI;
    const Real wx = (I.c0.x * cx + I.c1.x * cy) + I.c2.x * cz;
    const Real wy = (I.c0.y * cx + I.c1.y * cy) + I.c2.y * cz;
    const Real wz = (I.c0.z * cx + I.c1.z * cy) + I.c2.z * cz;
    if constexpr (onB) {
        s.v.x += px * m, s.v.y += py * m, s.v.z += pz * m;
        s.w.x += wx, s.w.y += wy, s.w.z += wz;
    } else {
        s.v.x -= px * m, s.v.y -= py * m, s.v.z -= pz * m;
        s.w.x -= wx, s.w.y -= wy, s.w.z -= wz;
    }
}


// A joint's solved impulse y (softened, or folded with the warm start as
// solveTree explains) into its accumulated impulse and onto its two bodies:
// the kept-factor passes' and the chains' last step.
inline void applyJointImpulse(JointConstraint& j, SolverBody* bodies, const Vec3& rA, const Vec3& rB, const double* y,
                              const JointContext& ctx, bool foldedWarmStart) {
    Vec3 d{static_cast<Real>(y[0]), static_cast<Real>(y[1]), static_cast<Real>(y[2])};
    if (foldedWarmStart) {
        d = d * ctx.soft.massScale + j.impulse.linear * (1 - ctx.soft.massScale - ctx.soft.impulseScale);
        j.impulse.linear = d;
    } else {
        if (ctx.useBias) d = d * ctx.soft.massScale - j.impulse.linear * ctx.soft.impulseScale;
        j.impulse.linear += d;
    }
    SolverBody& a = bodies[j.bodyA];
    SolverBody& b = bodies[j.bodyB];
    if (a.invMass > 0) pushEnd<false>(a, rA, d.x, d.y, d.z);
    if (b.invMass > 0) pushEnd<true>(b, rB, d.x, d.y, d.z);
}

}  // namespace

template <class ZAt>
bool JointTreeSolver::reusedResiduals(std::uint32_t tree, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                                      const JointContext& ctx, ZAt zAt) {
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    // Only a relax pass checks the guard (solveTree).
    const bool guard = !ctx.useBias;
    // Right-hand sides, parents first (a joint's before its child's forward
    // step subtracts from it): the residual J v (+ biasRate C) of a joint,
    // zero for a body.
    for (std::uint32_t i = end; i-- > begin;) {
        Factor& f = factors_[i];
        if (kind_[i] == kBodyNode) {
            for (int k = 0; k < 6; ++k) zAt(i, k) = 0;
            continue;
        }
        JointConstraint& j = joints[nodes_[i].ref];
        const SolverBody& a = bodies[j.bodyA];
        const SolverBody& b = bodies[j.bodyB];
        const JointFrame& fr = currentFrame(j, a, b, ctx);
        if (guard && (turnedTooFar(fr.rA, f.factorA, guardTurn2_) || turnedTooFar(fr.rB, f.factorB, guardTurn2_))) return false;
        f.rA = fr.rA;
        f.rB = fr.rB;
        // b.v + b.w x rB - a.v - a.w x rA (+ biasRate d), per component (solveChain's).
        Real rx = ((b.v.x + (b.w.y * fr.rB.z - b.w.z * fr.rB.y)) - a.v.x) - (a.w.y * fr.rA.z - a.w.z * fr.rA.y);
        Real ry = ((b.v.y + (b.w.z * fr.rB.x - b.w.x * fr.rB.z)) - a.v.y) - (a.w.z * fr.rA.x - a.w.x * fr.rA.z);
        Real rz = ((b.v.z + (b.w.x * fr.rB.y - b.w.y * fr.rB.x)) - a.v.z) - (a.w.x * fr.rA.y - a.w.y * fr.rA.x);
        if (ctx.useBias) {
            const Real bias = ctx.soft.biasRate;
            rx += fr.d.x * bias, ry += fr.d.y * bias, rz += fr.d.z * bias;
        }
        zAt(i, 0) = rx, zAt(i, 1) = ry, zAt(i, 2) = rz;
    }
    return true;
}

bool JointTreeSolver::solveTreeReused(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                      const JointContext& ctx, bool foldedWarmStart) {
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    if (!reusedResiduals(tree, joints, bodies, ctx, [this](std::uint32_t i, int k) -> double& { return factors_[i].z[k]; }))
        return false;
    if (laneOnly_[tree]) copyFactorFromLanes(tree);  // factored in its group's lanes (factorGroupInLanes)
    // Forward substitution on the stored factor, children first.
    for (std::uint32_t i = begin; i < end; ++i) {
        switch (kind_[i]) {
            case kBodyNode: forward<6, 3>(i); break;
            case kJointBelowJoint: forwardChainJoint(i); break;
            default: forward<3, 6>(i); break;
        }
    }
    // Back-substitution, parents first: y = D^-1 z - D^-1 Hp^T y_parent.
    for (std::uint32_t i = end; i-- > begin;) {
        switch (kind_[i]) {
            case kBodyNode: backSubstitute<6, 3>(i); break;
            case kJointBelowJoint: backSubstituteChainJoint(i); break;
            default: backSubstitute<3, 6>(i); break;
        }
    }
    // Impulses, children first (solveTree's).
    for (std::uint32_t i = begin; i < end; ++i) {
        if (kind_[i] == kBodyNode) continue;
        const Factor& f = factors_[i];
        applyJointImpulse(joints[nodes_[i].ref], bodies, f.rA, f.rB, f.y, ctx, foldedWarmStart);
    }
    return true;
}

// solveTree's (and factorGroupInLanes') first step of a factorization: the
// initial diagonal blocks and right-hand sides, parents first (a joint below
// a contracted body adds that body's share to its parent joint), and the
// anchors, into factors_.
void JointTreeSolver::buildBlocks(std::uint32_t tree, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                                  const JointContext& ctx) {
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    // Initial diagonal blocks and right-hand sides, parents first (a joint
    // below a contracted body adds that body's share to its parent joint).
    for (std::uint32_t i = end; i-- > begin;) {
        const Node& n = nodes_[i];
        Factor& f = factors_[i];
        if (n.joint) {
            JointConstraint& j = joints[n.ref];
            const SolverBody& a = bodies[j.bodyA];
            const SolverBody& b = bodies[j.bodyB];
            const JointFrame& fr = currentFrame(j, a, b, ctx);
            f.rA = fr.rA;
            f.rB = fr.rB;
            Vec3 r = b.v + cross(b.w, fr.rB) - a.v - cross(a.w, fr.rA);
            if (ctx.useBias) r += fr.d * ctx.soft.biasRate;
            f.z[0] = r.x, f.z[1] = r.y, f.z[2] = r.z;
            f.factorA = fr.rA;
            f.factorB = fr.rB;
            // D = -(the contracted ends' share of J M^-1 J^T): those bodies are
            // eliminated before everything else (build()). A contracted leaf's
            // share is added here by its joint; the share of a contracted body
            // with a child joint by that child, below, with the coupling.
            f.D[0][0] = f.D[1][0] = f.D[1][1] = f.D[2][0] = f.D[2][1] = f.D[2][2] = 0;  // lower triangle: all that is read
            double T[3][3];
            if (n.ownA) {
                const BodyCoupling ca(a);
                ca.rightSkew(T, fr.rA);
                ca.subtractShare(f.D, fr.rA, T);
            }
            if (n.ownB) {
                const BodyCoupling cb(b);
                cb.rightSkew(T, fr.rB);
                cb.subtractShare(f.D, fr.rB, T);
            }
            if (n.via != kNone) {
                // The contracted body between this joint (anchor c) and the
                // parent joint (anchor p): its share of both joints' K and the
                // coupling H(parent, this) = -J_p M^-1 J_c^T.
                Factor& pf = factors_[n.parent];
                const BodyCoupling cv(bodies[n.via]);
                const Vec3& c = n.viaIsA ? fr.rA : fr.rB;
                const Vec3& p = n.viaIsParentA ? pf.rA : pf.rB;
                const double sc = n.viaIsA ? -1 : 1, sp = n.viaIsParentA ? -1 : 1;
                cv.rightSkew(T, c);
                cv.subtractShare(f.D, c, T);
                cv.couple(f.Hp, p, T, -sp * sc);
                cv.rightSkew(T, p);
                cv.subtractShare(pf.D, p, T);
            }
        } else {
            for (double& z : f.z) z = 0;
            const SolverBody& b = bodies[n.ref];
            for (auto& row : f.D) {
                for (double& x : row) x = 0;
            }
            const double m = 1.0 / static_cast<double>(b.invMass);
            const Mat3 I = inverse(b.invI);
            for (int k = 0; k < 3; ++k) {
                f.D[k][k] = m;
                for (int l = 0; l < 3; ++l) f.D[3 + k][3 + l] = static_cast<double>(I(k, l));
            }
        }
    }
}

// Factor and forward-substitute the nodes [begin, end), children first;
// false when a block is not definite.
bool JointTreeSolver::eliminateNodes(std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = begin; i < end; ++i) {
        const Node& n = nodes_[i];
        bool ok;
        if (!n.joint) {
            ok = eliminate<6, 3>(i);
        } else if (n.parent != kNone && nodes_[n.parent].joint) {
            ok = eliminateChainJoint(i);
        } else {
            ok = eliminate<3, 6>(i);
        }
        if (!ok) return false;
    }
    return true;
}

// Back-substitute the nodes [begin, end), parents first:
// y = D^-1 z - D^-1 Hp^T y_parent.
void JointTreeSolver::backSubstituteNodes(std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = end; i-- > begin;) {
        const Node& n = nodes_[i];
        if (!n.joint) {
            backSubstitute<6, 3>(i);
        } else if (n.parent != kNone && nodes_[n.parent].joint) {
            backSubstituteChainJoint(i);
        } else {
            backSubstitute<3, 6>(i);
        }
    }
}

bool JointTreeSolver::solveTree(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                const JointContext& ctx, bool refactor, bool foldedWarmStart) {
    if (chain_[tree]) return solveChain(tree, joints, bodies, ctx, refactor, foldedWarmStart);
    // A reused factorization first checks that no anchor of the tree has
    // turned by more than kGuardTurn since it was made (the guard): a
    // stale K^-1 far from the current K may amplify instead of solve (a
    // factorization kept for a whole step, 5 sub-steps, sent the chain
    // benchmark to NaN at step 156). Tripped: this tree factors again now.
    // Only a relax pass needs the check: the anchors move with the positions,
    // and a biased pass sees the anchors of the relax pass before it (or
    // of its own factorization).
    if (!refactor) {
        if (solveTreeReused(tree, joints, bodies, ctx, foldedWarmStart)) return true;
        ++guardTripsOf_[tree];  // tripped (nothing applied): factor now, below
    }
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    laneOnly_[tree] = 0;  // factors_ holds this factorization
    buildBlocks(tree, joints, bodies, ctx);
    if (!eliminateNodes(begin, end)) return false;
    if (lanes_ != 0 && groupOf_[tree] != kNone) copyFactorToLanes(tree);
    backSubstituteNodes(begin, end);
    // Impulses: y = -(J M^-1 J^T)^-1 r, softened as a whole in the biased pass.
    for (std::uint32_t i = begin; i < end; ++i) {
        const Node& n = nodes_[i];
        if (!n.joint) continue;
        const Factor& f = factors_[i];
        JointConstraint& j = joints[n.ref];
        Vec3 d{static_cast<Real>(f.y[0]), static_cast<Real>(f.y[1]), static_cast<Real>(f.y[2])};
        if (foldedWarmStart) {
            // The warm start wasn't applied (markWarmStartFree): with it, the
            // exact y would have been y - lambda0 and the pass would have
            // applied lambda0 + s (y - lambda0) - i lambda0 in all, s y + (1 - s - i)
            // lambda0 (s + i = 1 for the soft coefficients, to rounding): the
            // same total, applied at once, and the new accumulated impulse.
            d = d * ctx.soft.massScale + j.impulse.linear * (1 - ctx.soft.massScale - ctx.soft.impulseScale);
            j.impulse.linear = d;
            applyPointToMovingEnds(bodies[j.bodyA], bodies[j.bodyB], f.rA, f.rB, d);
            continue;
        }
        if (ctx.useBias) d = d * ctx.soft.massScale - j.impulse.linear * ctx.soft.impulseScale;
        j.impulse.linear += d;
        applyPointToMovingEnds(bodies[j.bodyA], bodies[j.bodyB], f.rA, f.rB, d);
    }
    return true;
}

// A chain tree in one children-first sweep (issue 8, sixth round; docs/joints.md).
// solveTree's four loops over the generic Factor storage (blocks and
// residuals parents first, elimination or forward substitution children
// first, back-substitution, impulses) become two plus the impulses: each
// link builds its block and residual and is eliminated (or forward-
// substituted) at once, children first, carrying to its parent what the
// generic loops wrote into the parent's Factor (the body's share of the
// parent's block, the elimination's updates of its block and right-hand
// side), which the parent adds after its own terms, as before. Every value
// gets the same operations in the same order: the same bits (chain state
// hash unchanged). The parent's frame is needed for the coupling through
// the body between them; it is the next link's own frame (kept, so computed
// once per position update as before).
bool JointTreeSolver::solveChain(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                 const JointContext& ctx, bool refactor, bool foldedWarmStart) {
    const std::uint32_t begin = treeStart_[tree], root = treeStart_[tree + 1] - 1;
    // Only a relax pass that reuses checks the guard (solveTree).
    bool guard = !refactor && !ctx.useBias;
    bool again;
    do {
        again = false;
        // From the child (the link before): its body's share of this link's
        // block, its elimination's update of the block (lower triangle) and
        // of the right-hand side.
        double share[6] = {}, dsub[6] = {}, zsub[3] = {};
        JointConstraint* jc = &joints[nodes_[begin].ref];
        const JointFrame* fr = &currentFrame(*jc, bodies[jc->bodyA], bodies[jc->bodyB], ctx);
        for (std::uint32_t i = begin; i <= root; ++i) {
            ChainLink& L = links_[i];
            const JointConstraint& j = *jc;
            const SolverBody& a = bodies[j.bodyA];
            const SolverBody& b = bodies[j.bodyB];
            const JointFrame& f = *fr;
            L.rA = f.rA;
            L.rB = f.rB;
            // b.v + b.w x rB - a.v - a.w x rA (+ biasRate d), per component.
            Real rx = ((b.v.x + (b.w.y * f.rB.z - b.w.z * f.rB.y)) - a.v.x) - (a.w.y * f.rA.z - a.w.z * f.rA.y);
            Real ry = ((b.v.y + (b.w.z * f.rB.x - b.w.x * f.rB.z)) - a.v.y) - (a.w.z * f.rA.x - a.w.x * f.rA.z);
            Real rz = ((b.v.z + (b.w.x * f.rB.y - b.w.y * f.rB.x)) - a.v.z) - (a.w.x * f.rA.y - a.w.y * f.rA.x);
            if (ctx.useBias) {
                const Real bias = ctx.soft.biasRate;
                rx += f.d.x * bias, ry += f.d.y * bias, rz += f.d.z * bias;
            }
            if (guard && (turnedTooFar(f.rA, L.factorA, guardTurn2_) || turnedTooFar(f.rB, L.factorB, guardTurn2_))) {
                guard = false;
                refactor = true;
                ++guardTripsOf_[tree];
                again = true;
                break;
            }
            // The parent's frame (the next link's own).
            const JointFrame* pfr = nullptr;
            if (i < root) {
                jc = &joints[nodes_[i + 1].ref];
                pfr = &currentFrame(*jc, bodies[jc->bodyA], bodies[jc->bodyB], ctx);
                if (i + 2 <= root) {
                    // The constraints sit in colour order (a chain's alternate
                    // between two colours, ~600 bytes each): the lines the link
                    // after next reads, ahead of time (chain benchmark: 0.112 ->
                    // 0.109 ms/step median with the impulse loop's below).
                    const JointConstraint& ahead = joints[nodes_[i + 2].ref];
                    prefetch(&ahead.bodyA);
                    prefetch(&ahead.centreDelta);
                    prefetch(&ahead.frame);
                    prefetch(&ahead.frameAt);
                }
            }
            double z0 = rx, z1 = ry, z2 = rz;
            if (i > begin) z0 -= zsub[0], z1 -= zsub[1], z2 -= zsub[2];
            if (refactor) {
                L.factorA = f.rA;
                L.factorB = f.rB;
                double D[3][6] = {};  // lower triangle: minus this joint's K
                double T[3][3];
                if (L.ownA) {
                    const BodyCoupling ca(a);
                    ca.rightSkew(T, f.rA);
                    ca.subtractShare(D, f.rA, T);
                }
                if (L.ownB) {
                    const BodyCoupling cb(b);
                    cb.rightSkew(T, f.rB);
                    cb.subtractShare(D, f.rB, T);
                }
                double Hp[3][6] = {};
                double shareUp[6] = {};
                if (i < root) {
                    const BodyCoupling cv(bodies[L.via]);
                    const Vec3& c = L.viaIsA ? f.rA : f.rB;
                    const Vec3& p = L.viaIsParentA ? pfr->rA : pfr->rB;
                    const double sc = L.viaIsA ? -1 : 1, sp = L.viaIsParentA ? -1 : 1;
                    cv.rightSkew(T, c);
                    cv.subtractShare(D, c, T);
                    cv.couple(Hp, p, T, -sp * sc);
                    cv.rightSkew(T, p);
                    cv.shareTerms(shareUp, p, T);
                }
                if (i > begin) {
                    D[0][0] += share[0], D[1][0] += share[1], D[1][1] += share[2];
                    D[2][0] += share[3], D[2][1] += share[4], D[2][2] += share[5];
                    D[0][0] -= dsub[0], D[1][0] -= dsub[1], D[1][1] -= dsub[2];
                    D[2][0] -= dsub[3], D[2][1] -= dsub[4], D[2][2] -= dsub[5];
                }
                SymmetricInverse3 inv;
                if (!invertNegativeDefinite3(D, inv)) return false;
                const double i00 = inv.i00, i11 = inv.i11, i22 = inv.i22, i10 = inv.i10, i20 = inv.i20, i21 = inv.i21;
                L.D[0] = i00, L.D[1] = i11, L.D[2] = i22, L.D[3] = i10, L.D[4] = i20, L.D[5] = i21;
                if (i == root) {
                    inv.timesFromZero(z0, z1, z2, L.z);  // invertInPlace<3>, multiplyInPlace<3> (eliminate<3, 6>: no parent)
                    break;
                }
                // eliminateChainJoint.
                inv.times(z0, z1, z2, L.z);
                const double y0 = L.z[0], y1 = L.z[1], y2 = L.z[2];
                double x[3][3];
                for (int c = 0; c < 3; ++c) {
                    const double h0 = Hp[c][0], h1 = Hp[c][1], h2 = Hp[c][2];
                    x[c][0] = i00 * h0 + i10 * h1 + i20 * h2;
                    x[c][1] = i10 * h0 + i11 * h1 + i21 * h2;
                    x[c][2] = i20 * h0 + i21 * h1 + i22 * h2;
                    L.X[c][0] = x[c][0], L.X[c][1] = x[c][1], L.X[c][2] = x[c][2];
                    L.Hp[c][0] = h0, L.Hp[c][1] = h1, L.Hp[c][2] = h2;
                }
                for (int k = 0; k < 3; ++k) {
                    const double h0 = Hp[k][0], h1 = Hp[k][1], h2 = Hp[k][2];
                    zsub[k] = h0 * y0 + h1 * y1 + h2 * y2;
                }
                // D_parent -= Hp X, lower triangle in shareTerms' order.
                const auto hx = [&](int rr, int cc) {
                    return Hp[rr][0] * x[cc][0] + Hp[rr][1] * x[cc][1] + Hp[rr][2] * x[cc][2];
                };
                dsub[0] = hx(0, 0), dsub[1] = hx(1, 0), dsub[2] = hx(1, 1);
                dsub[3] = hx(2, 0), dsub[4] = hx(2, 1), dsub[5] = hx(2, 2);
                for (int k = 0; k < 6; ++k) share[k] = shareUp[k];
            } else {
                const SymmetricInverse3 inv{L.D[0], L.D[1], L.D[2], L.D[3], L.D[4], L.D[5]};
                if (i == root) {
                    inv.timesFromZero(z0, z1, z2, L.z);
                    break;
                }
                // forwardChainJoint.
                inv.times(z0, z1, z2, L.z);
                const double y0 = L.z[0], y1 = L.z[1], y2 = L.z[2];
                for (int k = 0; k < 3; ++k) zsub[k] = L.Hp[k][0] * y0 + L.Hp[k][1] * y1 + L.Hp[k][2] * y2;
            }
            fr = pfr;
        }
    } while (again);
    // Back-substitution, parents first: y = D^-1 z - D^-1 Hp^T y_parent.
    // (Applying each link's impulses here as its y is known, with the
    // per-body order kept, gave the same bits with 4 % more instructions
    // in the whole chain step and no measurable wall-clock gain.)
    {
        ChainLink& R = links_[root];
        R.y[0] = R.z[0], R.y[1] = R.z[1], R.y[2] = R.z[2];
    }
    double p0 = links_[root].y[0], p1 = links_[root].y[1], p2 = links_[root].y[2];
    for (std::uint32_t i = root; i-- > begin;) {
        ChainLink& L = links_[i];
        for (int k = 0; k < 3; ++k) L.y[k] = ((L.z[k] - L.X[0][k] * p0) - L.X[1][k] * p1) - L.X[2][k] * p2;
        p0 = L.y[0], p1 = L.y[1], p2 = L.y[2];
    }
    // Impulses, children first (solveTree's order).
    for (std::uint32_t i = begin; i <= root; ++i) {
        const ChainLink& L = links_[i];
        JointConstraint& j = joints[nodes_[i].ref];
        if (i + 2 <= root) {
            const JointConstraint& ahead = joints[nodes_[i + 2].ref];
            prefetch(&ahead.bodyA);
            prefetch(&ahead.impulse.linear);
        }
        applyJointImpulse(j, bodies, L.rA, L.rB, L.y, ctx, foldedWarmStart);
    }
    return true;
}

template <int dim, int pdim>
bool JointTreeSolver::eliminate(std::uint32_t i) {
    const Node& n = nodes_[i];
    Factor& f = factors_[i];
    if (!invertInPlace<dim>(f.D)) return false;  // f.D <- D^-1
    multiplyInPlace<dim>(f.D, f.z);  // z <- D^-1 z
    if (n.parent == kNone) return true;
    Factor& pf = factors_[n.parent];
    // H(parent, this).
    if constexpr (dim == 6) {  // a body of the parent joint
        double J[3][6];
        jacobian(J, n.bodyIsA ? pf.rA : pf.rB, n.bodyIsA ? -1 : 1);
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 6; ++c) f.Hp[r][c] = J[r][c];
        }
    } else if constexpr (pdim == 6) {  // a joint on the parent body: the transpose
        double J[3][6];
        jacobian(J, n.bodyIsA ? f.rA : f.rB, n.bodyIsA ? -1 : 1);
        for (int r = 0; r < 6; ++r) {
            for (int c = 0; c < 3; ++c) f.Hp[r][c] = J[c][r];
        }
    }  // else: a joint below a contracted body, H(parent, this) = -J_p M^-1 J^T set with D (solveTree)
    // X = D^-1 Hp^T (kept for back-substitution); D_parent -= Hp X; z_parent -= Hp (D^-1 z).
    for (int c = 0; c < pdim; ++c) {
        for (int k = 0; k < dim; ++k) {
            double t = 0;
            for (int l = 0; l < dim; ++l) t += f.D[k][l] * f.Hp[c][l];
            f.X[c][k] = t;
        }
    }
    for (int r = 0; r < pdim; ++r) {
        double zr = 0;
        for (int k = 0; k < dim; ++k) zr += f.Hp[r][k] * f.z[k];
        pf.z[r] -= zr;
        for (int c = 0; c <= r; ++c) {
            double s = 0;
            for (int k = 0; k < dim; ++k) s += f.Hp[r][k] * f.X[c][k];
            pf.D[r][c] -= s;
        }
    }
    return true;
}

// The joint-below-joint case (every link of a chain) written out with its
// 3x3 blocks in locals: the same operations in the same order as
// eliminate<3, 3> (so the same bits), without the generic loops over the
// 6x6 storage. Chain benchmark (callgrind, 600 steps): eliminate<3, 3>
// 325 instructions per call before; the whole run 1,053 M -> 1,035 M.
bool JointTreeSolver::eliminateChainJoint(std::uint32_t i) {
    Factor& f = factors_[i];
    Factor& pf = factors_[nodes_[i].parent];
    // D^-1, in locals and stored.
    SymmetricInverse3 inv;
    if (!invertNegativeDefinite3(f.D, inv)) return false;
    inv.store(f.D);
    const double i00 = inv.i00, i11 = inv.i11, i22 = inv.i22, i10 = inv.i10, i20 = inv.i20, i21 = inv.i21;
    // z <- D^-1 z.
    const double z0 = f.z[0], z1 = f.z[1], z2 = f.z[2];
    const double y0 = i00 * z0 + i10 * z1 + i20 * z2;
    const double y1 = i10 * z0 + i11 * z1 + i21 * z2;
    const double y2 = i20 * z0 + i21 * z1 + i22 * z2;
    f.z[0] = y0, f.z[1] = y1, f.z[2] = y2;
    // X = D^-1 Hp^T (row c: D^-1 times row c of Hp); z_parent -= Hp (D^-1 z);
    // D_parent -= Hp X (lower triangle).
    double x[3][3];
    for (int c = 0; c < 3; ++c) {
        const double h0 = f.Hp[c][0], h1 = f.Hp[c][1], h2 = f.Hp[c][2];
        x[c][0] = i00 * h0 + i10 * h1 + i20 * h2;
        x[c][1] = i10 * h0 + i11 * h1 + i21 * h2;
        x[c][2] = i20 * h0 + i21 * h1 + i22 * h2;
        f.X[c][0] = x[c][0], f.X[c][1] = x[c][1], f.X[c][2] = x[c][2];
    }
    for (int r = 0; r < 3; ++r) {
        const double h0 = f.Hp[r][0], h1 = f.Hp[r][1], h2 = f.Hp[r][2];
        pf.z[r] -= h0 * y0 + h1 * y1 + h2 * y2;
        for (int c = 0; c <= r; ++c) pf.D[r][c] -= h0 * x[c][0] + h1 * x[c][1] + h2 * x[c][2];
    }
    return true;
}

// Forward substitution alone, on the stored factor.
template <int dim, int pdim>
void JointTreeSolver::forward(std::uint32_t i) {
    const Node& n = nodes_[i];
    Factor& f = factors_[i];
    multiplyInPlace<dim>(f.D, f.z);  // z <- D^-1 z
    if (n.parent == kNone) return;
    Factor& pf = factors_[n.parent];
    for (int r = 0; r < pdim; ++r) {
        double zr = 0;
        for (int k = 0; k < dim; ++k) zr += f.Hp[r][k] * f.z[k];
        pf.z[r] -= zr;
    }
}

template <int dim, int pdim>
void JointTreeSolver::backSubstitute(std::uint32_t i) {
    const Node& n = nodes_[i];
    Factor& f = factors_[i];
    if (n.parent == kNone) {
        for (int k = 0; k < dim; ++k) f.y[k] = f.z[k];
        return;
    }
    const Factor& pf = factors_[n.parent];
    for (int k = 0; k < dim; ++k) {
        double s = f.z[k];
        for (int r = 0; r < pdim; ++r) s -= f.X[r][k] * pf.y[r];
        f.y[k] = s;
    }
}

void JointTreeSolver::solve(std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx) {
    // One factorization per sub-step, in its first biased pass; later passes
    // (more iterations, the relax pass after the position update) reuse it
    // with the current anchors in the residual and the impulses: the anchors
    // turn by at most a sub-step's rotation in between, and the factorization
    // is 60 % of the solve (ragdoll pile: measured in docs/joints.md).
    const bool refactor = beginPass(ctx.useBias);
    solveTrees(0, static_cast<std::uint32_t>(treeCount()), joints, bodies, ctx, refactor);
}

bool JointTreeSolver::beginPass(bool useBias) {
    // Since issue 8's fifth round the factorization is also reused across
    // position updates: a relax pass follows the sub-step's position update,
    // and its anchors are exactly those of the next sub-step's warm start and
    // biased passes (the deltas don't change in between). Since issue 21 the
    // default age has no limit: one factorization per step, kept by each
    // tree while its anchors turned less than kGuardTurn since (solveTree; a
    // ragdoll lying or falling barely turns, a whipping chain's links trip
    // it and factor again, tree by tree). Figures in docs/joints.md.
    if (!useBias) ++factorAge_;  // a relax pass: the positions moved since the last pass
    const bool refactor = !factored_ || factorAge_ >= maxFactorAge_;
    if (refactor) {
        factored_ = true;
        factorAge_ = 0;
        factorizations_ += trees_;
        lanes_ = lanesWanted_;  // every tree factors in this pass: its lanes get their blocks
        std::fill(valid_.begin(), valid_.end(), std::uint8_t{1});  // singular trees try again
    }
    // The warm start folded into this pass (the sub-step's first biased one).
    foldThisPass_ = useBias && firstBiasedPass_ && foldWarmStart_;
    if (useBias) firstBiasedPass_ = false;
    return refactor;
}

void JointTreeSolver::solveTrees(std::uint32_t firstTree, std::uint32_t endTree, std::vector<JointConstraint>& joints,
                                 SolverBody* bodies, const JointContext& ctx, bool refactor) {
    for (std::uint32_t t = firstTree; t < endTree; ++t) {
        // A group of four whole in this range, all on a kept factorization:
        // in lanes. Anything else (a pass that factors, a singular tree, a
        // group cut by the range) one tree at a time, with the same bits.
        // A pass that factors factors such a group in lanes too (setLaneFactor).
        if (lanes_ != 0 && (!refactor || laneFactor_) && groupOf_[t] == t && t + 4 <= endTree && valid_[t] &&
            valid_[t + 1] && valid_[t + 2] && valid_[t + 3]) {
            if (refactor) {
                factorGroupInLanes(t, joints, bodies, ctx);
            } else {
                solveGroupInLanes(t, joints, bodies, ctx);
            }
            t += 3;
            continue;
        }
        solveOneTree(t, joints, bodies, ctx, refactor);
    }
}

void JointTreeSolver::solveOneTree(std::uint32_t t, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                   const JointContext& ctx, bool refactor) {
    {
        const std::uint32_t begin = treeStart_[t], end = treeStart_[t + 1];
        const bool folded = foldThisPass_ && warmFree_[t];
        if (valid_[t] && solveTree(t, joints, bodies, ctx, refactor, folded)) return;
        valid_[t] = 0;  // singular: Gauss-Seidel until the next factorization
        // Singular (degenerate geometry): this pass falls back to Gauss-Seidel blocks.
        for (std::uint32_t i = begin; i < end; ++i) {
            if (!nodes_[i].joint) continue;
            JointConstraint& j = joints[nodes_[i].ref];
            const JointFrame& fr = currentFrame(j, bodies[j.bodyA], bodies[j.bodyB], ctx);
            // The warm start it skipped (solveTree fails before applying anything).
            if (folded) applyPointToMovingEnds(bodies[j.bodyA], bodies[j.bodyB], fr.rA, fr.rB, j.impulse.linear);
            const Mat3 K = pointInverseMass(bodies[j.bodyA], bodies[j.bodyB], fr.rA, fr.rB);
            if (!(determinant(K) > 0)) continue;
            // On copies of a static or kinematic end (unchanged by the impulse, and
            // maybe shared with a tree another thread solves: never written).
            SolverBody copyA, copyB;
            SolverBody& a = bodies[j.bodyA].invMass > 0 ? bodies[j.bodyA] : (copyA = bodies[j.bodyA]);
            SolverBody& b = bodies[j.bodyB].invMass > 0 ? bodies[j.bodyB] : (copyB = bodies[j.bodyB]);
            solvePointBlock(a, b, fr.rA, fr.rB, fr.d, j.impulse.linear, ctx, inverse(K));
        }
    }
}

void JointTreeSolver::solveGroupInLanes(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                        const JointContext& ctx) {
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[first];
    const std::uint32_t count = treeStart_[first + 1] - treeStart_[first];
    TreeLane4* data = laneData_.data();
    // The residuals, tree by tree into their lanes (solveTreeReused's, guard included).
    ++lanePassesOf_[first];
    unsigned tripped = 0;
#if FULCRUM_TREE_WIDE_ENDS
    const bool wide = wideEnds_;
#else
    const bool wide = false;
#endif
    if (wide) {
#if FULCRUM_TREE_WIDE_ENDS
        tripped = lanes_ == 2 ? wideResidualsAvx2(first, joints, bodies, ctx) : wideResiduals(first, joints, bodies, ctx);
#endif
    } else {
        for (int lane = 0; lane < 4; ++lane) {
            const std::uint32_t t = first + static_cast<std::uint32_t>(lane), begin = treeStart_[t];
            const auto zAt = [&](std::uint32_t i, int k) -> double& { return data[lanes[i - begin].off + k].v[lane]; };
            if (!reusedResiduals(t, joints, bodies, ctx, zAt)) tripped |= 1u << lane;
        }
    }
    // Forward and back-substitution for the four at once (a tripped lane's
    // result is not used).
    if (tripped != 15u) {
        if (lanes_ == 2) {
            solveTreeLanesAvx2(lanes, count, data);
        } else {
            solveTreeLanes(lanes, count, data);
        }
    }
    groupImpulses(first, joints, bodies, ctx, tripped, wide);
}

// A group of four on a pass that factors: each tree's blocks built as
// solveTree builds them, gathered into its lane, the eliminations and the
// back-substitution in the lanes' factor kernel, then the impulses as a
// kept-factor pass applies them (same bits as solveTree tree by tree: the
// trees share no moving body). The kernel's blocks stay in the lanes for the
// kept-factor passes; factors_ gets them only if a scalar pass needs them
// (laneOnly_, solveTreeReused). A block not definite in any tree: the four
// one by one, as without lanes (nothing was applied yet).
void JointTreeSolver::factorGroupInLanes(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                         const JointContext& ctx) {
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[first];
    const std::uint32_t count = treeStart_[first + 1] - treeStart_[first];
    TreeLane4* data = laneData_.data();
    for (std::uint32_t k = 0; k < 4; ++k) {
        buildBlocks(first + k, joints, bodies, ctx);
        gatherBlocksToLane(first + k);
    }
    const unsigned failed = lanes_ == 2 ? factorTreeLanesAvx2(lanes, count, data) : factorTreeLanes(lanes, count, data);
    if (failed != 0) {
        for (std::uint32_t k = 0; k < 4; ++k) solveOneTree(first + k, joints, bodies, ctx, true);
        return;
    }
    ++laneFactorPassesOf_[first];
    for (std::uint32_t k = 0; k < 4; ++k) laneOnly_[first + k] = 1;
    if (laneFactorCheck_) {
        for (std::uint32_t k = 0; k < 4; ++k) {
            ++laneFactorChecksOf_[first];
            if (!laneFactorMatchesScalar(first + k, joints, bodies, ctx)) ++laneFactorMismatchesOf_[first];
        }
    }
#if FULCRUM_TREE_WIDE_ENDS
    const bool wide = wideEnds_;
#else
    const bool wide = false;
#endif
    groupImpulses(first, joints, bodies, ctx, 0, wide);
}

bool JointTreeSolver::laneFactorMatchesScalar(std::uint32_t tree, std::vector<JointConstraint>& joints,
                                              const SolverBody* bodies, const JointContext& ctx) {
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    buildBlocks(tree, joints, bodies, ctx);
    // solveTree's eliminations and back-substitution.
    if (!eliminateNodes(begin, end)) return false;
    backSubstituteNodes(begin, end);
    laneOnly_[tree] = 0;  // factors_ holds the same factorization now
    const std::uint32_t group = groupOf_[tree];
    const int lane = static_cast<int>(tree - group);
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[group];
    const auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; };
    for (std::uint32_t i = begin; i < end; ++i) {
        const TreeLaneNode& n = lanes[i - begin];
        const Factor& f = factors_[i];
        const TreeLane4* b = laneData_.data() + n.off;
        const TreeLane4* D = b + 2 * n.dim;
        const TreeLane4* Hp = D + n.dim * n.dim;
        const TreeLane4* X = Hp + n.pdim * n.dim;
        for (int k = 0; k < n.dim; ++k) {
            if (!same(f.y[k], b[n.dim + k].v[lane])) return false;
            for (int c = 0; c < n.dim; ++c) {
                if (!same(f.D[k][c], D[k * n.dim + c].v[lane])) return false;
            }
            for (int r = 0; r < n.pdim; ++r) {
                if (!same(f.Hp[r][k], Hp[r * n.dim + k].v[lane]) || !same(f.X[r][k], X[r * n.dim + k].v[lane])) return false;
            }
        }
    }
    return true;
}

// The group's impulses after its lanes' kernel (the kept-factor passes' and
// the factoring passes'), y in the lanes: the four at once where none
// tripped and they fold the warm start alike, else tree by tree.
void JointTreeSolver::groupImpulses(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                    const JointContext& ctx, unsigned tripped, bool wide) {
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[first];
    const TreeLane4* data = laneData_.data();
#if FULCRUM_TREE_WIDE_ENDS
    // The four trees' impulses at once, where no guard tripped and the four
    // fold the warm start alike (in rain always).
    if (wide && tripped == 0) {
        const bool folded = foldThisPass_ && warmFree_[first];
        bool alike = true;
        for (std::uint32_t k = 1; k < 4; ++k) alike = alike && (foldThisPass_ && warmFree_[first + k]) == folded;
        if (alike) {
            if (lanes_ == 2) {
                wideImpulsesAvx2(first, joints, bodies, ctx, folded);
            } else {
                wideImpulses(first, joints, bodies, ctx, folded);
            }
            return;
        }
    }
#endif
    // A tree whose guard tripped factors again (nothing of it was applied;
    // the trees share no moving body, so the order between them is free): in
    // the group's lanes (refactorTrippedInLanes) where the passes that factor
    // do (setLaneFactor), else, or where its elimination failed there, alone
    // (solveOneTree), as it would have one by one.
    // A lane that failed there factors at once (its blocks' anchors are
    // now the current ones: a kept-factor attempt would not trip again).
    unsigned alone = tripped;
    bool factorAlone = false;
    if (tripped != 0 && laneFactor_) {
        alone = refactorTrippedInLanes(first, joints, bodies, ctx, tripped);
        factorAlone = true;
    }
    // The impulses tree by tree (solveTreeReused's).
    for (int lane = 0; lane < 4; ++lane) {
        const std::uint32_t t = first + static_cast<std::uint32_t>(lane);
        if ((alone >> lane) & 1u) {
            solveOneTree(t, joints, bodies, ctx, factorAlone);
            continue;
        }
        // Factored again in this pass: the anchors of its blocks (buildBlocks), as solveTree's impulses.
        const bool refactored = ((tripped >> lane) & 1u) != 0;
        const bool folded = foldThisPass_ && warmFree_[t];
        const std::uint32_t begin = treeStart_[t], end = treeStart_[t + 1];
        for (std::uint32_t i = begin; i < end; ++i) {
            if (kind_[i] == kBodyNode) continue;
            const TreeLane4* y = data + lanes[i - begin].off + 3;  // a joint's y follows its z[3]
            const double yl[3] = {y[0].v[lane], y[1].v[lane], y[2].v[lane]};
            // The residuals' anchors: the Factor's copy, or (the wide
            // residuals write none) the joint's frame they were read from.
            JointConstraint& j = joints[nodes_[i].ref];
            const Factor& f = factors_[i];
            const bool frame = wide && !refactored;
            applyJointImpulse(j, bodies, frame ? j.frame.rA : f.rA, frame ? j.frame.rB : f.rB, yl, ctx, folded);
        }
    }
}

#if FULCRUM_TREE_WIDE_ENDS
namespace {

// Four floats per register, lane k the k-th tree of a group. Each lane gets
// the scalar code's operations (reusedResiduals, applyJointImpulse, pushEnd)
// in its order: IEEE add, subtract, multiply and compare per lane, and the
// conversions between float and double rounded as static_cast (cvtpd2ps,
// cvtps2pd: exact). Rows of structs are read and written four floats at a
// time (simd.hpp's transposes); a float beyond a field that a store
// rewrites is the value just read (no other thread writes it: the trees
// share no moving body, and a joint belongs to one tree).
using W = __m128;

static_assert(sizeof(SolverBody) == 24 * sizeof(float) && offsetof(SolverBody, v) == 0 &&
                  offsetof(SolverBody, invMass) == 3 * sizeof(float) && offsetof(SolverBody, w) == 4 * sizeof(float) &&
                  offsetof(SolverBody, invI) == 13 * sizeof(float),
              "the wide ends read a solver body's floats 0-7 and 12-23: v, invMass, w, dp.x; dtheta.z, invI, padding");
static_assert(sizeof(JointFrame) >= 12 * sizeof(float) && offsetof(JointFrame, rA) == 0 &&
                  offsetof(JointFrame, rB) == 3 * sizeof(float) && offsetof(JointFrame, d) == 6 * sizeof(float),
              "the wide ends read a frame's floats 0-11: rA, rB, d, and a float of qA");
static_assert(offsetof(JointImpulses, linear) == 0 && sizeof(JointImpulses) >= 4 * sizeof(float),
              "the wide ends read and write an impulse's floats 0-3: linear and angular.x");

FULCRUM_TREE_WIDE_INLINE void loadRows(const float* const* rows, W* out) { simd::Sse2Policy::loadTransposed4(rows, out); }
FULCRUM_TREE_WIDE_INLINE void storeRows(float* const* rows, const W* in) { simd::Sse2Policy::storeTransposed4(rows, in); }
FULCRUM_TREE_WIDE_INLINE W add(W a, W b) { return _mm_add_ps(a, b); }
FULCRUM_TREE_WIDE_INLINE W sub(W a, W b) { return _mm_sub_ps(a, b); }
FULCRUM_TREE_WIDE_INLINE W mul(W a, W b) { return _mm_mul_ps(a, b); }
// One TreeLane4's four doubles as floats (static_cast<Real> each), and back.
FULCRUM_TREE_WIDE_INLINE W toFloats(const TreeLane4& x) {
    return _mm_movelh_ps(_mm_cvtpd_ps(_mm_load_pd(x.v)), _mm_cvtpd_ps(_mm_load_pd(x.v + 2)));
}
FULCRUM_TREE_WIDE_INLINE void widenFloatLanes(W f, TreeLane4& x) {
    _mm_store_pd(x.v, _mm_cvtps_pd(f));
    _mm_store_pd(x.v + 2, _mm_cvtps_pd(_mm_movehl_ps(f, f)));
}
// turnedTooFar per lane: |r - rf|^2 > turn2 |rf|^2, dot's order.
FULCRUM_TREE_WIDE_INLINE W turnedTooFar4(W rx, W ry, W rz, W fx, W fy, W fz, W turn2) {
    const W dx = sub(rx, fx), dy = sub(ry, fy), dz = sub(rz, fz);
    const W moved = add(add(mul(dx, dx), mul(dy, dy)), mul(dz, dz));
    const W length = add(add(mul(fx, fx), mul(fy, fy)), mul(fz, fz));
    return _mm_cmpgt_ps(moved, mul(turn2, length));
}

// pushEnd for four bodies (every one dynamic), lane k: bodies[index[k]].
// The rows are read where they are used (r x P first, then I^-1 (r x P) as
// its columns arrive, then v and w): fewer values live at once, fewer spills
// of the 16 SSE registers.
template <bool onB>
FULCRUM_TREE_WIDE_INLINE void pushEnds(SolverBody* bodies, const std::uint32_t* index, W rx, W ry, W rz, W px, W py, W pz) {
    float* rows[4];
    for (int k = 0; k < 4; ++k) rows[k] = reinterpret_cast<float*>(bodies + index[k]);
    const W cx = sub(mul(ry, pz), mul(rz, py)), cy = sub(mul(rz, px), mul(rx, pz)), cz = sub(mul(rx, py), mul(ry, px));
    W in[4];
    const float* at12[4] = {rows[0] + 12, rows[1] + 12, rows[2] + 12, rows[3] + 12};
    loadRows(at12, in);  // dtheta.z, invI.c0
    W wx = mul(in[1], cx), wy = mul(in[2], cx), wz = mul(in[3], cx);
    const float* at16[4] = {rows[0] + 16, rows[1] + 16, rows[2] + 16, rows[3] + 16};
    loadRows(at16, in);  // invI.c1, invI.c2.x
    wx = add(wx, mul(in[0], cy)), wy = add(wy, mul(in[1], cy)), wz = add(wz, mul(in[2], cy));
    wx = add(wx, mul(in[3], cz));
    const float* at20[4] = {rows[0] + 20, rows[1] + 20, rows[2] + 20, rows[3] + 20};
    loadRows(at20, in);  // invI.c2.y, invI.c2.z, padding
    wy = add(wy, mul(in[0], cz)), wz = add(wz, mul(in[1], cz));
    loadRows(rows, in);  // v.x, v.y, v.z, invMass
    const W m = in[3];
    if constexpr (onB) {
        in[0] = add(in[0], mul(px, m)), in[1] = add(in[1], mul(py, m)), in[2] = add(in[2], mul(pz, m));
    } else {
        in[0] = sub(in[0], mul(px, m)), in[1] = sub(in[1], mul(py, m)), in[2] = sub(in[2], mul(pz, m));
    }
    storeRows(rows, in);
    float* at4[4] = {rows[0] + 4, rows[1] + 4, rows[2] + 4, rows[3] + 4};
    loadRows(at4, in);  // w.x, w.y, w.z, dp.x
    if constexpr (onB) {
        in[0] = add(in[0], wx), in[1] = add(in[1], wy), in[2] = add(in[2], wz);
    } else {
        in[0] = sub(in[0], wx), in[1] = sub(in[1], wy), in[2] = sub(in[2], wz);
    }
    storeRows(at4, in);
}

// Four bodies all dynamic (inverse mass > 0), as pushEnd's test.
FULCRUM_TREE_WIDE_INLINE bool allMoving(const SolverBody* bodies, const std::uint32_t* index) {
    return bodies[index[0]].invMass > 0 && bodies[index[1]].invMass > 0 && bodies[index[2]].invMass > 0 &&
           bodies[index[3]].invMass > 0;
}

}  // namespace

FULCRUM_TREE_WIDE_INLINE unsigned JointTreeSolver::wideResidualsBody(std::uint32_t first, std::vector<JointConstraint>& joints,
                                                                     const SolverBody* bodies, const JointContext& ctx) {
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[first];
    const std::uint32_t count = treeStart_[first + 1] - treeStart_[first];
    TreeLane4* data = laneData_.data();
    const std::uint32_t begin[4] = {treeStart_[first], treeStart_[first + 1], treeStart_[first + 2], treeStart_[first + 3]};
    const bool guard = !ctx.useBias, useBias = ctx.useBias;
    static_assert(offsetof(Factor, rB) == offsetof(Factor, rA) + 3 * sizeof(float) &&
                      offsetof(Factor, factorA) == offsetof(Factor, rA) + 6 * sizeof(float) &&
                      offsetof(Factor, factorB) == offsetof(Factor, rA) + 9 * sizeof(float),
                  "the guard reads a Factor's floats from rA to factorB's end as three rows of four");
    const W turn2 = _mm_set1_ps(guardTurn2_), bias = _mm_set1_ps(ctx.soft.biasRate);
    W trips = _mm_setzero_ps();
    // Parents first, as reusedResiduals (each node writes only its own z).
    for (std::uint32_t p = count; p-- > 0;) {
        TreeLane4* z = data + lanes[p].off;
        if (lanes[p].kind == kBodyNode) {
            for (int k = 0; k < 6; ++k) z[k] = TreeLane4{};
            continue;
        }
        const float* frame[4];
        const float* rowA[4];
        const float* rowB[4];
        for (int k = 0; k < 4; ++k) {
            JointConstraint& j = joints[nodes_[begin[k] + p].ref];
            const SolverBody& a = bodies[j.bodyA];
            const SolverBody& b = bodies[j.bodyB];
            frame[k] = &currentFrame(j, a, b, ctx).rA.x;
            rowA[k] = &a.v.x;
            rowB[k] = &b.v.x;
        }
        W f0[4], f1[4];
        loadRows(frame, f0);  // rA, rB.x
        const float* frame4[4] = {frame[0] + 4, frame[1] + 4, frame[2] + 4, frame[3] + 4};
        loadRows(frame4, f1);  // rB.y, rB.z, d.x, d.y
        const W rAx = f0[0], rAy = f0[1], rAz = f0[2], rBx = f0[3], rBy = f1[0], rBz = f1[1];
        if (guard) {
            // factorA and factorB: floats 6-11 from the Factor's rA.
            const float* f[4];
            for (int k = 0; k < 4; ++k) f[k] = &factors_[begin[k] + p].rA.x + 4;
            W g4[4], g8[4];
            loadRows(f, g4);  // rB.y, rB.z, factorA.x, factorA.y
            for (int k = 0; k < 4; ++k) f[k] += 4;
            loadRows(f, g8);  // factorA.z, factorB
            const W tA = turnedTooFar4(rAx, rAy, rAz, g4[2], g4[3], g8[0], turn2);
            const W tB = turnedTooFar4(rBx, rBy, rBz, g8[1], g8[2], g8[3], turn2);
            trips = _mm_or_ps(trips, _mm_or_ps(tA, tB));
        }
        W va[4], wa[4], vb[4], wb[4];
        loadRows(rowA, va);
        loadRows(rowB, vb);
        for (int k = 0; k < 4; ++k) rowA[k] += 4, rowB[k] += 4;
        loadRows(rowA, wa);
        loadRows(rowB, wb);
        // b.v + b.w x rB - a.v - a.w x rA (+ biasRate d), reusedResiduals' order.
        W rx = sub(sub(add(vb[0], sub(mul(wb[1], rBz), mul(wb[2], rBy))), va[0]), sub(mul(wa[1], rAz), mul(wa[2], rAy)));
        W ry = sub(sub(add(vb[1], sub(mul(wb[2], rBx), mul(wb[0], rBz))), va[1]), sub(mul(wa[2], rAx), mul(wa[0], rAz)));
        W rz = sub(sub(add(vb[2], sub(mul(wb[0], rBy), mul(wb[1], rBx))), va[2]), sub(mul(wa[0], rAy), mul(wa[1], rAx)));
        if (useBias) {
            W f2[4];
            const float* frame8[4] = {frame[0] + 8, frame[1] + 8, frame[2] + 8, frame[3] + 8};
            loadRows(frame8, f2);  // d.z, qA's first three
            rx = add(rx, mul(f1[2], bias)), ry = add(ry, mul(f1[3], bias)), rz = add(rz, mul(f2[0], bias));
        }
        widenFloatLanes(rx, z[0]);
        widenFloatLanes(ry, z[1]);
        widenFloatLanes(rz, z[2]);
    }
    return static_cast<unsigned>(_mm_movemask_ps(trips));
}

FULCRUM_TREE_WIDE_INLINE void JointTreeSolver::wideImpulsesBody(std::uint32_t first, std::vector<JointConstraint>& joints,
                                                                SolverBody* bodies, const JointContext& ctx, bool folded) {
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[first];
    const std::uint32_t count = treeStart_[first + 1] - treeStart_[first];
    const TreeLane4* data = laneData_.data();
    const std::uint32_t begin[4] = {treeStart_[first], treeStart_[first + 1], treeStart_[first + 2], treeStart_[first + 3]};
    const W massScale = _mm_set1_ps(ctx.soft.massScale), impulseScale = _mm_set1_ps(ctx.soft.impulseScale);
    const W keep = _mm_set1_ps(1 - ctx.soft.massScale - ctx.soft.impulseScale);  // applyJointImpulse's folded factor
    // Children first, as solveTreeReused's impulses (a body's pushes in the scalar order).
    for (std::uint32_t p = 0; p < count; ++p) {
        if (lanes[p].kind == kBodyNode) continue;
        const TreeLane4* y = data + lanes[p].off + 3;  // a joint's y follows its z[3]
        W dx = toFloats(y[0]), dy = toFloats(y[1]), dz = toFloats(y[2]);
        JointConstraint* j[4];
        float* impulse[4];
        const float* frame[4];
        std::uint32_t indexA[4], indexB[4];
        for (int k = 0; k < 4; ++k) {
            j[k] = &joints[nodes_[begin[k] + p].ref];
            impulse[k] = &j[k]->impulse.linear.x;
            frame[k] = &j[k]->frame.rA.x;  // current: the residuals' (currentFrame)
            indexA[k] = j[k]->bodyA;
            indexB[k] = j[k]->bodyB;
        }
        W lambda[4];
        loadRows(impulse, lambda);  // linear, angular.x
        if (folded) {
            dx = add(mul(dx, massScale), mul(lambda[0], keep));
            dy = add(mul(dy, massScale), mul(lambda[1], keep));
            dz = add(mul(dz, massScale), mul(lambda[2], keep));
            lambda[0] = dx, lambda[1] = dy, lambda[2] = dz;
        } else {
            if (ctx.useBias) {
                dx = sub(mul(dx, massScale), mul(lambda[0], impulseScale));
                dy = sub(mul(dy, massScale), mul(lambda[1], impulseScale));
                dz = sub(mul(dz, massScale), mul(lambda[2], impulseScale));
            }
            lambda[0] = add(lambda[0], dx), lambda[1] = add(lambda[1], dy), lambda[2] = add(lambda[2], dz);
        }
        storeRows(impulse, lambda);
        W f0[4], f1[4];
        loadRows(frame, f0);  // rA, rB.x
        const float* frame4[4] = {frame[0] + 4, frame[1] + 4, frame[2] + 4, frame[3] + 4};
        loadRows(frame4, f1);  // rB.y, rB.z, d.x, d.y
        const bool movingA = allMoving(bodies, indexA), movingB = allMoving(bodies, indexB);
        if (movingA) pushEnds<false>(bodies, indexA, f0[0], f0[1], f0[2], dx, dy, dz);
        if (movingB) pushEnds<true>(bodies, indexB, f0[3], f1[0], f1[1], dx, dy, dz);
        if (movingA && movingB) continue;
        // A static or kinematic end somewhere: lane by lane, the scalar pushEnd
        // (A before B in each tree, as applyJointImpulse).
        alignas(16) float px[4], py[4], pz[4];
        _mm_store_ps(px, dx), _mm_store_ps(py, dy), _mm_store_ps(pz, dz);
        for (int k = 0; k < 4; ++k) {
            SolverBody& a = bodies[indexA[k]];
            SolverBody& b = bodies[indexB[k]];
            if (!movingA && a.invMass > 0) pushEnd<false>(a, j[k]->frame.rA, px[k], py[k], pz[k]);
            if (!movingB && b.invMass > 0) pushEnd<true>(b, j[k]->frame.rB, px[k], py[k], pz[k]);
        }
    }
}

unsigned JointTreeSolver::wideResiduals(std::uint32_t first, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                                        const JointContext& ctx) {
    return wideResidualsBody(first, joints, bodies, ctx);
}

void JointTreeSolver::wideImpulses(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                                   const JointContext& ctx, bool folded) {
    wideImpulsesBody(first, joints, bodies, ctx, folded);
}

FULCRUM_TREE_WIDE_VEX unsigned JointTreeSolver::wideResidualsAvx2(std::uint32_t first, std::vector<JointConstraint>& joints,
                                                                  const SolverBody* bodies, const JointContext& ctx) {
    return wideResidualsBody(first, joints, bodies, ctx);
}

FULCRUM_TREE_WIDE_VEX void JointTreeSolver::wideImpulsesAvx2(std::uint32_t first, std::vector<JointConstraint>& joints,
                                                             SolverBody* bodies, const JointContext& ctx, bool folded) {
    wideImpulsesBody(first, joints, bodies, ctx, folded);
}
#endif

namespace {

// One node's D^-1, Hp and X into lane `lane` of its block (TreeLaneNode's layout).
template <int dim, int pdim, class F>
void copyBlocksToLane(const F& f, TreeLane4* block, int lane) {
    TreeLane4* D = block + 2 * dim;
    TreeLane4* Hp = D + dim * dim;
    TreeLane4* X = Hp + pdim * dim;
    for (int r = 0; r < dim; ++r) {
        for (int k = 0; k < dim; ++k) D[r * dim + k].v[lane] = f.D[r][k];
    }
    for (int r = 0; r < pdim; ++r) {
        for (int k = 0; k < dim; ++k) Hp[r * dim + k].v[lane] = f.Hp[r][k];
    }
    for (int r = 0; r < pdim; ++r) {
        for (int k = 0; k < dim; ++k) X[r * dim + k].v[lane] = f.X[r][k];
    }
}

}  // namespace

namespace {

// The reverse of copyBlocksToLane: lane `lane` of a block into the node's
// Factor (D^-1, Hp, X: what a kept-factor pass reads).
template <int dim, int pdim, class F>
void copyLaneToBlocks(F& f, const TreeLane4* block, int lane) {
    const TreeLane4* D = block + 2 * dim;
    const TreeLane4* Hp = D + dim * dim;
    const TreeLane4* X = Hp + pdim * dim;
    for (int r = 0; r < dim; ++r) {
        for (int k = 0; k < dim; ++k) f.D[r][k] = D[r * dim + k].v[lane];
    }
    for (int r = 0; r < pdim; ++r) {
        for (int k = 0; k < dim; ++k) f.Hp[r][k] = Hp[r * dim + k].v[lane];
    }
    for (int r = 0; r < pdim; ++r) {
        for (int k = 0; k < dim; ++k) f.X[r][k] = X[r * dim + k].v[lane];
    }
}

// A node's blocks before its elimination into lane `lane` (factorTreeLanes'
// input): z, D's lower triangle and H(parent, this), given in Hp (row r,
// column k: Hp[r][k]).
template <int dim, int pdim, class F>
void gatherToLane(const F& f, const double (*Hp)[6], TreeLane4* block, int lane) {
    TreeLane4* D = block + 2 * dim;
    TreeLane4* H = D + dim * dim;
    for (int k = 0; k < dim; ++k) block[k].v[lane] = f.z[k];
    for (int r = 0; r < dim; ++r) {
        for (int c = 0; c <= r; ++c) D[r * dim + c].v[lane] = f.D[r][c];
    }
    for (int r = 0; r < pdim; ++r) {
        for (int k = 0; k < dim; ++k) H[r * dim + k].v[lane] = Hp[r][k];
    }
}

}  // namespace

void JointTreeSolver::copyFactorFromLanes(std::uint32_t tree) {
    const std::uint32_t group = groupOf_[tree];
    const int lane = static_cast<int>(tree - group);
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[group];
    for (std::uint32_t i = begin; i < end; ++i) {
        const TreeLaneNode& n = lanes[i - begin];
        Factor& f = factors_[i];
        const TreeLane4* block = laneData_.data() + n.off;
        if (n.kind == kJointBelowJoint) {
            copyLaneToBlocks<3, 3>(f, block, lane);
        } else if (n.kind == kBodyNode) {
            if (n.pdim != 0) copyLaneToBlocks<6, 3>(f, block, lane);
            else copyLaneToBlocks<6, 0>(f, block, lane);
        } else {
            if (n.pdim != 0) copyLaneToBlocks<3, 6>(f, block, lane);
            else copyLaneToBlocks<3, 0>(f, block, lane);
        }
    }
    laneOnly_[tree] = 0;
}

void JointTreeSolver::gatherBlocksToLane(std::uint32_t tree) {
    const std::uint32_t group = groupOf_[tree];
    gatherBlocks(tree, laneNodes_.data() + treeStart_[group], laneData_.data(), static_cast<int>(tree - group));
}

void JointTreeSolver::gatherBlocks(std::uint32_t tree, const TreeLaneNode* lanes, TreeLane4* data, int lane) {
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    for (std::uint32_t i = begin; i < end; ++i) {
        const TreeLaneNode& ln = lanes[i - begin];
        const Node& n = nodes_[i];
        const Factor& f = factors_[i];
        TreeLane4* block = data + ln.off;
        if (ln.kind == kJointBelowJoint) {
            gatherToLane<3, 3>(f, f.Hp, block, lane);  // H(parent, this) built with D (buildBlocks)
        } else if (ln.kind == kBodyNode) {
            if (ln.pdim == 0) {
                gatherToLane<6, 0>(f, nullptr, block, lane);
                continue;
            }
            // A body of the parent joint: eliminate<6, 3>'s H(parent, this).
            const Factor& pf = factors_[n.parent];
            double J[3][6];
            jacobian(J, n.bodyIsA ? pf.rA : pf.rB, n.bodyIsA ? -1 : 1);
            double H[6][6];
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 6; ++c) H[r][c] = J[r][c];
            }
            gatherToLane<6, 3>(f, H, block, lane);
        } else {
            if (ln.pdim == 0) {
                gatherToLane<3, 0>(f, nullptr, block, lane);
                continue;
            }
            // A joint on the parent body: eliminate<3, 6>'s transpose.
            double J[3][6];
            jacobian(J, n.bodyIsA ? f.rA : f.rB, n.bodyIsA ? -1 : 1);
            double H[6][6];
            for (int r = 0; r < 6; ++r) {
                for (int c = 0; c < 3; ++c) H[r][c] = J[c][r];
            }
            gatherToLane<3, 6>(f, H, block, lane);
        }
    }
}

unsigned JointTreeSolver::refactorTrippedInLanes(std::uint32_t first, std::vector<JointConstraint>& joints,
                                                 const SolverBody* bodies, const JointContext& ctx, unsigned tripped) {
    // Why (issue 21, branch `rain11`): a tripped tree factored alone wrote
    // its ~1 kB Factor per node and then copied D^-1, Hp and X into its lane
    // (copyFactorToLanes), every lane write a miss (each TreeLane4 touched
    // for one double); rain trips a quarter of its trees' kept passes. Here
    // the group's block is factored in a scratch copy that stays in cache
    // (one per thread: groups are solved concurrently), one kernel for all
    // the tripped lanes, and only their lanes move into the group's block.
    // A lane that did not trip gets a tripped tree's blocks (the kernel then
    // computes only valid factorizations; its result is dropped), so its
    // kept factorization and this pass's y stay in place.
    // All four tripped (rain's groups often turn alike): in place, as
    // factorGroupInLanes (a lane that fails is not used again before the
    // next pass that factors gathers it anew: its tree turns Gauss-Seidel).
    const std::uint32_t begin = treeStart_[first], count = treeStart_[first + 1] - begin;
    for (int lane = 0; lane < 4; ++lane) {
        if ((tripped >> lane) & 1u) buildBlocks(first + static_cast<std::uint32_t>(lane), joints, bodies, ctx);
    }
    unsigned failed;
    if (tripped == 15u) {
        const TreeLaneNode* lanes = laneNodes_.data() + begin;
        TreeLane4* data = laneData_.data();
        for (int lane = 0; lane < 4; ++lane) gatherBlocks(first + static_cast<std::uint32_t>(lane), lanes, data, lane);
        failed = lanes_ == 2 ? factorTreeLanesAvx2(lanes, count, data) : factorTreeLanes(lanes, count, data);
    } else {
        const TreeLaneNode* local = laneNodesLocal_.data() + begin;
        const std::uint32_t size = laneBlockSize_[first];
        thread_local std::vector<TreeLane4> scratch;
        if (scratch.size() < size) scratch.resize(size);
        TreeLane4* work = scratch.data();
        for (int lane = 0; lane < 4; ++lane) {
            if ((tripped >> lane) & 1u) gatherBlocks(first + static_cast<std::uint32_t>(lane), local, work, lane);
        }
        // The other lanes: the first tripped lane's blocks.
        const int stand = std::countr_zero(tripped);
        for (std::uint32_t i = 0; i < size; ++i) {
            double* v = work[i].v;
            for (int lane = 0; lane < 4; ++lane) {
                if (((tripped >> lane) & 1u) == 0) v[lane] = v[stand];
            }
        }
        failed = (lanes_ == 2 ? factorTreeLanesAvx2(local, count, work) : factorTreeLanes(local, count, work)) |
                 trippedLaneFailures_;
        const unsigned done = tripped & ~failed;
        TreeLane4* block = laneData_.data() + laneNodes_[begin].off;
        for (std::uint32_t i = 0; i < size && done != 0; ++i) {
            for (int lane = 0; lane < 4; ++lane) {
                if ((done >> lane) & 1u) block[i].v[lane] = work[i].v[lane];
            }
        }
    }
    failed = (failed | trippedLaneFailures_) & tripped;  // the other lanes' results were dropped
    const unsigned done = tripped & ~failed;
    for (int lane = 0; lane < 4; ++lane) {
        if ((tripped >> lane) & 1u) ++guardTripsOf_[first + static_cast<std::uint32_t>(lane)];  // as solveTree counts a trip
    }
    for (int lane = 0; lane < 4; ++lane) {
        if (((done >> lane) & 1u) == 0) continue;
        const std::uint32_t t = first + static_cast<std::uint32_t>(lane);
        ++trippedLaneFactorsOf_[first];
        laneOnly_[t] = 1;  // factors_ holds its blocks, not their factorization
        if (laneFactorCheck_) {
            ++laneFactorChecksOf_[first];
            if (!laneFactorMatchesScalar(t, joints, bodies, ctx)) ++laneFactorMismatchesOf_[first];
        }
    }
    return failed;
}

void JointTreeSolver::copyFactorToLanes(std::uint32_t tree) {
    const std::uint32_t group = groupOf_[tree];
    const int lane = static_cast<int>(tree - group);
    const std::uint32_t begin = treeStart_[tree], end = treeStart_[tree + 1];
    const TreeLaneNode* lanes = laneNodes_.data() + treeStart_[group];
    for (std::uint32_t i = begin; i < end; ++i) {
        const TreeLaneNode& n = lanes[i - begin];
        const Factor& f = factors_[i];
        TreeLane4* block = laneData_.data() + n.off;
        if (n.kind == kJointBelowJoint) {
            copyBlocksToLane<3, 3>(f, block, lane);
        } else if (n.kind == kBodyNode) {
            if (n.pdim != 0) copyBlocksToLane<6, 3>(f, block, lane);
            else copyBlocksToLane<6, 0>(f, block, lane);
        } else {
            if (n.pdim != 0) copyBlocksToLane<3, 6>(f, block, lane);
            else copyBlocksToLane<3, 0>(f, block, lane);
        }
    }
}

bool JointTreeSolver::sameLaneBlocks(const JointTreeSolver& other) const {
    if (groupOf_ != other.groupOf_ || laneData_.size() != other.laneData_.size()) return false;
    for (std::uint32_t t = 0; t < trees_; ++t) {
        if (groupOf_[t] != t) continue;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            const TreeLaneNode& n = laneNodes_[i];
            // After z[dim] and y[dim]: D^-1, Hp, X.
            const std::size_t from = n.off + 2u * n.dim, count = n.dim * n.dim + 2u * n.pdim * n.dim;
            if (std::memcmp(laneData_.data() + from, other.laneData_.data() + from, count * sizeof(TreeLane4)) != 0)
                return false;
        }
    }
    return true;
}

void JointTreeSolver::groupTrees() {
    groupOf_.assign(trees_, kNone);
    lanePassesOf_.assign(trees_, 0);
    laneFactorPassesOf_.assign(trees_, 0);
    trippedLaneFactorsOf_.assign(trees_, 0);
    laneFactorChecksOf_.assign(trees_, 0);
    laneFactorMismatchesOf_.assign(trees_, 0);
    laneOnly_.assign(trees_, 0);
    laneNodes_.resize(nodes_.size());
    laneNodesLocal_.resize(nodes_.size());
    laneBlockSize_.assign(trees_, 0);
    const auto sameShape = [&](std::uint32_t t, std::uint32_t u) {
        const std::uint32_t bt = treeStart_[t], bu = treeStart_[u], n = treeStart_[t + 1] - bt;
        if (treeStart_[u + 1] - bu != n || chain_[t] || chain_[u]) return false;
        for (std::uint32_t p = 0; p < n; ++p) {
            const std::uint32_t pt = nodes_[bt + p].parent, pu = nodes_[bu + p].parent;
            if (kind_[bt + p] != kind_[bu + p] || (pt == kNone) != (pu == kNone)) return false;
            if (pt != kNone && pt - bt != pu - bu) return false;
        }
        return true;
    };
    std::size_t total = 0;
    // Groups start at multiples of 4, as the task ranges do (JointSolver::solveTrees).
    for (std::uint32_t t = 0; t + 4 <= trees_; t += 4) {
        if (!(sameShape(t, t + 1) && sameShape(t, t + 2) && sameShape(t, t + 3))) continue;
        for (std::uint32_t k = 0; k < 4; ++k) groupOf_[t + k] = t;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            TreeLaneNode& ln = laneNodes_[i];
            const Node& n = nodes_[i];
            ln.kind = kind_[i];
            ln.dim = kind_[i] == kBodyNode ? 6 : 3;
            ln.pdim = n.parent == kNone ? 0 : kind_[i] == kJointBelowBody ? 6 : 3;
            ln.off = static_cast<std::uint32_t>(total);
            total += 2u * ln.dim + ln.dim * ln.dim + 2u * ln.pdim * ln.dim;
        }
        const std::uint32_t base = laneNodes_[treeStart_[t]].off;
        laneBlockSize_[t] = static_cast<std::uint32_t>(total) - base;
        for (std::uint32_t i = treeStart_[t]; i < treeStart_[t + 1]; ++i) {
            const std::uint32_t parent = nodes_[i].parent;
            laneNodes_[i].parentOff = parent == kNone ? TreeLaneNode::kNoParent : laneNodes_[parent].off;
            TreeLaneNode& local = laneNodesLocal_[i];
            local = laneNodes_[i];
            local.off -= base;
            if (local.parentOff != TreeLaneNode::kNoParent) local.parentOff -= base;
        }
    }
    laneData_.assign(total, TreeLane4{});
}

void JointTreeSolver::setLanes(int mode) {
    if (mode == 2 && !treeLanesAvx2Compiled()) mode = 1;
    lanesWanted_ = mode < 0 ? 0 : mode > 2 ? 2 : mode;
}

}  // namespace fulcrum::detail
