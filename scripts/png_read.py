"""Reads a non-interlaced PNG with the standard library alone (zlib and the five PNG
row filters): 8- or 16-bit grey, grey + alpha, RGB or RGBA — what Blender and libwave's
caustic maps write. Used by bench/flicker.py and tests/test_cli.py, independent of the
writers they check.

    width, height, channels, rows = read_png(path)  # rows: lists of channel values per pixel, row 0 at the top
"""
import struct
import zlib

_CHANNELS = {0: 1, 4: 2, 2: 3, 6: 4}  # PNG colour type → channels


def read_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth not in (8, 16) or colour not in _CHANNELS or interlace:
        raise ValueError(f"{path}: only non-interlaced 8- or 16-bit grey/RGB(A) PNGs")
    channels, size = _CHANNELS[colour], depth // 8
    bpp, stride = channels * size, width * channels * size
    raw, rows, previous = zlib.decompress(idat), [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = previous[i]
            c = previous[i - bpp] if i >= bpp else 0
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
        rows.append(list(line) if size == 1 else [line[2 * i] << 8 | line[2 * i + 1] for i in range(stride // 2)])
        previous = line
    return width, height, channels, rows
