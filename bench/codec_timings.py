#!/usr/bin/env python3
"""Every shipped example at its own fps, as a user runs it (the default codec) and as
plain floats (--codec none), side by side in one process: wall time, the run's plan
and frame timings, the output's size, and the codec's share of a frame (the default
run's frame time over the plain one's, minus one). Prints a Markdown table for
bench/RESULTS.md.

    python3 bench/codec_timings.py [WAVE] [EXAMPLE.json ...]

With KEEP=DIR in the environment, each example's default output is kept as DIR/NAME
(for bench/blender_playback.py to import the same outputs).

The files form's frame time includes writing its files (the plain run writes twice the
bytes, so the codec's share is, if anything, understated for it).
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
WAVE = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build/release/bindings-cli/wave")
EXAMPLES = [pathlib.Path(p) for p in sys.argv[2:]] or sorted((ROOT / "examples").glob("*.json"))


def size(folder):
    return sum(p.stat().st_size for p in pathlib.Path(folder).rglob("*") if p.is_file() and p.suffix in (".glb", ".gltf", ".bin", ".pc2"))


def run(scene, out, *args):
    start = time.perf_counter()
    r = subprocess.run([WAVE, "run", str(scene), "-o", out, "--json", *args], capture_output=True, text=True)
    wall = time.perf_counter() - start
    if r.returncode != 0:
        raise SystemExit(f"{scene}: {r.stderr}")
    report = json.loads(r.stdout)
    return report, wall, size(out)


print("| example | form | codec | frames | vertices | plan s | frames s (plain) | ms/frame (plain) | codec share | wall s (plain) | MB (plain) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
with tempfile.TemporaryDirectory() as d:
    for scene in EXAMPLES:
        default, wall, bytes_ = run(scene, os.path.join(d, "a"))
        plain, wall_plain, bytes_plain = run(scene, os.path.join(d, "b"), "--codec", "none")
        s, p = default["surface"], plain["surface"]
        t, tp = default["timings_ms"], plain["timings_ms"]
        frames = max(1, s["frames"])
        share = t["frames"] / tp["frames"] - 1.0 if tp["frames"] > 0 else float("nan")
        print(f"| {scene.stem} | {s['form']} | {s['codec']} | {s['frames']} | {s['vertices']} | {t['plan'] / 1e3:.1f} | "
              f"{t['frames'] / 1e3:.1f} ({tp['frames'] / 1e3:.1f}) | {t['frames'] / frames:.0f} ({tp['frames'] / frames:.0f}) | "
              f"{share:+.2f} | {wall:.1f} ({wall_plain:.1f}) | {bytes_ / 1e6:.1f} ({bytes_plain / 1e6:.1f}) |", flush=True)
        if os.environ.get("KEEP"):
            subprocess.run(["rm", "-rf", os.path.join(os.environ["KEEP"], scene.stem)])
            os.makedirs(os.environ["KEEP"], exist_ok=True)
            shutil.move(os.path.join(d, "a"), os.path.join(os.environ["KEEP"], scene.stem))
        for f in ("a", "b"):
            subprocess.run(["rm", "-rf", os.path.join(d, f)])
