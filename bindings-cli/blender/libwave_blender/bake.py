"""Baking a libwave animation into the .blend (docs/blender.md, "Baked into the .blend").

Every frame's positions and shading go into one hidden mesh of frame_count × n loose
vertices ("<water> frames": frame k's vertex i is point k·n + i, its position the
frame's position, with float attributes foam, reflect, refract and a colour when the
file has one). A Geometry Nodes modifier on the water picks loop frame
k = (scene frame − start) mod frame_count with Blender's own nodes (Scene Time, Math,
Object Info, Sample Index, Set Position, Store Named Attribute): the saved .blend plays
in any Blender from 3.4 on without the add-on and without the source files.
"""
import bpy
import numpy as np

QUANTITIES = ("foam", "reflect", "refract")


def _value_socket(sockets, data_type_label, name="Value"):
    """The enabled socket called `name` (Blender 3.4 keeps one per data type and hides
    the others; 4.x has one)."""
    candidates = [s for s in sockets if s.name == name and s.enabled]
    if not candidates:
        raise RuntimeError(f"no enabled {name} socket for {data_type_label}")
    return candidates[0]


def _frames_mesh(name, anim):
    """frame_count × n loose vertices holding every frame (see the module's docstring)."""
    first = anim.frame(0)
    n, count = len(first.positions), anim.frame_count
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(n * count)
    positions = np.empty((count, n, 3), np.float32)
    shading = {q: np.zeros((count, n), np.float32) for q in QUANTITIES if getattr(first, q) is not None}
    colour = np.ones((count, n, 4), np.float32) if first.color is not None else None
    for k in range(count):
        f = anim.frame(k)
        positions[k] = f.positions
        for q, values in shading.items():
            values[k] = getattr(f, q)
        if colour is not None:
            colour[k, :, :3] = f.color
    mesh.vertices.foreach_set("co", positions.ravel())
    for q, values in shading.items():
        mesh.attributes.new(q, "FLOAT", "POINT").data.foreach_set("value", values.ravel())
    if colour is not None:
        mesh.attributes.new("colour", "FLOAT_COLOR", "POINT").data.foreach_set("color", colour.ravel())
    mesh.update()
    return mesh, list(shading) + (["colour"] if colour is not None else [])


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


def _player(name, frames_object, vertex_count, frame_count, frame_start, attributes):
    """The node group: loop frame k's sample of every point, written onto the water."""
    group = _new_group(name)
    nodes, links = group.nodes, group.links
    group_in, group_out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    time = nodes.new("GeometryNodeInputSceneTime")
    k = _math(nodes, links, "WRAP", _math(nodes, links, "FLOOR", _math(nodes, links, "SUBTRACT", time.outputs["Frame"], frame_start)),
              frame_count, 0.0)
    index = nodes.new("GeometryNodeInputIndex")
    source = _math(nodes, links, "MULTIPLY_ADD", k, vertex_count, index.outputs["Index"])
    info = nodes.new("GeometryNodeObjectInfo")
    info.transform_space = "ORIGINAL"
    info.inputs["Object"].default_value = frames_object

    def sample(data_type, value):
        node = nodes.new("GeometryNodeSampleIndex")
        node.data_type, node.domain = data_type, "POINT"
        links.new(info.outputs["Geometry"], node.inputs["Geometry"])
        links.new(value, _value_socket(node.inputs, data_type))
        links.new(source, node.inputs["Index"])
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
    the `water` object through a Geometry Nodes modifier; returns the frames object."""
    mesh, attributes = _frames_mesh(water.name + " frames", anim)
    frames_object = bpy.data.objects.new(mesh.name, mesh)
    context.collection.objects.link(frames_object)
    frames_object.hide_render = True
    frames_object.hide_set(True)
    frames_object.parent = water  # moves with the water when an artist moves it
    modifier = water.modifiers.new("libwave frames", "NODES")
    modifier.node_group = _player(water.name + " frames", frames_object, len(water.data.vertices), anim.frame_count,
                                  frame_start, attributes)
    water["libwave_baked"] = anim.path
    return frames_object
