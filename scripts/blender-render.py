# Renders an output of `wave run` through the libwave add-on with Cycles on the CPU:
#   blender -b --factory-startup --python scripts/blender-render.py -- ADDON_ZIP RUN_DIR OUT.png [FRAME]
# The add-on imports the water (positions, foam, reflect, refract per frame); this script
# adds what the .glb does not carry yet: a camera from the open sea, a low sun and a sky.
import math
import os
import sys

import addon_utils
import bpy

addon_zip, run, out = sys.argv[sys.argv.index("--") + 1:][:3]
frame = int((sys.argv[sys.argv.index("--") + 1:] + ["30"])[3])
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
source = os.path.join(run, "index.json") if os.path.exists(os.path.join(run, "index.json")) else os.path.join(run, "animation.glb")
bpy.ops.import_scene.libwave(filepath=source)
scene = bpy.context.scene
water = next(o for o in scene.objects if o.type == "MESH")
xs = [v.co.x for v in water.data.vertices]
ys = [v.co.y for v in water.data.vertices]
cx, cy, size = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, max(max(xs) - min(xs), max(ys) - min(ys))
cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(cam)
cam.location = (cx - 0.35 * size, cy - 0.75 * size, 0.28 * size)
direction = (cx - cam.location.x, cy + 0.1 * size - cam.location.y, -cam.location.z)
cam.rotation_euler = (math.atan2(math.hypot(direction[0], direction[1]), -direction[2]), 0.0,
                      math.atan2(direction[1], direction[0]) - math.pi / 2)
cam.data.lens = 28
scene.camera = cam
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(60), 0.0, math.radians(160))
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.45, 0.6, 0.8, 1.0)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
scene.world = world
# A sandy bottom under the water, so the transmission has something to show.
bpy.ops.mesh.primitive_plane_add(size=size * 1.4, location=(cx, cy, -2.0))
sand = bpy.data.materials.new("sand")
sand.use_nodes = True
sand.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.55, 0.45, 0.3, 1.0)
bpy.context.object.data.materials.append(sand)
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 16
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = 480, 270
scene.frame_set(frame)
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"LIBWAVE-RENDER wrote {out} (frame {frame})")
