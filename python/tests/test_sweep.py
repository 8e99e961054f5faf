"""python3 -m fulcrum sweep (docs/scale-out.md): the grid, the CSV (equal bit for
bit to separate single-world runs), --summary, and the errors (exit status 2,
before anything runs)."""
import copy
import csv
import json
import os
import subprocess
import sys

import pytest

import fulcrum
from fulcrum import sweep

SCENE = {
    "world": {"dt": 0.01},
    "bodies": [
        {"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.2}, "mass": 1, "position": [0, 1.5, 0],
         "linear_velocity": [1, 0, 0]},
        {"name": "box", "shape": {"type": "box", "half_extents": [0.2, 0.2, 0.2]}, "mass": 2, "position": [2, 0.2, 0]},
    ],
}
STEPS = 80


@pytest.fixture
def scene_file(tmp_path):
    path = tmp_path / "ball.json"
    path.write_text(json.dumps(SCENE))
    return path


def run_sweep(*args, cwd=None):
    env = dict(os.environ)
    return subprocess.run([sys.executable, "-m", "fulcrum", "sweep", *map(str, args)], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=120)


def expected_rows(points):
    """The CSV rows of separate single-world runs, each scene edited by hand."""
    out = []
    for w, (restitution, friction) in enumerate(points):
        scene = copy.deepcopy(SCENE)
        scene["bodies"][1]["restitution"] = restitution
        scene["bodies"][1]["friction"] = friction
        world = fulcrum.load_scene(scene)
        world.step(world.scene_dt, steps=STEPS)
        for body in world.bodies():
            if body.type == "dynamic":
                out.append([str(w), repr(restitution), repr(friction), body.name]
                           + [repr(float(x)) for x in body.position] + [repr(float(x)) for x in body.linear_velocity])
    return out


def test_grid_order_and_values():
    path, values = sweep.parse_set("bodies[ball].restitution=0:1:5")
    assert path == "bodies[ball].restitution" and values == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert sweep.parse_set("world.substeps=2:8:4")[1] == [2, 4, 6, 8]
    assert sweep.parse_set("x=0.1,0.2,0.5")[1] == [0.1, 0.2, 0.5]
    assert sweep.grid([("a", [1, 2]), ("b", [3, 4, 5])]) == [(1, 3), (1, 4), (1, 5), (2, 3), (2, 4), (2, 5)]


def test_csv_equals_separate_runs_bit_for_bit(scene_file, tmp_path):
    out = tmp_path / "results.csv"
    r = run_sweep(scene_file, "--set", "bodies[ball].restitution=0:1:3", "--set", "bodies[ball].friction=0.1,0.9",
                  "--steps", STEPS, "--threads", 2, "--out", out, "--summary")
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""  # no progress bar in a pipe
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["world", "bodies[ball].restitution", "bodies[ball].friction", "body", "x", "y", "z", "vx", "vy", "vz"]
    points = [(r_, f) for r_ in (0.0, 0.5, 1.0) for f in (0.1, 0.9)]
    assert rows[1:] == expected_rows(points)
    # The restitution mattered (the comparison compares different worlds).
    assert rows[1][5] != rows[9][5]
    # --summary: min/max/mean of each output column.
    lines = r.stdout.splitlines()
    assert lines[0].split() == ["column", "min", "max", "mean"]
    ys = [float(row[5]) for row in rows[1:]]
    y = next(l.split() for l in lines if l.split()[0] == "y")
    assert (float(y[1]), float(y[2])) == (min(ys), max(ys))
    assert float(y[3]) == pytest.approx(sum(ys) / len(ys), rel=1e-12)


def test_boolean_settings_sweep_as_true_false_lists(tmp_path):
    # A list may hold true / false (a boolean setting such as
    # world.push_out_grown_overlaps); the CSV column reads them as JSON does,
    # and each world equals its scene with the key written by hand, bit for
    # bit. Ranges stay numbers.
    assert sweep.parse_set("world.push_out_grown_overlaps=false,true")[1] == [False, True]
    assert sweep.parse_set("world.sleeping=true")[1] == [True]
    with pytest.raises(sweep.SweepError, match="'maybe' is not a number, true or false"):
        sweep.parse_set("world.sleeping=maybe,true")
    with pytest.raises(sweep.SweepError, match="'true' is not a number"):
        sweep.parse_set("world.sleeping=true:false:2")
    # A box struck end-on into a row by a heavier one at 20 m/s (no gravity):
    # the push-out acts there (tests/solver/grown_overlap_test.cpp).
    box = {"type": "box", "half_extents": [0.5, 0.5, 0.5]}
    scene = {"world": {"gravity": [0, 0, 0], "dt": 1 / 60},
             "bodies": [{"name": "striker", "shape": box, "mass": 10, "friction": 0, "position": [-1.5, 0, 0],
                         "linear_velocity": [20, 0, 0]}]
             + [{"name": f"b{i}", "shape": box, "mass": 1, "friction": 0, "position": [i, 0, 0]} for i in range(4)]}
    path = tmp_path / "row.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / "results.csv"
    r = run_sweep(path, "--set", "world.push_out_grown_overlaps=false,true", "--steps", 30, "--out", out)
    assert r.returncode == 0, r.stderr
    rows = list(csv.reader(out.open()))
    assert rows[0][:3] == ["world", "world.push_out_grown_overlaps", "body"]
    expected = []
    for w, on in enumerate((False, True)):
        edited = copy.deepcopy(scene)
        edited["world"]["push_out_grown_overlaps"] = on
        world = fulcrum.load_scene(edited)
        world.step(world.scene_dt, steps=30)
        for body in world.bodies():
            expected.append([str(w), "true" if on else "false", body.name]
                            + [repr(float(x)) for x in body.position] + [repr(float(x)) for x in body.linear_velocity])
    assert rows[1:] == expected
    assert rows[1][3:] != rows[6][3:]  # the setting mattered: the striker ends elsewhere


@pytest.mark.parametrize("setting, message", [
    ("bodies[bal].restitution=0:1:3", "no element named 'bal'"),
    ("bodies[ball].restitution=0:1:x", "'x' is not a number"),
    ("bodies[ball].restitution=0:1:0", "must be a whole number >= 1"),
    ("bodies[ball].restitution=0,3", "value 3 refused"),
    ("bodies[ball].restitutoin=0.5", "unknown key"),
    ("bodies[ball].restitution", "expected PATH=a:b:n"),
    ("bodies[7].mass=1", "index 7 out of range"),
])
def test_bad_set_is_exit_2_naming_it_before_running(scene_file, tmp_path, setting, message):
    out = tmp_path / "results.csv"
    r = run_sweep(scene_file, "--set", setting, "--steps", STEPS, "--out", out)
    assert r.returncode == 2
    assert setting.split("=")[0] in r.stderr and message in r.stderr, r.stderr
    assert not out.exists()


def test_missing_scene_is_exit_2(tmp_path):
    r = run_sweep(tmp_path / "nope.json", "--set", "bodies[ball].mass=1", "--out", tmp_path / "r.csv")
    assert r.returncode == 2 and "nope.json" in r.stderr


@pytest.mark.parametrize("extra, message", [
    # A billion values used to be a MemoryError traceback while the list was made.
    (["--set", "bodies[ball].mass=1:2:1000000000"], "the count n of a:b:n must be at most 1000000, got 1000000000"),
    (["--set", "bodies[ball].mass=1:2:1001", "--set", "bodies[box].mass=1:2:1000"],
     "the grid holds 1001000 worlds, at most 1000000: split the sweep"),
    (["--set", "bodies[ball].mass=1", "--chunk-size", "0"], "--chunk-size must be >= 1, got 0"),
])
def test_huge_grids_and_bad_options_are_exit_2(scene_file, tmp_path, capsys, extra, message):
    out = tmp_path / "results.csv"
    assert sweep.main([str(scene_file), *extra, "--out", str(out)]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()


def test_bad_out_and_binary_scene_are_exit_2_before_running(scene_file, tmp_path, capsys):
    # Both used to be tracebacks: --out only after the whole run, the scene at decoding.
    assert sweep.main([str(scene_file), "--set", "bodies[ball].mass=1", "--out", str(tmp_path)]) == 2
    assert f"--out {tmp_path}: is a directory" in capsys.readouterr().err
    missing = tmp_path / "no" / "r.csv"
    assert sweep.main([str(scene_file), "--set", "bodies[ball].mass=1", "--out", str(missing)]) == 2
    assert "the directory does not exist" in capsys.readouterr().err
    garbage = tmp_path / "garbage.json"
    garbage.write_bytes(b"{\xff\xfe\x00 binary")
    assert sweep.main([str(garbage), "--set", "bodies[ball].mass=1", "--out", str(tmp_path / "r.csv")]) == 2
    assert "garbage.json: not UTF-8 text at byte offset 1: a scene file is JSON text" in capsys.readouterr().err


def test_progress_bar_only_on_a_terminal(scene_file, tmp_path):
    import pty

    main, secondary = pty.openpty()
    try:
        r = subprocess.run([sys.executable, "-m", "fulcrum", "sweep", str(scene_file), "--set",
                            "bodies[ball].restitution=0:1:3", "--steps", str(STEPS), "--out", str(tmp_path / "r.csv")],
                           stdout=subprocess.PIPE, stderr=secondary, timeout=120)
        os.close(secondary)
        secondary = None
        shown = b""
        while True:
            try:
                chunk = os.read(main, 4096)
            except OSError:  # Linux: EIO once the terminal's other end is closed
                break
            if not chunk:
                break
            shown += chunk
    finally:
        if secondary is not None:
            os.close(secondary)
        os.close(main)
    assert r.returncode == 0
    assert b"sweep [" in shown and b"100%" in shown
    assert r.stdout == b""


def test_worlds_of_different_dt_run_with_their_own(scene_file, tmp_path):
    out = tmp_path / "r.csv"
    r = run_sweep(scene_file, "--set", "world.dt=0.01,0.02", "--steps", 30, "--out", out)
    assert r.returncode == 0, r.stderr
    rows = list(csv.reader(out.open()))[1:]
    for w, dt in enumerate((0.01, 0.02)):
        scene = copy.deepcopy(SCENE)
        scene["world"]["dt"] = dt
        world = fulcrum.load_scene(scene)
        world.step(world.scene_dt, steps=30)
        ball = world.find_body("ball")
        row = next(row for row in rows if row[0] == str(w) and row[2] == "ball")
        assert row[3:6] == [repr(float(x)) for x in ball.position]
    assert rows[0][3] != rows[2][3]  # the two dts moved the ball differently
