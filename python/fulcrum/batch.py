"""fulcrum.Batch: N independent worlds stepped together (docs/scale-out.md).

    batch = fulcrum.Batch("scenes/ball.json", count=3,
                          overrides=[{"bodies[ball].restitution": r} for r in (0.2, 0.5, 0.8)], threads=2)
    batch.step(1 / 60, steps=120)
    batch.positions()          # (3, bodies, 3) float64

Each world steps on one thread, one world per task, so its numbers are bit for
bit those of the same world run alone, whatever the count and the threads.
"""

from __future__ import annotations

import json as _json
import os as _os

from . import _fulcrum

__all__ = ["Batch", "scene_text"]


def scene_text(source, source_name: str | None = None) -> tuple[str, str]:
    """(JSON text, name for errors) of a scene given as a path, a dict or JSON text."""
    if isinstance(source, dict):
        return _json.dumps(source), source_name or "<dict>"
    if isinstance(source, str) and source.lstrip().startswith("{"):
        return source, source_name or "<string>"
    if isinstance(source, (str, _os.PathLike)):
        path = _os.fspath(source)
        try:
            with open(path, encoding="utf-8") as f:
                return f.read(), source_name or path
        except OSError as e:
            raise _fulcrum.SceneError(f"{path}: cannot open file for reading ({e.strerror})") from None
        except UnicodeDecodeError as e:  # binary garbage, or another encoding
            raise _fulcrum.SceneError(f"{path}: not UTF-8 text at byte offset {e.start}: a scene file is JSON text") from None
    raise TypeError(f"argument 'scene': expected a path, a dict or JSON text, got {type(source).__name__}")


def _override_pairs(overrides: dict, index: int) -> list[tuple[str, str]]:
    if not isinstance(overrides, dict):
        raise TypeError(f"overrides[{index}]: expected a dict of scene paths to values, got {type(overrides).__name__}")
    pairs = []
    for path, value in overrides.items():
        if hasattr(value, "tolist"):  # NumPy scalars and arrays
            value = value.tolist()
        try:
            pairs.append((str(path), _json.dumps(value, allow_nan=False)))
        except (TypeError, ValueError) as e:
            raise _fulcrum.Error(f"overrides[{index}]: {path}: the value cannot be written as JSON ({e})") from None
    return pairs


class Batch:
    """N independent worlds stepped together on ``threads`` threads.

    ``scene``: a path, a dict or JSON text (``count`` worlds of it, each with
    its ``overrides[i]``: a dict of scene-file paths to values such as
    ``{"bodies[ball].restitution": 0.3, "world.gravity": [0, -1.6, 0]}``; a
    single dict applies to every world), or a list of scenes (one world each).
    Every world is read before any is built: a bad path or value raises
    fulcrum.SceneError naming it.
    """

    def __init__(self, scene, count: int | None = None, overrides=None, threads: int = 1, *,
                 source_name: str | None = None):
        if isinstance(scene, (list, tuple)):
            if overrides:
                raise TypeError("Batch: overrides apply to one scene; give them in the scenes of the list instead")
            if count is not None and count != len(scene):
                raise _fulcrum.Error(f"Batch: count={count} but {len(scene)} scenes were given")
            texts = [scene_text(s) for s in scene]
            self._core = _fulcrum._Batch([t for t, _ in texts], [n for _, n in texts], threads)
            return
        text, name = scene_text(scene, source_name)
        if isinstance(overrides, dict):
            sets = [_override_pairs(overrides, 0)] * (1 if count is None else count)
        else:
            sets = [_override_pairs(o, i) for i, o in enumerate(overrides or [])]
        if count is None:
            count = len(sets) if sets else 1
        if sets and len(sets) != count:
            raise _fulcrum.Error(f"Batch: {len(sets)} overrides for count={count} worlds (give one per world)")
        self._core = _fulcrum._Batch(text, name, count, sets, threads)

    def __len__(self) -> int:
        return len(self._core)

    def __repr__(self) -> str:
        return f"<fulcrum.Batch of {len(self)} worlds, {self.threads} threads>"

    @property
    def count(self) -> int:
        """Number of worlds."""
        return len(self._core)

    @property
    def threads(self) -> int:
        return self._core.threads

    @property
    def body_count(self) -> int:
        """Bodies per world (the same in every world, else fulcrum.Error)."""
        return self._core.body_count

    @property
    def joint_count(self) -> int:
        """Joints per world (the same in every world, else fulcrum.Error)."""
        return self._core.joint_count

    def body_names(self, world: int = 0) -> list[str]:
        """Names of world ``world``'s bodies, in array order."""
        return self._core.body_names(world)

    def body_types(self, world: int = 0) -> list[str]:
        """"static", "dynamic" or "kinematic" for each body of world ``world``."""
        return self._core.body_types(world)

    def step(self, dt: float, steps: int = 1) -> None:
        """Steps every world ``steps`` times by ``dt`` (the GIL released)."""
        self._core.step(dt, steps)

    def positions(self):
        """(count, bodies, 3) float64: body origins."""
        return self._core.positions()

    def orientations(self):
        """(count, bodies, 4) float64: quaternions (w, x, y, z)."""
        return self._core.orientations()

    def linear_velocities(self):
        """(count, bodies, 3) float64: velocities of the centres of mass."""
        return self._core.linear_velocities()

    def angular_velocities(self):
        """(count, bodies, 3) float64."""
        return self._core.angular_velocities()

    def set_linear_velocities(self, values) -> None:
        """From a (count, bodies, 3) array; static bodies are left alone."""
        self._core.set_linear_velocities(values)

    def set_angular_velocities(self, values) -> None:
        """From a (count, bodies, 3) array; static bodies are left alone."""
        self._core.set_angular_velocities(values)

    def apply_forces(self, values) -> None:
        """Forces (N) at the centres of mass for the next step, from a (count, bodies, 3) array."""
        self._core.apply_forces(values)

    def set_joint_motor_speeds(self, values) -> None:
        """Hinge and slider motor speeds from a (count, joints) array (other joints ignore theirs)."""
        self._core.set_joint_motor_speeds(values)

    def reset(self, world: int, snapshot: bytes | None = None) -> None:
        """World ``world`` back to its start, or to ``snapshot`` (bytes of
        Batch.snapshot() or World.save_snapshot())."""
        if snapshot is None:
            self._core.reset(world)
        else:
            self._core.reset(world, bytes(snapshot))

    def snapshot(self, world: int) -> bytes:
        """World ``world``'s whole state as bytes, for reset(world, snapshot)."""
        return self._core.snapshot(world)
