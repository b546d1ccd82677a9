#!/usr/bin/env python3
"""Frame-to-frame flicker between rendered PNGs: the share of pixels whose brightest
channel change exceeds a threshold (0.1 of full scale), for pairs of images.

    python3 bench/flicker.py A.png B.png [C.png D.png ...] [--threshold 0.1]

Prints one line per pair. Render noise is the same measure between one frame rendered
with two Cycles seeds (scripts/blender-render.py … FRAME SEED); flicker from the mesh
is what two consecutive frames change beyond it. Reads 8-bit RGB/RGBA PNGs (what
Blender writes) with scripts/png_read.py (the standard library alone).
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from png_read import read_png  # noqa: E402


def flicker(a, b, threshold):
    wa, ha, ca, ra = read_png(a)
    wb, hb, cb, rb = read_png(b)
    if (wa, ha) != (wb, hb):
        raise SystemExit(f"{a} and {b} differ in size")
    limit = threshold * 255.0
    changed = 0
    for la, lb in zip(ra, rb):
        for x in range(wa):
            if max(abs(la[x * ca + k] - lb[x * cb + k]) for k in range(3)) > limit:
                changed += 1
    return changed / (wa * ha)


def main():
    args, threshold = sys.argv[1:], 0.1
    if "--threshold" in args:
        i = args.index("--threshold")
        threshold = float(args[i + 1])
        del args[i:i + 2]
    if not args or len(args) % 2:
        raise SystemExit(__doc__)
    for a, b in zip(args[0::2], args[1::2]):
        print(f"{a} -> {b}: {100.0 * flicker(a, b, threshold):.2f} % of pixels change by > {threshold}")


if __name__ == "__main__":
    main()
