"""Many worlds on a Dask cluster (docs/scale-out.md).

    from dask.distributed import Client
    import fulcrum.distributed as fd
    spec = fd.BatchSpec("ball.json", overrides=[{"bodies[ball].restitution": r} for r in rs], steps=300)
    results = fd.run(spec, client=Client("tcp://scheduler:8786"))   # == fd.run_local(spec)

The worlds travel in chunks: a task gets the scene as JSON text and its
chunk's overrides, runs them as a fulcrum.Batch on one thread, and returns
arrays. A task depends on nothing but its arguments, so when a worker dies
Dask simply computes the lost chunks again elsewhere: a lost worker costs
time, never results. Results come back in world order, bit for bit those of
run_local (a world's numbers do not depend on its batch or its thread).
Dask (Debian's python3-distributed) is imported only by run().
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Optional

from . import _fulcrum
from .batch import _override_pairs, scene_text

__all__ = ["BatchSpec", "WorldResult", "run", "run_local"]


@dataclass
class BatchSpec:
    """``count`` worlds of one scene, world i with ``overrides[i]`` (as for
    fulcrum.Batch), each run ``steps`` steps of ``dt`` (default: the scene's
    own ``steps`` and ``dt``, after the overrides)."""
    scene: Any
    count: Optional[int] = None
    overrides: Any = None
    steps: Optional[int] = None
    dt: Optional[float] = None
    source_name: Optional[str] = None


@dataclass
class WorldResult:
    """One world at the end of its run: (bodies, 3) arrays (orientations (bodies, 4))."""
    positions: Any
    orientations: Any
    linear_velocities: Any
    angular_velocities: Any
    body_names: list = field(default_factory=list)
    body_types: list = field(default_factory=list)


@dataclass
class _Work:
    """The worlds of a run, read and checked: chunks are cut from it."""
    texts: list        # per world: JSON text of its scene
    names: list        # per world: name for errors
    overrides: list    # per world: [(path, JSON value)]
    dts: list
    steps: list


def _plan(work, steps: Optional[int], dt: Optional[float]) -> _Work:
    """Reads every world's scene (so every error shows before anything runs)."""
    if isinstance(work, BatchSpec):
        text, name = scene_text(work.scene, work.source_name)
        o = work.overrides
        if isinstance(o, dict):
            sets = [_override_pairs(o, 0)] * (1 if work.count is None else work.count)
        else:
            sets = [_override_pairs(x, i) for i, x in enumerate(o or [])]
        count = work.count if work.count is not None else (len(sets) or 1)
        if sets and len(sets) != count:
            raise _fulcrum.Error(f"BatchSpec: {len(sets)} overrides for count={count} worlds (give one per world)")
        sets = sets or [[]] * count
        texts, names = [text] * count, [name] * count
        steps = work.steps if steps is None else steps
        dt = work.dt if dt is None else dt
    else:
        pairs = [scene_text(s) for s in work]
        texts, names = [t for t, _ in pairs], [n for _, n in pairs]
        sets = [[] for _ in texts]
    plan = _Work(texts, names, sets, [], [])
    cache = {}
    for text, name, o in zip(texts, names, sets):
        key = (id(text), tuple(o))
        if key not in cache:
            cache[key] = _fulcrum._scene_run_settings(text, name, o)
        scene_dt, scene_steps = cache[key]
        plan.dts.append(scene_dt if dt is None else float(dt))
        plan.steps.append(scene_steps if steps is None else int(steps))
    if any(s < 0 for s in plan.steps):
        raise _fulcrum.Error(f"steps must be >= 0, got {min(plan.steps)}")
    return plan


def _chunks(plan: _Work, size: int):
    """[(first, end)] of consecutive worlds with one scene text, dt and step count, at most ``size`` long."""
    out, first = [], 0
    for i in range(1, len(plan.texts) + 1):
        if (i == len(plan.texts) or i - first >= size or plan.texts[i] is not plan.texts[first]
                or plan.dts[i] != plan.dts[first] or plan.steps[i] != plan.steps[first]):
            out.append((first, i))
            first = i
    return out


def run_chunk(text: str, name: str, overrides: list, dt: float, steps: int, threads: int = 1,
              progress: Optional[Callable[[int], None]] = None) -> list:
    """Runs one chunk (worlds of one scene, each with its overrides) as a Batch;
    a pure function of its arguments (what a Dask task runs)."""
    core = _fulcrum._Batch(text, name, len(overrides), [list(o) for o in overrides], threads)
    done = 0
    slices = 20 if progress else 1
    for k in range(slices):
        n = steps * (k + 1) // slices - done
        core.step(dt, n)
        done += n
        if progress:
            progress(len(overrides) * n)
    p, q, v, w = core.positions(), core.orientations(), core.linear_velocities(), core.angular_velocities()
    names, types = core.body_names(0), core.body_types(0)
    return [WorldResult(p[i], q[i], v[i], w[i], names, types) for i in range(len(overrides))]


def run_local(work, *, threads: int = 1, steps: Optional[int] = None, dt: Optional[float] = None,
              progress: Optional[Callable[[int, int], None]] = None) -> list:
    """The same as run(), on this machine's threads: one Batch per group of
    worlds sharing a scene, dt and step count. ``progress(done, total)`` is
    called with world-steps."""
    plan = _plan(work, steps, dt)
    total, done = sum(plan.steps), 0
    results = []

    def tick(n):
        nonlocal done
        done += n
        progress(done, total)

    for first, end in _chunks(plan, len(plan.texts)):
        results += run_chunk(plan.texts[first], plan.names[first], plan.overrides[first:end], plan.dts[first],
                             plan.steps[first], threads, tick if progress else None)
    return results


def run(work, client, *, steps: Optional[int] = None, dt: Optional[float] = None, chunk_size: Optional[int] = None,
        retries: int = 2, progress: Optional[Callable[[int, int], None]] = None) -> list:
    """Runs ``work`` (a BatchSpec, or a list of scenes: paths, dicts or JSON
    text) on the Dask cluster of ``client`` (a dask.distributed.Client) and
    returns one WorldResult per world, in order, bit for bit equal to
    run_local(work). Every scene is read here first: errors are raised before
    anything is sent. ``chunk_size`` worlds go in one task (default: about
    four tasks per worker thread); ``retries`` re-runs a task that raised (a
    worker that died is handled by Dask itself: its tasks run again
    elsewhere). ``progress(done, total)`` counts worlds."""
    from dask.distributed import as_completed  # Debian: python3-distributed

    plan = _plan(work, steps, dt)
    n = len(plan.texts)
    if chunk_size is None:
        slots = max(1, sum(client.nthreads().values()))
        chunk_size = max(1, math.ceil(n / (4 * slots)))
    if chunk_size < 1:
        raise _fulcrum.Error(f"chunk_size must be >= 1, got {chunk_size}")
    chunks = _chunks(plan, chunk_size)
    # A scene's text is sent to the cluster once, not once per chunk. A fresh
    # key per run (hash=False): a key released by the previous run may still be
    # in the middle of being forgotten by the scheduler.
    texts = {}
    for first, _ in chunks:
        key = id(plan.texts[first])
        if key not in texts:
            texts[key] = client.scatter(plan.texts[first], hash=False)
    futures = [client.submit(run_chunk, texts[id(plan.texts[a])], plan.names[a], plan.overrides[a:b], plan.dts[a],
                             plan.steps[a], 1, pure=True, retries=retries)
               for a, b in chunks]
    if progress:
        done = 0
        size = {id(f): b - a for f, (a, b) in zip(futures, chunks)}
        for f in as_completed(futures):
            done += size[id(f)]
            progress(done, n)
    results = []
    for part in client.gather(futures):
        results += part
    return results
