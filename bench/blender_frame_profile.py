# Where the add-on's sequential frame change spends its time, step by step, over 24 frames
# (medians): decoding the frame (the add-on's Animation._decode: the libwave module, as on
# the worker thread), writing positions and foam/reflect/refract into the mesh
# (foreach_set, mesh.update), the depsgraph update, and a renderer's to_mesh.
#   blender -b --factory-startup --python bench/blender_frame_profile.py -- ADDON_ZIP OUTPUT_FILE
# OUTPUT_FILE: a compressed output's index.json or .glb (meshopt or Draco).
import sys
import time

import addon_utils
import bpy
import numpy as np
args = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=args[0], overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
bpy.ops.import_scene.libwave(filepath=args[1])
import libwave_blender as lb
water = bpy.data.objects["libwave water"]
anim = lb._animation(water[lb._PROP])
mesh = water.data
bpy.app.handlers.frame_change_post.clear()
T = {}
def t(name, fn):
    s = time.perf_counter(); r = fn(); T.setdefault(name, []).append(time.perf_counter() - s); return r
for k in range(1, 25):
    try:
        f = t("decode", lambda: anim._decode(k, False))
    except TypeError:
        f = t("decode", lambda: anim._decode(k))
    def write():
        mesh.vertices.foreach_set("co", np.ascontiguousarray(f.positions, np.float32).ravel())
        for name, values in (("foam", f.foam), ("reflect", f.reflect), ("refract", f.refract)):
            lb._attribute(mesh, name).data.foreach_set("value", np.ascontiguousarray(values, np.float32))
        mesh.update()
    t("write", write)
    def ev():
        dg = bpy.context.evaluated_depsgraph_get()
        return dg
    t("depsgraph", ev)
    def tm():
        dg = bpy.context.evaluated_depsgraph_get()
        water.evaluated_get(dg).to_mesh(); water.evaluated_get(dg).to_mesh_clear()
    t("to_mesh", tm)
print("PROF " + ", ".join(f"{k} {1e3*np.median(v):.1f}" for k, v in T.items()))
