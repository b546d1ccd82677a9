# Live water in Blender: terrain → first playable frame, and the whole loop in the
# background, for the default bay's size (libwave's gonzato-bay, 100 m, as a Blender mesh)
# and a 1 km coast (a wavy 1:25 beach with a headland and a shoal, 5 m vertices), with
# the panel's defaults (one 6 s swell 0.6 m high, medium quality, far field, 24 fps):
#   blender -b --factory-startup --python bench/blender_live.py -- ADDON_ZIP OUT_DIR [REPEATS]
# For each terrain and run: the operator's return (the UI's wait), the time until the water
# shows frame 0, until the loop is complete, the longest main-thread poll (the timer's
# work: playing the frames written so far; what the UI freezes for at most), the frames
# and vertices; then a second Generate (the cache).
import math
import os
import shutil
import statistics
import sys
import tempfile
import time

import addon_utils
import bpy
import numpy as np

zip_path, out = sys.argv[sys.argv.index("--") + 1:][:2]
repeats = int(sys.argv[sys.argv.index("--") + 3]) if len(sys.argv) > sys.argv.index("--") + 3 else 3
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
tempfile.tempdir = out
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
live = sys.modules["libwave_blender.live"]
libwave = sys.modules["libwave_blender.frames"]._libwave_module()


def grid_mesh(name, xs, ys, z):
    """A mesh object of the grid xs × ys with heights z[j, i] (quads)."""
    nx, ny = len(xs), len(ys)
    gx, gy = np.meshgrid(xs, ys)
    verts = np.stack([gx.ravel(), gy.ravel(), z.ravel()], 1)
    j, i = np.mgrid[0:ny - 1, 0:nx - 1]
    a = (j * nx + i).ravel()
    quads = np.stack([a, a + 1, a + nx + 1, a + nx], 1)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.astype(np.float32).ravel())
    mesh.loops.add(4 * len(quads))
    mesh.loops.foreach_set("vertex_index", quads.astype(np.int32).ravel())
    mesh.polygons.add(len(quads))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 4 * len(quads), 4, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(quads), 4, np.int32))
    mesh.update(calc_edges=True)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.collection.objects.link(obj)
    return obj


def bay():
    s = libwave.procedural_seafloor("gonzato-bay")
    (x0, y0), (dx, dy) = s.origin, s.spacing
    z = np.array(s.elevation)
    return grid_mesh("bay 100 m", x0 + dx * np.arange(z.shape[1]), y0 + dy * np.arange(z.shape[0]), z)


def coast():
    xs = np.linspace(0.0, 1000.0, 201)
    ys = np.linspace(0.0, 1000.0, 201)
    gx, gy = np.meshgrid(xs, ys)
    shore = 700.0 + 60.0 * np.sin(gx / 1000.0 * 2 * math.pi * 1.5) + 120.0 * np.exp(-((gx - 300.0) / 90.0) ** 2)
    z = np.clip((gy - shore) / 25.0, -18.0, 15.0)
    z += 9.0 * np.exp(-((gx - 650.0) ** 2 + (gy - 450.0) ** 2) / (2 * 60.0 ** 2))  # a shoal offshore
    return grid_mesh("coast 1 km", xs, ys, z)


def run(terrain):
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.view_layer.objects.active = terrain
    bpy.ops.object.libwave_water_add()
    water = bpy.context.active_object
    rows = []
    for r in range(repeats):
        shutil.rmtree(os.path.join(out, "libwave_blender_cache"), ignore_errors=True)
        t0 = time.perf_counter()
        bpy.ops.object.libwave_generate()
        returned = time.perf_counter() - t0
        first = None
        longest = 0.0
        while live.busy(water):
            p0 = time.perf_counter()
            live.poll_jobs()
            longest = max(longest, time.perf_counter() - p0)
            if first is None and water.get("libwave_live_mesh"):
                first = time.perf_counter() - t0
            time.sleep(0.01)
        total = time.perf_counter() - t0
        status = water.libwave_water.status
        if "failed" in status:
            print(f"LIVE-BENCH {terrain.name}: {status}")
            return
        rows.append((returned, first, total, longest))
        water["libwave_live_mesh"] = ""  # the next run's first frame is seen afresh
    t0 = time.perf_counter()
    bpy.ops.object.libwave_generate()
    cached = time.perf_counter() - t0
    frames = bpy.context.scene.frame_end + 1
    med = [statistics.median(c) for c in zip(*rows)]
    print(f"LIVE-BENCH {terrain.name}: {len(terrain.data.vertices)} terrain vertices, {frames} frames of "
          f"{len(water.data.vertices)} vertices; medians of {len(rows)}: operator {med[0] * 1000:.0f} ms, first frame "
          f"{med[1]:.2f} s, whole loop {med[2]:.2f} s, longest main-thread poll {med[3] * 1000:.0f} ms; "
          f"cached generate {cached * 1000:.0f} ms; runs {[(round(a, 2), round(b, 2), round(c, 2)) for _, a, b, c in [(0,) + r[1:] for r in rows]]}",
          flush=True)
    bpy.data.objects.remove(water)


for make in (bay, coast):
    run(make())
