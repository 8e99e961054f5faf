// Box-box by the separating axis test over the 15 axes (3 face normals of
// each box, 9 edge-edge cross products), then face clipping for face contacts
// or the closest points of the two edges for edge contacts.
//
// A face manifold's gaps are measured along the normal from the reference
// face to the clipped incident face, so each is the distance that point can
// travel along the normal before it meets the reference face. When the part
// of B nearest A lies outside the reference face's prism (clipped away), B
// can meet A first elsewhere: at A's face edge, with a side face of B or one
// of its edges. The manifold's smallest gap then over-states how far the
// bodies can close along the normal, and a speculative contact that does so
// lets them overlap for a step. firstTouchAlong measures that distance exactly
// and the manifold gets the touching point when clipping missed it
// (docs/reliability.md, "Fuzzing").
//
// Axis choice follows Gregorius ("The Separating Axis Test", GDC 2013; "Robust
// Contact Creation for Physics Simulations", GDC 2015): a face of A wins over a
// face of B, and faces win over edges, unless the other is better by a
// tolerance. Without that bias, two boxes resting face to face flip between
// reference faces from one frame to the next as float noise changes which
// separation is larger, and the contact points and feature ids flicker.
#include <algorithm>
#include <cmath>

#include "collision/collide_pairs.hpp"

namespace fulcrum::detail {

namespace {

constexpr Real kAbsTol = Real(0.005);  // metres
constexpr Real kRelTol = Real(0.05);

// A rejected pair's proof for the contact manager's apart cache
// (docs/narrow-phase.md, "Pairs proved apart"): the boxes' separation s along
// a unit axis is never more than their distance (every point of A lies below
// A's support plane along it and every point of B above B's, s farther on).
// Gottschalk's epsilon only makes the extents longer, so s shorter. Without it
// a tumbling cube in a pile ran the SAT again every step for every
// neighbour its fattened bounds still met (washer: the most common pair).
bool provedApart(Manifold& m, Real s) {
    m.apartBy = s;
    return false;
}

bool clearlyBetter(Real candidate, Real incumbent) {
    return candidate > incumbent + kAbsTol + kRelTol * std::fabs(incumbent);
}

// The centre of the box's edge along its axis `skip` that lies furthest along
// `dir`, and which sign each other axis took (bit k set: +).
Vec3 supportingEdgeCentre(const ConvexShape& box, const Mat3& r, int skip, const Vec3& dir, std::uint32_t& signs) {
    Vec3 c = box.xf.p;
    signs = 0;
    for (int k = 0; k < 3; ++k) {
        if (k == skip) continue;
        const Real s = dot(dir, r.col(k)) >= 0 ? Real(1) : Real(-1);
        c += r.col(k) * (s * box.halfExtents[static_cast<std::size_t>(k)]);
        signs |= (s > 0 ? 1u : 0u) << k;
    }
    return c;
}

// How far B, moved along -n (unit, A to B), travels before it touches A
// (negative: how far it must move along +n to come out), with the touching
// points on A and B. The Minkowski difference B - A of two boxes is the
// intersection of the slabs along the 15 SAT axes (its facets are spanned by
// pairs of the six edge directions), so B touches A at the t where the ray
// t n enters it: the largest of (separation along u) / (u . n) over the axes
// u turned towards n. Every such ratio is a lower bound of that t, so
// skipping an axis too close to perpendicular to n (its ratio is rounding)
// can only under-state the distance.
struct Touch {
    Real distance = -1e30f;
    Vec3 pointA, pointB;
    std::uint32_t id = 0;
};

// The caller only needs the touch when it comes before `enough`: the search
// stops at the first axis that reaches it (then no points are made). The six
// face axes go first, since they need no square root and in the common case
// (B's face meeting A's edge) one of them is the answer.
Touch firstTouchAlong(const ConvexShape& a, const ConvexShape& b, const Mat3& ra, const Mat3& rb, const Vec3& n,
                      Real enough) {
    constexpr Real kMinCosine = Real(0.01);
    const Vec3 ea = a.halfExtents, eb = b.halfExtents, d = b.xf.p - a.xf.p;
    const auto projection = [](const Mat3& r, const Vec3& e, const Vec3& u) {
        return e.x * std::fabs(dot(r.col(0), u)) + e.y * std::fabs(dot(r.col(1), u)) + e.z * std::fabs(dot(r.col(2), u));
    };
    Touch best;
    int bestAxis = -1;
    Vec3 bestU;
    for (int k = 0; k < 15; ++k) {
        Vec3 u;
        if (k < 3) {
            u = ra.col(k);
        } else if (k < 6) {
            u = rb.col(k - 3);
        } else {
            u = cross(ra.col((k - 6) / 3), rb.col((k - 6) % 3));
            const Real len = length(u);
            if (len < Real(1e-5)) continue;
            u = u / len;
        }
        Real cosine = dot(u, n);
        if (cosine < 0) {
            u = -u;
            cosine = -cosine;
        }
        if (cosine < kMinCosine) continue;
        const Real t = (dot(d, u) - projection(ra, ea, u) - projection(rb, eb, u)) / cosine;
        if (t > best.distance) {
            best.distance = t;
            bestAxis = k;
            bestU = u;
            if (t >= enough) return best;
        }
    }
    // n is itself one of the axes (a face normal), so one always counts;
    // should rounding say otherwise, the clipped points stand.
    if (bestAxis < 0) {
        best.distance = enough;
        return best;
    }
    // The touching features: a face of one box against the other's
    // supporting vertex, or A's supporting edge along u against B's along -u.
    const Vec3 shift = n * best.distance;
    best.id = 0x80008000u | static_cast<std::uint32_t>(bestAxis);
    if (bestAxis < 3) {
        best.pointB = b.support(-bestU);
        best.pointA = best.pointB - shift;
    } else if (bestAxis < 6) {
        best.pointA = a.support(bestU);
        best.pointB = best.pointA + shift;
    } else {
        const int i = (bestAxis - 6) / 3, j = (bestAxis - 6) % 3;
        std::uint32_t signsA, signsB;
        const Vec3 ca = supportingEdgeCentre(a, ra, i, bestU, signsA), cb = supportingEdgeCentre(b, rb, j, -bestU, signsB) - shift;
        const Vec3 da = ra.col(i) * ea[static_cast<std::size_t>(i)], db = rb.col(j) * eb[static_cast<std::size_t>(j)];
        Real s, t;
        closestSegmentSegment(ca - da, ca + da, cb - db, cb + db, s, t);
        best.pointA = ca - da + da * (2 * s);
        best.pointB = cb - db + db * (2 * t) + shift;
    }
    return best;
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
        if (s > margin) return provedApart(m, s);
        if (s > sepA) { sepA = s; axisA = i; }
    }
    for (int j = 0; j < 3; ++j) {
        const std::size_t uj = static_cast<std::size_t>(j);
        const Real s = std::fabs(dB[uj]) - (eb[uj] + absC[0][j] * ea.x + absC[1][j] * ea.y + absC[2][j] * ea.z);
        if (s > margin) return provedApart(m, s);
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
                if (s > margin) return provedApart(m, s);
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
        std::uint32_t signsA, signsB;
        const Vec3 ca = supportingEdgeCentre(a, ra, edgeI, n, signsA), cb = supportingEdgeCentre(b, rb, edgeJ, -n, signsB);
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
    buildFaceManifold(a, b, n, margin, m, useB ? 2 : 1);
    // The clipped points' nearest is never nearer than the face axis's
    // separation (each is a real path along n onto the reference face); when
    // it lies farther, the nearest part of B was clipped away and the bodies
    // may touch before any of the points reaches the face. Only a positive
    // gap is a promise to the solver (a speculative contact); pairs whose
    // clipped points overlap, as in a resting pile, skip the measurement.
    constexpr Real kTouchTolerance = Real(1e-4);  // metres
    const Real clippedGap = -m.maxDepth();
    if (m.pointCount > 0 && clippedGap > std::max(faceSep, Real(0)) + kTouchTolerance) {
        const Touch touch = firstTouchAlong(a, b, ra, rb, n, clippedGap - kTouchTolerance);
        if (clippedGap > touch.distance + kTouchTolerance) {
            // Into a free slot, else in place of the point with the largest
            // gap (the one that constrains the bodies least).
            std::uint32_t slot = m.pointCount;
            if (slot == Manifold::kMaxPoints) {
                slot = 0;
                for (std::uint32_t k = 1; k < m.pointCount; ++k) {
                    if (m.points[k].depth < m.points[slot].depth) slot = k;
                }
            } else {
                ++m.pointCount;
            }
            ContactPoint& point = m.points[slot];
            point.position = (touch.pointA + touch.pointB) * Real(0.5);
            point.depth = -touch.distance;
            point.featureId = touch.id;
        }
    }
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
