#!/usr/bin/env python3
"""The WebAssembly command-line tool against the native one (docs/determinism.md).

Runs `fulcrum run SCENE --json` natively (FULCRUM_SIMD=scalar) and as
`node build-wasm/fulcrum.js run SCENE --json` on each scene and requires the
two reports to be equal in every number, bit for bit (both print each number
in its shortest round-trip form), except the wall-clock time.

Usage: compare_wasm.py NATIVE_CLI WASM_JS SCENE [SCENE ...]
A SCENE is a scene file, or `pyramid20`: the benchmark scene (bench_wasm.py)
written to a temporary file.
Exit 77 (CTest: skipped) when WASM_JS does not exist: build it with
scripts/build-wasm.sh.
"""
import json
import os
import subprocess
import sys
import tempfile

from bench_wasm import pyramid20

GENERATED = {"pyramid20": lambda: dict(pyramid20(), world=dict(pyramid20()["world"], steps=300))}

TIMING_KEYS = {"wall_seconds", "profile"}


def report(command, env):
    out = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    if out.returncode != 0:
        sys.exit(f"{' '.join(command)} failed ({out.returncode}): {out.stderr.strip()}")
    return json.loads(out.stdout)


def differences(native, wasm, path="$"):
    if isinstance(native, dict) and isinstance(wasm, dict):
        keys = (set(native) | set(wasm)) - TIMING_KEYS
        for k in sorted(keys):
            if k not in native or k not in wasm:
                yield f"{path}.{k}: only in {'native' if k in native else 'wasm'}"
            else:
                yield from differences(native[k], wasm[k], f"{path}.{k}")
    elif isinstance(native, list) and isinstance(wasm, list):
        if len(native) != len(wasm):
            yield f"{path}: {len(native)} entries native, {len(wasm)} wasm"
        for i, (a, b) in enumerate(zip(native, wasm)):
            yield from differences(a, b, f"{path}[{i}]")
    elif native != wasm or type(native) is not type(wasm):
        yield f"{path}: native {native!r}, wasm {wasm!r}"


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    native_cli, wasm_js, scenes = sys.argv[1], sys.argv[2], sys.argv[3:]
    if not os.path.exists(wasm_js):
        print(f"{wasm_js} not built (scripts/build-wasm.sh): skipped")
        return 77
    env = dict(os.environ, FULCRUM_SIMD="scalar")
    failed = False
    generated = tempfile.TemporaryDirectory()
    for scene in scenes:
        if scene in GENERATED:
            name = scene
            scene = os.path.join(generated.name, scene + ".json")
            with open(scene, "w") as f:
                json.dump(GENERATED[name](), f)
        native = report([native_cli, "run", scene, "--json"], env)
        wasm = report(["node", wasm_js, "run", scene, "--json"], env)
        diffs = list(differences(native, wasm))
        print(f"{scene}: {'same bits' if not diffs else f'{len(diffs)} differences'}")
        for d in diffs[:20]:
            print("  " + d)
        failed = failed or bool(diffs)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
