# The add-on's zip alone, as an artist installs it: a factory-settings Blender with no
# PYTHONPATH imports a meshopt files form (decoded by the libwave module the zip
# carries), plays it, and makes the sky world.
#   blender -b --factory-startup --python tests/blender_addon_bundled.py -- ADDON_ZIP INDEX_JSON FRAMES
import sys

import addon_utils
import bpy

zip_path, index, frames = sys.argv[sys.argv.index("--") + 1:][:3]
errors = []
if any(p for p in sys.path if "bindings-cli/python" in p) or "libwave" in sys.modules:
    errors.append("libwave is on Blender's path: this test needs none")
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
if bpy.ops.import_scene.libwave(filepath=index) != {"FINISHED"}:
    errors.append("the import failed")
else:
    scene = bpy.context.scene
    water = bpy.data.objects["libwave water"]
    if scene.frame_end != int(frames) - 1:
        errors.append(f"frames 0 … {scene.frame_end}, expected {int(frames) - 1}")
    before = [v.co.z for v in water.data.vertices[:2000]]
    scene.frame_set(2)
    if before == [v.co.z for v in water.data.vertices[:2000]]:
        errors.append("frame 2 looks like frame 0")
    if "libwave_blender.libwave" not in sys.modules:
        errors.append("the zip's libwave module was not the one loaded")
    if scene.world is None or not any(n.type == "TEX_SKY" for n in scene.world.node_tree.nodes):
        errors.append("no sky world")
print("\n".join(errors) if errors else "LIBWAVE-BUNDLED ok")
sys.exit(1 if errors else 0)
