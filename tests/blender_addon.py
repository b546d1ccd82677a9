# The Blender add-on in Debian's Blender (run as: blender -b --factory-startup --python
# tests/blender_addon.py -- ADDON_ZIP OUT_DIR...): installs the zip, imports each run
# folder's animation (morph/nodes .glb, or the files form's index.json) and checks at
# frames 0, 1, k and k + loop (the loop repeats) that every vertex's position and its
# foam/reflect/refract equal the file's frame values as libwave's own reader gives them.
import math
import os
import sys

import addon_utils
import bpy
import numpy as np

import libwave

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip, runs = args[0], args[1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.preferences.addon_install(filepath=addon_zip, overwrite=True)
addon_utils.enable("libwave_blender", default_set=True)
errors = []


def source(folder):
    return os.path.join(folder, "index.json") if os.path.exists(os.path.join(folder, "index.json")) else \
        os.path.join(folder, "animation.glb")


def check_point_cache(folder, reference):
    """The pc2 form without the add-on: its .obj base mesh (axes kept: z up) with Blender's
    Mesh Cache modifier reading animation.pc2 shows the morph run's frames."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.wm.obj_import(filepath=os.path.join(folder, "animation.obj"), forward_axis="Y", up_axis="Z")
    obj = bpy.context.selected_objects[0]
    cache = obj.modifiers.new("libwave", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = os.path.join(folder, "animation.pc2")
    expected = libwave.read_animation(reference)
    n, scene = expected["vertex_count"], bpy.context.scene
    if len(obj.data.vertices) != n:
        errors.append(f"{folder}: the .obj has {len(obj.data.vertices)} vertices, expected {n}")
        return
    for f in [0, 1, expected["frame_count"] // 2]:
        scene.frame_set(f)
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
        co = np.empty(3 * n, np.float32)
        mesh.vertices.foreach_get("co", co)
        gap = np.abs(co.reshape(n, 3) - expected["positions"][f]).max()
        if gap > 1e-5:
            errors.append(f"{folder}: Mesh Cache frame {f}: positions off by {gap}")
    print(f"LIBWAVE-ADDON checked {folder}: the PC2 point cache through Blender's Mesh Cache modifier")


def check_sunbeams(folder, scene, frames):
    """The sunbeam volumes (sunbeams/sunbeams-NNNN.vdb) play as a Volume object's VDB
    sequence in step with the water (file k at scene frame k, file 0 again at the loop's
    end), its grid "sunlight" drives the material's emission, and a Cycles render from
    under the water is brighter with the volume than without it."""
    obj = bpy.data.objects.get("libwave sunbeams")
    if obj is None or obj.type != "VOLUME":
        errors.append(f"{folder}: no sunbeam volume was imported")
        return
    volume = obj.data
    if not volume.is_sequence or volume.frame_duration != frames or volume.sequence_mode != "REPEAT":
        errors.append(f"{folder}: the sunbeam volume does not play the {frames} files in a loop")
    for frame, k in [(0, 0), (1, 1), (frames, 0)]:
        scene.frame_set(frame)
        grids = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.grids
        grids.load()
        wanted = os.path.join(folder, "sunbeams", "sunbeams-%04d.vdb" % k)
        if os.path.normpath(bpy.path.abspath(grids.frame_filepath)) != os.path.normpath(wanted) or \
                [g.name for g in grids] != ["sunlight"]:
            errors.append(f"{folder}: scene frame {frame} shows {grids.frame_filepath} {[g.name for g in grids]}, not {wanted}")
    tree = volume.materials[0].node_tree
    if not any(n.type == "ATTRIBUTE" and n.attribute_name == "sunlight" for n in tree.nodes) or \
            not any(n.type == "EMISSION" and n.inputs["Strength"].is_linked for n in tree.nodes):
        errors.append(f"{folder}: the sunbeam material does not emit by the sunlight grid")
    # From 2 m under the still water in the pool's middle, looking up towards the sun
    # (the sun lamp's +Z), where the water scatters its beam forwards to the eye.
    scene.frame_set(0)
    eye = bpy.data.objects.new("under", bpy.data.cameras.new("under"))
    scene.collection.objects.link(eye)
    eye.location = (5.0, 5.0, -2.0)
    towards_sun = bpy.data.objects["libwave sun"].matrix_world.to_3x3().col[2]
    eye.rotation_euler = towards_sun.to_track_quat("-Z", "Y").to_euler()
    kept = scene.camera
    scene.camera = eye
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 4
    scene.cycles.seed = 0
    scene.render.resolution_x, scene.render.resolution_y = 48, 32

    def mean(name):
        scene.render.filepath = os.path.join(folder, name)
        bpy.ops.render.render(write_still=True)
        return float(np.array(bpy.data.images.load(scene.render.filepath).pixels[:], np.float32).reshape(32, 48, 4)[:, :, :3].mean())

    lit = mean("under-sunbeams.png")
    obj.hide_render = True
    plain = mean("under-plain.png")
    obj.hide_render = False
    scene.camera = kept
    print(f"LIBWAVE-ADDON sunbeams: under the water, mean {lit:.4f} with the volume, {plain:.4f} without")
    if not lit > 1.05 * plain:
        errors.append(f"{folder}: the sunbeam volume does not light the water ({lit} against {plain})")


def check_caustics(folder, scene, water, frames):
    """The seafloor plays the caustic maps (caustics/caustics-NNNN.png) as an image
    sequence in step with the water: seen from above with only its emission (no sun, no
    sky, the water hidden from the camera), scene frames 0 and N (the loop's end) look
    alike, frame 1 differs, and frame 0 follows map 0's pattern better than any other
    map's (the floor's depth colour and the PNG's sRGB encoding blur the match)."""
    floor = bpy.data.objects["libwave seafloor"]
    mat = floor.data.materials[0]
    images = [n for n in mat.node_tree.nodes if n.type == "TEX_IMAGE"]
    if not images or images[0].image.source != "SEQUENCE" or images[0].image_user.frame_duration != frames:
        errors.append(f"{folder}: the seafloor material does not play the {frames} caustic maps")
        return
    if "caustics" not in floor.data.uv_layers:
        errors.append(f"{folder}: the seafloor has no caustics UV map")
        return
    bpy.data.objects["libwave sun"].hide_render = True
    if "libwave sunbeams" in bpy.data.objects:  # only the floor's own emission
        bpy.data.objects["libwave sunbeams"].hide_render = True
    water.visible_camera = False
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    top = bpy.data.objects.new("top", bpy.data.cameras.new("top"))
    top.data.type = "ORTHO"
    xs = [v.co.x for v in floor.data.vertices]
    ys = [v.co.y for v in floor.data.vertices]
    top.data.ortho_scale = max(xs) - min(xs)  # the maps' rectangle (a square pool)
    top.location = (0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys)), 20.0)
    scene.collection.objects.link(top)
    scene.camera = top
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.cycles.filter_width = 0.01  # each pixel samples its centre: no jitter between frames
    scene.render.resolution_x = scene.render.resolution_y = 64

    def grey(frame):
        scene.frame_set(frame)
        scene.render.filepath = os.path.join(folder, f"floor-{frame}.png")
        bpy.ops.render.render(write_still=True)
        return np.array(bpy.data.images.load(scene.render.filepath).pixels[:], np.float32).reshape(64, 64, 4)[:, :, :3].mean(axis=2)

    def map_file(k):  # the PNG itself, rows flipped to Blender's bottom-up order
        image = bpy.data.images.load(os.path.join(folder, "caustics", "caustics-%04d.png" % k))
        return np.array(image.pixels[:], np.float32).reshape(64, 64, 4)[:, :, 0]

    first, second, wrapped = grey(0), grey(1), grey(frames)
    step, loop = np.abs(first - second).mean(), np.abs(first - wrapped).mean()
    # The pool's lines run along x, a pixel or two wide: compare the profiles across
    # them (means along x), softened over three rows against sampling offsets.
    profile = lambda a: np.convolve(a.mean(axis=1), np.ones(3) / 3.0, mode="same")
    corr = lambda a, b: float(np.corrcoef(profile(a), profile(b))[0, 1])
    against = [corr(first, map_file(k)) for k in range(frames)]
    own, others = against[0], max(against[1:])
    print(f"LIBWAVE-ADDON caustics: frame 0 vs 1 {step:.4f}, 0 vs {frames} {loop:.4f}; "
          f"frame 0 against map 0 {own:.2f}, the best other map {others:.2f}")
    if not (step > 0.01 and loop < 0.1 * step and own > 0.6 and own > others + 0.1):
        errors.append(f"{folder}: the caustic sequence is out of step with the frames")



def check_haze(folder, scene):
    """Koschmieder's haze on the land apron, measured in a Cycles render: a telephoto
    camera 5 m above the bay's land looks inland level with the apron's plain, so the
    rows below the horizon meet the land from a few hundred metres to tens of
    kilometres away. A pixel is (1 − τ) land + τ sky with τ = 1 − e^{−3.912 d / V}: τ
    is measured per row from the same view with the haze off (land) and with the
    seafloor hidden (sky), and must match the formula, its d from rays cast through
    each pixel at the seafloor, within 0.02 (64 Cycles samples; measured 0.005)."""
    from mathutils import Euler, Vector
    floor = bpy.data.objects["libwave seafloor"]
    mat = floor.data.materials[0]
    values = [n for n in mat.node_tree.nodes if n.type == "VALUE" and n.label == "visibility (m)"]
    if not values:
        errors.append(f"{folder}: the seafloor material has no haze (visibility) node")
        return
    visibility = values[0].outputs[0].default_value
    co = np.array([v.co[:] for v in floor.data.vertices])  # Blender axes: z up, the bay's land at the top (y = 100)
    border = co[(np.abs(co[:, 1] - 100.0) < 1e-3) & (np.abs(co[:, 0] - 50.0) < 1e-3)]
    if len(border) != 1 or not border[0, 2] > 0.0:
        errors.append(f"{folder}: no land node at the bay's border (50, 100): {border}")
        return
    height, rows, cols, fov = 5.0, 90, 16, np.radians(1.0)
    cam = bpy.data.objects.new("haze camera", bpy.data.cameras.new("haze camera"))
    scene.collection.objects.link(cam)
    cam.location = (50.0, 100.0, float(border[0, 2]) + height)
    cam.rotation_euler = Euler((np.pi / 2, 0.0, 0.0))  # level, looking along +y (inland)
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle_y = fov
    cam.data.clip_start, cam.data.clip_end = 1.0, 1e7
    saved = (scene.camera, scene.render.resolution_x, scene.render.resolution_y, scene.cycles.filter_width,
             scene.view_settings.view_transform, scene.cycles.samples)
    scene.camera = cam
    scene.cycles.samples = 64  # 1 440 pixels
    scene.render.resolution_x, scene.render.resolution_y = cols, rows
    scene.render.image_settings.file_format = "OPEN_EXR"  # linear: the mix is linear in the scene's light
    scene.view_settings.view_transform = "Standard"
    scene.cycles.filter_width = 0.01  # a pixel holds its own rays alone
    hidden = [o for o in scene.objects if o != floor and o.type == "MESH"]
    for o in hidden:
        o.hide_render = True
    def render(name):
        scene.render.filepath = os.path.join(folder, name)
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        return np.array(image.pixels[:], np.float32).reshape(rows, cols, 4)[::-1, :, :3]  # top row first
    hazed = render("haze.exr")
    values[0].outputs[0].default_value = 1e15
    land = render("haze-off.exr")
    values[0].outputs[0].default_value = visibility
    floor.hide_render = True
    sky = render("haze-sky.exr")
    floor.hide_render = False
    for o in hidden:
        o.hide_render = False
    scene.camera, scene.render.resolution_x, scene.render.resolution_y, scene.cycles.filter_width, \
        scene.view_settings.view_transform, scene.cycles.samples = saved
    scene.render.image_settings.file_format = "PNG"
    # The distance to the seafloor of 4 × 4 rays through each pixel (the image plane
    # at distance 1 spans tan(fov / 2) above and below the axis).
    to_floor = floor.matrix_world.inverted()
    eye = cam.matrix_world.translation
    half = np.tan(fov / 2)
    def expected_tau(r, c):
        taus = []
        for a in range(4):
            for b in range(4):
                u = ((c + (a + 0.5) / 4) / cols * 2 - 1) * half * cols / rows
                v = (1 - (r + (b + 0.5) / 4) / rows * 2) * half
                direction = Vector((u, 1.0, v)).normalized()  # camera looking along +y, z up
                hit, where, _, _ = floor.ray_cast(to_floor @ eye, to_floor.to_3x3() @ direction)
                taus.append(1.0 - np.exp(-3.912 * (floor.matrix_world @ where - eye).length / visibility) if hit else 1.0)
        return float(np.mean(taus))
    worst, checked, nearest = 0.0, 0, np.inf
    for r in range(rows // 2 + 1, rows):  # below the horizon (the middle row)
        contrast = (land[r] - sky[r]).mean(axis=0)
        if np.abs(contrast).max() < 0.02:
            continue
        tau = float(np.dot((land[r] - hazed[r]).mean(axis=0), contrast) / np.dot(contrast, contrast))
        expected = float(np.mean([expected_tau(r, c) for c in range(cols)]))
        worst = max(worst, abs(tau - expected))
        checked += 1
        nearest = min(nearest, -np.log(1.0 - expected) * visibility / 3.912)
    print(f"LIBWAVE-ADDON haze: visibility {visibility:g} m, {checked} rows from {nearest:.0f} m, "
          f"worst |τ − τ_Koschmieder| {worst:.3f}")
    if checked < 30 or worst > 0.02:
        errors.append(f"{folder}: haze off Koschmieder's law by {worst} ({checked} rows)")


def file_vertex(mesh):
    """Each of the add-on's water vertices' index in the file (its "file vertex" attribute)."""
    values = np.empty(len(mesh.vertices), np.int32)
    mesh.attributes["file vertex"].data.foreach_get("value", values)
    return values.astype(np.int64)


def check_whitewater(folder, scene, water, expected):
    """The whitewater's look (docs/whitewater.md, "The look in Blender"): the water keeps its
    frame-0 positions as "rest" and its material breaks the foam into the lace node group
    at them; the particles' object draws each foam particle as one lace sheet laid on the
    water (its "anchor" found on the water), spray as streaked droplets and bubbles as
    specks, each kind with its material."""
    from libwave_blender import whitewater
    rest = np.empty(3 * len(water.data.vertices), np.float32)
    water.data.attributes["rest"].data.foreach_get("vector", rest)
    first = np.asarray(expected["positions"][0], np.float32).reshape(-1, 3)[file_vertex(water.data)]
    if np.abs(rest.reshape(-1, 3) - first).max() > 1e-5:
        errors.append(f"{folder}: the water's rest attribute is not its first frame")
    tree = water.data.materials[0].node_tree
    if not any(n.type == "GROUP" and n.node_tree.name == "libwave foam lace" for n in tree.nodes) \
            or not any(n.type == "ATTRIBUTE" and n.attribute_name == "rest" for n in tree.nodes):
        errors.append(f"{folder}: the water material does not break its foam into lace at the rest positions")
    bsdf = next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
    # The water's surface below the mesh's scale: a bump of ripples into its normal, and its
    # roughness driven (by the foam value), not a constant.
    if bsdf is None or not bsdf.inputs["Normal"].is_linked or bsdf.inputs["Normal"].links[0].from_node.type != "BUMP" \
            or not bsdf.inputs["Roughness"].is_linked:
        errors.append(f"{folder}: the water's Principled BSDF has no ripple bump or no roughness from the foam")
    ww = [o for o in scene.objects if "libwave_whitewater" in o]
    if len(ww) != 1:
        errors.append(f"{folder}: {len(ww)} whitewater objects")
        return
    files = whitewater.sequence(folder)
    k = max(files, key=lambda f: os.path.getsize(files[f]))  # the busiest frame
    # In the viewport plain points, one per particle of the viewport's share (every
    # share_step-th), unless the modifier asks for the full look; a render takes them all.
    scene.frame_set(k - 1)
    scene.frame_set(k)  # frame k's particles read ahead on the worker during frame k − 1
    every = whitewater.read_points(files[k])["kind"]
    share = ww[0][whitewater.SHARE_PROP]
    kinds = every[::whitewater.share_step(share)]
    shown = np.empty(3 * len(ww[0].data.vertices), np.float32)
    ww[0].data.vertices.foreach_get("co", shown)
    want = whitewater.read_points(files[k], share)["positions"]
    if shown.size != want.size or np.abs(shown.reshape(-1, 3) - want).max(initial=0.0) > 1e-6:
        errors.append(f"{folder}: the whitewater shown at frame {k} is not its file's particles")
    if not (0 < share < 1 and len(kinds) < len(every) or len(every) < 2):
        errors.append(f"{folder}: the viewport's share {share} shows {len(kinds)} of {len(every)} particles")
    modifier = ww[0].modifiers[0]

    def drawn():
        quick = ww[0].evaluated_get(bpy.context.evaluated_depsgraph_get())
        points = len(quick.evaluated_geometry().pointcloud.points) if hasattr(quick, "evaluated_geometry") else None
        quick_mesh = quick.to_mesh()
        faces = len(quick_mesh.polygons)
        quick.to_mesh_clear()
        return points, faces, len(ww[0].data.vertices)
    points, faces, vertices = drawn()
    if faces != 0:
        errors.append(f"{folder}: the viewport draws {faces} whitewater faces, not plain points")
    if vertices != len(kinds) or points is not None and points != len(kinds):
        errors.append(f"{folder}: the viewport holds {vertices} and draws {points} points for {len(kinds)} particles")
    whitewater.on_render_init(scene)  # what a render (still or animation) calls first
    if len(ww[0].data.vertices) != len(every):
        errors.append(f"{folder}: a render takes {len(ww[0].data.vertices)} of the frame's {len(every)} particles")
    whitewater.on_render_done(scene)
    # A real (tiny) render: the particles are all there when it starts, the share after it.
    seen = []

    def record(render_scene, depsgraph=None):
        seen.append(len(ww[0].data.vertices))
    r = scene.render
    saved = (r.engine, r.resolution_x, r.resolution_y, r.resolution_percentage, ww[0].hide_render, scene.cycles.samples)
    r.engine, r.resolution_x, r.resolution_y, r.resolution_percentage, scene.cycles.samples = "CYCLES", 16, 9, 100, 1
    ww[0].hide_render = True  # the count is checked, not the look
    bpy.app.handlers.render_pre.append(record)
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.render_pre.remove(record)
        r.engine, r.resolution_x, r.resolution_y, r.resolution_percentage, ww[0].hide_render, scene.cycles.samples = saved
    if seen != [len(every)]:
        errors.append(f"{folder}: a render started with {seen} particles, not the frame's {len(every)}")
    if len(ww[0].data.vertices) != len(kinds):
        errors.append(f"{folder}: after the render the viewport holds {len(ww[0].data.vertices)} points, not {len(kinds)}")
    modifier[whitewater._input_identifier(modifier.node_group, whitewater.VIEWPORT_FULL)] = True
    ww[0].update_tag()
    scene.frame_set(k)
    evaluated = ww[0].evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    try:
        names = [m.name if m else "" for m in mesh.materials]
        index = np.empty(len(mesh.polygons), np.int32)
        mesh.polygons.foreach_get("material_index", index)
        faces = {kind: int((index == names.index(f"libwave whitewater {kind}")).sum()) if f"libwave whitewater {kind}" in names else 0
                 for kind in ("spray", "foam", "bubbles")}
        n = {kind: int((np.abs(kinds - i) < 0.5).sum()) for i, kind in enumerate(("spray", "foam", "bubbles"))}
        print(f"LIBWAVE-ADDON whitewater frame {k}: particles {n}, faces {faces}")
        if faces["foam"] != n["foam"]:
            errors.append(f"{folder}: frame {k}: {faces['foam']} foam sheets for {n['foam']} foam particles")
        if faces["bubbles"] != 4 * n["bubbles"]:
            errors.append(f"{folder}: frame {k}: {faces['bubbles']} bubble faces for {n['bubbles']} bubbles")
        # Each spray particle a puff of up to SPRAY_DROPLETS droplets (fewer as it ages).
        if not (n["spray"] == 0) == (faces["spray"] == 0) or faces["spray"] > 4 * whitewater.SPRAY_DROPLETS * n["spray"]:
            errors.append(f"{folder}: frame {k}: {faces['spray']} spray faces for {n['spray']} spray particles")
        if n["foam"] and "anchor" not in mesh.attributes:
            errors.append(f"{folder}: frame {k}: the foam sheets carry no anchor")
        elif n["foam"]:
            anchor = np.empty(3 * len(mesh.vertices), np.float32)
            mesh.attributes["anchor"].data.foreach_get("vector", anchor)
            lift = np.abs(anchor.reshape(-1, 3)[:, 2])
            # On the water the anchor is the rest position minus the sheet's: a wave's
            # displacement, not zero (no water found) and not a position (the sheet at 0).
            if not 1e-4 < lift.max() < 5.0:
                errors.append(f"{folder}: frame {k}: the foam sheets' anchors reach {lift.max()} m")
    finally:
        evaluated.to_mesh_clear()
    if n["spray"] + n["foam"] + n["bubbles"] == 0:
        errors.append(f"{folder}: frame {k} has no whitewater to check")


def check_meter(path, scene, imported_exposure):
    """The exposure meter (exposure.py): the import that made the sky metered through the
    file's camera (a daylight scene's exposure below 0 stops: the physical sky is bright);
    through a camera that sees only a uniform background of linear RGB c the log-average
    luminance is exactly c's Rec. 709 luminance L, and the meter sets log2(0.18 / L)."""
    if not (-16.0 <= imported_exposure < -0.25):
        errors.append(f"{path}: the import metered an exposure of {imported_exposure} stops (a daylight sky wants less than 0)")
    colour, strength = (0.3, 0.5, 0.9), 2.0
    background = scene.world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*colour, 1.0)
    background.inputs["Strength"].default_value = strength
    hidden = [o for o in scene.objects if o.type != "CAMERA" and not o.hide_render]
    for o in hidden:
        o.hide_render = True
    try:
        bpy.ops.scene.libwave_meter_exposure()
    finally:
        for o in hidden:
            o.hide_render = False
    luminance = strength * (0.2126 * colour[0] + 0.7152 * colour[1] + 0.0722 * colour[2])
    expected = math.log2(0.18 / (1e-4 + luminance))
    got = scene.view_settings.exposure
    print(f"LIBWAVE-ADDON meter: imported {imported_exposure:+.2f} stops; uniform sky {got:+.3f} (expected {expected:+.3f})")
    if abs(got - expected) > 0.02:
        errors.append(f"{path}: the meter set {got} stops through a uniform sky of luminance {luminance}, expected {expected}")


def check_file_normals(path, scene, expected):
    """Imported with the file's normals, every corner's normal at frames 1 and N/2 is its
    vertex's normal in the file (within 1°: the quantised base's int8 steps)."""
    before = set(bpy.data.objects)
    bpy.ops.import_scene.libwave(filepath=path, file_normals=True)
    obj = next(o for o in bpy.data.objects if o not in before and "libwave_source" in o)
    mesh, frames = obj.data, expected["frame_count"]
    for f in [1, frames // 2]:
        scene.frame_set(f)
        if hasattr(mesh, "calc_normals_split"):  # Blender 3.x; 4.1+ keeps corner_normals up to date
            mesh.calc_normals_split()
        corners = np.empty(3 * len(mesh.loops), np.float32)
        (mesh.corner_normals if hasattr(mesh, "corner_normals") else mesh.loops).foreach_get(
            "vector" if hasattr(mesh, "corner_normals") else "normal", corners)
        vertex = np.empty(len(mesh.loops), np.int64)
        mesh.loops.foreach_get("vertex_index", vertex)
        want = np.asarray(expected["normals"][f % frames]).reshape(-1, 3)[file_vertex(mesh)[vertex]]
        want /= np.linalg.norm(want, axis=1, keepdims=True)
        angle = np.degrees(np.arccos(np.clip((corners.reshape(-1, 3) * want).sum(axis=1), -1.0, 1.0)))
        if angle.max() > 1.0:
            errors.append(f"{path}: frame {f}: the file's normals are off by up to {angle.max():.2f}° "
                          f"({(angle > 1.0).sum()} of {len(angle)} corners beyond 1°)")
    bpy.data.objects.remove(obj)


for folder in runs:
    if folder.endswith("pc2"):
        check_point_cache(folder, os.path.join(os.path.dirname(folder), "morph", "animation.glb"))
        continue
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    path = source(folder)
    # The sky: made where the scene has no world (factory settings: none), kept where the
    # artist has one (the nodes run), its sun where the file's sun lamp is.
    artist = None
    if folder.endswith("nodes"):
        artist = bpy.data.worlds.new("artist's world")
        bpy.context.scene.world = artist
    else:
        bpy.context.scene.world = None
    bpy.context.scene.view_settings.exposure = 0.0
    result = bpy.ops.import_scene.libwave(filepath=path)
    if result != {"FINISHED"}:
        errors.append(f"{path}: import {result}")
        continue
    scene = bpy.context.scene
    imported_exposure = scene.view_settings.exposure
    if artist is not None:
        if scene.world != artist:
            errors.append(f"{path}: the artist's world was replaced by {scene.world}")
    elif scene.world is None or not scene.world.name.startswith("libwave sky"):
        errors.append(f"{path}: no sky world made ({scene.world})")
    else:
        # Two Nishita skies: the one that lights (no disc: the lamp is the sun) and the
        # one camera rays see (with the disc), switched by the light path's camera ray.
        skies = [nd for nd in scene.world.node_tree.nodes if nd.type == "TEX_SKY"]
        sun = bpy.data.objects.get("libwave sun")
        paths = [nd for nd in scene.world.node_tree.nodes if nd.type == "LIGHT_PATH"]
        if (len(skies) != 2 or any(sk.sky_type != "NISHITA" for sk in skies) or sun is None or
                sorted(bool(sk.sun_disc) for sk in skies) != [False, True] or len(paths) != 1 or
                not paths[0].outputs["Is Camera Ray"].is_linked):
            errors.append(f"{path}: the sky world has not its two Nishita skies (lit without a disc, seen with one "
                          f"by camera rays), or there is no sun lamp")
        else:  # the skies' sun direction is the lamp's (its +Z: it shines along −Z)
            lamp = np.array(sun.matrix_world.col[2][:3])
            for sk in skies:
                e, r = sk.sun_elevation, sk.sun_rotation
                to_sun = np.array([-math.cos(e) * math.sin(r), math.cos(e) * math.cos(r), math.sin(e)])
                if np.linalg.norm(to_sun - lamp / np.linalg.norm(lamp)) > 1e-4:
                    errors.append(f"{path}: the sky's sun points to {to_sun}, the lamp's to {lamp}")
    water = [o for o in scene.objects if o.type == "MESH" and "libwave_source" in o]
    expected = libwave.read_animation(path)
    frames, n = expected["frame_count"], expected["vertex_count"]
    if len(water) != 1 or len(water[0].data.vertices) != n:
        errors.append(f"{path}: expected one object of {n} vertices")
        continue
    obj = water[0]
    if abs(scene.render.fps / scene.render.fps_base - expected["fps"]) > 1e-6 or scene.frame_end != frames - 1:
        errors.append(f"{path}: fps {scene.render.fps}/{scene.render.fps_base}, frames {scene.frame_start}..{scene.frame_end}")
    # The add-on lays the mesh out for locality; "file vertex" maps it back to the file:
    # a permutation, under which the mesh's triangles are the file's (in another order).
    index = file_vertex(obj.data)
    corners = np.empty(len(obj.data.loops), np.int32)
    obj.data.loops.foreach_get("vertex_index", corners)
    if not np.array_equal(np.sort(index), np.arange(n)):
        errors.append(f"{path}: the water's \"file vertex\" attribute is not a permutation of its {n} vertices")
        continue

    def rows(t):  # each triangle from its smallest corner on (its winding kept), the list sorted
        t = np.asarray(t, np.int64).reshape(-1, 3)
        turn = np.argmin(t, axis=1)[:, None]
        t = np.take_along_axis(t, (turn + np.arange(3)) % 3, axis=1)
        return t[np.lexsort(t.T[::-1])]
    mine, theirs = rows(index[corners]), rows(expected["triangles"])
    if mine.shape != theirs.shape or not np.array_equal(mine, theirs):
        errors.append(f"{path}: the water's triangles, mapped back by \"file vertex\", are not the file's")
    # Laid out for locality: a triangle's corners lie nearer each other in the mesh than in the file.
    spread = lambda t: float(np.median(np.ptp(np.asarray(t, np.int64).reshape(-1, 3), axis=1)))
    if not spread(corners) < spread(expected["triangles"]):
        errors.append(f"{path}: the water is not laid out for locality (corner spread {spread(corners)} "
                      f"against the file's {spread(expected['triangles'])})")
    # 1, 2, 3: frames decoded ahead on the worker (compressed outputs), after a jump too.
    for f in [0, 1, 2, 3, frames // 2, frames // 2 + 1, frames + 1]:
        scene.frame_set(f)
        k = f % frames
        co = np.empty(3 * n, np.float32)
        obj.data.vertices.foreach_get("co", co)
        # Both decode the same file: float32's rounding apart. Quantised, the add-on adds the
        # node's translation to its scale times the int16 in float32, so each coordinate is
        # good to a few of float32's steps at its own size plus the node's (≤ 128 m on the
        # bay): ~2e-5 m in the bay, 8 mm on the skirt at 80 km.
        want = np.asarray(expected["positions"][k], np.float32).reshape(n, 3)[index]
        tol = 1e-6 if "quant" not in folder else 1e-6 + 8.0 * np.spacing(np.abs(want) + np.float32(128.0))
        gap = np.abs(co.reshape(n, 3) - want) - tol
        if (gap > 0).any():
            errors.append(f"{path}: frame {f} (loop frame {k}): positions off by {(gap + tol).max()} (tolerance {np.max(tol)})")
        for name in ("foam", "reflect", "refract"):
            values = np.empty(n, np.float32)
            obj.data.attributes[name].data.foreach_get("value", values)
            gap = np.abs(values - np.asarray(expected[name][k])[index]).max()
            if gap > (1e-6 if "quant" not in folder else 1.0 / 65535.0 + 1e-6):
                errors.append(f"{path}: frame {f}: {name} off by {gap}")
        if len(expected.get("colors", [])):  # Ts'o's baked colour (outputs.color)
            rgba = np.empty(4 * n, np.float32)
            obj.data.attributes["colour"].data.foreach_get("color", rgba)
            gap = np.abs(rgba.reshape(n, 4)[:, :3] - np.asarray(expected["colors"][k])[index]).max()
            if gap > 1e-6:
                errors.append(f"{path}: frame {f}: colour off by {gap}")
    # A mesh without "file vertex" (a .blend saved before the add-on laid meshes out) plays
    # in the file's order: its frames must not be gathered through an order computed now.
    import libwave_blender
    saved_index = file_vertex(obj.data)
    obj.data.attributes.remove(obj.data.attributes["file vertex"])
    libwave_blender._mesh_orders.clear()
    scene.frame_set(2)
    co = np.empty(3 * n, np.float32)
    obj.data.vertices.foreach_get("co", co)
    if np.abs(co.reshape(n, 3) - np.asarray(expected["positions"][2 % frames], np.float32).reshape(n, 3)).max() > 5e-4:
        errors.append(f"{path}: a mesh without \"file vertex\" does not play the file's order")
    obj.data.attributes.new("file vertex", "INT", "POINT").data.foreach_set("value", saved_index.astype(np.int32))
    libwave_blender._mesh_orders.clear()
    if not all(p.use_smooth for p in obj.data.polygons):
        errors.append(f"{path}: the water is not smooth-shaded")
    mat = obj.data.materials[0]
    if not any(n.type == "ATTRIBUTE" and n.attribute_name == "foam" for n in mat.node_tree.nodes):
        errors.append(f"{path}: the material does not read the foam attribute")
    if True:  # every form carries the seafloor, camera and sun (the files form in its frame 0)
        kinds = sorted(o.name for o in scene.objects if "libwave_source" not in o)
        # The default scene throws whitewater (issue 66): its particles' object, where the
        # form shows it beside the water, is the whitewater's own test's business.
        if os.path.isdir(os.path.join(folder, "whitewater")):
            kinds = [k for k in kinds if not k.startswith("libwave whitewater")]
        beside = ["libwave camera", "libwave seafloor", "libwave sun"] + (["libwave sunbeams"] if folder.endswith("caustics") else [])
        if kinds != beside:
            errors.append(f"{path}: beside the water: {kinds}")
        elif scene.camera is None or scene.camera.name != "libwave camera":
            errors.append(f"{path}: the file's camera is not the scene's")
        else:  # the camera's clip range holds the whole seafloor (a km-scale coast too)
            floor = bpy.data.objects["libwave seafloor"]
            eye = scene.camera.matrix_world.translation
            reach = max((floor.matrix_world @ v.co - eye).length for v in floor.data.vertices)
            if not scene.camera.data.clip_start < 1.0 < reach < scene.camera.data.clip_end:
                errors.append(f"{path}: the camera clips at {scene.camera.data.clip_start} … {scene.camera.data.clip_end} m, "
                              f"the seafloor reaches {reach} m")
        if folder.endswith("morph"):  # a small Cycles render from the file's camera shows water, seafloor and sky
            world = bpy.data.worlds.new("sky")
            world.use_nodes = True
            world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.3, 0.5, 0.9, 1.0)
            scene.world = world
            scene.render.engine = "CYCLES"
            scene.cycles.samples = 4
            scene.cycles.use_denoising = False
            scene.render.resolution_x, scene.render.resolution_y = 160, 90
            scene.render.filepath = os.path.join(folder, "render.png")
            bpy.ops.render.render(write_still=True)
            def render(name):
                scene.render.filepath = os.path.join(folder, name)
                bpy.ops.render.render(write_still=True)
                return np.array(bpy.data.images.load(scene.render.filepath).pixels[:], np.float32).reshape(90, 160, 4)[:, :, :3]
            seafloor = bpy.data.objects["libwave seafloor"]
            full = render("render.png")
            obj.hide_render = True
            no_water = render("render-seafloor.png")
            seafloor.hide_render = True
            sky_only = render("render-sky.png")
            obj.hide_render = seafloor.hide_render = False
            differs = lambda a, b: np.abs(a - b).max(axis=2) > 0.05
            water_share = float(differs(full, no_water).mean())
            ground = float(differs(no_water, sky_only).mean())
            sky = float((~differs(full, sky_only)).mean())
            print(f"LIBWAVE-ADDON render: sky {sky:.2f}, water {water_share:.2f}, seafloor (under the water) {ground:.2f}")
            if min(sky, water_share, ground) < 0.05:
                errors.append(f"{path}: the render lacks sky, water or seafloor: {sky}, {water_share}, {ground}")
            check_haze(folder, scene)
            check_meter(path, scene, imported_exposure)
    if folder.endswith("morph") and os.path.isdir(os.path.join(folder, "whitewater")):
        check_whitewater(folder, scene, obj, expected)
    if folder.endswith(("morph", "quant", "files")):  # option "The file's normals": custom normals per frame
        check_file_normals(path, scene, expected)
    if folder.endswith("caustics"):
        check_sunbeams(folder, scene, frames)
        check_caustics(folder, scene, obj, frames)
        # The option "Ts'o's baked colour": the water emits the colour attribute.
        if bpy.ops.import_scene.libwave(filepath=path, baked_colour=True) != {"FINISHED"}:
            errors.append(f"{path}: import with the baked colour failed")
        else:
            again = [o for o in bpy.context.scene.objects if "libwave_source" in o and o != obj]
            tree = again[0].data.materials[0].node_tree
            emits = [nd for nd in tree.nodes if nd.type == "EMISSION" and nd.inputs["Color"].is_linked and
                     nd.inputs["Color"].links[0].from_node.type == "ATTRIBUTE" and
                     nd.inputs["Color"].links[0].from_node.attribute_name == "colour"]
            if not emits:
                errors.append(f"{path}: the baked-colour material does not emit the colour attribute")
    elif len(expected.get("colors", [])) == 0:
        try:  # an operator that reports an error raises in a script
            bpy.ops.import_scene.libwave(filepath=path, baked_colour=True)
            errors.append(f"{path}: the baked colour was accepted from a file without colour")
        except RuntimeError as e:
            if "has no baked colour" not in str(e):
                errors.append(f"{path}: the baked colour refused with {e}")
    print(f"LIBWAVE-ADDON checked {path}: {frames} frames of {n} vertices")

print("\n".join(errors) if errors else "LIBWAVE-ADDON ok")
sys.exit(1 if errors else 0)
