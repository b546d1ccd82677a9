"""Reads libwave's animations (docs/export.md) frame by frame, without Blender's glTF importer.

Every form `wave run` writes: `morph` (one mesh, a morph target per frame), `nodes` (a
node per frame whose scale is switched), `files` (a .glb/.gltf per frame listed in
index.json); plain float32 or KHR_mesh_quantization. Draco-compressed files need the
libwave Python module (`libwave.read_frame`), which decodes them.

Arrays come back in Blender's axes (z up): glTF's (x, y, z) is Blender's (x, −z, y).
"""
import base64
import concurrent.futures
import importlib
import json
import math
import os
import struct
import sys

import numpy as np

_COMPONENTS = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


class LibwaveFileError(Exception):
    """A file this reader cannot use; the message says which and why."""


# What the add-on reads is checked as libwave's C++ reader checks it (docs/hardening.md):
# a message naming the file, never a traceback, a hang or memory run out.
MAX_FRAMES = 10_000_000  # the schema's /animation/max_frames
AHEAD = 1  # compressed frames decoded ahead of the one shown, each on a worker of its own (2 was no faster on 2 cores)
BAKE_BYTES = 4e9  # a bake holds every frame in the .blend: ~40 bytes a vertex a frame in Blender's meshes


def printable(text):
    """`text` with control and bidirectional-formatting characters shown as escapes (as
    libwave's messages show them): a name read from a file never drives the display."""
    out = []
    for ch in str(text):
        o = ord(ch)
        if (o < 0x20 and ch != "\t") or 0x7F <= o < 0xA0:
            out.append(f"\\x{o:02X}" if o < 0x100 else f"\\u{{{o:04X}}}")
        elif o in (0x061C, 0x200E, 0x200F) or 0x202A <= o <= 0x202E or 0x2066 <= o <= 0x2069:
            out.append(f"\\u{{{o:04X}}}")
        else:
            out.append(ch)
    return "".join(out)


def _fail(path, what):
    raise LibwaveFileError(printable(f"{path}: {what}"))


def _json(text, path):
    """JSON, or LibwaveFileError naming the file (deep nesting included: Python's own
    recursion limit raised RecursionError through the import)."""
    try:
        return json.loads(text)
    except RecursionError:
        _fail(path, "JSON nested too deeply")
    except (ValueError, UnicodeDecodeError) as e:
        _fail(path, f"not JSON ({e})")


def inside(folder, name, what):
    """The path of `name` (read from a file in `folder`) if it stays inside the folder:
    relative, no `..` part, its real path inside the folder's (libwave's rule)."""
    if not isinstance(name, str) or not name or "\0" in name:
        _fail(what, f"{name!r} is not a file name")
    if os.path.isabs(name) or ".." in name.replace("\\", "/").split("/"):
        _fail(what, f"'{name}' leaves its folder (an absolute path or ..); paths read from files stay inside {folder}")
    root = os.path.realpath(folder)
    real = os.path.realpath(os.path.join(folder, name))
    if os.path.commonpath([root, real]) != root:
        _fail(what, f"'{name}': a link leads out of the folder, to {real}")
    return os.path.join(folder, name)


def _regular(path):
    """Refuses what is not a regular file before it is opened (a FIFO would block Blender)."""
    import stat
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        _fail(path, f"cannot read it ({e.strerror})")
    if not stat.S_ISREG(mode):
        _fail(path, "a directory, not a file" if stat.S_ISDIR(mode) else "not a regular file (a FIFO, socket or device)")


def _number(value, what, path, low, high, whole=False):
    """A number of a file in [low, high] (whole if asked), else LibwaveFileError naming it."""
    ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value) and low <= value <= high
    if ok and whole and value != int(value):
        ok = False
    if not ok:
        _fail(path, f"{what} {printable(repr(value))[:40]} is not {'a whole number' if whole else 'a number'} in [{low}, {high}]")
    return int(value) if whole else float(value)


def read_gltf(path):
    """(document, [buffer]) of a .glb or .gltf (external or data-URI buffers). A .glb's
    buffer stays in the file (_FileBuffer): a reader reads the ranges it asks for (a
    compressed file's dressing, one frame of a plain one), not the whole file."""
    _regular(path)
    with open(path, "rb") as f:
        head = f.read(20)
        if head[:4] == b"glTF":
            if len(head) < 20:
                _fail(path, "a truncated GLB header")
            length = struct.unpack_from("<I", head, 12)[0]
            size = os.fstat(f.fileno()).st_size
            if 20 + length > size:
                _fail(path, "the JSON chunk runs past the file")
            doc = _json(f.read(length), path)
            if not isinstance(doc, dict):
                _fail(path, "not a glTF document (its JSON is not an object)")
            offset = 20 + length
            binary = b""
            if offset + 8 <= size:
                chunk = struct.unpack_from("<I", os.pread(f.fileno(), 4, offset))[0]
                binary = _FileBuffer(path, offset + 8, min(chunk, size - offset - 8))
            return doc, [binary]
        data = head + f.read()
    doc = _json(data, path)
    buffers = []
    for i, b in enumerate(doc.get("buffers", []) if isinstance(doc, dict) else []):
        uri = b.get("uri", "") if isinstance(b, dict) else ""
        if not uri:  # EXT_meshopt_compression's fallback buffer: no data (libwave's module decodes)
            buffers.append(b"")
        elif uri.startswith("data:"):
            try:
                buffers.append(base64.b64decode(uri.split(",", 1)[1], validate=True))
            except (IndexError, ValueError):
                _fail(path, f"buffer {i}: its data: URI is not base64")
        else:
            from urllib.parse import unquote_plus
            file = inside(os.path.dirname(path), unquote_plus(uri), f"{path}: buffer {i}'s uri")
            _regular(file)
            with open(file, "rb") as f:
                buffers.append(f.read())
    if not isinstance(doc, dict):
        _fail(path, "not a glTF document (its JSON is not an object)")
    return doc, buffers


class _FileBuffer:
    """A .glb's BIN chunk left in its file: `read` takes a range when it is asked for."""

    def __init__(self, path, offset, length):
        self.path, self.offset, self.length = path, offset, length

    def __len__(self):
        return self.length

    def read(self, start, n):
        if start < 0 or n < 0 or start + n > self.length:
            raise LibwaveFileError(f"{self.path}: an accessor runs past its buffer")
        with open(self.path, "rb") as f:
            data = os.pread(f.fileno(), n, self.offset + start)
        if len(data) != n:
            raise LibwaveFileError(f"{self.path}: the file ends inside its buffer")
        return data


def _from_buffer(raw, dtype, count, start):
    """`count` values of `dtype` from byte `start` of a buffer (bytes or a _FileBuffer)."""
    if isinstance(raw, _FileBuffer):
        return np.frombuffer(raw.read(start, count * dtype.itemsize), dtype, count)
    return np.frombuffer(raw, dtype, count, start)


def accessor(doc, buffers, index):
    """An accessor as a (count, width) float32 array (normalised integers mapped to [−1, 1] / [0, 1])."""
    a = doc["accessors"][index]
    dtype = np.dtype(_COMPONENTS[a["componentType"]])
    width = _WIDTH[a["type"]]
    count = a["count"]
    if not isinstance(count, int) or not 0 <= count <= 1 << 28:
        raise LibwaveFileError(f"accessor {index}: count {count!r} is not a whole number in [0, 2^28]")
    if "bufferView" in a:
        view = doc["bufferViews"][a["bufferView"]]
        raw = buffers[view.get("buffer", 0)]
        view_start, view_length = view.get("byteOffset", 0), view.get("byteLength", 0)
        start = view_start + a.get("byteOffset", 0)
        stride = view.get("byteStride", dtype.itemsize * width)
        element = dtype.itemsize * width
        # Every element inside its view and the view inside its buffer (as_strided reads
        # whatever memory a stride points at: a hostile one crashed Blender).
        if not (isinstance(stride, int) and (stride == element or (4 <= stride <= 252 and stride % 4 == 0 and stride >= element))):
            raise LibwaveFileError(f"accessor {index}: byteStride {stride!r} is not a multiple of 4 in [4, 252] holding its elements")
        if view_start < 0 or view_length < 0 or view_start + view_length > len(raw) or (
                count > 0 and start - view_start + (count - 1) * stride + element > view_length) or start < view_start:
            raise LibwaveFileError(f"accessor {index} runs past its bufferView")
        if stride == dtype.itemsize * width:
            values = _from_buffer(raw, dtype, count * width, start).reshape(count, width)
        else:
            span = ((count - 1) * stride + dtype.itemsize * width) if count else 0
            span += (-span) % dtype.itemsize
            window = _from_buffer(raw, np.dtype(np.uint8), span, start)
            values = np.lib.stride_tricks.as_strided(window.view(dtype), (count, width), (stride, dtype.itemsize))
        values = values.astype(np.float32)
    else:  # zeros, unless sparse
        values = np.zeros((count, width), np.float32)
    sparse = a.get("sparse")
    if sparse:  # a morph target's moving vertices only
        def packed(part, part_dtype, part_width):
            view = doc["bufferViews"][part["bufferView"]]
            start = view.get("byteOffset", 0) + part.get("byteOffset", 0)
            return _from_buffer(buffers[view.get("buffer", 0)], part_dtype, sparse["count"] * part_width,
                                start).reshape(sparse["count"], part_width)
        indices = packed(sparse["indices"], np.dtype(_COMPONENTS[sparse["indices"]["componentType"]]), 1)[:, 0]
        if len(indices) and (int(indices.max()) >= count or int(indices.min()) < 0):
            raise LibwaveFileError(f"accessor {index}: sparse indices out of range")
        values[indices.astype(np.int64)] = packed(sparse["values"], dtype, width).astype(np.float32)
    if a.get("normalized"):
        if dtype.kind == "i":
            values = np.maximum(values / float(np.iinfo(dtype).max), -1.0)
        else:
            values = values / float(np.iinfo(dtype).max)
    return values


def to_rgba(rgb):
    """(n, 3) colours as Blender's flat RGBA float array (alpha 1)."""
    rgba = np.ones((len(rgb), 4), np.float32)
    rgba[:, :3] = rgb
    return rgba.ravel()


def to_blender(xyz):
    """glTF y-up → Blender z-up."""
    return np.stack([xyz[:, 0], -xyz[:, 2], xyz[:, 1]], axis=1)


class Frame:
    """One frame: positions and normals (n, 3), the shading (n,) each (None when absent),
    colour (n, 3) or None."""

    def __init__(self, positions, foam=None, reflect=None, refract=None, color=None, normals=None):
        self.positions, self.foam, self.reflect, self.refract, self.color = positions, foam, reflect, refract, color
        self.normals = normals


def _shading(attrs, get):
    """foam, reflect, refract from either layout: TEXCOORD_1/2 (Blender 3.4) or _FOAM/_REFLECT/_REFRACT."""
    if "_FOAM" in attrs:
        return get("_FOAM")[:, 0], get("_REFLECT")[:, 0], get("_REFRACT")[:, 0]
    if "TEXCOORD_2" in attrs:
        uv1, uv2 = get("TEXCOORD_1"), get("TEXCOORD_2")
        return uv2[:, 0], uv1[:, 0], uv1[:, 1]
    return None, None, None


def _node_transform(doc, mesh_index):
    """(translation, scale) of the node showing mesh `mesh_index` (quantised positions use it)."""
    for n in doc.get("nodes", []):
        if n.get("mesh") == mesh_index:
            return np.array(n.get("translation", [0, 0, 0]), np.float32), np.array(n.get("scale", [1, 1, 1]), np.float32)
    return np.zeros(3, np.float32), np.ones(3, np.float32)


def _primitive_frame(doc, buffers, mesh_index, target=None, excess=(), primitive=0):
    """A frame from one of a mesh's primitives (and, for the morph form, one of its targets
    and the NORMAL-only targets in `excess` that its key weighs in)."""
    prim = doc["meshes"][mesh_index]["primitives"][primitive]
    if "KHR_draco_mesh_compression" in prim.get("extensions", {}):
        raise LibwaveFileError("Draco-compressed")
    attrs = prim["attributes"]
    # Quantised positions (normalised int16 in the frame or in the morph deltas) are undone
    # by their mesh node's transform; plain float positions are final (a nodes-form frame
    # node's scale only switches it on and off). A quantised frame's far-field skirt, its
    # second primitive, holds floats in the same node frame: the first primitive decides.
    first = doc["meshes"][mesh_index]["primitives"][0]
    position_accessors = [first["attributes"]["POSITION"]] + [t["POSITION"] for t in first.get("targets", []) if "POSITION" in t]
    if any(doc["accessors"][i].get("normalized") for i in position_accessors[:2]):
        translation, scale = _node_transform(doc, mesh_index)
    else:
        translation, scale = np.zeros(3, np.float32), np.ones(3, np.float32)

    def get(name):
        values = accessor(doc, buffers, attrs[name])
        if target is not None and name in prim["targets"][target]:
            values = values + accessor(doc, buffers, prim["targets"][target][name])
        return values

    positions = to_blender(get("POSITION") * scale + translation)
    foam, reflect, refract = _shading(attrs, get)
    color = get("COLOR_0")[:, :3] if "COLOR_0" in attrs else None
    normals = None
    if "NORMAL" in attrs:
        normals = get("NORMAL")
        for t in excess:  # a quantised normal's turn beyond ±1
            normals = normals + accessor(doc, buffers, prim["targets"][t]["NORMAL"])
        normals = to_blender(normals / np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12))
    return Frame(positions, foam, reflect, refract, color, normals)


_GLTF_TO_BLENDER = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]], np.float64)


def _node_matrix(node):
    """A node's 4 × 4 world matrix in Blender's axes (its translation and rotation; libwave's
    camera and sun nodes are roots)."""
    x, y, z, w = node.get("rotation", [0.0, 0.0, 0.0, 1.0])
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = _GLTF_TO_BLENDER @ r
    m[:3, 3] = _GLTF_TO_BLENDER @ np.array(node.get("translation", [0.0, 0.0, 0.0]))
    return m


class Dressing:
    """What a libwave .glb carries beside the water: seafloor (positions, triangles, colours),
    camera (matrix, vertical fov, aspect), sun (matrix, intensity); each None when absent."""

    def __init__(self, doc, buffers):
        self.seafloor = self.camera = self.sun = None
        # The caustic maps beside the file (docs/underwater.md): (uv per seafloor vertex,
        # libwave_caustics of the seafloor material's extras), or None.
        self.caustics = None
        # The sunbeam volumes beside the file: libwave_sunbeams of the seafloor
        # material's extras, or None.
        self.sunbeams = None
        for node in doc.get("nodes", []):
            if node.get("name") == "seafloor" and "mesh" in node:
                prim = doc["meshes"][node["mesh"]]["primitives"][0]
                positions = to_blender(accessor(doc, buffers, prim["attributes"]["POSITION"]))
                colours = accessor(doc, buffers, prim["attributes"]["COLOR_0"])[:, :3] if "COLOR_0" in prim["attributes"] else None
                self.seafloor = (positions, _triangles(doc, buffers, node["mesh"]), colours)
                extras = doc.get("materials", [{}])[prim["material"]].get("extras", {}) if "material" in prim else {}
                if "libwave_caustics" in extras and "TEXCOORD_0" in prim["attributes"]:
                    self.caustics = (accessor(doc, buffers, prim["attributes"]["TEXCOORD_0"]), extras["libwave_caustics"])
                self.sunbeams = extras.get("libwave_sunbeams")
            elif "camera" in node:
                cam = doc["cameras"][node["camera"]].get("perspective", {})
                self.camera = (_node_matrix(node), cam.get("yfov", 0.7), cam.get("aspectRatio", 16 / 9))
            elif "KHR_lights_punctual" in node.get("extensions", {}):
                light = doc["extensions"]["KHR_lights_punctual"]["lights"][node["extensions"]["KHR_lights_punctual"]["light"]]
                self.sun = (_node_matrix(node), light.get("intensity", 1.0), light.get("color", [1, 1, 1]))


def _triangles(doc, buffers, mesh_index, primitive=0):
    prim = doc["meshes"][mesh_index]["primitives"][primitive]
    if "indices" not in prim:
        raise LibwaveFileError("a primitive without indices")
    return accessor(doc, buffers, prim["indices"]).astype(np.int64).reshape(-1, 3)


def _mesh_triangles(doc, buffers, mesh_index):
    """A frame's mesh's triangles (its primitives joined, as `_mesh_frame` joins them)."""
    if len(doc["meshes"][mesh_index]["primitives"]) == 1:
        return _triangles(doc, buffers, mesh_index)
    return _mesh_frame(doc, buffers, mesh_index)[1]


def _mesh_frame(doc, buffers, mesh_index, target=None, excess=()):
    """(Frame, triangles (m, 3)) of a frame's mesh: its primitive (triangles None: the
    file's), or its primitives joined (a quantised frame and its far-field skirt,
    docs/far-field.md) as libwave's reader joins them: a later primitive's vertex at the
    bit-equal position of a first primitive's vertex (the seam) welded onto it, then the
    later primitives' other vertices."""
    count = len(doc["meshes"][mesh_index]["primitives"])
    if count == 1:
        return _primitive_frame(doc, buffers, mesh_index, target, excess), None
    parts = [(_primitive_frame(doc, buffers, mesh_index, target, excess, k), _triangles(doc, buffers, mesh_index, k))
             for k in range(count)]
    bits = np.dtype((np.void, 12))

    def keys(f):  # each vertex's position bits, −0 as +0
        return np.ascontiguousarray(f.positions.astype(np.float32) + np.float32(0.0)).view(bits).ravel()

    first_keys = keys(parts[0][0])
    total = len(first_keys)
    fresh, triangles = [], [parts[0][1]]
    for f, t in parts[1:]:
        own = keys(f)
        _, at_first, at_own = np.intersect1d(first_keys, own, assume_unique=False, return_indices=True)
        index = np.full(len(own), -1, np.int64)
        index[at_own] = at_first
        new = index < 0
        index[new] = total + np.arange(np.count_nonzero(new))
        total += np.count_nonzero(new)
        fresh.append(new)
        triangles.append(index[t])

    def join(name):
        values = [getattr(f, name) for f, _ in parts]
        if values[0] is None:
            return None
        return np.concatenate([values[0]] + [v[new] for v, new in zip(values[1:], fresh)])

    frame = Frame(join("positions"), join("foam"), join("reflect"), join("refract"), join("color"), join("normals"))
    return frame, np.concatenate(triangles)


def _spread_bits(v):
    """The low 16 bits of each of `v` (uint64) moved to the even bit positions."""
    v = v & 0xFFFF
    v = (v | (v << 8)) & 0x00FF00FF
    v = (v | (v << 4)) & 0x0F0F0F0F
    v = (v | (v << 2)) & 0x33333333
    return (v | (v << 1)) & 0x55555555


def locality_order(positions, triangles):
    """(order, triangles') for a mesh whose neighbours lie near each other in memory: the
    triangles sorted along a Z-order (Morton) curve of their centres' x, y (16 bits each
    over the mesh's extent), the vertices numbered by their first use in that list (any
    unused vertex after, in file order). Vertex i of the new mesh is file vertex order[i];
    triangles' holds the new numbers (each triangle's corners in their order: the winding
    kept). Blender's update of a changed mesh (vertex normals: a scatter over every
    corner) took 35 ms in this order against 60–65 ms in the file's on a 150 k-vertex
    coast (docs/blender.md, "Playback")."""
    triangles = np.asarray(triangles, np.int64).reshape(-1, 3)
    n = len(positions)
    if not len(triangles) or not n:
        return np.arange(n, dtype=np.int64), triangles
    if triangles.min() < 0 or triangles.max() >= n:
        bad = int(triangles.min()) if triangles.min() < 0 else int(triangles.max())
        raise LibwaveFileError(f"a triangle's vertex {bad} is not among the {n} vertices")
    centre = np.asarray(positions, np.float64)[:, :2][triangles].mean(axis=1)
    low, extent = centre.min(axis=0), np.ptp(centre, axis=0)
    cell = np.floor((centre - low) / np.where(extent > 0, extent, 1.0) * 65535.0).astype(np.uint64)
    code = _spread_bits(cell[:, 0]) | (_spread_bits(cell[:, 1]) << np.uint64(1))
    triangles = triangles[np.argsort(code, kind="stable")]
    corners = triangles.ravel()
    _, first = np.unique(corners, return_index=True)
    used = corners[np.sort(first)]
    unused = np.setdiff1d(np.arange(n, dtype=np.int64), used, assume_unique=True)
    order = np.concatenate([used, unused])
    new = np.empty(n, np.int64)
    new[order] = np.arange(n, dtype=np.int64)
    return order, new[triangles]


def _gathered(f, order, k=None):
    """Frame `f` with every per-vertex array taken in `order` (None: `f` itself; None
    arrays stay None); a frame of another vertex count than the order's is a file error."""
    if order is None:
        return f
    if len(f.positions) != len(order):
        raise LibwaveFileError(f"frame {k}: {len(f.positions)} vertices, the mesh has {len(order)}")
    take = lambda a: None if a is None else np.ascontiguousarray(np.asarray(a)[order])
    return Frame(take(f.positions), take(f.foam), take(f.reflect), take(f.refract), take(f.color), take(f.normals))


class Animation:
    """A libwave animation: `frame(k)` gives loop frame k; `triangles` (the file's), `fps`,
    `frame_count`. Frames come in the file's vertex order, or, after set_order(order), in
    `order` (vertex i of the frames is the file's vertex order[i]): the order of the mesh
    that shows them, taken on the worker that decodes a frame ahead too."""

    def __init__(self, path):
        try:
            self._open(path)
            self.order = None
        except (KeyError, IndexError, TypeError, ValueError, AttributeError, StopIteration, struct.error) as e:
            # Whatever the checks below did not name: the file, never a traceback.
            raise LibwaveFileError(printable(f"{path}: not a libwave animation the add-on can read "
                                             f"({type(e).__name__}: {str(e)[:200]})")) from None

    def set_order(self, order):
        """Frames from now on in `order` (None: the file's); what was read or decoded ahead
        in another order is dropped."""
        if order is self.order or (order is not None and self.order is not None and np.array_equal(order, self.order)):
            return  # the same (None, None included: a mesh in the file's order keeps its cache and look-ahead)
        for future in self._ahead.values():
            future.cancel()
        self._ahead, self._cache = {}, {}
        self.order = None if order is None else np.asarray(order, np.int64)

    def first_positions(self):
        """Frame 0's positions in the file's order, read without caching or decoding ahead
        (for locality_order, before the mesh is made)."""
        if (self.form == "files" and self._draco_files) or self._module_frames:
            return self._decode(0, False).positions
        order, self.order = self.order, None
        try:
            return self.frame(0).positions
        finally:
            self.order, self._cache = order, {}

    def _open(self, path):
        self.path = os.path.abspath(path)
        self.folder = os.path.dirname(self.path)
        self._cache = {}
        self._draco_files = False  # a files form of Draco or meshopt frames, each decoded by libwave's module
        self._module_frames = False  # a compressed .glb/.gltf, each frame decoded alone by libwave's module
        self._ahead = {}  # frame → its decoding on the worker (compressed files form)
        self._worker = None
        self._reader = None  # libwave.FrameReader of a compressed output, kept open across frames
        # Whether frames carry the file's normals (the option "The file's normals"; apply_frame
        # sets it per object): without, a compressed frame's normals are neither read nor decoded.
        self.want_normals = True
        self.dressing = None  # the seafloor, camera and sun a single-file form carries
        if os.path.basename(path) == "index.json" or path.endswith(".json"):
            _regular(path)
            with open(path, "rb") as f:
                index = _json(f.read(), path)
            if not isinstance(index, dict) or not isinstance(index.get("frames"), list) or not index["frames"]:
                _fail(path, "not a frame index (no \"frames\")")
            self.form = "files"
            self.fps = _number(index.get("fps"), "fps", path, 0, 1000)
            if self.fps <= 0:
                _fail(path, "fps is 0")
            if len(index["frames"]) > MAX_FRAMES:
                _fail(path, f"{len(index['frames'])} frames, more than {MAX_FRAMES}")
            self.files = [inside(self.folder, next(c["file"] for c in e["content"] if c["file"].endswith((".glb", ".gltf"))),
                                 f"{path}: frames[{i}]'s file")[len(self.folder) + 1:]
                          for i, e in enumerate(index["frames"])]
            self.first_frame = _number(index["frames"][0].get("frame", 0), "frames[0].frame", path, 0, MAX_FRAMES, True)
            self.frame_count = len(self.files)
            self.loop_frames = _number(index.get("loop_frames", self.frame_count), "loop_frames", path, 0, MAX_FRAMES, True)
            self.scene = index.get("scene", "")
            doc, buffers = self._frame_file(0)
            # Draco or meshopt frames, decoded by libwave's module (a FrameReader kept open on
            # the index: the frame files' shared views decoded once; it refuses a frame of
            # other triangles, as Draco frames of different orders would be).
            self._draco_files = _compressed(doc)
            if self._draco_files:
                self._reader = _frame_reader(path)
                self.triangles = np.asarray(self._reader.triangles).astype(np.int64).reshape(-1, 3)
            else:
                self.triangles = _mesh_triangles(doc, buffers, 0)
            self.dressing = Dressing(doc, buffers)  # the loop's frame 0 carries the seafloor, camera and sun
            return
        self.doc, self.buffers = read_gltf(path)
        doc = self.doc
        # Compressed meshes (Draco, meshopt): each frame decoded alone by libwave's module
        # (a FrameReader kept open on the file: its JSON, static views and triangles read
        # once, a frame's own views read and decoded on each change), one ahead on a
        # worker; the rest of the file (its JSON, the weights track, the seafloor, camera
        # and sun) is plain and read here as for any file.
        self._module_frames = _compressed(doc)
        extras = doc.get("asset", {}).get("extras", {}).get("libwave", {})
        if not extras and doc.get("asset", {}).get("generator") != "libwave":
            raise LibwaveFileError(f"{path}: not written by libwave (no asset.extras.libwave)")
        prim = doc["meshes"][0]["primitives"][0]
        self.scene = extras.get("scene", "")
        times = None
        if doc.get("animations"):
            sampler = doc["animations"][0]["samplers"][0]
            times = accessor(doc, self.buffers, sampler["input"])[:, 0]
        if "targets" in prim and prim["targets"]:
            self.form = "morph"
            # A target per frame; quantised files add NORMAL-only targets after them
            # (a normal's turn beyond ±1), which the add-on does not need.
            self.frame_count = sum("POSITION" in t for t in prim["targets"])
            # Each key's row of the weights track: the NORMAL-only targets it weighs in.
            targets, self._excess = len(prim["targets"]), {}
            if doc.get("animations") and targets > self.frame_count:
                weights = accessor(doc, self.buffers, doc["animations"][0]["samplers"][0]["output"])[:, 0]
                rows = weights.reshape(-1, targets)[:, self.frame_count:]
                for k, t in zip(*np.nonzero(rows)):
                    self._excess.setdefault(int(k), []).append(self.frame_count + int(t))
        else:
            self.form = "nodes"
            self.frame_nodes = [n for n in doc.get("nodes", []) if "mesh" in n and n.get("name") != "seafloor"]
            self.frame_count = len(self.frame_nodes)
        if "fps" in extras:
            self.fps = _number(extras["fps"], "asset.extras.libwave.fps", path, 0, 1000)
        else:
            self.fps = 1.0 / float(times[1] - times[0]) if times is not None and len(times) > 1 else 24.0
        if not (math.isfinite(self.fps) and 0 < self.fps <= 1000):
            _fail(path, f"fps {self.fps} is not in (0, 1000]")
        self.loop_frames = _number(extras.get("loop_frames", self.frame_count), "asset.extras.libwave.loop_frames", path, 0, MAX_FRAMES, True)
        self.first_frame = _number(extras.get("first_frame", 0), "asset.extras.libwave.first_frame", path, 0, MAX_FRAMES, True)
        if self._module_frames:
            self._reader = _frame_reader(path)
            self.triangles = np.asarray(self._reader.triangles).astype(np.int64).reshape(-1, 3)
        else:
            self.triangles = _mesh_triangles(doc, self.buffers, 0)
        self.dressing = Dressing(doc, self.buffers)

    def _frame_file(self, k):
        return read_gltf(os.path.join(self.folder, self.files[k]))

    def _decode(self, k, normals=True, order=None):
        """Frame k of a compressed output through the FrameReader (on a worker when ahead:
        the module releases the GIL), checked finite there too, in `order`."""
        try:
            f = self._reader.frame(k, normals)
        except (ValueError, RuntimeError) as e:  # libwave.InputError / Error: a frame that does not decode, other triangles
            raise LibwaveFileError(printable(str(e))) from None
        frame = Frame(f["positions"], f["foam"], f["reflect"], f["refract"], f["colors"], f["normals"])
        _finite(frame, k, self.path)
        return _gathered(frame, order, k)  # on the worker too, for a frame ahead

    def _decoded_frame(self, k):
        """Frame k of a compressed output (files form or one file): from the bounded cache,
        else decoded now; then frames k + 1 … k + AHEAD are decoded ahead on worker threads
        (libwave's module releases the GIL while it reads), so sequential playback finds
        each frame ready."""
        normals = self.want_normals
        future = self._ahead.pop(k, None)
        f = future.result() if future is not None else None
        if f is None or (normals and f.normals is None):  # not ahead, or ahead without the normals now wanted
            f = self._decode(k, normals, self.order)
        self._ahead = {j: fu for j, fu in self._ahead.items() if 0 < (j - k) % self.frame_count <= AHEAD}  # a jump drops the rest
        for step in range(1, AHEAD + 1):
            nxt = (k + step) % self.frame_count
            if nxt not in self._ahead and nxt != k:
                if self._worker is None:
                    self._worker = concurrent.futures.ThreadPoolExecutor(max_workers=AHEAD, thread_name_prefix="libwave-decode")
                self._ahead[nxt] = self._worker.submit(self._decode, nxt, normals, self.order)
        return f

    def frame(self, k):
        """Frame k of the file (0 ≤ k < frame_count)."""
        if k in self._cache and not (self.want_normals and self._cache[k].normals is None):
            return self._cache[k]
        if (self.form == "files" and self._draco_files) or self._module_frames:
            f = self._decoded_frame(k)  # checked finite where it was decoded
            self._cache = {k: f}
            return f
        try:
            if self.form == "files":
                doc, buffers = self._frame_file(k)
                f, triangles = _mesh_frame(doc, buffers, 0)
            elif self.form == "morph":
                f, triangles = _mesh_frame(self.doc, self.buffers, 0, k, self._excess.get(k, ()))
            else:
                f, triangles = _mesh_frame(self.doc, self.buffers, self.frame_nodes[k]["mesh"])
            if triangles is not None and not np.array_equal(triangles, self.triangles):
                raise LibwaveFileError("other triangles than frame 0")
        except (KeyError, IndexError, TypeError, ValueError, struct.error) as e:
            raise LibwaveFileError(printable(f"{self.path}: frame {k}: not a frame the add-on can read "
                                             f"({type(e).__name__}: {str(e)[:200]})")) from None
        except LibwaveFileError as e:
            raise LibwaveFileError(f"{self.path}: frame {k}: {e}; re-encode it plainly: wave convert FILE -o OUT") from None
        _finite(f, k, self.path)
        try:
            f = _gathered(f, self.order, k)
        except LibwaveFileError as e:
            raise LibwaveFileError(f"{self.path}: {e}") from None
        self._cache = {k: f}  # one frame at a time: the files form streams from disk
        return f


def _finite(f, k, path):
    """Refuses a frame with a NaN or infinite value (libwave's writer never writes one):
    Blender imported them silently, a vertex at NaN."""
    for name in ("positions", "normals", "foam", "reflect", "refract", "color"):
        a = getattr(f, name)
        if a is not None and not np.all(np.isfinite(a)):
            bad = int(np.argwhere(~np.isfinite(np.asarray(a).reshape(len(a), -1)))[0][0])
            _fail(path, f"frame {k}: {name} of vertex {bad} is not a finite number")


def _compressed(doc):
    """Whether a file's meshes need libwave's module: Draco or EXT_meshopt_compression."""
    return ("EXT_meshopt_compression" in doc.get("extensionsUsed", [])
            or "KHR_draco_mesh_compression" in doc["meshes"][0]["primitives"][0].get("extensions", {}))


def _libwave_module():
    """libwave's Python module: the copy the add-on's zip carries (libwave_blender/libwave,
    built for Debian 12's Python 3.11), else one on Blender's path. ImportError says why
    neither loads (another Python, a missing system library)."""
    if "libwave" in sys.modules:  # already loaded from Blender's path: one copy per process (pybind11's types)
        return sys.modules["libwave"]
    if __package__ and os.path.isdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), "libwave")):
        try:
            return importlib.import_module(__package__ + ".libwave")  # the zip's copy
        except ImportError as bundled:
            try:
                return importlib.import_module("libwave")
            except ImportError:
                raise bundled from None
    return importlib.import_module("libwave")


def _frame_reader(path):
    """libwave.FrameReader on a compressed output (Draco or meshopt), kept open across
    frames, or a message saying how to read it otherwise."""
    libwave = _module_or_advice(path)
    if not hasattr(libwave, "FrameReader"):  # a module on Blender's path older than the add-on
        raise LibwaveFileError(f"{path} is compressed, and the libwave module Blender loads ({getattr(libwave, '__file__', '?')}, "
                               f"version {getattr(libwave, '__version__', '?')}) has no FrameReader: use the module the add-on's "
                               "zip carries, or build libwave there again (docs/blender.md)")
    try:
        return libwave.FrameReader(path)
    except (ValueError, RuntimeError) as e:  # libwave.InputError / Error, naming the file
        raise LibwaveFileError(printable(str(e))) from None


def _module_or_advice(path):
    """libwave's module, or LibwaveFileError saying how to read `path` without it."""
    try:
        return _libwave_module()
    except ImportError as e:
        raise LibwaveFileError(
            f"{path} is compressed (Draco or EXT_meshopt_compression), which Blender's Python cannot decode by itself, "
            f"and libwave's Python module does not load here ({e}): the add-on carries it for Debian 12's Blender 3.4 "
            "(Python 3.11); put a module built for this Blender's Python on its path (docs/blender.md), or re-encode "
            "the run plainly (wave convert FILE -o OUT, or wave run --codec none)") from None


def check_bake(anim):
    """Refuses a bake whose frames would not fit (BAKE_BYTES) before any is made: an index
    declaring 10⁶ frames baked until memory ran out."""
    n = len(anim.first_positions())
    need = 40.0 * n * anim.frame_count
    if need > BAKE_BYTES:
        raise LibwaveFileError(printable(
            f"{anim.path}: baking {anim.frame_count} frames of {n} vertices would hold about {need / 1e9:.1f} GB in the "
            f".blend (over {BAKE_BYTES / 1e9:.0f} GB); import it without baking (the frames stream from disk)"))
