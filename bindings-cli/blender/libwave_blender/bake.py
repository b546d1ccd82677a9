"""Baking a libwave animation into the .blend (docs/blender.md, "Baked into the .blend").

Every frame goes into a mesh of its own, n loose vertices at the frame's positions with
float point attributes foam, reflect, refract (and a colour when the file has one), in a
collection "<water> frames" kept out of the view layer. A Geometry Nodes modifier on the
water picks loop frame k = (scene frame − start) mod frame_count with Blender's own
nodes (Scene Time, Math, Collection Info, Delete Geometry on instances, Realize
Instances, Sample Index by vertex index, Set Position, Store Named Attribute): the saved
.blend plays in any Blender from 3.4 on without the add-on and without the source files.
A frame change realises one frame's points only (one mesh holding every frame made
Sample Index evaluate all of them: 0.65 s a frame for the default run).
"""
import bpy
import numpy as np

from .frames import to_rgba

QUANTITIES = ("foam", "reflect", "refract")


def _value_socket(sockets, data_type_label, name="Value"):
    """The enabled socket called `name` (Blender 3.4 keeps one per data type and hides
    the others; 4.x has one)."""
    candidates = [s for s in sockets if s.name == name and s.enabled]
    if not candidates:
        raise RuntimeError(f"no enabled {name} socket for {data_type_label}")
    return candidates[0]


def _frame_meshes(name, anim):
    """One mesh of n loose vertices per frame (see the module's docstring): its positions
    are the frame's, its float attributes the frame's shading. Returns the meshes and
    the names of the attributes they carry."""
    first = anim.frame(0)
    n = len(first.positions)
    attributes = [q for q in QUANTITIES if getattr(first, q) is not None] + (["colour"] if first.color is not None else [])
    meshes = []
    for k in range(anim.frame_count):
        f = anim.frame(k)
        mesh = bpy.data.meshes.new(f"{name} {k:05d}")
        mesh.vertices.add(n)
        mesh.vertices.foreach_set("co", np.ascontiguousarray(f.positions, np.float32).ravel())
        for q in attributes:
            if q == "colour":
                mesh.attributes.new(q, "FLOAT_COLOR", "POINT").data.foreach_set("color", to_rgba(f.color))
            else:
                mesh.attributes.new(q, "FLOAT", "POINT").data.foreach_set("value", np.ascontiguousarray(getattr(f, q), np.float32))
        mesh.update()
        meshes.append(mesh)
    return meshes, attributes


def _new_group(name):
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if hasattr(group, "interface"):  # Blender 4.x
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:  # Blender 3.x
        group.inputs.new("NodeSocketGeometry", "Geometry")
        group.outputs.new("NodeSocketGeometry", "Geometry")
    return group


def _math(nodes, links, operation, a, b=None, c=None):
    node = nodes.new("ShaderNodeMath")
    node.operation = operation
    for socket, value in zip(node.inputs, (a, b, c)):
        if value is None:
            continue
        if isinstance(value, bpy.types.NodeSocket):
            links.new(value, socket)
        else:
            socket.default_value = value
    return node.outputs[0]


def _player(name, frames, frame_count, frame_start, attributes):
    """The node group: loop frame k's points (instance k of the `frames` collection,
    realised), sampled by vertex index and written onto the water."""
    group = _new_group(name)
    nodes, links = group.nodes, group.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    time = nodes.new("GeometryNodeInputSceneTime")
    k = _math(nodes, links, "WRAP", _math(nodes, links, "FLOOR", _math(nodes, links, "SUBTRACT", time.outputs["Frame"], frame_start)),
              frame_count, 0.0)
    # The collection's objects as instances, one per frame in name order (k:05d), in
    # their own coordinates; all but instance k deleted, that one realised.
    info = nodes.new("GeometryNodeCollectionInfo")
    info.transform_space = "ORIGINAL"
    info.inputs["Collection"].default_value = frames
    info.inputs["Separate Children"].default_value = True
    info.inputs["Reset Children"].default_value = True
    other = nodes.new("FunctionNodeCompare")
    other.data_type, other.operation = "FLOAT", "NOT_EQUAL"
    other.inputs["Epsilon"].default_value = 0.25
    links.new(nodes.new("GeometryNodeInputIndex").outputs["Index"], other.inputs[0])
    links.new(k, other.inputs[1])
    keep = nodes.new("GeometryNodeDeleteGeometry")
    keep.domain = "INSTANCE"
    links.new(info.outputs[0], keep.inputs["Geometry"])
    links.new(other.outputs["Result"], keep.inputs["Selection"])
    realised = nodes.new("GeometryNodeRealizeInstances")
    links.new(keep.outputs["Geometry"], realised.inputs["Geometry"])
    index = nodes.new("GeometryNodeInputIndex")

    def sample(data_type, value):
        node = nodes.new("GeometryNodeSampleIndex")
        node.data_type, node.domain = data_type, "POINT"
        links.new(realised.outputs["Geometry"], node.inputs["Geometry"])
        links.new(value, _value_socket(node.inputs, data_type))
        links.new(index.outputs["Index"], node.inputs["Index"])
        return _value_socket(node.outputs, data_type)

    geometry = group_in.outputs["Geometry"]
    move = nodes.new("GeometryNodeSetPosition")
    links.new(geometry, move.inputs["Geometry"])
    links.new(sample("FLOAT_VECTOR", nodes.new("GeometryNodeInputPosition").outputs["Position"]), move.inputs["Position"])
    geometry = move.outputs["Geometry"]
    for attribute in attributes:
        data_type = "FLOAT_COLOR" if attribute == "colour" else "FLOAT"
        read = nodes.new("GeometryNodeInputNamedAttribute")
        read.data_type = data_type
        read.inputs["Name"].default_value = attribute
        store = nodes.new("GeometryNodeStoreNamedAttribute")
        store.data_type, store.domain = data_type, "POINT"
        store.inputs["Name"].default_value = attribute
        links.new(geometry, store.inputs["Geometry"])
        links.new(sample(data_type, _value_socket(read.outputs, data_type, "Attribute")), _value_socket(store.inputs, data_type))
        geometry = store.outputs["Geometry"]
    links.new(geometry, group_out.inputs["Geometry"])
    for i, node in enumerate(nodes):
        node.location = (220 * (i % 8), -180 * (i // 8))
    return group


def bake(context, water, anim, frame_start=0):
    """Stores every frame of `anim` (a frames.Animation) in the .blend and plays it on
    the `water` object through a Geometry Nodes modifier; returns the frames' collection."""
    meshes, attributes = _frame_meshes(water.name + " frame", anim)
    frames = bpy.data.collections.new(water.name + " frames")
    context.scene.collection.children.link(frames)
    for mesh in meshes:
        frames.objects.link(bpy.data.objects.new(mesh.name, mesh))
    # Out of the view layer (not drawn, not rendered); the node group still reads it.
    layer = context.view_layer.layer_collection.children[frames.name]
    layer.exclude = True
    modifier = water.modifiers.new("libwave frames", "NODES")
    modifier.node_group = _player(water.name + " frames", frames, anim.frame_count, frame_start, attributes)
    water["libwave_baked"] = anim.path
    return frames
