# Inside Blender's Python (Debian's Blender 3.4 embeds Python 3.11, like the module):
# run a libwave scene and build the animated mesh directly from its arrays — no file in
# between. One shape key per frame, switched by CONSTANT keyframes (as the glTF's STEP
# weights), foam and the Fresnel weight as float attributes per frame on the shape keys'
# mesh (the last frame's) and the camera-independent rest UVs.
#
#   PYTHONPATH=<dir of libwave.*.so> blender -b --factory-startup \
#       --python examples/blender_shape_keys.py -- [SCENE.json] [OUT.blend] [FRAMES]
import sys

import bpy
import libwave
import numpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
scene = libwave.read_scene(argv[0]) if argv and argv[0] else libwave.default_scene()
out = argv[1] if len(argv) > 1 else ""
plan = libwave.plan(scene)
anim = libwave.animate(scene, plan, 0, int(argv[2]) if len(argv) > 2 else None)
positions = anim.positions  # (frames, vertices, 3) float32, z up — Blender is z up too

bpy.ops.wm.read_factory_settings(use_empty=True)
mesh = bpy.data.meshes.new(scene.name[:60])
n, tris = anim.vertex_count, anim.triangles
mesh.vertices.add(n)
mesh.vertices.foreach_set("co", positions[0].ravel())
mesh.loops.add(tris.size)
mesh.loops.foreach_set("vertex_index", tris.ravel().astype("int32"))
mesh.polygons.add(len(tris))
mesh.polygons.foreach_set("loop_start", (3 * numpy.arange(len(tris))).astype("int32"))
mesh.polygons.foreach_set("loop_total", numpy.full(len(tris), 3, dtype="int32"))
mesh.update(calc_edges=True)
mesh.validate()
uv = mesh.uv_layers.new(name="rest")
uv.data.foreach_set("uv", anim.texcoords[tris.ravel()].ravel())
if anim.foam.size:
    foam = mesh.attributes.new("foam", "FLOAT", "POINT")
    foam.data.foreach_set("value", anim.foam[0])
    reflect = mesh.attributes.new("reflect", "FLOAT", "POINT")
    reflect.data.foreach_set("value", anim.reflect[0])

obj = bpy.data.objects.new("water", mesh)
bpy.context.scene.collection.objects.link(obj)
obj.shape_key_add(name="Basis", from_mix=False)
bscene = bpy.context.scene
bscene.render.fps = int(round(anim.fps))
bscene.frame_start, bscene.frame_end = 1, anim.frame_count
for k in range(anim.frame_count):
    key = obj.shape_key_add(name=f"frame_{anim.first_frame + k:04d}", from_mix=False)
    key.data.foreach_set("co", positions[k].ravel())
    # One-hot: this key is 1 on its frame only (CONSTANT interpolation = glTF STEP).
    for frame, value in ((k, 0.0), (k + 1, 1.0), (k + 2, 0.0)):
        if 1 <= frame <= anim.frame_count:
            key.value = value
            key.keyframe_insert("value", frame=frame)
    for fcurve in mesh.shape_keys.animation_data.action.fcurves:
        for point in fcurve.keyframe_points:
            point.interpolation = "CONSTANT"

print(f"LIBWAVE-BLENDER vertices={len(mesh.vertices)} triangles={len(mesh.polygons)} "
      f"shape_keys={len(mesh.shape_keys.key_blocks) - 1} fps={bscene.render.fps}")
if out:
    bpy.ops.wm.save_as_mainfile(filepath=out)
