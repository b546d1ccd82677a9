# The Blender add-on in Debian's Blender (run as: blender -b --factory-startup --python
# tests/blender_addon.py -- ADDON_ZIP OUT_DIR...): installs the zip, imports each run
# folder's animation (morph/nodes .glb, or the files form's index.json) and checks at
# frames 0, 1, k and k + loop (the loop repeats) that every vertex's position and its
# foam/reflect/refract equal the file's frame values as libwave's own reader gives them.
import os
import sys

import addon_utils
import bpy
import numpy as np

import libwave

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip, runs = args[0], args[1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
errors = []


def source(folder):
    return os.path.join(folder, "index.json") if os.path.exists(os.path.join(folder, "index.json")) else \
        os.path.join(folder, "animation.glb")


for folder in runs:
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    path = source(folder)
    result = bpy.ops.import_scene.libwave(filepath=path)
    if result != {"FINISHED"}:
        errors.append(f"{path}: import {result}")
        continue
    scene = bpy.context.scene
    water = [o for o in scene.objects if o.type == "MESH"]
    expected = libwave.read_animation(path)
    frames, n = expected["frame_count"], expected["vertex_count"]
    if len(water) != 1 or len(water[0].data.vertices) != n:
        errors.append(f"{path}: expected one object of {n} vertices")
        continue
    obj = water[0]
    if abs(scene.render.fps / scene.render.fps_base - expected["fps"]) > 1e-6 or scene.frame_end != frames - 1:
        errors.append(f"{path}: fps {scene.render.fps}/{scene.render.fps_base}, frames {scene.frame_start}..{scene.frame_end}")
    tol = 1e-6 if "quant" not in folder else 2.0 * np.abs(expected["positions"]).max() / 32767.0
    for f in [0, 1, frames // 2, frames + 1]:
        scene.frame_set(f)
        k = f % frames
        co = np.empty(3 * n, np.float32)
        obj.data.vertices.foreach_get("co", co)
        gap = np.abs(co.reshape(n, 3) - expected["positions"][k]).max()
        if gap > tol:
            errors.append(f"{path}: frame {f} (loop frame {k}): positions off by {gap}")
        for name in ("foam", "reflect", "refract"):
            values = np.empty(n, np.float32)
            obj.data.attributes[name].data.foreach_get("value", values)
            gap = np.abs(values - expected[name][k]).max()
            if gap > (1e-6 if "quant" not in folder else 1.0 / 65535.0 + 1e-6):
                errors.append(f"{path}: frame {f}: {name} off by {gap}")
    mat = obj.data.materials[0]
    if not any(n.type == "ATTRIBUTE" and n.attribute_name == "foam" for n in mat.node_tree.nodes):
        errors.append(f"{path}: the material does not read the foam attribute")
    print(f"LIBWAVE-ADDON checked {path}: {frames} frames of {n} vertices")

print("\n".join(errors) if errors else "LIBWAVE-ADDON ok")
sys.exit(1 if errors else 0)
