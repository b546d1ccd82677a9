# The live workflow's picture (docs/blender.md, "Live water"): a bay with a shoal built as
# a Blender mesh, Add → libwave Water on it with the panel's defaults, Generate, and a
# Cycles render of one frame from a camera on the headland.
#   blender -b --factory-startup --python scripts/blender-live-render.py -- ADDON_ZIP OUT.png [FRAME]
import math
import os
import sys
import tempfile
import time

import addon_utils
import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
zip_path, png = args[:2]
frame = int(args[2]) if len(args) > 2 else 30
tempfile.tempdir = tempfile.mkdtemp(prefix="libwave-live-render-")
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
pkg = sys.modules["libwave_blender"]
live = sys.modules["libwave_blender.live"]

# The terrain (as tests/blender_live.py): 100 m, open sea along y = 0, a parabolic bay on a
# 1:10 slope, a shoal in its mouth; coloured sand to grass by height.
bpy.ops.mesh.primitive_grid_add(x_subdivisions=160, y_subdivisions=160, size=100.0, location=(50.0, 50.0, 0.0))
terrain = bpy.context.active_object
terrain.name = "Bay"
co = np.empty(3 * len(terrain.data.vertices), np.float32)
terrain.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
x, y = co[:, 0] + 50.0, co[:, 1] + 50.0
shore = 55.0 + 35.0 * (1.0 - ((x - 50.0) / 50.0) ** 2)
z = np.clip(-0.1 * (shore - y), -5.0, 2.0) + 2.5 * np.exp(-((x - 50.0) ** 2 + (y - 38.0) ** 2) / (2 * 7.0 ** 2))
co[:, 2] = np.minimum(z, 2.0)
terrain.data.vertices.foreach_set("co", co.ravel())
terrain.data.update()
terrain.data.polygons.foreach_set("use_smooth", np.ones(len(terrain.data.polygons), bool))
mat = bpy.data.materials.new("terrain")
mat.use_nodes = True
nodes, links = mat.node_tree.nodes, mat.node_tree.links
bsdf = nodes["Principled BSDF"]
bsdf.inputs["Roughness"].default_value = 0.95
geo = nodes.new("ShaderNodeNewGeometry")
sep = nodes.new("ShaderNodeSeparateXYZ")
ramp = nodes.new("ShaderNodeValToRGB")
mapr = nodes.new("ShaderNodeMapRange")
mapr.inputs["From Min"].default_value, mapr.inputs["From Max"].default_value = -5.0, 2.0
links.new(geo.outputs["Position"], sep.inputs["Vector"])
links.new(sep.outputs["Z"], mapr.inputs["Value"])
links.new(mapr.outputs["Result"], ramp.inputs["Fac"])
stops = ramp.color_ramp.elements
stops[0].position, stops[0].color = 0.0, (0.18, 0.16, 0.11, 1)
stops[1].position, stops[1].color = 0.74, (0.75, 0.66, 0.46, 1)
e = stops.new(0.86)
e.color = (0.72, 0.64, 0.45, 1)
e = stops.new(0.95)
e.color = (0.16, 0.3, 0.08, 1)
links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
terrain.data.materials.append(mat)

bpy.ops.object.libwave_water_add()
water = bpy.context.active_object
scene = bpy.context.scene
t0 = time.perf_counter()
bpy.ops.object.libwave_generate()
while live.busy(water):
    live.poll_jobs()
    time.sleep(0.05)
live.poll_jobs()
print(f"LIVE-RENDER generated in {time.perf_counter() - t0:.1f} s: {water.libwave_water.status}")
scene.frame_set(frame)

cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
cam.data.lens = 28
cam.data.clip_end = 5000.0
scene.collection.objects.link(cam)
cam.location = (2.0, 80.0, 18.0)
direction = np.array([58.0, 42.0, 0.0]) - np.array(cam.location)
cam.rotation_euler = (math.atan2(math.hypot(direction[0], direction[1]), -direction[2]), 0.0,
                      math.atan2(direction[1], direction[0]) - math.pi / 2)
scene.camera = cam
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(40), 0.0, math.radians(20))
scene.collection.objects.link(sun)
pkg.make_world(bpy.context, None, "REPLACE")
scene.render.engine = "CYCLES"
scene.cycles.samples = 16
scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
scene.cycles.device = "CPU"
scene.render.resolution_x, scene.render.resolution_y = 480, 270
scene.render.image_settings.file_format = "PNG"
scene.render.filepath = os.path.abspath(png)
bpy.ops.render.render(write_still=True)
print(f"LIVE-RENDER wrote {png}")
