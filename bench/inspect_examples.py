#!/usr/bin/env python3
"""The examples on their traced ray strips and on the water mesh (the default), side by side: `wave run`
(2 fps, no Draco) then `wave inspect`, and the plan's time (best of 3) with and without
the water mesh. Prints the tables of docs/inspect.md and bench/RESULTS.md.

    python3 bench/inspect_examples.py [WAVE_EXE]   # default build/release/bindings-cli/wave
"""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
WAVE = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "release", "bindings-cli", "wave")
EXAMPLES = os.path.join(ROOT, "examples")

# (label, example, surface variants: name -> what /surface becomes)
STRIPS = {"water_mesh": False}
CASES = [
    ("default bay (`gonzato-bay.json`)", "gonzato-bay.json",
     [("ray strips", STRIPS), ("water mesh (default)", None), ("wave-field, water mesh", {"kind": "wave-field"})]),
    ("`gonzato-island.json`", "gonzato-island.json",
     [("ray strips", STRIPS), ("water mesh (default)", None), ("wave-field, water mesh", {"kind": "wave-field"})]),
    ("`breaking-beach.json`", "breaking-beach.json", [("strips + breakers", STRIPS), ("water mesh + breakers (default)", None)]),
    ("`breaking-okushiri.json`", "breaking-okushiri.json",
     [("strips + breakers", STRIPS), ("water mesh + breakers (default)", None)]),
    ("`coast-with-wind-waves.json`", "coast-with-wind-waves.json",
     [("strips + wind sea", STRIPS), ("water mesh + wind sea (default)", None)]),
]


def scene_file(example, surface):
    with open(os.path.join(EXAMPLES, example)) as f:
        doc = json.load(f)
    if surface is not None:
        if surface.get("kind") == "wave-field":
            for key in ("fronts", "motion", "breakers"):
                doc.pop(key, None)
        doc["surface"] = dict(doc.get("surface", {}), **surface) if "kind" not in surface else surface
    # Next to the example, so that its relative seafloor path still resolves.
    path = os.path.join(EXAMPLES, ".inspect-%d-%s" % (os.getpid(), example))
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def run(scene, out):
    r = subprocess.run([WAVE, "run", scene, "-o", out, "--fps", "2", "--no-draco", "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(r.stderr)
    return json.loads(r.stdout)


def n(x):
    return f"{x:,}".replace(",", " ")


def main():
    rows, costs = [], []
    with tempfile.TemporaryDirectory() as d:
        for label, example, variants in CASES:
            for k, (name, surface) in enumerate(variants):
                scene = scene_file(example, surface)
                try:
                    plans, frames = [], []
                    for i in range(3):
                        out = os.path.join(d, "%s-%d-%d" % (example, k, i))
                        report = run(scene, out)
                        plans.append(report["timings_ms"]["plan"])
                        frames.append(report["timings_ms"]["frames"] / report["surface"]["frames"])
                    m = json.loads(subprocess.run([WAVE, "inspect", out, "--json"], capture_output=True, text=True,
                                                  check=True).stdout)
                finally:
                    os.remove(scene)
                w = m["worst"]
                loops = m["boundary"]["loops"]
                where = "; ".join("%d edges, %d on the border, %.1f m in" % (l["edges"], l["vertices_on_border"], l["farthest_inside_m"])
                                  for l in loops[:2]) + (" (+%d more)" % (len(loops) - 2) if len(loops) > 2 else "")
                rows.append("| %s | %s | %s | %d | %s | %s | %s (%s / %s) | %.3g° (%.3g°) | %.3g m (%.2g m) | %s | %.3g m/s | %s |" % (
                    label if k == 0 else "", name, n(m["vertices"]), m["unreferenced_vertices"], n(w["folds"]), n(w["lips"]),
                    n(w["slivers"]), n(w["lip_slivers"]), n(w["shore_slivers"]), w["smallest_angle_deg"], w["smallest_angle_off_lips_deg"],
                    w["longest_edge_m"], w["median_edge_m"], n(w["long_edges"]), w["max_speed_m_s"], where))
                costs.append("| %s | %s | %s | %.0f | %.1f |" % (label if k == 0 else "", name, n(m["vertices"]), min(plans), min(frames)))
    print("| scene | surface | vertices | unreferenced | folds | lips | slivers < 15° (on lips / the shore) | smallest angle (off both) "
          "| longest edge (median) "
          "| long edges | fastest vertex | boundary loops |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print()
    print("| scene | surface | vertices | plan (ms, best of 3) | frame (ms, best of 3; untangling included) |")
    print("|---|---|---|---|---|")
    print("\n".join(costs))


if __name__ == "__main__":
    main()
