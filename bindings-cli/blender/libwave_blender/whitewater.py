"""Whitewater beside an animation (docs/whitewater.md): `wave run` with /whitewater writes
one POINTS .glb per loop frame, whitewater/whitewater-NNNN.glb. The add-on makes one
object whose vertices are the frame's particles (attributes size, kind, age, velocity),
replaced on every frame change, and a Geometry Nodes modifier that draws them (docs/
whitewater.md, "The look in Blender"): spray as puffs of fine droplets streaked along
their velocity, thinning with age; foam as sheets of lace laid on the water, the same
lace pattern (lace_group) as the water material's own foam; bubbles as faint specks."""

import concurrent.futures
import os
import re
import time

import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import frames

FOLDER = "whitewater"
_NAME = re.compile(r"whitewater-(\d{4,})\.glb$")
_PROP = "libwave_whitewater"  # the folder whose files the object plays


_listed = {}  # folder → ((inode, mtime) of its whitewater folder, sequence): a frame change lists it once
_ahead = {}  # object name → ((file, share, its (mtime, size) then), read_points on the worker): its next loop frame's
_worker = None


def sequence(folder):
    """{loop frame: file} of the whitewater files beside an animation in `folder` ({} when none).
    Listed again only when the whitewater folder changed (its inode or mtime; a folder
    changed in the last 2 s is not cached): listing 200–300 files on every frame change
    cost a few milliseconds of playback."""
    root = os.path.join(folder, FOLDER)
    if not os.path.isdir(root) or os.path.islink(root):
        _listed.pop(folder, None)
        return {}
    st = os.stat(root)
    stamp = (st.st_ino, st.st_mtime_ns)
    held = _listed.get(folder)
    if held is not None and held[0] == stamp:
        return held[1]
    found = {}
    for name in os.listdir(root):
        m = _NAME.match(name)
        if m:
            found[int(m.group(1))] = os.path.join(root, name)
    if time.time() - st.st_mtime > 2.0:  # a folder still being written may change within its mtime's tick
        _listed[folder] = (stamp, found)
    return found


# The share of a frame's particles the viewport shows (the whitewater object's property
# "libwave_viewport_share", 0–1, as Blender's particle systems have a viewport display
# amount): a breaking coast throws 200–400 k particles a frame, and reading and setting
# them all made each frame change of playback 15–30 ms slower. Renders take every
# particle (on_render_init). The share is a fixed stride through the file's order, the
# same particles on every play.
VIEWPORT_SHARE = 0.25
SHARE_PROP = "libwave_viewport_share"
_rendering = False  # between render_init and render_complete / render_cancel


def shown_share(obj, render_done=False):
    """The share of its particles `obj` shows now: 1 while a render runs, else its
    viewport share (clamped to 0.01–1). `render_done`: asked from render_complete /
    render_cancel, where an interactive render's job still counts as running."""
    if _rendering or (not render_done and hasattr(bpy.app, "is_job_running") and bpy.app.is_job_running("RENDER")):
        return 1.0
    try:
        share = float(obj.get(SHARE_PROP, VIEWPORT_SHARE))
    except (TypeError, ValueError):
        share = VIEWPORT_SHARE
    return min(1.0, max(0.01, share)) if share == share else VIEWPORT_SHARE


def share_step(share):
    """The stride through a frame's particles that shows `share` of them."""
    return max(1, int(round(1.0 / share)))


def read_points(path, share=1.0):
    """A frame's particles: dict of positions (n, 3) in Blender's axes (z up), velocity
    (n, 3), age, size and kind (n,) — empty arrays for a frame with none. With `share`
    < 1, every share_step(share)-th particle only (taken before any conversion)."""
    doc, buffers = frames.read_gltf(path)
    extras = doc.get("scenes", [{}])[0].get("extras", {}).get("libwave_whitewater")
    if not isinstance(extras, dict):
        raise frames.LibwaveFileError(frames.printable(f"{path}: not a libwave whitewater file (no scene extras libwave_whitewater)"))
    empty = read_points_empty()
    if not doc.get("meshes"):
        return empty
    prim = doc["meshes"][0]["primitives"][0]
    if prim.get("mode") != 0:
        raise frames.LibwaveFileError(frames.printable(f"{path}: its primitive is not POINTS (mode {prim.get('mode')!r})"))
    attrs = prim["attributes"]
    step = share_step(share)
    get = lambda name: frames.accessor(doc, buffers, attrs[name])[::step]
    out = {"positions": frames.to_blender(get("POSITION")), "velocity": frames.to_blender(get("_VELOCITY")),
           "age": get("_AGE")[:, 0], "size": get("_SIZE")[:, 0], "kind": get("_KIND")[:, 0]}
    n = len(out["positions"])
    if any(len(v) != n for v in out.values()):
        raise frames.LibwaveFileError(frames.printable(f"{path}: the particles' attributes differ in count"))
    if n and not np.isfinite(out["positions"]).all():
        raise frames.LibwaveFileError(frames.printable(f"{path}: a particle's position is not finite"))
    return out


# The look (docs/whitewater.md, "The look in Blender"), tuned on the breaking beach from
# 1–8 m above the water at 640 × 360 and 16 Cycles samples.
SPRAY_DROPLETS = 64   # droplets drawn for each spray particle (a particle is a puff of spray)
SPRAY_STREAK = 0.06   # s: a droplet trails its particle along the velocity by up to this (the puff's streak)
SPRAY_SHUTTER = 1.0 / 48.0  # s: each droplet drawn as long as a film camera's shutter (180° at 24 fps) smears it
SPRAY_DROPLET = 0.12  # a droplet's radius, × the particle's size (× 0.5 … 1.5 at random: 2–20 mm for sizes 4–12 cm)
SPRAY_SPREAD = 2.0    # a puff's radius grows by this × the particle's size a second (the mist spreading)
SPRAY_THIN = 0.8      # s: the share of a puff's droplets still drawn falls as e^(−age / this)
SPRAY_OPACITY = 0.9   # a droplet's opacity when thrown; it fades like the puff thins
SPRAY_GLOW = 0.35     # the puff's multiple scattering, as an emission of this strength
FOAM_SHEET = 3.0      # a foam particle's sheet of lace: a square this × its size from centre to edge
SHEET_SHARPNESS = 2.5  # how fast a sheet's lace fades in over the lace's value (the water's own: 6); at 6 the
                       # sheets read as "flat, sharp-edged blobs" (a reviewer)
FOAM_STREAK = 1.5     # s: the sheet is stretched along the flow by 1 + speed × this (at most 3 ×)
FOAM_FRESH = 2.0      # s: fresh foam is dense lace, old foam a thin web: its density falls as e^(−age / this)
FOAM_LIFT = 0.02      # m: the sheets float this far above the water
FOAM_DENSITY = (0.25, 0.85)  # the lace's density in an old sheet's middle, and in a fresh one's
BUBBLE_RADIUS = 0.5   # a bubble drawn at this × its size
BUBBLE_OPACITY = 0.2  # faint


def _new_group(name, kind):
    """An empty node group of `kind` ("GeometryNodeTree" or "ShaderNodeTree")."""
    group = bpy.data.node_groups.new(name, kind)
    return group


def _socket(group, in_out, socket_type, name):
    if hasattr(group, "interface"):  # Blender 4.0+
        group.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    elif in_out == "INPUT":  # 3.x
        group.inputs.new(socket_type, name)
    else:
        group.outputs.new(socket_type, name)


class _Tree:
    """Small helpers to wire a node tree: math on sockets or numbers."""

    def __init__(self, tree):
        self.nodes, self.links = tree.nodes, tree.links

    def node(self, kind, **settings):
        n = self.nodes.new(kind)
        for key, value in settings.items():
            setattr(n, key, value)
        return n

    def put(self, socket, value):
        if isinstance(value, bpy.types.NodeSocket):
            self.links.new(value, socket)
        elif value is not None:
            socket.default_value = value

    def noise(self, vector, scale, detail, dimensions="3D"):
        """A Noise Texture node of `scale` and `detail` at `vector` (a socket)."""
        n = self.node("ShaderNodeTexNoise", noise_dimensions=dimensions)
        n.inputs["Scale"].default_value = scale
        n.inputs["Detail"].default_value = detail
        self.links.new(vector, n.inputs["Vector"])
        return n

    def math(self, operation, a, b=None, c=None):
        n = self.node("ShaderNodeMath", operation=operation)
        for socket, value in zip(n.inputs, (a, b, c)):
            self.put(socket, value)
        return n.outputs[0]

    def vmath(self, operation, a, b=None, scale=None):
        n = self.node("ShaderNodeVectorMath", operation=operation)
        self.put(n.inputs[0], a)
        self.put(n.inputs[1], b)
        if scale is not None:
            self.put(n.inputs["Scale"], scale)
        return n.outputs["Value" if operation in ("LENGTH", "DOT_PRODUCT", "DISTANCE") else "Vector"]

    def clamp01(self, a):
        n = self.node("ShaderNodeClamp")
        self.put(n.inputs["Value"], a)
        return n.outputs[0]

    def combine(self, x, y, z):
        n = self.node("ShaderNodeCombineXYZ")
        for socket, value in zip(n.inputs, (x, y, z)):
            self.put(socket, value)
        return n.outputs[0]

    def separate(self, vector):
        n = self.node("ShaderNodeSeparateXYZ")
        self.put(n.inputs[0], vector)
        return n.outputs

    def mix_shader(self, fac, a, b):
        n = self.node("ShaderNodeMixShader")
        self.put(n.inputs["Fac"], fac)
        self.links.new(a, n.inputs[1])
        self.links.new(b, n.inputs[2])
        return n.outputs["Shader"]


def lace_group():
    """The shader node group "libwave foam lace": Vector (m) → Lace, about 0 … 1, a pattern
    in x and y (foam lies on the water; a 2D Voronoi searches 9 cells, a 3D one 27): low along
    a web of lines (the edges of Voronoi cells about 1 m and 0.3 m across, their space
    warped by noise so that the web is torn, not cellular), high in the holes between
    them, raised in small round bubbles (the nearest-point distance of cells 0.1 m across)
    and grained by fine noise. A material shows foam where Lace < its foam density: a
    little foam is a thin broken web, more of it thickens the web into lace with bubbles,
    full foam closes the holes."""
    group = bpy.data.node_groups.get("libwave foam lace")
    if group is not None:
        return group
    group = _new_group("libwave foam lace", "ShaderNodeTree")
    _socket(group, "INPUT", "NodeSocketVector", "Vector")
    _socket(group, "OUTPUT", "NodeSocketFloat", "Lace")
    t = _Tree(group)
    inp, out = t.node("NodeGroupInput"), t.node("NodeGroupOutput")
    p = inp.outputs[0]
    warp = t.noise(p, 0.7, 3.0, "2D")
    warped = t.vmath("ADD", p, t.vmath("SCALE", t.vmath("SUBTRACT", warp.outputs["Color"], (0.5, 0.5, 0.5)), scale=1.2))

    def voronoi(scale, feature, width, vector=warped):
        v = t.node("ShaderNodeTexVoronoi", feature=feature, voronoi_dimensions="2D")
        v.inputs["Scale"].default_value = scale
        t.links.new(vector, v.inputs["Vector"])
        return t.clamp01(t.math("DIVIDE", v.outputs["Distance"], width))

    grain = t.noise(p, 30.0, 2.0, "2D")
    web = t.math("ADD", t.math("MULTIPLY", voronoi(1.0, "DISTANCE_TO_EDGE", 0.3), 0.45),
                 t.math("MULTIPLY", voronoi(3.5, "DISTANCE_TO_EDGE", 0.35), 0.3))
    bubbles = t.math("SUBTRACT", 1.0, voronoi(10.0, "F1", 0.45, p))  # 1 at a bubble's centre
    lace = t.math("MULTIPLY_ADD", bubbles, 0.25, web)
    lace = t.math("MULTIPLY_ADD", grain.outputs["Fac"], 0.4, t.math("SUBTRACT", lace, 0.2))
    t.links.new(lace, out.inputs[0])
    return group


def _lace_mask(t, coordinates, density, sharpness=6.0):
    """Foam's coverage 0 … 1: where the lace at `coordinates` (m) lies under `density`,
    fading in over 1 / `sharpness` of the lace (thin foam lets the water through)."""
    lace = t.node("ShaderNodeGroup")
    lace.node_tree = lace_group()
    t.links.new(coordinates, lace.inputs[0])
    return t.clamp01(t.math("MULTIPLY", t.math("SUBTRACT", density, lace.outputs[0]), sharpness))


def foam_shader(t):
    """Foam's own shading: white, matt, a little light let through (a froth of bubbles)."""
    white = t.node("ShaderNodeBsdfDiffuse")
    white.inputs["Color"].default_value = (0.9, 0.92, 0.94, 1.0)
    through = t.node("ShaderNodeBsdfTranslucent")
    through.inputs["Color"].default_value = (0.8, 0.88, 0.9, 1.0)
    return t.mix_shader(0.25, white.outputs[0], through.outputs[0])


def _attribute(t, name, output="Fac"):
    a = t.node("ShaderNodeAttribute")
    a.attribute_name = name
    return a.outputs[output]


def _material(name, build):
    mat = bpy.data.materials.get(name)
    if mat is not None:
        return mat
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    tree = mat.node_tree
    tree.nodes.clear()
    t = _Tree(tree)
    out = t.node("ShaderNodeOutputMaterial")
    t.links.new(build(t), out.inputs["Surface"])
    if hasattr(mat, "blend_method"):  # EEVEE: the transparent share by dithering
        mat.blend_method = "HASHED"
    return mat


def _fade(t, age, time):
    """e^(−age / time)."""
    return t.math("EXPONENT", t.math("DIVIDE", t.math("MULTIPLY", age, -1.0), time))


def _no_shadow(t, opacity):
    """`opacity` for camera and light bounces, 0 for shadow rays: a mist of droplets lets
    the sun through (it scatters it forwards) where an opaque droplet would blot the foam
    under it with a shadow."""
    shadow = t.node("ShaderNodeLightPath").outputs["Is Shadow Ray"]
    return t.math("MULTIPLY", opacity, t.math("SUBTRACT", 1.0, shadow))


def spray_material():
    """Spray droplets: bright white and semi-translucent, fading as the puff thins."""
    def build(t):
        white = t.node("ShaderNodeBsdfDiffuse")
        white.inputs["Color"].default_value = (0.95, 0.97, 1.0, 1.0)
        through = t.node("ShaderNodeBsdfTranslucent")
        through.inputs["Color"].default_value = (0.95, 0.97, 1.0, 1.0)
        droplet = t.mix_shader(0.5, white.outputs[0], through.outputs[0])
        # A puff is optically thick: light scattered many times in it leaves it white on
        # every side, lit or not, which a few dozen drawn droplets cannot carry; a faint
        # glow stands in for it (SPRAY_GLOW, of the sky's white).
        glow = t.node("ShaderNodeEmission")
        glow.inputs["Color"].default_value = (0.9, 0.95, 1.0, 1.0)
        glow.inputs["Strength"].default_value = SPRAY_GLOW
        lit = t.node("ShaderNodeAddShader")
        t.links.new(droplet, lit.inputs[0])
        t.links.new(glow.outputs[0], lit.inputs[1])
        droplet = lit.outputs[0]
        opacity = t.math("MULTIPLY", _fade(t, _attribute(t, "age"), SPRAY_THIN), SPRAY_OPACITY)
        return t.mix_shader(_no_shadow(t, opacity), t.node("ShaderNodeBsdfTransparent").outputs[0], droplet)
    return _material("libwave whitewater spray", build)


def foam_material():
    """Foam particles' sheets: the water's lace (lace_group) at the water's rest
    coordinates (the shading point's position plus the sheet's "anchor": the same pattern
    as the water's own foam, riding with it), dense while the foam is fresh and a thin web
    as it ages, thinning to nothing towards the sheet's edge ("lace": the sheet's own
    coordinates); transparent elsewhere. Where sheets overlap, the densest one shows: the
    lace stays one pattern."""
    def build(t):
        local = _attribute(t, "lace", "Vector")
        at = t.vmath("ADD", t.node("ShaderNodeNewGeometry").outputs["Position"], _attribute(t, "anchor", "Vector"))
        x, y, _ = t.separate(local)
        r = t.math("MULTIPLY", t.math("SQRT", t.math("ADD", t.math("MULTIPLY", x, x), t.math("MULTIPLY", y, y))), 2.0)
        edge = t.node("ShaderNodeMapRange")  # 1 at the centre, 0 from r 1
        t.put(edge.inputs["Value"], r)
        edge.inputs["From Min"].default_value, edge.inputs["From Max"].default_value = 0.0, 1.0
        edge.inputs["To Min"].default_value, edge.inputs["To Max"].default_value = 1.0, 0.0
        edge.interpolation_type = "SMOOTHSTEP"
        fresh = t.math("MULTIPLY_ADD", _fade(t, _attribute(t, "age"), FOAM_FRESH), FOAM_DENSITY[1] - FOAM_DENSITY[0],
                       FOAM_DENSITY[0])
        density = t.math("MULTIPLY", fresh, edge.outputs["Result"])
        mask = _lace_mask(t, at, density, SHEET_SHARPNESS)
        # Seen by camera rays only: a sheet's underside, a few centimetres over the water,
        # would otherwise darken the water's reflection in the lace's holes.
        seen = t.math("MULTIPLY", mask, t.node("ShaderNodeLightPath").outputs["Is Camera Ray"])
        return t.mix_shader(seen, t.node("ShaderNodeBsdfTransparent").outputs[0], foam_shader(t))
    return _material("libwave whitewater foam", build)


def bubble_material():
    """Bubbles under the surface: faint pale blue-white specks seen through the water."""
    def build(t):
        pale = t.node("ShaderNodeBsdfDiffuse")
        pale.inputs["Color"].default_value = (0.75, 0.88, 0.92, 1.0)
        return t.mix_shader(_no_shadow(t, BUBBLE_OPACITY), t.node("ShaderNodeBsdfTransparent").outputs[0], pale.outputs[0])
    return _material("libwave whitewater bubbles", build)


def material():
    """The material the whitewater object's own mesh carries (its drawn geometry takes the
    three kinds' materials in the node group): the spray's."""
    return spray_material()


def _specks(t, points, selection, rotation, scale):
    """A tetrahedron (base radius 1, 1 high, centred) on each of `points` (where `selection`),
    turned by `rotation` and scaled by `scale` (sockets or None), realised."""
    tetra = t.node("GeometryNodeMeshCone")
    tetra.inputs["Vertices"].default_value = 3
    tetra.inputs["Radius Top"].default_value = 0.0
    tetra.inputs["Radius Bottom"].default_value = 1.0
    tetra.inputs["Depth"].default_value = 1.0
    on = t.node("GeometryNodeInstanceOnPoints")
    t.links.new(points, on.inputs["Points"])
    t.links.new(tetra.outputs["Mesh"], on.inputs["Instance"])
    for name, value in (("Selection", selection), ("Rotation", rotation), ("Scale", scale)):
        if value is not None:
            t.links.new(value, on.inputs[name])
    real = t.node("GeometryNodeRealizeInstances")
    t.links.new(on.outputs[0], real.inputs["Geometry"])
    return real.outputs[0]


def _node_group():
    """Geometry Nodes for the particles (docs/whitewater.md, "The look in Blender"):
    * spray (kind 0): each particle a puff of SPRAY_DROPLETS droplets (small tetrahedra
      pointing along the velocity, as long as SPRAY_SHUTTER smears them), strung back
      along its velocity over SPRAY_STREAK s and scattered over a radius that grows with
      its age, fewer as it ages;
    * foam (kind 1): each particle a flat square sheet laid on the water (the group's
      input "Water"), FOAM_SHEET × its size from centre to edge, stretched along its
      velocity, turned at random, whose material draws the lace in it (attributes
      "lace": the sheet's own coordinates, "anchor": the water's rest position under it
      minus its own);
    * bubbles (kind 2): small faint specks.
    The Named Attribute node of Blender 3.x keeps an output per data type, all named
    "Attribute": the enabled one is linked."""
    group = bpy.data.node_groups.get("libwave whitewater points")
    if group is not None:
        return group
    group = _new_group("libwave whitewater points", "GeometryNodeTree")
    _socket(group, "INPUT", "NodeSocketGeometry", "Geometry")
    _socket(group, "INPUT", "NodeSocketObject", "Water")
    _socket(group, "INPUT", "NodeSocketBool", VIEWPORT_FULL)
    _socket(group, "OUTPUT", "NodeSocketGeometry", "Geometry")
    t = _Tree(group)
    inp, out = t.node("NodeGroupInput"), t.node("NodeGroupOutput")
    geometry = inp.outputs[0]

    def attribute(name, data_type="FLOAT"):
        node = t.node("GeometryNodeInputNamedAttribute", data_type=data_type)
        node.inputs["Name"].default_value = name
        return next(o for o in node.outputs if o.name == "Attribute" and getattr(o, "enabled", True))

    def random(low, high, seed, data_type="FLOAT"):
        node = t.node("FunctionNodeRandomValue", data_type=data_type)
        vector = data_type == "FLOAT_VECTOR"
        for socket in node.inputs:
            if socket.name == "Seed":
                socket.default_value = seed
            elif socket.identifier == ("Min" if vector else "Min_001"):
                socket.default_value = low
            elif socket.identifier == ("Max" if vector else "Max_001"):
                socket.default_value = high
        t.links.new(t.node("GeometryNodeInputIndex").outputs[0], node.inputs["ID"])
        return next(o for o in node.outputs if o.identifier == ("Value" if vector else "Value_001"))

    def is_kind(k):
        return t.math("COMPARE", attribute("kind"), float(k), 0.5)

    def with_material(geometry, material):
        node = t.node("GeometryNodeSetMaterial")
        t.links.new(geometry, node.inputs["Geometry"])
        node.inputs["Material"].default_value = material
        return node.outputs[0]

    size, age, velocity = attribute("size"), attribute("age"), attribute("velocity", "FLOAT_VECTOR")

    # Spray: puffs of streaked droplets.
    points = t.node("GeometryNodeMeshToPoints")
    t.links.new(geometry, points.inputs["Mesh"])
    t.links.new(is_kind(0), points.inputs["Selection"])
    droplets = t.node("GeometryNodeDuplicateElements", domain="POINT")
    droplets.label = "spray droplets"
    t.links.new(points.outputs[0], droplets.inputs["Geometry"])
    droplets.inputs["Amount"].default_value = SPRAY_DROPLETS
    streak = t.vmath("SCALE", velocity, scale=t.math("MULTIPLY", random(0.0, 1.0, 21), -SPRAY_STREAK))
    reach = t.math("MULTIPLY", size, t.math("MULTIPLY_ADD", age, SPRAY_SPREAD, 0.6))
    scatter = t.vmath("SCALE", random((-1.0, -1.0, -0.6), (1.0, 1.0, 0.6), 22, "FLOAT_VECTOR"), scale=reach)
    moved = t.node("GeometryNodeSetPosition")
    t.links.new(droplets.outputs["Geometry"], moved.inputs["Geometry"])
    t.links.new(t.vmath("ADD", streak, scatter), moved.inputs["Offset"])
    thinned = t.node("GeometryNodeDeleteGeometry", domain="POINT")
    t.links.new(moved.outputs[0], thinned.inputs["Geometry"])
    t.links.new(t.math("GREATER_THAN", random(0.0, 1.0, 24), _fade(t, age, SPRAY_THIN)), thinned.inputs["Selection"])
    # Each droplet a small tetrahedron (a point cloud takes no material in Blender 3.4's
    # Set Material; at a few pixels a droplet's shape does not show) pointing along the
    # velocity, as long as a shutter of SPRAY_SHUTTER s draws it.
    radius = t.math("MULTIPLY", size, t.math("MULTIPLY", random(0.5, 1.5, 23), SPRAY_DROPLET))
    length = t.math("MULTIPLY_ADD", t.vmath("LENGTH", velocity), SPRAY_SHUTTER, t.math("MULTIPLY", radius, 2.0))
    along = t.node("FunctionNodeAlignEulerToVector", axis="Z", pivot_axis="AUTO")
    t.links.new(velocity, along.inputs["Vector"])
    spray = with_material(_specks(t, thinned.outputs[0], None, along.outputs[0], t.combine(radius, radius, length)),
                          spray_material())

    # Foam: sheets of lace lying on the water.
    square = t.node("GeometryNodeMeshGrid")
    square.inputs["Size X"].default_value = square.inputs["Size Y"].default_value = 1.0
    square.inputs["Vertices X"].default_value = square.inputs["Vertices Y"].default_value = 2
    local = t.node("GeometryNodeStoreNamedAttribute", data_type="FLOAT_VECTOR", domain="POINT")
    local.inputs["Name"].default_value = "lace"
    t.links.new(square.outputs[0], local.inputs["Geometry"])
    t.links.new(t.node("GeometryNodeInputPosition").outputs[0], next(s for s in local.inputs if s.identifier == "Value_Vector"))
    speed = t.vmath("LENGTH", velocity)
    stretch = t.math("MINIMUM", t.math("MULTIPLY_ADD", speed, FOAM_STREAK, 1.0), 3.0)
    across = t.math("MULTIPLY", size, 2.0 * FOAM_SHEET)
    sheet = t.combine(t.math("MULTIPLY", across, stretch), across, 1.0)  # the sheet's scale: the flow stretches it

    def store(geometry, name, value):
        node = t.node("GeometryNodeStoreNamedAttribute", data_type="FLOAT_VECTOR", domain="POINT")
        node.inputs["Name"].default_value = name
        t.links.new(geometry, node.inputs["Geometry"])
        t.links.new(value, next(s for s in node.inputs if s.identifier == "Value_Vector"))
        return node.outputs[0]

    # On the water (the water object of the group's input "Water"): each sheet laid on the
    # surface point nearest its particle, FOAM_LIFT along the surface's normal, tilted to
    # it, and its "anchor" the water's rest position there ("rest", set by the add-on's
    # import) minus its own: the lace's coordinates are a shading point's position plus
    # the anchor, the same pattern as the water's own foam, riding with the water. Without
    # a water object the sheets lie flat where the particles are and the lace is the
    # world's.
    water = t.node("GeometryNodeObjectInfo", transform_space="RELATIVE")
    t.links.new(inp.outputs[1], water.inputs["Object"])
    count = t.node("GeometryNodeAttributeDomainSize", component="MESH")
    t.links.new(water.outputs["Geometry"], count.inputs[0])
    has_water = t.math("MINIMUM", count.outputs["Point Count"], 1.0)
    here = t.node("GeometryNodeInputPosition").outputs[0]

    def on_water(field):
        node = t.node("GeometryNodeSampleNearestSurface", data_type="FLOAT_VECTOR")
        t.links.new(water.outputs["Geometry"], node.inputs["Mesh"])
        t.links.new(field, next(s for s in node.inputs if s.identifier == "Value_Vector"))
        t.links.new(here, node.inputs["Sample Position"])
        return next(s for s in node.outputs if s.identifier == "Value_Vector")

    normal = on_water(t.node("GeometryNodeInputNormal").outputs[0])
    surface = t.vmath("ADD", on_water(here), t.vmath("SCALE", normal, scale=FOAM_LIFT))
    placed = t.vmath("ADD", here, t.vmath("SCALE", t.vmath("SUBTRACT", surface, here), scale=has_water))
    anchor = t.vmath("SCALE", t.vmath("SUBTRACT", on_water(attribute("rest", "FLOAT_VECTOR")), placed), scale=has_water)
    laid = t.node("GeometryNodeSetPosition")
    t.links.new(geometry, laid.inputs["Geometry"])
    t.links.new(is_kind(1), laid.inputs["Selection"])
    t.links.new(placed, laid.inputs["Position"])
    carrying = store(laid.outputs[0], "anchor", anchor)
    turn = t.node("FunctionNodeAlignEulerToVector", axis="X", pivot_axis="Z")
    t.links.new(t.combine(0.0, 0.0, random(0.0, 6.2831853, 32)), turn.inputs["Rotation"])
    t.links.new(t.clamp01(t.math("MULTIPLY", speed, 4.0)), turn.inputs["Factor"])
    t.links.new(velocity, turn.inputs["Vector"])
    tilt = t.node("FunctionNodeAlignEulerToVector", axis="Z", pivot_axis="AUTO")
    t.links.new(turn.outputs[0], tilt.inputs["Rotation"])
    t.links.new(has_water, tilt.inputs["Factor"])
    t.links.new(normal, tilt.inputs["Vector"])
    sheets = t.node("GeometryNodeInstanceOnPoints")
    sheets.label = "foam sheets"
    t.links.new(carrying, sheets.inputs["Points"])
    t.links.new(is_kind(1), sheets.inputs["Selection"])
    t.links.new(local.outputs[0], sheets.inputs["Instance"])
    t.links.new(tilt.outputs[0], sheets.inputs["Rotation"])
    t.links.new(sheet, sheets.inputs["Scale"])
    real = t.node("GeometryNodeRealizeInstances")  # the instances' attributes onto the sheets' vertices
    t.links.new(sheets.outputs[0], real.inputs["Geometry"])
    foam = with_material(real.outputs[0], foam_material())

    # Bubbles: faint specks.
    bubble = t.math("MULTIPLY", size, BUBBLE_RADIUS)
    bubbles = with_material(_specks(t, geometry, is_kind(2), None, t.combine(bubble, bubble, bubble)), bubble_material())

    join = t.node("GeometryNodeJoinGeometry")
    for part in (bubbles, foam, spray):
        t.links.new(part, join.inputs["Geometry"])

    # In the viewport the particles as plain points, unless the modifier's VIEWPORT_FULL
    # is ticked: the droplets, sheets and specks cost seconds a frame change (3.4 s
    # against 0.16 s without them, breaking-beach's 60 k particles); renders always
    # draw them in full.
    quick = t.node("GeometryNodeMeshToPoints")
    t.links.new(geometry, quick.inputs["Mesh"])
    t.links.new(t.math("MULTIPLY", size, 0.5), quick.inputs["Radius"])
    light = t.math("MULTIPLY", t.node("GeometryNodeIsViewport").outputs[0], t.math("SUBTRACT", 1.0, inp.outputs[2]))
    switch = t.node("GeometryNodeSwitch", input_type="GEOMETRY")
    enabled = [socket for socket in switch.inputs if getattr(socket, "enabled", True)]
    t.links.new(light, next(socket for socket in enabled if socket.name == "Switch"))
    t.links.new(join.outputs[0], next(socket for socket in enabled if socket.name == "False"))
    t.links.new(quick.outputs[0], next(socket for socket in enabled if socket.name == "True"))
    t.links.new(next(socket for socket in switch.outputs if getattr(socket, "enabled", True)), out.inputs[0])
    for i, node in enumerate(group.nodes):
        node.location = (200 * (i % 10), -160 * (i // 10))
    return group


def _set_points(mesh, points):
    mesh.clear_geometry()
    n = len(points["positions"])
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.ascontiguousarray(points["positions"], np.float32).ravel())
    for name in ("size", "kind", "age"):
        a = mesh.attributes.get(name) or mesh.attributes.new(name, "FLOAT", "POINT")
        a.data.foreach_set("value", np.ascontiguousarray(points[name], np.float32))
    v = mesh.attributes.get("velocity") or mesh.attributes.new("velocity", "FLOAT_VECTOR", "POINT")
    v.data.foreach_set("vector", np.ascontiguousarray(points["velocity"], np.float32).ravel())
    mesh.update()


def apply_frame(obj, scene_frame, render_done=False):
    """Shows the particles of loop frame (scene_frame − frame_start) mod the loop."""
    files = sequence(obj[_PROP])
    if not files:
        return
    loop = int(obj.get("libwave_loop_frames", 0)) or (max(files) + 1)
    k = (scene_frame - obj.get("libwave_frame_start", 0)) % loop
    first = int(obj.get("libwave_first_frame", 0))
    path = files.get(first + k)
    share = shown_share(obj, render_done)
    _set_points(obj.data, _points(obj.name, path, share) if path else read_points_empty())
    _read_ahead(obj.name, files.get(first + (k + 1) % loop), share)
    obj["libwave_frame"] = k
    obj["libwave_shown_share"] = share


def _stamp(path):
    """(mtime in ns, size) of `path`, or None when it cannot be read."""
    try:
        st = os.stat(path)
    except OSError:
        return None
    return st.st_mtime_ns, st.st_size


def _points(obj_name, path, share):
    """read_points(path, share), taken from what was read ahead for the object when it is
    that file, at that share, unchanged since (a run rewriting the folder is read again);
    a read ahead that failed is read again here, so that its error is this frame's."""
    entry = _ahead.pop(obj_name, None)
    if entry is not None:
        key, future = entry
        if key == (path, share, _stamp(path)):
            try:
                return future.result()
            except (OSError, KeyError, IndexError, ValueError, frames.LibwaveFileError):
                pass
        else:
            future.cancel()
    return read_points(path, share)


def _read_ahead(obj_name, path, share):
    """Starts reading `path` for the object on the worker (its next frame: sequential
    playback finds the particles read while Blender evaluated this frame; frame_set lets
    other threads run then). Each object keeps one read ahead; a jump replaces it."""
    global _worker
    old = _ahead.pop(obj_name, None)
    if old is not None:
        old[1].cancel()
    if path is None:
        return
    if _worker is None:
        _worker = concurrent.futures.ThreadPoolExecutor(max_workers=1, thread_name_prefix="libwave-whitewater")
    _ahead[obj_name] = ((path, share, _stamp(path)), _worker.submit(read_points, path, share))


@persistent
def forget_read_ahead(*_args):
    """A .blend loaded: what was read ahead belongs to the old one."""
    for _key, future in _ahead.values():
        future.cancel()
    _ahead.clear()


def read_points_empty():
    return {"positions": np.zeros((0, 3), np.float32), "velocity": np.zeros((0, 3), np.float32),
            "age": np.zeros(0, np.float32), "size": np.zeros(0, np.float32), "kind": np.zeros(0, np.float32)}


def _input_identifier(group, name):
    if hasattr(group, "interface"):  # Blender 4.0+
        return next(i.identifier for i in group.interface.items_tree if i.name == name and i.in_out == "INPUT")
    return group.inputs[name].identifier


# The whitewater modifier's input that draws the particles in full in the viewport too
# (unticked: plain points there, in full in renders).
VIEWPORT_FULL = "Full in viewport"


# Cycles' transparent bounces the import asks for at least: foam sheets and spray droplets
# seen at a grazing angle overlap many deep (Blender's default 8 leaves them black).
TRANSPARENT_BOUNCES = 64


def import_points(context, folder, frame_count, first_frame=0, frame_start=0, water=None):
    """The whitewater object of the files in `folder`/whitewater (None when there are none):
    scene frame f shows file first_frame + (f − frame_start) mod frame_count, as the water does.
    `water`: the water object whose "rest" attribute gives the foam's lace its coordinates
    (without it each sheet's lace is its own). Cycles' transparent bounces are raised to
    TRANSPARENT_BOUNCES."""
    if not sequence(folder):
        return None
    mesh = bpy.data.meshes.new("libwave whitewater")
    obj = bpy.data.objects.new(mesh.name, mesh)
    context.collection.objects.link(obj)
    mod = obj.modifiers.new("libwave whitewater", "NODES")
    mod.node_group = _node_group()
    if water is not None:
        mod[_input_identifier(mod.node_group, "Water")] = water
    cycles = getattr(context.scene, "cycles", None)
    if cycles is not None and cycles.transparent_max_bounces < TRANSPARENT_BOUNCES:
        cycles.transparent_max_bounces = TRANSPARENT_BOUNCES
    obj.data.materials.append(material())
    obj[_PROP] = os.path.abspath(folder)
    obj["libwave_loop_frames"] = int(frame_count)
    obj["libwave_first_frame"] = int(first_frame)
    obj["libwave_frame_start"] = int(frame_start)
    obj[SHARE_PROP] = VIEWPORT_SHARE
    ui = obj.id_properties_ui(SHARE_PROP)
    ui.update(min=0.01, max=1.0, soft_min=0.01, soft_max=1.0, step=5,
              description="Share of each frame's whitewater particles the viewport shows (renders show all)")
    add_handlers()
    apply_frame(obj, context.scene.frame_current)
    return obj


def _apply_each(scene, render_done=False, only_changed=False):
    """apply_frame on each whitewater object of `scene` (with `only_changed`, those whose
    shown share is not the one wanted now); a file that fails is said, not raised."""
    for obj in scene.objects:
        if obj.type != "MESH" or _PROP not in obj:
            continue
        if only_changed and obj.get("libwave_shown_share", 1.0) == shown_share(obj, render_done):
            continue
        try:
            apply_frame(obj, scene.frame_current, render_done)
        except (OSError, KeyError, IndexError, frames.LibwaveFileError) as e:
            print(frames.printable(f"libwave: {obj.name}: {e}"))


@persistent
def on_frame_change(scene, depsgraph=None):
    _apply_each(scene)


def _show_all(scene, rendering):
    """Switches between the viewport's share and every particle, on the frame shown."""
    global _rendering
    _rendering = rendering
    _apply_each(scene, render_done=not rendering, only_changed=True)


@persistent
def on_render_init(scene, depsgraph=None):
    """A render takes every particle (a still render changes no frame: the frame shown is
    read again in full here)."""
    _show_all(scene, True)


@persistent
def on_render_done(scene, depsgraph=None):
    """After a render (complete or cancelled) the viewport shows its share again."""
    _show_all(scene, False)


RENDER_HANDLERS = (("render_init", on_render_init), ("render_complete", on_render_done), ("render_cancel", on_render_done))


def add_handlers():
    """The frame change, render and load handlers, each once."""
    if on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(on_frame_change)
    if forget_read_ahead not in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.append(forget_read_ahead)
    for name, handler in RENDER_HANDLERS:
        if handler not in getattr(bpy.app.handlers, name):
            getattr(bpy.app.handlers, name).append(handler)


def remove_handlers():
    if on_frame_change in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.remove(on_frame_change)
    if forget_read_ahead in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(forget_read_ahead)
    for name, handler in RENDER_HANDLERS:
        if handler in getattr(bpy.app.handlers, name):
            getattr(bpy.app.handlers, name).remove(handler)
