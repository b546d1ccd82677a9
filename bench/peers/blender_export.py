# Peer measurement for bench/RESULTS.md: Blender's own glTF exporter on a wavy grid of
# the same sizes as bench_export.cpp (one static frame, positions + normals + UVs).
#   blender -b --factory-startup --python bench/peers/blender_export.py -- OUT_DIR
import math
import os
import sys
import time

import bpy
import numpy

numpy.bool = bool  # Debian 12's Blender 3.4 glTF add-on uses numpy.bool (removed in numpy 1.24)

out_dir = sys.argv[sys.argv.index("--") + 1]
for side in (257, 1000):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side - 1, y_subdivisions=side - 1, size=side * 0.1)
    obj = bpy.context.active_object
    co = numpy.empty(len(obj.data.vertices) * 3, dtype=numpy.float32)
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    co[:, 2] = 0.3 * numpy.sin(0.8 * co[:, 0] + 0.3 * co[:, 1])
    obj.data.vertices.foreach_set("co", co.ravel())
    obj.data.update()
    path = os.path.join(out_dir, f"blender-{side}.glb")
    start = time.perf_counter()
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLB", export_normals=True, export_texcoords=True,
                              export_animations=False)
    seconds = time.perf_counter() - start
    print(f"BLENDER-EXPORT vertices={len(obj.data.vertices)} seconds={seconds:.3f} bytes={os.path.getsize(path)}")
