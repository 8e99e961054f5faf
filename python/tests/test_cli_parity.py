"""The Python binding steps a scene to the same bits as `fulcrum run --json`
(the CLI is build/release/apps/fulcrum/fulcrum, or FULCRUM_CLI)."""
import json
import subprocess

import numpy as np
import pytest

import fulcrum

SCENES = ["projectile.json", "box_stack.json", "joints.json", "chain.json", "all_shapes.json", "dzhanibekov.json",
          "rope_and_cloth.json", "spring_mass.json"]


def run_cli(cli, scene, steps, *extra):
    out = subprocess.run([str(cli), "run", str(scene), "--json", "--steps", str(steps), *extra],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def as_real(values):
    # The JSON holds the engine's numbers (fulcrum.real_dtype: float32, or
    # float64 in a FULCRUM_DOUBLE build) in their shortest decimal form:
    # parsed and rounded to that type they are those bits again.
    return np.asarray(values, dtype=np.float64).astype(fulcrum.real_dtype)


@pytest.mark.parametrize("scene", SCENES)
def test_python_equals_cli_bit_for_bit(repo, cli, scene):
    path = repo / "scenes" / scene
    steps = 120
    report = run_cli(cli, path, steps)
    w = fulcrum.load_scene(path)
    w.step(w.scene_dt, steps=steps)
    bodies = report["bodies"]
    assert len(bodies) == w.body_count
    for key, ours in [("position", w.positions()), ("orientation", w.orientations()),
                      ("linear_velocity", w.linear_velocities()), ("angular_velocity", w.angular_velocities())]:
        theirs = as_real([b[key] for b in bodies])
        np.testing.assert_array_equal(ours.astype(fulcrum.real_dtype), theirs, err_msg=f"{scene}: {key}")
        # Widening the engine's Real to float64 is exact: the arrays hold exactly those numbers.
        np.testing.assert_array_equal(ours, ours.astype(fulcrum.real_dtype).astype(np.float64))


def test_threads_and_run_give_the_same_bits(repo, cli):
    path = repo / "scenes" / "box_stack.json"
    one = fulcrum.load_scene(path).run(steps=90).positions()
    four = fulcrum.load_scene(path)
    four.threads = 4
    four.parallel_min_bodies = 0   # use the pool even for this small scene
    four.run(steps=90)
    np.testing.assert_array_equal(one, four.positions())
    report = run_cli(cli, path, 90, "--threads", "4")
    np.testing.assert_array_equal(one.astype(fulcrum.real_dtype), as_real([b["position"] for b in report["bodies"]]))
