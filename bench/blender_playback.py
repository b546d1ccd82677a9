# The add-on's import and frame changes of libwave outputs (any form and codec), in
# one headless Blender session with factory settings and no PYTHONPATH: the add-on's
# zip carries the libwave module that decodes meshopt and Draco.
#   blender -b --factory-startup --python bench/blender_playback.py -- ADDON_ZIP OUTPUT...
# Per output (a run's folder, its index.json or its .glb): the import's time; a frame
# change in sequential playback (each frame of the loop after the previous one, the
# evaluated mesh taken as a renderer asks for it: mean and worst); a random jump (64
# frames drawn with a fixed seed: mean and worst). Prints a Markdown table.
import os
import random
import sys
import time

import addon_utils
import bpy

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip, outputs = args[0], args[1:]


def source_of(path):
    if os.path.isdir(path):
        for name in ("index.json", "animation.glb", "animation.gltf"):
            if os.path.exists(os.path.join(path, name)):
                return os.path.join(path, name)
        found = sorted(n for n in os.listdir(path) if n.startswith("animation") and n.endswith(".glb"))
        if found:
            return os.path.join(path, found[0])
    return path


def change(scene, water, frame):
    start = time.perf_counter()
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    water.evaluated_get(depsgraph).to_mesh()
    water.evaluated_get(depsgraph).to_mesh_clear()
    return time.perf_counter() - start


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
rows = []
for output in outputs:
    source = source_of(output)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("libwave_blender", default_set=True)
    start = time.perf_counter()
    bpy.ops.import_scene.libwave(filepath=source)
    took = time.perf_counter() - start
    scene = bpy.context.scene
    water = bpy.data.objects["libwave water"]
    frames = list(range(scene.frame_start, scene.frame_end + 1))
    change(scene, water, frames[0])
    sequential = [change(scene, water, f) for f in frames[1:]]
    rng = random.Random(1)
    jumps = [change(scene, water, rng.choice(frames)) for _ in range(64)]
    vertices = len(water.data.vertices)
    rows.append(f"| {os.path.relpath(source, os.path.dirname(os.path.dirname(source)))} | {vertices} | {len(frames)} | "
                f"{took:.2f} s | {1e3 * sum(sequential) / len(sequential):.1f} / {1e3 * max(sequential):.1f} ms | "
                f"{1e3 * sum(jumps) / len(jumps):.1f} / {1e3 * max(jumps):.1f} ms |")
    print(rows[-1], flush=True)
print("| output | vertices | frames | import | sequential change (mean / worst) | random jump (mean / worst) |")
print("|---|---|---|---|---|---|")
print("\n".join(rows))
