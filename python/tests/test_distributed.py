"""fulcrum.distributed and `sweep --scheduler` on real Dask clusters (Debian's
python3-distributed), all on 127.0.0.1: a LocalCluster of worker processes,
a `dask-scheduler` with two `dask-worker` processes started here, and one of
those workers killed mid-run. Every result must equal the local run bit for
bit (docs/scale-out.md)."""
import csv
import os
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

import pytest

distributed = pytest.importorskip("distributed", reason="python3-distributed (scripts/install-deps.sh)")

import fulcrum  # noqa: E402
import fulcrum.distributed as fd  # noqa: E402

# Debian's tornado warns about its own use of the event loop.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")

BALL = {
    "world": {"dt": 0.01},
    "bodies": [
        {"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.2}, "mass": 1, "position": [0, 1.5, 0],
         "linear_velocity": [1, 0, 0]},
    ],
}

# A ten-box tower that keeps its bodies awake: long enough chunks for a worker to die during the run.
TOWER = {
    "world": {"sleeping": False},
    "bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}}]
    + [{"name": f"box{i}", "shape": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}, "mass": 1,
        "position": [0.05 * i, 0.3 + 0.61 * i, 0]} for i in range(10)],
}


def ball_spec(n=12):
    return fd.BatchSpec(BALL, overrides=[{"bodies[ball].restitution": i / (n - 1)} for i in range(n)], steps=60)


def assert_same(got, want):
    assert len(got) == len(want)
    for i, (a, b) in enumerate(zip(got, want)):
        for name in ("positions", "orientations", "linear_velocities", "angular_velocities"):
            assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), (i, name)
        assert a.body_names == b.body_names


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def command(name):
    path = shutil.which(name) or os.path.join(os.path.dirname(sys.executable), name)
    if not os.path.exists(path):
        pytest.skip(f"{name} not installed (python3-distributed)")
    return path


class CliCluster:
    """dask-scheduler and two dask-worker processes (no nanny: the process is the worker)."""

    def __init__(self):
        self.port = free_port()
        self.address = f"tcp://127.0.0.1:{self.port}"
        self.procs = []
        # The workers import the same fulcrum as the tests (PYTHONPATH may be relative).
        package_parent = os.path.dirname(os.path.dirname(os.path.abspath(fulcrum.__file__)))
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([package_parent, os.environ.get("PYTHONPATH", "")]))
        quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
        self.procs.append(subprocess.Popen([command("dask-scheduler"), "--host", "127.0.0.1", "--port", str(self.port),
                                            "--no-dashboard"], **quiet))
        self.workers = [subprocess.Popen([command("dask-worker"), self.address, "--host", "127.0.0.1", "--nthreads", "1",
                                          "--no-nanny", "--no-dashboard", "--name", f"w{i}"], **quiet)
                        for i in range(2)]
        self.procs += self.workers

    def stop(self):
        for p in reversed(self.procs):
            if p.poll() is None:
                p.terminate()
        for p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


@pytest.fixture
def cli_cluster():
    cluster = CliCluster()
    try:
        with distributed.Client(cluster.address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
            yield cluster, client
    finally:
        cluster.stop()


def test_local_cluster_of_processes_equals_the_local_run():
    spec = ball_spec()
    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        got = fd.run(spec, client, chunk_size=3)
    assert_same(got, fd.run_local(spec, threads=2))
    # The worlds differ (bounces), so order matters and is checked.
    assert got[0].positions[1, 1] != got[-1].positions[1, 1]


def test_scheduler_and_workers_on_loopback_equal_the_local_run(cli_cluster, tmp_path):
    cluster, client = cli_cluster
    spec = ball_spec()
    assert_same(fd.run(spec, client, chunk_size=2), fd.run_local(spec))
    # A list of scenes, one world each.
    scenes = [BALL, TOWER, BALL]
    assert_same(fd.run(scenes, client, steps=30, chunk_size=1), fd.run_local(scenes, steps=30))
    # And the command line: --scheduler gives the same CSV as a local run.
    scene = tmp_path / "ball.json"
    scene.write_text(__import__("json").dumps(BALL))
    outs = []
    for extra in ([], ["--scheduler", cluster.address, "--chunk-size", "2"]):
        out = tmp_path / f"r{len(outs)}.csv"
        r = subprocess.run([sys.executable, "-m", "fulcrum", "sweep", str(scene), "--set",
                            "bodies[ball].restitution=0:1:6", "--set", "bodies[ball].friction=0.2,0.8", "--steps", "60",
                            "--out", str(out), *extra], capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        outs.append(list(csv.reader(out.open())))
    assert len(outs[0]) == 1 + 12
    assert outs[0] == outs[1]


def test_a_worker_killed_mid_run_costs_time_not_results(cli_cluster):
    cluster, client = cli_cluster
    spec = fd.BatchSpec(TOWER, overrides=[{"bodies[box9].position": [0.05 * i, 5.79, 0]} for i in range(10)],
                        steps=12000)
    first_result = threading.Event()
    outcome = {}

    def progress(done, total):
        first_result.set()

    def go():
        try:
            outcome["results"] = fd.run(spec, client, chunk_size=1, progress=progress)
        except BaseException as e:  # reported by the main thread
            outcome["error"] = e

    runner = threading.Thread(target=go)
    runner.start()
    assert first_result.wait(timeout=60), "no chunk finished"
    victim = cluster.workers[0]
    address = next(a for a, w in client.scheduler_info()["workers"].items() if w["name"] == "w0")
    busy = client.processing()[address]
    victim.send_signal(signal.SIGKILL)
    # It died holding work: that work has to be computed again elsewhere.
    assert busy, "the killed worker had no task"
    victim.wait(timeout=10)
    runner.join(timeout=120)
    assert not runner.is_alive()
    assert "error" not in outcome, outcome.get("error")
    assert_same(outcome["results"], fd.run_local(spec))
    # The run really lost a worker part-way: one is left.
    deadline = time.time() + 20
    while len(client.scheduler_info()["workers"]) != 1 and time.time() < deadline:
        time.sleep(0.1)
    assert len(client.scheduler_info()["workers"]) == 1
