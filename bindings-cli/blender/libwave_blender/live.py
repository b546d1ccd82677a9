"""libwave water generated live from a terrain mesh in the scene (docs/blender.md, "Live water").

Add → libwave Water makes a water object; its panel (Properties editor → Object → libwave
Water) picks any mesh object as the seafloor and sets the water level, the swells, wind
waves, breakers, foam, the far field and the quality. Generate hands the terrain's
evaluated world-space triangles to libwave in memory (libwave.Seafloor.from_triangles)
and runs the scene on a worker thread (libwave releases the GIL), a timer polling it: the
UI stays live, the panel shows the progress and a Cancel button. The frames are written
in the files form (index.json and frames/frame-NNNN.glb, as `wave run` writes it) into a
cache folder beside the .blend (a temporary folder while it is unsaved, moved beside it
on save) named by a hash of the terrain, the settings and libwave's version: a second
Generate with nothing changed plays the cached frames without computing, a change
computes a new entry. The water plays them through the add-on's importer (frames.py,
the frame-change handler), from the first frame on while the rest are computed.
Export scene JSON writes the same scene for `wave run` (the terrain as a PLY file beside
it): a farm run gives the frames the live Generate gives.
"""
import hashlib
import json
import math
import os
import shutil
import sys
import tempfile
import threading
import time

import bpy
import numpy as np
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from . import frames

GRAVITY = 9.81
CACHE_VERSION = 1  # part of the cache key: bump when what a setting means changes
FIRST_CHUNK = 1    # frames of the first chunk: the water plays as soon as frame 0 is written
CHUNK = 8          # frames per later chunk (progress and Cancel between chunks)
_QUALITY = {"DRAFT": 0.5, "MEDIUM": 1.0, "HIGH": 2.0}
_jobs = {}  # water object name → Job


def _pkg():
    return sys.modules[__package__]


def _libwave():
    return frames._libwave_module()


class LiveError(Exception):
    """Input the live water cannot use; the message is for the operator's report."""


# ---------------------------------------------------------------------------------------
# Settings (saved in the .blend with the object)
# ---------------------------------------------------------------------------------------

def _is_mesh(self, obj):
    return obj.type == "MESH" and not obj.libwave_water.is_water


def _is_empty(self, obj):
    return obj.type == "EMPTY"


class LIBWAVE_PG_swell(bpy.types.PropertyGroup):
    period: FloatProperty(name="Period (s)", default=6.0, min=0.5, max=30.0,
                          description="The swell's period; its deep-water wavelength is g T² / 2π (6 s: 56 m)")
    height: FloatProperty(name="Height (m)", default=0.6, min=0.01, soft_max=8.0, max=30.0,
                          description="Deep-water wave height, trough to crest (twice the amplitude)")
    direction: FloatProperty(name="Direction", subtype="ANGLE", default=math.pi / 2,
                             description="Where the swell travels to, counter-clockwise from +X (90°: towards +Y)")
    direction_object: PointerProperty(name="From empty", type=bpy.types.Object, poll=_is_empty,
                                      description="An empty whose local +X axis (in the horizontal plane) gives the "
                                                  "direction instead of the dial")


class LIBWAVE_PG_water(bpy.types.PropertyGroup):
    is_water: BoolProperty(default=False, options={"HIDDEN"})
    terrain: PointerProperty(name="Seafloor", type=bpy.types.Object, poll=_is_mesh,
                             description="Any mesh object: its evaluated world-space triangles (modifiers applied) "
                                         "are the seafloor and the land")
    water_level: FloatProperty(name="Water level", subtype="DISTANCE", unit="LENGTH", default=0.0,
                               description="Height of still water (world Z); the terrain below it is under water")
    swells: CollectionProperty(type=LIBWAVE_PG_swell)
    wind: BoolProperty(name="Wind waves", default=False,
                       description="A wind sea (JONSWAP spectrum, FFT) on top of the swell, fading towards the shore")
    wind_speed: FloatProperty(name="Wind (m/s)", default=8.0, min=1.0, max=40.0)
    wind_direction: FloatProperty(name="Wind direction", subtype="ANGLE", default=math.pi / 2,
                                  description="Where the wind blows to, counter-clockwise from +X")
    breakers: BoolProperty(name="Breakers", default=False,
                           description="Jeschke's procedural breakers (curling lips) where the swell breaks; the loop "
                                       "then holds three different crests (three periods)")
    foam_fade: FloatProperty(name="Foam fade (periods)", default=0.3, min=0.02, max=5.0,
                             description="Foam left by a breaking crest fades with this time constant, in the swell's "
                                         "periods")
    foam_onset: FloatProperty(name="Foam onset", default=0.9, min=0.1, max=1.0,
                              description="Foam starts where the wave height reaches this share of the breaking height")
    far_field: BoolProperty(name="Far field", default=True,
                            description="Continue the sea beyond the terrain to the horizon (a coarser skirt carrying "
                                        "the swell)")
    quality: EnumProperty(name="Quality", default="MEDIUM",
                          items=[("DRAFT", "Draft", "Half the rays and nodes: fast previews"),
                                 ("MEDIUM", "Medium", "Rays about 1/40 of the swell's wavelength apart"),
                                 ("HIGH", "High", "Twice the rays and nodes")])
    # State (shown, not edited)
    cache: StringProperty(name="Cache", default="", subtype="DIR_PATH", options={"HIDDEN"})
    key: StringProperty(default="", options={"HIDDEN"})
    progress: FloatProperty(name="Progress", default=0.0, min=0.0, max=1.0, subtype="FACTOR", options={"HIDDEN"})
    status: StringProperty(default="", options={"HIDDEN"})


# ---------------------------------------------------------------------------------------
# The terrain and the scene
# ---------------------------------------------------------------------------------------

def terrain_arrays(context, terrain):
    """(vertices (n, 3) float64 in world space, Blender units; triangles (t, 3) int32) of
    `terrain`'s evaluated mesh (modifiers applied), or LiveError saying what is wrong."""
    if terrain is None:
        raise LiveError("pick a seafloor: any mesh object (the terrain)")
    if terrain.type != "MESH":
        raise LiveError(f"'{terrain.name}' is {'an' if terrain.type[0] in 'AEIOU' else 'a'} {terrain.type.lower()} object, "
                        "not a mesh: pick a mesh object as the seafloor (convert it with Object → Convert → Mesh)")
    depsgraph = context.evaluated_depsgraph_get()
    evaluated = terrain.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        mesh.calc_loop_triangles()
        n, t = len(mesh.vertices), len(mesh.loop_triangles)
        co = np.empty(3 * n, np.float32)
        mesh.vertices.foreach_get("co", co)
        tris = np.empty(3 * t, np.int32)
        mesh.loop_triangles.foreach_get("vertices", tris)
    finally:
        evaluated.to_mesh_clear()
    if t == 0:
        raise LiveError(f"'{terrain.name}' has no faces: the seafloor needs a surface (a grid, a sculpted plane)")
    m = np.array(terrain.matrix_world, np.float64)
    world = co.reshape(-1, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]
    return world, tris.reshape(-1, 3)


def swell_direction(swell):
    """The swell's (dx, dy): its empty's local +X in the horizontal plane, else the dial."""
    if swell.direction_object is not None:
        x = np.array(swell.direction_object.matrix_world, np.float64)[:3, 0]
        if math.hypot(x[0], x[1]) > 1e-9:
            return math.atan2(x[1], x[0])
    return swell.direction


def _direction(angle):
    """(dx, dy) of an angle (rad) held in float32 (a dial, an empty's matrix): the angle
    rounded to 10⁻⁴ degree first, so that 90° is [0, 1], not [−4.4e-08, 1]."""
    a = math.radians(round(math.degrees(float(angle)), 4))
    return [round(math.cos(a), 12) + 0.0, round(math.sin(a), 12) + 0.0]


def _setting(v):
    """A panel value (Blender keeps float32) as the decimal it was typed as: 0.3, not 0.30000001192092896."""
    return float(f"{float(v):.7g}")


def scene_document(settings, fps, extent, depth, name):
    """The scene `wave run` would run (docs/scene.md) for the panel's settings, a terrain
    `extent` m across and `depth` m deep at its deepest; /seafloor is added by the caller."""
    q = _QUALITY[settings.quality]
    swells = list(settings.swells)
    if not swells:
        raise LiveError("add a swell (the + beside Swells)")
    first = swells[0]
    wavelength = GRAVITY * first.period ** 2 / (2.0 * math.pi)
    # Rays about 1/40 of the swell's wavelength apart, at most 200 across the terrain; the
    # water mesh's vertices per local wavelength fall as the terrain grows past 150 m
    # (16 there, 6 for a kilometre): the first frame stays within seconds (bench/RESULTS.md).
    ray = max(wavelength / 40.0, extent / 200.0) / q
    per_wavelength = max(4, min(64, round(16.0 * q * min(1.0, math.sqrt(150.0 / extent)))))
    doc = {
        "name": f"libwave water over {name}",
        "isobaths": {"spacing": max(depth / 20.0, 0.05)},
        "waves": [],
        "trace": {"ray_spacing": ray},
        # Past 150 m a ray is inserted where neighbours part by 2 spacings (1.2 below): a
        # kilometre's refraction round headlands and shoals inserted thousands.
        "fronts": {"step": 0.4 * ray, "split_distance": (1.2 if extent <= 150.0 else 2.0) * ray},
        "surface": {"water_mesh": {"vertices_per_wavelength": per_wavelength},
                    "far_field": {} if settings.far_field else False},
        "shade": {"foam_fade_periods": _setting(settings.foam_fade), "foam_onset": _setting(settings.foam_onset)},
        "animation": {"fps": fps},
        "outputs": {"form": "files", "codec": "none", "seafloor": False, "camera": False, "sun": False},
    }
    a = swell_direction(first)
    doc["waves"].append({"period": _setting(first.period), "amplitude": _setting(first.height) / 2.0,
                         "direction": _direction(a)})
    if len(swells) > 1:  # the traced surface carries one train; the others ride on it as Gerstner waves
        doc["gerstner"] = []
        for s in swells[1:]:
            a = swell_direction(s)
            doc["gerstner"].append({"wavelength": GRAVITY * _setting(s.period) ** 2 / (2.0 * math.pi),
                                    "amplitude": _setting(s.height) / 2.0,
                                    "direction": _direction(a)})
    loop = _setting(first.period) * (3 if settings.breakers else 1)  # Jeschke's three different crests
    if settings.wind:
        doc["ocean"] = {"spectrum": "jonswap", "wind_speed": _setting(settings.wind_speed),
                        "wind_direction": _direction(settings.wind_direction),
                        "resolution": 64 if q < 1 else 128, "size": max(50.0, min(extent, 400.0)),
                        # a whole multiple of the swell's loop (three periods with breakers), about 10 s
                        "repeat_time": loop * max(1, round(10.0 / loop))}
    if settings.breakers:
        doc["breakers"] = "jeschke"
    return doc


class Setup:
    """What a Generate or an export needs, gathered on the main thread: the terrain in
    metres, the scene, the cache key."""

    def __init__(self, context, water):
        settings = water.libwave_water
        scene = context.scene
        self.unit = scene.unit_settings.scale_length if scene.unit_settings.system != "NONE" else 1.0
        if not self.unit > 0.0:
            self.unit = 1.0
        vertices, self.triangles = terrain_arrays(context, settings.terrain)
        self.vertices = vertices * self.unit  # metres
        self.level = _setting(settings.water_level) * self.unit
        self.offset = 0.0 - self.level  # metres added to the terrain's z: still water at z = 0 (never −0.0)
        self.terrain_name = settings.terrain.name
        lowest = float(self.vertices[:, 2].min())
        if not lowest < self.level:
            raise LiveError(f"no water: '{self.terrain_name}' lies wholly above the water level (its lowest point is at "
                            f"z = {lowest / self.unit:.3g}, the level at {settings.water_level:.3g}): raise the water "
                            "level or lower the terrain")
        lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
        extent = float(max(hi[0] - lo[0], hi[1] - lo[1]))
        if not extent > 0.0:
            raise LiveError(f"'{self.terrain_name}' has no horizontal extent (it stands on edge)")
        q = _QUALITY[settings.quality]
        self.spacing = extent / (200.0 * q)
        fps = scene.render.fps / scene.render.fps_base
        self.document = scene_document(settings, fps, extent, self.level - lowest, self.terrain_name)
        self.document["seafloor"] = {"source": "terrain.ply", "spacing": self.spacing, "vertical_offset": self.offset}
        self.document = json.loads(json.dumps(self.document))  # plain JSON values (the hash's and the file's)
        h = hashlib.sha256()
        for part in (f"libwave {getattr(_libwave(), '__version__', '?')} cache {CACHE_VERSION}",
                     json.dumps(self.document, sort_keys=True)):
            h.update(part.encode())
        h.update(np.ascontiguousarray(self.vertices).tobytes())
        h.update(np.ascontiguousarray(self.triangles, np.int32).tobytes())
        self.key = h.hexdigest()
        self.folder = os.path.join(cache_root(), self.key[:16])

    def seafloor(self, libwave):
        return libwave.Seafloor.from_triangles(self.vertices, self.triangles, spacing=self.spacing,
                                               vertical_offset=self.offset, name=f"Blender object '{self.terrain_name}'")


def cache_root(blend_path=None):
    """Where live frames are cached: `<blend>_libwave/` beside the saved .blend, else a
    folder in the system's temporary directory."""
    path = bpy.data.filepath if blend_path is None else blend_path
    if path:
        folder, name = os.path.split(path)
        return os.path.join(folder, os.path.splitext(name)[0] + "_libwave")
    return os.path.join(tempfile.gettempdir(), "libwave_blender_cache")


def _complete(folder, key):
    try:
        with open(os.path.join(folder, "done.json")) as f:
            return json.load(f).get("key") == key and os.path.exists(os.path.join(folder, "index.json"))
    except (OSError, ValueError):
        return False


def write_ply(path, vertices, triangles):
    """A binary PLY of `vertices` (n, 3) as doubles (exact) and `triangles` (t, 3)."""
    t = np.ascontiguousarray(triangles, np.int32).reshape(-1, 3)
    faces = np.empty(len(t), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    faces["n"], faces["v"] = 3, t
    with open(path, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\ncomment libwave terrain from Blender\nelement vertex {len(vertices)}\n"
                 "property double x\nproperty double y\nproperty double z\n"
                 f"element face {len(t)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        f.write(np.ascontiguousarray(vertices, "<f8").tobytes())
        f.write(faces.tobytes())


# ---------------------------------------------------------------------------------------
# The worker: libwave on a thread (the module releases the GIL), frames written as they come
# ---------------------------------------------------------------------------------------

class Job:
    """One Generate: a thread computing into `folder` + ".part", renamed to `folder` when
    complete. Read by the main thread (poll_jobs) through plain attributes."""

    def __init__(self, setup, water_name):
        self.setup = setup
        self.water = water_name
        self.folder = setup.folder
        self.part = setup.folder + ".part"
        self.cancel = False
        self.progress = 0.0
        self.status = "reading the terrain"
        self.frames_written = 0   # frames listed in the part folder's index.json
        self.frames_total = 0
        self.frames_shown = 0     # what the main thread last played
        self.error = None
        self.done = False
        self.started = time.perf_counter()
        self.first_frame_s = None  # seconds from Generate to frame 0 written
        self.thread = threading.Thread(target=self._run, name=f"libwave {water_name}", daemon=True)

    def start(self):
        self.thread.start()

    def _run(self):
        try:
            self._work()
        except Exception as e:  # libwave.Error, OSError, ... : shown in the panel, never a traceback in the UI
            self.error = frames.printable(str(e)) or type(e).__name__
        finally:
            if self.error is not None or self.cancel:
                shutil.rmtree(self.part, ignore_errors=True)
            self.done = True

    def _work(self):
        libwave = _libwave()
        s = self.setup
        shutil.rmtree(self.part, ignore_errors=True)
        os.makedirs(os.path.join(self.part, "frames"))
        with open(os.path.join(self.part, "scene.json"), "w") as f:
            json.dump(s.document, f, indent=1, sort_keys=True)
        # The terrain as the scene's file too (its /seafloor must name one that exists): the
        # cache then holds what `wave run scene.json` needs to compute these frames again.
        write_ply(os.path.join(self.part, "terrain.ply"), s.vertices, s.triangles)
        seafloor = s.seafloor(libwave)
        self.status, self.progress = "tracing the swell over the terrain", 0.05
        scene = libwave.Scene(s.document, self.part)
        plan = libwave.plan(scene, seafloor=seafloor)
        if self.cancel:
            return
        fps = scene.fps
        total = max(1, round(plan.loop_period * fps))
        self.frames_total = total
        self.status, self.progress = f"frames 0 of {total}", 0.3
        index = {"fps": fps, "loop_frames": total, "loop_period_s": plan.loop_period, "scene": scene.name,
                 "live_key": s.key, "frames": []}
        first = 0
        while first < total and not self.cancel:
            end = min(total, first + (FIRST_CHUNK if first == 0 else CHUNK))
            anim = libwave.animate(scene, plan, first, end)
            for i in range(anim.frame_count):
                k = first + i
                name = f"frames/frame-{k:04d}.glb"
                data = anim.frame_glb(i)
                with open(os.path.join(self.part, name), "wb") as f:
                    f.write(data)
                z = anim.positions[i][:, 2]
                index["frames"].append({"frame": k, "time": k / fps, "file": name,
                                        "content": [{"file": name, "bytes": len(data), "sha256": hashlib.sha256(data).hexdigest()}],
                                        "height_range_m": [float(z.min()), float(z.max())]})
            tmp = os.path.join(self.part, "index.json.tmp")
            with open(tmp, "w") as f:
                json.dump(index, f, indent=1)
            os.replace(tmp, os.path.join(self.part, "index.json"))
            if first == 0:
                self.first_frame_s = time.perf_counter() - self.started
            first = end
            self.frames_written = first
            self.status = f"frames {first} of {total}"
            self.progress = 0.3 + 0.7 * first / total
        if self.cancel:
            return
        with open(os.path.join(self.part, "done.json"), "w") as f:
            json.dump({"key": s.key, "frames": total, "seconds": time.perf_counter() - self.started}, f)
        shutil.rmtree(self.folder, ignore_errors=True)
        os.replace(self.part, self.folder)


def _tag_redraw():
    wm = bpy.context.window_manager
    for window in (wm.windows if wm is not None else []):
        for area in window.screen.areas:
            if area.type in {"PROPERTIES", "VIEW_3D"}:
                area.tag_redraw()


def poll_jobs():
    """Brings every running Generate's state into Blender (the timer calls it, and a
    headless script may): progress and status on the water's settings, the frames
    written so far played, the finished cache adopted. Returns whether any job runs."""
    for name, job in list(_jobs.items()):
        water = bpy.data.objects.get(name)
        if water is None:  # deleted while it ran
            job.cancel = True
            if job.done:
                del _jobs[name]
            continue
        settings = water.libwave_water
        settings.progress = job.progress
        settings.status = job.status
        if job.done:
            del _jobs[name]
            if job.error is not None:
                settings.status = f"failed: {job.error}"
                settings.progress = 0.0
                print(f"libwave: {name}: {job.error}")
                continue
            if job.cancel:
                settings.status = "cancelled"
                settings.progress = 0.0
                continue
            _adopt(bpy.context, water, job.setup, job.folder)
            settings.status = f"{job.frames_total} frames in {time.perf_counter() - job.started:.1f} s " \
                              f"(first frame after {job.first_frame_s:.1f} s)"
            settings.progress = 1.0
            _prune(job.folder)
        elif job.frames_written > job.frames_shown and (job.frames_shown == 0 or
                                                         job.frames_written >= 2 * job.frames_shown + CHUNK):
            # Frame 0 as soon as it is written, then as the frames double: each re-reading of
            # the index and frame 0 holds the UI for a moment (0.2 s on a 59 k-vertex coast).
            job.frames_shown = job.frames_written
            _play(bpy.context, water, job.setup, os.path.join(job.part, "index.json"), final=False)
    _tag_redraw()
    return bool(_jobs)


def _timer():
    return 0.1 if poll_jobs() else None


def busy(water=None):
    return (water.name in _jobs) if water is not None else bool(_jobs)


def job_of(water):
    return _jobs.get(water.name)


# ---------------------------------------------------------------------------------------
# Playing the frames (the importer's machinery: frames.Animation and the frame handler)
# ---------------------------------------------------------------------------------------

def _play(context, water, setup, index, final):
    pkg = _pkg()
    pkg._animations.pop(os.path.abspath(index), None)
    for path in [p for p in pkg._animations if os.path.dirname(p) == os.path.dirname(os.path.abspath(index))]:
        pkg._animations.pop(path, None)
    anim = pkg._animation(os.path.abspath(index))
    mesh = water.data
    shown = water.get("libwave_live_mesh", "")
    # The same frames moved from the job's ".part" folder to the cache: the mesh stays.
    same = shown == anim.path or os.path.dirname(shown) == os.path.dirname(anim.path) + ".part"
    if mesh is None or len(mesh.vertices) != len(anim.first_positions()) or not same \
            or len(mesh.polygons) != len(anim.triangles):
        old = mesh
        mesh = pkg.water_mesh(water.name, anim)
        pkg.set_rest(mesh)
        pkg._smooth(mesh)
        mesh.materials.append(pkg.water_material())
        water.data = mesh
        if old is not None and old.users == 0:
            bpy.data.meshes.remove(old)
    water["libwave_live_mesh"] = anim.path
    water[pkg._PROP] = anim.path
    water["libwave_frame_start"] = 0
    water["libwave_file_normals"] = False
    water.location = (0.0, 0.0, setup.level / setup.unit)
    water.rotation_euler = (0.0, 0.0, 0.0)
    water.scale = (1.0 / setup.unit,) * 3
    if final:
        scene = context.scene
        scene.frame_start = 0
        scene.frame_end = anim.loop_frames - 1
    pkg.apply_frame(water, context.scene.frame_current)


def _adopt(context, water, setup, folder):
    settings = water.libwave_water
    settings.cache = folder
    settings.key = setup.key
    _play(context, water, setup, os.path.join(folder, "index.json"), final=True)


def _prune(keep):
    """Removes the cache entries beside `keep` that no live water plays (a setting changed)."""
    root = os.path.dirname(keep)
    used = {os.path.normpath(o.libwave_water.cache) for o in bpy.data.objects if o.libwave_water.is_water}
    used |= {os.path.normpath(j.part) for j in _jobs.values()} | {os.path.normpath(j.folder) for j in _jobs.values()}
    try:
        entries = os.listdir(root)
    except OSError:
        return
    for e in entries:
        p = os.path.normpath(os.path.join(root, e))
        if p not in used and os.path.isdir(p) and os.path.exists(os.path.join(p, "index.json")) and \
                (os.path.exists(os.path.join(p, "done.json")) or p.endswith(".part")):
            shutil.rmtree(p, ignore_errors=True)


def generate(context, water):
    """Starts a Generate for `water` (or plays its cache when nothing changed). Returns
    ("cached" | "started", Setup); LiveError for input it cannot use."""
    if water.name in _jobs:
        raise LiveError(f"'{water.name}' is generating: wait or press Cancel")
    _libwave()  # ImportError here: the module does not load (said by the caller)
    setup = Setup(context, water)
    settings = water.libwave_water
    if _complete(setup.folder, setup.key):
        _adopt(context, water, setup, setup.folder)
        settings.status = "cached frames (nothing changed)"
        settings.progress = 1.0
        return "cached", setup
    job = Job(setup, water.name)
    _jobs[water.name] = job
    settings.status, settings.progress = job.status, 0.0
    job.start()
    if not bpy.app.timers.is_registered(_timer):
        bpy.app.timers.register(_timer, first_interval=0.1)
    return "started", setup


# ---------------------------------------------------------------------------------------
# Operators and the panel
# ---------------------------------------------------------------------------------------

def _water_of(context):
    obj = context.object
    return obj if obj is not None and obj.libwave_water.is_water else None


def default_direction(vertices, level):
    """A swell direction for a terrain: from its deep water towards its shallows and land
    (the mean position of the deepest fifth of the points to that of the points above
    the deepest fifth's depth), as waves come in from the open sea."""
    z = vertices[:, 2]
    deep = z <= np.quantile(z, 0.2)
    shallow = ~deep
    if not deep.any() or not shallow.any() or z.min() >= level:
        return math.pi / 2
    d = vertices[shallow, :2].mean(axis=0) - vertices[deep, :2].mean(axis=0)
    return math.atan2(d[1], d[0]) if math.hypot(*d) > 1e-9 else math.pi / 2


class OBJECT_OT_libwave_water_add(bpy.types.Operator):
    """Add a libwave water object: waves generated by libwave over a terrain mesh of the scene"""

    bl_idname = "object.libwave_water_add"
    bl_label = "libwave Water"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        terrain = context.active_object if context.active_object is not None and \
            context.active_object.type == "MESH" and not context.active_object.libwave_water.is_water else None
        mesh = bpy.data.meshes.new("libwave Water")
        size, centre, level = 10.0, (0.0, 0.0), 0.0
        direction = math.pi / 2
        if terrain is not None:
            try:
                v, _ = terrain_arrays(context, terrain)
                lo, hi = v.min(axis=0), v.max(axis=0)
                size, centre = float(max(hi[0] - lo[0], hi[1] - lo[1])), ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2)
                direction = default_direction(v, level)
            except LiveError:
                terrain = None
        h = size / 2
        mesh.from_pydata([(centre[0] - h, centre[1] - h, 0), (centre[0] + h, centre[1] - h, 0),
                          (centre[0] + h, centre[1] + h, 0), (centre[0] - h, centre[1] + h, 0)], [], [(0, 1, 2, 3)])
        mesh.materials.append(_pkg().water_material())
        water = bpy.data.objects.new("libwave Water", mesh)
        context.collection.objects.link(water)
        s = water.libwave_water
        s.is_water = True
        s.terrain = terrain
        s.water_level = level
        swell = s.swells.add()
        swell.direction = direction
        for o in context.selected_objects:
            o.select_set(False)
        water.select_set(True)
        context.view_layer.objects.active = water
        return {"FINISHED"}


class OBJECT_OT_libwave_generate(bpy.types.Operator):
    """Generate the water's frames with libwave in the background (the UI stays live; cached frames are reused when nothing changed)"""

    bl_idname = "object.libwave_generate"
    bl_label = "Generate"

    @classmethod
    def poll(cls, context):
        return _water_of(context) is not None

    def execute(self, context):
        water = _water_of(context)
        try:
            how, setup = generate(context, water)
        except LiveError as e:
            self.report({"ERROR"}, f"libwave: {e}")
            return {"CANCELLED"}
        except ImportError as e:
            self.report({"ERROR"}, f"libwave: its Python module does not load in this Blender ({e}); the add-on's zip "
                                   "carries one for Debian 12's Blender 3.4 (Python 3.11): docs/blender.md")
            return {"CANCELLED"}
        except (ValueError, RuntimeError, OSError) as e:  # libwave.InputError (a ValueError) / Error, a file
            self.report({"ERROR"}, frames.printable(f"libwave: {e}"))
            return {"CANCELLED"}
        if how == "cached":
            self.report({"INFO"}, f"libwave: nothing changed, playing the cached frames ({setup.folder})")
        else:
            self.report({"INFO"}, "libwave: generating in the background")
        return {"FINISHED"}


class OBJECT_OT_libwave_cancel(bpy.types.Operator):
    """Stop the running Generate (what it computed is discarded)"""

    bl_idname = "object.libwave_cancel"
    bl_label = "Cancel"

    @classmethod
    def poll(cls, context):
        w = _water_of(context)
        return w is not None and busy(w)

    def execute(self, context):
        _jobs[_water_of(context).name].cancel = True
        return {"FINISHED"}


class OBJECT_OT_libwave_swell(bpy.types.Operator):
    """Add or remove a swell"""

    bl_idname = "object.libwave_swell"
    bl_label = "Swell"
    bl_options = {"REGISTER", "UNDO"}
    remove: IntProperty(default=-1)

    @classmethod
    def poll(cls, context):
        return _water_of(context) is not None

    def execute(self, context):
        swells = _water_of(context).libwave_water.swells
        if self.remove >= 0:
            if len(swells) <= 1:
                self.report({"ERROR"}, "libwave: the water needs a swell")
                return {"CANCELLED"}
            swells.remove(self.remove)
        else:
            new = swells.add()
            if len(swells) > 1:
                new.direction, new.period, new.height = swells[0].direction + 0.5, 10.0, 0.3
        return {"FINISHED"}


class OBJECT_OT_libwave_export_scene(bpy.types.Operator, ExportHelper):
    """Write the water's scene as JSON for `wave run` (a farm, Slurm): the terrain beside it as a PLY mesh"""

    bl_idname = "object.libwave_export_scene"
    bl_label = "Export scene JSON"
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    @classmethod
    def poll(cls, context):
        return _water_of(context) is not None

    def execute(self, context):
        try:
            export_scene(context, _water_of(context), self.filepath)
        except LiveError as e:
            self.report({"ERROR"}, f"libwave: {e}")
            return {"CANCELLED"}
        except OSError as e:
            self.report({"ERROR"}, f"libwave: {self.filepath}: {e.strerror or e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"libwave: wrote {self.filepath}")
        return {"FINISHED"}


def export_scene(context, water, path):
    """Writes `path` (the scene) and `<stem>-terrain.ply` beside it: `wave run path`
    computes the frames Generate computes."""
    setup = Setup(context, water)
    stem = os.path.splitext(os.path.basename(path))[0]
    ply = stem + "-terrain.ply"
    doc = dict(setup.document)
    doc["seafloor"] = dict(doc["seafloor"], source=ply)
    write_ply(os.path.join(os.path.dirname(os.path.abspath(path)), ply), setup.vertices, setup.triangles)
    with open(path, "w") as f:
        json.dump(doc, f, indent=2, sort_keys=True)
        f.write("\n")
    return doc


class OBJECT_PT_libwave_water(bpy.types.Panel):
    bl_label = "libwave Water"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return _water_of(context) is not None

    def draw(self, context):
        water = _water_of(context)
        s = water.libwave_water
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "terrain")
        layout.prop(s, "water_level")
        box = layout.box()
        row = box.row()
        row.label(text="Swells")
        row.operator(OBJECT_OT_libwave_swell.bl_idname, text="", icon="ADD").remove = -1
        for i, swell in enumerate(s.swells):
            col = box.column(align=True)
            head = col.row()
            head.label(text=f"Swell {i + 1}" + (" (traced)" if i == 0 else " (deep water)"))
            head.operator(OBJECT_OT_libwave_swell.bl_idname, text="", icon="X").remove = i
            col.prop(swell, "period")
            col.prop(swell, "height")
            sub = col.row()
            sub.enabled = swell.direction_object is None
            sub.prop(swell, "direction")
            col.prop(swell, "direction_object")
        col = layout.column()
        col.prop(s, "wind")
        sub = col.column(align=True)
        sub.enabled = s.wind
        sub.prop(s, "wind_speed")
        sub.prop(s, "wind_direction")
        layout.prop(s, "breakers")
        col = layout.column(align=True)
        col.prop(s, "foam_fade")
        col.prop(s, "foam_onset")
        layout.prop(s, "far_field")
        layout.prop(s, "quality")
        row = layout.row()
        if busy(water):
            row.prop(s, "progress", text=s.status or "working", slider=True)
            row.operator(OBJECT_OT_libwave_cancel.bl_idname, text="", icon="CANCEL")
        else:
            row.operator(OBJECT_OT_libwave_generate.bl_idname, icon="MOD_OCEAN")
            if s.status:
                layout.label(text=s.status)
        layout.operator(OBJECT_OT_libwave_export_scene.bl_idname, icon="EXPORT")


def _add_menu(self, context):
    self.layout.operator(OBJECT_OT_libwave_water_add.bl_idname, text="libwave Water", icon="MOD_OCEAN")


@persistent
def _on_save(*args):
    """A water cached in the temporary folder moves beside the .blend once it is saved (the
    file names the old folder: _on_load finds the new one when it is opened)."""
    if not bpy.data.filepath:
        return
    temp, root = cache_root(""), cache_root()
    pkg = _pkg()
    for water in bpy.data.objects:
        s = water.libwave_water
        if not s.is_water or not s.cache or water.name in _jobs:
            continue
        if os.path.normpath(os.path.dirname(s.cache)) != os.path.normpath(temp):
            continue
        target = os.path.join(root, os.path.basename(s.cache))
        try:
            os.makedirs(root, exist_ok=True)
            if not os.path.exists(target):
                shutil.move(s.cache, target)
        except OSError as e:
            print(f"libwave: {water.name}: the cache stays in {s.cache} ({e})")
            continue
        pkg._animations.pop(os.path.join(s.cache, "index.json"), None)
        s.cache = target
        water[pkg._PROP] = os.path.join(target, "index.json")
        water["libwave_live_mesh"] = water[pkg._PROP]


@persistent
def _on_load(*args):
    """Finds each live water's cache again on opening a .blend: beside it (where saving moved
    it; the file itself was written before the move and names the temporary folder), else
    in the temporary folder."""
    pkg = _pkg()
    for water in bpy.data.objects:
        s = water.libwave_water
        if not s.is_water or not s.key:
            continue
        for folder in (os.path.join(cache_root(), s.key[:16]), os.path.join(cache_root(""), s.key[:16]), s.cache):
            if folder and _complete(folder, s.key):
                s.cache = folder
                water[pkg._PROP] = water["libwave_live_mesh"] = os.path.join(folder, "index.json")
                break
        else:
            s.status = "the cached frames are gone: Generate again"
            if pkg._PROP in water:
                del water[pkg._PROP]  # nothing to play: the handler leaves the water as it is


classes = (LIBWAVE_PG_swell, LIBWAVE_PG_water, OBJECT_OT_libwave_water_add, OBJECT_OT_libwave_generate,
           OBJECT_OT_libwave_cancel, OBJECT_OT_libwave_swell, OBJECT_OT_libwave_export_scene, OBJECT_PT_libwave_water)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Object.libwave_water = PointerProperty(type=LIBWAVE_PG_water)
    bpy.types.VIEW3D_MT_add.append(_add_menu)
    if _on_save not in bpy.app.handlers.save_post:
        bpy.app.handlers.save_post.append(_on_save)
    if _on_load not in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.append(_on_load)


def unregister():
    for job in _jobs.values():
        job.cancel = True
    if bpy.app.timers.is_registered(_timer):
        bpy.app.timers.unregister(_timer)
    if _on_save in bpy.app.handlers.save_post:
        bpy.app.handlers.save_post.remove(_on_save)
    if _on_load in bpy.app.handlers.load_post:
        bpy.app.handlers.load_post.remove(_on_load)
    bpy.types.VIEW3D_MT_add.remove(_add_menu)
    del bpy.types.Object.libwave_water
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
