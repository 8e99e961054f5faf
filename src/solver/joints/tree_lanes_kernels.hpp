// The kernel of tree_lanes.hpp, included by tree_lanes.cpp (the baseline
// target) and tree_lanes_avx2.cpp (-mavx2) with FULCRUM_TREE_LANES_NS and
// FULCRUM_TREE_LANES_FN set. No include guard: one inclusion per file.
#include <cmath>
#include <cstring>

#include "solver/joints/tree_lanes.hpp"

namespace fulcrum::detail::FULCRUM_TREE_LANES_NS {

// Four lanes (V): with GCC and Clang a vector-extension type of four
// doubles, whose + - * are the lane-wise IEEE operations, the scalar ones;
// the compiler splits it into two SSE2 (or WebAssembly SIMD128) registers or
// keeps it in one AVX register. It never crosses a function boundary (the
// ABI of a 32-byte vector argument differs with and without AVX), so
// everything below is inlined into one kernel. Elsewhere a plain struct.
#if defined(__GNUC__) || defined(__clang__)
typedef double V __attribute__((vector_size(32), may_alias));
#define FULCRUM_TREE_LANES_INLINE inline __attribute__((always_inline))
FULCRUM_TREE_LANES_INLINE const V& ld(const TreeLane4& x) { return *reinterpret_cast<const V*>(x.v); }
FULCRUM_TREE_LANES_INLINE V& lanesOf(TreeLane4& x) { return *reinterpret_cast<V*>(x.v); }
#define FULCRUM_TREE_LANES_ZERO V{0.0, 0.0, 0.0, 0.0}
#define FULCRUM_TREE_LANES_SPLAT(x) V{(x), (x), (x), (x)}
FULCRUM_TREE_LANES_INLINE double laneOf(const V& x, int k) { return x[k]; }
// std::sqrt per lane: the correctly rounded square root, as the scalar one.
// (Results by reference: a 32-byte vector never crosses a function boundary by value.)
FULCRUM_TREE_LANES_INLINE void sqrtLanes(const V& x, V& out) {
    out = V{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}
#else
struct V {
    double p[4];
};
#define FULCRUM_TREE_LANES_INLINE inline
inline V operator+(const V& a, const V& b) { return {{a.p[0] + b.p[0], a.p[1] + b.p[1], a.p[2] + b.p[2], a.p[3] + b.p[3]}}; }
inline V operator-(const V& a, const V& b) { return {{a.p[0] - b.p[0], a.p[1] - b.p[1], a.p[2] - b.p[2], a.p[3] - b.p[3]}}; }
inline V operator*(const V& a, const V& b) { return {{a.p[0] * b.p[0], a.p[1] * b.p[1], a.p[2] * b.p[2], a.p[3] * b.p[3]}}; }
inline V operator/(const V& a, const V& b) { return {{a.p[0] / b.p[0], a.p[1] / b.p[1], a.p[2] / b.p[2], a.p[3] / b.p[3]}}; }
inline V operator-(const V& a) { return {{-a.p[0], -a.p[1], -a.p[2], -a.p[3]}}; }
inline double laneOf(const V& x, int k) { return x.p[k]; }
inline void sqrtLanes(const V& x, V& out) { out = {{std::sqrt(x.p[0]), std::sqrt(x.p[1]), std::sqrt(x.p[2]), std::sqrt(x.p[3])}}; }
inline const V& ld(const TreeLane4& x) { return *reinterpret_cast<const V*>(x.v); }
inline V& lanesOf(TreeLane4& x) { return *reinterpret_cast<V*>(x.v); }
#define FULCRUM_TREE_LANES_ZERO V{{0.0, 0.0, 0.0, 0.0}}
#define FULCRUM_TREE_LANES_SPLAT(x) V{{(x), (x), (x), (x)}}
#endif
static_assert(sizeof(V) == sizeof(TreeLane4));

// forward<dim, pdim> (tree_solver.cpp): z <- D^-1 z (multiplyInPlace: t = 0,
// t += a[r][k] x[k]), then the parent's z[r] -= (zr = 0, zr += Hp[r][k] z[k]).
template <int dim, int pdim>
FULCRUM_TREE_LANES_INLINE void forwardGeneric(TreeLane4* b, TreeLane4* parent) {
    TreeLane4* z = b;
    const TreeLane4* D = b + 2 * dim;
    V x[dim], y[dim];
    for (int k = 0; k < dim; ++k) x[k] = ld(z[k]);
    for (int r = 0; r < dim; ++r) {
        V t = FULCRUM_TREE_LANES_ZERO;
        for (int k = 0; k < dim; ++k) t = t + ld(D[r * dim + k]) * x[k];
        y[r] = t;
    }
    for (int r = 0; r < dim; ++r) lanesOf(z[r]) = y[r];
    if constexpr (pdim > 0) {
        const TreeLane4* Hp = D + dim * dim;
        for (int r = 0; r < pdim; ++r) {
            V zr = FULCRUM_TREE_LANES_ZERO;
            for (int k = 0; k < dim; ++k) zr = zr + ld(Hp[r * dim + k]) * y[k];
            lanesOf(parent[r]) = ld(parent[r]) - zr;
        }
    } else {
        (void)parent;
    }
}

// forwardChainJoint: y = D^-1 z written out (no `0 +`), parent z[r] -= Hp[r] . y.
FULCRUM_TREE_LANES_INLINE void forwardChain(TreeLane4* b, TreeLane4* parent) {
    const TreeLane4* D = b + 6;
    const TreeLane4* Hp = D + 9;
    const V z0 = ld(b[0]), z1 = ld(b[1]), z2 = ld(b[2]);
    const V y0 = (ld(D[0]) * z0 + ld(D[1]) * z1) + ld(D[2]) * z2;
    const V y1 = (ld(D[3]) * z0 + ld(D[4]) * z1) + ld(D[5]) * z2;
    const V y2 = (ld(D[6]) * z0 + ld(D[7]) * z1) + ld(D[8]) * z2;
    lanesOf(b[0]) = y0, lanesOf(b[1]) = y1, lanesOf(b[2]) = y2;
    for (int r = 0; r < 3; ++r)
        lanesOf(parent[r]) = ld(parent[r]) - ((ld(Hp[3 * r]) * y0 + ld(Hp[3 * r + 1]) * y1) + ld(Hp[3 * r + 2]) * y2);
}

// backSubstitute<dim, pdim> (and backSubstituteChainJoint, the same order):
// y[k] = z[k] - X[0][k] py[0] - X[1][k] py[1] ..., a root's y = z.
template <int dim, int pdim>
FULCRUM_TREE_LANES_INLINE void backGeneric(TreeLane4* b, const TreeLane4* parentY) {
    const TreeLane4* z = b;
    TreeLane4* y = b + dim;
    if constexpr (pdim == 0) {
        (void)parentY;
        for (int k = 0; k < dim; ++k) y[k] = z[k];
    } else {
        const TreeLane4* X = b + 2 * dim + dim * dim + pdim * dim;
        V p[pdim];
        for (int r = 0; r < pdim; ++r) p[r] = ld(parentY[r]);
        for (int k = 0; k < dim; ++k) {
            V s = ld(z[k]);
            for (int r = 0; r < pdim; ++r) s = s - ld(X[r * dim + k]) * p[r];
            lanesOf(y[k]) = s;
        }
    }
}


// ---- The factorization (factorTreeLanes): JointTreeSolver::eliminate<dim,
// pdim> and eliminateChainJoint with invertInPlace, cholesky,
// applyCholeskyInverse, invertNegativeDefinite3 and multiplyInPlace
// (tree_solver.cpp), every operation in the scalar order, the constant
// starts (0 +, the unit columns) included. A comparison that fails in a
// lane marks it (the scalar code returns false there); its other values are
// not used.
// Lanes where !(x > 1e-300): the scalar checks' failures.
FULCRUM_TREE_LANES_INLINE unsigned notPositive(const V& x) {
    unsigned m = 0;
    for (int k = 0; k < 4; ++k) m |= !(laneOf(x, k) > 1e-300) ? 1u << k : 0u;
    return m;
}

// invertNegativeDefinite3 on D's lower triangle (row major, 3 x 3), the
// inverse stored full and symmetric (SymmetricInverse3::store). Returns the
// failed lanes; i[] = i00, i11, i22, i10, i20, i21.
FULCRUM_TREE_LANES_INLINE unsigned invertLanes3(TreeLane4* D, V i[6]) {
    const V m00 = -ld(D[0]), m10 = -ld(D[3]), m11 = -ld(D[4]), m20 = -ld(D[6]), m21 = -ld(D[7]), m22 = -ld(D[8]);
    const V c00 = m11 * m22 - m21 * m21;
    const V c10 = m21 * m20 - m10 * m22;
    const V c20 = m10 * m21 - m11 * m20;
    const V det = (m00 * c00 + m10 * c10) + m20 * c20;
    const V minor2 = m00 * m11 - m10 * m10;
    const unsigned failed = notPositive(m00) | notPositive(minor2) | notPositive(det);
    const V s = FULCRUM_TREE_LANES_SPLAT(-1.0) / det;
    const V c11 = m00 * m22 - m20 * m20;
    const V c21 = m20 * m10 - m00 * m21;
    i[0] = c00 * s, i[1] = c11 * s, i[2] = minor2 * s, i[3] = c10 * s, i[4] = c20 * s, i[5] = c21 * s;
    lanesOf(D[0]) = i[0], lanesOf(D[4]) = i[1], lanesOf(D[8]) = i[2];
    lanesOf(D[1]) = i[3], lanesOf(D[3]) = i[3];
    lanesOf(D[2]) = i[4], lanesOf(D[6]) = i[4];
    lanesOf(D[5]) = i[5], lanesOf(D[7]) = i[5];
    return failed;
}

// invertInPlace<6>: the Cholesky factor of the lower triangle, then each
// unit column through applyCholeskyInverse<6>, the full inverse stored.
FULCRUM_TREE_LANES_INLINE unsigned invertLanes6(TreeLane4* D) {
    V L[6][6];
    for (int r = 0; r < 6; ++r) {
        for (int c = 0; c <= r; ++c) L[r][c] = ld(D[r * 6 + c]);
    }
    unsigned failed = 0;
    for (int j = 0; j < 6; ++j) {
        V s = L[j][j];
        for (int k = 0; k < j; ++k) s = s - L[j][k] * L[j][k];
        failed |= notPositive(s);
        V root;
        sqrtLanes(s, root);
        const V inv = FULCRUM_TREE_LANES_SPLAT(1.0) / root;
        L[j][j] = inv;
        for (int i = j + 1; i < 6; ++i) {
            V t = L[i][j];
            for (int k = 0; k < j; ++k) t = t - L[i][k] * L[j][k];
            L[i][j] = t * inv;
        }
    }
    for (int c = 0; c < 6; ++c) {
        V e[6];
        for (int r = 0; r < 6; ++r) e[r] = FULCRUM_TREE_LANES_SPLAT(r == c ? 1.0 : 0.0);
        for (int i = 0; i < 6; ++i) {
            V t = e[i];
            for (int k = 0; k < i; ++k) t = t - L[i][k] * e[k];
            e[i] = t * L[i][i];
        }
        for (int i = 5; i >= 0; --i) {
            V t = e[i];
            for (int k = i + 1; k < 6; ++k) t = t - L[k][i] * e[k];
            e[i] = t * L[i][i];
        }
        for (int r = 0; r < 6; ++r) lanesOf(D[r * 6 + c]) = e[r];
    }
    return failed;
}

// eliminate<dim, pdim> on node block b (pdim 0: a root), parent block p.
template <int dim, int pdim>
FULCRUM_TREE_LANES_INLINE unsigned eliminateGeneric(TreeLane4* b, TreeLane4* p) {
    TreeLane4* z = b;
    TreeLane4* D = b + 2 * dim;
    unsigned failed;
    if constexpr (dim == 6) {
        failed = invertLanes6(D);
    } else {
        V i[6];
        failed = invertLanes3(D, i);
    }
    // multiplyInPlace<dim>: z <- D^-1 z, each row from 0.
    V x[dim];
    {
        V y[dim];
        for (int k = 0; k < dim; ++k) x[k] = ld(z[k]);
        for (int r = 0; r < dim; ++r) {
            V t = FULCRUM_TREE_LANES_ZERO;
            for (int k = 0; k < dim; ++k) t = t + ld(D[r * dim + k]) * x[k];
            y[r] = t;
        }
        for (int r = 0; r < dim; ++r) lanesOf(z[r]) = y[r], x[r] = y[r];
    }
    if constexpr (pdim > 0) {
        const TreeLane4* Hp = D + dim * dim;
        TreeLane4* X = D + dim * dim + pdim * dim;
        TreeLane4* pz = p;
        TreeLane4* pD = p + 2 * pdim;
        for (int c = 0; c < pdim; ++c) {
            for (int k = 0; k < dim; ++k) {
                V t = FULCRUM_TREE_LANES_ZERO;
                for (int l = 0; l < dim; ++l) t = t + ld(D[k * dim + l]) * ld(Hp[c * dim + l]);
                lanesOf(X[c * dim + k]) = t;
            }
        }
        for (int r = 0; r < pdim; ++r) {
            V zr = FULCRUM_TREE_LANES_ZERO;
            for (int k = 0; k < dim; ++k) zr = zr + ld(Hp[r * dim + k]) * x[k];
            lanesOf(pz[r]) = ld(pz[r]) - zr;
            for (int c = 0; c <= r; ++c) {
                V s = FULCRUM_TREE_LANES_ZERO;
                for (int k = 0; k < dim; ++k) s = s + ld(Hp[r * dim + k]) * ld(X[c * dim + k]);
                lanesOf(pD[r * pdim + c]) = ld(pD[r * pdim + c]) - s;
            }
        }
    } else {
        (void)p;
    }
    return failed;
}

// eliminateChainJoint: a joint below a joint (3 x 3 blocks), its sums
// written out without the 0 starts.
FULCRUM_TREE_LANES_INLINE unsigned eliminateChain(TreeLane4* b, TreeLane4* p) {
    TreeLane4* z = b;
    TreeLane4* D = b + 6;
    const TreeLane4* Hp = D + 9;
    TreeLane4* X = b + 6 + 9 + 9;
    V i[6];
    const unsigned failed = invertLanes3(D, i);
    const V i00 = i[0], i11 = i[1], i22 = i[2], i10 = i[3], i20 = i[4], i21 = i[5];
    const V z0 = ld(z[0]), z1 = ld(z[1]), z2 = ld(z[2]);
    const V y0 = (i00 * z0 + i10 * z1) + i20 * z2;
    const V y1 = (i10 * z0 + i11 * z1) + i21 * z2;
    const V y2 = (i20 * z0 + i21 * z1) + i22 * z2;
    lanesOf(z[0]) = y0, lanesOf(z[1]) = y1, lanesOf(z[2]) = y2;
    V x[3][3];
    for (int c = 0; c < 3; ++c) {
        const V h0 = ld(Hp[3 * c]), h1 = ld(Hp[3 * c + 1]), h2 = ld(Hp[3 * c + 2]);
        x[c][0] = (i00 * h0 + i10 * h1) + i20 * h2;
        x[c][1] = (i10 * h0 + i11 * h1) + i21 * h2;
        x[c][2] = (i20 * h0 + i21 * h1) + i22 * h2;
        lanesOf(X[3 * c]) = x[c][0], lanesOf(X[3 * c + 1]) = x[c][1], lanesOf(X[3 * c + 2]) = x[c][2];
    }
    TreeLane4* pD = p + 6;  // the parent is a joint: z[3], y[3], then D
    for (int r = 0; r < 3; ++r) {
        const V h0 = ld(Hp[3 * r]), h1 = ld(Hp[3 * r + 1]), h2 = ld(Hp[3 * r + 2]);
        lanesOf(p[r]) = ld(p[r]) - ((h0 * y0 + h1 * y1) + h2 * y2);
        for (int c = 0; c <= r; ++c)
            lanesOf(pD[3 * r + c]) = ld(pD[3 * r + c]) - ((h0 * x[c][0] + h1 * x[c][1]) + h2 * x[c][2]);
    }
    return failed;
}

// Back-substitution, parents first (a root's y = z).
FULCRUM_TREE_LANES_INLINE void backAll(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data) {
    constexpr std::uint8_t kBody = 0, kBelowJoint = 1;
    for (std::uint32_t i = count; i-- > 0;) {
        const TreeLaneNode& n = nodes[i];
        TreeLane4* b = data + n.off;
        if (n.parentOff == TreeLaneNode::kNoParent) {
            if (n.kind == kBody) backGeneric<6, 0>(b, nullptr);
            else backGeneric<3, 0>(b, nullptr);
            continue;
        }
        const TreeLane4* parentY = data + n.parentOff + n.pdim;  // the parent's y (its dim is our pdim)
        if (n.kind == kBody) backGeneric<6, 3>(b, parentY);
        else if (n.kind == kBelowJoint) backGeneric<3, 3>(b, parentY);
        else backGeneric<3, 6>(b, parentY);
    }
}

}  // namespace fulcrum::detail::FULCRUM_TREE_LANES_NS

namespace fulcrum::detail {

void FULCRUM_TREE_LANES_FN(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data) {
    using namespace FULCRUM_TREE_LANES_NS;
    // The node kinds of JointTreeSolver (tree_solver.hpp).
    constexpr std::uint8_t kBody = 0, kBelowJoint = 1;
    for (std::uint32_t i = 0; i < count; ++i) {
        const TreeLaneNode& n = nodes[i];
        TreeLane4* b = data + n.off;
        TreeLane4* parent = n.parentOff == TreeLaneNode::kNoParent ? nullptr : data + n.parentOff;
        if (n.kind == kBelowJoint) {
            forwardChain(b, parent);
        } else if (n.kind == kBody) {
            if (parent) forwardGeneric<6, 3>(b, parent);
            else forwardGeneric<6, 0>(b, nullptr);
        } else {
            if (parent) forwardGeneric<3, 6>(b, parent);
            else forwardGeneric<3, 0>(b, nullptr);
        }
    }
    FULCRUM_TREE_LANES_NS::backAll(nodes, count, data);
#if defined(FULCRUM_TREE_LANES_LEAVE)
    FULCRUM_TREE_LANES_LEAVE();
#endif
}

unsigned FULCRUM_TREE_LANES_FACTOR_FN(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data) {
    using namespace FULCRUM_TREE_LANES_NS;
    constexpr std::uint8_t kBody = 0, kBelowJoint = 1;
    unsigned failed = 0;
    // Elimination and forward substitution, children first.
    for (std::uint32_t i = 0; i < count; ++i) {
        const TreeLaneNode& n = nodes[i];
        TreeLane4* b = data + n.off;
        TreeLane4* parent = n.parentOff == TreeLaneNode::kNoParent ? nullptr : data + n.parentOff;
        if (n.kind == kBelowJoint) {
            failed |= eliminateChain(b, parent);
        } else if (n.kind == kBody) {
            failed |= parent ? eliminateGeneric<6, 3>(b, parent) : eliminateGeneric<6, 0>(b, nullptr);
        } else {
            failed |= parent ? eliminateGeneric<3, 6>(b, parent) : eliminateGeneric<3, 0>(b, nullptr);
        }
    }
    backAll(nodes, count, data);
#if defined(FULCRUM_TREE_LANES_LEAVE)
    FULCRUM_TREE_LANES_LEAVE();
#endif
    return failed;
}

}  // namespace fulcrum::detail

#undef FULCRUM_TREE_LANES_INLINE
#undef FULCRUM_TREE_LANES_ZERO
#undef FULCRUM_TREE_LANES_SPLAT
