# Live water in Blender (docs/blender.md, "Live water"): a factory-settings Blender 3.4
# with no PYTHONPATH installs the add-on's zip, builds a 100 m bay with a shoal as a mesh
# with bpy, adds libwave water on it and generates. Checks: the operator returns before
# the work is done and the progress moves; the water then animates over the loop and its
# foam attribute changes; a second Generate reuses the cache (no recompute: timed); a
# changed swell recomputes; the exported scene JSON run by `wave run` gives the live
# frames' positions; a terrain with no water below the level and a non-mesh object give
# an operator report, not a traceback.
#   blender -b --factory-startup --python tests/blender_live.py -- ADDON_ZIP WAVE_EXE OUT_DIR
import json
import math
import os
import shutil
import subprocess
import sys
import time

import addon_utils
import bpy
import numpy as np

zip_path, wave_exe, out = sys.argv[sys.argv.index("--") + 1:][:3]
errors = []


def check(ok, what):
    if not ok:
        errors.append(what)
        print("FAILED:", what, flush=True)


shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
live = sys.modules["libwave_blender.live"]
frames = sys.modules["libwave_blender.frames"]
check("libwave" not in sys.modules, "a libwave module on Blender's path was loaded (this test needs the zip's own)")
# The cache of an unsaved .blend lives in the temporary folder: point it into OUT_DIR.
os.environ["TMPDIR"] = out
import tempfile  # noqa: E402
tempfile.tempdir = out

# The terrain: 100 m × 100 m, open sea along y = 0 (5 m deep), a parabolic bay whose beach
# runs from the headlands (y = 55) to the bay head (y = 90) on a 1:10 slope, and a
# Gaussian shoal (2.5 m high) in the bay's mouth; moved and turned as an object is.
bpy.ops.mesh.primitive_grid_add(x_subdivisions=100, y_subdivisions=100, size=100.0, location=(50.0, 50.0, 0.0))
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

bpy.ops.object.libwave_water_add()
water = bpy.context.active_object
settings = water.libwave_water
check(settings.is_water and settings.terrain == terrain, "Add → libwave Water did not pick the active terrain")
swell_dir = settings.swells[0].direction
check(abs(math.sin(swell_dir) - 1.0) < 0.2, f"the default swell does not run from the open sea up the bay ({math.degrees(swell_dir):.0f}°)")
settings.swells[0].period = 5.0
settings.swells[0].height = 0.6
settings.swells[0].direction = math.pi / 2
bpy.context.scene.render.fps = 12  # a short loop for the test: 60 frames


def wait(water, limit=120.0):
    """Polls as the UI's timer does; returns (progress samples, seconds)."""
    samples, t0 = [], time.perf_counter()
    while live.busy(water) and time.perf_counter() - t0 < limit:
        live.poll_jobs()
        samples.append(water.libwave_water.progress)
        time.sleep(0.02)
    live.poll_jobs()
    return samples, time.perf_counter() - t0


def positions(obj):
    dg = bpy.context.evaluated_depsgraph_get()
    me = obj.evaluated_get(dg).data
    a = np.empty(3 * len(me.vertices), np.float32)
    me.vertices.foreach_get("co", a)
    return a.reshape(-1, 3)


def foam(obj):
    a = obj.data.attributes["foam"]
    v = np.empty(len(a.data), np.float32)
    a.data.foreach_get("value", v)
    return v


# Generate: the operator returns at once, the work goes on, the progress moves.
t0 = time.perf_counter()
result = bpy.ops.object.libwave_generate()
returned = time.perf_counter() - t0
check(result == {"FINISHED"}, f"generate returned {result}")
check(live.busy(water), "the operator returned after the work was done (not in the background)")
job = live.job_of(water)
progress, took = wait(water)
first_frame_s = job.first_frame_s if job else None
check(not live.busy(water), "the generate did not finish in 120 s")
check(settings.status.startswith(("60 frames", "cached")) and "failed" not in settings.status, f"status: {settings.status}")
distinct = sorted(set(round(p, 3) for p in progress))
check(len(distinct) >= 4 and all(b >= a for a, b in zip(progress, progress[1:])) and settings.progress == 1.0,
      f"the progress did not move steadily to 1: {distinct[:12]}")
print(f"LIVE generate: operator returned in {returned:.3f} s, first frame after {first_frame_s:.2f} s, "
      f"done in {took:.2f} s, {len(distinct)} progress values", flush=True)
cache = settings.cache
check(os.path.isfile(os.path.join(cache, "index.json")) and os.path.isfile(os.path.join(cache, "done.json")),
      f"no complete cache in {cache!r}")

# The water animates over the loop and its foam changes.
scene = bpy.context.scene
check((scene.frame_start, scene.frame_end) == (0, 59), f"frame range {scene.frame_start} … {scene.frame_end}, expected 0 … 59")
scene.frame_set(0)
p0, f0 = positions(water), foam(water)
moved, foams = [], [f0]
for k in (15, 30, 45):
    scene.frame_set(k)
    moved.append(float(np.abs(positions(water)[:, 2] - p0[:, 2]).max()))
    foams.append(foam(water))
scene.frame_set(60)
check(np.array_equal(positions(water), p0), "frame 60 (the loop's end) is not frame 0 again")
check(min(moved) > 0.05, f"the water barely moves over the loop: {moved}")
check(max(float(np.abs(f - f0).max()) for f in foams[1:]) > 0.05 and max(float(f.max()) for f in foams) > 0.2,
      "the foam attribute does not change over the loop")
check(float(water.matrix_world.translation.z) == 0.0, "the water is not at the water level")

# A second Generate with nothing changed: the cache, no recompute.
t0 = time.perf_counter()
result = bpy.ops.object.libwave_generate()
again = time.perf_counter() - t0
check(result == {"FINISHED"} and not live.busy(water) and settings.cache == cache and "cached" in settings.status,
      f"the second generate did not reuse the cache ({settings.status})")
scene.frame_set(30)
check(moved[1] > 0 and float(np.abs(positions(water)[:, 2] - p0[:, 2]).max()) == moved[1], "the cached frames differ")
print(f"LIVE cache: second generate {again:.3f} s (first {took:.2f} s)", flush=True)
check(again < 0.5 * took, f"the second generate took {again:.2f} s, the first {took:.2f} s: recomputed?")

# A changed swell recomputes (a new cache entry), and the old one is dropped.
settings.swells[0].height = 0.9
bpy.ops.object.libwave_generate()
check(live.busy(water), "a changed swell did not recompute")
wait(water)
check(settings.cache != cache and os.path.isfile(os.path.join(settings.cache, "done.json")), "no new cache for the new swell")
check(not os.path.exists(cache), "the stale cache entry is still there")
scene.frame_set(0)
p_new = positions(water)
check(p_new.shape != p0.shape or not np.array_equal(p_new, p0), "the new swell's frame 0 is the old one's")

# The exported scene JSON, run by `wave run`, gives the live frames.
scene_json = os.path.join(out, "export", "bay.json")
os.makedirs(os.path.dirname(scene_json))
check(bpy.ops.object.libwave_export_scene(filepath=scene_json) == {"FINISHED"}, "export failed")
doc = json.load(open(scene_json))
check(doc["seafloor"]["source"] == "bay-terrain.ply" and os.path.isfile(os.path.join(out, "export", "bay-terrain.ply")),
      f"the exported scene does not reference its terrain: {doc['seafloor']}")
t0 = time.perf_counter()
r = subprocess.run([wave_exe, "run", scene_json, "-o", os.path.join(out, "farm"), "-q"], capture_output=True, text=True)
check(r.returncode == 0, f"wave run failed: {r.stderr}")
if r.returncode == 0:
    farm = frames.Animation(os.path.join(out, "farm", "index.json"))
    mine = frames.Animation(os.path.join(settings.cache, "index.json"))
    check(farm.frame_count == mine.frame_count == 60, f"frames: wave run {farm.frame_count}, live {mine.frame_count}")
    worst = max(float(np.abs(farm.frame(k).positions - mine.frame(k).positions).max()) for k in range(mine.frame_count))
    worst_foam = max(float(np.abs(farm.frame(k).foam - mine.frame(k).foam).max()) for k in range(mine.frame_count))
    check(worst == 0.0 and worst_foam == 0.0, f"wave run's frames differ from the live ones by {worst} m (foam {worst_foam})")
    print(f"LIVE farm: wave run {time.perf_counter() - t0:.2f} s, {farm.frame_count} frames, largest difference {worst} m", flush=True)

# Saved: the cache moves from the temporary folder beside the .blend, and still plays.
blend = os.path.join(out, "saved", "bay.blend")
os.makedirs(os.path.dirname(blend))
scene.frame_set(7)
before = positions(water)
bpy.ops.wm.save_as_mainfile(filepath=blend)
check(os.path.dirname(settings.cache) == os.path.join(out, "saved", "bay_libwave") and
      os.path.isfile(os.path.join(settings.cache, "index.json")), f"the cache did not move beside the .blend: {settings.cache}")
scene.frame_set(8)
scene.frame_set(7)
check(np.array_equal(positions(water), before), "the moved cache plays other frames")
# Opened again: the water finds its cache beside the .blend and plays it.
bpy.ops.wm.open_mainfile(filepath=blend)
water = bpy.data.objects["libwave Water"]
settings, scene, terrain = water.libwave_water, bpy.context.scene, bpy.data.objects["Bay"]
bpy.context.view_layer.objects.active = water
scene.frame_set(8)
scene.frame_set(7)
check(settings.cache.startswith(os.path.join(out, "saved")) and np.array_equal(positions(water), before),
      f"the reopened .blend does not play its cache ({settings.cache})")

# Cancel: the work stops after its current step, nothing of it stays, the cache in use is kept.
kept = settings.cache
settings.swells[0].period = 7.0
bpy.ops.object.libwave_generate()
part = live.job_of(water).part
check(bpy.ops.object.libwave_cancel() == {"FINISHED"}, "cancel failed")
wait(water)
check(settings.status == "cancelled" and not os.path.exists(part) and settings.cache == kept,
      f"cancel: status {settings.status!r}, part left: {os.path.exists(part)}, cache {settings.cache}")
settings.swells[0].period = 5.0


# The panel draws every setting it names (no window here: a stand-in layout checks the names).
class Layout:
    use_property_split = False
    enabled = True

    def __getattr__(self, name):
        return lambda *a, **k: self

    def prop(self, data, name, **k):
        check(hasattr(data, name), f"the panel draws {name}, which {type(data).__name__} has not")
        return self

    def operator(self, idname, **k):
        mod, name = idname.split(".")
        check(hasattr(getattr(bpy.ops, mod), name), f"the panel's operator {idname} does not exist")
        return self


panel = live.OBJECT_PT_libwave_water
settings.swells.add()
panel.draw(type("P", (), {"layout": Layout()})(), bpy.context)
check(panel.poll(bpy.context), "the panel does not show for the water")
settings.swells.remove(1)

# Every setting makes a scene libwave accepts: two swells (the second's direction from an
# empty turned 30°), wind waves, breakers, no far field, each quality.
libwave = frames._libwave_module()
bpy.ops.object.empty_add(rotation=(0.0, 0.0, math.radians(30.0)))
empty = bpy.context.active_object
bpy.context.view_layer.objects.active = water
second = settings.swells.add()
second.direction_object = empty
settings.wind, settings.breakers, settings.far_field = True, True, False
for quality in ("DRAFT", "MEDIUM", "HIGH"):
    settings.quality = quality
    setup = live.Setup(bpy.context, water)
    live.write_ply(os.path.join(out, "terrain.ply"), setup.vertices, setup.triangles)  # the scene's /seafloor must exist
    parsed = libwave.Scene(setup.document, out)
    if quality == "DRAFT":  # planned too (the frames not computed): libwave takes every combination
        t0 = time.perf_counter()
        planned = libwave.plan(parsed, seafloor=setup.seafloor(libwave))
        print(f"LIVE every setting: draft plan {time.perf_counter() - t0:.2f} s, loop {planned.loop_period} s", flush=True)
    check(parsed.get("/gerstner/0/direction") == [round(math.cos(math.radians(30.0)), 12), 0.5] and
          parsed.get("/waves/0/direction") == [0.0, 1.0] and
          parsed.get("/breakers") == "jeschke" and parsed.get("/ocean/wind_speed") == 8.0, f"{quality}: {setup.document}")
settings.swells.remove(1)
settings.wind, settings.breakers, settings.far_field, settings.quality = False, False, True, "MEDIUM"

# The terrain turned 90° about z and Blender units of 2 m: its world-space triangles in
# metres (float32 rounding on the turned border: no ring of land), the water scaled back.
scene.unit_settings.scale_length = 2.0
terrain.rotation_euler = (0.0, 0.0, math.pi / 2)
settings.swells[0].direction = math.pi  # the open sea now lies towards +x
bpy.ops.object.libwave_generate()
wait(water)
setup = live.Setup(bpy.context, water)
check(settings.status.startswith("60 frames") and setup.seafloor(libwave).stats()["nodata_count"] == 0 and
      tuple(water.scale) == (0.5, 0.5, 0.5), f"turned, 2 m units: {settings.status}, scale {tuple(water.scale)}")
scene.frame_set(10)
v = positions(water) * 0.5  # Blender units, as the scene shows them
check(abs(float(np.median(v[:, 2]))) < 0.2 and float(np.abs(v[:, :2]).max()) > 100.0,
      f"the water in 2 m units: median height {float(np.median(v[:, 2]))} BU")
scene.unit_settings.scale_length = 1.0
terrain.rotation_euler = (0.0, 0.0, 0.0)
settings.swells[0].direction = math.pi / 2

# Input it cannot use: a clear report, not a traceback.
def report_of(**change):
    for k, v in change.items():
        setattr(settings, k, v)
    try:
        r = bpy.ops.object.libwave_generate()
        return f"no error ({r})"
    except RuntimeError as e:  # an operator's ERROR report, raised to the calling script
        return str(e)


message = report_of(water_level=-20.0)
check("no water" in message and "Traceback" not in message and not live.busy(water), f"dry terrain: {message}")
print(f"LIVE dry terrain: {message.strip()}")
settings.water_level = 0.0
bpy.ops.object.text_add()
text = bpy.context.active_object
bpy.context.view_layer.objects.active = water
try:
    settings.terrain = text
    message = report_of()
except (TypeError, ValueError, RuntimeError) as e:  # the picker refuses it outright
    message = f"refused by the picker: {e}"
check(("not a mesh" in message or "refused" in message) and "Traceback" not in message, f"non-mesh object: {message}")
print(f"LIVE non-mesh: {message.strip()}")

print("\n".join(errors) if errors else "LIBWAVE-LIVE ok", flush=True)
sys.exit(1 if errors else 0)
