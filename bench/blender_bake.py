# The add-on's streamed import (with Blender's normals, then the file's) beside its bake
# into the .blend, in one Blender session:
#   blender -b --factory-startup --python bench/blender_bake.py -- ADDON_ZIP SOURCE OUT_DIR
# For each route: the import's time, the RSS it adds over Blender's own (after factory
# settings), the time of a frame change over the whole loop (mean, each frame once, plus
# the evaluated mesh as a renderer asks for it), and for the bake the saved .blend's size
# and the same frame changes once it is reopened without the add-on.
import os
import sys
import time

import addon_utils
import bpy

addon_zip, source, out = sys.argv[sys.argv.index("--") + 1:][:3]


def rss_mb():
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS")) / 1024.0


def play(scene, water):
    """Mean seconds per frame change over the scene's range, each frame evaluated."""
    frames = range(scene.frame_start, scene.frame_end + 1)
    start = time.perf_counter()
    for f in frames:
        scene.frame_set(f)
        water.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
        water.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()
    return (time.perf_counter() - start) / len(frames)


def fresh():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("libwave_blender", default_set=True)


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
rows = []
for route in ("streamed", "streamed, the file's normals", "baked"):
    fresh()
    base = rss_mb()
    start = time.perf_counter()
    bpy.ops.import_scene.libwave(filepath=source, bake=route == "baked", file_normals="normals" in route)
    took = time.perf_counter() - start
    scene = bpy.context.scene
    water = bpy.data.objects["libwave water"]
    after = rss_mb() - base
    per_frame = play(scene, water)
    peak = rss_mb() - base
    row = f"| add-on, {route} | {took:.2f} s | +{after:.0f} MB | +{peak:.0f} MB | {1e3 * per_frame:.1f} ms |"
    if route == "baked":
        blend = os.path.join(out, "baked.blend")
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        row += f" {os.path.getsize(blend) / 1e6:.1f} MB |"
        addon_utils.disable("libwave_blender", default_set=True)
        bpy.ops.wm.read_factory_settings(use_empty=True)
        base = rss_mb()
        start = time.perf_counter()
        bpy.ops.wm.open_mainfile(filepath=blend)
        took = time.perf_counter() - start
        scene = bpy.context.scene
        after = rss_mb() - base
        per_frame = play(scene, bpy.data.objects["libwave water"])
        rows.append(row)
        row = (f"| the saved .blend reopened, no add-on | {took:.2f} s (open) | +{after:.0f} MB | +{rss_mb() - base:.0f} MB "
               f"| {1e3 * per_frame:.1f} ms | — |")
    else:
        row += " — |"
    rows.append(row)
print("| route | import | RSS after import | RSS after playing the loop | per frame change | .blend |")
print("|---|---|---|---|---|---|")
print("\n".join(rows))
