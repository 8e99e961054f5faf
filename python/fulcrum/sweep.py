"""``python3 -m fulcrum sweep``: a parameter grid run as a batch, locally or on Dask.

    python3 -m fulcrum sweep SCENE.json --set "bodies[ball].restitution=0:1:11" [--set ...]
        --steps N [--scheduler tcp://HOST:PORT] [--threads T] [--chunk-size K] --out results.csv [--summary]

The grid holds every combination of the --set values, the last --set varying
fastest; the CSV has one row per world and dynamic body at the end of the run:
``world,<set paths...>,body,x,y,z,vx,vy,vz`` (numbers as Python's repr of the
engine's values, so they read back exactly). Bad --set paths or values are an
error naming them (exit status 2) before anything runs.
"""

from __future__ import annotations

import argparse
import csv
import itertools
import json
import os
import sys

from . import _fulcrum
from .batch import scene_text
from .distributed import BatchSpec, run, run_local

COLUMNS = ("x", "y", "z", "vx", "vy", "vz")
# The most worlds one sweep's grid may hold (docs/reliability.md, "Bad input"):
# a typo such as 0:1:1000000000 is refused before any list of values is made.
MAX_WORLDS = 1_000_000


class SweepError(Exception):
    """A bad command line: printed as ``fulcrum sweep: error: ...``, exit status 2."""


def _number(token: str, setting: str):
    try:
        value = json.loads(token)
    except ValueError:
        value = None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SweepError(f"--set '{setting}': '{token}' is not a number")
    return value


def _list_value(token: str, setting: str):
    """A value of a list: a number, or true / false (a boolean setting such as
    world.push_out_grown_overlaps or world.sleeping)."""
    if token in ("true", "false"):
        return token == "true"
    try:
        return _number(token, setting)
    except SweepError:
        raise SweepError(f"--set '{setting}': '{token}' is not a number, true or false") from None


def parse_set(setting: str) -> tuple[str, list]:
    """'PATH=a:b:n' (n values from a to b, ends included) or 'PATH=v1,v2,...'
    (numbers, or true / false) -> (path, values)."""
    path, eq, spec = setting.partition("=")
    path = path.strip()
    if not eq or not path or not spec.strip():
        raise SweepError(f"--set '{setting}': expected PATH=a:b:n or PATH=v1,v2,...")
    spec = spec.strip()
    if ":" in spec:
        parts = spec.split(":")
        if len(parts) != 3:
            raise SweepError(f"--set '{setting}': a range is a:b:n (from a to b in n values)")
        a, b = _number(parts[0], setting), _number(parts[1], setting)
        n = _number(parts[2], setting)
        if not isinstance(n, int) or n < 1:
            raise SweepError(f"--set '{setting}': the count n of a:b:n must be a whole number >= 1, got {parts[2]}")
        if n > MAX_WORLDS:
            raise SweepError(f"--set '{setting}': the count n of a:b:n must be at most {MAX_WORLDS}, got {n}")
        if n == 1:
            return path, [a]
        values = [a + (b - a) * i / (n - 1) for i in range(n)]
        values[-1] = b  # the end exactly, whatever the rounding
        if isinstance(a, int) and isinstance(b, int) and all(float(v).is_integer() for v in values):
            values = [int(v) for v in values]
        else:
            values = [float(v) for v in values]
        return path, values
    return path, [_list_value(t.strip(), setting) for t in spec.split(",")]


def grid(sets: list[tuple[str, list]]) -> list[tuple]:
    """Every combination, the last set varying fastest."""
    count = 1
    for _, values in sets:
        count *= len(values)
    if count > MAX_WORLDS:
        raise SweepError(f"the grid holds {count} worlds, at most {MAX_WORLDS}: split the sweep")
    return list(itertools.product(*(values for _, values in sets)))


def _progress_bar(stream):
    """A one-line bar on a terminal; nothing in a pipe or a file."""
    if not stream.isatty():
        return None
    last = [-1]

    def show(done, total):
        percent = 100 * done // max(total, 1)
        if percent == last[0]:
            return
        last[0] = percent
        filled = 30 * done // max(total, 1)
        stream.write(f"\rsweep [{'#' * filled}{'.' * (30 - filled)}] {percent:3d}%")
        if done >= total:
            stream.write("\n")
        stream.flush()

    return show


def _cell(value) -> str:
    """A --set value in the CSV: a number as Python's repr, a boolean as in JSON."""
    return json.dumps(value) if isinstance(value, bool) else repr(value)


def rows(points, paths, results):
    """CSV rows: one per world and dynamic body."""
    for w, (point, result) in enumerate(zip(points, results)):
        for b, (name, kind) in enumerate(zip(result.body_names, result.body_types)):
            if kind != "dynamic":
                continue
            p, v = result.positions[b], result.linear_velocities[b]
            yield ([w] + [_cell(x) for x in point] + [name or f"body{b}"]
                   + [repr(float(x)) for x in p] + [repr(float(x)) for x in v])


def summary(table, out):
    out.write(f"{'column':>8} {'min':>24} {'max':>24} {'mean':>24}\n")
    for k, column in enumerate(COLUMNS):
        values = [float(r[-6 + k]) for r in table]
        if not values:
            continue
        out.write(f"{column:>8} {min(values)!r:>24} {max(values)!r:>24} {sum(values) / len(values)!r:>24}\n")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python3 -m fulcrum sweep",
                                     description="Runs a scene over the grid of every --set combination.")
    parser.add_argument("scene", help="scene file (docs/scene-format.md)")
    parser.add_argument("--set", action="append", default=[], dest="sets", metavar="PATH=VALUES",
                        help='a scene path and its values: "bodies[ball].restitution=0:1:11" or "...=0.1,0.2,0.5"')
    parser.add_argument("--steps", type=int, default=None, help="steps per world (default: the scene's steps)")
    parser.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT", help="run on this Dask scheduler")
    parser.add_argument("--threads", type=int, default=1, help="threads of a local run (default 1)")
    parser.add_argument("--chunk-size", type=int, default=None, help="worlds per Dask task (default: ~4 tasks per worker)")
    parser.add_argument("--out", required=True, help="the CSV file to write")
    parser.add_argument("--summary", action="store_true", help="print min/max/mean of each output column")
    args = parser.parse_args(argv)

    try:
        if not args.sets:
            raise SweepError("give at least one --set PATH=VALUES")
        if args.steps is not None and args.steps < 0:
            raise SweepError(f"--steps must be >= 0, got {args.steps}")
        if args.threads < 1:
            raise SweepError(f"--threads must be >= 1, got {args.threads}")
        if args.chunk_size is not None and args.chunk_size < 1:
            raise SweepError(f"--chunk-size must be >= 1, got {args.chunk_size}")
        # Checked before the run, not after it: a sweep's results must have somewhere to go.
        if os.path.isdir(args.out):
            raise SweepError(f"--out {args.out}: is a directory, give a CSV file name")
        if not os.path.isdir(os.path.dirname(os.path.abspath(args.out))):
            raise SweepError(f"--out {args.out}: the directory does not exist")
        sets = [parse_set(s) for s in args.sets]
        paths = [p for p, _ in sets]
        if len(set(paths)) != len(paths):
            raise SweepError("the same path is given to --set twice")
        text, name = scene_text(args.scene)
        points = grid(sets)
        # Each value alone first, so an error names the --set that is wrong.
        for (path, values), setting in zip(sets, args.sets):
            for value in values:
                try:
                    _fulcrum._scene_run_settings(text, name, [(path, json.dumps(value))])
                except _fulcrum.Error as e:
                    raise SweepError(f"--set '{setting}': {e}") from None
        spec = BatchSpec(text, overrides=[dict(zip(paths, p)) for p in points], steps=args.steps, source_name=name)
    except SweepError as e:
        print(f"fulcrum sweep: error: {e}", file=sys.stderr)
        return 2
    except _fulcrum.Error as e:
        print(f"fulcrum sweep: error: {e}", file=sys.stderr)
        return 2

    progress = _progress_bar(sys.stderr)
    try:
        if args.scheduler:
            from dask.distributed import Client

            try:
                client = Client(args.scheduler)
            except OSError as e:  # unreachable, refused, timed out
                print(f"fulcrum sweep: error: --scheduler {args.scheduler}: {e}", file=sys.stderr)
                return 1
            with client:
                results = run(spec, client, chunk_size=args.chunk_size, progress=progress)
        else:
            results = run_local(spec, threads=args.threads, progress=progress)
    except _fulcrum.Error as e:  # combinations refused together, or a world that failed
        print(f"fulcrum sweep: error: {e}", file=sys.stderr)
        return 2 if isinstance(e, _fulcrum.SceneError) else 1

    table = list(rows(points, paths, results))
    try:
        with open(args.out, "w", newline="", encoding="utf-8") as f:
            writer = csv.writer(f, lineterminator="\n")
            writer.writerow(["world", *paths, "body", *COLUMNS])
            writer.writerows(table)
    except OSError as e:
        print(f"fulcrum sweep: error: --out {args.out}: cannot write ({e.strerror})", file=sys.stderr)
        return 1
    if args.summary:
        summary(table, sys.stdout)
    return 0
