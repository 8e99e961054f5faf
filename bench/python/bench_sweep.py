"""A 1,000-world sweep three ways (docs/benchmarks.md, "Batches"): local threads,
a LocalCluster of 2 worker processes, and dask-scheduler + 2 dask-worker
processes on 127.0.0.1; wall time, and the cost of a Dask task (the same run
cut into 1,000 one-world tasks against the default ~8 tasks).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/bench_sweep.py [--worlds 1000] [--steps 300]
"""
import argparse
import os
import socket
import subprocess
import sys
import time

import distributed

import fulcrum.distributed as fd


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=1000)
    parser.add_argument("--steps", type=int, default=300)
    args = parser.parse_args()

    scene = {
        "world": {"dt": 0.01, "sleeping": False},
        "bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}}]
        + [{"name": f"b{i}", "shape": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}, "mass": 1,
            "position": [1.0 * i, 0.3, 0]} for i in range(9)]
        + [{"name": "ball", "shape": {"type": "sphere", "radius": 0.2}, "mass": 1, "position": [0, 2, 2]}],
    }
    n = args.worlds
    spec = fd.BatchSpec(scene, overrides=[{"bodies[ball].restitution": i / (n - 1)} for i in range(n)], steps=args.steps)


    def timed(f):
        t = time.perf_counter()
        out = f()
        return time.perf_counter() - t, out


    def best(f, rounds=3):
        return min(timed(f)[0] for _ in range(rounds))


    local1 = best(lambda: fd.run_local(spec, threads=1))
    local2 = best(lambda: fd.run_local(spec, threads=2))
    print(f"{n} worlds x {args.steps} steps (10 bodies): local 1 thread {local1:.2f} s, 2 threads {local2:.2f} s")
    reference = fd.run_local(spec)


    def on(client, label):
        coarse = best(lambda: fd.run(spec, client))
        fine = best(lambda: fd.run(spec, client, chunk_size=1))
        same = all(a.positions.tobytes() == b.positions.tobytes() for a, b in zip(fd.run(spec, client), reference))
        per_task = (fine - coarse) / (n - 8)
        print(f"{label}: {coarse:.2f} s in ~8 tasks, {fine:.2f} s in {n} tasks: {per_task * 1e3:.2f} ms per task; "
              f"bit for bit the local run: {same}")


    with distributed.LocalCluster(n_workers=2, processes=True, threads_per_worker=1, host="127.0.0.1",
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        on(client, "LocalCluster, 2 worker processes")

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    address = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    procs += [subprocess.Popen(["dask-worker", address, "--host", "127.0.0.1", "--nthreads", "1", "--no-dashboard"],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=dict(os.environ)) for _ in range(2)]
    try:
        with distributed.Client(address, timeout=30) as client:
            client.wait_for_workers(2, timeout=60)
            on(client, "dask-scheduler + 2 dask-workers on loopback")
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait()


if __name__ == "__main__":  # worker processes import this file: run only here
    main()
    sys.exit(0)
