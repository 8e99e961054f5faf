"""Fulcrum, a 3D rigid-body physics engine, from Python.

    import fulcrum
    w = fulcrum.World(gravity=(0, -9.81, 0))
    w.create_body(shape=fulcrum.Plane((0, 1, 0), 0), type="static")
    ball = w.create_body(shape=fulcrum.Sphere(0.5), position=(0, 10, 0), mass=1.0, name="ball")
    w.step(1 / 60, steps=120)
    print(ball.position, w.positions())

Everything runs in the C++ engine (the compiled module fulcrum._fulcrum); this
package adds scene loading from dicts and JSON text and World.run. Arrays are
float64 NumPy arrays holding the engine's float32 numbers exactly. See
docs/python.md for the whole API.
"""

from __future__ import annotations

import json as _json
import os as _os

from . import _fulcrum
from ._fulcrum import (  # noqa: F401  (re-exported)
    Body,
    BodyKinematics,
    Box,
    Capsule,
    Character,
    ParticleSystem,
    Compound,
    Contact,
    ConvexHull,
    Cylinder,
    Error,
    HeightField,
    Joint,
    Mesh,
    NumericalError,
    Plane,
    RayHit,
    Recorder,
    Robot,
    SceneError,
    Shape,
    ShapeHit,
    Sphere,
    Spring,
    Vehicle,
    World,
    load_snapshot,
    load_urdf,
)
from .batch import Batch  # noqa: F401  (re-exported)

__all__ = [
    "Batch", "Body", "BodyKinematics", "Box", "Capsule", "Character", "Compound", "Contact", "ConvexHull",
    "Cylinder", "Error", "HeightField", "Joint", "Mesh", "NumericalError", "ParticleSystem", "Plane", "RayHit",
    "Recorder", "Robot", "SceneError", "Shape", "ShapeHit", "Sphere", "Spring", "Vehicle", "World", "load_scene",
    "load_snapshot", "load_urdf", "real_dtype",
]

__version__ = "0.1.0"

# Tracebacks and reprs say fulcrum.Error, not fulcrum._fulcrum.Error.
for _name in __all__:
    _obj = globals().get(_name)
    if isinstance(_obj, type) and _obj.__module__ == _fulcrum.__name__:
        _obj.__module__ = __name__

#: The engine's floating-point type (``Real`` in C++): the arrays the binding
#: returns are float64, holding values of this type exactly.
real_dtype = "float32" if _fulcrum.real_bytes == 4 else "float64"


def _parameters(doc: str, name: str):
    """[(parameter, type)] of the first overload in a pybind11 docstring."""
    line = next((l for l in (doc or "").splitlines() if l.lstrip().startswith(name + "(")), "")
    inner, depth, params, current = line[line.find("(") + 1:], 0, [], ""
    for ch in inner:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            if depth == 0:
                break
            depth -= 1
        if ch == "," and depth == 0:
            params.append(current)
            current = ""
        else:
            current += ch
    params.append(current)
    out = []
    for p in params:
        p = p.split("=")[0].strip()
        if ":" in p:
            pname, ptype = (x.strip() for x in p.split(":", 1))
            out.append((pname, ptype))
        elif p == "*":
            out.append(("*", ""))
    return out


_CHECKS = {"float": lambda v: isinstance(v, (int, float)) or hasattr(v, "__float__"),
           "int": lambda v: isinstance(v, int) or hasattr(v, "__index__"),
           "bool": lambda v: isinstance(v, bool) or hasattr(v, "__bool__"),
           "str": lambda v: isinstance(v, str)}


def _explain(name: str, doc: str, args, kwargs):
    """pybind11 says which overloads exist; this names the argument that fits none."""
    params = [p for p in _parameters(doc, name) if p[0] != "*"]
    given = dict(zip((p[0] for p in params), args))
    given.update(kwargs)
    for pname, ptype in params:
        check = _CHECKS.get(ptype)
        if pname in given and check and not check(given[pname]):
            return f"{name}(): argument '{pname}': expected {ptype}, got {type(given[pname]).__name__}"
    return None


def _name_bad_arguments(cls, method: str):
    import functools

    original = getattr(cls, method)
    label = cls.__name__ if method == "__init__" else method

    @functools.wraps(original)
    def checked(*args, **kwargs):
        try:
            return original(*args, **kwargs)
        except TypeError as e:
            if "incompatible function arguments" not in str(e) and "incompatible constructor arguments" not in str(e):
                raise
            better = _explain("__init__" if method == "__init__" else method, original.__doc__, args, kwargs)
            raise TypeError(better.replace("__init__()", label + "()") if better else str(e)) from None

    setattr(cls, method, checked)


# Wrong Python types get a TypeError naming the argument (pybind11's own message
# lists the signatures). Not on the per-step calls (step, the arrays), whose
# overhead is measured (docs/benchmarks.md).
for _cls in (World, Body, Joint, Spring, ParticleSystem, Character, Vehicle, Recorder, Sphere, Box, Capsule, Cylinder,
             ConvexHull, Plane, Mesh, Compound, HeightField):
    for _method in list(vars(_cls)):
        if _method == "__init__" or _method.startswith(("create_", "overlap_", "ray_cast", "shape_cast", "set_",
                                                         "apply_", "destroy_", "find_", "mass_properties")):
            if callable(getattr(_cls, _method)):
                _name_bad_arguments(_cls, _method)


def _name_bad_property_values(cls):
    """Property setters: a TypeError naming the property (pybind11 says 'arg1')."""
    import re

    for pname, attr in list(vars(cls).items()):
        if not isinstance(attr, property) or attr.fset is None:
            continue
        # "(arg0: fulcrum._fulcrum.Body, arg1: float) -> None": the value is the last.
        types = re.findall(r"arg\d+: ([\w.]+)", attr.fset.__doc__ or "")
        expected = types[-1] if len(types) > 1 else "another type"

        def checked(self, value, _fset=attr.fset, _label=f"{cls.__name__}.{pname}", _expected=expected):
            try:
                _fset(self, value)
            except TypeError as e:
                if "incompatible function arguments" not in str(e):
                    raise
                raise TypeError(f"{_label}: expected {_expected}, got {type(value).__name__}") from None

        setattr(cls, pname, property(attr.fget, checked, None, attr.__doc__))


for _cls in (World, Body, Joint):
    _name_bad_property_values(_cls)


def load_scene(source, *, source_name: str | None = None) -> World:
    """A World built from a scene (docs/scene-format.md).

    ``source`` is a path (str or os.PathLike) to a scene file, a dict in the
    scene format, or the JSON text of one (a str starting with ``{``). Bad
    input raises fulcrum.Error (a SceneError) naming the file, the path in the
    document and the reason. The world's ``scene_dt`` and ``scene_steps`` are
    the scene's ``dt`` and ``steps``; ``World.run()`` steps them.
    """
    if isinstance(source, dict):
        return _fulcrum._load_scene_text(_json.dumps(source), source_name or "<dict>")
    if isinstance(source, str) and source.lstrip().startswith("{"):
        return _fulcrum._load_scene_text(source, source_name or "<string>")
    if isinstance(source, (str, _os.PathLike)):
        return _fulcrum._load_scene_file(_os.fspath(source))
    raise TypeError(
        f"argument 'source': expected a path, a dict or JSON text, got {type(source).__name__}")


def _run(self: World, steps: int | None = None, dt: float | None = None) -> World:
    """Steps the scene's run: ``steps`` (default ``scene_steps``) steps of ``dt``
    (default ``scene_dt``), as ``fulcrum run`` does, with the GIL released.
    Returns the world."""
    self.step(self.scene_dt if dt is None else dt, steps=self.scene_steps if steps is None else steps)
    return self


World.run = _run
