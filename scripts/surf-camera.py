"""Prints a LIBWAVE_CAMERA value (scripts/blender-render.py) for a view along a breaking
crest: the youngest spray (younger than 0.4 s) of a whitewater frame marks the lip; the
camera stands DIST m along the crest from it, UP m above still water, looking at it.

    /usr/bin/python3 scripts/surf-camera.py OUT/whitewater/whitewater-0033.glb 25 1.5 0.34,0.94

(the last argument: the swell's direction, as the scene gives it)."""
import sys, json, struct, numpy as np
path, dist, up = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
dx, dy = (float(v) for v in sys.argv[4].split(","))  # the swell's direction
b = open(path, "rb").read()
jl = struct.unpack("<I", b[12:16])[0]; j = json.loads(b[20:20 + jl]); n = j["scenes"][0]["extras"]["libwave_whitewater"]["points"]
f = np.frombuffer(b[20 + jl + 8:], dtype="<f4")
pos = f[:3 * n].reshape(-1, 3); age = f[6 * n:7 * n]; kind = f[8 * n:9 * n]
sel = (kind == 0) & (age < 0.4)
p = pos[sel]
x, y, z = p[:, 0], -p[:, 2], p[:, 1]  # glTF → z up
cx, cy = np.median(x), np.median(y)
k = np.argmin((x - cx) ** 2 + (y - cy) ** 2)
tx, ty = x[k], y[k]
norm = (dx * dx + dy * dy) ** 0.5; dx, dy = dx / norm, dy / norm
ux, uy = dy, -dx  # along the crest
print(f"{tx + dist * ux:.2f},{ty + dist * uy:.2f},{up:.2f},{tx:.2f},{ty:.2f},{0.3:.2f}")
