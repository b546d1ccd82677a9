#!/usr/bin/env python3
"""The far field's cost per scene: vertices, plan and frame times with and without it.

    python3 bench/far_field_cost.py [WAVE] [REPEATS]

Each traced example is run as a plain morph file (the far field is left out of Draco
and quantised files), frames 0–8, alternately with `"far_field": false` and with the
default far field, REPEATS times each (default 3); the table gives the medians of
`wave run`'s own plan and per-frame times, and the vertex counts. Side by side in one
run, so the ratios hold on a shared machine.
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WAVE = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "release", "bindings-cli", "wave")
REPEATS = int(sys.argv[2]) if len(sys.argv) > 2 else 3
SCENES = ["gonzato-bay", "gonzato-island", "breaking-beach", "tso-barsky", "planar-beach", "breaking-okushiri"]


def run(scene, out):
    r = subprocess.run([WAVE, "run", scene, "-o", out, "--frames", "0:8"], capture_output=True, text=True, check=True)
    plan = float(re.search(r"plan ([0-9.]+) ms", r.stdout).group(1))
    frame = float(re.search(r"frames ([0-9.]+) ms each", r.stdout).group(1))
    vertices = int(re.search(r"^mesh +([0-9]+) vertices", r.stdout, re.M).group(1))
    return plan, frame, vertices


def main():
    print("| scene | vertices: off → on | plan (ms): off → on | frame (ms): off → on |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        for name in SCENES:
            with open(os.path.join(ROOT, "examples", name + ".json")) as f:
                doc = json.load(f)
            doc["outputs"] = {"form": "morph"}
            if not os.path.isabs(doc["seafloor"]["source"]) and os.path.exists(os.path.join(ROOT, "examples", doc["seafloor"]["source"])):
                doc["seafloor"]["source"] = os.path.join(ROOT, "examples", doc["seafloor"]["source"])
            paths = {}
            for mode in ("off", "on"):
                scene = json.loads(json.dumps(doc))
                if mode == "off":
                    scene.setdefault("surface", {})["far_field"] = False
                paths[mode] = os.path.join(d, f"{name}-{mode}.json")
                with open(paths[mode], "w") as f:
                    json.dump(scene, f)
            results = {"off": [], "on": []}
            for _ in range(REPEATS):
                for mode in ("off", "on"):
                    results[mode].append(run(paths[mode], os.path.join(d, f"out-{name}-{mode}")))
            med = {m: [statistics.median(r[i] for r in results[m]) for i in range(3)] for m in results}
            print(f"| {name} | {med['off'][2]:.0f} → {med['on'][2]:.0f} | {med['off'][0]:.0f} → {med['on'][0]:.0f} "
                  f"| {med['off'][1]:.1f} → {med['on'][1]:.1f} |", flush=True)


if __name__ == "__main__":
    main()
