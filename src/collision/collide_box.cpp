// Box-box by the separating axis test over the 15 axes (3 face normals of
// each box, 9 edge-edge cross products), then face clipping for face contacts
// or the closest points of the two edges for edge contacts.
//
// Axis choice follows Gregorius ("The Separating Axis Test", GDC 2013; "Robust
// Contact Creation for Physics Simulations", GDC 2015): a face of A wins over a
// face of B, and faces win over edges, unless the other is better by a
// tolerance. Without that bias, two boxes resting face to face flip between
// reference faces from one frame to the next as float noise changes which
// separation is larger, and the contact points and feature ids flicker.
#include <cmath>

#include "collision/collide_pairs.hpp"

namespace fulcrum::detail {

namespace {

constexpr Real kAbsTol = Real(0.005);  // metres
constexpr Real kRelTol = Real(0.05);

bool clearlyBetter(Real candidate, Real incumbent) {
    return candidate > incumbent + kAbsTol + kRelTol * std::fabs(incumbent);
}

}  // namespace

bool collideBoxBox(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    const Mat3 ra = toMat3(a.xf.q), rb = toMat3(b.xf.q);
    const Vec3 ea = a.halfExtents, eb = b.halfExtents;
    const Vec3 d = b.xf.p - a.xf.p;
    const Vec3 dA = transposeMul(ra, d), dB = transposeMul(rb, d);
    Real c[3][3], absC[3][3];
    bool parallel = false;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            c[i][j] = dot(ra.col(i), rb.col(j));
            // Gottschalk's epsilon keeps near-parallel edge axes from being
            // judged by the noise in their tiny cross products.
            absC[i][j] = std::fabs(c[i][j]) + Real(1e-6);
            if (absC[i][j] > Real(0.99999)) parallel = true;
        }
    }

    Real sepA = -1e30f, sepB = -1e30f, sepE = -1e30f;
    int axisA = 0, axisB = 0, edgeI = 0, edgeJ = 0;
    Vec3 edgeAxis;
    for (int i = 0; i < 3; ++i) {
        const std::size_t ui = static_cast<std::size_t>(i);
        const Real s = std::fabs(dA[ui]) - (ea[ui] + absC[i][0] * eb.x + absC[i][1] * eb.y + absC[i][2] * eb.z);
        if (s > margin) return false;
        if (s > sepA) { sepA = s; axisA = i; }
    }
    for (int j = 0; j < 3; ++j) {
        const std::size_t uj = static_cast<std::size_t>(j);
        const Real s = std::fabs(dB[uj]) - (eb[uj] + absC[0][j] * ea.x + absC[1][j] * ea.y + absC[2][j] * ea.z);
        if (s > margin) return false;
        if (s > sepB) { sepB = s; axisB = j; }
    }
    if (!parallel) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                // Axis A_i x B_j in A's frame: e_i x (column j of C).
                const Vec3 bj{c[0][j], c[1][j], c[2][j]};
                Vec3 ei;
                ei[static_cast<std::size_t>(i)] = 1;
                const Vec3 axis = cross(ei, bj);
                const Real len = length(axis);
                if (len < Real(1e-5)) continue;
                const Vec3 u = axis / len;
                const Real projA = ea.x * std::fabs(u.x) + ea.y * std::fabs(u.y) + ea.z * std::fabs(u.z);
                Real projB = 0;
                for (int k = 0; k < 3; ++k) {
                    const Vec3 bk{c[0][k], c[1][k], c[2][k]};
                    projB += eb[static_cast<std::size_t>(k)] * std::fabs(dot(bk, u));
                }
                const Real s = std::fabs(dot(dA, u)) - projA - projB;
                if (s > margin) return false;
                if (s > sepE) { sepE = s; edgeI = i; edgeJ = j; edgeAxis = ra * u; }
            }
        }
    }

    bool useB = clearlyBetter(sepB, sepA);
    const Real faceSep = useB ? sepB : sepA;
    if (clearlyBetter(sepE, faceSep)) {
        Vec3 n = edgeAxis;
        if (dot(n, d) < 0) n = -n;
        // Supporting edges: A's along n, B's along -n.
        Vec3 ca = a.xf.p, cb = b.xf.p;
        std::uint32_t signsA = 0, signsB = 0;
        for (int k = 0; k < 3; ++k) {
            const std::size_t uk = static_cast<std::size_t>(k);
            if (k != edgeI) {
                const Real s = dot(n, ra.col(k)) >= 0 ? Real(1) : Real(-1);
                ca += ra.col(k) * (s * ea[uk]);
                signsA |= (s > 0 ? 1u : 0u) << k;
            }
            if (k != edgeJ) {
                const Real s = dot(n, rb.col(k)) <= 0 ? Real(1) : Real(-1);
                cb += rb.col(k) * (s * eb[uk]);
                signsB |= (s > 0 ? 1u : 0u) << k;
            }
        }
        const Vec3 da = ra.col(edgeI) * ea[static_cast<std::size_t>(edgeI)];
        const Vec3 db = rb.col(edgeJ) * eb[static_cast<std::size_t>(edgeJ)];
        Real s, t;
        closestSegmentSegment(ca - da, ca + da, cb - db, cb + db, s, t);
        const Vec3 pa = ca - da + da * (2 * s), pb = cb - db + db * (2 * t);
        m.normal = n;
        m.pointCount = 0;
        const std::uint32_t id = 0x80000000u | (static_cast<std::uint32_t>(edgeI) << 12) | (signsA << 8) |
                                 (static_cast<std::uint32_t>(edgeJ) << 4) | signsB;
        addContact(m, pa, pb, dot(pa - pb, n), id, margin);
        return m.pointCount > 0;
    }
    Vec3 n;
    if (useB) {
        n = rb.col(axisB) * (dB[static_cast<std::size_t>(axisB)] >= 0 ? Real(1) : Real(-1));
    } else {
        n = ra.col(axisA) * (dA[static_cast<std::size_t>(axisA)] >= 0 ? Real(1) : Real(-1));
    }
    buildFaceManifold(a, b, n, a.support(n), b.support(-n), margin, m, useB ? 2 : 1);
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
