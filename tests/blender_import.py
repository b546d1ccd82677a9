# Imports a libwave animation.glb into Blender (run as: blender -b --factory-startup
# --python tests/blender_import.py -- FILE FPS FRAMES VERTICES) and checks that the
# morph targets arrive as shape keys driven so that frame k shows exactly frame_k.
import sys

import bpy
import numpy

numpy.bool = bool  # Debian 12's Blender 3.4 importer uses numpy.bool, removed in numpy 1.24

path, fps, frames, vertices = sys.argv[sys.argv.index("--") + 1:][:4]
form = (sys.argv[sys.argv.index("--") + 1:] + ["morph"])[4]
fps, frames, vertices = float(fps), int(frames), int(vertices)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
# Set before importing: the importer converts seconds with the scene's fps.
scene.render.fps = round(fps)
scene.render.fps_base = round(fps) / fps
bpy.ops.import_scene.gltf(filepath=path)
# The water; the file also carries the seafloor, a camera and the sun.
meshes = [o for o in scene.objects if o.type == "MESH" and o.name != "seafloor"]
errors = []
if sorted(o.name for o in scene.objects if o.type != "MESH" or o.name == "seafloor")[:3] != ["camera", "seafloor", "sun"]:
    errors.append("expected the seafloor, camera and sun beside the water, got " +
                  str(sorted(o.name for o in scene.objects if o.type != "MESH" or o.name == "seafloor")))
if form == "nodes":
    # One object per frame, each shown (scale 1) only on its own frame.
    if len(meshes) != frames:
        errors.append(f"expected {frames} mesh objects (one per frame), got {len(meshes)}")
    by_name = {o.name: o for o in meshes}
    for f in range(0, frames, max(1, frames // 7)):
        scene.frame_set(f)
        shown = sorted(o.name for o in meshes if o.matrix_world.to_scale()[0] > 0.5)
        if shown != ["frame_%04d" % f]:
            errors.append(f"frame {f} shows {shown}")
elif len(meshes) != 1:
    errors.append(f"expected one mesh object, got {len(meshes)}")
else:
    obj = meshes[0]
    keys = obj.data.shape_keys.key_blocks if obj.data.shape_keys else []
    if len(obj.data.vertices) != vertices:
        errors.append(f"{len(obj.data.vertices)} vertices, expected {vertices}")
    if len(keys) != frames + 1:
        errors.append(f"{len(keys)} shape keys, expected {frames} + basis")
    for f in range(frames):
        scene.frame_set(f)
        on = [k.name for k in keys[1:] if k.value > 0.5]
        if on != ["frame_%04d" % f]:
            errors.append(f"frame {f} shows {on}")
    # The compatibility layout: TEXCOORD_1 = (R, T), TEXCOORD_2 = (foam, 0) arrive as
    # UV maps (Blender stores 1 - v); R + T = 1 at every loop corner of frame 0.
    uvs = obj.data.uv_layers
    if len(uvs) != 3:
        errors.append(f"{len(uvs)} UV maps, expected 3 (TEXCOORD_0, and R/T and foam in TEXCOORD_1/2)")
    else:
        rt = uvs[1].data
        worst = max(abs(rt[i].uv[0] + (1.0 - rt[i].uv[1]) - 1.0) for i in range(0, len(rt), 97))
        if worst > 1e-4:  # the quantised file stores UVs as uint16 (1.5e-5 steps)
            errors.append(f"R + T differs from 1 by {worst} in the second UV map")
        foam = [uvs[2].data[i].uv[0] for i in range(len(uvs[2].data))]
        if not (min(foam) >= 0.0 and max(foam) <= 1.0):
            errors.append(f"foam outside [0, 1]: {min(foam)} .. {max(foam)}")
for e in errors:
    print("BLENDER-IMPORT-ERROR", e)
print("BLENDER-IMPORT", "ok" if not errors else "failed")
sys.exit(1 if errors else 0)
