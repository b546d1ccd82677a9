#!/usr/bin/env python3
"""`wave validate`'s peak-memory estimate beside the measured peak RSS of `wave run`, for
every example (issue: the estimate within 25 %), and the output
size beside the estimate. Each run is measured in a fresh interpreter whose only child
is `wave` (RUSAGE_CHILDREN's ru_maxrss).

    python3 bench/memory_estimate.py [--wave build/release/bindings-cli/wave] [SCENE ...]
"""
import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def peak_rss(cmd):
    code = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL); "
            "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-c", code, *cmd], capture_output=True, text=True)
    rc, kb = map(int, out.stdout.split())
    if rc != 0:
        raise SystemExit(f"{' '.join(cmd)} failed: {out.stderr}")
    return kb * 1024, time.monotonic() - t0


def folder_bytes(path):
    return sum(p.stat().st_size for p in pathlib.Path(path).rglob("*") if p.is_file())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--wave", default=str(ROOT / "build/release/bindings-cli/wave"))
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    scenes = a.scenes or sorted(str(p) for p in (ROOT / "examples").glob("*.json"))
    print("| scene | form | frames | vertices | estimated peak | measured peak RSS | ratio | output est. | output | time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        v = subprocess.run([a.wave, "validate", scene, "--json"], capture_output=True, text=True, check=True)
        est = json.loads(v.stdout)["estimate"]
        with tempfile.TemporaryDirectory() as d:
            rss, secs = peak_rss([a.wave, "run", scene, "-q", "-o", d + "/out"])
            out = folder_bytes(d + "/out")
        name = pathlib.Path(scene).stem
        print(f"| {name} | {est['form']} | {est['frames']} | {est['vertices']} | {est['peak_memory_bytes'] / 1e6:.0f} MB | "
              f"{rss / 1e6:.0f} MB | {rss / est['peak_memory_bytes']:.2f} | {est['output_bytes'] / 1e6:.0f} MB | "
              f"{out / 1e6:.0f} MB | {secs:.1f} s |", flush=True)


if __name__ == "__main__":
    main()
