"""Bad input found by the hunt of issue 26 ("Bad input, everywhere"): each case
used to be accepted silently, crash or raise a bare MemoryError; now it is a
fulcrum.Error naming the argument (docs/reliability.md, "Bad input")."""
import json
import os
import subprocess
import sys
import textwrap

import pytest

import fulcrum


def test_world_counts_have_upper_limits():
    with pytest.raises(fulcrum.Error, match=r"world: substeps must be at most 1000, got 1000000000"):
        fulcrum.World(substeps=10**9)
    with pytest.raises(fulcrum.Error, match=r"world: solverIterations must be at most 1000"):
        fulcrum.World(solver_iterations=10**9)
    with pytest.raises(fulcrum.Error, match=r"world: threads must be at most 1024, got 1000000"):
        fulcrum.World(threads=10**6)
    w = fulcrum.World()
    with pytest.raises(fulcrum.Error, match=r"substeps must be at most 1000"):
        w.substeps = 1001
    assert w.substeps == 5


def test_scene_dt_and_steps_are_checked_when_set():
    # A NaN dt used to be kept and written by save_scene; run() failed later.
    w = fulcrum.World()
    # 1e-310: below the smallest normal number of either build's Real (0 in
    # float32, subnormal in float64).
    for bad in (float("nan"), float("inf"), 0.0, -1.0, 1e-310):
        with pytest.raises(fulcrum.Error, match=r"World.scene_dt: must be a positive finite time step"):
            w.scene_dt = bad
    with pytest.raises(fulcrum.Error, match=r"World.scene_steps: must not be negative, got -5"):
        w.scene_steps = -5
    assert w.scene_dt == pytest.approx(1 / 60) and w.scene_steps == 600
    w.scene_dt, w.scene_steps = 0.01, 7
    assert json.loads(w.scene_json())["world"]["dt"] == pytest.approx(0.01)


@pytest.mark.parametrize("orientation", [(0, 0, 0, 0), (float("nan"), 0, 0, 0)])
def test_compound_child_orientation_zero_or_nan_is_an_error(orientation):
    # The binding normalised first, which turned both into the identity.
    with pytest.raises(fulcrum.Error, match=r"compound: children\[0\]"):
        fulcrum.Compound([(fulcrum.Sphere(1), (0, 0, 0), orientation)])
    child = fulcrum.Compound([(fulcrum.Sphere(1), (0, 0, 0), (2, 0, 0, 0))]).children[0]
    assert tuple(child[2]) == (1, 0, 0, 0)  # a non-unit one is still normalised


def test_compound_nested_too_deep_is_an_error_not_a_crash():
    # 100,000 levels built in a loop overflowed the stack (a segfault) at create_body.
    s = fulcrum.Sphere(1)
    for _ in range(32):
        s = fulcrum.Compound([s])
    w = fulcrum.World()
    w.create_body(shape=s)
    w.step(1 / 60)
    with pytest.raises(fulcrum.Error, match=r"nested deeper than 32 levels"):
        fulcrum.Compound([s])


def test_huge_rope_is_an_error():
    with pytest.raises(fulcrum.Error, match=r"rope \(unnamed\): segments must be below 100000000"):
        fulcrum.World().create_rope(start=(0, 0, 0), end=(1, 0, 0), segments=10**9)


def test_batch_out_of_memory_is_an_error():
    # Under an address-space limit a billion worlds fail at once; it was a bare
    # MemoryError (std::bad_alloc) naming nothing.
    code = textwrap.dedent("""
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
        import fulcrum
        try:
            fulcrum.Batch({"bodies": []}, count=10**9)
        except fulcrum.Error as e:
            print("Error:", e)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env=os.environ)
    assert "Error: makeSceneBatch: out of memory building 1000000000 worlds of <dict>" in out.stdout, out.stderr
