# Run by ctest inside Blender (PYTHONPATH at the built module): the example builds the
# mesh from libwave's arrays in Blender's own Python; then Blender's evaluated mesh at
# each frame must be libwave's frame (the shape keys switch one-hot, CONSTANT).
import runpy
import sys

import bpy
import numpy

example, scene_path = sys.argv[sys.argv.index("--") + 1:][:2]
sys.argv = [example, "--", scene_path, "", "6"]
result = runpy.run_path(example, run_name="__main__")
anim = result["anim"]
obj = bpy.data.objects["water"]
assert len(obj.data.shape_keys.key_blocks) == anim.frame_count + 1
worst = 0.0
for k in range(anim.frame_count):
    bpy.context.scene.frame_set(k + 1)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    co = numpy.empty(3 * len(evaluated.vertices), dtype=numpy.float32)
    evaluated.vertices.foreach_get("co", co)
    worst = max(worst, float(numpy.abs(co.reshape(-1, 3) - anim.positions[k]).max()))
assert worst < 1e-5, f"Blender's frames differ from libwave's by {worst} m"
print(f"LIBWAVE-BLENDER-CHECK frames={anim.frame_count} worst={worst:.2e}")
