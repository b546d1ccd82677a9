# Renders an output of `wave run` through the libwave add-on with Cycles on the CPU:
#   blender -b --factory-startup --python scripts/blender-render.py -- ADDON_ZIP RUN_DIR OUT.png [FRAME [SEED]]
# (SEED: Cycles' sampling seed, default 0; two seeds of one frame measure render noise;
# LIBWAVE_NO_CAUSTICS=1 imports without the caustic maps, LIBWAVE_NO_SUNBEAMS=1 without
# the sunbeam volumes, to compare (LIBWAVE_SUNBEAM_STRENGTH=S sets their strength);
# LIBWAVE_CAMERA="x,y,z,tx,ty,tz" puts the camera at x,y,z looking at tx,ty,tz,
# Blender axes, for close-ups; LIBWAVE_BAKE=FILE.blend imports baked into the .blend
# and saves it, ready to render, as FILE.blend: `blender -b --factory-startup FILE.blend
# -o OUT -f FRAME` then renders it without the add-on; LIBWAVE_FILE_NORMALS=1 imports
# with the file's normals as custom normals; LIBWAVE_VISIBILITY=M sets the add-on's haze
# (m; 0 for none; unset: the add-on's default); LIBWAVE_NO_FOAM=1 renders the water's
# shape alone: no foam in its material and no whitewater particles; LIBWAVE_FOAM_SHEETS=0
# leaves the foam particles' lace sheets out (the water's own foam, spray and bubbles stay); LIBWAVE_SIZE=WxH the
# image size, default 640x360; LIBWAVE_SAMPLES=N Cycles' samples, default 16; LIBWAVE_EXPOSURE=STOPS the
# view's exposure, else metered through the camera at the frame rendered (the add-on's meter).)
# The add-on imports the water (positions, foam, reflect, refract per frame), the
# seafloor, camera and sun the .glb carries and its physical sky; this script renders
# (LIBWAVE_FLAT_SKY=1: a flat blue background instead of the add-on's sky, as before).
import math
import os
import sys

import addon_utils
import bpy

addon_zip, run, out = sys.argv[sys.argv.index("--") + 1:][:3]
frame = int((sys.argv[sys.argv.index("--") + 1:] + ["30"])[3])
seed = int((sys.argv[sys.argv.index("--") + 1:] + ["30", "0"])[4])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
source = os.path.join(run, "index.json") if os.path.exists(os.path.join(run, "index.json")) else os.path.join(run, "animation.glb")
bake = os.environ.get("LIBWAVE_BAKE")
haze = {"visibility": float(os.environ["LIBWAVE_VISIBILITY"])} if "LIBWAVE_VISIBILITY" in os.environ else {}
if "LIBWAVE_SUNBEAM_STRENGTH" in os.environ:
    haze["sunbeam_strength"] = float(os.environ["LIBWAVE_SUNBEAM_STRENGTH"])
bpy.ops.import_scene.libwave(filepath=source, caustics=os.environ.get("LIBWAVE_NO_CAUSTICS") != "1", bake=bool(bake),
                             file_normals=os.environ.get("LIBWAVE_FILE_NORMALS") == "1",
                             sunbeams=os.environ.get("LIBWAVE_NO_SUNBEAMS") != "1",
                             meter_exposure=False, **haze)  # metered below, through the camera and frame rendered
scene = bpy.context.scene
if os.environ.get("LIBWAVE_NO_FOAM") == "1":  # the water's shape alone: no foam in the material, no whitewater
    for obj in list(scene.objects):
        if "libwave_whitewater" in obj:
            bpy.data.objects.remove(obj)
    mat = bpy.data.materials.get("libwave water")
    if mat is not None:
        mix = next(n for n in mat.node_tree.nodes if n.type == "OUTPUT_MATERIAL").inputs["Surface"].links[0].from_node
        for link in list(mix.inputs["Fac"].links):
            mat.node_tree.links.remove(link)
        mix.inputs["Fac"].default_value = 0.0
if os.environ.get("LIBWAVE_FOAM_SHEETS") == "0":  # the foam particles not drawn: the water's foam, spray, bubbles
    group = bpy.data.node_groups.get("libwave whitewater points")
    for node in (group.nodes if group else []):
        if node.label == "foam sheets":
            node.inputs["Selection"].default_value = False
            for link in list(node.inputs["Selection"].links):
                group.links.remove(link)
if scene.camera is None:  # the files form carries no camera: one from the open sea
    water = next(o for o in scene.objects if "libwave_source" in o or "libwave_baked" in o)
    xs = [v.co.x for v in water.data.vertices]
    ys = [v.co.y for v in water.data.vertices]
    cx, cy, size = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, max(max(xs) - min(xs), max(ys) - min(ys))
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    cam.location = (cx, cy - 1.1 * size, 0.4 * size)
    cam.rotation_euler = (math.atan2(1.1, 0.4), 0.0, 0.0)
    scene.camera = cam
if os.environ.get("LIBWAVE_CAMERA"):
    from mathutils import Vector
    x, y, z, tx, ty, tz = map(float, os.environ["LIBWAVE_CAMERA"].split(","))
    scene.camera.location = (x, y, z)
    scene.camera.rotation_euler = (Vector((tx, ty, tz)) - Vector((x, y, z))).to_track_quat("-Z", "Y").to_euler()
    scene.camera.data.clip_start = 1e-3 * (Vector((tx, ty, tz)) - Vector((x, y, z))).length
if os.environ.get("LIBWAVE_FLAT_SKY") == "1" or scene.world is None:  # the add-on's own sky otherwise
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.45, 0.6, 0.8, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
    scene.world = world
scene.frame_set(frame)
if "LIBWAVE_EXPOSURE" in os.environ:  # the view's exposure (stops)
    scene.view_settings.exposure = float(os.environ["LIBWAVE_EXPOSURE"])
elif os.environ.get("LIBWAVE_FLAT_SKY") == "1":  # as before the meter
    scene.view_settings.exposure = 0.0
else:  # metered through the camera used, at the frame rendered
    bpy.ops.scene.libwave_meter_exposure()
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = int(os.environ.get("LIBWAVE_SAMPLES", "16"))
scene.cycles.use_denoising = False
scene.cycles.seed = seed
scene.render.resolution_x, scene.render.resolution_y = map(int, os.environ.get("LIBWAVE_SIZE", "640x360").split("x"))
if bake:
    bpy.ops.wm.save_as_mainfile(filepath=bake)
scene.frame_set(frame)
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"LIBWAVE-RENDER wrote {out} (frame {frame})")
