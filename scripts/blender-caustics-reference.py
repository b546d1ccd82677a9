# The caustics on the seafloor seen from straight above, the water hidden from the
# camera (it still refracts the light): either as libwave's maps light them through the
# add-on ("map"), or path-traced by Cycles itself with manifold next-event estimation
# (Blender >= 3.2's shadow caustics: the sun a caustics light, the water a caster, the
# floor a receiver; "cycles"). docs/underwater.md compares the two.
#   blender -b --factory-startup --python scripts/blender-caustics-reference.py -- ADDON_ZIP RUN_DIR OUT.png FRAME map|cycles [SAMPLES]
import os
import sys
import time

import addon_utils
import bpy

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip, run, out, frame, mode = args[:5]
samples = int(args[5]) if len(args) > 5 else (16 if mode == "map" else 256)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
source = os.path.join(run, "index.json") if os.path.exists(os.path.join(run, "index.json")) else os.path.join(run, "animation.glb")
bpy.ops.import_scene.libwave(filepath=source, caustics=mode == "map")
scene = bpy.context.scene
water = next(o for o in scene.objects if "libwave_source" in o)
floor = next(o for o in scene.objects if o.name.startswith("libwave seafloor"))
sun = next(o for o in scene.objects if o.type == "LIGHT")
water.visible_camera = False  # the floor seen without the surface in front of it
if mode == "cycles":
    sun.data.cycles.is_caustics_light = True
    water.cycles.is_caustics_caster = True
    floor.cycles.is_caustics_receiver = True
    # MNEE needs a plain refracting caster: the water as glass of water's index.
    glass = bpy.data.materials.new("water glass")
    glass.use_nodes = True
    nodes = glass.node_tree.nodes
    nodes.remove(nodes.get("Principled BSDF"))
    bsdf = nodes.new("ShaderNodeBsdfGlass")
    bsdf.inputs["IOR"].default_value = 1.33
    bsdf.inputs["Roughness"].default_value = 0.0
    glass.node_tree.links.new(bsdf.outputs["BSDF"], nodes.get("Material Output").inputs["Surface"])
    water.data.polygons.foreach_set("use_smooth", [True] * len(water.data.polygons))  # MNEE needs smooth normals
    water.data.materials.clear()
    water.data.materials.append(glass)
    sun.data.angle = 0.00925  # the real sun's 0.53°
xs = [v.co.x for v in floor.data.vertices]
ys = [v.co.y for v in floor.data.vertices]
cam = bpy.data.objects.new("top", bpy.data.cameras.new("top"))
cam.data.type = "ORTHO"
cam.data.ortho_scale = max(max(xs) - min(xs), max(ys) - min(ys))
cam.location = ((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, 50.0)
cam.data.clip_end = 200.0
scene.collection.objects.link(cam)
scene.camera = cam
world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.45, 0.6, 0.8, 1.0)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.3
scene.world = world
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.max_bounces = 8
scene.cycles.transmission_bounces = 8
scene.render.resolution_x = scene.render.resolution_y = 400
scene.frame_set(int(frame))
scene.render.filepath = out
start = time.time()
bpy.ops.render.render(write_still=True)
print(f"LIBWAVE-CAUSTICS {mode} wrote {out} (frame {frame}, {samples} samples) in {time.time() - start:.1f} s")
