#include "contacts/recycled_points.hpp"

#include <type_traits>

#include "contacts/contact_manager.hpp"

#if defined(__SSE2__) && !defined(FULCRUM_DOUBLE)
#define FULCRUM_RECYCLE_LANES 1
#include <emmintrin.h>
#endif

namespace fulcrum::detail {

bool refreshRecycledPointsScalar(CachedManifold& m, const Transform& xA, const Transform& xB) {
    bool touching = false;
    for (std::uint32_t k = 0; k < m.pointCount; ++k) {
        CachedPoint& p = m.points[k];
        const Vec3 pA = transformPoint(xA, p.localA), pB = transformPoint(xB, p.localB);
        p.position = (pA + pB) * Real(0.5);
        p.depth = dot(m.normal, pA - pB);
        p.depthAfter = p.depth;
        touching = touching || p.depth > -kTouchSlop;
    }
    return touching;
}

bool refreshRecycledManifoldScalar(CachedManifold& m, const Transform& xA, const Transform& xB) {
    m.normal = rotate(xA.q, m.localNormal);
    return refreshRecycledPointsScalar(m, xA, xB);
}

PairPoses pairPosesScalar(const BodyFrame& a, const BodyFrame& b) {
    const Transform xA{a.com - rotate(a.q, a.localCom), a.q}, xB{b.com - rotate(b.q, b.localCom), b.q};
    return {xA, xB, relative(xA, xB)};
}

#if FULCRUM_RECYCLE_LANES

namespace {

static_assert(std::is_same_v<Real, float> && sizeof(Vec3) == 3 * sizeof(float));

// A Vec3 as lanes x, y, z and a zero (nothing past the Vec3 is read).
__m128 load3(const Vec3& v) {
    const __m128 xy = _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(&v.x)));
    return _mm_movelh_ps(xy, _mm_load_ss(&v.z));
}
void store3(Vec3& v, __m128 r) {
    _mm_storel_pi(reinterpret_cast<__m64*>(&v.x), r);
    _mm_store_ss(&v.z, _mm_movehl_ps(r, r));
}
// The lanes (y, z, x) and (z, x, y): cross(a, b) = a.yzx b.zxy - a.zxy b.yzx,
// lane by lane the scalar cross's products and difference.
__m128 yzx(__m128 a) { return _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 0, 2, 1)); }
__m128 zxy(__m128 a) { return _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 1, 0, 2)); }

// quat.hpp's rotate(q, v) = v + t w + u x t with t = 2 (u x v), the
// quaternion's lanes set up once.
class RotationLanes {
public:
    explicit RotationLanes(const Quat& q)
        : uYzx_(_mm_set_ps(0, q.x, q.z, q.y)), uZxy_(_mm_set_ps(0, q.y, q.x, q.z)), w_(_mm_set1_ps(q.w)) {}
    __m128 rotate(__m128 v) const {
        const __m128 t = _mm_mul_ps(cross(v), _mm_set1_ps(2));
        return _mm_add_ps(_mm_add_ps(v, _mm_mul_ps(t, w_)), cross(t));
    }

private:
    // u x v
    __m128 cross(__m128 v) const { return _mm_sub_ps(_mm_mul_ps(uYzx_, zxy(v)), _mm_mul_ps(uZxy_, yzx(v))); }
    __m128 uYzx_, uZxy_, w_;
};

// transformPoint(t, v) = rotate(t.q, v) + t.p.
class TransformLanes {
public:
    explicit TransformLanes(const Transform& t) : rotation_(t.q), p_(load3(t.p)) {}
    __m128 rotate(__m128 v) const { return rotation_.rotate(v); }
    __m128 point(__m128 v) const { return _mm_add_ps(rotation_.rotate(v), p_); }

private:
    RotationLanes rotation_;
    __m128 p_;
};

bool refreshInLanes(CachedManifold& m, const TransformLanes& a, const TransformLanes& b) {
    const __m128 normal = load3(m.normal);
    const __m128 half = _mm_set1_ps(0.5f);
    bool touching = false;
    for (std::uint32_t k = 0; k < m.pointCount; ++k) {
        CachedPoint& p = m.points[k];
        const __m128 pA = a.point(load3(p.localA)), pB = b.point(load3(p.localB));
        store3(p.position, _mm_mul_ps(_mm_add_ps(pA, pB), half));
        // dot(normal, pA - pB): (x x' + y y') + z z', as the scalar dot adds.
        const __m128 products = _mm_mul_ps(normal, _mm_sub_ps(pA, pB));
        const __m128 xy = _mm_add_ss(products, _mm_shuffle_ps(products, products, _MM_SHUFFLE(1, 1, 1, 1)));
        p.depth = _mm_cvtss_f32(_mm_add_ss(xy, _mm_movehl_ps(products, products)));
        p.depthAfter = p.depth;
        touching = touching || p.depth > -kTouchSlop;
    }
    return touching;
}

}  // namespace

bool refreshRecycledPoints(CachedManifold& m, const Transform& xA, const Transform& xB) {
    return refreshInLanes(m, TransformLanes(xA), TransformLanes(xB));
}

bool refreshRecycledManifold(CachedManifold& m, const Transform& xA, const Transform& xB) {
    const TransformLanes a(xA);
    store3(m.normal, a.rotate(load3(m.localNormal)));
    return refreshInLanes(m, a, TransformLanes(xB));
}

PairPoses pairPoses(const BodyFrame& a, const BodyFrame& b) {
    PairPoses poses;
    const __m128 pA = _mm_sub_ps(load3(a.com), RotationLanes(a.q).rotate(load3(a.localCom)));
    const __m128 pB = _mm_sub_ps(load3(b.com), RotationLanes(b.q).rotate(load3(b.localCom)));
    store3(poses.a.p, pA);
    poses.a.q = a.q;
    store3(poses.b.p, pB);
    poses.b.q = b.q;
    // relative(a, b): inverseRotate(a.q, pB - pA), i.e. rotate by the conjugate; the product scalar.
    const Quat inverseA = conjugate(a.q);
    store3(poses.relative.p, RotationLanes(inverseA).rotate(_mm_sub_ps(pB, pA)));
    poses.relative.q = inverseA * b.q;
    return poses;
}

#else

bool refreshRecycledPoints(CachedManifold& m, const Transform& xA, const Transform& xB) {
    return refreshRecycledPointsScalar(m, xA, xB);
}

bool refreshRecycledManifold(CachedManifold& m, const Transform& xA, const Transform& xB) {
    return refreshRecycledManifoldScalar(m, xA, xB);
}

PairPoses pairPoses(const BodyFrame& a, const BodyFrame& b) { return pairPosesScalar(a, b); }

#endif

}  // namespace fulcrum::detail
