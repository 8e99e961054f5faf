// World queries: ray casts, overlap tests and shape casts against every body
// (declarations in include/fulcrum/world.hpp, types in query.hpp, user guide
// in docs/queries.md).
//
// Every query has the same two stages:
//   1. candidates: the broad phase's trees (fat boxes) for the query's bounds
//      or segment, plus the few bodies that have left their proxy since the
//      last step (world/stray_bodies.hpp), which are tested one by one;
//   2. exact test per candidate: the filter, a cull on the body's tight
//      bounds, then the shape test (rayCastShape, GJK, shapeCast).
// Results never depend on the order the trees visit their leaves: ties are
// broken by creation order, and lists are sorted, so the answer is the same
// whatever the tree's shape (e.g. after the static tree is rebuilt).
//
// Nothing here allocates except the caller's output vector, and nothing
// writes to the world except the lazily rebuilt stray list (thread-safe).
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/heightfield.hpp"
#include "collision/mesh_bvh.hpp"
#include "collision/shape_cast.hpp"
#include "collision/shape_queries.hpp"
#include "collision/support.hpp"
#include "dynamics/validation.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

static_assert(kNoSubShapeIndex == kNoSubShape, "the public and internal 'no sub-shape' values must agree");

// ---- stray bodies ----------------------------------------------------------------

void detail::StrayBodies::refresh(const WorldImpl& w) const {
    const std::uint64_t want = w.stepCount + 1;
    if (stamp_.load(std::memory_order_acquire) == want) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stamp_.load(std::memory_order_relaxed) == want) return;
    slots_.clear();
    flags_.assign(w.bodySlots.size(), 0);
    const BroadPhase& bp = w.contactManager.broadPhase();
    const auto count = static_cast<std::uint32_t>(w.motion.size());
    for (std::uint32_t d = 0; d < count; ++d) {
        // Static bodies move only by setTransform, which moves their proxy.
        if (w.params[d].type == BodyType::Static) continue;
        const std::uint32_t slot = w.denseToSlot[d];
        const AABB tight = w.cold[d].shape.bounds(w.originTransform(d));
        if (bp.fatAABB(w.contactManager.proxyOfSlot(slot)).contains(tight)) continue;
        slots_.push_back(slot);
        flags_[slot] = 1;
    }
    // Slot order: deterministic, and the hand-tested bodies come in the same order every time.
    std::sort(slots_.begin(), slots_.end());
    stamp_.store(want, std::memory_order_release);
}

namespace {

using detail::Subject;

// Errors name the query: "World::castRay: ray.origin must be finite, got (nan, 0, 0)".
Subject query(std::string_view name) { return {name, {}, UINT32_MAX}; }

// ---- validation ----------------------------------------------------------------

void validateFilter(const WorldImpl& w, const Subject& who, const QueryFilter& filter) {
    if (!filter.excludeBody.isNull() && !w.isLive(filter.excludeBody)) {
        detail::fail(who, "filter.excludeBody",
                     "must be null or a live body, got a stale or unknown handle (index " +
                         std::to_string(filter.excludeBody.index) + ", generation " +
                         std::to_string(filter.excludeBody.generation) + ")");
    }
}

void validateRay(const WorldImpl& w, const Subject& who, const Ray& ray, const QueryFilter& filter) {
    detail::requireFinite(who, "ray.origin", ray.origin);
    detail::requireFinite(who, "ray.translation", ray.translation);
    if (lengthSquared(ray.translation) == Real(0)) {
        detail::fail(who, "ray.translation", "must not be zero (a ray needs a direction), got (0, 0, 0)");
    }
    detail::requireFinite(who, "ray.maxFraction", ray.maxFraction);
    if (ray.maxFraction < 0 || ray.maxFraction > 1) {
        detail::fail(who, "ray.maxFraction",
                     "must be in [0, 1] (scale ray.translation for longer rays), got " +
                         detail::formatReal(ray.maxFraction));
    }
    // The end point must be representable too (origin + translation overflowing to inf).
    if (!isFinite(ray.origin + ray.translation)) {
        detail::fail(who, "ray.translation", "takes the end point beyond the float range, got " +
                                                 detail::formatVec(ray.translation));
    }
    validateFilter(w, who, filter);
}

// A shape usable as a query shape: finite placement, not a plane or mesh.
Transform validateQueryShape(const Subject& who, const Shape& shape, const Transform& transform) {
    detail::requireFinite(who, "transform.p", transform.p);
    const Quat q = detail::requireOrientation(who, "transform.q", transform.q);
    if (shape.staticOnly()) {
        detail::fail(who, "shape",
                     std::string("must be convex or a compound of convex shapes (planes and meshes have no finite "
                                 "volume to test or sweep), got a ") +
                         toString(shape.type()) + (shape.type() == ShapeType::Compound ? " holding a plane or mesh" : ""));
    }
    return {transform.p, q};
}

// ---- filters, order ----------------------------------------------------------------

bool passes(const WorldImpl& w, std::uint32_t dense, const QueryFilter& filter) {
    const detail::BodyParams& p = w.params[dense];
    if (p.isSensor && !filter.includeSensors) return false;
    if ((p.filter.category & filter.mask) == 0 || (filter.category & p.filter.mask) == 0) return false;
    return filter.excludeBody.isNull() || w.denseToSlot[dense] != filter.excludeBody.index;
}

std::uint64_t serialOf(const WorldImpl& w, BodyId id) { return w.cold[w.bodySlots[id.index].dense].creationSerial; }

void sortByCreation(const WorldImpl& w, std::vector<BodyId>& ids) {
    std::sort(ids.begin(), ids.end(), [&](BodyId a, BodyId b) { return serialOf(w, a) < serialOf(w, b); });
}

// Calls fn(dense) once for every body whose proxy overlaps `box` or which is
// stray (then fn's own tests decide).
template <class Fn>
void forEachCandidate(const WorldImpl& w, const AABB& box, Fn&& fn) {
    const detail::StrayBodies& stray = w.strayBodies;
    stray.refresh(w);
    w.contactManager.broadPhase().query(box, [&](ProxyId, std::uint32_t slot) {
        if (!stray.isStray(slot)) fn(w.bodySlots[slot].dense);
        return true;
    });
    for (const std::uint32_t slot : stray.slots()) {
        if (slot < w.bodySlots.size() && w.bodySlots[slot].dense != detail::kNoIndex) fn(w.bodySlots[slot].dense);
    }
}

// Plane of a plane shape placed at xf, in world space: n . p = offset.
void worldPlane(const Shape& plane, const Transform& xf, Vec3& n, Real& offset) {
    n = rotate(xf.q, plane.planeNormal());
    offset = plane.planeOffset() + dot(n, xf.p);
}

// ---- exact overlap tests ----------------------------------------------------------

// Whether convex cores with rounding radii overlap or touch (GJK on the cores,
// van den Bergen's core-shape split: exact for spheres and capsules).
bool convexOverlap(const detail::ConvexShape& a, const detail::ConvexShape& b) {
    const detail::GjkResult g = detail::gjkDistance(a, b, false);
    return g.overlap || g.distance <= a.radius + b.radius;
}

// Query shape q at xq (convex or compound of convex) against a body's shape b at xb.
bool shapesOverlap(const Shape& q, const Transform& xq, const Shape& b, const Transform& xb) {
    if (q.type() == ShapeType::Compound) {
        for (const CompoundChild& c : q.children()) {
            if (shapesOverlap(c.shape, xq * c.transform, b, xb)) return true;
        }
        return false;
    }
    if (b.type() == ShapeType::Compound) {
        const AABB qBounds = q.bounds(xq);
        for (const CompoundChild& c : b.children()) {
            const Transform xc = xb * c.transform;
            if (c.shape.type() != ShapeType::Plane && !overlaps(c.shape.bounds(xc), qBounds)) continue;
            if (shapesOverlap(q, xq, c.shape, xc)) return true;
        }
        return false;
    }
    const detail::ConvexShape cq = detail::makeConvex(q, xq);
    switch (b.type()) {
        case ShapeType::Plane: {
            // The half-space n . p <= offset: the query's deepest point along -n decides.
            Vec3 n;
            Real offset;
            worldPlane(b, xb, n, offset);
            return dot(n, cq.support(-n)) <= offset;
        }
        case ShapeType::Mesh: {
            // Meshes are surfaces: any triangle within reach of the query shape.
            const TriangleMesh& mesh = b.mesh();
            const AABB local = transformBounds(inverse(xb), q.bounds(xq));
            bool found = false;
            const auto test = [&](std::uint32_t t) {
                const auto& idx = mesh.triangles[t];
                const detail::ConvexShape tri =
                    detail::makeTriangle(transformPoint(xb, mesh.vertices[idx[0]]), transformPoint(xb, mesh.vertices[idx[1]]),
                                         transformPoint(xb, mesh.vertices[idx[2]]));
                found = convexOverlap(cq, tri);
                return !found;
            };
            if (mesh.bvh) {
                queryTriangles(mesh, local, test);
            } else {
                for (std::uint32_t t = 0; t < mesh.triangles.size() && !found; ++t) {
                    if (overlaps(triangleBounds(mesh, t), local)) test(t);
                }
            }
            return found;
        }
        case ShapeType::HeightField: {
            // A surface too, as a mesh.
            const HeightField& hf = b.heightField();
            bool found = false;
            detail::forEachHeightFieldTriangle(hf, transformBounds(inverse(xb), q.bounds(xq)), [&](std::uint32_t t) {
                Vec3 v[3];
                hf.triangle(t, v);
                found = convexOverlap(cq, detail::makeTriangle(transformPoint(xb, v[0]), transformPoint(xb, v[1]), transformPoint(xb, v[2])));
                return !found;
            });
            return found;
        }
        default: return convexOverlap(cq, detail::makeConvex(b, xb));
    }
}

void overlapQuery(const WorldImpl& w, const Shape& shape, const Transform& xf, const QueryFilter& filter,
                  std::vector<BodyId>& out) {
    out.clear();
    const AABB bounds = shape.bounds(xf);
    forEachCandidate(w, bounds, [&](std::uint32_t d) {
        if (!passes(w, d, filter)) return;
        const Shape& bodyShape = w.cold[d].shape;
        const Transform bodyXf = w.originTransform(d);
        if (bodyShape.type() != ShapeType::Plane && !overlaps(bodyShape.bounds(bodyXf), bounds)) return;
        if (shapesOverlap(shape, xf, bodyShape, bodyXf)) out.push_back(w.idOfDense(d));
    });
    sortByCreation(w, out);
}

// ---- ray casts ---------------------------------------------------------------------

RayCastHit toHit(const WorldImpl& w, std::uint32_t dense, const RayHit& h) {
    return {w.idOfDense(dense), h.point, h.normal, h.fraction, h.child, h.triangle};
}

// Calls fn(dense, clip) for every body the segment [0, clip] may reach; fn
// returns the new clip (closest-hit queries shrink it to their best hit).
// Tree callbacks never return 0 (that would stop the cast before ties at
// fraction 0 are seen), and the static tree is cast separately so that a
// zero-length ray (maxFraction 0) still reaches it.
template <class Fn>
void forEachRayCandidate(const WorldImpl& w, const Ray& ray, Fn&& fn) {
    const detail::StrayBodies& stray = w.strayBodies;
    stray.refresh(w);
    const BroadPhase& bp = w.contactManager.broadPhase();
    Real clip = ray.maxFraction;
    const RayCastInput input{ray.origin, ray.translation, ray.maxFraction};
    const auto visit = [&](const RayCastInput& current, std::int32_t, std::uint32_t proxy) -> Real {
        const std::uint32_t slot = bp.userValue(static_cast<ProxyId>(proxy));
        if (stray.isStray(slot)) return -1;
        clip = fn(w.bodySlots[slot].dense, std::min(clip, current.maxFraction));
        return clip > Real(0) ? clip : -1;  // -1: go on with the current clip
    };
    bp.movingTree().rayCast(input, visit);
    bp.staticTree().rayCast({ray.origin, ray.translation, clip}, visit);
    for (const std::uint32_t slot : stray.slots()) {
        if (slot < w.bodySlots.size() && w.bodySlots[slot].dense != detail::kNoIndex) {
            clip = fn(w.bodySlots[slot].dense, clip);
        }
    }
}

// The body's first hit within [0, clip], after the filter and a tight-bounds cull.
std::optional<RayHit> rayCastBody(const WorldImpl& w, std::uint32_t d, const Ray& ray, const QueryFilter& filter,
                                  Real clip) {
    if (!passes(w, d, filter)) return std::nullopt;
    const Shape& shape = w.cold[d].shape;
    const Transform xf = w.originTransform(d);
    if (shape.type() != ShapeType::Plane && rayCastAABB(shape.bounds(xf), ray.origin, ray.translation, clip) < 0) {
        return std::nullopt;
    }
    return rayCastShape(shape, xf, ray.origin, ray.translation, clip);
}

}  // namespace

// ---- World ----------------------------------------------------------------------------

std::optional<RayCastHit> World::castRay(const Ray& ray, const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    validateRay(w, query("World::castRay"), ray, filter);
    std::optional<RayCastHit> best;
    std::uint64_t bestSerial = 0;
    forEachRayCandidate(w, ray, [&](std::uint32_t d, Real clip) -> Real {
        const std::optional<RayHit> h = rayCastBody(w, d, ray, filter, clip);
        if (h) {
            const std::uint64_t serial = w.cold[d].creationSerial;
            if (!best || h->fraction < best->fraction || (h->fraction == best->fraction && serial < bestSerial)) {
                best = toHit(w, d, *h);
                bestSerial = serial;
            }
        }
        // Keep visiting candidates that tie with the best (they may win on creation order).
        return best ? std::max(best->fraction, std::numeric_limits<Real>::min()) : clip;
    });
    return best;
}

void World::castRayAll(const Ray& ray, std::vector<RayCastHit>& out, const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    validateRay(w, query("World::castRayAll"), ray, filter);
    out.clear();
    forEachRayCandidate(w, ray, [&](std::uint32_t d, Real clip) -> Real {
        if (const std::optional<RayHit> h = rayCastBody(w, d, ray, filter, clip)) out.push_back(toHit(w, d, *h));
        return clip;
    });
    std::sort(out.begin(), out.end(), [&](const RayCastHit& a, const RayCastHit& b) {
        if (a.fraction != b.fraction) return a.fraction < b.fraction;
        return serialOf(w, a.body) < serialOf(w, b.body);
    });
}

std::vector<RayCastHit> World::castRayAll(const Ray& ray, const QueryFilter& filter) const {
    std::vector<RayCastHit> out;
    castRayAll(ray, out, filter);
    return out;
}

void World::overlapAABB(const AABB& box, std::vector<BodyId>& out, const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::overlapAABB");
    detail::requireFinite(who, "box.min", box.min);
    detail::requireFinite(who, "box.max", box.max);
    if (box.isEmpty()) {
        detail::fail(who, "box", "must have min <= max on every axis, got min " + detail::formatVec(box.min) +
                                     ", max " + detail::formatVec(box.max));
    }
    validateFilter(w, who, filter);
    out.clear();
    forEachCandidate(w, box, [&](std::uint32_t d) {
        if (!passes(w, d, filter)) return;
        const Shape& shape = w.cold[d].shape;
        const Transform xf = w.originTransform(d);
        bool hit;
        if (shape.type() == ShapeType::Plane) {
            // A plane's bounds are (nearly) everything: test the half-space exactly.
            Vec3 n;
            Real offset;
            worldPlane(shape, xf, n, offset);
            const Vec3 corner{n.x > 0 ? box.min.x : box.max.x, n.y > 0 ? box.min.y : box.max.y,
                              n.z > 0 ? box.min.z : box.max.z};
            hit = dot(n, corner) <= offset;
        } else {
            hit = overlaps(shape.bounds(xf), box);
        }
        if (hit) out.push_back(w.idOfDense(d));
    });
    sortByCreation(w, out);
}

std::vector<BodyId> World::overlapAABB(const AABB& box, const QueryFilter& filter) const {
    std::vector<BodyId> out;
    overlapAABB(box, out, filter);
    return out;
}

void World::overlapSphere(const Vec3& center, Real radius, std::vector<BodyId>& out, const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::overlapSphere");
    detail::requireFinite(who, "center", center);
    detail::requirePositive(who, "radius", radius);
    validateFilter(w, who, filter);
    overlapQuery(w, Shape::sphere(radius), {center, Quat::identity()}, filter, out);
}

std::vector<BodyId> World::overlapSphere(const Vec3& center, Real radius, const QueryFilter& filter) const {
    std::vector<BodyId> out;
    overlapSphere(center, radius, out, filter);
    return out;
}

void World::overlapBox(const Vec3& center, const Vec3& halfExtents, const Quat& orientation, std::vector<BodyId>& out,
                       const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::overlapBox");
    detail::requireFinite(who, "center", center);
    detail::requireFinite(who, "halfExtents", halfExtents);
    if (!(minComponent(halfExtents) > 0)) {
        detail::fail(who, "halfExtents", "must be positive on every axis, got " + detail::formatVec(halfExtents));
    }
    const Quat q = detail::requireOrientation(who, "orientation", orientation);
    validateFilter(w, who, filter);
    overlapQuery(w, Shape::box(halfExtents), {center, q}, filter, out);
}

std::vector<BodyId> World::overlapBox(const Vec3& center, const Vec3& halfExtents, const Quat& orientation,
                                      const QueryFilter& filter) const {
    std::vector<BodyId> out;
    overlapBox(center, halfExtents, orientation, out, filter);
    return out;
}

void World::overlapShape(const Shape& shape, const Transform& transform, std::vector<BodyId>& out,
                         const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::overlapShape");
    const Transform xf = validateQueryShape(who, shape, transform);
    validateFilter(w, who, filter);
    overlapQuery(w, shape, xf, filter, out);
}

std::vector<BodyId> World::overlapShape(const Shape& shape, const Transform& transform,
                                        const QueryFilter& filter) const {
    std::vector<BodyId> out;
    overlapShape(shape, transform, out, filter);
    return out;
}

std::optional<ShapeCastHit> World::castShape(const Shape& shape, const Transform& transform, const Vec3& translation,
                                             const QueryFilter& filter) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::castShape");
    const Transform xf = validateQueryShape(who, shape, transform);
    detail::requireFinite(who, "translation", translation);
    if (lengthSquared(translation) == Real(0)) {
        detail::fail(who, "translation", "must not be zero (use overlapShape to test a shape in place), got (0, 0, 0)");
    }
    if (!isFinite(xf.p + translation)) {
        detail::fail(who, "translation", "takes the shape beyond the float range, got " + detail::formatVec(translation));
    }
    validateFilter(w, who, filter);

    // shapeCast reports contact within kCastTolerance of touching, so the
    // candidate boxes and the lower bound below are widened by it: a body that
    // close counts as hit, whether or not its bounds quite reach.
    constexpr Real kCastTolerance = Real(1e-4);  // shapeCast's default
    const AABB start = shape.bounds(xf).fattened(kCastTolerance);
    AABB swept = start;
    swept.grow(shape.bounds({xf.p + translation, xf.q}).fattened(kCastTolerance));
    const Vec3 center = start.center(), half = start.halfExtents();

    std::optional<ShapeCastHit> best;
    std::uint64_t bestSerial = 0;
    forEachCandidate(w, swept, [&](std::uint32_t d) {
        if (!passes(w, d, filter)) return;
        const Shape& bodyShape = w.cold[d].shape;
        const Transform bodyXf = w.originTransform(d);
        if (bodyShape.type() != ShapeType::Plane) {
            // Lower bound on the time of impact: the start box's centre, swept,
            // entering the body's bounds grown by the start box (Minkowski sum).
            const AABB b = bodyShape.bounds(bodyXf);
            const AABB grown{b.min - half, b.max + half};
            const Real bound = best ? best->fraction : Real(1);
            if (rayCastAABB(grown, center, translation, bound) < 0) return;
        }
        const ShapeCastResult r = shapeCast(shape, xf, translation, bodyShape, bodyXf, kCastTolerance);
        if (!r.hit) return;
        const std::uint64_t serial = w.cold[d].creationSerial;
        if (!best || r.fraction < best->fraction || (r.fraction == best->fraction && serial < bestSerial)) {
            best = ShapeCastHit{w.idOfDense(d), r.fraction, r.point, -r.normal};
            bestSerial = serial;
        }
    });
    return best;
}

// ---- closest points ----------------------------------------------------------------

namespace {

// Refuses what closestPoints cannot measure, naming the argument.
void requireMeasurable(const Subject& who, const char* argument, const Shape& shape) {
    const ShapeType t = shape.type();
    if (t == ShapeType::Mesh || t == ShapeType::HeightField) {
        detail::fail(who, argument,
                     std::string("must be convex, a plane or a compound of them (a ") + toString(t) +
                         " has no bound on the search for its closest triangle)");
    }
    for (const CompoundChild& c : shape.children()) requireMeasurable(who, argument, c.shape);
}

ClosestPoints convexClosest(const detail::ConvexShape& a, const detail::ConvexShape& b) {
    const detail::GjkResult g = detail::gjkDistance(a, b, false);
    if (!g.overlap && g.distance > Real(1e-6)) {
        const Vec3 n = (g.pointB - g.pointA) / g.distance;
        return {g.distance - a.radius - b.radius, g.pointA + n * a.radius, g.pointB - n * b.radius, n};
    }
    const detail::PenetrationResult p = detail::epaPenetration(a, b);
    if (p.valid) return {-p.depth, p.pointA, p.pointB, p.normal};
    // Touching cores without a usable penetration (degenerate): the centres say which way.
    const Vec3 d = b.center() - a.center();
    const Real len = length(d);
    const Vec3 n = len > 0 ? d / len : Vec3{0, 1, 0};
    return {-(a.radius + b.radius), g.pointA + n * a.radius, g.pointB - n * b.radius, n};
}

// Convex `b` and the half-space of plane `a` (normal n out of the solid).
ClosestPoints planeClosest(const Shape& plane, const Transform& xp, const detail::ConvexShape& b) {
    Vec3 n;
    Real offset;
    worldPlane(plane, xp, n, offset);
    const Vec3 deepest = b.support(-n);
    const Real gap = dot(n, deepest) - offset;
    return {gap, deepest - n * gap, deepest, n};
}

ClosestPoints flipped(const ClosestPoints& c) { return {c.distance, c.pointB, c.pointA, -c.normal}; }

ClosestPoints closestRecursive(const Subject& who, const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    const auto best = [&](auto&& each, std::span<const CompoundChild> children) {
        ClosestPoints out;
        out.distance = std::numeric_limits<Real>::max();
        for (const CompoundChild& c : children) {
            const ClosestPoints r = each(c);
            if (r.distance < out.distance) out = r;
        }
        return out;
    };
    if (a.type() == ShapeType::Compound) {
        return best([&](const CompoundChild& c) { return closestRecursive(who, c.shape, xa * c.transform, b, xb); }, a.children());
    }
    if (b.type() == ShapeType::Compound) {
        return best([&](const CompoundChild& c) { return closestRecursive(who, a, xa, c.shape, xb * c.transform); }, b.children());
    }
    const bool planeA = a.type() == ShapeType::Plane, planeB = b.type() == ShapeType::Plane;
    if (planeA && planeB) detail::fail(who, "shapes", "cannot both be planes (two infinite half-spaces have no closest points)");
    if (planeA) return planeClosest(a, xa, detail::makeConvex(b, xb));
    if (planeB) return flipped(planeClosest(b, xb, detail::makeConvex(a, xa)));
    return convexClosest(detail::makeConvex(a, xa), detail::makeConvex(b, xb));
}

}  // namespace

ClosestPoints World::closestPoints(BodyId a, BodyId b) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::closestPoints");
    const std::uint32_t da = w.resolveBody(a, "World::closestPoints"), db = w.resolveBody(b, "World::closestPoints");
    requireMeasurable(who, "body a's shape", w.cold[da].shape);
    requireMeasurable(who, "body b's shape", w.cold[db].shape);
    return closestRecursive(who, w.cold[da].shape, w.originTransform(da), w.cold[db].shape, w.originTransform(db));
}

ClosestPoints World::closestPoints(const Shape& shape, const Transform& transform, BodyId body) const {
    const WorldImpl& w = *impl_;
    const Subject who = query("World::closestPoints");
    detail::requireFinite(who, "transform.p", transform.p);
    const Quat q = detail::requireOrientation(who, "transform.q", transform.q);
    const std::uint32_t d = w.resolveBody(body, "World::closestPoints");
    requireMeasurable(who, "shape", shape);
    requireMeasurable(who, "the body's shape", w.cold[d].shape);
    return closestRecursive(who, shape, {transform.p, q}, w.cold[d].shape, w.originTransform(d));
}

Real World::distanceBetween(BodyId a, BodyId b) const { return closestPoints(a, b).distance; }

}  // namespace fulcrum
