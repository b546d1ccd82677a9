# Peer measurement for bench/RESULTS.md: Blender's Ocean modifier (Tessendorf FFT, in
# Blender 3.4 from Debian) per frame at the grids of bench_ocean.cpp, foam and normals
# on, the same gale as examples/open-ocean.json. Run by bench/peers/ocean_side_by_side.sh:
#   blender -b --factory-startup --python bench/peers/blender_ocean.py
import time

import bpy

for resolution, grid in ((16, 256), (32, 1024)):  # Blender's grid is resolution² (probed: 16 → 257² vertices)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_plane_add()
    obj = bpy.context.active_object
    ocean = obj.modifiers.new("ocean", "OCEAN")
    ocean.geometry_mode = "GENERATE"
    ocean.resolution = ocean.viewport_resolution = resolution
    ocean.spatial_size = 1000
    ocean.spectrum = "PHILLIPS"
    ocean.wind_velocity = 31.0
    ocean.wave_scale_min = 0.5
    ocean.choppiness = 1.6
    ocean.use_normals = True
    ocean.use_foam = True
    ocean.foam_layer_name = "foam"
    ocean.foam_coverage = 0.4
    # Three rounds of 12 frames, the median round (a shared machine swings a single
    # round by tens of per cent, as it does libwave's repetitions).
    frames, rounds, vertices = 12, [], 0
    for r in range(3):
        seconds = 0.0
        for f in range(frames + 1):
            ocean.time = (r * (frames + 1) + f) / 24.0
            start = time.perf_counter()
            depsgraph = bpy.context.evaluated_depsgraph_get()
            depsgraph.update()
            mesh = obj.evaluated_get(depsgraph).data  # the generated mesh with normals and foam
            vertices = len(mesh.vertices)
            if f > 0:  # a round's first frame is not counted (the very first also builds the spectrum)
                seconds += time.perf_counter() - start
        rounds.append(1000.0 * seconds / frames)
    rounds.sort()
    print(f"BLENDER-OCEAN grid={grid} vertices={vertices} ms_per_frame={rounds[1]:.1f} "
          f"rounds={'/'.join(f'{x:.1f}' for x in rounds)}")
