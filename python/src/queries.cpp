// Queries (ray casts, overlaps, shape casts, closest points) with results as objects, and the
// contact manifolds of the last step (docs/queries.md).
#include "common.hpp"

namespace fulcrum::python {

namespace {

struct PyRayHit {
    py::object body;
    RayCastHit hit;
};
struct PyShapeHit {
    py::object body;
    ShapeCastHit hit;
};
struct PyContact {
    py::object bodyA, bodyB;
    ContactReport report;
};

QueryFilter filterOf(const PyWorld& w, std::uint32_t category, std::uint32_t mask, py::object exclude, bool sensors) {
    QueryFilter f;
    f.category = category;
    f.mask = mask;
    f.excludeBody = bodyIdOf(exclude, w.state, "exclude");
    f.includeSensors = sensors;
    return f;
}

py::list bodyList(const PyWorld& w, const std::vector<BodyId>& ids) {
    py::list out;
    for (const BodyId id : ids) out.append(bodyObject(w.state, id));
    return out;
}

py::object subIndex(std::uint32_t i) { return i == kNoSubShapeIndex ? py::object(py::none()) : py::object(py::int_(i)); }

#define FULCRUM_FILTER_ARGS                                                                                           \
    py::arg("category") = 0xFFFFFFFFu, py::arg("mask") = 0xFFFFFFFFu, py::arg("exclude") = py::none(),             \
        py::arg("include_sensors") = false

}  // namespace

void bindQueries(py::module_& m) {
    py::class_<PyRayHit>(m, "RayHit", "A ray cast's hit: body, point, normal (outward), fraction, child, triangle.")
        .def_readonly("body", &PyRayHit::body)
        .def_property_readonly("point", [](const PyRayHit& h) { return fromVec3(h.hit.point); })
        .def_property_readonly("normal", [](const PyRayHit& h) { return fromVec3(h.hit.normal); })
        .def_property_readonly("fraction", [](const PyRayHit& h) { return h.hit.fraction; },
                               "Of the translation: a distance when the translation is a unit direction.")
        .def_property_readonly("child", [](const PyRayHit& h) { return subIndex(h.hit.child); }, "Compound child hit, or None.")
        .def_property_readonly("triangle", [](const PyRayHit& h) { return subIndex(h.hit.triangle); }, "Mesh triangle hit, or None.")
        .def("__repr__", [](const PyRayHit& h) {
            return "<fulcrum.RayHit fraction " + std::to_string(h.hit.fraction) + " at " + reprVec3(h.hit.point) + ">";
        });
    py::class_<PyShapeHit>(m, "ShapeHit", "A shape cast's first contact: body, fraction of the translation, point, normal.")
        .def_readonly("body", &PyShapeHit::body)
        .def_property_readonly("fraction", [](const PyShapeHit& h) { return h.hit.fraction; })
        .def_property_readonly("point", [](const PyShapeHit& h) { return fromVec3(h.hit.point); })
        .def_property_readonly("normal", [](const PyShapeHit& h) { return fromVec3(h.hit.normal); })
        .def("__repr__", [](const PyShapeHit& h) {
            return "<fulcrum.ShapeHit fraction " + std::to_string(h.hit.fraction) + " at " + reprVec3(h.hit.point) + ">";
        });
    py::class_<PyContact>(m, "Contact", "A touching contact manifold of the last step.")
        .def_readonly("body_a", &PyContact::bodyA)
        .def_readonly("body_b", &PyContact::bodyB)
        .def_property_readonly("normal", [](const PyContact& c) { return fromVec3(c.report.normal); }, "Unit, from A to B.")
        .def_property_readonly("depth", [](const PyContact& c) { return c.report.depth; }, "Positive when overlapping, m.")
        .def_property_readonly("points", [](const PyContact& c) { return fromVec3List(c.report.points); }, "(k, 3) world points.")
        .def_property_readonly("normal_impulse", [](const PyContact& c) { return c.report.normalImpulse; },
                               "N s on B along the normal, summed over the points, over the last step.")
        .def_property_readonly("friction_impulse", [](const PyContact& c) { return fromVec3(c.report.frictionImpulse); },
                               "N s, tangent impulse on B over the last step, (3,).")
        .def_property_readonly("force", [](const PyContact& c) { return fromVec3(c.report.force); },
                               "N on B, averaged over the last step, (3,).")
        .def_property_readonly("point_normal_impulses",
                               [](const PyContact& c) {
                                   py::list out;
                                   for (const Real v : c.report.pointNormalImpulses) out.append(v);
                                   return out;
                               },
                               "N s per point (as points).")
        .def("__repr__", [](const PyContact& c) {
            return "<fulcrum.Contact " + std::to_string(c.report.points.size()) + " points, depth " +
                   std::to_string(c.report.depth) + ">";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    cls.def(
        "ray_cast",
        [](const PyWorld& w, py::object origin, py::object translation, Real maxFraction, bool all,
           std::uint32_t category, std::uint32_t mask, py::object exclude, bool sensors) -> py::object {
            const World& world = w.world();
            const Ray ray{toVec3(origin, "origin"), toVec3(translation, "translation"), maxFraction};
            const QueryFilter f = filterOf(w, category, mask, exclude, sensors);
            if (all) {
                py::list out;
                for (const RayCastHit& h : world.castRayAll(ray, f)) out.append(PyRayHit{bodyObject(w.state, h.body), h});
                return out;
            }
            const auto hit = world.castRay(ray, f);
            if (!hit) return py::none();
            return py::cast(PyRayHit{bodyObject(w.state, hit->body), *hit});
        },
        py::arg("origin"), py::arg("translation"), py::kw_only(), py::arg("max_fraction") = 1, py::arg("all") = false,
        FULCRUM_FILTER_ARGS,
        "Casts the segment origin + t * translation, t in [0, max_fraction]: the closest RayHit or None; with "
        "all=True every body entered, sorted by fraction. Filters: category / mask bits, exclude (a Body), "
        "include_sensors.");
    cls.def(
        "overlap_aabb",
        [](const PyWorld& w, py::object lo, py::object hi, std::uint32_t category, std::uint32_t mask, py::object exclude, bool sensors) {
            const AABB box{toVec3(lo, "min"), toVec3(hi, "max")};
            return bodyList(w, w.world().overlapAABB(box, filterOf(w, category, mask, exclude, sensors)));
        },
        py::arg("min"), py::arg("max"), py::kw_only(), FULCRUM_FILTER_ARGS,
        "Bodies whose bounds overlap the box, in creation order.");
    cls.def(
        "overlap_sphere",
        [](const PyWorld& w, py::object center, Real radius, std::uint32_t category, std::uint32_t mask, py::object exclude, bool sensors) {
            return bodyList(w, w.world().overlapSphere(toVec3(center, "center"), radius, filterOf(w, category, mask, exclude, sensors)));
        },
        py::arg("center"), py::arg("radius"), py::kw_only(), FULCRUM_FILTER_ARGS,
        "Bodies whose shape overlaps (or touches) the sphere, in creation order.");
    cls.def(
        "overlap_box",
        [](const PyWorld& w, py::object center, py::object half, py::object orientation, std::uint32_t category,
           std::uint32_t mask, py::object exclude, bool sensors) {
            return bodyList(w, w.world().overlapBox(toVec3(center, "center"), toVec3(half, "half_extents"),
                                                    toQuat(orientation, "orientation"),
                                                    filterOf(w, category, mask, exclude, sensors)));
        },
        py::arg("center"), py::arg("half_extents"), py::kw_only(), py::arg("orientation") = py::make_tuple(1, 0, 0, 0),
        FULCRUM_FILTER_ARGS, "Bodies whose shape overlaps the oriented box, in creation order.");
    cls.def(
        "overlap_shape",
        [](const PyWorld& w, const Shape& shape, py::object position, py::object orientation, std::uint32_t category,
           std::uint32_t mask, py::object exclude, bool sensors) {
            const Transform xf(toVec3(position, "position"), normalize(toQuat(orientation, "orientation")));
            return bodyList(w, w.world().overlapShape(shape, xf, filterOf(w, category, mask, exclude, sensors)));
        },
        py::arg("shape"), py::arg("position"), py::kw_only(), py::arg("orientation") = py::make_tuple(1, 0, 0, 0),
        FULCRUM_FILTER_ARGS, "Bodies whose shape overlaps `shape` placed at position / orientation.");
    cls.def(
        "shape_cast",
        [](const PyWorld& w, const Shape& shape, py::object position, py::object translation, py::object orientation,
           std::uint32_t category, std::uint32_t mask, py::object exclude, bool sensors) -> py::object {
            const Transform xf(toVec3(position, "position"), normalize(toQuat(orientation, "orientation")));
            const auto hit = w.world().castShape(shape, xf, toVec3(translation, "translation"),
                                                 filterOf(w, category, mask, exclude, sensors));
            if (!hit) return py::none();
            return py::cast(PyShapeHit{bodyObject(w.state, hit->body), *hit});
        },
        py::arg("shape"), py::arg("position"), py::arg("translation"), py::kw_only(),
        py::arg("orientation") = py::make_tuple(1, 0, 0, 0), FULCRUM_FILTER_ARGS,
        "Sweeps a convex shape (no rotation) along translation: its first contact as a ShapeHit, or None.");
    const auto closestDict = [](const ClosestPoints& c) {
        return py::dict(py::arg("distance") = c.distance, py::arg("point_a") = fromVec3(c.pointA),
                        py::arg("point_b") = fromVec3(c.pointB), py::arg("normal") = fromVec3(c.normal));
    };
    cls.def(
        "closest_points",
        [closestDict](const PyWorld& w, py::object a, py::object b, py::object position, py::object orientation) {
            const BodyId idB = bodyIdOf(b, w.state, "b");
            if (py::isinstance<Shape>(a)) {
                if (position.is_none()) throw py::type_error("argument 'position': needed when 'a' is a Shape");
                const Transform xf(toVec3(position, "position"), toQuat(orientation, "orientation"));
                return closestDict(w.world().closestPoints(a.cast<const Shape&>(), xf, idB));
            }
            return closestDict(w.world().closestPoints(bodyIdOf(a, w.state, "a"), idB));
        },
        py::arg("a"), py::arg("b"), py::kw_only(), py::arg("position") = py::none(),
        py::arg("orientation") = py::make_tuple(1, 0, 0, 0),
        "Closest points of body a (or Shape a at position / orientation) and body b: a dict of distance (negative: "
        "overlap depth), point_a, point_b and normal (unit, from a towards b). Convex shapes, planes and compounds.");
    cls.def(
        "distance",
        [](const PyWorld& w, py::object a, py::object b) {
            return w.world().distanceBetween(bodyIdOf(a, w.state, "a"), bodyIdOf(b, w.state, "b"));
        },
        py::arg("a"), py::arg("b"), "Distance between the surfaces of two bodies (negative: overlap depth).");
    cls.def(
        "contacts",
        [](const PyWorld& w) {
            py::list out;
            for (ContactReport& c : w.world().contacts())
                out.append(PyContact{bodyObject(w.state, c.bodyA), bodyObject(w.state, c.bodyB), std::move(c)});
            return out;
        },
        "The touching contact manifolds of the last step, as Contact objects.");
    cls.def(
        "contact_force",
        [](const PyWorld& w, py::object body) { return fromVec3(w.world().contactForce(bodyIdOf(body, w.state, "body"))); },
        py::arg("body"), "The sum of the contact forces on a body over the last step (N, world).");
    cls.def(
        "contact_forces",
        [](const PyWorld& w, py::iterable bodies) {
            std::vector<BodyId> ids;
            for (py::handle b : bodies) ids.push_back(bodyIdOf(py::reinterpret_borrow<py::object>(b), w.state, "bodies"));
            return fromVec3List(w.world().contactForces(ids));
        },
        py::arg("bodies"), "contact_force for several bodies in one pass, as an (n, 3) array.");
    cls.def(
        "contact_hit_events",
        [](const PyWorld& w) {
            py::list out;
            for (const ContactHitEvent& e : w.world().contactHitEvents())
                out.append(py::dict(py::arg("body_a") = bodyObject(w.state, e.bodyA),
                                    py::arg("body_b") = bodyObject(w.state, e.bodyB), py::arg("point") = fromVec3(e.point),
                                    py::arg("normal") = fromVec3(e.normal), py::arg("approach_speed") = e.approachSpeed));
            return out;
        },
        "Impacts of the last step faster than hit_event_threshold: [{'body_a', 'body_b', 'point', 'normal', "
        "'approach_speed'}, ...].");
}

}  // namespace fulcrum::python
