#!/usr/bin/env python3
"""One frame of a libwave output read by a player, each way the libwave module offers:
`read_animation` opened anew for each frame (the add-on's way before the FrameReader:
the frame file of the files form, or `read_animation(path, k, 1)` of a .glb), and
`FrameReader.frame(k)` of a reader kept open (with and without the normals). Checks
that both give the same bytes, then prints the median wall time of a frame, over the
loop's frames in order (the first of each way left out: it opens the reader).

    PYTHONPATH=build/release/bindings-cli/python python3 bench/frame_reader.py OUTPUT...

OUTPUT: a run's folder (index.json or animation.glb), an index.json or a .glb/.gltf.
"""
import json
import os
import statistics
import sys
import time

import numpy as np

import libwave


def source_of(path):
    if os.path.isdir(path):
        for name in ("index.json", "animation.glb", "animation.gltf"):
            if os.path.exists(os.path.join(path, name)):
                return os.path.join(path, name)
    return path


def main(outputs, frames=24):
    print("| output | vertices | read_animation per frame | FrameReader.frame | … without normals |")
    print("|---|---|---|---|---|")
    for output in outputs:
        source = source_of(output)
        reader = libwave.FrameReader(source)
        if source.endswith(".json"):
            with open(source) as f:
                files = [os.path.join(os.path.dirname(source), e["file"]) for e in json.load(f)["frames"]]
            alone = lambda k: libwave.read_animation(files[k])
        else:
            alone = lambda k: libwave.read_animation(source, k, 1)
        ks = list(range(min(frames, reader.frame_count)))
        times = {"alone": [], "reader": [], "positions": []}
        for k in ks:
            start = time.perf_counter()
            a = alone(k)
            times["alone"].append(time.perf_counter() - start)
            start = time.perf_counter()
            f = reader.frame(k)
            times["reader"].append(time.perf_counter() - start)
            start = time.perf_counter()
            reader.frame(k, False)
            times["positions"].append(time.perf_counter() - start)
            for name in ("positions", "normals", "foam", "reflect", "refract", "colors"):
                want = a[name][0] if len(a[name]) else None
                if (want is None) != (f[name] is None) or (want is not None and want.tobytes() != f[name].tobytes()):
                    sys.exit(f"{source}: frame {k}: {name} differs between read_animation and FrameReader")
            if not np.array_equal(a["triangles"], reader.triangles):
                sys.exit(f"{source}: frame {k}: triangles differ")
        ms = {w: 1e3 * statistics.median(t[1:]) for w, t in times.items()}
        print(f"| {os.path.relpath(source, os.path.dirname(os.path.dirname(source)))} | {reader.vertex_count} | "
              f"{ms['alone']:.1f} ms | {ms['reader']:.1f} ms | {ms['positions']:.1f} ms |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
