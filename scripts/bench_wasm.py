#!/usr/bin/env python3
"""Step time of the native and the WebAssembly command-line tools (docs/benchmarks.md).

Writes the benchmark scenes pyramid20 and chain (bench/scenes.hpp) as scene
files, takes the cloth from scenes/cloth_on_sphere.json, and runs each with
`fulcrum run SCENE --json` natively (FULCRUM_SIMD=scalar, and the default
path) and with `node build-wasm/fulcrum.js`, one thread, interleaved rounds;
the fastest round's wall time per step is kept (this VM's noise only adds
time). Also checks that the final reports agree bit for bit with the native
scalar run.

Usage: bench_wasm.py NATIVE_CLI WASM_JS [--rounds N] [--steps N] [--also LABEL=WASM_JS ...]
"""
import argparse
import json
import os
import subprocess
import tempfile


def pyramid20():
    bodies = [{"name": "ground", "type": "static", "shape": {"type": "box", "half_extents": [50, 0.5, 50]},
               "position": [0, -0.5, 0], "friction": 0.6}]
    for row in range(20):
        count = 20 - row
        for i in range(count):
            bodies.append({"name": f"b{row}_{i}", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1,
                           "position": [i - 0.5 * (count - 1), 0.5 + row, 0], "friction": 0.6})
    return {"world": {"gravity": [0, -9.81, 0], "dt": 1 / 60, "sleeping": False}, "bodies": bodies}


def chain(links=100):
    s = 0.7071067811865476  # capsule axis y turned onto x
    bodies, joints = [], []
    for i in range(links):
        bodies.append({"name": f"link{i}", "shape": {"type": "capsule", "radius": 0.1, "half_height": 0.4}, "mass": 1,
                       "position": [0.5 + i, 60, 0], "orientation": [s, 0, 0, s]})
        joints.append({"name": f"j{i}", "type": "ball", "body_a": None if i == 0 else f"link{i - 1}",
                       "body_b": f"link{i}", "anchor": [float(i), 60, 0]})
    return {"world": {"gravity": [0, -9.81, 0], "dt": 1 / 60}, "bodies": bodies, "joints": joints}


def run(command, scene, steps, env):
    out = subprocess.run(command + ["run", scene, "--json", "--steps", str(steps)], env=env, capture_output=True,
                         text=True, check=True)
    report = json.loads(out.stdout)
    seconds = report.pop("wall_seconds")
    return seconds * 1000 / steps, report


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("native")
    parser.add_argument("wasm")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--steps", type=int, default=300)
    parser.add_argument("--also", action="append", default=[], metavar="LABEL=WASM_JS",
                        help="another WebAssembly build in the same rounds (e.g. other compiler flags)")
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    with tempfile.TemporaryDirectory() as tmp:
        scenes = {}
        for name, scene in (("pyramid20", pyramid20()), ("chain", chain())):
            scenes[name] = os.path.join(tmp, name + ".json")
            with open(scenes[name], "w") as f:
                json.dump(scene, f)
        scenes["cloth"] = os.path.join(here, "..", "scenes", "cloth_on_sphere.json")
        runners = {
            "native scalar": ([args.native], dict(os.environ, FULCRUM_SIMD="scalar")),
            "native default SIMD": ([args.native], dict(os.environ)),
            "wasm (Node)": (["node", args.wasm], dict(os.environ)),
        }
        for extra in args.also:
            label, path = extra.split("=", 1)
            runners[f"wasm {label} (Node)"] = (["node", path], dict(os.environ))
        print("| scene | steps | " + " | ".join(f"{r} ms/step" for r in runners) + " | wasm / native scalar | same bits |")
        print("|---|---|" + "---|" * len(runners) + "---|---|")
        for name, path in scenes.items():
            best = {r: float("inf") for r in runners}
            reports = {}
            for _ in range(args.rounds):
                for r, (command, env) in runners.items():
                    ms, reports[r] = run(command, path, args.steps, env)
                    best[r] = min(best[r], ms)
            same = all(reports[r] == reports["native scalar"] for r in runners if r.startswith("wasm"))
            ratio = best["wasm (Node)"] / best["native scalar"]
            print(f"| {name} | {args.steps} | " + " | ".join(f"{best[r]:.3f}" for r in runners) +
                  f" | {ratio:.2f} | {'yes' if same else 'NO'} |")


if __name__ == "__main__":
    main()
