// Shapes: fulcrum.Shape and one Python class per kind (Sphere, Box, Capsule,
// Cylinder, ConvexHull, Plane, Mesh, Compound, HeightField), each a thin subclass of the
// engine's Shape value so isinstance() works and body.shape comes back as the
// kind it is.
#include <cstdio>

#include "common.hpp"

namespace fulcrum::python {

namespace {

struct SphereShape : Shape {};
struct BoxShape : Shape {};
struct CapsuleShape : Shape {};
struct CylinderShape : Shape {};
struct HullShape : Shape {};
struct PlaneShape : Shape {};
struct MeshShape : Shape {};
struct CompoundShape : Shape {};
struct HeightFieldShape : Shape {};

template <class Kind>
Kind as(Shape s) {
    Kind k;
    static_cast<Shape&>(k) = std::move(s);
    return k;
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

std::string describeKind(const Shape& s);

// Rounded shapes add their convex radius to the repr.
std::string describe(const Shape& s) {
    std::string text = describeKind(s);
    if (s.convexRadius() > 0) text.insert(text.size() - 1, ", convex_radius=" + number(s.convexRadius()));
    return text;
}

std::string describeKind(const Shape& s) {
    switch (s.type()) {
        case ShapeType::Sphere: return "Sphere(" + number(s.radius()) + ")";
        case ShapeType::Box: return "Box(" + reprVec3(s.halfExtents()) + ")";
        case ShapeType::Capsule: return "Capsule(" + number(s.radius()) + ", " + number(s.halfHeight()) + ")";
        case ShapeType::Cylinder: return "Cylinder(" + number(s.radius()) + ", " + number(s.halfHeight()) + ")";
        case ShapeType::ConvexHull: return "ConvexHull(<" + std::to_string(s.hull().vertices.size()) + " vertices>)";
        case ShapeType::Plane: return "Plane(" + reprVec3(s.planeNormal()) + ", " + number(s.planeOffset()) + ")";
        case ShapeType::Mesh:
            return "Mesh(<" + std::to_string(s.mesh().vertices.size()) + " vertices, " +
                   std::to_string(s.mesh().triangles.size()) + " triangles>)";
        case ShapeType::Compound: return "Compound(<" + std::to_string(s.children().size()) + " children>)";
        case ShapeType::HeightField:
            return "HeightField(<" + std::to_string(s.heightField().rows) + " x " + std::to_string(s.heightField().columns) +
                   " samples>, (" + number(s.heightField().spacingX) + ", " + number(s.heightField().spacingZ) + "))";
    }
    return "Shape()";
}

std::vector<std::array<std::uint32_t, 3>> toTriangles(py::handle value) {
    auto a = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || value.is_none() || a.ndim() != 2 || a.shape(1) != 3) {
        PyErr_Clear();
        throw py::type_error("argument 'triangles': expected an (m, 3) array of vertex indices");
    }
    std::vector<std::array<std::uint32_t, 3>> out(static_cast<std::size_t>(a.shape(0)));
    const long long* d = a.data();
    for (std::size_t i = 0; i < out.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            const long long v = d[3 * i + k];
            if (v < 0 || v > 0xFFFFFFFELL) fail("mesh: triangles[" + std::to_string(i) + "] has a negative or too large index");
            out[i][k] = static_cast<std::uint32_t>(v);
        }
    return out;
}

}  // namespace

// The scene-file description of a shape (save_scene of a world built in Python).
ShapeDesc describeShape(const Shape& s) {
    ShapeDesc d;
    d.type = s.type();
    d.convexRadius = s.convexRadius();
    switch (s.type()) {
        case ShapeType::Sphere: d.radius = s.radius(); break;
        case ShapeType::Box: d.halfExtents = s.halfExtents(); break;
        case ShapeType::Capsule:
        case ShapeType::Cylinder: d.radius = s.radius(), d.halfHeight = s.halfHeight(); break;
        case ShapeType::ConvexHull: d.points = s.hull().vertices; break;
        case ShapeType::Plane: d.normal = s.planeNormal(), d.offset = s.planeOffset(); break;
        case ShapeType::Mesh:
            d.vertices = s.mesh().vertices;
            d.triangles = s.mesh().triangles;
            break;
        case ShapeType::Compound:
            for (const CompoundChild& c : s.children()) d.children.push_back({describeShape(c.shape), c.transform.p, c.transform.q});
            break;
        case ShapeType::HeightField: {
            const HeightField& h = s.heightField();
            d.rows = h.rows, d.columns = h.columns, d.spacingX = h.spacingX, d.spacingZ = h.spacingZ;
            d.heights = h.heights;
            d.holes = h.holes;
            break;
        }
    }
    return d;
}

py::object shapeToPython(const Shape& s) {
    switch (s.type()) {
        case ShapeType::Sphere: return py::cast(as<SphereShape>(s));
        case ShapeType::Box: return py::cast(as<BoxShape>(s));
        case ShapeType::Capsule: return py::cast(as<CapsuleShape>(s));
        case ShapeType::Cylinder: return py::cast(as<CylinderShape>(s));
        case ShapeType::ConvexHull: return py::cast(as<HullShape>(s));
        case ShapeType::Plane: return py::cast(as<PlaneShape>(s));
        case ShapeType::Mesh: return py::cast(as<MeshShape>(s));
        case ShapeType::Compound: return py::cast(as<CompoundShape>(s));
        case ShapeType::HeightField: return py::cast(as<HeightFieldShape>(s));
    }
    return py::cast(s);
}

void bindShapes(py::module_& m) {
    py::class_<Shape>(m, "Shape",
                      "A collision shape: an immutable value, cheap to share between bodies. Make one with Sphere, "
                      "Box, Capsule, Cylinder, ConvexHull, Plane, Mesh or Compound.")
        .def_property_readonly("type", [](const Shape& s) { return std::string(toString(s.type())); },
                               "The kind: 'sphere', 'box', 'capsule', 'cylinder', 'convex_hull', 'plane', 'mesh', 'compound', "
                               "'heightfield'.")
        .def_property_readonly("static_only", &Shape::staticOnly, "True for planes, meshes, heightfields and compounds holding them.")
        .def_property_readonly("volume", &Shape::volume, "m^3 (planes and meshes: an error).")
        .def(
            "mass_properties",
            [](const Shape& s, Real density) {
                const MassProperties mp = s.massProperties(density);
                return py::dict(py::arg("mass") = mp.mass, py::arg("center_of_mass") = fromVec3(mp.centerOfMass),
                                py::arg("inertia") = fromMat3(mp.inertia));
            },
            py::arg("density"), "Mass, centre of mass and inertia about it (shape axes) at a density (kg/m^3), as a dict.")
        .def(
            "local_bounds",
            [](const Shape& s) {
                const AABB b = s.localBounds();
                return py::make_tuple(fromVec3(b.min), fromVec3(b.max));
            },
            "(min, max) corners of the bounds in the shape's frame.")
        .def("__repr__", [](const Shape& s) { return "fulcrum." + describe(s); })
        .def_property_readonly("convex_radius", &Shape::convexRadius,
                               "The rounding radius of a rounded box, cylinder or hull (m; 0 for plain shapes): the "
                               "shape is its core swept by a sphere of this radius (docs/shapes.md).")
        // Scaled shapes (docs/shapes.md): a new shape of the kind the scale leaves.
        .def(
            "scaled",
            [](const Shape& s, py::object scale) {
                const Vec3 v = py::isinstance<py::float_>(scale) || py::isinstance<py::int_>(scale)
                                   ? Vec3::splat(scale.cast<Real>())
                                   : toVec3(scale, "scale");
                return shapeToPython(Shape::scaled(s, v));
            },
            py::arg("scale"),
            "This shape scaled about its origin by a number or (sx, sy, sz) (negative mirrors), baked into a new shape: "
            "a box stays a box, a hull a hull; spheres and capsules need a uniform scale, cylinders sx == sz.");

    py::class_<SphereShape, Shape>(m, "Sphere", "A sphere of a radius (m), centred on the body origin.")
        .def(py::init([](Real radius) { return as<SphereShape>(Shape::sphere(radius)); }), py::arg("radius"))
        .def_property_readonly("radius", &Shape::radius);
    py::class_<BoxShape, Shape>(m, "Box", "A box of half extents (x, y, z) in metres, centred on the body origin.")
        .def(py::init([](py::object half, Real convexRadius) {
                 return as<BoxShape>(Shape::roundedBox(toVec3(half, "half_extents"), convexRadius));
             }),
             py::arg("half_extents"), py::arg("convex_radius") = 0)
        .def_property_readonly("half_extents", [](const Shape& s) { return fromVec3(s.halfExtents()); });
    py::class_<CapsuleShape, Shape>(m, "Capsule",
                                    "A capsule along local y: the segment from -half_height to +half_height swept by a sphere of radius.")
        .def(py::init([](Real radius, Real halfHeight) { return as<CapsuleShape>(Shape::capsule(radius, halfHeight)); }),
             py::arg("radius"), py::arg("half_height"))
        .def_property_readonly("radius", &Shape::radius)
        .def_property_readonly("half_height", &Shape::halfHeight);
    py::class_<CylinderShape, Shape>(m, "Cylinder", "A cylinder along local y, from -half_height to +half_height.")
        .def(py::init([](Real radius, Real halfHeight, Real convexRadius) {
                 return as<CylinderShape>(Shape::roundedCylinder(radius, halfHeight, convexRadius));
             }),
             py::arg("radius"), py::arg("half_height"), py::arg("convex_radius") = 0)
        .def_property_readonly("radius", &Shape::radius)
        .def_property_readonly("half_height", &Shape::halfHeight);
    py::class_<HullShape, Shape>(m, "ConvexHull",
                                 "The convex hull of a point cloud ((n, 3), at least 4 points not all in a plane).")
        .def(py::init([](py::object points, Real convexRadius) {
                 const std::vector<Vec3> p = toVec3List(points, "points");
                 return as<HullShape>(Shape::roundedConvexHull(p, convexRadius));
             }),
             py::arg("points"), py::arg("convex_radius") = 0)
        .def_property_readonly("vertices", [](const Shape& s) { return fromVec3List(s.hull().vertices); },
                               "The hull's vertices, (k, 3).");
    py::class_<PlaneShape, Shape>(m, "Plane",
                                  "The infinite plane {p : normal . p = offset}, solid on the side opposite the normal. Static bodies only.")
        .def(py::init([](py::object normal, Real offset) { return as<PlaneShape>(Shape::plane(toVec3(normal, "normal"), offset)); }),
             py::arg("normal") = py::make_tuple(0, 1, 0), py::arg("offset") = 0)
        .def_property_readonly("normal", [](const Shape& s) { return fromVec3(s.planeNormal()); })
        .def_property_readonly("offset", &Shape::planeOffset);
    py::class_<MeshShape, Shape>(m, "Mesh",
                                 "A static triangle mesh: vertices (n, 3) and triangles (m, 3) of indices, counter-clockwise seen from the front.")
        .def(py::init([](py::object vertices, py::object triangles) {
                 const std::vector<Vec3> v = toVec3List(vertices, "vertices");
                 const auto t = toTriangles(triangles);
                 return as<MeshShape>(Shape::mesh(v, t));
             }),
             py::arg("vertices"), py::arg("triangles"))
        .def_property_readonly("vertices", [](const Shape& s) { return fromVec3List(s.mesh().vertices); })
        .def_property_readonly("triangles", [](const Shape& s) {
            const auto& t = s.mesh().triangles;
            py::array_t<std::uint32_t> a({static_cast<py::ssize_t>(t.size()), py::ssize_t(3)});
            std::uint32_t* d = a.mutable_data();
            for (const auto& tri : t) *d++ = tri[0], *d++ = tri[1], *d++ = tri[2];
            return a;
        });
    py::class_<HeightFieldShape, Shape>(
        m, "HeightField",
        "A static heightfield: heights (rows, columns), sample (r, c) at local (c * dx, heights[r, c], r * dz) with "
        "spacing (dx, dz) in metres; holes: cell indices r * (columns - 1) + c without collision. Each cell is split "
        "along its diagonal from sample (r, c) to (r + 1, c + 1). Static bodies only.")
        .def(py::init([](py::object heights, py::object spacing, py::object holes) {
                 auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(heights);
                 if (!a || heights.is_none() || a.ndim() != 2) {
                     PyErr_Clear();
                     throw py::type_error("argument 'heights': expected a 2-d array (rows, columns) of heights");
                 }
                 // Counts and values go to Shape::heightField unchecked: it names the field that is wrong.
                 const auto rows = static_cast<std::uint64_t>(a.shape(0)), columns = static_cast<std::uint64_t>(a.shape(1));
                 const auto clampCount = [](std::uint64_t n) { return static_cast<std::uint32_t>(std::min<std::uint64_t>(n, 0xFFFFFFFFu)); };
                 std::vector<Real> h(static_cast<std::size_t>(a.size()));
                 for (std::size_t i = 0; i < h.size(); ++i) h[i] = static_cast<Real>(a.data()[i]);
                 Real dx = 0, dz = 0;
                 if (py::isinstance<py::float_>(spacing) || py::isinstance<py::int_>(spacing)) {
                     dx = dz = spacing.cast<Real>();
                 } else {
                     const auto sp = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(spacing);
                     if (!sp || spacing.is_none() || sp.ndim() != 1 || sp.shape(0) != 2) {
                         PyErr_Clear();
                         throw py::type_error("argument 'spacing': expected (dx, dz) or a number");
                     }
                     dx = static_cast<Real>(sp.data()[0]), dz = static_cast<Real>(sp.data()[1]);
                 }
                 std::vector<std::uint32_t> cells;
                 if (!holes.is_none()) {
                     for (py::handle v : py::iter(holes)) {
                         const long long cell = v.cast<long long>();
                         if (cell < 0 || cell > 0xFFFFFFFELL) fail("heightfield: holes has a negative or too large cell index");
                         cells.push_back(static_cast<std::uint32_t>(cell));
                     }
                 }
                 return as<HeightFieldShape>(Shape::heightField(clampCount(rows), clampCount(columns), dx, dz, h, cells));
             }),
             py::arg("heights"), py::arg("spacing") = py::make_tuple(1, 1), py::arg("holes") = py::none())
        .def_property_readonly("rows", [](const Shape& s) { return s.heightField().rows; })
        .def_property_readonly("columns", [](const Shape& s) { return s.heightField().columns; })
        .def_property_readonly("spacing", [](const Shape& s) {
            return py::make_tuple(s.heightField().spacingX, s.heightField().spacingZ);
        })
        .def_property_readonly("heights", [](const Shape& s) {
            const HeightField& h = s.heightField();
            py::array_t<Real> a({static_cast<py::ssize_t>(h.rows), static_cast<py::ssize_t>(h.columns)});
            std::copy(h.heights.begin(), h.heights.end(), a.mutable_data());
            return a;
        })
        .def_property_readonly("holes", [](const Shape& s) { return s.heightField().holes; });
    py::class_<CompoundShape, Shape>(m, "Compound",
                                     "Several shapes rigidly joined. children: a list of Shape, (shape, position) or "
                                     "(shape, position, orientation (w, x, y, z)).")
        .def(py::init([](py::iterable children) {
                 std::vector<CompoundChild> list;
                 std::size_t i = 0;
                 for (py::handle child : children) {
                     const std::string where = "children[" + std::to_string(i++) + "]";
                     CompoundChild c;
                     if (py::isinstance<Shape>(child)) {
                         c.shape = child.cast<Shape>();
                     } else if (py::isinstance<py::tuple>(child) || py::isinstance<py::list>(child)) {
                         const py::sequence seq = py::reinterpret_borrow<py::sequence>(child);
                         if (seq.size() < 1 || seq.size() > 3 || !py::isinstance<Shape>(seq[0]))
                             throw py::type_error("argument '" + where + "': expected a Shape, (shape, position) or (shape, position, orientation)");
                         c.shape = seq[0].cast<Shape>();
                         if (seq.size() > 1) c.transform.p = toVec3(seq[1], "position");
                         if (seq.size() > 2) {
                             // normalize() turns a zero or NaN quaternion into the identity:
                             // hand those on as given, for Shape::compound to refuse.
                             const Quat q = toQuat(seq[2], "orientation");
                             c.transform.q = length(q) > Real(0) ? normalize(q) : q;
                         }
                     } else {
                         throw py::type_error("argument '" + where + "': expected a Shape, (shape, position) or (shape, position, orientation)");
                     }
                     list.push_back(std::move(c));
                 }
                 return as<CompoundShape>(Shape::compound(list));
             }),
             py::arg("children"))
        // Convex decomposition (docs/shapes.md): a closed mesh as a compound of hulls.
        .def_static(
            "from_mesh",
            [](py::object vertices, py::object triangles, int maxHulls, Real maxConcavity, int resolution) {
                const std::vector<Vec3> v = toVec3List(vertices, "vertices");
                const auto t = toTriangles(triangles);
                ConvexDecompositionOptions o;
                o.maxHulls = maxHulls, o.maxConcavity = maxConcavity, o.resolution = resolution;
                return as<CompoundShape>(Shape::convexDecomposition(v, t, o));
            },
            py::arg("vertices"), py::arg("triangles"), py::arg("max_hulls") = 32, py::arg("max_concavity") = 0.01,
            py::arg("resolution") = 64,
            "A compound of convex hulls approximating the solid a closed triangle mesh bounds (counter-clockwise "
            "seen from outside), for a concave dynamic body: Shape::convexDecomposition, docs/shapes.md.")
        .def_property_readonly("children", [](const Shape& s) {
            py::list out;
            for (const CompoundChild& c : s.children())
                out.append(py::make_tuple(shapeToPython(c.shape), fromVec3(c.transform.p), fromQuat(c.transform.q)));
            return out;
        }, "[(shape, position, orientation), ...]");
}

}  // namespace fulcrum::python
