#!/usr/bin/env python3
"""libwave stage by stage from Python: real bathymetry in, one animated frame out.

    python3 examples/pipeline.py OKUSHIRI_ASC OUT.glb [FRAME]

The same stages as examples/pipeline.cpp, with NumPy arrays between them: the Okushiri
grid (1:400 laboratory model) is read through GDAL, sliced into isobaths, a 0.6 s swell
is traced as Gonzato's adaptive fronts whose heights come from the refraction–diffraction
field, the fronts become ray strips, the water is meshed and takes the strips' fields
(the field's where no strip passed), a skirt continues it to the horizon, Gonzato's
profile moves it at frame FRAME (default 3, 25 frames/s) and the skirt follows the
border's fitted swell, breaking foam is added (the skirt takes the border's), the frame is untangled, its normals and Fresnel weights computed, and it is
written as a .glb. The scene pipeline then gives the same frame of the same scene, and
every array must be equal bit for bit (exit 1 otherwise; 2 on bad input).
"""
import sys
from typing import Any, Dict

import numpy as np

import libwave

PERIOD, AMPLITUDE, DIRECTION = 0.6, 0.004, (1.0, 0.15)
CAMERA = (2.5, -2.0, 1.2)
FPS = 25.0


def frame_by_stages(grid_path: str, frame: int) -> Dict[str, Any]:
    seafloor = libwave.read_seafloor(grid_path)
    isobaths = libwave.extract_isobaths(seafloor, spacing=0.01)
    fronts = libwave.trace_fronts(seafloor, PERIOD, AMPLITUDE, DIRECTION, isobaths,
                                  ray_spacing=0.02, step=0.01, split_distance=0.03)
    field = libwave.solve_wave_field(seafloor, PERIOD, AMPLITUDE, DIRECTION)
    libwave.take_field_amplitudes(field, fronts)
    strips = libwave.build_ray_strips(fronts)
    mesh = libwave.mesh_water(seafloor, PERIOD, AMPLITUDE, per_wavelength=16)
    on_mesh = libwave.resample_ray_strips(strips, seafloor, mesh)
    libwave.fill_strip_gaps(field, seafloor, on_mesh)  # where no strip passed, the field's wave
    motion = libwave.plan_gonzato_motion(on_mesh)

    # The far field: a skirt to the horizon (2000 camera heights, at least ten domains and 5 km),
    # moved by the swell's fundamental and first overtone fitted at the border.
    size = float(max(np.ptp(mesh.x), np.ptp(mesh.y)))
    # Its sizes read the depth no shallower than where the swell breaks (H/γ, γ = 0.78).
    skirt = libwave.plan_sea_skirt(seafloor, mesh.x, mesh.y, mesh.triangles, PERIOD, max(2000 * CAMERA[2], 10 * size, 5000.0),
                                   min_depth=2 * AMPLITUDE / 0.78)
    omega = 2 * np.pi / PERIOD
    waves = [(omega, h, DIRECTION, 0.0) for h in (1, 2)]
    times = libwave.far_field_sample_times(PERIOD, len(waves))
    # The waterline: the shoreline under the sand, a film of water left by the troughs.
    waterline = libwave.plan_waterline(mesh, seafloor, AMPLITUDE)

    def moved(s: float) -> "np.ndarray[Any, np.dtype[np.float32]]":
        p = np.ascontiguousarray(motion.evaluate(s), dtype=np.float32)
        waterline.apply(p)
        return p

    far = libwave.plan_far_field(skirt, seafloor, waves, mesh.x, mesh.y, times, np.stack([moved(s) for s in times]))
    x, y = np.concatenate([mesh.x, skirt.x]), np.concatenate([mesh.y, skirt.y])
    triangles = np.concatenate([mesh.triangles, skirt.triangles])
    # Gonzato's sections bounded by their packing (the default) never turn over: no lips.
    untangle = libwave.plan_untangle(x, y, triangles, lips_overturn=False)

    t = frame / FPS
    n = mesh.vertex_count
    positions = np.zeros((n + skirt.vertex_count, 3), np.float32)
    positions[:n] = moved(t)
    far.evaluate(t, positions)
    foam = np.zeros(n + skirt.vertex_count, np.float32)
    foam[:n] = libwave.breaking_foam(on_mesh, motion, t)
    far.foam(foam)  # the border's foam carried onto the skirt with its residual motion
    untangle.apply(positions, foam)
    normals = libwave.vertex_normals(positions, triangles)
    reflect, refract = libwave.fresnel_weights(positions, normals, CAMERA)
    texcoords = libwave.domain_texcoords(seafloor, x, y)
    print(f"stages: {len(isobaths)} isobaths, {fronts.initial_rays + fronts.inserted_rays} rays, "
          f"{len(strips.triangles)} strip triangles, water mesh {mesh.vertex_count} vertices, {len(mesh.triangles)} triangles, "
          f"skirt {skirt.vertex_count} vertices to {skirt.reach:g} m")
    return {"positions": positions, "normals": normals, "texcoords": texcoords, "foam": foam,
            "reflect": reflect, "refract": refract, "triangles": triangles}


def scene(grid_path: str) -> libwave.Scene:
    return libwave.Scene({
        "name": "pipeline example",
        "seafloor": {"source": grid_path},
        "isobaths": {"spacing": 0.01},
        "waves": [{"period": PERIOD, "amplitude": AMPLITUDE, "direction": list(DIRECTION)}],
        "trace": {"ray_spacing": 0.02},
        "fronts": {"step": 0.01, "split_distance": 0.03},
        "camera": {"position": list(CAMERA)},
        "animation": {"fps": FPS},
    })


def main() -> int:
    if len(sys.argv) < 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    grid_path, out = sys.argv[1], sys.argv[2]
    frame = int(sys.argv[3]) if len(sys.argv) > 3 else 3
    try:
        f = frame_by_stages(grid_path, frame)
        with open(out, "wb") as file:
            file.write(libwave.frame_glb(f["positions"], f["normals"], f["triangles"], f["texcoords"], f["foam"],
                                         f["reflect"], f["refract"], fps=FPS, frame=frame))
        print(f"wrote frame {frame} to {out}")
        s = scene(grid_path)
        anim = libwave.animate(s, libwave.plan(s), frame, frame + 1)
        ok = True
        for name in ("positions", "normals", "texcoords", "foam", "reflect", "refract", "triangles"):
            theirs = np.asarray(getattr(anim, name))
            if name not in ("texcoords", "triangles"):
                theirs = theirs[0]
            if theirs.shape != f[name].shape or theirs.tobytes() != f[name].tobytes():
                print(f"differs from the scene pipeline: {name}")
                ok = False
        print("equal to the scene pipeline's frame, bit for bit" if ok else "NOT equal to the scene pipeline's frame")
        return 0 if ok else 1
    except libwave.InputError as e:
        print(f"pipeline: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
