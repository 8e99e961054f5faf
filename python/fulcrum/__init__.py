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
    ParticleSystem,
    Compound,
    Contact,
    ConvexHull,
    Cylinder,
    Error,
    Joint,
    Mesh,
    NumericalError,
    Plane,
    RayHit,
    Recorder,
    SceneError,
    Shape,
    ShapeHit,
    Sphere,
    Spring,
    World,
    load_snapshot,
)

__all__ = [
    "Body", "BodyKinematics", "Box", "Capsule", "Compound", "Contact", "ConvexHull", "Cylinder", "Error", "Joint",
    "Mesh", "NumericalError", "ParticleSystem", "Plane", "RayHit", "Recorder", "SceneError", "Shape", "ShapeHit",
    "Sphere", "Spring", "World", "load_scene", "load_snapshot", "real_dtype",
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
