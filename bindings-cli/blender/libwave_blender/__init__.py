"""libwave for Blender: File → Import → libwave animation (docs/blender.md).

Imports what `wave run` writes — the morph, nodes and files forms, plain or quantised
(Draco through libwave's Python module) — as one water object whose positions and
per-vertex foam, reflect and refract are updated on every frame change (the files form
streams its frames from disk), with the scene's fps and frame range set, the loop
repeating past its end, and an editable water material that reads the foam; or, on
request, baked into the .blend (bake.py) so that the saved file plays without the
add-on. Works in
Debian's Blender 3.4 (no numpy.bool patch needed: Blender's glTF importer is not used);
the Blender 4.x names and APIs it meets are guarded (not tested here: no Blender 4).
"""
import math
import os

import bpy
import numpy as np
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from . import bake as baking
from . import exposure
from . import frames
from . import live
from . import whitewater

bl_info = {
    "name": "libwave animation",
    "author": "libwave",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > libwave animation; Add > libwave Water",
    "description": "Coastal wave animations from libwave: imported, or generated live over a terrain mesh of the scene",
    "category": "Import-Export",
}

_PROP = "libwave_source"  # custom property on the object: the file it plays
# Haze on the seafloor seen from the camera (m; _add_haze): a clear day, 40 km.
DEFAULT_VISIBILITY = 40000.0
_animations = {}  # source path → frames.Animation (reopened after a .blend is loaded)


def _animation(path):
    if path not in _animations:
        _animations[path] = frames.Animation(path)
    return _animations[path]


def _attribute(mesh, name):
    a = mesh.attributes.get(name)
    if a is None:
        a = mesh.attributes.new(name, "FLOAT", "POINT")
    return a


_mesh_orders = {}  # (mesh pointer, vertices, faces) → its "file vertex" (None: the file's order)


def mesh_order(mesh):
    """The order of `mesh`'s vertices in the file (its "file vertex" attribute; None for a
    mesh without one, which a .blend saved before the attribute holds: the file's order),
    read once per mesh. The mesh is what decides the order a frame is gathered in: a
    file rewritten since, or another order computed now, must not scramble it."""
    key = (mesh.as_pointer(), len(mesh.vertices), len(mesh.polygons))
    if key not in _mesh_orders:
        a = mesh.attributes.get("file vertex")
        order = None
        if a is not None and a.data_type == "INT" and a.domain == "POINT":
            order = np.empty(len(mesh.vertices), np.int32)
            a.data.foreach_get("value", order)
            order = order.astype(np.int64)
            if not np.array_equal(np.sort(order), np.arange(len(order))):
                order = None  # an attribute of that name that is not ours: the file's order
        if len(_mesh_orders) > 64:
            _mesh_orders.clear()
        _mesh_orders[key] = order
    return _mesh_orders[key]


def apply_frame(obj, scene_frame):
    """Shows loop frame (scene_frame − frame_start) mod frame_count of the object's animation."""
    anim = _animation(obj[_PROP])
    anim.set_order(mesh_order(obj.data))
    k = (scene_frame - obj.get("libwave_frame_start", 0)) % anim.frame_count
    anim.want_normals = bool(obj.get("libwave_file_normals"))  # a compressed frame's normals decoded only for these
    f = anim.frame(k)
    mesh = obj.data
    mesh.vertices.foreach_set("co", np.ascontiguousarray(f.positions, np.float32).ravel())
    for name, values in (("foam", f.foam), ("reflect", f.reflect), ("refract", f.refract)):
        if values is not None:
            _attribute(mesh, name).data.foreach_set("value", np.ascontiguousarray(values, np.float32))
    if f.color is not None:
        colour = mesh.attributes.get("colour") or mesh.attributes.new("colour", "FLOAT_COLOR", "POINT")
        colour.data.foreach_set("color", frames.to_rgba(f.color))
    if obj.get("libwave_file_normals") and f.normals is not None:
        mesh.update()  # the custom normals are stored against the new positions' own normals
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(f.normals, np.float32))
    mesh.update()
    obj["libwave_frame"] = k


@persistent
def _on_frame_change(scene, depsgraph=None):
    for obj in scene.objects:
        if obj.type == "MESH" and _PROP in obj:
            try:
                apply_frame(obj, scene.frame_current)
            except (OSError, frames.LibwaveFileError) as e:  # a moved file: say so once per frame, keep Blender usable
                print(f"libwave: {obj.name}: {e}")


def _mesh_from_arrays(name, positions, triangles):
    """A mesh of `positions` (n, 3) and `triangles` (t, 3) through foreach_set: a 263 k-vertex
    ocean in a fraction of from_pydata's time (which walks Python lists)."""
    mesh = bpy.data.meshes.new(name)
    triangles = np.ascontiguousarray(triangles, np.int32).reshape(-1, 3)
    n, t = len(positions), len(triangles)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(positions, np.float32).ravel())
    mesh.loops.add(3 * t)
    mesh.loops.foreach_set("vertex_index", triangles.ravel())
    mesh.polygons.add(t)
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * t, 3, dtype=np.int32))
    try:  # Blender 3.x; read-only from 4.0, where loop_start alone defines the faces
        mesh.polygons.foreach_set("loop_total", np.full(t, 3, np.int32))
    except (AttributeError, TypeError, RuntimeError):
        pass
    mesh.update(calc_edges=True)
    return mesh


def water_mesh(name, anim):
    """The water's mesh for `anim` (frames.Animation) at its frame 0, laid out for locality
    (frames.locality_order), with the point attribute "file vertex": each vertex's index
    in the file (the map back to the file's order, for a check or a pipeline's own
    per-vertex data; apply_frame gathers each frame through it). `anim` then gives its
    frames in that order."""
    order, triangles = frames.locality_order(anim.first_positions(), anim.triangles)
    anim.set_order(order)
    mesh = _mesh_from_arrays(name, anim.frame(0).positions, triangles)
    mesh.attributes.new("file vertex", "INT", "POINT").data.foreach_set("value", np.ascontiguousarray(order, np.int32))
    return mesh


def _smooth(mesh, custom_normals=False):
    """Smooth shading (Blender's vertex normals of the animated positions); with
    `custom_normals` the mesh takes custom normals (Blender 3.x needs auto smooth for them)."""
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), bool))
    if custom_normals and hasattr(mesh, "use_auto_smooth"):  # removed in Blender 4.1
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi  # no sharp edges: an overturning lip keeps its fan


def water_material(baked_colour=False):
    """Principled water (transmission, IOR 1.333) mixed with foam by the foam attribute
    broken into lace (docs/blender.md, "Foam"): foam shows where the lace pattern at the
    vertex's rest position (attribute "rest", set_rest) lies under the foam value, so a
    little foam is a thin broken web, more of it thick lace, full foam solid white, and the
    pattern rides with the water; with `baked_colour`, the water emits the file's `colour`
    attribute (Ts'o's eq. 4.1, R · sky + T · water colour: the shading baked by `wave run`)
    instead."""
    name = "libwave water (Ts'o colour)" if baked_colour else "libwave water"
    mat = bpy.data.materials.get(name)
    if mat is not None:
        return mat
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    if baked_colour:
        water = nodes.new("ShaderNodeEmission")
        colour = nodes.new("ShaderNodeAttribute")
        colour.attribute_name = "colour"
        links.new(colour.outputs["Color"], water.inputs["Color"])
        colour.location = (-600, 250)
    else:
        water = nodes.new("ShaderNodeBsdfPrincipled")
        water.inputs["Base Color"].default_value = (0.02, 0.12, 0.16, 1.0)
        water.inputs["Roughness"].default_value = WATER_ROUGHNESS
        water.inputs["IOR"].default_value = 1.333
        for transmission in ("Transmission Weight", "Transmission"):  # Blender 4.x, 3.x
            if transmission in water.inputs:
                water.inputs[transmission].default_value = 1.0
                break
    t = whitewater._Tree(mat.node_tree)
    foam = nodes.new("ShaderNodeAttribute")
    foam.attribute_name = "foam"
    rest = nodes.new("ShaderNodeAttribute")
    rest.attribute_name = "rest"
    # A little more lace than the value alone would give (the value is a smooth share over
    # a mesh triangle; lace at that share looks thinner than it is).
    density = t.math("POWER", foam.outputs["Fac"], FOAM_LACE_GAMMA)
    # Patches: the foam a breaker leaves gathers in patches and streaks metres across,
    # with clean water between (a uniform web over the whole surf zone read as cracked
    # glaze from above): its density times a slow noise at the rest coordinates.
    patches = t.noise(rest.outputs["Vector"], FOAM_PATCH_SCALE, 2.0, "2D")
    patchy = t.clamp01(t.math("MULTIPLY", t.math("SUBTRACT", patches.outputs["Fac"], FOAM_PATCH_EDGE), 5.0))
    density = t.math("MULTIPLY", density, t.math("MINIMUM", t.math("ADD", patchy, t.math("POWER", foam.outputs["Fac"], 4.0)), 1.0))
    if not baked_colour:
        # Aerated water is rough: where the foam value stands (the surf a breaker left,
        # between the lace's threads too), the surface's roughness rises with it, so the
        # holes in the lace show the sky and the land blurred, as churned water does,
        # not as a mirror (a wave face there mirrored the grass behind the beach as sharp
        # green islands in the surf).
        rough = t.math("MINIMUM", t.math("MULTIPLY", foam.outputs["Fac"], 1.0 / SURF_FOAM), 1.0)
        links.new(t.math("MULTIPLY_ADD", rough, SURF_ROUGHNESS - WATER_ROUGHNESS, WATER_ROUGHNESS), water.inputs["Roughness"])
        # Ripples below the mesh's scale (capillary and short wind waves, a few cm to a few
        # dm, riding with the water at its rest coordinates) as a bump: a wave face mirrored
        # the land behind the beach as one sharp island; real water breaks a reflection
        # into streaks and glints.
        ripples = t.noise(rest.outputs["Vector"], RIPPLE_SCALE, 4.0)
        bump = t.node("ShaderNodeBump")
        bump.inputs["Strength"].default_value = RIPPLE_STRENGTH
        bump.inputs["Distance"].default_value = RIPPLE_HEIGHT
        links.new(ripples.outputs["Fac"], bump.inputs["Height"])
        links.new(bump.outputs["Normal"], water.inputs["Normal"])
    mix = nodes.new("ShaderNodeMixShader")
    mix.label = "foam: the foam value broken into lace"
    mask = whitewater._lace_mask(t, rest.outputs["Vector"], density)
    links.new(mask, mix.inputs["Fac"])
    links.new(water.outputs[0], mix.inputs[1])
    links.new(whitewater.foam_shader(t), mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    for i, node in enumerate((foam, water, mix, out)):
        node.location = (-600 + 250 * i, 0)
    rest.location = (-600, -250)
    return mat


FOAM_LACE_GAMMA = 0.7  # the foam value's density for the lace: value ** this
WATER_ROUGHNESS = 0.1  # calm water's: at 0.04 the land behind a beach mirrored in the wave faces as sharp grass
SURF_ROUGHNESS = 0.3  # churned water's, reached where the foam value is SURF_FOAM or more
SURF_FOAM = 0.3
FOAM_PATCH_SCALE = 0.12  # the patches' noise scale (per metre: patches ~5–10 m across)
FOAM_PATCH_EDGE = 0.42  # the noise (about 0.5 ± 0.15) clears the web below this, keeps it whole 0.2 above (full foam stays full)
RIPPLE_SCALE = 6.0  # the ripples' noise scale (per metre of the rest coordinates: features of ~10–20 cm)
RIPPLE_STRENGTH = 0.35
RIPPLE_HEIGHT = 0.05  # m


def set_rest(mesh):
    """The water's "rest" attribute: each vertex's position now (the first frame's, at
    import), fixed while the frames move the vertices: the foam lace's coordinates, which
    so ride with the water."""
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    rest = mesh.attributes.get("rest") or mesh.attributes.new("rest", "FLOAT_VECTOR", "POINT")
    rest.data.foreach_set("vector", co)


# Koschmieder's law: a dark object's contrast against the horizon sky falls as
# e^{−σ d}, and the meteorological visibility V is where it reaches 2 %: σ = −ln 0.02 / V.
_KOSCHMIEDER = -math.log(0.02)


def _math(tree, operation, *inputs, label=""):
    """A Math node of `operation` in node tree `tree`, its inputs in order: a socket is
    linked, a number set."""
    node = tree.nodes.new("ShaderNodeMath")
    node.operation = operation
    node.label = label
    for socket, value in zip(node.inputs, inputs):
        if isinstance(value, bpy.types.NodeSocket):
            tree.links.new(value, socket)
        else:
            socket.default_value = value
    return node


def _add_haze(mat, visibility):
    """Aerial perspective for the seafloor seen straight from the camera: the surface
    gives way to what lies behind it (the world's sky, at the horizon) by the share
    1 − e^{−σ d} of Koschmieder's law, d the distance to the camera, σ = 3.912 / V.
    The land apron that carries a coast's hinterland to the horizon then fades into the
    sky as a real coast does in haze, instead of ending at the horizon as a flat plain.
    Only camera rays: the seafloor seen through the water, and shadows, are unchanged.
    The visibility stays a Value node of the material ("visibility (m)")."""
    if not visibility > 0.0:
        return
    tree = mat.node_tree
    nodes, links = tree.nodes, tree.links
    out = nodes.get("Material Output")
    shader = out.inputs["Surface"].links[0].from_socket
    camera = nodes.new("ShaderNodeCameraData")
    v = nodes.new("ShaderNodeValue")
    v.label = "visibility (m)"
    v.outputs[0].default_value = float(visibility)
    ratio = _math(tree, "DIVIDE", camera.outputs["View Distance"], v.outputs[0])
    optical = _math(tree, "MULTIPLY", ratio.outputs["Value"], -_KOSCHMIEDER)
    kept = _math(tree, "EXPONENT", optical.outputs["Value"])
    gone = _math(tree, "SUBTRACT", 1.0, kept.outputs["Value"])
    path = nodes.new("ShaderNodeLightPath")
    share = _math(tree, "MULTIPLY", gone.outputs["Value"], path.outputs["Is Camera Ray"],
                  label="haze: (1 − e^(−3.912 d / V)) on camera rays")
    clear = nodes.new("ShaderNodeBsdfTransparent")
    mix = nodes.new("ShaderNodeMixShader")
    links.new(share.outputs["Value"], mix.inputs["Fac"])
    links.new(shader, mix.inputs[1])
    links.new(clear.outputs["BSDF"], mix.inputs[2])
    links.new(mix.outputs["Shader"], out.inputs["Surface"])
    for i, node in enumerate((camera, ratio, optical, kept, gone, share, mix)):
        node.location = (-900 + 200 * i, 500)
    v.location, path.location, clear.location = (-900, 350), (-100, 700), (100, 350)
    out.location = (500, 300)
    if hasattr(mat, "blend_method"):  # Eevee (3.x) blends the transparent share by dithering
        mat.blend_method = "HASHED"


def _new_seafloor_material(name):
    """A rough Principled BSDF coloured by the seafloor's "depth colour" attribute, varied
    over the ground: (material, its BSDF node, the node whose Color output is the floor's
    colour)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    t = whitewater._Tree(mat.node_tree)
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 0.9
    colour = mat.node_tree.nodes.new("ShaderNodeAttribute")
    colour.attribute_name = "depth colour"
    # The file's colours are per vertex and smooth (sand, grass by height): one flat green
    # read as a lawn to the horizon. Patches tens of metres across and clumps of a metre
    # vary their brightness, drier patches turn towards straw, and a bump of the same
    # clumps gives the ground a texture; positions in the world, so the land beyond the
    # data varies as the data's does.
    where = t.node("ShaderNodeNewGeometry").outputs["Position"]
    patches = t.noise(where, GROUND_PATCH_SCALE, 4.0)
    clumps = t.noise(where, GROUND_CLUMP_SCALE, 2.0)
    dry = t.noise(where, GROUND_PATCH_SCALE * 1.7, 3.0)  # where the grass dries (another noise, ~20 m): yellower, browner
    # Land only: the bottom under the water stays the file's smooth sand (varied, it read as
    # "grass texture under the surface" in the caustics cove); full from 0.25 m above still
    # water, none at and below it.
    height = t.node("ShaderNodeSeparateXYZ")
    t.links.new(where, height.inputs[0])
    land = t.clamp01(t.math("MULTIPLY", height.outputs["Z"], 4.0))
    dryness = t.math("MULTIPLY", t.clamp01(t.math("MULTIPLY", t.math("SUBTRACT", dry.outputs["Fac"], 0.45), 4.0)), land)
    tint = t.vmath("ADD", (1.0, 1.0, 1.0), t.vmath("SCALE", t.vmath("SUBTRACT", GROUND_DRY_TINT, (1.0, 1.0, 1.0)), scale=dryness))
    varied = t.node("ShaderNodeHueSaturation")
    t.links.new(t.vmath("MULTIPLY", colour.outputs["Color"], tint), varied.inputs["Color"])
    light = t.math("ADD", t.math("MULTIPLY", patches.outputs["Fac"], GROUND_PATCH_CONTRAST),
                   t.math("MULTIPLY", clumps.outputs["Fac"], GROUND_CLUMP_CONTRAST))
    spread = t.math("MULTIPLY", t.math("SUBTRACT", light, 0.5 * (GROUND_PATCH_CONTRAST + GROUND_CLUMP_CONTRAST)), land)
    t.put(varied.inputs["Value"], t.math("MAXIMUM", t.math("ADD", spread, 1.0), 0.0))
    t.links.new(varied.outputs["Color"], bsdf.inputs["Base Color"])
    bump = t.node("ShaderNodeBump")
    t.put(bump.inputs["Strength"], t.math("MULTIPLY", land, 0.3))
    bump.inputs["Distance"].default_value = 0.1
    t.links.new(clumps.outputs["Fac"], bump.inputs["Height"])
    t.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return mat, bsdf, varied


GROUND_PATCH_SCALE = 0.03  # per metre: patches ~30 m across
GROUND_CLUMP_SCALE = 0.8  # per metre: clumps ~1 m across
GROUND_PATCH_CONTRAST = 1.8  # brightness × (1 + this × (noise − 0.5)) over the patches (noise about 0.5 ± 0.15)
GROUND_CLUMP_CONTRAST = 0.8
GROUND_DRY_TINT = (1.5, 1.15, 0.6)  # a dry patch's colour × this (linear RGB): green grass to straw, sand to a warmer sand


def _seafloor_material(visibility):
    name = "libwave seafloor" if not visibility > 0.0 else f"libwave seafloor (visibility {visibility:g} m)"
    mat = bpy.data.materials.get(name)
    if mat is None:
        mat = _new_seafloor_material(name)[0]
        _add_haze(mat, visibility)
    return mat


def _socket(node, *names):
    """The first input of `node` among `names` (Blender 4 renamed some, e.g. "Emission"
    became "Emission Color")."""
    return next(node.inputs[n] for n in names if n in node.inputs)


def _caustic_material(folder, caustics, sun_irradiance, visibility):
    """The seafloor material with the caustic maps as an image sequence (docs/underwater.md):
    the floor emits its colour (the depth colour varied over the ground) × the map's irradiance / π (what a diffuse floor
    lit by it would send back), since Cycles' sun does not
    reach the floor through the refracting water (caustics are the path a path tracer
    finds last). Looping with the animation, frame 0 at scene frame 0."""
    mat, bsdf, colour = _new_seafloor_material("libwave seafloor with caustics")
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    links.new(colour.outputs["Color"], _socket(bsdf, "Emission Color", "Emission"))
    uv = nodes.new("ShaderNodeUVMap")
    uv.uv_map = "caustics"
    image_node = nodes.new("ShaderNodeTexImage")
    image_node.interpolation = "Linear"
    image_node.extension = "EXTEND"
    first = os.path.join(folder, caustics["images"] % 0)
    image = bpy.data.images.load(first, check_existing=True)
    image.source = "SEQUENCE"
    image.colorspace_settings.name = "Non-Color"
    image_node.image = image
    user = image_node.image_user
    user.frame_duration = int(caustics["frames"])
    user.frame_start = 0
    user.frame_offset = -1  # Blender counts the sequence from 1: file 0 at scene frame 0
    user.use_cyclic = True
    user.use_auto_refresh = True
    links.new(uv.outputs["UV"], image_node.inputs["Vector"])
    # Irradiance E = map × full scale × the sun's on flat water; a diffuse floor of albedo
    # ρ sends back ρ E / π, and Cycles' emission of strength S and colour ρ is ρ S.
    scale = _math(mat.node_tree, "MULTIPLY", image_node.outputs["Color"], float(caustics["full_scale"]) * sun_irradiance / math.pi,
                  label="E / π: map × full scale × sun irradiance / π")
    links.new(scale.outputs["Value"], bsdf.inputs["Emission Strength"])
    for i, node in enumerate((uv, image_node, scale)):
        node.location = (-900 + 250 * i, -300)
    colour.location = (-500, 200)
    _add_haze(mat, visibility)
    return mat


# Sunbeams: the water scatters the sun's beam towards the eye by b · p(θ) per metre
# and steradian, θ the angle between the beam and the way to the eye. b, the scattering
# coefficient, is taken as half the water's attenuation c (coastal and ocean waters
# scatter about as much as they absorb), and p is Henyey–Greenstein's phase function
# with mean cosine g = 0.85 (sea water's particles scatter forwards: a view towards the
# sun sees the shafts ~80 times brighter than an isotropic medium would show them).
_SUNBEAM_COLOUR = (0.55, 0.85, 0.95, 1.0)
_SUNBEAM_G = 0.85


def _sunbeam_material(info, sun_irradiance, strength):
    """The sunbeam volume's material: each voxel emits b · p(θ) · E (E = the grid × the
    sun's irradiance on flat water) per metre, times `strength`, and absorbs c per metre.
    Henyey–Greenstein: p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}), cos θ = the
    beam's direction · Geometry's Incoming (towards the eye)."""
    mat = bpy.data.materials.new("libwave sunbeams")
    mat.use_nodes = True
    tree = mat.node_tree
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    light = nodes.new("ShaderNodeAttribute")
    light.attribute_name = info.get("grid", "sunlight")
    attenuation = float(info.get("attenuation", 0.15))
    view = nodes.new("ShaderNodeNewGeometry")
    beam = nodes.new("ShaderNodeCombineXYZ")
    direction = frames.to_blender(np.array([info.get("direction", [0.0, -1.0, 0.0])], np.float64))[0]
    for socket, value in zip(beam.inputs, direction):
        socket.default_value = float(value)
    cos = nodes.new("ShaderNodeVectorMath")
    cos.operation = "DOT_PRODUCT"
    links.new(view.outputs["Incoming"], cos.inputs[0])
    links.new(beam.outputs["Vector"], cos.inputs[1])
    g = _SUNBEAM_G
    spread = _math(tree, "MULTIPLY_ADD", cos.outputs["Value"], -2.0 * g, 1.0 + g * g)
    power = _math(tree, "POWER", spread.outputs["Value"], 1.5)
    phase = _math(tree, "DIVIDE", 0.5 * attenuation * (1.0 - g * g) / (4.0 * math.pi) * sun_irradiance * float(strength),
                  power.outputs["Value"], label="b · p(θ) × sun irradiance × strength")
    scale = _math(tree, "MULTIPLY", light.outputs["Fac"], phase.outputs["Value"])
    glow = nodes.new("ShaderNodeEmission")
    glow.inputs["Color"].default_value = _SUNBEAM_COLOUR
    links.new(scale.outputs["Value"], glow.inputs["Strength"])
    absorb = nodes.new("ShaderNodeVolumeAbsorption")
    absorb.inputs["Density"].default_value = attenuation
    absorb.inputs["Color"].default_value = _SUNBEAM_COLOUR
    both = nodes.new("ShaderNodeAddShader")
    links.new(glow.outputs["Emission"], both.inputs[0])
    links.new(absorb.outputs["Volume"], both.inputs[1])
    links.new(both.outputs["Shader"], out.inputs["Volume"])
    for i, node in enumerate((view, cos, spread, power, phase, scale, glow, both, out)):
        node.location = (-1600 + 220 * i, 0)
    beam.location, light.location, absorb.location = (-1600, -250), (-500, 250), (-300, -250)
    return mat


def _sunbeam_volume(context, folder, info, sun_irradiance, strength):
    """The sunlight in the water as a Volume object playing the VDB sequence beside the
    file (docs/underwater.md) with `_sunbeam_material`: the shafts under focusing crests
    glow, brightest looking towards the sun, and fade with distance. Looping with the
    animation, file 0 at scene frame 0."""
    volume = bpy.data.volumes.new("libwave sunbeams")
    volume.filepath = os.path.join(folder, info["volumes"] % 0)
    volume.is_sequence = True
    volume.frame_duration = int(info["frames"])
    volume.frame_start = 0
    volume.frame_offset = -1  # Blender counts the sequence from 1: file 0 at scene frame 0
    volume.sequence_mode = "REPEAT"
    volume.materials.append(_sunbeam_material(info, sun_irradiance, strength))
    obj = bpy.data.objects.new("libwave sunbeams", volume)
    context.collection.objects.link(obj)
    return obj


def _sun_irradiance(dressing):
    """The sun's irradiance on a horizontal plane: its energy × sin(elevation) (1 without a sun)."""
    if dressing.sun is None:
        return 1.0
    matrix, intensity, _ = dressing.sun
    return float(intensity) * max(0.0, float(np.asarray(matrix)[2, 2]))


def import_dressing(context, dressing, folder="", caustics=True, visibility=DEFAULT_VISIBILITY, sunbeams=True,
                    sunbeam_strength=1.0):
    """The seafloor, camera and sun a libwave .glb carries, as Blender objects (the camera
    becomes the scene's); with `caustics`, the caustic maps beside the file (in `folder`)
    light the seafloor; `visibility` (m) hazes the seafloor seen from the camera with
    distance (Koschmieder's law; 0: none); with `sunbeams`, the sunbeam volumes beside
    the file glow in the water, `sunbeam_strength` times the single-scattering estimate."""
    from mathutils import Matrix
    made = []
    if dressing.seafloor is not None:
        positions, triangles, colours = dressing.seafloor
        mesh = _mesh_from_arrays("libwave seafloor", positions, triangles)
        _smooth(mesh)
        if colours is not None:
            mesh.attributes.new("depth colour", "FLOAT_COLOR", "POINT").data.foreach_set("color", frames.to_rgba(colours))
        maps = dressing.caustics if caustics else None
        if maps is not None and os.path.exists(os.path.join(folder, maps[1]["images"] % 0)):
            uv, info = maps
            layer = mesh.uv_layers.new(name="caustics")
            loops = np.empty(len(mesh.loops), np.int64)
            mesh.loops.foreach_get("vertex_index", loops)
            corner_uv = np.asarray(uv, np.float32)[loops].copy()
            corner_uv[:, 1] = 1.0 - corner_uv[:, 1]  # glTF's v runs down, Blender's up
            layer.data.foreach_set("uv", corner_uv.ravel())
            mesh.materials.append(_caustic_material(folder, info, _sun_irradiance(dressing), visibility))
        else:
            mesh.materials.append(_seafloor_material(visibility))
        obj = bpy.data.objects.new("libwave seafloor", mesh)
        context.collection.objects.link(obj)
        made.append(obj)
        beams = dressing.sunbeams if sunbeams else None
        if beams is not None and os.path.exists(os.path.join(folder, beams["volumes"] % 0)):
            made.append(_sunbeam_volume(context, folder, beams, _sun_irradiance(dressing), sunbeam_strength))
    if dressing.camera is not None:
        matrix, yfov, aspect = dressing.camera
        cam = bpy.data.cameras.new("libwave camera")
        cam.sensor_fit = "VERTICAL"
        cam.angle_y = yfov
        if dressing.seafloor is not None:  # a km-scale coast lies beyond Blender's default 100 m clip
            corners = dressing.seafloor[0]
            eye = np.asarray(matrix)[:3, 3]
            reach = float(np.max(np.linalg.norm(np.asarray(corners, np.float64) - eye, axis=1)))
            cam.clip_end = max(cam.clip_end, 1.5 * reach)
            cam.clip_start = max(cam.clip_start, cam.clip_end * 1e-6)  # a far field reaches 2000 camera heights
        obj = bpy.data.objects.new("libwave camera", cam)
        obj.matrix_world = Matrix(matrix.tolist())
        context.collection.objects.link(obj)
        context.scene.camera = obj
        render = context.scene.render
        render.resolution_x = max(1, round(render.resolution_y * aspect))
        made.append(obj)
    if dressing.sun is not None:
        matrix, intensity, colour = dressing.sun
        light = bpy.data.lights.new("libwave sun", "SUN")
        light.energy = intensity
        light.color = colour[:3]
        obj = bpy.data.objects.new("libwave sun", light)
        obj.matrix_world = Matrix(matrix.tolist())
        context.collection.objects.link(obj)
        made.append(obj)
    return made


# The world: Blender's physical sky (the Sky Texture node's Nishita model in 3.x and
# 4.x) with its sun where the file's sun is, or an HDRI; the sun lamp lights the scene
# directly, so the sky draws no sun disc of its own (no second sun).
SKY_STRENGTH = 0.3  # the Nishita sky's radiance is absolute: a third keeps the lamp's light in proportion


def _default_world(world):
    """Whether `world` is Blender's untouched default (a grey background, no nodes of the artist's)."""
    if world is None:
        return True
    if world.name != "World" or (world.use_nodes and world.node_tree is not None and
                                 any(n.type not in {"BACKGROUND", "OUTPUT_WORLD"} for n in world.node_tree.nodes)):
        return False
    return True


def sun_angles(matrix):
    """The Sky Texture's (sun_elevation, sun_rotation) for a sun lamp's world matrix: the
    direction to the sun is the lamp's +Z (it shines along −Z); the sky puts its sun at
    (−cos e · sin r, cos e · cos r, sin e)."""
    d = np.asarray(matrix)[:3, 2]
    d = d / max(np.linalg.norm(d), 1e-12)
    return math.asin(max(-1.0, min(1.0, float(d[2])))), math.atan2(-float(d[0]), float(d[1]))


def make_world(context, dressing, mode="AUTO", hdri=""):
    """A world for the scene (docs/blender.md, "Sky"): with `mode` AUTO only where the
    scene has none or Blender's untouched default, REPLACE always, KEEP never. The sky is
    Blender's physical sky with the sun where the file's is (30° up without one), or the
    HDRI image `hdri` when given. Returns the world made, or None."""
    scene = context.scene
    if mode == "KEEP" or (mode == "AUTO" and not _default_world(scene.world)):
        return None
    world = bpy.data.worlds.new("libwave sky")
    world.use_nodes = True
    tree = world.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputWorld")
    background = tree.nodes.new("ShaderNodeBackground")
    background.location = (-250, 0)
    tree.links.new(background.outputs["Background"], out.inputs["Surface"])
    if hdri:
        env = tree.nodes.new("ShaderNodeTexEnvironment")
        env.location = (-550, 0)
        env.image = bpy.data.images.load(os.path.abspath(bpy.path.abspath(hdri)), check_existing=True)
        tree.links.new(env.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = 1.0
    else:
        if dressing is not None and dressing.sun is not None:
            elevation, rotation = sun_angles(dressing.sun[0])
        else:
            elevation, rotation = math.radians(30.0), 0.0

        def physical_sky(disc, y):
            sky = tree.nodes.new("ShaderNodeTexSky")
            sky.location = (-750, y)
            sky.label = "sky seen (sun disc)" if disc else "sky lighting (no disc: the lamp is the sun)"
            types = [item.identifier for item in sky.bl_rna.properties["sky_type"].enum_items]
            sky.sky_type = "NISHITA" if "NISHITA" in types else types[-1]  # guarded: a later Blender may rename it
            for name, value in (("sun_elevation", max(elevation, 0.0)), ("sun_rotation", rotation % (2.0 * math.pi)),
                                ("sun_disc", disc), ("altitude", 0.0)):
                if hasattr(sky, name):
                    setattr(sky, name, value)
            return sky

        # The sky lights the scene without a disc (the sun lamp is the sun: no second
        # one); the camera sees the same sky with the sun's disc in it, as a photograph
        # of a low sun shows it. Only camera rays see the disc: it lights nothing.
        lit, seen = physical_sky(False, 150), physical_sky(True, -150)
        background.location = (-250, 150)
        tree.links.new(lit.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = SKY_STRENGTH
        camera_background = tree.nodes.new("ShaderNodeBackground")
        camera_background.location = (-250, -150)
        tree.links.new(seen.outputs["Color"], camera_background.inputs["Color"])
        camera_background.inputs["Strength"].default_value = SKY_STRENGTH
        path = tree.nodes.new("ShaderNodeLightPath")
        path.location = (-250, 400)
        mix = tree.nodes.new("ShaderNodeMixShader")
        mix.location = (0, 0)
        tree.links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
        tree.links.new(background.outputs["Background"], mix.inputs[1])
        tree.links.new(camera_background.outputs["Background"], mix.inputs[2])
        tree.links.new(mix.outputs["Shader"], out.inputs["Surface"])
    scene.world = world
    return world


def import_animation(context, path, set_scene=True, caustics=True, bake=False, baked_colour=False, file_normals=False,
                     visibility=DEFAULT_VISIBILITY, sunbeams=True, sunbeam_strength=1.0, world="AUTO", hdri="",
                     whitewater_points=True, meter_exposure=True):
    """Creates the water object for `path` (a .glb/.gltf or index.json); with `set_scene`
    the scene's fps and frame range become the animation's; with `caustics` the caustic
    maps beside it (when the run wrote them) light the seafloor; with `bake` every frame
    is stored in the .blend and played by Blender's own nodes (bake.py), otherwise the
    frames are read from the file on each frame change; with `baked_colour` the water
    shows the file's baked colour (a ValueError when it has none); with `file_normals`
    (not with `bake`) each frame change also sets the file's normals as custom normals;
    `visibility` (m) hazes the seafloor with distance (0: none); with `sunbeams` the
    sunbeam volumes beside it (when the run wrote them) glow in the water,
    `sunbeam_strength` times the single-scattering estimate; `world` and `hdri` as
    make_world takes them (the sky over the scene); with `whitewater_points` the
    whitewater particles beside it (when the run wrote them, /whitewater) drawn by
    Geometry Nodes: spray droplets, foam lace, bubbles (docs/whitewater.md); with
    `meter_exposure`, where the import made the sky and the scene has a camera, the
    view's exposure metered through it (exposure.meter)."""
    anim = _animation(os.path.abspath(path))
    if bake:
        frames.check_bake(anim)  # before the water object is made
    mesh = water_mesh("libwave water", anim)
    if baked_colour and anim.frame(0).color is None:
        bpy.data.meshes.remove(mesh)
        raise ValueError(f"{path} has no baked colour (run the scene with \"outputs\": {{\"color\": true}})")
    set_rest(mesh)
    _smooth(mesh, file_normals and not bake)
    mesh.materials.append(water_material(baked_colour))
    obj = bpy.data.objects.new(mesh.name, mesh)
    context.collection.objects.link(obj)
    obj["libwave_form"] = anim.form
    if bake:
        baking.bake(context, obj, anim)
    else:
        obj[_PROP] = anim.path
        obj["libwave_frame_start"] = 0
        obj["libwave_file_normals"] = bool(file_normals)
    scene = context.scene
    if set_scene:
        scene.render.fps = max(1, round(anim.fps))
        scene.render.fps_base = scene.render.fps / anim.fps
        scene.frame_start = 0
        scene.frame_end = anim.frame_count - 1  # the loop; frames past it repeat it (the handler wraps)
    if _on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(_on_frame_change)
    if anim.dressing is not None:
        import_dressing(context, anim.dressing, anim.folder, caustics, visibility, sunbeams, sunbeam_strength)
    sky = make_world(context, anim.dressing, world, hdri)
    if whitewater_points:
        whitewater.import_points(context, anim.folder, anim.frame_count, getattr(anim, "first_frame", 0), water=obj)
    if not bake:
        apply_frame(obj, scene.frame_current)
    if meter_exposure and sky is not None:  # the add-on's own light: exposed for, as a camera meters it
        try:
            exposure.meter(context)
        except Exception as e:  # noqa: BLE001 — a meter that fails leaves the exposure, never the import
            print(frames.printable(f"libwave: the exposure was not metered: {e}"))
    return obj


class ImportLibwave(bpy.types.Operator, ImportHelper):
    """Import a libwave animation: animation.glb/.gltf (morph or nodes form) or index.json (files form)"""

    bl_idname = "import_scene.libwave"
    bl_label = "Import libwave animation"
    bl_options = {"REGISTER", "UNDO"}
    filename_ext = ".glb"
    filter_glob: StringProperty(default="*.glb;*.gltf;index.json", options={"HIDDEN"})
    set_scene: BoolProperty(name="Set fps and frame range", default=True)
    caustics: BoolProperty(name="Caustics on the seafloor", default=True,
                           description="Light the seafloor with the caustic maps beside the file (/underwater)")
    bake: BoolProperty(name="Bake into the .blend", default=False,
                       description="Store every frame in the .blend and play it with Geometry Nodes: the saved file "
                                   "plays without this add-on and without the source files (memory: all frames)")

    baked_colour: BoolProperty(name="Ts'o's baked colour", default=False,
                               description="Shade the water by the colour `wave run` baked (outputs.color: Ts'o's "
                                           "R · sky + T · water colour) instead of the physical water material")

    file_normals: BoolProperty(name="The file's normals", default=False,
                               description="Set the file's exact normals as custom normals on every frame change "
                                           "(about 0.1 s a frame for 16 000 vertices); off: Blender's smooth normals of "
                                           "the animated positions. Not with the bake")

    visibility: FloatProperty(name="Haze: visibility (m)", default=DEFAULT_VISIBILITY, min=0.0, soft_max=200000.0,
                              description="Aerial perspective on the seafloor seen from the camera: it fades into the "
                                          "sky with distance, to 2 % contrast at this distance (Koschmieder); a coast's "
                                          "land carried to the horizon fades as in haze. 0: none")

    sunbeams: BoolProperty(name="Sunbeams in the water", default=True,
                           description="Play the sunbeam volumes beside the file (/underwater/sunbeams) as a glowing "
                                       "volume in the water")

    sunbeam_strength: FloatProperty(name="Sunbeam strength", default=1.0, min=0.0, soft_max=100.0,
                                    description="Times the single-scattering estimate (b = c / 2, isotropic); real "
                                                "water scatters forwards, so views towards the sun may want more")

    world: EnumProperty(name="Sky", default="AUTO",
                        items=[("AUTO", "Sky where none", "A physical sky with the file's sun where the scene has no "
                                                          "world or Blender's default grey one"),
                               ("REPLACE", "Replace the world", "A new sky world even where the scene has one"),
                               ("KEEP", "Keep the scene's world", "Make no world")])
    hdri: StringProperty(name="HDRI", default="", subtype="FILE_PATH",
                         description="An environment image for the sky instead of the physical sky (with Sky: where "
                                     "none or replace)")

    whitewater: BoolProperty(name="Whitewater", default=True,
                             description="Play the whitewater particles beside the file (/whitewater: spray, foam, "
                                         "bubbles) through Geometry Nodes: streaked droplets, sheets of foam lace on the water, "
                                         "faint specks (rendered by Cycles)")

    meter_exposure: BoolProperty(name="Meter the exposure", default=True,
                                 description="Where the import makes the sky: set the view's exposure from a small "
                                             "render through the file's camera, as a camera's meter would (its "
                                             "log-average luminance to middle grey); the physical sky is absolute, "
                                             "a view into a low sun needs stops less than a noon beach")

    def execute(self, context):
        try:
            import_animation(context, self.filepath, self.set_scene, self.caustics, self.bake, self.baked_colour,
                             self.file_normals, self.visibility, self.sunbeams, self.sunbeam_strength, self.world,
                             self.hdri, self.whitewater, self.meter_exposure)
        except (OSError, KeyError, ValueError, frames.LibwaveFileError) as e:
            self.report({"ERROR"}, frames.printable(f"libwave: {e}"))
            return {"CANCELLED"}
        return {"FINISHED"}


def _menu(self, context):
    self.layout.operator(ImportLibwave.bl_idname, text="libwave animation (.glb, index.json)")


@persistent
def _forget_meshes(*_args):
    """A .blend loaded: its meshes are new (a freed mesh's address may come back)."""
    _mesh_orders.clear()


def register():
    live.register()
    if _forget_meshes not in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.append(_forget_meshes)
    bpy.utils.register_class(exposure.MeterExposure)
    bpy.utils.register_class(ImportLibwave)
    bpy.types.TOPBAR_MT_file_import.append(_menu)
    if _on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(_on_frame_change)
    whitewater.add_handlers()


def unregister():
    if _forget_meshes in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(_forget_meshes)
    whitewater.remove_handlers()
    if _on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(_on_frame_change)
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(ImportLibwave)
    bpy.utils.unregister_class(exposure.MeterExposure)
    live.unregister()
