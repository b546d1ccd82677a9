"""Whitewater beside an animation (docs/whitewater.md): `wave run` with /whitewater writes
one POINTS .glb per loop frame, whitewater/whitewater-NNNN.glb. The add-on makes one
object whose vertices are the frame's particles (attributes size, kind, age, velocity),
replaced on every frame change, and a Geometry Nodes modifier that turns each vertex
into a sphere of its size (Mesh to Points: Cycles renders point clouds) with a
whitewater material: spray and foam white, bubbles a pale blue-white seen through the
water."""

import os
import re

import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import frames

FOLDER = "whitewater"
_NAME = re.compile(r"whitewater-(\d{4,})\.glb$")
_PROP = "libwave_whitewater"  # the folder whose files the object plays


def sequence(folder):
    """{loop frame: file} of the whitewater files beside an animation in `folder` ({} when none)."""
    root = os.path.join(folder, FOLDER)
    if not os.path.isdir(root) or os.path.islink(root):
        return {}
    found = {}
    for name in os.listdir(root):
        m = _NAME.match(name)
        if m:
            found[int(m.group(1))] = os.path.join(root, name)
    return found


def read_points(path):
    """A frame's particles: dict of positions (n, 3) in Blender's axes (z up), velocity
    (n, 3), age, size and kind (n,) — empty arrays for a frame with none."""
    doc, buffers = frames.read_gltf(path)
    extras = doc.get("scenes", [{}])[0].get("extras", {}).get("libwave_whitewater")
    if not isinstance(extras, dict):
        raise frames.LibwaveFileError(frames.printable(f"{path}: not a libwave whitewater file (no scene extras libwave_whitewater)"))
    empty = {"positions": np.zeros((0, 3), np.float32), "velocity": np.zeros((0, 3), np.float32),
             "age": np.zeros(0, np.float32), "size": np.zeros(0, np.float32), "kind": np.zeros(0, np.float32)}
    if not doc.get("meshes"):
        return empty
    prim = doc["meshes"][0]["primitives"][0]
    if prim.get("mode") != 0:
        raise frames.LibwaveFileError(frames.printable(f"{path}: its primitive is not POINTS (mode {prim.get('mode')!r})"))
    attrs = prim["attributes"]
    get = lambda name: frames.accessor(doc, buffers, attrs[name])
    out = {"positions": frames.to_blender(get("POSITION")), "velocity": frames.to_blender(get("_VELOCITY")),
           "age": get("_AGE")[:, 0], "size": get("_SIZE")[:, 0], "kind": get("_KIND")[:, 0]}
    n = len(out["positions"])
    if any(len(v) != n for v in out.values()):
        raise frames.LibwaveFileError(frames.printable(f"{path}: the particles' attributes differ in count"))
    if n and not np.isfinite(out["positions"]).all():
        raise frames.LibwaveFileError(frames.printable(f"{path}: a particle's position is not finite"))
    return out


def material():
    """Whitewater: white, rough and a little translucent (spray and foam scatter light through);
    bubbles (kind 2) pale blue."""
    mat = bpy.data.materials.get("libwave whitewater")
    if mat is not None:
        return mat
    mat = bpy.data.materials.new("libwave whitewater")
    mat.use_nodes = True
    tree = mat.node_tree
    bsdf = tree.nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 0.6
    kind = tree.nodes.new("ShaderNodeAttribute")
    kind.attribute_name = "kind"
    ramp = tree.nodes.new("ShaderNodeValToRGB")  # 0 spray, 1 foam: white; 2 bubble: pale blue
    ramp.color_ramp.interpolation = "CONSTANT"
    ramp.color_ramp.elements[0].position = 0.0
    ramp.color_ramp.elements[0].color = (0.92, 0.94, 0.95, 1.0)
    ramp.color_ramp.elements[1].position = 0.75
    ramp.color_ramp.elements[1].color = (0.7, 0.85, 0.9, 1.0)
    scale = tree.nodes.new("ShaderNodeMath")
    scale.operation = "MULTIPLY"
    scale.inputs[1].default_value = 0.5  # kind 0 … 2 → 0 … 1
    tree.links.new(kind.outputs["Fac"], scale.inputs[0])
    tree.links.new(scale.outputs[0], ramp.inputs["Fac"])
    tree.links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def _node_group():
    """Geometry Nodes: foam (kind 1) as flat pancakes lying on the water (an icosphere
    instance scaled by `size`, a fifth as thick), spray and bubbles as points of radius
    `size`; all with the whitewater material."""
    group = bpy.data.node_groups.get("libwave whitewater points")
    if group is not None:
        return group
    group = bpy.data.node_groups.new("libwave whitewater points", "GeometryNodeTree")
    if hasattr(group, "interface"):  # Blender 4.0+
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:  # 3.x
        group.inputs.new("NodeSocketGeometry", "Geometry")
        group.outputs.new("NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    inp, out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")

    def attribute(name):
        node = nodes.new("GeometryNodeInputNamedAttribute")
        node.data_type = "FLOAT"
        node.inputs["Name"].default_value = name
        # Blender 3.x keeps an output per data type, all named "Attribute": the float one
        # is the one enabled (outputs["Attribute"] was the vector one, read as 0.5).
        return next(o for o in node.outputs if o.name == "Attribute" and getattr(o, "enabled", True))

    size, kind = attribute("size"), attribute("kind")
    is_foam = nodes.new("ShaderNodeMath")  # kind == 1 (within ½)
    is_foam.operation = "COMPARE"
    links.new(kind, is_foam.inputs[0])
    is_foam.inputs[1].default_value = 1.0
    is_foam.inputs[2].default_value = 0.5
    not_foam = nodes.new("ShaderNodeMath")
    not_foam.operation = "SUBTRACT"
    not_foam.inputs[0].default_value = 1.0
    links.new(is_foam.outputs[0], not_foam.inputs[1])
    # Spray and bubbles: spheres (Cycles' point clouds).
    to_points = nodes.new("GeometryNodeMeshToPoints")
    links.new(inp.outputs[0], to_points.inputs["Mesh"])
    links.new(not_foam.outputs[0], to_points.inputs["Selection"])
    links.new(size, to_points.inputs["Radius"])
    # Foam: pancakes, instanced on the mesh's vertices (a size of 0 would make a singular
    # instance: held at a millimetre).
    sphere = nodes.new("GeometryNodeMeshIcoSphere")
    sphere.inputs["Radius"].default_value = 1.0
    sphere.inputs["Subdivisions"].default_value = 2
    held = nodes.new("ShaderNodeMath")
    held.operation = "MAXIMUM"
    links.new(size, held.inputs[0])
    held.inputs[1].default_value = 1e-3
    flat = nodes.new("ShaderNodeMath")
    flat.operation = "MULTIPLY"
    links.new(held.outputs[0], flat.inputs[0])
    flat.inputs[1].default_value = 0.2
    # No two alike: each pancake stretched 0.5–1.5 along one axis and 0.6–1.2 along the
    # other (a draw per point, seeded by its index) and turned about z.
    def stretched(low, high, seed):
        draw = nodes.new("FunctionNodeRandomValue")
        draw.data_type = "FLOAT"
        for socket in draw.inputs:
            if socket.identifier == "Min_001":
                socket.default_value = low
            elif socket.identifier == "Max_001":
                socket.default_value = high
            elif socket.name == "Seed":
                socket.default_value = seed
        times = nodes.new("ShaderNodeMath")
        times.operation = "MULTIPLY"
        links.new(held.outputs[0], times.inputs[0])
        links.new(next(o for o in draw.outputs if o.identifier == "Value_001"), times.inputs[1])
        return times.outputs[0]

    scale = nodes.new("ShaderNodeCombineXYZ")
    links.new(stretched(0.5, 1.5, 11), scale.inputs["X"])
    links.new(stretched(0.6, 1.2, 12), scale.inputs["Y"])
    links.new(flat.outputs[0], scale.inputs["Z"])
    turn = nodes.new("FunctionNodeRandomValue")
    turn.data_type = "FLOAT_VECTOR"
    for socket in turn.inputs:
        if socket.identifier == "Max" and socket.type == "VECTOR":
            socket.default_value = (0.0, 0.0, 6.2831853)
        elif socket.name == "Seed":
            socket.default_value = 13
    instances = nodes.new("GeometryNodeInstanceOnPoints")
    links.new(inp.outputs[0], instances.inputs["Points"])
    links.new(is_foam.outputs[0], instances.inputs["Selection"])
    links.new(sphere.outputs["Mesh"], instances.inputs["Instance"])
    links.new(scale.outputs["Vector"], instances.inputs["Scale"])
    links.new(next(o for o in turn.outputs if o.identifier == "Value"), instances.inputs["Rotation"])
    join = nodes.new("GeometryNodeJoinGeometry")
    links.new(to_points.outputs["Points"], join.inputs["Geometry"])
    links.new(instances.outputs["Instances"], join.inputs["Geometry"])
    set_material = nodes.new("GeometryNodeSetMaterial")
    set_material.inputs["Material"].default_value = material()
    links.new(join.outputs["Geometry"], set_material.inputs["Geometry"])
    links.new(set_material.outputs["Geometry"], out.inputs[0])
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


def apply_frame(obj, scene_frame):
    """Shows the particles of loop frame (scene_frame − frame_start) mod the loop."""
    files = sequence(obj[_PROP])
    if not files:
        return
    loop = int(obj.get("libwave_loop_frames", 0)) or (max(files) + 1)
    k = (scene_frame - obj.get("libwave_frame_start", 0)) % loop
    path = files.get(int(obj.get("libwave_first_frame", 0)) + k)
    _set_points(obj.data, read_points(path) if path else read_points_empty())
    obj["libwave_frame"] = k


def read_points_empty():
    return {"positions": np.zeros((0, 3), np.float32), "velocity": np.zeros((0, 3), np.float32),
            "age": np.zeros(0, np.float32), "size": np.zeros(0, np.float32), "kind": np.zeros(0, np.float32)}


def import_points(context, folder, frame_count, first_frame=0, frame_start=0):
    """The whitewater object of the files in `folder`/whitewater (None when there are none):
    scene frame f shows file first_frame + (f − frame_start) mod frame_count, as the water does."""
    if not sequence(folder):
        return None
    mesh = bpy.data.meshes.new("libwave whitewater")
    obj = bpy.data.objects.new(mesh.name, mesh)
    context.collection.objects.link(obj)
    mod = obj.modifiers.new("libwave whitewater", "NODES")
    mod.node_group = _node_group()
    obj.data.materials.append(material())
    obj[_PROP] = os.path.abspath(folder)
    obj["libwave_loop_frames"] = int(frame_count)
    obj["libwave_first_frame"] = int(first_frame)
    obj["libwave_frame_start"] = int(frame_start)
    if on_frame_change not in bpy.app.handlers.frame_change_post:
        bpy.app.handlers.frame_change_post.append(on_frame_change)
    apply_frame(obj, context.scene.frame_current)
    return obj


@persistent
def on_frame_change(scene, depsgraph=None):
    for obj in scene.objects:
        if obj.type == "MESH" and _PROP in obj:
            try:
                apply_frame(obj, scene.frame_current)
            except (OSError, KeyError, IndexError, frames.LibwaveFileError) as e:
                print(frames.printable(f"libwave: {obj.name}: {e}"))
