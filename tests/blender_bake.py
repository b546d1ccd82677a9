# The add-on's bake (run as: blender -b --factory-startup --python tests/blender_bake.py --
# save ADDON_ZIP SOURCE BLEND, then in a second Blender: ... -- check BLEND SOURCE).
# `save` installs the add-on, imports SOURCE baked and saves BLEND. `check` opens BLEND
# in a factory-settings Blender, where the add-on is not enabled (checked: not loaded, no
# frame handler), and checks at frames 0, 1, k and
# k + loop that the evaluated water's positions and foam/reflect/refract equal the file's
# frame values as libwave's own reader gives them.
import os
import sys

import addon_utils
import bpy
import numpy as np

import libwave

args = sys.argv[sys.argv.index("--") + 1:]
errors = []
if args[0] == "save":
    addon_zip, source, blend = args[1:4]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
    addon_utils.enable("libwave_blender", default_set=True)
    result = bpy.ops.import_scene.libwave(filepath=source, bake=True)
    if result != {"FINISHED"}:
        errors.append(f"{source}: baked import {result}")
    else:
        bpy.ops.wm.save_as_mainfile(filepath=blend)
        print(f"LIBWAVE-BAKE saved {blend} ({os.path.getsize(blend) / 1e6:.1f} MB)")
else:
    blend, source = args[1:3]
    bpy.ops.wm.open_mainfile(filepath=blend)
    if "libwave_blender" in sys.modules or any("libwave" in h.__module__ for h in bpy.app.handlers.frame_change_post):
        errors.append("the add-on is loaded: the check would not show that the .blend plays without it")
    scene = bpy.context.scene
    water = bpy.data.objects["libwave water"]
    expected = libwave.read_animation(source)
    frames, n = expected["frame_count"], expected["vertex_count"]
    for f in [0, 1, frames // 2, frames + 1, -1]:
        scene.frame_set(f)
        k = f % frames
        mesh = water.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
        if len(mesh.vertices) != n:
            errors.append(f"frame {f}: {len(mesh.vertices)} vertices, expected {n}")
            break
        co = np.empty(3 * n, np.float32)
        mesh.vertices.foreach_get("co", co)
        index = np.empty(n, np.int32)  # the mesh's vertices in the file's numbering
        mesh.attributes["file vertex"].data.foreach_get("value", index)
        # The add-on dequantises in float32, libwave's reader in double: a few ulps apart.
        want = np.asarray(expected["positions"][k]).reshape(n, 3)[index]
        gap = (np.abs(co.reshape(n, 3) - want) / (1e-6 + 1e-6 * np.abs(want))).max()
        if gap > 1.0:
            errors.append(f"frame {f} (loop frame {k}): positions off by {gap} × (1e-6 + 1e-6 |p|)")
        for name in ("foam", "reflect", "refract"):
            values = np.empty(n, np.float32)
            mesh.attributes[name].data.foreach_get("value", values)
            gap = np.abs(values - np.asarray(expected[name][k])[index]).max()
            if gap > 1e-6:
                errors.append(f"frame {f}: {name} off by {gap}")
        water.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh_clear()
    print(f"LIBWAVE-BAKE checked {blend}: {frames} frames of {n} vertices, without the add-on")
print("\n".join(errors) if errors else "LIBWAVE-BAKE ok")
sys.exit(1 if errors else 0)
