#!/usr/bin/env python3
"""Breaker faces on an exported water mesh, per frame over the loop (issue 65).

    wave run examples/breaking-beach.json --no-draco --no-quantize --codec none \
        --form files --fps 4 -o OUT
    /usr/bin/python3 bench/surf_faces.py OUT [--rect 0,0,200,200] [--json]

Reads the `files` form (one .glb per frame, plain floats), keeps the water mesh's
triangles inside the domain rectangle (the far-field skirt lies outside it) and prints
per frame and over the loop:
* the slope of each triangle (the angle of its normal from up; > 90° faces down):
  median, 99th, 99.9th percentile and maximum; triangles steeper than 30° and 60°;
  triangles facing down;
* the smallest 3D angle of the triangles that do not face down, and how many of them
  are slivers (< 15°);
* per crest: the domain cut into bins along x (--bin m) and the loop into swell
  periods (--period s); in each (bin, period) with a breaking crest (a triangle
  steeper than 20°) the steepest slope. The least of these is what "every crest's face
  reaches" measures.
Only numpy; glTF y-up is mapped back to z-up (x, y, z) = (x, -z, y).
"""
import argparse
import glob
import json
import os
import struct
import sys

import numpy as np

TYPES = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def read_glb(path):
    data = open(path, "rb").read()
    n = struct.unpack("<I", data[12:16])[0]
    doc = json.loads(data[20:20 + n])
    off = 20 + n
    bin_len = struct.unpack("<I", data[off:off + 4])[0]
    blob = data[off + 8:off + 8 + bin_len]

    def accessor(i):
        a = doc["accessors"][i]
        v = doc["bufferViews"][a["bufferView"]]
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        dt = np.dtype(TYPES[a["componentType"]])
        w = WIDTH[a["type"]]
        arr = np.frombuffer(blob, dtype=dt, count=a["count"] * w, offset=start)
        return arr.reshape(a["count"], w) if w > 1 else arr

    mesh = next(m for m in doc["meshes"] if m.get("name") == "water")
    prim = mesh["primitives"][0]
    pos = accessor(prim["attributes"]["POSITION"]).astype(np.float64)
    tri = accessor(prim["indices"]).astype(np.int64).reshape(-1, 3)
    xyz = np.stack([pos[:, 0], -pos[:, 2], pos[:, 1]], axis=1)
    return xyz, tri


def frame_stats(xyz, tri, rect):
    x0, y0, x1, y1 = rect
    eps = 1e-4
    inside = (xyz[:, 0] >= x0 - eps) & (xyz[:, 0] <= x1 + eps) & (xyz[:, 1] >= y0 - eps) & (xyz[:, 1] <= y1 + eps)
    t = tri[inside[tri].all(axis=1)]
    a, b, c = xyz[t[:, 0]], xyz[t[:, 1]], xyz[t[:, 2]]
    n = np.cross(b - a, c - a)
    nl = np.linalg.norm(n, axis=1)
    ok = nl > 0
    slope = np.degrees(np.arctan2(np.hypot(n[:, 0], n[:, 1]), n[:, 2]))
    down = n[:, 2] < 0

    def angle(p, q, r):
        u, v = q - p, r - p
        cu = np.einsum("ij,ij->i", u, v) / np.maximum(np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1), 1e-300)
        return np.degrees(np.arccos(np.clip(cu, -1, 1)))

    smallest = np.minimum(np.minimum(angle(a, b, c), angle(b, c, a)), angle(c, a, b))
    up = ok & ~down
    centroid_x = (a[:, 0] + b[:, 0] + c[:, 0]) / 3.0
    return {
        "triangles": int(len(t)),
        "vertices": int(inside.sum()),
        "p50": float(np.percentile(slope[ok], 50)),
        "p99": float(np.percentile(slope[ok], 99)),
        "p999": float(np.percentile(slope[ok], 99.9)),
        "max": float(slope[ok].max()),
        "over30": int((slope > 30).sum()),
        "over60": int((slope > 60).sum()),
        "down": int(down.sum()),
        "slivers_up": int((smallest[up] < 15).sum()),
        "smallest_up": float(smallest[up].min()),
        "slivers_down": int((smallest[down] < 15).sum()),
    }, slope, centroid_x


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--rect", default="0,0,200,200", help="x0,y0,x1,y1 of the domain (planar-beach: 0,0,200,200)")
    ap.add_argument("--bin", type=float, default=10.0, help="bin width along x for the per-crest faces (m)")
    ap.add_argument("--period", type=float, default=8.0, help="swell period: the loop's crests (s)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rect = [float(v) for v in args.rect.split(",")]
    index = json.load(open(os.path.join(args.out, "index.json")))
    fps = float(index["fps"])
    files = sorted(glob.glob(os.path.join(args.out, "frames", "frame-*.glb")))
    if not files:
        sys.exit("no frames/frame-*.glb in " + args.out + " (run with --form files)")
    per = []
    crest = {}  # (bin, period) -> steepest slope
    for i, f in enumerate(files):
        xyz, tri = read_glb(f)
        st, slope, cx = frame_stats(xyz, tri, rect)
        st["frame"] = i
        per.append(st)
        k = int(i / fps // args.period)
        bins = np.floor((cx - rect[0]) / args.bin).astype(int)
        for b in np.unique(bins[slope > 20]):
            crest[(int(b), k)] = max(crest.get((int(b), k), 0.0), float(slope[bins == b].max()))
    keys = ["p50", "p99", "p999", "max", "over30", "over60", "down", "slivers_up", "smallest_up", "slivers_down"]
    summary = {"frames": len(per), "vertices": per[0]["vertices"], "triangles": per[0]["triangles"]}
    for key in keys:
        vals = np.array([p[key] for p in per])
        summary[key] = {"median_frame": float(np.median(vals)),
                        "worst": float(vals.min() if key == "smallest_up" else vals.max())}
    faces = np.array(list(crest.values())) if crest else np.zeros(0)
    summary["crest_faces"] = {"count": int(len(faces)),
                              "least_deg": float(faces.min()) if len(faces) else 0.0,
                              "median_deg": float(np.median(faces)) if len(faces) else 0.0,
                              "under60": int((faces < 60).sum()), "under30": int((faces < 30).sum())}
    if args.json:
        print(json.dumps({"summary": summary, "per_frame": per}, indent=1))
        return
    print(f"{len(per)} frames, {summary['vertices']} water vertices, {summary['triangles']} triangles in the rectangle")
    print(f"{'':14s}{'median frame':>14s}{'worst frame':>14s}")
    for key in keys:
        print(f"{key:14s}{summary[key]['median_frame']:14.2f}{summary[key]['worst']:14.2f}")
    cf = summary["crest_faces"]
    print(f"crest faces ({args.bin:g} m bins x {args.period:g} s periods with a slope > 20°): {cf['count']}, "
          f"least {cf['least_deg']:.1f}°, median {cf['median_deg']:.1f}°, under 60°: {cf['under60']}, under 30°: {cf['under30']}")


if __name__ == "__main__":
    main()
