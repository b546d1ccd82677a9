#!/usr/bin/env python3
"""Frame-to-frame flicker between rendered PNGs: the share of pixels whose brightest
channel change exceeds a threshold (0.1 of full scale), for pairs of images.

    python3 bench/flicker.py A.png B.png [C.png D.png ...] [--threshold 0.1]

Prints one line per pair. Render noise is the same measure between one frame rendered
with two Cycles seeds (scripts/blender-render.py … FRAME SEED); flicker from the mesh
is what two consecutive frames change beyond it. Reads 8-bit, non-interlaced RGB/RGBA
PNGs (what Blender writes) with the standard library alone.
"""
import struct
import sys
import zlib


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise SystemExit(f"{path}: only 8-bit RGB/RGBA, non-interlaced")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


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
