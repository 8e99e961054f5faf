// The kernel of tree_lanes.hpp, included by tree_lanes.cpp (the baseline
// target) and tree_lanes_avx2.cpp (-mavx2) with FULCRUM_TREE_LANES_NS and
// FULCRUM_TREE_LANES_FN set. No include guard: one inclusion per file.
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
#else
struct V {
    double p[4];
};
#define FULCRUM_TREE_LANES_INLINE inline
inline V operator+(const V& a, const V& b) { return {{a.p[0] + b.p[0], a.p[1] + b.p[1], a.p[2] + b.p[2], a.p[3] + b.p[3]}}; }
inline V operator-(const V& a, const V& b) { return {{a.p[0] - b.p[0], a.p[1] - b.p[1], a.p[2] - b.p[2], a.p[3] - b.p[3]}}; }
inline V operator*(const V& a, const V& b) { return {{a.p[0] * b.p[0], a.p[1] * b.p[1], a.p[2] * b.p[2], a.p[3] * b.p[3]}}; }
inline const V& ld(const TreeLane4& x) { return *reinterpret_cast<const V*>(x.v); }
inline V& lanesOf(TreeLane4& x) { return *reinterpret_cast<V*>(x.v); }
#define FULCRUM_TREE_LANES_ZERO V{{0.0, 0.0, 0.0, 0.0}}
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
#if defined(FULCRUM_TREE_LANES_LEAVE)
    FULCRUM_TREE_LANES_LEAVE();
#endif
}

}  // namespace fulcrum::detail

#undef FULCRUM_TREE_LANES_INLINE
#undef FULCRUM_TREE_LANES_ZERO
