#!/usr/bin/env python3
"""The `wave` command line as a user meets it: exit codes (0 ok, 2 bad input or usage,
1 runtime failure), `error: …` on stderr naming the file/value, and no partial output."""
import array
import hashlib
import json
import math
import os
import pathlib
import time
import signal
import random
import resource
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

WAVE = os.environ["WAVE_EXE"]
DATA = os.environ["LIBWAVE_DATA_DIR"]
VALIDATOR = os.environ["GLTF_VALIDATOR"]  # scripts/gltf-validator/validate.mjs (Khronos, npm)


def validate_gltf(test, path):
    """Every file we export passes the Khronos glTF validator with no errors."""
    r = subprocess.run(["node", VALIDATOR, path], capture_output=True, text=True, timeout=600)
    test.assertEqual(r.returncode, 0, r.stdout + r.stderr)
    report = json.loads(r.stdout.splitlines()[-1])
    test.assertEqual(report["numErrors"], 0, report)
    return report


def read_glb(path):
    """(json, binary chunk) of a .glb, read by hand: independent of the writer."""
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert magic == b"glTF" and version == 2 and length == len(data)
    json_len, json_type = struct.unpack_from("<I4s", data, 12)
    assert json_type == b"JSON"
    doc = json.loads(data[20:20 + json_len])
    bin_len, bin_type = struct.unpack_from("<I4s", data, 20 + json_len)
    assert bin_type == b"BIN\0"
    return doc, data[28 + json_len:28 + json_len + bin_len]


# glTF component types: struct code, size, and the divisor of a normalised integer
# (KHR_mesh_quantization; signed ones clamp at -1).
COMPONENTS = {5126: ("f", 4, None), 5120: ("b", 1, 127.0), 5121: ("B", 1, 255.0), 5122: ("h", 2, 32767.0), 5123: ("H", 2, 65535.0)}


def floats(doc, binary, accessor):
    """An accessor's values as floats, flat (normalised integers decoded): its view
    (zeros without one, its byteStride honoured), then its sparse substitutions (morph
    targets store only the vertices that move)."""
    a = doc["accessors"][accessor]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    code, size, divisor = COMPONENTS[a["componentType"]]
    decode = (lambda v: v) if divisor is None or not a.get("normalized") else (lambda v: max(v / divisor, -1.0))

    def elements(start, count, stride):
        out = []
        for e in range(count):
            out.extend(decode(v) for v in struct.unpack_from("<%d%s" % (width, code), binary, start + e * stride))
        return out

    if "bufferView" in a:
        view = doc["bufferViews"][a["bufferView"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        values = elements(start, a["count"], view.get("byteStride", width * size))
    else:
        values = [0.0] * (a["count"] * width)
    sparse = a.get("sparse")
    if sparse:
        n = sparse["count"]
        index_view = doc["bufferViews"][sparse["indices"]["bufferView"]]
        value_view = doc["bufferViews"][sparse["values"]["bufferView"]]
        index_code = {5121: "B", 5123: "H", 5125: "I"}[sparse["indices"]["componentType"]]
        indices = struct.unpack_from("<%d%s" % (n, index_code), binary, index_view.get("byteOffset", 0) + sparse["indices"].get("byteOffset", 0))
        packed = elements(value_view.get("byteOffset", 0) + sparse["values"].get("byteOffset", 0), n, width * size)
        for i, k in enumerate(indices):
            values[k * width:(k + 1) * width] = packed[i * width:(i + 1) * width]
    return tuple(values)


# The built-in default scene until issue 66 (Gonzato's bay, a 5 s swell of 0.3 m, his
# plunging profile on the water mesh, 24 fps): tests that measured it keep it.
OLD_DEFAULT = {"name": "default: Gonzato's bay with a swell", "seafloor": {"source": "gonzato-bay"},
               "waves": [{"period": 5, "amplitude": 0.3, "direction": [0, 1]}], "trace": {"ray_spacing": 1},
               "fronts": {"step": 0.4, "split_distance": 1.2}, "outputs": {"quantize": True}}

def write_scene(folder, doc, name="s.json"):
    """Writes a scene document as a file in `folder`; returns its path."""
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def wave(*args, cwd=None):
    return subprocess.run([WAVE, *args], capture_output=True, text=True, cwd=cwd, timeout=120)


class Basics(unittest.TestCase):
    def test_version_and_help(self):
        r = wave("--version")
        self.assertEqual(r.returncode, 0)
        self.assertRegex(r.stdout, r"^wave \d+\.\d+\.\d+")
        r = wave("--help")
        self.assertEqual(r.returncode, 0)
        for sub in ("run", "dispersion", "seafloor"):
            self.assertIn(sub, r.stdout)
        r = wave("dispersion", "--help")
        self.assertEqual(r.returncode, 0)
        self.assertIn("--period", r.stdout)

    def test_dispersion_json(self):
        r = wave("dispersion", "--period", "10", "--depth", "5", "--json", "--deep-height", "2")
        self.assertEqual(r.returncode, 0, r.stderr)
        d = json.loads(r.stdout)
        # L/L0 at d/L0 = 5/156.13 = 0.032: SPM Table C-1 gives 0.4335 (interpolated).
        self.assertAlmostEqual(d["wavelength_m"] / d["deep_wavelength_m"], 0.4335, delta=2e-3)
        self.assertAlmostEqual(d["celerity_m_per_s"], d["wavelength_m"] / 10.0, places=12)
        self.assertFalse(d["breaking"])

    def test_dispersion_dry(self):
        r = wave("dispersion", "--period", "10", "--depth", "-1", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertTrue(json.loads(r.stdout)["dry"])

    def test_seafloor_info_on_real_data(self):
        r = wave("seafloor", "info", os.path.join(DATA, "bathymetry/haringvliet_swan_f31hari_250m.bot"),
                 "--swan-grid", "88,117", "--swan-spacing", "250", "--nodata", "-99", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        d = json.loads(r.stdout)
        self.assertEqual(d["nodes"], [88, 117])
        self.assertGreater(d["nodata_count"], 0)
        r = wave("seafloor", "info", "berkhoff-shoal", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertAlmostEqual(json.loads(r.stdout)["depth_range_m"][1], 0.45, places=9)


class BadInput(unittest.TestCase):
    def expect_error(self, args, code, *parts):
        r = wave(*args)
        self.assertEqual(r.returncode, code, f"{args}: stdout={r.stdout} stderr={r.stderr}")
        self.assertTrue(r.stderr.startswith("error: "), r.stderr)
        for p in parts:
            self.assertIn(p, r.stderr)

    def test_usage_errors_exit_2(self):
        self.expect_error(["frobnicate"], 2)
        self.expect_error([], 2)
        self.expect_error(["dispersion", "--period", "abc", "--depth", "3"], 2, "abc")
        self.expect_error(["dispersion", "--period", "-4", "--depth", "3"], 2, "-4")
        self.expect_error(["dispersion", "--depth", "3"], 2, "--period")
        # Ranges said plainly (not "0 to 1.797e308" written out in 300 digits).
        self.expect_error(["seafloor", "info", "planar-beach", "--spacing", "-1"], 2, "--spacing: must be >= 0, got -1")
        self.expect_error(["run", "--threads", "0"], 2, "--threads: must be > 0, got 0")
        self.expect_error(["run", "--fps", "0"], 2, "--fps: must be > 0, got 0")
        r = wave("dispersion", "--period", "8", "--depth", "3", "--deep-height", "-2")
        self.assertEqual(r.returncode, 2)
        self.assertLess(len(r.stderr), 200, r.stderr)

    def test_bad_files_exit_2(self):
        with tempfile.TemporaryDirectory() as d:
            missing = os.path.join(d, "missing.asc")
            self.expect_error(["seafloor", "info", missing], 2, missing, "not found")
            # A directory is named as one (an ifstream opens it and reads nothing).
            for name in ["dir.ply", "dir.off", "dir.json"]:
                folder = os.path.join(d, name)
                os.mkdir(folder)
                self.expect_error(["seafloor", "info", folder], 2, folder, "a directory, not a file")
            self.expect_error(["run", os.path.join(d, "dir.json")], 2, "dir.json", "a directory, not a file")
            bot = os.path.join(d, "x.bot")
            with open(bot, "w") as f:
                f.write("1 2 3\n")
            self.expect_error(["seafloor", "info", bot], 2, bot, "--swan-grid")
            self.expect_error(["seafloor", "info", bot, "--swan-grid", "2,2", "--swan-spacing", "1"], 2,
                              "truncated")
            cj = os.path.join(d, "c.json")
            with open(cj, "w") as f:
                f.write('{"contours": [{"depth": "two", "points": [[0,0],[1,1]]}]}')
            self.expect_error(["seafloor", "info", cj], 2, cj, "/contours/0/depth")
            self.expect_error(["seafloor", "info", "atlantis"], 2, "atlantis")


class Contours(unittest.TestCase):
    def test_isobath_refraction_traces_okushiri(self):
        # Ts'o–Barsky's exact crossings on the real Monai cove at full scale: rays guided
        # along the coast (their turns cancel, max_turn never fires) used to run to
        # /fronts/max_steps or max_points; now they are removed as trapped after three
        # crossings of the domain and the tracing ends.
        with open(os.path.join(EXAMPLES, "breaking-okushiri.json")) as f:
            scene = json.load(f)
        scene["fronts"]["refraction"] = "isobath"
        scene["seafloor"]["source"] = os.path.join(DATA, "bathymetry", "okushiri_monai_lab1to400_1p4cm.asc")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            r = wave("trace", path, "-o", os.path.join(d, "out"), "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            fronts = json.loads(r.stdout)
            self.assertIn("exact isobath crossings", fronts["mode"])
            self.assertGreater(fronts["rays_trapped"], 0)
            self.assertGreater(fronts["rays_aground"], 1000)  # most of the swell reaches the shore
            # One crossing along the swell (1, 0.15) of the 2 195 × 1 361 m domain:
            # (2 195 + 0.15 · 1 361) / 1.011 = 2 373 m, 593 fronts of 4 m; at most three.
            self.assertLessEqual(fronts["steps"], 3 * 593 + 1)

    def test_json_round_trip_and_obj(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "bay.json")
            r = wave("contours", "gonzato-bay", "--levels", "1,2.5", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(out) as f:
                doc = json.load(f)
            self.assertEqual(sorted(c["depth"] for c in doc["contours"]), [0.0, 1.0, 2.5])
            # The written file is a valid seafloor input again.
            r = wave("seafloor", "info", out, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(r.stdout)["contour_lines"], 3)
            obj = os.path.join(d, "bay.obj")
            self.assertEqual(wave("contours", "gonzato-bay", "--level-spacing", "1", "-o", obj).returncode, 0)
            text = open(obj).read()
            self.assertEqual(text.count("\nl "), 5)
            self.assertNotIn(" -0\n", text)

    def test_bad_levels_exit_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "x.json")
            r = wave("contours", "gonzato-bay", "--levels", "9", "-o", out)
            self.assertEqual(r.returncode, 2)
            self.assertIn("level 9", r.stderr)
            self.assertIn("-2 .. 5", r.stderr)
            r = wave("contours", "gonzato-bay", "--levels", "1", "-o", os.path.join(d, "x.txt"))
            self.assertEqual(r.returncode, 2)
            self.assertIn(".json", r.stderr)
            self.assertEqual(os.listdir(d), [])


EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")

# The sanitizer suite runs this file too (ctest --preset asan). A test whose subject is
# that two runs give the same bytes (threads, slices, repeats) repeats runs other tests
# make under ASan, and a sanitizer sees nothing in the comparison: release only.
UNDER_ASAN = "ASAN_OPTIONS" in os.environ
same_bytes_test = unittest.skipIf(UNDER_ASAN, "compares two runs' bytes: the release suite's")
ASAN_SELECTION = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "asan-selection.json")


def skip_what_the_sanitizers_reach_elsewhere(prefix, namespace):
    """Under ASan, skips the test methods of `namespace` (a suite's globals()) that
    tests/data/asan-selection.json lists: every line of our code they reach is reached
    under the sanitizers by the unit tests and the methods kept (scripts/asan-selection.py).
    The release suite runs them all, and so does the selection's own measurement
    (LIBWAVE_ASAN_SELECTION=off)."""
    if not UNDER_ASAN or os.environ.get("LIBWAVE_ASAN_SELECTION") == "off":
        return
    with open(ASAN_SELECTION) as f:
        listed = json.load(f)
    for name, entry in listed["skipped"].items():
        suite, cls, method = name.split(".")
        if suite == prefix and hasattr(namespace.get(cls), method):
            reason = f"its {entry['lines']} lines run under the sanitizers in other tests ({listed['measured']})"
            setattr(namespace[cls], method, unittest.skip(reason)(getattr(namespace[cls], method)))


def read_ply_header(path):
    """(format, vertex count, face count, vertex property names) of a PLY file."""
    with open(path, "rb") as f:
        lines = []
        while True:
            line = f.readline().decode("ascii").strip()
            lines.append(line)
            if line == "end_header" or not line:
                break
    assert lines[0] == "ply", lines[:2]
    fmt = lines[1].split()[1]
    counts, props, element = {}, [], None
    for line in lines:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            counts[element] = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            props.append(words[-1])
    return fmt, counts.get("vertex"), counts.get("face"), props


class MainJob(unittest.TestCase):
    OUTPUTS = ["animation.glb", "isobaths.json", "rays.csv", "report.json", "surface-frame-0000.obj"]
    STRIP_OUTPUTS = ["animation.glb", "isobaths.json", "strips.ply", "report.json", "surface-frame-0000.obj"]

    def test_default_scene(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("Gonzato's bay", r.stdout)
            self.assertEqual(sorted(os.listdir(out)), sorted(self.STRIP_OUTPUTS + ["whitewater"]))  # no temporaries left
            with open(os.path.join(out, "report.json")) as f:
                report = json.load(f)
            self.assertEqual(report["surface"]["kind"], "ray-strips")
            # Gonzato: one ray per metre across the 100 m bay's mouth and the part of its
            # side the slightly oblique swell enters over.
            self.assertGreaterEqual(report["trace"]["initial_rays"], 100)
            self.assertGreater(report["trace"]["inserted_rays"], 50)
            self.assertEqual(report["surface"]["frames"], 72)  # 6 s loop at 12 fps
            # The showcase (issue 66): Jeschke's breakers, a wind sea, whitewater.
            self.assertGreater(report["surface"]["breakers"]["breaking_rays"], 100)
            self.assertGreater(report["surface"]["wind_sea"]["significant_height_m"], 0.3)
            self.assertEqual(len(os.listdir(os.path.join(out, "whitewater"))), 72)
            fmt, vertices, faces, props = read_ply_header(os.path.join(out, "strips.ply"))
            self.assertEqual(fmt, "binary_little_endian")
            self.assertEqual((vertices, faces), (report["trace"]["vertices"], report["trace"]["triangles"]))
            # The exported surface is the water mesh, the strips' fields resampled on it.
            mesh = report["surface"]["water_mesh"]
            self.assertEqual(mesh["vertices_per_wavelength"], 16)
            # … continued to the horizon by the far field's skirt (docs/far-field.md).
            far = report["surface"]["far_field"]
            self.assertEqual((mesh["vertices"] + far["vertices"], mesh["triangles"] + far["triangles"]),
                             (report["surface"]["vertices"], report["surface"]["triangles"]))
            self.assertGreaterEqual(far["distance_m"], 2000 * 3.5)  # the default camera stands 3.5 m up
            for name in ["ray", "step", "phase", "k", "omega", "amplitude", "depth", "slope", "rise", "flag", "caustic"]:
                self.assertIn(name, props)
            self.check_animation(out, report)
            # Quantised (KHR_mesh_quantization), within issue 25's 50 MB for the default run.
            self.assertTrue(report["surface"]["quantized"])
            self.assertLess(os.path.getsize(os.path.join(out, "animation.glb")), 50e6)
            # Shading in the default (UV-map) layout, morphed per frame like positions.
            doc, binary = read_glb(os.path.join(out, "animation.glb"))
            prim = doc["meshes"][0]["primitives"][0]
            self.assertIn("TEXCOORD_1", prim["attributes"])
            self.assertIn("TEXCOORD_2", prim["attributes"])
            self.assertIn("TEXCOORD_1", prim["targets"][5])
            rt = floats(doc, binary, prim["attributes"]["TEXCOORD_1"])
            self.assertLess(max(abs(rt[i] + rt[i + 1] - 1.0) for i in range(0, len(rt), 2)), 1.0 / 65535)  # R + T = 1 (uint16)
            # Foam appears somewhere in the loop (waves break in the bay) and stays in [0, 1].
            foam_max = 0.0
            base = floats(doc, binary, prim["attributes"]["TEXCOORD_2"])[0::2]
            for target in prim["targets"][:report["surface"]["frames"]:10]:
                delta = floats(doc, binary, target["TEXCOORD_2"])[0::2]
                frame = [b + d for b, d in zip(base, delta)]
                self.assertGreaterEqual(min(frame), -1e-4)  # uint16 base + int16 delta
                self.assertLessEqual(max(frame), 1.0 + 1e-4)
                foam_max = max(foam_max, max(frame))
            self.assertGreater(foam_max, 0.5)

    def test_seafloor_apron_closes_on_the_far_rectangle_and_the_water_meets_sand(self):
        # The seafloor under the far field (docs/far-field.md, the seafloor apron): the
        # default bay's grid ([0, 100]² m, 0.5 m nodes) continued to the skirt's far
        # rectangle. Every edge inside is shared by two triangles and the mesh's only
        # border is that rectangle. A triangle touching the grid's border stays within a
        # cell or so of it: a renderer's smooth normals carry the border's slopes (and
        # their light) that far only. (The pale wedge of land from the bay's beach to
        # the horizon was the border's colour extruded to the far rectangle; the terrain
        # beyond the data now fades it: docs/far-field.md.)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", "-o", out, "--frames", "0:1", "--no-quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "report-frames-0-1.json")) as f:
                reach = json.load(f)["surface"]["far_field"]["distance_m"]
            doc, binary = read_glb(os.path.join(out, "animation-frames-0-1.glb"))
            prim = next(m for m in doc["meshes"] if m["name"] == "seafloor")["primitives"][0]
            g = floats(doc, binary, prim["attributes"]["POSITION"])
            plan = [(g[i], -g[i + 2]) for i in range(0, len(g), 3)]  # glTF y up: libwave's (x, −z)
            a = doc["accessors"][prim["indices"]]
            view = doc["bufferViews"][a["bufferView"]]
            code = {5125: "I", 5123: "H"}[a["componentType"]]
            idx = struct.unpack_from("<%d%s" % (a["count"], code), binary, view.get("byteOffset", 0) + a.get("byteOffset", 0))
            tris = [idx[i:i + 3] for i in range(0, len(idx), 3)]
            outside = lambda p: max(-p[0], p[0] - 100.0, -p[1], p[1] - 100.0)  # > 0 beyond the grid's rectangle
            on_border = [abs(outside(p)) < 1e-4 for p in plan]
            self.assertEqual(sum(on_border), 4 * 200)  # the grid's border nodes
            uses = {}
            for t in tris:
                for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                    uses[tuple(sorted(e))] = uses.get(tuple(sorted(e)), 0) + 1
            self.assertLessEqual(max(uses.values()), 2)
            open_edges = [e for e, n in uses.items() if n == 1]
            self.assertGreater(len(open_edges), 0)
            for e in open_edges:
                for v in e:
                    self.assertGreater(outside(plan[v]), 0.99 * reach, plan[v])
            longest = 0.0
            for t in tris:
                if any(on_border[v] for v in t):
                    longest = max(longest, max(math.dist(plan[t[i]], plan[t[(i + 1) % 3]]) for i in range(3)))
            self.assertLessEqual(longest, 0.5 * math.sqrt(2.0) + 1e-3)
            # The colours blend across each triangle: a grass line at the waterline drew
            # the grid's diagonals into the water's edge, green teeth a cell apart in a
            # close-up of the shore. Every triangle the waterline crosses is sand (red over
            # green) at all its corners; grass (green over red) begins above the beach.
            colour = floats(doc, binary, prim["attributes"]["COLOR_0"])
            sand = [colour[3 * v] >= colour[3 * v + 1] for v in range(len(plan))]
            height = g[1::3]
            shore = [t for t in tris if min(height[v] for v in t) <= 0.0 < max(height[v] for v in t)]
            self.assertGreater(len(shore), 100)
            self.assertEqual([t for t in shore if not all(sand[v] for v in t)], [])
            self.assertTrue(any(not sand[v] and height[v] > 1.2 for v in range(len(plan))))  # 2 × the 0.3 m swell's height

    def test_named_attributes_and_colour(self):
        with tempfile.TemporaryDirectory() as d:
            scene, out = os.path.join(d, "s.json"), os.path.join(d, "out")
            with open(scene, "w") as f:
                json.dump({"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
                           "fronts": {"step": 0.8, "split_distance": 2.4},
                           "outputs": {"attributes": "named", "color": True},
                           "shade": {"fresnel": "tso"}, "camera": {"position": [50, -20, 30]}}, f)
            r = wave("run", scene, "-o", out, "--json", "--codec", "none")  # floats, read by hand below
            self.assertEqual(r.returncode, 0, r.stderr)
            glb = os.path.join(out, "animation.glb")
            validate_gltf(self, glb)
            doc, binary = read_glb(glb)
            attrs = doc["meshes"][0]["primitives"][0]["attributes"]
            for name in ["_REFLECT", "_REFRACT", "_FOAM", "COLOR_0"]:
                self.assertIn(name, attrs)
            self.assertNotIn("TEXCOORD_1", attrs)
            reflect = floats(doc, binary, attrs["_REFLECT"])
            self.assertGreaterEqual(min(reflect), 0.02 - 1e-6)  # Ts'o's parabola never goes below 0.02

    def check_animation(self, out, report):
        glb = os.path.join(out, "animation.glb")
        validate_gltf(self, glb)
        doc, binary = read_glb(glb)
        frames, fps = report["surface"]["frames"], report["surface"]["fps"]
        prim = doc["meshes"][0]["primitives"][0]
        # One morph target per frame; a quantised file adds NORMAL-only targets after them.
        targets = len(prim["targets"])
        self.assertEqual(sum("POSITION" in t for t in prim["targets"]), frames)
        self.assertTrue(all(sorted(t) == ["NORMAL"] for t in prim["targets"][frames:]))
        self.assertEqual(doc["meshes"][0]["extras"]["targetNames"][1], "frame_0001")
        self.assertEqual(doc["accessors"][prim["attributes"]["POSITION"]]["count"], report["surface"]["vertices"])
        sampler = doc["animations"][0]["samplers"][0]
        self.assertEqual(sampler["interpolation"], "STEP")
        self.assertEqual(doc["animations"][0]["channels"][0]["target"]["path"], "weights")
        times = floats(doc, binary, sampler["input"])
        weights = floats(doc, binary, sampler["output"])
        for k, t in enumerate(times):
            self.assertLessEqual(t, k / fps)  # largest float32 <= k / fps
            self.assertEqual(weights[k * targets:k * targets + frames].count(1.0), 1)
            self.assertEqual(weights[k * targets + k], 1.0)
            self.assertLessEqual(weights[k * targets + frames:(k + 1) * targets].count(1.0), 1)
            self.assertEqual(set(weights[k * targets:(k + 1) * targets]) - {0.0, 1.0}, set())
        # The base mesh is frame 0: the OBJ frame (z up) mapped to glTF's y up (quantised:
        # the float base is the positions over the mesh node's scale, one float rounding).
        base = floats(doc, binary, prim["attributes"]["POSITION"])
        obj = [tuple(map(float, line.split()[1:])) for line in open(os.path.join(out, "surface-frame-0000.obj"))
               if line.startswith("v ")]
        f32 = lambda value: struct.unpack("<f", struct.pack("<f", value))[0]  # OBJ holds the shortest float text
        scale = next(n.get("scale", [1.0])[0] for n in doc["nodes"] if n.get("mesh") == 0)
        for v in range(0, len(obj), max(1, len(obj) // 50)):
            x, y, z = obj[v]
            if report["surface"].get("quantized"):
                for got, want in zip(base[3 * v:3 * v + 3], (x, z, -y)):
                    self.assertAlmostEqual(got * scale, want, delta=1e-6 * (1.0 + abs(want)))
            else:
                self.assertEqual(base[3 * v:3 * v + 3], (f32(x), f32(z), f32(-y)))

    def run_example(self, name, out):
        """Runs an example scene into `out` as plain floats (check_animation reads them by
        hand), checks its animation, returns the report."""
        r = wave("run", os.path.join(EXAMPLES, name), "-o", out, "--json", "--codec", "none")
        self.assertEqual(r.returncode, 0, r.stderr)
        report = json.loads(r.stdout)
        self.check_animation(out, report)
        return report

    def test_tso_barsky_scene_loops_over_six_seconds(self):
        with tempfile.TemporaryDirectory() as d:
            report = self.run_example("tso-barsky.json", d)
            self.assertEqual(report["surface"]["loop_period_s"], 6.0)  # LCM of 6 s and 1 s
            self.assertEqual(report["surface"]["frames"], 144)
            self.assertEqual(report["surface"]["control_grid"], [100, 100])
            self.assertGreater(report["trace"]["crossings"], 500)
            # Its 1 s train (L = 1.56 m) is resolved on 0.47 m cells (issue 66: on 0.94 m
            # cells it aliased, and its crests met the beach as a toothed waterline).
            self.assertEqual(report["warnings"], [])
            # On 1 m cells it aliases: said, not hidden.
            doc = json.load(open(os.path.join(EXAMPLES, "tso-barsky.json")))
            doc["surface"]["grid"] = [50, 50]
            r = wave("run", write_scene(d, doc), "-o", os.path.join(d, "coarse"), "--json", "--frames", "0:1", "--codec", "none")
            self.assertEqual(r.returncode, 0, r.stderr)
            warnings = json.loads(r.stdout)["warnings"]
            self.assertEqual(len(warnings), 1)
            self.assertIn("T = 1 s", warnings[0])

    def test_real_bathymetry_end_to_end(self):
        with tempfile.TemporaryDirectory() as d:
            report = self.run_example("okushiri.json", d)
            self.assertGreater(report["trace"]["rays_aground"], 100)
            lo, hi = report["surface"]["height_range_m"]
            self.assertLess(hi, 0.02)  # 4 mm waves shoal, but stay bounded by breaking
            self.assertGreater(hi, 0.004)

    @same_bytes_test
    def test_outputs_are_deterministic(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a"), os.path.join(d, "b")
            scene = os.path.join(EXAMPLES, "planar-beach.json")
            self.assertEqual(wave("run", scene, "-o", a).returncode, 0)
            self.assertEqual(wave("run", scene, "-o", b).returncode, 0)
            for name in self.OUTPUTS:
                self.assertEqual(open(os.path.join(a, name), "rb").read(), open(os.path.join(b, name), "rb").read(), name)

    @same_bytes_test
    def test_ray_strips_are_identical_with_one_and_two_threads(self):
        with tempfile.TemporaryDirectory() as d:
            a, b = os.path.join(d, "a"), os.path.join(d, "b")
            # The whole trace and surface, 20 frames (4 fps) of the loop: the frames are
            # evaluated by the same code at any rate.
            self.assertEqual(wave("run", "--threads", "1", "--fps", "4", "-o", a).returncode, 0)
            self.assertEqual(wave("run", "--threads", "2", "--fps", "4", "-o", b).returncode, 0)
            for name in ["animation.glb", "strips.ply", "surface-frame-0000.obj"]:
                self.assertEqual(open(os.path.join(a, name), "rb").read(), open(os.path.join(b, name), "rb").read(), name)
            self.assertEqual(wave("run", "--threads", "0").returncode, 2)

    def test_gonzato_examples(self):
        # Traced only: the default scene is the bay and is animated above; the island's
        # animation would be ~350 MB.
        r = wave("trace", os.path.join(EXAMPLES, "gonzato-bay.json"), "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        bay = json.loads(r.stdout)
        self.assertEqual(bay["initial_rays"], 100)
        # The paper: 209 new rays, 39 097 facets for its bay (its exact shape is not given).
        self.assertGreater(bay["triangles"], 20000)
        self.assertLess(bay["triangles"], 80000)
        r = wave("trace", os.path.join(EXAMPLES, "gonzato-island.json"), "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        island = json.loads(r.stdout)
        self.assertGreater(island["rays_aground"], 0)
        self.assertGreater(island["rays_trapped"], 0)  # orbits round the shelf, cut at 180 degrees
        self.assertGreater(island["caustic_points"], 0)  # rays wrapping round meet behind the island

    def test_schema_describes_every_example_and_validate_checks_without_running(self):
        import jsonschema  # Debian: python3-jsonschema (scripts/install-deps.sh)
        r = wave("schema")
        self.assertEqual(r.returncode, 0, r.stderr)
        schema = json.loads(r.stdout)
        jsonschema.Draft202012Validator.check_schema(schema)
        for name in sorted(os.listdir(EXAMPLES)):
            if name.endswith(".json"):
                jsonschema.validate(json.load(open(os.path.join(EXAMPLES, name))), schema)
                r = wave("validate", os.path.join(EXAMPLES, name), "--json")
                self.assertEqual(r.returncode, 0, f"{name}: {r.stderr}")
                self.assertTrue(json.loads(r.stdout)["valid"])
        # A typo is an error for both the schema and the parser.
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.json")
            doc = {"waves": [{"period": 5}], "fronts": {"stpe": 0.4}}
            with open(bad, "w") as f:
                json.dump(doc, f)
            with self.assertRaises(jsonschema.ValidationError):
                jsonschema.validate(doc, schema)
            r = wave("validate", bad)
            self.assertEqual(r.returncode, 2)
            self.assertIn("/fronts/stpe", r.stderr)
            self.assertEqual(os.listdir(d), ["bad.json"])

    def test_trace_summary_and_strip_mesh(self):
        with tempfile.TemporaryDirectory() as d:
            ply, csv = os.path.join(d, "strips.ply"), os.path.join(d, "fronts.csv")
            r = wave("trace", os.path.join(EXAMPLES, "gonzato-bay.json"), "--mesh-out", ply, "-o", csv, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            summary = json.loads(r.stdout)
            for key in ["initial_rays", "inserted_rays", "rays_aground", "steps", "vertices", "triangles"]:
                self.assertIn(key, summary)
            _, vertices, faces, _ = read_ply_header(ply)
            self.assertEqual((vertices, faces), (summary["vertices"], summary["triangles"]))
            rows = pathlib.Path(csv).read_text().splitlines()
            self.assertEqual(rows[0], "front,ray,x,y,dir_x,dir_y,phase,k,depth,slope,rise,amplitude,flag")
            self.assertEqual(len(rows) - 1, summary["points"])
            # The same fronts refracted at exact isobath crossings.
            scene = os.path.join(d, "iso.json")
            with open(scene, "w") as f:
                json.dump({"waves": [{"period": 5, "amplitude": 0.3}], "isobaths": {"spacing": 0.25},
                           "fronts": {"refraction": "isobath"}}, f)
            r = wave("trace", scene, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            iso = json.loads(r.stdout)
            self.assertIn("isobath", iso["mode"])
            self.assertEqual(iso["initial_rays"], 100)
            self.assertLess(abs(iso["triangles"] - summary["triangles"]), 0.1 * summary["triangles"])
            os.remove(scene)
            # --mesh-out on a height-field scene, or nothing asked: exit 2, nothing written.
            r = wave("trace", os.path.join(EXAMPLES, "planar-beach.json"), "--mesh-out", os.path.join(d, "x.ply"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("ray-strips", r.stderr)
            self.assertEqual(wave("trace", os.path.join(EXAMPLES, "planar-beach.json")).returncode, 2)
            self.assertEqual(sorted(os.listdir(d)), ["fronts.csv", "strips.ply"])

    def test_trace_writes_csv(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "rays.csv")
            r = wave("trace", os.path.join(EXAMPLES, "planar-beach.json"), "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows = open(out).read().splitlines()
            self.assertTrue(rows[1].startswith("0,0,"))
            self.assertTrue(any(row.endswith(",aground") for row in rows))

    def test_bad_scenes_exit_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            bad = os.path.join(d, "bad.json")
            out = os.path.join(d, "out")
            cases = [
                ('{"waves": [{"period": -6}]}', "/waves/0/period"),
                ('{"waves": [{"period": "six"}]}', "expected a number"),
                ('{"waves": [{"period": 6}], "outputs": {"color": "yes"}}', "expected true or false"),
                ('{"waves": [{"period": 6, "direction": [0, 0]}]}', "/waves/0/direction"),
                ('{"waves": [{"period": 6}], "surface": {"kind": "height-field", "footprint": "blob"}}', "bresenham, smooth"),
                ('{"waves": [{"period": 6}], "surface": {"grid": [5, 5]}}', "/surface/grid"),
                ('{"waves": [{"period": 6}, {"period": 7}]}', "/waves"),
                ('{"waves": [{"period": 6}], "surface": {"kind": "height-field"}, "fronts": {}}', "/fronts"),
                ('{"waves": [{"period": 6}], "fronts": {"step": -1}}', "/fronts/step"),
                ('{"waves": [{"period": 6}], "motion": {"profile": "gerstner"}}', "/motion/profile"),
                ('{"waves": [{"period": 6}], "motion": {"stretch_max": -1}}', "/motion/stretch_max"),
                ('{"waves": [{"period": 6}], "camera": {"position": [50, 99, 0.5]}}', "/camera/position"),
                ('{"waves": [{"period": 6}], "camera": {"position": [1, 2]}}', "/camera/position"),
                ('{"waves": [{"period": 6}], "animation": {"fps": -24}}', "/animation/fps"),
                ('{"waves": [{"period": 6}], "outputs": {"attributes": "all"}}', "uv-maps"),
                ('{"waves": [{"period": 6}], "outputs": {"colour": true}}', "/outputs/colour"),
                ('{"waves": [{"period": 6}], "shade": {"foam_onset": 1.5}}', "/shade/foam_onset"),
                ('{"waves": [{"period": 6}], "shade": {"foam_fade_periods": 0}}', "/shade/foam_fade_periods"),
                ('{"waves": [{"period": 6}], "shade": {"foam_fade_periods": 0.3, "foam_fade_time": 2}}', "/shade/foam_fade_periods"),
                ('{"waves": [{"period": 6}], "outputs": {"draco": true, "quantize": true}}', "/outputs/draco"),
                ('{"waves": [{"period": 6}], "outputs": {"form": "files", "draco": {"position_bits": 40}}}', "/outputs/draco/position_bits"),
                ('{"waves": [{"period": 6}], "seafloor": {"source": "nowhere.asc"}}', "/seafloor/source"),
                ('{"waves": [{"period": 6}], "trace": {"rays": 3}}', "/trace/rays"),
                ('{"waves": [{"period": 6}], "isobaths": {"levels": [99]}}', "level 99"),
                ('{"waves": []}', "/waves"),
                ('{"waves": [{"period": 6}], "trace": {"ray_spacing": 0.0001, "max_rays": 10}}', "max_rays"),
                ('{"waves": [{"period": 6}', "not valid JSON"),
            ]
            for text, part in cases:
                with open(bad, "w") as f:
                    f.write(text)
                r = wave("run", bad, "-o", out)
                self.assertEqual(r.returncode, 2, f"{text}: {r.stderr}")
                self.assertTrue(r.stderr.startswith("error: "))
                self.assertIn(part, r.stderr, text)
                self.assertFalse(os.path.exists(out), text)
            r = wave("run", os.path.join(d, "missing.json"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("not found", r.stderr)

    def test_an_output_folder_below_a_file_is_refused_without_partial_files(self):
        # The -o value is the user's input: refused before any work (exit 2), naming it.
        # (A full disk, a runtime failure, exits 1: tests/test_hostile.py, Recovery.)
        with tempfile.TemporaryDirectory() as d:
            blocker = os.path.join(d, "file")
            with open(blocker, "w") as f:
                f.write("x")
            r = wave("run", "-o", os.path.join(blocker, "sub"))
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(blocker + " is a file, not a folder", r.stderr)
            self.assertEqual(os.listdir(d), ["file"])


class OutputForms(unittest.TestCase):
    """The forms and containers of the default scene's output, frame slices and `wave merge`
    (a class of its own: under ASan the main job's tests took ~10 minutes in one)."""

    SMALL = {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
             "fronts": {"step": 0.8, "split_distance": 2.4}}

    def test_the_run_summary_names_what_each_form_wrote(self):
        # The "wrote" line from the forms' table (ExportFormInfo::summary_files, _contents):
        # a ply run said "frames as morph targets" before.
        expected = {"morph": "(3 frames as morph targets, STEP weights;", "nodes": "(3 scale-switched nodes;",
                    "files": "frames/ + index.json (3 files;", "pc2": ".obj + .pc2 (3 point-cache samples;",
                    "ply": "(3 binary PLY frames;"}
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            for form, words in expected.items():
                r = wave("run", scene, "-o", os.path.join(d, form), "--form", form, "--frames", "0:3", "--fps", "12")
                self.assertEqual(r.returncode, 0, r.stderr)
                wrote = next(line for line in r.stdout.splitlines() if line.startswith("wrote"))
                self.assertIn(words, wrote, form)
                self.assertEqual("morph targets" in wrote, form == "morph", form)

    def test_files_form_slices_merge_in_the_index(self):
        with tempfile.TemporaryDirectory() as d:
            scene, out = os.path.join(d, "s.json"), os.path.join(d, "out")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            for frames in ["0:5", "5:12"]:  # two machines' slices into one folder
                r = wave("run", scene, "-o", out, "--form", "files", "--frames", frames, "--fps", "12", "-q")
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertEqual(r.stdout, "")  # --quiet
            with open(os.path.join(out, "index.json")) as f:
                index = json.load(f)
            self.assertEqual(index["loop_frames"], 60)  # 5 s at 12 fps
            self.assertEqual([f["frame"] for f in index["frames"]], list(range(12)))
            for f in index["frames"]:
                self.assertLessEqual(f["time"], f["frame"] / 12)
                self.assertTrue(os.path.exists(os.path.join(out, f["file"])))
            validate_gltf(self, os.path.join(out, index["frames"][7]["file"]))
            self.assertEqual(len(os.listdir(os.path.join(out, "frames"))), 12)
            # A slice's frames are the whole run's frames, byte for byte.
            whole = os.path.join(d, "whole")
            self.assertEqual(wave("run", scene, "-o", whole, "--form", "files", "--fps", "12", "-q").returncode, 0)
            for name in ["frame-0003.glb", "frame-0007.glb"]:
                self.assertEqual(pathlib.Path(out, "frames", name).read_bytes(), pathlib.Path(whole, "frames", name).read_bytes())
            # A slice of another animation (other fps) into the same folder: refused, nothing written.
            before = sorted(os.listdir(os.path.join(out, "frames")))
            r = wave("run", scene, "-o", out, "--form", "files", "--frames", "0:3", "--fps", "24")
            self.assertEqual(r.returncode, 2)
            self.assertIn("index.json", r.stderr)
            self.assertEqual(sorted(os.listdir(os.path.join(out, "frames"))), before)

    @same_bytes_test
    def test_slices_merged_are_one_run_byte_for_byte(self):
        # Four --slice runs into one folder (as a Slurm array would, in any order), then
        # `wave merge`: the folder equals a single run's, file for file and byte for byte.
        for container in ["glb", "gltf"]:
            with tempfile.TemporaryDirectory() as d:
                scene, sliced, whole = os.path.join(d, "s.json"), os.path.join(d, "sliced"), os.path.join(d, "whole")
                with open(scene, "w") as f:
                    json.dump(self.SMALL, f)
                common = ["--form", "files", "--fps", "4", "--container", container, "-q"]
                for i in [2, 0, 3, 1]:
                    r = wave("run", scene, "-o", sliced, "--slice", "%d/4" % i, *common)
                    self.assertEqual(r.returncode, 0, r.stderr)
                # Each slice reports alone; only the one holding frame 0 writes its OBJ.
                self.assertIn("report-frames-15-20.json", os.listdir(sliced))
                self.assertNotIn("report.json", os.listdir(sliced))
                self.assertEqual(wave("run", scene, "-o", whole, *common).returncode, 0)
                r = wave("merge", sliced)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("joined 4 slice reports", r.stdout)
                tree = lambda root: sorted(str(p.relative_to(root)) for p in pathlib.Path(root).rglob("*"))
                self.assertEqual(tree(sliced), tree(whole))
                for name in tree(whole):
                    if os.path.isfile(os.path.join(whole, name)):
                        self.assertEqual(pathlib.Path(sliced, name).read_bytes(), pathlib.Path(whole, name).read_bytes(), name)
                report = json.load(open(os.path.join(sliced, "report.json")))
                self.assertEqual((report["surface"]["frames"], report["surface"]["first_frame"]), (20, 0))

    def test_merge_refuses_missing_frames_unless_partial(self):
        with tempfile.TemporaryDirectory() as d:
            scene, out = os.path.join(d, "s.json"), os.path.join(d, "out")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            for i in [0, 2]:
                self.assertEqual(wave("run", scene, "-o", out, "--slice", "%d/4" % i, "--form", "files", "--fps", "4", "-q").returncode, 0)
            os.remove(os.path.join(out, "index.json"))
            r = wave("merge", out)
            self.assertEqual(r.returncode, 2)
            self.assertIn("10 of 20 frames are missing (first: 5)", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "index.json")))  # nothing written
            r = wave("merge", out, "--partial")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "index.json")) as f:
                index = json.load(f)
            self.assertEqual([f["frame"] for f in index["frames"]], list(range(5)) + list(range(10, 15)))
            # The slice reports stay as they are until the loop is complete.
            self.assertEqual(sorted(n for n in os.listdir(out) if n.startswith("report")),
                             ["report-frames-0-5.json", "report-frames-10-15.json"])
            # A frame of another animation in the folder: refused, naming the file.
            other = os.path.join(d, "other")
            self.assertEqual(wave("run", scene, "-o", other, "--frames", "5:6", "--form", "files", "--fps", "8", "-q").returncode, 0)
            os.replace(os.path.join(other, "frames", "frame-0005.glb"), os.path.join(out, "frames", "frame-0005.glb"))
            r = wave("merge", out, "--partial")
            self.assertEqual(r.returncode, 2)
            self.assertIn("frame-0005.glb: belongs to another animation", r.stderr)
            self.assertEqual(wave("merge", os.path.join(d, "nothing")).returncode, 2)

    def test_draco_nodes_and_files_validate_and_shrink(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:  # the water alone: Draco compresses it, not the seafloor beside it
                json.dump({**self.SMALL, "outputs": {**self.SMALL.get("outputs", {}), "seafloor": False}}, f)
            sizes = {}
            for draco in [False, True]:
                out = os.path.join(d, "draco" if draco else "plain")
                args = ["run", scene, "-o", out, "--form", "nodes", "--fps", "6", "-q"] + (["--draco"] if draco else [])
                self.assertEqual(wave(*args).returncode, 0)
                glb = os.path.join(out, "animation.glb")
                validate_gltf(self, glb)
                sizes[draco] = os.path.getsize(glb)
                doc, _ = read_glb(glb)
                self.assertEqual("KHR_draco_mesh_compression" in doc.get("extensionsRequired", []), draco)
            self.assertLess(sizes[True], sizes[False] / 3)
            out = os.path.join(d, "files")
            self.assertEqual(wave("run", scene, "-o", out, "--form", "files", "--frames", "0:2", "--draco", "-q").returncode, 0)
            validate_gltf(self, os.path.join(out, "frames", "frame-0001.glb"))
            # Morph: the base compressed, the targets float in the same order.
            out = os.path.join(d, "morph")
            self.assertEqual(wave("run", scene, "-o", out, "--draco", "--fps", "6", "-q").returncode, 0)
            validate_gltf(self, os.path.join(out, "animation.glb"))
            doc, _ = read_glb(os.path.join(out, "animation.glb"))
            prim = doc["meshes"][0]["primitives"][0]
            self.assertIn("KHR_draco_mesh_compression", prim["extensions"])
            self.assertEqual(len(prim["targets"]), 30)

    def test_a_failing_write_leaves_the_previous_outputs_intact(self):
        with tempfile.TemporaryDirectory() as d:
            scene, out = os.path.join(d, "s.json"), os.path.join(d, "out")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            self.assertEqual(wave("run", scene, "-o", out, "-q").returncode, 0)
            before = {n: pathlib.Path(out, n).read_bytes() for n in os.listdir(out)}
            # A folder where the first frame file goes: publishing it fails (a frames/ that
            # is a file is refused before any frame is computed: test_hostile.py, Resume).
            os.makedirs(os.path.join(out, "frames", "frame-0000.glb", "in-the-way"))
            r = wave("run", scene, "-o", out, "--form", "files", "--fps", "6")
            self.assertEqual(r.returncode, 1, r.stderr)
            self.assertTrue(r.stderr.startswith("error: "))
            after = {n: pathlib.Path(out, n).read_bytes() for n in os.listdir(out)
                     if n != "frames" and not n.startswith(".wave-partial-")}
            self.assertEqual(after, before)  # nothing replaced, no staging folder left
            # The computed frames wait in the partial folder: once the obstacle is gone,
            # --resume publishes them without computing any again.
            shutil.rmtree(os.path.join(out, "frames"))
            r = wave("run", scene, "-o", out, "--form", "files", "--fps", "6", "--resume", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            resumed = json.loads(r.stdout)["resume"]
            self.assertEqual(resumed, {"kept_frames": 30, "computed_frames": 0})
            self.assertEqual(len(os.listdir(os.path.join(out, "frames"))), 30)
            self.assertEqual([n for n in os.listdir(out) if n.startswith(".wave-")], [])

    def test_quantized_forms_validate_and_shrink(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            sizes = {}
            for form in ["morph", "nodes", "files"]:
                for quantize in [False, True]:
                    out = os.path.join(d, f"{form}-{quantize}")
                    args = ["run", scene, "-o", out, "--form", form, "--fps", "6", "-q"] + (["--quantize"] if quantize else ["--codec", "none"])
                    self.assertEqual(wave(*args).returncode, 0)
                    path = os.path.join(out, "frames", "frame-0003.glb") if form == "files" else os.path.join(out, "animation.glb")
                    validate_gltf(self, path)
                    sizes[form, quantize] = os.path.getsize(path)
                    doc, _ = read_glb(path)
                    self.assertEqual("KHR_mesh_quantization" in doc.get("extensionsRequired", []), quantize)
                self.assertLess(sizes[form, True], 0.8 * sizes[form, False], form)
            r = wave("run", scene, "-o", os.path.join(d, "both"), "--form", "files", "--draco", "--quantize")
            self.assertEqual(r.returncode, 2)
            self.assertFalse(os.path.exists(os.path.join(d, "both")))

    def test_gltf_container_with_external_bin(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            out = os.path.join(d, "morph")
            r = wave("run", scene, "-o", out, "--container", "gltf", "--fps", "6", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("animation.gltf", json.loads(r.stdout)["outputs"])
            gltf = json.load(open(os.path.join(out, "animation.gltf")))
            self.assertEqual(gltf["buffers"][0]["uri"], "animation.bin")
            self.assertEqual(gltf["buffers"][0]["byteLength"], os.path.getsize(os.path.join(out, "animation.bin")))
            validate_gltf(self, os.path.join(out, "animation.gltf"))
            out = os.path.join(d, "files")
            r = wave("run", scene, "-o", out, "--container", "gltf", "--form", "files", "--frames", "0:2", "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "index.json")) as f:
                index = json.load(f)
            self.assertEqual(index["frames"][1]["file"], "frames/frame-0001.gltf")
            validate_gltf(self, os.path.join(out, "frames", "frame-0001.gltf"))
            self.assertTrue(os.path.exists(os.path.join(out, "frames", "frame-0001.bin")))

    def test_nodes_form_and_frame_slices(self):
        with tempfile.TemporaryDirectory() as d:
            scene, out = os.path.join(d, "s.json"), os.path.join(d, "out")
            with open(scene, "w") as f:
                json.dump(self.SMALL, f)
            r = wave("run", scene, "-o", out, "--form", "nodes", "--fps", "6", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            glb = os.path.join(out, "animation.glb")
            validate_gltf(self, glb)
            doc, binary = read_glb(glb)
            frames = report["surface"]["frames"]
            self.assertEqual(frames, 30)
            # One mesh per frame, and the seafloor beside them (with the camera and the sun).
            self.assertEqual([m["name"] for m in doc["meshes"]].count("seafloor"), 1)
            self.assertEqual(len(doc["meshes"]) - 1, frames)
            self.assertEqual(sorted(n["name"] for n in doc["nodes"] if n["name"] in ("seafloor", "camera", "sun")),
                             ["camera", "seafloor", "sun"])
            channels = doc["animations"][0]["channels"]
            self.assertEqual(len(channels), frames)
            self.assertTrue(all(c["target"]["path"] == "scale" for c in channels))
            # Channel k's scale is 1 exactly at key k.
            sampler = doc["animations"][0]["samplers"][channels[3]["sampler"]]
            scales = floats(doc, binary, sampler["output"])
            self.assertEqual([scales[3 * k] for k in range(frames)], [1.0 if k == 3 else 0.0 for k in range(frames)])
            self.assertEqual(sampler["interpolation"], "STEP")
            # A morph slice: its own file, keys at the slice's absolute times.
            r = wave("run", scene, "-o", out, "--frames", "10:20", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            doc, binary = read_glb(os.path.join(out, "animation-frames-10-20.glb"))
            times = floats(doc, binary, doc["animations"][0]["samplers"][0]["input"])
            self.assertEqual(len(times), 10)
            self.assertLessEqual(times[0], 10 / 24)
            self.assertGreater(times[0], 10 / 24 - 1e-6)
            self.assertEqual(doc["meshes"][0]["extras"]["targetNames"][0], "frame_0010")
            for bad in ["5:3", "abc", "200:300", "0:10000", "100:121"]:
                r = wave("run", scene, "-o", os.path.join(d, "bad"), "--frames", bad)
                self.assertEqual(r.returncode, 2, bad)
                self.assertIn("frame", r.stderr)
                self.assertFalse(os.path.exists(os.path.join(d, "bad")))
            # A shot past the 120-frame loop is never cut short in silence: the message
            # says the loop's length and the keys that set it.
            r = wave("run", scene, "-o", os.path.join(d, "bad"), "--frames", "0:10000")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("the loop has 120 frames", r.stderr)
            self.assertIn("at least 416.667 s with a wind sea: /ocean with /ocean/repeat_time", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "bad")))
            # Each surface kind names its own key; with it the long shot runs (docs/scene.md, "Long shots").
            for kind, extra, key in (("height-field", {}, "with /surface/repeat_time"), ("ocean", {"ocean": {"resolution": 16, "size": 50}}, "with /ocean/repeat_time")):
                waves = {} if kind == "ocean" else {"waves": [{"period": 5, "amplitude": 0.3}]}
                other = write_scene(d, {"surface": {"kind": kind}, "animation": {"fps": 4}, **extra, **waves}, "long-" + kind + ".json")
                r = wave("run", other, "-o", os.path.join(d, "bad"), "--frames", "30:200")
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn("at least 50 s " + key, r.stderr)
                self.assertFalse(os.path.exists(os.path.join(d, "bad")))
            long_shot = write_scene(d, {"surface": {"kind": "ocean"}, "ocean": {"resolution": 16, "size": 50, "repeat_time": 50},
                                        "animation": {"fps": 4}}, "long.json")
            r = wave("run", long_shot, "-o", os.path.join(d, "long"), "--frames", "190:200", "--form", "files", "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(len(os.listdir(os.path.join(d, "long", "frames"))), 10)


class Codecs(unittest.TestCase):
    """The codec rule and EXT_meshopt_compression as users meet them (docs/export.md,
    "Meshopt compression" and "Which codec")."""

    def against(self, out, reference):
        r = wave("inspect", out, "--against", reference, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_a_real_coast_by_default_keeps_its_heights(self):
        # Breaking Okushiri (2.2 km, 151 k vertices) as a user runs it: its plain output
        # is over 32 MB, so meshopt frames, every height within 1 mm of the float run's
        # (measured: 7.6 µm), no terraces (Draco's one step for all axes left 22
        # distinct heights in a frame; at least 10 000 here), horizontal error under 1 %
        # of the shortest edge at each vertex; the files validate and inspect finds them
        # whole.
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(EXAMPLES, "breaking-okushiri.json")
            r = wave("run", scene, "-o", os.path.join(d, "default"), "--frames", "0:2", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(json.loads(r.stdout)["surface"]["codec"], "meshopt")
            r = wave("run", scene, "-o", os.path.join(d, "float"), "--frames", "0:2", "-q", "--no-draco", "--no-quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            validate_gltf(self, os.path.join(d, "default", "frames", "frame-0001.glb"))
            doc, _ = read_glb(os.path.join(d, "default", "frames", "frame-0001.glb"))
            self.assertEqual(doc["extensionsRequired"], ["EXT_meshopt_compression"])
            c = self.against(os.path.join(d, "default"), os.path.join(d, "float"))
            self.assertEqual(c["frames"], 2)
            self.assertLessEqual(c["height_error_m"], 1e-3)
            self.assertGreaterEqual(c["fewest_distinct_heights"], 10000)
            self.assertLess(c["horizontal_error_per_edge"], 0.01)
            self.assertLessEqual(c["skirt_height_error_m"], 1e-3)
            sizes = [sum(p.stat().st_size for p in pathlib.Path(d, out, "frames").iterdir()) for out in ("default", "float")]
            self.assertLess(sizes[0], 0.65 * sizes[1])
            r = wave("validate", scene, "--json")
            self.assertEqual(json.loads(r.stdout)["estimate"]["codec"], "meshopt")

    def test_the_codec_rule_and_its_overrides(self):
        # auto: plain floats for a small output, meshopt above 32 MB; --codec, --no-draco
        # and the scene's key override it; a scene naming a codec twice is refused.
        with tempfile.TemporaryDirectory() as d:
            small = write_scene(d, {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 4},
                                    "fronts": {"step": 1.6, "split_distance": 4.8}, "surface": {"far_field": False},
                                    "animation": {"fps": 4}}, "small.json")
            cases = [((small,), "none"), ((small, "--codec", "meshopt"), "meshopt"), ((), "quantize"),
                     ((os.path.join(EXAMPLES, "gonzato-bay.json"),), "meshopt"),
                     ((os.path.join(EXAMPLES, "gonzato-bay.json"), "--no-draco"), "none"),
                     ((os.path.join(EXAMPLES, "gonzato-bay.json"), "--codec", "draco"), "draco")]
            for k, (args, codec) in enumerate(cases):
                r = wave("run", *args, "-o", os.path.join(d, str(k)), "--frames", "0:1", "--json")
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertEqual(json.loads(r.stdout)["surface"]["codec"], codec, args)
            bad = write_scene(d, {"waves": [{"period": 5}], "outputs": {"codec": "meshopt", "draco": True}}, "bad.json")
            r = wave("run", bad, "-o", os.path.join(d, "bad"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("/outputs/codec", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "bad")))

    def test_draco_says_what_it_loses_and_inspect_matches_its_order(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(EXAMPLES, "breaking-okushiri.json")
            r = wave("run", scene, "-o", os.path.join(d, "draco"), "--frames", "0:1", "--draco")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("note: Draco puts positions on a 0.125 m lattice", r.stderr)
            self.assertEqual(wave("run", scene, "-o", os.path.join(d, "float"), "--frames", "0:1", "-q", "--codec", "none").returncode, 0)
            c = self.against(os.path.join(d, "draco"), os.path.join(d, "float"))  # Draco's own point order, matched
            # Half the domain's 0.125 m step, half the skirt's coarser one at its seam (measured 0.25 m).
            self.assertLessEqual(c["height_error_m"], 0.5)
            self.assertGreater(c["height_error_m"], 0.05)
            self.assertLess(c["fewest_distinct_heights"], 100)  # the terraces (measured: 22)

    def test_a_hostile_meshopt_stream_is_refused_naming_the_file(self):
        # A frame whose compressed positions are cut short: convert and inspect say so
        # (exit 2, the file and the view named) and write nothing.
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "m")
            self.assertEqual(wave("run", "-o", out, "--form", "files", "--frames", "0:1", "--codec", "meshopt", "-q").returncode, 0)
            frame = os.path.join(out, "frames", "frame-0000.glb")
            doc, binary = read_glb(frame)
            view = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]["bufferView"]
            doc["bufferViews"][view]["extensions"]["EXT_meshopt_compression"]["byteLength"] //= 3
            text = json.dumps(doc).encode()
            text += b" " * ((4 - len(text) % 4) % 4)
            glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(binary)) + struct.pack("<I4s", len(text), b"JSON") + text
            glb += struct.pack("<I4s", len(binary), b"BIN\0") + binary
            bad = os.path.join(d, "bad.glb")
            with open(bad, "wb") as f:
                f.write(glb)
            for args in (("convert", bad, "-o", os.path.join(d, "c")), ("inspect", bad)):
                r = wave(*args)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn(bad, r.stderr)
                self.assertIn("bufferView %d (EXT_meshopt_compression)" % view, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "c")))


class WindWaves(unittest.TestCase):
    """Tessendorf's FFT ocean as a surface of its own and superposed on the traced swell."""
    SMALL_OCEAN = {"surface": {"kind": "ocean"},
                   "ocean": {"resolution": 32, "size": 100, "wind_speed": 15, "repeat_time": 2, "choppiness": 4,
                             "small_wave_cutoff": 0.2},
                   "outputs": {"attributes": "named"}, "animation": {"fps": 8}}

    def write(self, d, doc, name="s.json"):
        path = os.path.join(d, name)
        with open(path, "w") as f:
            json.dump(doc, f)
        return path

    def example_frames(self, name, out):
        """The first two frames of an example: its report."""
        r = wave("run", os.path.join(EXAMPLES, name), "-o", out, "--frames", "0:2", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_refined_surfaces_validate(self):
        # OpenSubdiv on the default bay's water mesh, moved by Gonzato's profile and by
        # Jeschke's breakers: Loop level 1 has four times the triangles; the files
        # validate and carry the refined mesh.
        with tempfile.TemporaryDirectory() as d:
            for extra in [{}, {"breakers": "jeschke"}]:
                scene = dict(OutputForms.SMALL, refine={"scheme": "loop", "level": 1}, **extra)
                path, out = os.path.join(d, "r.json"), os.path.join(d, "out")
                with open(path, "w") as f:
                    json.dump(scene, f)
                r = wave("run", path, "-o", out, "--frames", "0:2", "--fps", "4", "--json")
                self.assertEqual(r.returncode, 0, r.stderr)
                report = json.loads(r.stdout)
                self.assertEqual(report["surface"]["refine"]["level"], 1)
                coarse = report["surface"]["refine"]["coarse_vertices"]
                coarse_triangles = report["surface"]["water_mesh"]["triangles"] + report["surface"]["far_field"]["triangles"]
                self.assertEqual(report["surface"]["triangles"], 4 * coarse_triangles)
                self.assertGreater(report["surface"]["vertices"], 3 * coarse)
                glb = os.path.join(out, "animation-frames-0-2.glb")
                validate_gltf(self, glb)
                doc, _ = read_glb(glb)
                self.assertEqual(doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]["count"],
                                 report["surface"]["vertices"])
                shutil.rmtree(out)

    def test_preview_renders_pngs_and_refuses_bad_input(self):
        with tempfile.TemporaryDirectory() as d:
            png = os.path.join(d, "sunset.png")
            r = wave("preview", os.path.join(EXAMPLES, "sunset.json"), "-o", png, "--width", "320", "--height", "160")
            self.assertEqual(r.returncode, 0, r.stderr)
            data = pathlib.Path(png).read_bytes()
            self.assertEqual(data[:8], b"\x89PNG\r\n\x1a\n")
            self.assertEqual(struct.unpack(">II", data[16:24]), (320, 160))  # IHDR width, height
            # wave run --preview: a contact sheet of four frames beside the export.
            out = os.path.join(d, "run")
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(dict(OutputForms.SMALL, preview={"image": [200, 100]}), f)
            r = wave("run", scene, "-o", out, "--fps", "2", "--preview", "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            sheet = pathlib.Path(out, "preview.png").read_bytes()
            self.assertEqual(struct.unpack(">II", sheet[16:24]), (200, 100))  # 2 × 2 frames of 100 × 50
            # Bad input: exit 2, the value named, no file.
            bad = os.path.join(d, "bad.json")
            with open(bad, "w") as f:
                json.dump(dict(OutputForms.SMALL, preview={"vertical_fov_degrees": 200}), f)
            r = wave("preview", bad, "-o", os.path.join(d, "bad.png"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("/preview/vertical_fov_degrees", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "bad.png")))

    def test_breaking_examples(self):
        # Jeschke's breakers parametrised from the traced rays: the planar beach breaks
        # in one band (H = γh), Okushiri in many places; files validate, foam present.
        for name, types in [("breaking-beach.json", {"plunging", "spilling"}), ("breaking-okushiri.json", {"plunging", "spilling"})]:
            with tempfile.TemporaryDirectory() as d:
                report = self.example_frames(name, d)
                b = report["surface"]["breakers"]
                self.assertEqual(b["model"], "jeschke")
                self.assertGreater(b["breaking_rays"], 0.3 * b["rays"])
                self.assertLessEqual(set(b["breaker_types"]), types | {"collapsing", "surging"})
                self.assertGreater(b["break_depth_m"][1], 0.5)
                # The beach: quantised morph targets (Blender 3.4 imports them); Okushiri:
                # meshopt frames (its plain output is over 32 MB: docs/export.md, "Which codec").
                frame = os.path.join(d, "animation-frames-0-2.glb" if name == "breaking-beach.json" else "frames/frame-0001.glb")
                validate_gltf(self, frame)
                doc, _ = read_glb(frame)
                self.assertIn("KHR_mesh_quantization" if name == "breaking-beach.json" else "EXT_meshopt_compression",
                              doc["extensionsRequired"])
                self.assertEqual(report["surface"]["codec"], "quantize" if name == "breaking-beach.json" else "meshopt")

    def test_open_ocean_example(self):
        # Two frames of the 512² gale: the patch, the analytic significant height, valid files.
        with tempfile.TemporaryDirectory() as d:
            report = self.example_frames("open-ocean.json", d)
            self.assertEqual(report["surface"]["kind"], "ocean")
            # The patch, and the skirt that carries it to the horizon (60 km: 2000 × the
            # camera's 30 m; docs/far-field.md, the open ocean to the horizon).
            skirt = report["surface"]["far_field"]
            self.assertEqual(skirt["distance_m"], 60000.0)
            self.assertGreater(skirt["vertices"], 10000)
            self.assertEqual(report["surface"]["vertices"], 513 * 513 + skirt["vertices"])
            self.assertEqual(report["surface"]["triangles"], 2 * 512 * 512 + skirt["triangles"])
            self.assertEqual(report["surface"]["loop_frames"], 160)  # 20 s at 8 fps
            # Phillips with the default A = α/2π: variance A π L²/2, L = V²/g (Hs 17.6 m at
            # 31 m/s); the lattice and the 0.5 m cutoff keep it within 5 %.
            L = 31.0 ** 2 / 9.81
            hs = 4 * (8.1e-3 / (2 * 3.141592653589793) * 3.141592653589793 * L * L / 2) ** 0.5
            self.assertAlmostEqual(report["surface"]["wind_sea"]["significant_height_m"] / hs, 1.0, delta=0.05)
            self.assertNotIn("isobaths.json", report["outputs"])
            # One animated .glb (scale-switched nodes, Draco): a slice of it here.
            self.assertEqual(sorted(os.listdir(d)), ["animation-frames-0-2.glb", "report-frames-0-2.json", "surface-frame-0000.obj",
                                                     "whitewater"])
            validate_gltf(self, os.path.join(d, "animation-frames-0-2.glb"))
            # The gale's whitecaps throw whitewater (/whitewater): a POINTS file per frame.
            self.assertEqual(sorted(os.listdir(os.path.join(d, "whitewater"))), ["whitewater-0000.glb", "whitewater-0001.glb"])
            doc, _ = read_glb(os.path.join(d, "whitewater", "whitewater-0001.glb"))
            self.assertGreater(doc["scenes"][0]["extras"]["libwave_whitewater"]["points"], 50000)

    def test_small_ocean_morph_foam_and_tiling(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", self.write(d, self.SMALL_OCEAN), "-o", out, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            self.assertEqual(report["surface"]["frames"], 16)
            glb = os.path.join(out, "animation.glb")
            validate_gltf(self, glb)
            doc, binary = read_glb(glb)
            prim = doc["meshes"][0]["primitives"][0]
            self.assertEqual(len(prim["targets"]), 16)
            foam = floats(doc, binary, prim["attributes"]["_FOAM"])
            peak = 0.0
            for target in prim["targets"]:
                frame = [b + t for b, t in zip(foam, floats(doc, binary, target["_FOAM"]))]
                self.assertGreaterEqual(min(frame), -1e-6)
                self.assertLessEqual(max(frame), 1 + 1e-6)
                peak = max(peak, max(frame))
            self.assertGreater(peak, 0.5)  # λ = 4 folds the crests
            # TEXCOORD_0 spans the patch exactly, so a texture tiles with the water; the
            # skirt round it (the patch's 33² vertices first) runs on beyond [0, 1].
            uv = floats(doc, binary, prim["attributes"]["TEXCOORD_0"])
            self.assertEqual((min(uv[0:2 * 33 * 33:2]), max(uv[0:2 * 33 * 33:2])), (0.0, 1.0))
            self.assertLess(min(uv[0::2]), -10.0)
            self.assertGreater(max(uv[0::2]), 10.0)
            # Where the skirt meets the patch the two are one surface: the patch's border
            # vertices are the skirt's (no second copy at the seam, no tile edge).
            position = floats(doc, binary, prim["attributes"]["POSITION"])
            rest = {(round(uv[2 * v], 6), round(uv[2 * v + 1], 6)) for v in range(len(uv) // 2)}
            self.assertEqual(len(rest), len(uv) // 2)
            self.assertEqual(len(position) // 3, len(uv) // 2)

    @same_bytes_test
    def test_ocean_is_identical_with_one_and_two_threads(self):
        with tempfile.TemporaryDirectory() as d:
            scene = self.write(d, self.SMALL_OCEAN)
            a, b = os.path.join(d, "a"), os.path.join(d, "b")
            self.assertEqual(wave("run", scene, "--threads", "1", "-o", a, "-q").returncode, 0)
            self.assertEqual(wave("run", scene, "--threads", "2", "-o", b, "-q").returncode, 0)
            self.assertEqual(pathlib.Path(a, "animation.glb").read_bytes(), pathlib.Path(b, "animation.glb").read_bytes())

    def test_coast_with_wind_waves_example(self):
        with tempfile.TemporaryDirectory() as d:
            report = self.example_frames("coast-with-wind-waves.json", d)
            self.assertEqual(report["surface"]["kind"], "ray-strips")
            self.assertEqual(report["surface"]["loop_period_s"], 24.0)  # 2 swell periods: the multiple nearest 20 s
            self.assertIn("wind_sea", report["surface"])
            self.assertGreater(report["trace"]["rays_aground"], 100)
            for name in sorted(os.listdir(os.path.join(d, "frames"))):
                validate_gltf(self, os.path.join(d, "frames", name))

    def test_bad_ocean_scenes_exit_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            ocean = lambda **o: {"surface": {"kind": "ocean"}, "ocean": o}
            cases = [
                (ocean(resolution=100), "/ocean/resolution: expected a power of two"),
                (ocean(wind_speed=0), "/ocean/wind_speed"),
                (ocean(repeat_time=0.01), "shorter than one frame"),
                (ocean(size=50, small_wave_cutoff=80), "/ocean/small_wave_cutoff: the cutoff 80 m is not smaller than the patch"),
                (ocean(spectrum="tma"), "/ocean/depth: the TMA spectrum needs a finite water depth"),
                (ocean(spectrum="bretschneider"), "jonswap, phillips, pierson-moskowitz, tma"),
                ({"surface": {"kind": "ocean"}, "waves": [{"period": 5}]}, "/waves: not for the open-ocean patch"),
                ({"waves": [{"period": 5}], "ocean": {"repeat_time": 12}}, "not a whole multiple of the swell's loop (5 s)"),
                ({"waves": [{"period": 5}], "gerstner": [{"wavelength": -1}]}, "/gerstner/0/wavelength"),
                ({"waves": [{"period": 5}], "shade": {"fold_softness": 0}}, "/shade/fold_softness"),
            ]
            for doc, part in cases:
                r = wave("run", self.write(d, doc, "bad.json"), "-o", out)
                self.assertEqual(r.returncode, 2, f"{doc}: {r.stderr}")
                self.assertTrue(r.stderr.startswith("error: "))
                self.assertIn(part, r.stderr, doc)
                self.assertFalse(os.path.exists(out), doc)
            r = wave("trace", self.write(d, self.SMALL_OCEAN), "--json")
            self.assertEqual(r.returncode, 2)
            self.assertIn("traces no rays", r.stderr)


def read_png16(path):
    """(width, height, rows of ints) of a 16-bit greyscale PNG (scripts/png_read.py:
    zlib and the five filters by hand, independent of the writer)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
    from png_read import read_png
    with open(path, "rb") as f:
        assert f.read(25)[24] == 16  # IHDR's bit depth
    width, height, channels, rows = read_png(path)
    assert channels == 1
    return width, height, rows


class Underwater(unittest.TestCase):
    """/underwater: a caustic map per frame beside the animation (docs/underwater.md)."""
    # A 10 m pool, 3 m deep at y = 0 to 6 m at y = 10, under 1 s waves 4 cm high: their
    # crests (a k² = 0.64 /m) focus sunlight n / ((n − 1) a k²) ≈ 6 m down.
    POOL = {"seafloor": {"source": "pool.asc"}, "waves": [{"period": 1.0, "amplitude": 0.04, "direction": [0, 1]}],
            "trace": {"ray_spacing": 0.1}, "preview": {"sun": {"elevation_degrees": 60, "azimuth_degrees": 100}},
            "underwater": {"map_size": 96, "water_type": "clear-ocean"}, "animation": {"fps": 10}}

    def write(self, d, doc, name="s.json"):
        with open(os.path.join(d, "pool.asc"), "w") as f:  # ESRI ASCII grid, first row at the top
            f.write("ncols 21\nnrows 21\nxllcorner 0\nyllcorner 0\ncellsize 0.5\n")
            for j in range(21):
                f.write(" ".join(["%.2f" % (-3.0 - 0.15 * (20 - j))] * 21) + "\n")
        path = os.path.join(d, name)
        with open(path, "w") as f:
            json.dump(doc, f)
        return path

    def test_a_map_per_frame_named_on_the_seafloor_and_looping(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", self.write(d, self.POOL), "-o", out, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            frames = report["surface"]["frames"]
            self.assertEqual(frames, 10)
            self.assertEqual(report["underwater"]["map_size"], [96, 96])
            self.assertEqual(report["underwater"]["attenuation_per_m"], 0.03)  # clear-ocean
            names = sorted(os.listdir(os.path.join(out, "caustics")))
            self.assertEqual(names, ["caustics-%04d.png" % f for f in range(frames)])
            glb = os.path.join(out, "animation.glb")
            validate_gltf(self, glb)
            doc, binary = read_glb(glb)
            floor = next(m for m in doc["meshes"] if m["name"] == "seafloor")["primitives"][0]
            extras = doc["materials"][floor["material"]]["extras"]["libwave_caustics"]
            self.assertEqual(extras["images"], "caustics/caustics-%04d.png")
            self.assertEqual((extras["frames"], extras["fps"], extras["texCoord"], extras["full_scale"]), (frames, 10.0, 0, 4.0))
            uv = floats(doc, binary, floor["attributes"]["TEXCOORD_0"])
            self.assertAlmostEqual(min(uv), 0.0, places=6)
            self.assertAlmostEqual(max(uv), 1.0, places=6)
            maps = []
            for f in range(frames):
                width, height, rows = read_png16(os.path.join(out, "caustics", names[f]))
                self.assertEqual((width, height), (96, 96))
                maps.append([v * 4.0 / 65535 for row in rows for v in row])
            # Light reaches the floor (clear water, sun at 60°), is focused into lines by
            # the crests and moves with them.
            first = maps[0]
            lit = [v for v in first if v > 0]
            self.assertGreater(len(lit), 0.8 * len(first))
            mean = sum(lit) / len(lit)
            self.assertGreater(mean, 0.5)
            self.assertGreater(max(first), 4.0 * mean)
            change = lambda a, b: sum(abs(x - y) for x, y in zip(a, b)) / len(a)
            step = change(maps[0], maps[1])
            self.assertGreater(change(maps[0], maps[frames // 2]), 0.1 * mean)
            # The loop closes: the last frame leads into the first as any frame into the next.
            self.assertLess(change(maps[-1], maps[0]), 1.5 * step)
            self.assertGreater(change(maps[-1], maps[0]), 0.5 * step)

    def test_a_sunbeam_volume_per_frame_named_on_the_seafloor(self):
        with tempfile.TemporaryDirectory() as d:
            out, again = os.path.join(d, "out"), os.path.join(d, "again")
            doc = dict(self.POOL, underwater=dict(self.POOL["underwater"], caustics=False, sunbeams={"voxels": [20, 24, 10]}))
            r = wave("run", self.write(d, doc), "-o", out, "--json", "--frames", "0:3")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            u = report["underwater"]
            self.assertEqual(u["sunbeam_volumes"], "sunbeams/sunbeams-%04d.vdb")
            self.assertEqual(u["voxels"], [20, 24, 10])
            self.assertAlmostEqual(u["volume_bottom_m"], -6.0)  # the pool's deepest point: clear water is still lit there
            self.assertAlmostEqual(u["voxel_size_m"][2], 0.6)
            self.assertNotIn("caustic_maps", u)
            self.assertFalse(os.path.exists(os.path.join(out, "caustics")))
            names = sorted(os.listdir(os.path.join(out, "sunbeams")))
            self.assertEqual(names, ["sunbeams-%04d.vdb" % f for f in range(3)])
            sizes = []
            for name in names:
                with open(os.path.join(out, "sunbeams", name), "rb") as f:
                    data = f.read()
                self.assertEqual(data[:8], bytes.fromhex("2042445600000000"))  # OpenVDB's magic number
                self.assertIn(b"sunlight", data)
                sizes.append(len(data))
            self.assertGreater(min(sizes), 1000)
            glb = os.path.join(out, "animation-frames-0-3.glb")
            validate_gltf(self, glb)
            doc_, _ = read_glb(glb)
            floor = next(m for m in doc_["meshes"] if m["name"] == "seafloor")["primitives"][0]
            extras = doc_["materials"][floor["material"]]["extras"]
            self.assertNotIn("libwave_caustics", extras)
            beams = extras["libwave_sunbeams"]
            self.assertEqual((beams["volumes"], beams["frames"], beams["fps"], beams["grid"], beams["attenuation"]),
                             ("sunbeams/sunbeams-%04d.vdb", 10, 10.0, "sunlight", 0.03))
            # The beam refracted from a sun 60° high: down (glTF's −y), at sin θt = cos 60° / 1.33.
            dx, dy, dz = beams["direction"]
            self.assertAlmostEqual(dx * dx + dy * dy + dz * dz, 1.0, places=9)
            self.assertAlmostEqual(math.sqrt(dx * dx + dz * dz), 0.5 / 1.33, places=9)
            self.assertLess(dy, 0.0)
            # The same volumes, byte for byte, on another run (no random archive identifier).
            self.assertEqual(wave("run", self.write(d, doc), "-o", again, "--frames", "0:3").returncode, 0)
            for name in names:
                with open(os.path.join(out, "sunbeams", name), "rb") as a, open(os.path.join(again, "sunbeams", name), "rb") as b:
                    self.assertEqual(a.read(), b.read(), name)

    def test_files_form_lists_each_frames_map_with_its_frame(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            doc = dict(self.POOL, outputs={"form": "files"}, underwater=dict(self.POOL["underwater"], sunbeams={"voxels": [8, 8, 4]}))
            r = wave("run", self.write(d, doc), "-o", out, "--frames", "2:5")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "index.json")) as f:
                index = json.load(f)
            for entry in index["frames"]:
                listed = json.dumps(entry)
                self.assertIn("caustics/caustics-%04d.png" % entry["frame"], listed)
                self.assertIn("sunbeams/sunbeams-%04d.vdb" % entry["frame"], listed)
            self.assertEqual(sorted(os.listdir(os.path.join(out, "caustics"))), ["caustics-%04d.png" % f for f in (2, 3, 4)])
            self.assertEqual(sorted(os.listdir(os.path.join(out, "sunbeams"))), ["sunbeams-%04d.vdb" % f for f in (2, 3, 4)])

    def test_bad_underwater_scenes_exit_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            bay = lambda **u: dict(self.POOL, underwater=u)
            cases = [
                (bay(water_type="murky"), "/underwater/water_type"),
                (bay(water_type="ocean", attenuation=0.1), "/underwater/attenuation: give /underwater/water_type or"),
                (bay(map_size=0), "/underwater/map_size"),
                (bay(full_scale=-1), "/underwater/full_scale"),
                (bay(colour=True), "/underwater"),
                (bay(sunbeams="yes"), "/underwater/sunbeams: expected true, false or an object"),
                (bay(sunbeams={"voxels": [8, 8]}), "/underwater/sunbeams/voxels"),
                (bay(sunbeams={"voxels": [8, 0, 8]}), "/underwater/sunbeams/voxels/1"),
                (bay(sunbeams={"voxels": [8, 8, 2000]}), "/underwater/sunbeams/voxels/2"),
                (bay(sunbeams={"darkest": 1.5}), "/underwater/sunbeams/darkest"),
                (bay(sunbeams={"glow": 1}), "/underwater/sunbeams"),
                (bay(sunbeams={"voxels": [1024, 1024, 1024]}), "/underwater/sunbeams/voxels [1024, 1024, 1024] need about 17.18 GB"),
                (dict(self.POOL, preview={"sun": {"elevation_degrees": -5}}), "/preview/sun: caustics need the sun above the horizon"),
                ({"surface": {"kind": "ocean"}, "underwater": {}}, "/underwater: caustics fall on a seafloor: the ocean surface has none"),
            ]
            for doc, part in cases:
                r = wave("run", self.write(d, doc, "bad.json"), "-o", out)
                self.assertEqual(r.returncode, 2, f"{doc}: {r.stderr}")
                self.assertTrue(r.stderr.startswith("error: "))
                self.assertIn(part, r.stderr, doc)
                self.assertFalse(os.path.exists(out), doc)


class Whitewater(unittest.TestCase):
    """/whitewater: a POINTS .glb of spray, foam and bubbles per frame (docs/whitewater.md)."""
    BEACH = {"seafloor": {"source": "planar-beach"}, "isobaths": {"spacing": 0.5},
             "waves": [{"period": 8.0, "amplitude": 0.4, "direction": [0.34, 0.94]}], "trace": {"ray_spacing": 4.0},
             "breakers": "jeschke", "whitewater": True, "animation": {"fps": 4}}

    def test_a_points_file_per_frame_valid_and_the_same_from_a_slice(self):
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, dict(self.BEACH, outputs={"form": "files"}))
            whole, alone = os.path.join(d, "whole"), os.path.join(d, "alone")
            r = wave("run", scene, "-o", whole, "--frames", "0:3", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)["whitewater"]
            self.assertEqual(report["sources"], ["breakers"])
            self.assertGreater(report["breaker_events"], 100)
            names = sorted(os.listdir(os.path.join(whole, "whitewater")))
            self.assertEqual(names, ["whitewater-%04d.glb" % f for f in range(3)])
            path = os.path.join(whole, "whitewater", "whitewater-0002.glb")
            validate_gltf(self, path)
            doc, binary = read_glb(path)
            prim = doc["meshes"][0]["primitives"][0]
            self.assertEqual(prim["mode"], 0)  # POINTS
            n = doc["accessors"][prim["attributes"]["POSITION"]]["count"]
            self.assertGreater(n, 1000)
            kinds = floats(doc, binary, prim["attributes"]["_KIND"])
            self.assertEqual(set(kinds), {0.0, 1.0, 2.0})  # spray, foam and bubbles
            # The index lists each frame's points with the frame's own files.
            with open(os.path.join(whole, "index.json")) as f:
                index = json.load(f)
            self.assertIn("whitewater/whitewater-0002.glb", [c["file"] for c in index["frames"][2]["content"]])
            # A frame computed alone (a farm's slice) is the same frame, byte for byte.
            r = wave("run", scene, "-o", alone, "--frames", "2:3")
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(path, "rb") as a, open(os.path.join(alone, "whitewater", "whitewater-0002.glb"), "rb") as b:
                self.assertEqual(a.read(), b.read())

    def test_gonzatos_breakers_throw_it_too(self):
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, {k: v for k, v in self.BEACH.items() if k != "breakers"})
            out = os.path.join(d, "out")
            r = wave("run", scene, "-o", out, "--frames", "0:2", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertGreater(json.loads(r.stdout)["whitewater"]["breaker_events"], 100)
            doc, binary = read_glb(os.path.join(out, "whitewater", "whitewater-0001.glb"))
            prim = doc["meshes"][0]["primitives"][0]
            self.assertGreater(doc["accessors"][prim["attributes"]["POSITION"]]["count"], 1000)

    def test_bad_options_name_the_key(self):
        with tempfile.TemporaryDirectory() as d:
            for doc, key in ((dict(self.BEACH, whitewater={"spray_density": -1}), "/whitewater/spray_density"),
                             (dict(self.BEACH, whitewater={"foam_lace": 2}), "/whitewater/foam_lace"),
                             # 10⁴ foam particles per m of crest living 10 min: refused before any frame.
                             (dict(self.BEACH, whitewater={"foam_density": 10000, "foam_life": 600}), "/whitewater/max_points"),
                             (dict(self.BEACH, whitewater={"spray": False, "foam": False, "bubbles": False}), "/whitewater"),
                             ({"seafloor": {"source": "planar-beach"}, "waves": self.BEACH["waves"], "surface": {"kind": "height-field"},
                               "whitewater": True}, "/whitewater")):
                out = os.path.join(d, "out")
                r = wave("run", write_scene(d, doc), "-o", out)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn(key, r.stderr)
                self.assertFalse(os.path.exists(out), "no partial output")


class Inspect(unittest.TestCase):
    """`wave inspect` on outputs, and the water mesh it checks (docs/inspect.md)."""

    def inspect(self, path, *extra):
        r = wave("inspect", path, "--json", *extra)
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)

    def test_wave_field_surface_on_the_water_mesh_is_clean(self):
        # The bay as a wave-field surface: one loop along the border and the shore, no
        # fold, slivers or unreferenced vertex in any frame, vertices at most as fast as
        # the wave (5 s swell in <= 10 m of water: C < 10 m/s; they only rise and fall).
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump({"seafloor": {"source": "gonzato-bay"}, "waves": [{"period": 5, "amplitude": 0.3}],
                           "surface": {"kind": "wave-field"}, "animation": {"fps": 4}}, f)
            out = os.path.join(d, "out")
            self.assertEqual(wave("run", scene, "-q", "-o", out).returncode, 0)
            m = self.inspect(out)
            self.assertEqual(m["frames"], 20)
            self.assertEqual(len(m["per_frame"]), 20)
            self.assertEqual((m["unreferenced_vertices"], m["non_manifold_edges"]), (0, 0))
            self.assertEqual(len(m["boundary"]["loops"]), 1)
            # The far field's skirt reaches 2000 camera heights (40 m) out on the three
            # wet sides; the beach side ends at the domain (y = 90).
            R = 80000.0
            self.assertEqual(m["boundary"]["border"], [-R, -R, 100.0 + R, 90.0])
            worst = m["worst"]
            self.assertEqual((worst["facing_down"], worst["folds"], worst["degenerate"]), (0, 0, 0))
            # The water mesh aims at 20°, the skirt too; a few skirt triangles on the water
            # mesh's border edges, which the skirt shares and never splits, stay just below 15°.
            self.assertGreaterEqual(worst["smallest_angle_deg"], 14.0)
            self.assertLessEqual(worst["slivers"], 5)
            self.assertLess(worst["max_speed_m_s"], 10.0)
            # Text: the same numbers for a person.
            r = wave("inspect", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("0 folds", r.stdout)
            self.assertIn("1 loop(s)", r.stdout)

    def test_the_examples_exported_surfaces_never_fold(self):
        # The default (the water mesh, untangled every frame): in every frame of the bay,
        # the island and the breaking beach, no triangle faces down but a breaking crest's
        # lip, every vertex is used, every edge has at most two triangles. (The same
        # scenes on their traced strips: 225, 11 537 and 1 509 folds; docs/inspect.md.)
        with tempfile.TemporaryDirectory() as d:
            for example, fps in [("gonzato-bay.json", 4), ("gonzato-island.json", 2), ("breaking-beach.json", 1),
                                 ("breaking-okushiri.json", 1)]:
                out = os.path.join(d, example)
                r = wave("run", os.path.join(EXAMPLES, example), "-q", "-o", out, "--fps", str(fps), "--no-draco", "--no-quantize")
                self.assertEqual(r.returncode, 0, r.stderr)
                # The breaking beach's plunging crests overturn on its surf-zone mesh: its
                # scene tells the lips its breakers draw (--scene) from folds.
                curl = example == "breaking-beach.json"
                m = self.inspect(out, *(("--scene", os.path.join(EXAMPLES, example)) if curl else ()))
                self.assertGreater(m["frames"], 8, example)
                self.assertEqual((m["unreferenced_vertices"], m["non_manifold_edges"]), (0, 0), example)
                self.assertEqual([f["folds"] for f in m["per_frame"] if f["folds"]], [], example)
                if curl:
                    # Measured at 1 fps: lips in 7 of 24 frames (up to 18 triangles), 0
                    # folds; slivers only on the lips; off them 14.6° at the least.
                    self.assertGreater(m["worst"]["lips"], 0, example)
                    self.assertEqual(m["worst"]["slivers"], m["worst"]["lip_slivers"], example)
                    self.assertGreaterEqual(m["worst"]["smallest_angle_off_lips_deg"], 14.0, example)
                    self.assertEqual(m["worst"]["long_edges"], 0, example)
                    self.assertEqual(m["boundary"]["shore_drift_m"], 0.0, example)
                    continue
                # Gonzato's sections pack no rest spacing below 0.6 (motion.min_packing), and
                # Jeschke's breakers take their tube's outer section (breakers.lip), which packs
                # none below 0.6 either: they lean and stand steep but do not turn over, so the
                # untangling frees no lip (UntangleOptions::lips_overturn). Eq. 7's curl,
                # smaller than the mesh, left ~300 slivers and ~600 triangles facing down a
                # frame on the bay, 100 and 285 on the island, and 8 and 24 edges over 3 × the
                # local spacing (2 fps); the beach's knife-thin tube 724 slivers, 1 592 facing
                # down and 92 long edges. Now none facing down, no slivers on the breaking
                # crests (the shore's band keeps 0.7 of its area: 4 and 4 at 0.3) and no edge
                # over 3 × the local spacing (2.79 ×, 2.91 × and 2.51 ×; 3.03 ×, 3.01 × and
                # 3.25 × before the shore band's stretch bound of 1.15 × and the skirt's sizes
                # read no shallower than the breaking depth). Breaking Okushiri: 2.69 ×
                # (3.11 × before the skirt's sizes grew from the breakers' band along the
                # border, 3.70 × with that alone, before the border's spacing was linear).
                self.assertEqual(m["worst"]["lips"], 0, example)
                self.assertEqual(m["worst"]["long_edges"], 0, example)
                # No triangle under 15° anywhere, the issue's bound, on the lips, the shore
                # and the far-field skirt included: 16.1°, 16.1°, 18.5° and 20.5° measured. Before
                # the field bridged the tears between layers of rays (fill_strip_gaps), the
                # island kept a triangle of 12.1° by the domain's side, whose vertices moved
                # half a wave apart; before the skirt's equilateral apexes and its cuts'
                # first steps, the bay's corners where the shore meets the domain's sides
                # held triangles of 11–14° (10, 6 and 2 slivers off the lips, 9.6°–12.0°,
                # with eq. 7's lips and the tube).
                self.assertEqual(m["worst"]["slivers"], 0, example)
                self.assertGreaterEqual(m["worst"]["smallest_angle_deg"], 15.0, example)
                # The water's edge holds on the shoreline in every frame, and no triangle
                # turns over across it (inspect counts those as folds, foamy or not): before,
                # 68 and 28 did on the bay's and the island's shores, and the edge drifted up
                # to 9 and 55 cm. The breaking beach's shore is its domain's side.
                if example != "breaking-beach.json":
                    self.assertGreater(m["boundary"]["shore_vertices"], 200, example)
                self.assertEqual(m["boundary"]["shore_drift_m"], 0.0, example)
                islands = {"gonzato-island.json": 1, "breaking-okushiri.json": 1}.get(example, 0)
                self.assertEqual(len(m["boundary"]["loops"]), 1 + islands, example)
            # Witness: the paper's tube ("lip": "tube") on the same beach overturns, and its
            # knife-thin tip is where inspect finds the slivers (724 a frame, 92 long edges).
            with open(os.path.join(EXAMPLES, "breaking-beach.json")) as f:
                doc = json.load(f)
            doc["breakers"]["lip"] = "tube"
            doc.pop("surface", None)  # on the ordinary mesh (W/16): the tube is smaller than it
            scene = os.path.join(d, "tube.json")
            with open(scene, "w") as f:
                json.dump(doc, f)
            r = wave("run", scene, "-q", "-o", os.path.join(d, "tube"), "--fps", "2", "--no-draco", "--no-quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            m = self.inspect(os.path.join(d, "tube"))
            self.assertGreater(m["worst"]["lips"], 500)
            self.assertGreater(m["worst"]["lip_slivers"], 300)
            self.assertGreater(m["worst"]["long_edges"], 30)
            # The skirt's sides stay on its far rectangle (12 km out: 2000 camera heights,
            # the example's camera 6 m up) and the beach side on the domain's border (no lip
            # hangs over it).
            R = 12000.0
            self.assertEqual(self.inspect(os.path.join(d, "gonzato-bay.json"))["boundary"]["border"], [-R, -R, 100.0 + R, 90.0])

    def test_breakers_on_the_water_mesh_leave_no_vertex_unused(self):
        # The breaking beach on the strips leaves vertices no triangle uses and a
        # sawtoothed side; on the water mesh every vertex is used and the sides are straight.
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(EXAMPLES, "breaking-beach.json")) as f:
                doc = json.load(f)
            doc["surface"] = {"water_mesh": {"vertices_per_wavelength": 8}}
            doc["outputs"] = {"form": "morph"}
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(doc, f)
            out = os.path.join(d, "out")
            r = wave("run", scene, "-q", "-o", out, "--fps", "2")
            self.assertEqual(r.returncode, 0, r.stderr)
            validate_gltf(self, os.path.join(out, "animation.glb"))
            m = self.inspect(os.path.join(out, "animation.glb"), "--sliver-angle", "10")
            self.assertEqual(m["options"]["sliver_angle_deg"], 10)
            self.assertEqual((m["unreferenced_vertices"], m["non_manifold_edges"]), (0, 0))
            self.assertEqual(len(m["boundary"]["loops"]), 1)
            loop = m["boundary"]["loops"][0]
            x0, y0, x1, y1 = m["boundary"]["border"]
            self.assertAlmostEqual(loop["length_m"], 2 * (x1 - x0 + y1 - y0), delta=1.0)  # the rectangle (shore at a side)
            bad = dict(doc, surface={"water_mesh": {"vertices_per_wavelength": 2}})
            with open(scene, "w") as f:
                json.dump(bad, f)
            r = wave("run", scene, "-q", "-o", out)
            self.assertEqual(r.returncode, 2)
            self.assertIn("/surface/water_mesh/vertices_per_wavelength", r.stderr)

    def test_gonzato_profile_on_the_water_mesh_folds_less_than_on_the_strips(self):
        # Gonzato's island: on the strips, rays crossing in the lee fold the surface by the
        # thousand; on the water mesh the strips' fields are resampled, every vertex used.
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(EXAMPLES, "gonzato-island.json")) as f:
                doc = json.load(f)
            worst = {}
            for mesh in [False, {"vertices_per_wavelength": 8}]:
                doc["surface"] = {"water_mesh": mesh, "far_field": False}  # the surfaces alone
                scene, out = os.path.join(d, "s.json"), os.path.join(d, "out-%s" % bool(mesh))
                with open(scene, "w") as f:
                    json.dump(doc, f)
                r = wave("run", scene, "-q", "-o", out, "--fps", "2")
                self.assertEqual(r.returncode, 0, r.stderr)
                m = self.inspect(out)
                worst[bool(mesh)] = m["worst"]
                if mesh:
                    self.assertEqual((m["unreferenced_vertices"], m["non_manifold_edges"]), (0, 0))
                    self.assertEqual(len(m["boundary"]["loops"]), 2)  # the border and the island's shore
                    self.assertEqual(m["boundary"]["loops"][0]["vertices_on_border"], m["boundary"]["loops"][0]["edges"])
            self.assertLess(worst[True]["folds"], worst[False]["folds"] / 10)
            self.assertLess(worst[True]["longest_edge_m"], worst[False]["longest_edge_m"] / 5)
            self.assertLessEqual(worst[True]["max_speed_m_s"], 1.05 * worst[False]["max_speed_m_s"])

    def test_traced_surfaces_move_no_faster_than_the_wave_frame_to_frame(self):
        # At the shipped 24 fps, chord speeds between consecutive frames: the untangling's
        # factors are continuous (its ramp; the lip's foam rising before the crest), so no
        # vertex outruns 1.5 × the celerity in the deepest water of the scene. Before the
        # ramp, vertices jumped metres between frames: 73 m/s on the bay, 68 on the island.
        for name, path in (("the old default bay", None), ("island", os.path.join(EXAMPLES, "gonzato-island.json"))):
            with self.subTest(scene=name), tempfile.TemporaryDirectory() as d:
                out = os.path.join(d, "out")
                r = wave("run", path or write_scene(d, OLD_DEFAULT), "-q", "-o", out, "--frames", "0:48", "--no-draco")
                self.assertEqual(r.returncode, 0, r.stderr)
                with open(os.path.join(out, "report-frames-0-48.json")) as f:
                    report = json.load(f)
                self.assertEqual(report["surface"]["fps"], 24.0)
                deepest = report["seafloor"]["depth_range_m"][1]
                c = wave("dispersion", "-T", "5", "-d", str(deepest), "--json")
                self.assertEqual(c.returncode, 0, c.stderr)
                celerity = json.loads(c.stdout)["celerity_m_per_s"]
                m = self.inspect(os.path.join(out, "animation-frames-0-48.glb"))
                worst = m["worst"]
                self.assertEqual(worst["folds"], 0)
                # Gonzato's sections, bounded in speed (1.5 c) and packing (0.6), keep every
                # vertex below the celerity of the deepest water; before the packing bound
                # the lips freed as their foam rose reached 1.8 × their own water's.
                self.assertLess(worst["max_speed_m_s"], celerity, "fastest vertex %d" % worst["fastest_vertex"])

    def test_scene_without_breakers_of_its_own_is_refused_naming_it(self):
        # --scene tells the lips a scene's breakers draw from folds: a scene whose motion
        # draws none (the open ocean) cannot, and says so (exit 2, nothing on stdout).
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            r = wave("run", "-q", "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            scene = os.path.join(EXAMPLES, "open-ocean.json")
            r = wave("inspect", out, "--scene", scene)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("open-ocean.json", r.stderr)
            self.assertIn("draws no lips", r.stderr)
            self.assertEqual(r.stdout, "")

    def test_bad_paths_exit_2_naming_them(self):
        with tempfile.TemporaryDirectory() as d:
            r = wave("inspect", os.path.join(d, "nowhere"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("nowhere", r.stderr)
            self.assertIn("no libwave output", wave("inspect", d).stderr)
            junk = os.path.join(d, "junk.glb")
            with open(junk, "wb") as f:
                f.write(b"glTF\x02\x00\x00\x00garbage")
            r = wave("inspect", junk)
            self.assertEqual(r.returncode, 2)
            self.assertIn("junk.glb", r.stderr)
            self.assertEqual(r.stdout, "")


class WaveField(unittest.TestCase):
    """The refraction-diffraction field: `wave field`, the wave-field surface, and the
    ray strips' amplitudes taken from it (docs/wave-field.md)."""

    def test_berkhoff_shoal_as_a_surface_and_a_geotiff(self):
        with tempfile.TemporaryDirectory() as d:
            r = wave("run", os.path.join(EXAMPLES, "berkhoff-shoal.json"), "-o", d, "--json", "--codec", "none")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            MainJob.check_animation(self, d, report)  # the Khronos glTF validator included
            self.assertEqual(report["surface"]["kind"], "wave-field")
            self.assertEqual(report["surface"]["frames"], 24)
            field = report["trace"]["fields"][0]
            self.assertAlmostEqual(field["incident_height_m"], 0.0464, delta=2e-4)
            lo, hi = report["surface"]["height_range_m"]
            self.assertLess(hi, 3.0 * 0.0464 / 2)  # the focus, H/H0 < 3: finite where rays cross
            tif, png = os.path.join(d, "f.tif"), os.path.join(d, "f.png")
            r = wave("field", os.path.join(EXAMPLES, "berkhoff-shoal.json"), "-o", tif, "--png", png, "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            summary = json.loads(r.stdout)
            self.assertGreater(summary["height_ratio_max"], 2.0)
            self.assertLess(summary["height_ratio_max"], 3.0)
            info = json.loads(subprocess.run(["gdalinfo", "-json", "-stats", tif], capture_output=True, text=True,
                                             check=True).stdout)
            self.assertEqual([b["description"] for b in info["bands"]], ["H/H0", "phase (rad)", "direction (degrees from +x)"])
            self.assertAlmostEqual(info["bands"][0]["maximum"], summary["height_ratio_max"], delta=1e-3)  # printed to 3 places
            self.assertLessEqual(info["bands"][1]["maximum"], math.pi + 1e-3)  # printed to 3 places
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_ray_strips_take_finite_amplitudes_from_the_field(self):
        # Gonzato's island: ray amplitudes spiked to +-2 m at the caustics and the edges
        # (the interior reaches 0.8 m); from the field they stay under 0.6 m.
        with tempfile.TemporaryDirectory() as d:
            island = os.path.join(EXAMPLES, "gonzato-island.json")
            r = wave("run", island, "-o", d, "--frames", "0:12", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            lo, hi = json.loads(r.stdout)["surface"]["height_range_m"]
            self.assertLess(max(-lo, hi), 0.6)
            with open(island) as f:
                scene = json.load(f)
            scene["field"] = {"amplitudes": "rays"}
            scene["surface"] = {"water_mesh": False}  # the spikes sit on the strips' own vertices
            path = os.path.join(d, "rays.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            r = wave("run", path, "-o", os.path.join(d, "rays"), "--frames", "0:12", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            lo, hi = json.loads(r.stdout)["surface"]["height_range_m"]
            self.assertGreater(max(-lo, hi), 1.0)

    def test_bad_field_requests_exit_2(self):
        with tempfile.TemporaryDirectory() as d:
            berkhoff = os.path.join(EXAMPLES, "berkhoff-shoal.json")
            for args, part in [(["field", berkhoff], "nothing to do"),
                               (["field", berkhoff, "--train", "1", "--json"], "--train 1"),
                               (["field", os.path.join(EXAMPLES, "open-ocean.json"), "--json"], "no seafloor"),
                               (["field", berkhoff, "-o", d], "a folder"),
                               (["trace", berkhoff, "--json"], "wave field")]:
                r = wave(*args)
                self.assertEqual(r.returncode, 2, args)
                self.assertIn(part, r.stderr)
            with open(berkhoff) as f:
                scene = json.load(f)
            scene["field"]["max_nodes"] = 1000
            path = os.path.join(d, "small.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            r = wave("field", path, "--json")
            self.assertEqual(r.returncode, 2)
            self.assertIn("/field/max_nodes", r.stderr)


class BlenderDelivery(unittest.TestCase):
    """What Debian's Blender 3.4 needs from a run: plain meshes on request (it has no Draco)."""

    def test_no_draco_overrides_the_scene(self):
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, {"name": "bay with Draco", "waves": [{"period": 5, "amplitude": 0.3}],
                                    "outputs": {"form": "files", "draco": True}})
            r = wave("run", scene, "-o", d, "--no-draco", "--frames", "0:2", "--json")
            self.assertEqual(r.returncode, 0, r.stderr)
            report = json.loads(r.stdout)
            self.assertFalse(report["surface"]["draco"])
            frame = next(f for f in report["outputs"] if f.endswith(".glb"))
            doc, _ = read_glb(os.path.join(d, frame))
            self.assertNotIn("KHR_draco_mesh_compression", doc.get("extensionsUsed", []))
            validate_gltf(self, os.path.join(d, frame))
            r = wave("run", "-o", os.path.join(d, "x"), "--draco", "--no-draco")
            self.assertEqual(r.returncode, 2)
            self.assertIn("excludes", r.stderr)

    def test_the_breaking_beach_imports_without_the_addon_and_quantisation_can_be_turned_off(self):
        # The flagship breaker example's default: one .glb of quantised morph targets
        # (Blender 3.4's own importer reads KHR_mesh_quantization, not Draco), with the
        # far field; --no-quantize gives floats, --draco Draco instead.
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(EXAMPLES, "breaking-beach.json")
            for extra, quantised, draco in [((), True, False), (("--no-quantize",), False, False), (("--draco",), False, True)]:
                out = os.path.join(d, "-".join(extra) or "default")
                r = wave("run", scene, "-o", out, "--frames", "0:3", "-q", *extra)
                self.assertEqual(r.returncode, 0, r.stderr)
                with open(os.path.join(out, "report-frames-0-3.json")) as f:
                    surface = json.load(f)["surface"]
                self.assertEqual((surface["form"], surface["quantized"], surface["draco"]), ("morph", quantised, draco), extra)
                self.assertIn("far_field", surface, extra)  # a Draco morph base keeps the skirt too
                validate_gltf(self, os.path.join(out, next(n for n in os.listdir(out) if n.endswith(".glb"))))
            r = wave("run", scene, "-o", os.path.join(d, "x"), "--quantize", "--no-quantize")
            self.assertEqual(r.returncode, 2)
            self.assertIn("excludes", r.stderr)

    def test_pc2_form_holds_every_frame(self):
        # The point cache equals the morph form's frames; the shading cache holds (reflect, refract, foam).
        with tempfile.TemporaryDirectory() as d:
            for form in ["pc2", "morph"]:
                r = wave("run", "-o", os.path.join(d, form), "--form", form, "--fps", "6", "-q", "--no-quantize")
                self.assertEqual(r.returncode, 0, r.stderr)
            data = pathlib.Path(d, "pc2", "animation.pc2").read_bytes()
            self.assertEqual(data[:12], b"POINTCACHE2\0")
            version, points, start, rate, samples = struct.unpack_from("<iiffi", data, 12)
            self.assertEqual((version, start, rate, samples), (1, 0.0, 1.0, 36))  # the default scene's 6 s loop at 6 fps
            self.assertEqual(len(data), 32 + 12 * points * samples)
            doc, binary = read_glb(os.path.join(d, "morph", "animation.glb"))
            prim = doc["meshes"][0]["primitives"][0]
            base = floats(doc, binary, prim["attributes"]["POSITION"])
            delta = floats(doc, binary, prim["targets"][7]["POSITION"])
            cache = struct.unpack_from(f"<{3 * points}f", data, 32 + 7 * 12 * points)
            for v in range(0, points, 997):  # glTF y up → z up: (x, y, z) → (x, −z, y)
                x, y, z = (base[3 * v + i] + delta[3 * v + i] for i in range(3))
                for got, want in zip(cache[3 * v:3 * v + 3], (x, -z, y)):
                    self.assertAlmostEqual(got, want, delta=1e-5)
            shading = pathlib.Path(d, "pc2", "animation-shading.pc2").read_bytes()
            self.assertEqual(len(shading), len(data))
            self.assertTrue(all(0.0 <= f <= 1.0 for f in struct.unpack_from("<300f", shading, 32)))
            validate_gltf(self, os.path.join(d, "pc2", "animation.glb"))


class CrashSafety(unittest.TestCase):
    """SIGKILL at random moments while `wave run` computes and writes: every file under
    its final name is complete (one of the two runs' versions, byte for byte), and the
    staging a killed run left is cleared by the next run."""

    def check_killed_runs(self, form, files_of, new_fps):
        with tempfile.TemporaryDirectory() as d:
            out, new = os.path.join(d, "out"), os.path.join(d, "new")
            base = ["run", "-q", "--form", form]
            self.assertEqual(wave(*base, "-o", out, "--fps", "12").returncode, 0)
            self.assertEqual(wave(*base, "-o", new, "--fps", new_fps).returncode, 0)
            old_files = files_of(out)
            new_files = files_of(new)
            rng = random.Random(1234)  # reproducible kill times
            for _ in range(6):
                p = subprocess.Popen([WAVE, *base, "-o", out, "--fps", new_fps], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                time.sleep(rng.uniform(0.05, 2.5))
                p.send_signal(signal.SIGKILL)
                p.wait()
                for name, data in files_of(out).items():
                    self.assertIn(data, (old_files.get(name), new_files.get(name)), name + ": truncated or mixed")
                for name in files_of(out):
                    if name.endswith(".glb"):
                        read_glb(os.path.join(out, name))  # the header's length matches the file
                if os.path.exists(os.path.join(out, "index.json")):  # every frame it lists is the one it checked
                    with open(os.path.join(out, "index.json")) as f:
                        Resume.assert_listed_files_intact(self, out, json.load(f))
            # The next run clears what killed runs left on this host and completes.
            self.assertEqual(wave(*base, "-o", out, "--fps", new_fps).returncode, 0)
            self.assertEqual([n for n in os.listdir(out) if n.startswith(".wave-staging-")], [])
            self.assertEqual(files_of(out), new_files)

    @staticmethod
    def final_files(root):
        """Every file under its final name (hidden temporaries are not outputs)."""
        found = {}
        for dirpath, dirnames, filenames in os.walk(root):
            dirnames[:] = [x for x in dirnames if not x.startswith(".")]
            for f in filenames:
                if not f.startswith("."):
                    path = os.path.join(dirpath, f)
                    found[os.path.relpath(path, root)] = pathlib.Path(path).read_bytes()
        return found

    def test_a_killed_convert_leaves_no_staging_past_the_next_command(self):
        """A SIGKILLed `wave convert` leaves its staging folder (the streamed frames); the
        next command on the folder removes it as it starts, even one that then fails on
        its input (exit 2): it used to go only when a later run published."""
        with tempfile.TemporaryDirectory() as d:
            src, out = os.path.join(d, "src"), os.path.join(d, "out")
            self.assertEqual(wave("run", "-q", "--form", "files", "--codec", "none", "-o", src).returncode, 0)
            os.makedirs(out)
            staged = lambda: [n for n in os.listdir(out) if n.startswith(".wave-staging-")]
            for command, args in ((["convert", os.path.join(src, "index.json"), "-o", out, "--form", "nodes"],
                                   ["convert", os.path.join(d, "missing.json"), "-o", out]),
                                  (["convert", os.path.join(src, "index.json"), "-o", out, "--form", "files"],
                                   ["merge", out])):
                p = subprocess.Popen([WAVE, *command], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                deadline = time.monotonic() + 60
                while not staged() and p.poll() is None and time.monotonic() < deadline:
                    time.sleep(0.002)
                p.send_signal(signal.SIGKILL)
                p.wait()
                self.assertEqual(p.returncode, -signal.SIGKILL, "killed before it finished")
                self.assertEqual(len(staged()), 1, "the killed convert's staging folder")
                r = wave(*args)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertEqual(staged(), [], f"wave {args[0]} that failed left the killed convert's staging")

    def test_sigkill_during_a_morph_run(self):
        self.check_killed_runs("morph", self.final_files, "16")  # a different animation replaces the old

    def test_sigkill_during_a_nodes_run(self):
        self.check_killed_runs("nodes", self.final_files, "16")

    def test_sigkill_during_a_files_run(self):
        # The files form merges into its folder's animation (same fps): every frame file
        # must still be whole after each kill.
        self.check_killed_runs("files", self.final_files, "12")


class Resume(unittest.TestCase):
    """The files form computes, writes and indexes a chunk of frames at a time into a
    hidden partial folder; `wave run --resume` keeps the frames its index lists whose
    files still match (size and SHA-256) and computes the others. The result is the
    uninterrupted run's output, byte for byte."""

    # 600 small frames (~70 kB each) in about a second: the sparse strips themselves
    # (the default water mesh would hold 16 vertices per wavelength whatever the rays).
    SCENE = {"name": "resume", "waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 5},
             "fronts": {"step": 2, "split_distance": 6}, "surface": {"water_mesh": False}, "animation": {"fps": 120}}
    FRAMES = 600

    @classmethod
    def setUpClass(cls):
        # The uninterrupted run, once for the class (each test gets its own copy: one
        # resumes into it). Under ASan a run takes ~20 s; seven of them were a third of
        # this class's time.
        cls.class_tmp = tempfile.TemporaryDirectory()
        scene = os.path.join(cls.class_tmp.name, "s.json")
        with open(scene, "w") as f:
            json.dump(cls.SCENE, f)
        cls.class_ref = os.path.join(cls.class_tmp.name, "ref")
        r = wave("run", scene, "-q", "--form", "files", "-o", cls.class_ref)
        assert r.returncode == 0, r.stderr

    @classmethod
    def tearDownClass(cls):
        cls.class_tmp.cleanup()

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.d = self.tmp.name
        self.scene = self.write_scene(self.SCENE)
        self.ref = os.path.join(self.d, "ref")
        shutil.copytree(self.class_ref, self.ref)

    def tearDown(self):
        self.tmp.cleanup()

    def write_scene(self, doc, name="s.json"):
        path = os.path.join(self.d, name)
        with open(path, "w") as f:
            json.dump(doc, f)
        return path

    @staticmethod
    def partial(out):
        """The partial folder and its index (None while there is none or it is being replaced)."""
        found = [n for n in os.listdir(out) if n.startswith(".wave-partial-")] if os.path.isdir(out) else []
        if len(found) != 1:
            return None, None
        root = os.path.join(out, found[0])
        try:
            with open(os.path.join(root, "index.json")) as f:
                return root, json.load(f)
        except (OSError, ValueError):
            return root, None

    def assert_listed_files_intact(self, root, index):
        for entry in index["frames"]:
            for c in entry["content"]:
                data = pathlib.Path(root, c["file"]).read_bytes()
                self.assertEqual(len(data), c["bytes"], c["file"])
                self.assertEqual(hashlib.sha256(data).hexdigest(), c["sha256"], c["file"])

    def kill_when_listed(self, args, out, frames):
        """Runs wave and SIGKILLs it as soon as its partial index lists `frames` frames."""
        p = subprocess.Popen([WAVE, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + 300
        while p.poll() is None and time.monotonic() < deadline:
            _, index = self.partial(out)
            if index and len(index["frames"]) >= frames:
                break
            time.sleep(0.005)
        p.send_signal(signal.SIGKILL)
        p.wait()
        self.assertEqual(p.returncode, -signal.SIGKILL, "killed before it finished")
        root, index = self.partial(out)
        self.assertGreaterEqual(len(index["frames"]), frames)
        return root, index

    def resume(self, out, scene=None):
        r = wave("run", scene or self.scene, "--form", "files", "-o", out, "--resume", "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        return json.loads(r.stdout)["resume"]

    def assert_same_as(self, out, ref):
        self.assertEqual(CrashSafety.final_files(out), CrashSafety.final_files(ref))
        self.assertEqual([n for n in os.listdir(out) if n.startswith(".wave-")], [])

    def test_random_kills_then_resume_give_the_uninterrupted_run(self):
        out = os.path.join(self.d, "out")
        rng = random.Random(2026)  # reproducible kill times
        for attempt in range(5):
            args = ["run", self.scene, "-q", "--form", "files", "-o", out] + (["--resume"] if attempt else [])
            p = subprocess.Popen([WAVE, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(rng.uniform(0.02, 0.6))
            p.send_signal(signal.SIGKILL)
            p.wait()
            # No final-named file until a run publishes: then they are the finished run's.
            final = CrashSafety.final_files(out) if os.path.isdir(out) else {}
            if final:
                self.assertEqual(final, CrashSafety.final_files(self.ref))
            root, index = self.partial(out)
            if index:
                self.assert_listed_files_intact(root, index)
        root, index = self.partial(out)
        listed = len(index["frames"]) if index else 0
        resumed = self.resume(out)
        if not CrashSafety.final_files(out) or listed:
            self.assertEqual(resumed["kept_frames"], listed)
        self.assertEqual(resumed["kept_frames"] + resumed["computed_frames"], self.FRAMES)
        self.assert_same_as(out, self.ref)

    def test_frames_whose_files_do_not_match_the_index_are_computed_again(self):
        out = os.path.join(self.d, "out")
        root, index = self.kill_when_listed(["run", self.scene, "-q", "--form", "files", "-o", out], out, 30)
        listed = len(index["frames"])
        # Same size, one byte changed; truncated; deleted: existence alone proves nothing.
        files = [os.path.join(root, index["frames"][k]["file"]) for k in (3, 11, 20)]
        data = bytearray(pathlib.Path(files[0]).read_bytes())
        data[len(data) // 2] ^= 0xFF
        pathlib.Path(files[0]).write_bytes(bytes(data))
        os.truncate(files[1], 100)
        os.remove(files[2])
        resumed = self.resume(out)
        self.assertEqual(resumed, {"kept_frames": listed - 3, "computed_frames": self.FRAMES - listed + 3})
        self.assert_same_as(out, self.ref)
        # A finished output is verified the same way by its own index.
        frame = os.path.join(out, "frames", "frame-0042.glb")
        data = bytearray(pathlib.Path(frame).read_bytes())
        data[-1] ^= 0x01
        pathlib.Path(frame).write_bytes(bytes(data))
        self.assertEqual(self.resume(out), {"kept_frames": self.FRAMES - 1, "computed_frames": 1})
        self.assert_same_as(out, self.ref)

    def test_frames_of_another_version_of_the_scene_are_not_kept(self):
        out = os.path.join(self.d, "out")
        self.kill_when_listed(["run", self.scene, "-q", "--form", "files", "-o", out], out, 20)
        # The same name, fps and loop, another amplitude: another run key.
        changed = json.loads(json.dumps(self.SCENE))
        changed["waves"][0]["amplitude"] = 0.35
        scene2 = self.write_scene(changed)  # over the same file
        ref2 = os.path.join(self.d, "ref2")
        self.assertEqual(wave("run", scene2, "-q", "--form", "files", "-o", ref2).returncode, 0)
        self.assertEqual(self.resume(out, scene2), {"kept_frames": 0, "computed_frames": self.FRAMES})
        self.assert_same_as(out, ref2)  # the other version's partial folder is gone too
        # Nor are the finished frames of the first version.
        self.assertEqual(self.resume(self.ref, scene2), {"kept_frames": 0, "computed_frames": self.FRAMES})
        self.assert_same_as(self.ref, ref2)

    def test_resumed_slices_merge_into_the_whole_runs_index(self):
        out = os.path.join(self.d, "out")
        self.kill_when_listed(["run", self.scene, "-q", "--form", "files", "-o", out, "--slice", "1/2"], out, 10)
        self.assertEqual(wave("run", self.scene, "-q", "--form", "files", "-o", out, "--slice", "0/2").returncode, 0)
        resumed = wave("run", self.scene, "--form", "files", "-o", out, "--slice", "1/2", "--resume", "--json")
        self.assertEqual(resumed.returncode, 0, resumed.stderr)
        self.assertGreaterEqual(json.loads(resumed.stdout)["resume"]["kept_frames"], 10)
        self.assertEqual(wave("merge", out, "-q").returncode, 0)
        self.assert_same_as(out, self.ref)  # index.json with its run key and checks, report.json

    def test_an_index_or_frame_of_other_types_is_not_read_as_ours(self):
        """index.json and a frame's asset extras are read back after crashes and can be
        edited by hand: a field of another type than libwave writes makes them "not
        ours" (named, exit 2, nothing replaced) or "no index" (wave merge rebuilds it) —
        never an exception from inside the JSON library (exit 1)."""
        out = os.path.join(self.d, "out")
        shutil.copytree(self.ref, out)
        index_path = os.path.join(out, "index.json")
        with open(index_path) as f:
            index = json.load(f)
        for key, value in [("fps", "120"), ("run_key", 5), ("loop_frames", -600), ("scene", ["resume"])]:
            # A run that is not resuming refuses to replace an index it cannot read.
            with open(index_path, "w") as f:
                json.dump({**index, key: value}, f)
            before = CrashSafety.final_files(out)
            r = wave("run", self.scene, "--form", "files", "-o", out, "--frames", "0:2")
            self.assertEqual(r.returncode, 2, f"{key}: {r.stderr}")
            self.assertIn(index_path + ": not a frame index of libwave", r.stderr)
            self.assertEqual(CrashSafety.final_files(out), before)
            self.assertEqual([n for n in os.listdir(out) if n.startswith(".wave-")], [])
            # merge indexes what is there: the frames' own files, with the run key the frames carry.
            r = wave("merge", out)
            self.assertEqual(r.returncode, 0, f"{key}: {r.stderr}")
            with open(index_path) as f:
                merged = json.load(f)
            self.assertEqual(len(merged["frames"]), self.FRAMES)
            self.assertEqual(merged["run_key"], index["run_key"])
            self.assertEqual([e["content"] for e in merged["frames"]], [e["content"] for e in index["frames"]], key)
            # --resume rebuilds it (docs/hardening.md): it checks the frames' files instead.
            with open(index_path, "w") as f:
                json.dump({**index, key: value}, f)
            r = wave("run", self.scene, "--form", "files", "-o", out, "--resume")
            self.assertEqual(r.returncode, 0, f"{key}: {r.stderr}")
            self.assertEqual(json.loads(pathlib.Path(index_path).read_text()), index, key)
            self.assertEqual([n for n in os.listdir(out) if n.startswith(".wave-")], [])
        # A frame whose asset extras have a string for the fps (same length: the GLB stays whole).
        frame = os.path.join(out, "frames", "frame-0007.glb")
        data = pathlib.Path(frame).read_bytes()
        self.assertIn(b'"fps":120.0', data)
        pathlib.Path(frame).write_bytes(data.replace(b'"fps":120.0', b'"fps":"120"', 1))
        r = wave("merge", out)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(frame + ": asset.extras.libwave lacks scene, fps, loop_frames or first_frame", r.stderr)

    def test_resume_is_refused_for_the_single_file_forms(self):
        r = wave("run", self.scene, "--form", "morph", "-o", os.path.join(self.d, "m"), "--resume")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--resume continues a run of the files form", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.d, "m")))

    def test_two_runs_of_one_range_do_not_share_a_partial_folder(self):
        out = os.path.join(self.d, "out")
        p = subprocess.Popen([WAVE, "run", self.scene, "-q", "--form", "files", "-o", out],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        while p.poll() is None and self.partial(out)[1] is None:
            time.sleep(0.005)
        r = wave("run", self.scene, "--form", "files", "-o", out, "--resume")
        p.wait()
        self.assertEqual(p.returncode, 0)
        if r.returncode != 0:  # the first still held the range
            self.assertEqual(r.returncode, 2)
            self.assertIn("another wave run is writing frames 0:600", r.stderr)
        self.assert_same_as(out, self.ref)


class RandomScenes(unittest.TestCase):
    """Property test through the whole pipeline: reproducible random seafloors (smooth
    grids written as ESRI ASCII: a sloping bottom with random bumps, depth, slope and
    extent) and random wave trains, surfaces, breakers, forms and compressions. Every
    run succeeds, reports finite heights, every file it exports passes the Khronos
    validator, and a ray-strips surface (the water mesh) has no fold, unused vertex or
    non-manifold edge in any frame, nor a triangle under 15° or an edge over 3 × the local
    spacing (tests/test_properties.cpp
    checks the kernels' invariants on such draws)."""

    DRAWS = 8

    @staticmethod
    def random_grid(rng, path):
        n = rng.randint(30, 70)
        cell = rng.uniform(1.0, 4.0)
        extent = cell * (n - 1)
        depth = rng.uniform(2.0, 15.0)
        shore = rng.uniform(0.6, 0.9) * extent  # where the slope reaches still water
        bumps = [(rng.uniform(0, extent), rng.uniform(0, extent), rng.uniform(-0.4, 0.4) * depth,
                  rng.uniform(0.05, 0.2) * extent) for _ in range(rng.randint(0, 4))]
        rows = []
        for j in range(n - 1, -1, -1):  # ESRI ASCII: the northern row first
            y = j * cell
            row = []
            for i in range(n):
                x = i * cell
                z = -depth * (1.0 - y / shore)
                for bx, by, h, w in bumps:
                    z += h * math.exp(-((x - bx) ** 2 + (y - by) ** 2) / (2 * w * w))
                row.append(f"{z:.4f}")
            rows.append(" ".join(row))
        with open(path, "w") as f:
            f.write(f"ncols {n}\nnrows {n}\nxllcorner 0\nyllcorner 0\ncellsize {cell}\n" + "\n".join(rows) + "\n")
        return extent, depth

    def random_scene(self, rng, d, k):
        extent, depth = self.random_grid(rng, os.path.join(d, f"floor-{k}.asc"))
        waves = []
        for _ in range(rng.randint(1, 2)):
            angle = math.radians(rng.uniform(-45, 45))
            waves.append({"period": rng.uniform(3, 12), "amplitude": rng.uniform(0.05, 0.8),
                          "direction": [math.sin(angle), math.cos(angle)]})
        kind = rng.choice(["ray-strips", "ray-strips", "height-field"])
        scene = {"name": f"random-{k}", "seafloor": {"source": f"floor-{k}.asc"}, "waves": waves[:1] if kind == "ray-strips" else waves,
                 "isobaths": {"spacing": depth / rng.randint(8, 20)},
                 "trace": {"ray_spacing": extent / rng.randint(20, 50)},
                 "surface": {"kind": kind},
                 "animation": {"fps": rng.choice([2, 4])}}
        if kind == "ray-strips":
            scene["fronts"] = {"step": extent / rng.randint(40, 120)}
            scene["fronts"]["split_distance"] = 3 * scene["trace"]["ray_spacing"]
            if rng.random() < 0.5:
                scene["breakers"] = "jeschke"
        form = rng.choice(["morph", "nodes", "files"])
        outputs = {"form": form}
        compression = rng.choice(["none", "quantize"] + (["draco"] if form != "morph" else []))
        if compression == "draco":
            outputs["draco"] = True
        elif compression == "quantize":
            outputs["quantize"] = True
        scene["outputs"] = outputs
        return scene

    def test_random_scenes_run_and_their_files_validate(self):
        rng = random.Random(20261201)
        checked = 0
        with tempfile.TemporaryDirectory() as d:
            for k in range(self.DRAWS):
                scene = self.random_scene(rng, d, k)
                path = os.path.join(d, f"scene-{k}.json")
                with open(path, "w") as f:
                    json.dump(scene, f)
                out = os.path.join(d, f"out-{k}")
                with self.subTest(draw=k, scene=json.dumps(scene)):
                    r = wave("run", path, "-o", out, "--json")
                    self.assertEqual(r.returncode, 0, r.stderr)
                    surface = json.loads(r.stdout)["surface"]
                    self.assertTrue(all(math.isfinite(z) for z in surface["height_range_m"]))
                    self.assertGreater(surface["triangles"], 0)
                    exported = [os.path.join(out, n) for n in os.listdir(out) if n.endswith((".glb", ".gltf"))]
                    if os.path.isdir(os.path.join(out, "frames")):
                        frames = sorted(os.listdir(os.path.join(out, "frames")))
                        exported += [os.path.join(out, "frames", n) for n in frames if n.endswith((".glb", ".gltf"))][:3]
                    self.assertTrue(exported)
                    for f in exported:
                        validate_gltf(self, f)
                    # The water mesh, untangled: no fold in any frame (Draco frames are left out:
                    # positions on their lattices can flip a sliver). Quantised foam can move
                    # a breaking lip's foam across inspect's 0.1 threshold: there a fold is
                    # allowed per 200 lips.
                    if scene["surface"]["kind"] == "ray-strips" and "draco" not in scene["outputs"]:
                        r = wave("inspect", out, "--json")
                        self.assertEqual(r.returncode, 0, r.stderr)
                        m = json.loads(r.stdout)
                        self.assertEqual((m["unreferenced_vertices"], m["non_manifold_edges"]), (0, 0))
                        quantised = "quantize" in scene["outputs"]
                        self.assertEqual([f["folds"] for f in m["per_frame"] if f["folds"] > (f["lips"] // 200 if quantised else 0)], [])
                        # The untangling keeps 16°, and no edge is over 3 × the local spacing (one
                        # draw had one of 3.11 × where the skirt went on over the land beyond a
                        # straight shore that was a whole side).
                        self.assertGreaterEqual(m["worst"]["smallest_angle_deg"], 15.0)
                        self.assertEqual(m["worst"]["long_edges"], 0)
                        checked += 1
            self.assertGreaterEqual(checked, 3)


class Limits(unittest.TestCase):
    """Hostile or mistaken scenes are refused up front — before memory is allocated —
    naming the limit and the option that raises it; `wave validate` estimates what a
    run would write and hold."""


    def run_limited(self, scene, *extra):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "hostile.json")
            with open(path, "w") as f:
                json.dump(scene, f)

            def cap():  # 4 GB of address space: an allocation before the check would fail
                resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
            t0 = time.monotonic()
            r = subprocess.run([WAVE, "run", path, "-q", "-o", os.path.join(d, "out"), *extra], capture_output=True,
                               text=True, timeout=120, preexec_fn=None if UNDER_ASAN else cap)
            elapsed = time.monotonic() - t0
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "out")), "no output for a refused scene")
            if not UNDER_ASAN:
                self.assertLess(elapsed, 20.0, "refused up front, not after the work")
            return r.stderr

    def test_hostile_scenes_are_refused_naming_the_limit(self):
        wave_train = [{"period": 5, "amplitude": 0.3}]
        # 10^9 rays: a ray spacing of 0.1 µm over the 100 m bay.
        err = self.run_limited({"waves": wave_train, "trace": {"ray_spacing": 1e-7}})
        self.assertIn("more than the limit of 1000000 (TraceOptions::max_rays, scene key /trace/max_rays", err)
        # 200 000 fps: out of the schema's range.
        err = self.run_limited({"waves": wave_train, "animation": {"fps": 200000}})
        self.assertIn("/animation/fps: expected a number in (0, 1000] (frames per second), got 200000", err)
        # More frames than max_frames.
        err = self.run_limited({"waves": wave_train, "animation": {"fps": 1000, "max_frames": 1000}})
        self.assertIn("the loop holds 5000 frames", err)
        self.assertIn("raise /animation/max_frames", err)
        # A subdivision level of 20.
        err = self.run_limited({"waves": wave_train, "refine": {"level": 20}})
        self.assertIn("/refine/level: expected a whole number in [1, 6], got 20", err)
        # 10^9 surface vertices (a 40 000² control grid).
        err = self.run_limited({"waves": wave_train, "surface": {"kind": "height-field", "grid": [40000, 40000]}})
        self.assertIn("exceed max_vertices", err)
        # Frame arrays over the memory limit, and the options that lower or raise it (a
        # quantised nodes file holds every frame; the others stream a chunk at a time).
        err = self.run_limited({"waves": wave_train, "animation": {"fps": 1000}, "outputs": {"form": "nodes", "quantize": True},
                                "surface": {"water_mesh": {"vertices_per_wavelength": 32}}})
        self.assertIn("GB of per-frame arrays", err)
        self.assertIn("use the morph form or drop /outputs/quantize", err)
        self.assertIn("wave run --max-memory-gb", err)
        # A 10^9-cell ocean patch is refused by the schema's range.
        err = self.run_limited({"surface": {"kind": "ocean"}, "ocean": {"resolution": 32768}})
        self.assertIn("/ocean/resolution", err)

    def test_a_slice_is_limited_by_its_own_frames(self):
        # A file written whole (quantised nodes) holds the frames of its run, not of the
        # loop: the 5 000-frame loop is refused under 2 GB, a slice of 3 of its frames runs
        # (its estimate was the loop's: 4.3 GB for 2 frames of breaking Okushiri).
        scene = {"waves": [{"period": 5, "amplitude": 0.3}], "animation": {"fps": 1000},
                 "outputs": {"form": "nodes", "quantize": True}, "trace": {"ray_spacing": 2},
                 "fronts": {"step": 0.8, "split_distance": 2.4}}
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "s.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            r = wave("run", path, "-q", "-o", os.path.join(d, "all"), "--max-memory-gb", "2")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("GB of per-frame arrays", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "all")))
            r = wave("run", path, "-q", "-o", os.path.join(d, "slice"), "--max-memory-gb", "2", "--frames", "100:103")
            self.assertEqual(r.returncode, 0, r.stderr)
            doc, _ = read_glb(os.path.join(d, "slice", "animation-frames-100-103.glb"))
            self.assertEqual(sum(1 for n in doc["nodes"] if n["name"].startswith("frame_") and "mesh" not in n), 3)

    def test_validate_estimates_the_output_and_the_memory(self):
        scene = os.path.join(EXAMPLES, "gonzato-bay.json")
        r = wave("validate", scene, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        est = json.loads(r.stdout)["estimate"]
        self.assertEqual(est["frames"], 120)
        with tempfile.TemporaryDirectory() as d:
            # Measured in a fresh interpreter whose only child is wave: its peak RSS.
            code = ("import resource, subprocess, sys; r = subprocess.run(sys.argv[1:]); "
                    "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)")
            out = subprocess.run([sys.executable, "-c", code, WAVE, "run", scene, "-q", "-o", os.path.join(d, "m")],
                                 capture_output=True, text=True, timeout=600)
            rc, rss_kb = map(int, out.stdout.split())
            self.assertEqual(rc, 0, out.stderr)
            size = os.path.getsize(os.path.join(d, "m", "animation.glb"))
            # The writer's dense layout, an upper bound: sparse targets (still vertices:
            # the dry beach, foam-free water) take less (the bay: 0.86 of it).
            self.assertTrue(0.7 < size / est["output_bytes"] < 1.02, f"{size} bytes vs estimate {est['output_bytes']}")
            if not UNDER_ASAN:
                ratio = rss_kb * 1024 / est["peak_memory_bytes"]
                self.assertTrue(0.75 < ratio < 1.33, f"peak RSS {rss_kb / 1e6:.2f} GB vs estimate {est['peak_memory_bytes'] / 1e9:.2f} GB")
            # Draco files: the measured bytes per vertex.
            r = wave("run", scene, "-q", "--form", "files", "--draco", "--frames", "0:12", "-o", os.path.join(d, "f"))
            self.assertEqual(r.returncode, 0, r.stderr)
            # (frame 0 also carries the seafloor, camera and sun: the water's frames are 1 … 11)
            frames = sum(os.path.getsize(os.path.join(d, "f", "frames", n)) for n in os.listdir(os.path.join(d, "f", "frames"))
                         if n != "frame-0000.glb")
            with open(os.path.join(d, "f", "report-frames-0-12.json")) as f:  # the water and its skirt
                draco_vertices = json.load(f)["surface"]["vertices"]
            per_frame_estimate = 9.2 * draco_vertices
            self.assertAlmostEqual(frames / 11 / per_frame_estimate, 1.0, delta=0.3)


class Streaming(unittest.TestCase):
    """A long animation is written a chunk of frames at a time (docs/export.md, "Streamed
    output"): under a data cap (RLIMIT_DATA) several times below its output, every form
    finishes with valid files, quantised morph targets too (a first pass over the
    positions finds their range), and `wave merge` indexes the files form's frames; the
    quantised nodes file, which holds every frame, is refused by the same cap."""

    SCENE = {"name": "long ocean", "surface": {"kind": "ocean"},
             "ocean": {"resolution": 128, "size": 200, "spectrum": "phillips", "wind_speed": 12, "repeat_time": 60,
                       "seed": 3},
             "animation": {"fps": 24}}
    # Bytes of data (RLIMIT_DATA: the heap and every private writable mapping — two worker
    # threads' stacks and arenas, the plan, the frames — but not the libraries' code, which
    # an address-space cap counted: OpenVDB's alone maps 57 MB).
    CAP = 320 << 20

    def capped(self, *args):
        def cap():
            resource.setrlimit(resource.RLIMIT_DATA, (self.CAP, self.CAP))
        return subprocess.run([WAVE, *args], capture_output=True, text=True, timeout=600,
                              preexec_fn=None if UNDER_ASAN else cap)

    def run_capped(self, d, *extra):
        path = os.path.join(d, "long.json")
        with open(path, "w") as f:
            json.dump(self.SCENE, f)
        out = os.path.join(d, "out-" + "-".join(a.strip("-") for a in extra))
        # Plain floats unless asked: the point is output far bigger than the cap.
        codec = () if {"--codec", "--quantize", "--draco"} & set(extra) else ("--codec", "none")
        return self.capped("run", path, "-q", "--threads", "2", "-o", out, *codec, *extra), out

    def test_a_long_animation_streams_under_a_memory_cap_far_below_its_size(self):
        if UNDER_ASAN:
            self.skipTest("address-space caps do not apply under ASan")
        with tempfile.TemporaryDirectory() as d:
            for form in ("morph", "nodes", "pc2", "files"):
                r, out = self.run_capped(d, "--form", form)
                self.assertEqual(r.returncode, 0, form + ": " + r.stderr)
                total = sum(p.stat().st_size for p in pathlib.Path(out).rglob("*") if p.is_file())
                self.assertGreater(total, 1.7 * self.CAP, form)  # the cap is far below what was written (pc2: 1.8×, the others ≥ 2.7×)
                self.assertEqual([p.name for p in pathlib.Path(out).iterdir() if p.name.startswith(".")], [], form)
                with open(os.path.join(out, "report.json")) as f:
                    self.assertEqual(json.load(f)["surface"]["frames"], 1440)
                if form == "morph":
                    # `wave convert` reads a morph file's targets from the file frame by
                    # frame (only its static parts are loaded): the 2.5× cap file → pc2.
                    self.assertGreater(os.path.getsize(os.path.join(out, "animation.glb")), 2.4 * self.CAP)
                    r = self.capped("convert", os.path.join(out, "animation.glb"), "--form", "pc2", "-o",
                                    os.path.join(d, "morph-to-pc2"), "-q")
                    self.assertEqual(r.returncode, 0, r.stderr)
                if form == "pc2":  # the conversion wrote the caches this run writes (morph deltas: float rounding)
                    for cache in pathlib.Path(out).glob("*.pc2"):
                        ran, converted = cache.read_bytes(), (pathlib.Path(d) / "morph-to-pc2" / cache.name).read_bytes()
                        self.assertEqual(ran[:32], converted[:32], cache.name)  # header: points, frames
                        self.assertEqual(len(ran), len(converted), cache.name)
                        # Whole frames spread over the loop (every one took minutes in pure
                        # Python): the first, the last and every 47th between.
                        points, frames = struct.unpack_from("<i", ran, 16)[0], struct.unpack_from("<i", ran, 28)[0]
                        size = 12 * points
                        self.assertEqual((frames, len(ran)), (1440, 32 + frames * size), cache.name)
                        for f in sorted({*range(0, frames, 47), frames - 1}):
                            a = array.array("f", ran[32 + f * size:32 + (f + 1) * size])
                            b = array.array("f", converted[32 + f * size:32 + (f + 1) * size])
                            self.assertLess(max(abs(x - y) for x, y in zip(a, b)), 1e-4, f"{cache.name} frame {f}")  # metres (a 200 m patch)
                    shutil.rmtree(os.path.join(d, "morph-to-pc2"))
                if form == "files":
                    # `wave merge` reads and hashes one frame's files at a time: under the
                    # same cap it rebuilds the index the run wrote, entry for entry.
                    with open(os.path.join(out, "index.json")) as f:
                        written = json.load(f)
                    os.remove(os.path.join(out, "index.json"))
                    r = self.capped("merge", out)
                    self.assertEqual(r.returncode, 0, r.stderr)
                    with open(os.path.join(out, "index.json")) as f:
                        merged = json.load(f)
                    self.assertEqual(len(merged["frames"]), 1440)
                    self.assertEqual([e["content"] for e in merged["frames"]], [e["content"] for e in written["frames"]])
                    # `wave convert` reads the frame files one at a time and streams the
                    # morph file out: under the same cap, a file 2.4× the cap.
                    converted = os.path.join(d, "converted")
                    r = self.capped("convert", os.path.join(out, "index.json"), "-o", converted, "-q")
                    self.assertEqual(r.returncode, 0, r.stderr)
                    with open(os.path.join(converted, "animation.glb"), "rb") as f:  # its JSON chunk alone
                        head = f.read(20)
                        doc = json.loads(f.read(struct.unpack_from("<I", head, 12)[0]))
                    self.assertEqual(len(doc["meshes"][0]["primitives"][0]["targets"]), 1440)
                    self.assertGreater(os.path.getsize(os.path.join(converted, "animation.glb")), 2.4 * self.CAP)
                    shutil.rmtree(converted)
                shutil.rmtree(out)
            # The morph file: a valid glTF whose last frame's target is there (validated
            # on a shorter loop of the same ocean: the validator itself holds the file).
            self.SCENE = dict(self.SCENE, ocean=dict(self.SCENE["ocean"], repeat_time=5))
            r, out = self.run_capped(d, "--form", "morph")
            self.assertEqual(r.returncode, 0, r.stderr)
            validate_gltf(self, os.path.join(out, "animation.glb"))
            doc, _ = read_glb(os.path.join(out, "animation.glb"))
            self.assertEqual(len(doc["meshes"][0]["primitives"][0]["targets"]), 120)
            quantised_short, _ = self.run_capped(d, "--form", "morph", "--quantize")
            self.assertEqual(quantised_short.returncode, 0, quantised_short.stderr)
            validate_gltf(self, os.path.join(d, "out-form-morph-quantize", "animation.glb"))
            shutil.rmtree(os.path.join(d, "out-form-morph-quantize"))
            self.SCENE = Streaming.SCENE
            r, out = self.run_capped(d, "--form", "morph", "--quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertGreater(os.path.getsize(os.path.join(out, "animation.glb")), 1.5 * self.CAP)
            shutil.rmtree(out)
            # Quantised nodes hold every frame (each frame's grid spans the animation): refused.
            r, out = self.run_capped(d, "--form", "nodes", "--quantize")
            self.assertNotEqual(r.returncode, 0)
            self.assertFalse(os.path.exists(out), "no partial output")


class Batch(unittest.TestCase):
    SCENES = {
        "bay.json": {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
                     "fronts": {"step": 0.8, "split_distance": 2.4}},
        "sea.json": {"surface": {"kind": "ocean"}, "ocean": {"resolution": 32, "size": 100, "repeat_time": 2},
                     "animation": {"fps": 8}},
        "broken.json": {"waves": [{"period": -5}]},
    }

    def scenes(self, d):
        folder = os.path.join(d, "scenes")
        os.makedirs(folder)
        for name, doc in self.SCENES.items():
            with open(os.path.join(folder, name), "w") as f:
                json.dump(doc, f)
        return folder

    def test_a_failed_scene_does_not_stop_the_others(self):
        with tempfile.TemporaryDirectory() as d:
            folder, out = self.scenes(d), os.path.join(d, "out")
            r = wave("batch", folder, "-o", out, "--jobs", "2", "--json")
            self.assertEqual(r.returncode, 2, r.stderr)  # bad input in one scene
            summary = json.loads(r.stdout)
            self.assertEqual((summary["scenes"], summary["ok"], summary["failed"]), (3, 2, 1))
            self.assertEqual(json.load(open(os.path.join(out, "batch-summary.json")))["ok"], 2)
            failed = [x for x in summary["results"] if x["status"] == "failed"]
            self.assertEqual(failed[0]["exit_code"], 2)
            self.assertIn("broken.json: /waves/0/period", failed[0]["error"])
            self.assertEqual(sorted(os.listdir(out)), ["batch-summary.json", "bay", "sea"])  # no temporaries, no partial
            # Each scene's outputs are what `wave run` writes for it alone.
            alone = os.path.join(d, "alone")
            self.assertEqual(wave("run", os.path.join(folder, "bay.json"), "-o", alone, "-q").returncode, 0)
            for name in ["animation.glb", "strips.ply", "report.json"]:
                self.assertEqual(pathlib.Path(out, "bay", name).read_bytes(), pathlib.Path(alone, name).read_bytes(), name)

    def test_patterns_run_options_and_bad_batches(self):
        with tempfile.TemporaryDirectory() as d:
            folder, out = self.scenes(d), os.path.join(d, "out")
            os.remove(os.path.join(folder, "broken.json"))
            r = wave("batch", os.path.join(folder, "s*.json"), os.path.join(folder, "bay.json"), "-o", out,
                     "--form", "files", "--fps", "4", "-q")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertEqual(r.stdout, "")
            index = json.load(open(os.path.join(out, "sea", "index.json")))
            self.assertEqual(index["fps"], 4)
            self.assertEqual(len(index["frames"]), 8)  # 2 s at 4 fps
            self.assertTrue(os.path.exists(os.path.join(out, "bay", "index.json")))
            # Two scenes with one name would write one folder: refused before running.
            other = os.path.join(d, "other")
            os.makedirs(other)
            with open(os.path.join(other, "bay.json"), "w") as f:
                json.dump(self.SCENES["bay.json"], f)
            r = wave("batch", folder, other, "-o", os.path.join(d, "clash"))
            self.assertEqual(r.returncode, 2)
            self.assertIn("rename one", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(d, "clash")))
            # A missing input is that scene's failure (bad input, exit 2); the others still run,
            # and the summary lists each run's files, bytes and frames.
            r = wave("batch", os.path.join(d, "nothing-*.json"), os.path.join(folder, "bay.json"), "-o", os.path.join(d, "some"))
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn("no such scene file", r.stdout)
            summary = json.load(open(os.path.join(d, "some", "batch-summary.json")))
            self.assertEqual((summary["scenes"], summary["ok"], summary["failed"]), (2, 1, 1))
            failed = [x for x in summary["results"] if x["status"] == "failed"][0]
            self.assertEqual(failed["exit_code"], 2)
            self.assertIn("nothing-*.json", failed["error"])
            ok = [x for x in summary["results"] if x["status"] == "ok"][0]
            files = {o["file"]: o["bytes"] for o in ok["outputs"]}
            self.assertIn("report.json", files)
            self.assertEqual(ok["bytes"], sum(files.values()))
            self.assertEqual(sum(files.values()), sum(os.path.getsize(os.path.join(ok["output"], f)) for f in files))
            self.assertEqual(ok["frames"], 120)  # 5 s at 24 fps
            # A slice (--frames) reports its own frames, read from the report the run
            # printed: it writes report-frames-A-B.json, and the folder holds the whole
            # loop's report.json from before ("frames": 0 then; 120 would be the old one's).
            r = wave("batch", os.path.join(folder, "bay.json"), "-o", os.path.join(d, "some"), "--frames", "2:5", "--json")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            sliced = json.loads(r.stdout)["results"][0]
            self.assertEqual(sliced["frames"], 3)
            self.assertIn("report-frames-2-5.json", [o["file"] for o in sliced["outputs"]])
            self.assertEqual(sorted(os.listdir(os.path.join(d, "some"))), ["batch-summary.json", "bay"])  # no temporaries


class OutputFolders(unittest.TestCase):
    """Reruns replace their predecessor's outputs (nothing stale), --overwrite clears what
    earlier runs left, and -o FILE.glb writes that one file."""
    SCENE = {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
             "fronts": {"step": 0.8, "split_distance": 2.4}, "animation": {"fps": 4}}

    def test_a_rerun_leaves_nothing_stale_and_overwrite_clears_the_folder(self):
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, self.SCENE)
            out = os.path.join(d, "out")
            run = lambda *args: self.assertEqual(wave("run", scene, "-o", out, "-q", *args).returncode, 0)
            run("--container", "gltf", "--preview")
            self.assertTrue({"animation.gltf", "animation.bin", "preview.png"} <= set(os.listdir(out)))
            with open(os.path.join(out, "notes.txt"), "w") as f:
                f.write("the artist's own file")
            run()  # glb now, no preview: the .gltf, .bin and preview.png were this report's and are stale
            names = set(os.listdir(out))
            self.assertIn("animation.glb", names)
            self.assertFalse({"animation.gltf", "animation.bin", "preview.png"} & names, names)
            self.assertIn("notes.txt", names)  # not ours: kept
            run("--frames", "0:2")  # a slice has its own report and files beside the loop's
            self.assertTrue({"animation-frames-0-2.glb", "report-frames-0-2.json", "animation.glb"} <= set(os.listdir(out)))
            r = wave("run", scene, "-o", out, "--overwrite", "--resume")
            self.assertEqual(r.returncode, 2)
            self.assertIn("excludes", r.stderr)
            run("--overwrite", "--form", "files")
            names = set(os.listdir(out))
            self.assertFalse({"animation.glb", "animation-frames-0-2.glb", "report-frames-0-2.json"} & names, names)
            self.assertTrue({"index.json", "frames", "report.json", "notes.txt"} <= names, names)
            run("--overwrite")  # back to one file: the files form's index and frames go
            names = set(os.listdir(out))
            self.assertFalse({"index.json", "frames"} & names, names)
            self.assertIn("animation.glb", names)
            self.assertEqual([n for n in names if n.startswith(".")], [])

    def test_another_form_after_a_files_run_leaves_no_stale_frames(self):
        """A morph run into a folder where a files run wrote its index.json and frames/:
        they go once the morph file is published (wave merge, convert and the readers
        found the old frames beside it); frames no report claims are refused, before any
        work, with the way out (--overwrite), and nothing is written."""
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, self.SCENE)
            out = os.path.join(d, "out")
            run = lambda *args: wave("run", scene, "-o", out, "-q", *args)
            self.assertEqual(run("--form", "files").returncode, 0)
            self.assertTrue({"index.json", "frames"} <= set(os.listdir(out)))
            self.assertEqual(run("--form", "morph").returncode, 0)
            names = set(os.listdir(out))
            self.assertIn("animation.glb", names)
            self.assertFalse({"index.json", "frames"} & names, names)
            r = wave("merge", out)  # nothing stale for it to index beside the morph file
            self.assertEqual(r.returncode, 2)
            self.assertIn("no frames/ folder", r.stderr)
            # Frames no report of the folder claims (a files run's, left by the old rule; or
            # someone's own): refused, naming them and --overwrite.
            os.makedirs(os.path.join(out, "frames"))
            shutil.copy(os.path.join(out, "animation.glb"), os.path.join(out, "frames", "frame-0000.glb"))
            before = {n: os.path.getmtime(os.path.join(out, n)) for n in os.listdir(out)}
            for form in ("morph", "nodes", "pc2"):
                r = run("--form", form)
                self.assertEqual(r.returncode, 2, r.stderr)
                self.assertIn(os.path.join(out, "frames") + ": a files form's frames that no report of this folder claims", r.stderr)
                self.assertIn(f"a {form} run here would leave them", r.stderr)
                self.assertIn("--overwrite", r.stderr)
                self.assertEqual({n: os.path.getmtime(os.path.join(out, n)) for n in os.listdir(out)}, before)
            self.assertEqual(run("--form", "morph", "--overwrite").returncode, 0)
            self.assertNotIn("frames", os.listdir(out))

    def test_o_file_glb_writes_that_one_file(self):
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, self.SCENE)
            target = os.path.join(d, "shots", "water.glb")
            r = wave("run", scene, "-o", target, "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(os.listdir(os.path.join(d, "shots")), ["water.glb"])
            validate_gltf(self, target)
            doc, _ = read_glb(target)
            self.assertEqual(len(doc["meshes"][0]["primitives"][0]["targets"]), 20)  # the 5 s loop at 4 fps
            # A slice keeps the name it was given; the range is in the file.
            r = wave("run", scene, "-o", os.path.join(d, "shots", "part.glb"), "--frames", "2:5", "-q")
            self.assertEqual(r.returncode, 0, r.stderr)
            doc, _ = read_glb(os.path.join(d, "shots", "part.glb"))
            self.assertEqual(len(doc["meshes"][0]["primitives"][0]["targets"]), 3)
            # Forms of many files are refused before anything is written.
            for args, what in ((["--form", "files"], "files"), (["--form", "pc2"], "pc2"), (["--container", "gltf"], "gltf")):
                r = wave("run", scene, "-o", os.path.join(d, "other", "x.glb"), *args)
                self.assertEqual(r.returncode, 2, r.stdout)
                self.assertIn(what, r.stderr)
                self.assertFalse(os.path.exists(os.path.join(d, "other", "x.glb")))
            self.assertEqual(sorted(os.listdir(os.path.join(d, "shots"))), ["part.glb", "water.glb"])


class Convert(unittest.TestCase):
    SCENE = {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
             "fronts": {"step": 0.8, "split_distance": 2.4}, "animation": {"fps": 6}}

    def positions(self, folder):
        """POSITION of every frame file of a files-form folder (glTF axes), by frame."""
        index = json.load(open(os.path.join(folder, "index.json")))
        out = []
        for f in index["frames"]:
            doc, binary = read_glb(os.path.join(folder, f["file"]))
            out.append(floats(doc, binary, doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]))
        return out

    @staticmethod
    def nearest_gaps(frame, want, inside):
        """The largest distance (per axis) from a point of `frame` to the nearest point of
        `want` (glTF axes, 1 m cells in x and z), over all points and over those where
        inside(x, z) holds."""
        cells = {}
        for i in range(0, len(want), 3):
            cells.setdefault((math.floor(want[i]), math.floor(want[i + 2])), []).append(i)
        worst = worst_inside = 0.0
        for i in range(0, len(frame), 3):
            x, y, z = frame[i:i + 3]
            near = min(max(abs(want[j] - x), abs(want[j + 1] - y), abs(want[j + 2] - z))
                       for a in (-1, 0, 1) for b in (-1, 0, 1)
                       for j in cells.get((math.floor(x) + a, math.floor(z) + b), []))
            worst = max(worst, near)
            if inside(x, z):
                worst_inside = max(worst_inside, near)
        return worst, worst_inside

    def normals(self, folder):
        """NORMAL of every frame file of a files-form folder, by frame, as unit triples."""
        out = []
        for f in json.load(open(os.path.join(folder, "index.json")))["frames"]:
            doc, binary = read_glb(os.path.join(folder, f["file"]))
            n = floats(doc, binary, doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"])
            out.append([tuple(c / math.sqrt(n[i] ** 2 + n[i + 1] ** 2 + n[i + 2] ** 2) for c in n[i:i + 3]) for i in range(0, len(n), 3)])
        return out

    def test_quantised_normals_turn_past_the_int16_range_by_targets_of_their_own(self):
        # A quantised morph target holds a normal's delta within ±1 (normalised int16);
        # a normal that turns further (a delta component beyond 1: > 60°, on the lips)
        # puts the excess in a NORMAL-only target weighted in by the same frame's key.
        # Eq. 7's sections (min_packing 0) curl lips whose normals turn that far.
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(dict(self.SCENE, motion={"min_packing": 0}), f)
            for name, args in (("float", ()), ("quantized", ("--quantize",))):
                self.assertEqual(wave("run", scene, "-o", os.path.join(d, name), "-q", *args).returncode, 0)
            doc, binary = read_glb(os.path.join(d, "float", "animation.glb"))
            prim = doc["meshes"][0]["primitives"][0]
            beyond = [k for k, t in enumerate(prim["targets"]) if max(map(abs, floats(doc, binary, t["NORMAL"]))) > 1]
            self.assertGreater(len(beyond), 5)  # the bay's lips turn their normals by more than 60°
            qdoc, _ = read_glb(os.path.join(d, "quantized", "animation.glb"))
            targets = qdoc["meshes"][0]["primitives"][0]["targets"]
            self.assertEqual(len(targets), 30 + len(beyond))
            self.assertTrue(all(sorted(t) == ["NORMAL"] for t in targets[30:]))
            self.assertEqual(qdoc["meshes"][0]["extras"]["targetNames"][30:],
                             ["frame_%04d normals beyond 1" % k for k in beyond])
            validate_gltf(self, os.path.join(d, "quantized", "animation.glb"))
            # Read back (base + the frame's targets by the weights track), every normal
            # within 0.5° of the float file's (the int8 base's rounding, 0.4° at most).
            for name in ("float", "quantized"):
                r = wave("convert", os.path.join(d, name, "animation.glb"), "-o", os.path.join(d, "c-" + name), "--form", "files", "-q")
                self.assertEqual(r.returncode, 0, r.stderr)
            worst = max(math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))))
                        for fa, fb in zip(self.normals(os.path.join(d, "c-float")), self.normals(os.path.join(d, "c-quantized")))
                        for a, b in zip(fa, fb))
            self.assertLess(worst, 0.5)

    def test_forms_round_trip_without_recomputing(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SCENE, f)
            run = lambda out, *args: self.assertEqual(wave("run", scene, "-o", os.path.join(d, out), "-q", *args).returncode, 0)
            run("files", "--form", "files", "--codec", "none")
            run("morph", "--codec", "none")
            run("quantized", "--quantize")
            run("draco", "--draco")
            convert = lambda src, out, *args: wave("convert", os.path.join(d, src), "-o", os.path.join(d, out), "--json", *args)
            # files -> morph: the very file `wave run` writes in the morph form; quantised
            # too (a first pass over the frames finds the deltas' range, as the run's
            # does), and the pc2 form's caches and base. The frames come a file at a
            # time (read_animation_pieces) into the streamed writers.
            r = convert("files/index.json", "c-morph")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(pathlib.Path(d, "c-morph", "animation.glb").read_bytes(),
                             pathlib.Path(d, "morph", "animation.glb").read_bytes())
            r = convert("files/index.json", "c-quantized", "--quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(pathlib.Path(d, "c-quantized", "animation.glb").read_bytes(),
                             pathlib.Path(d, "quantized", "animation.glb").read_bytes())
            run("pc2", "--form", "pc2")
            r = convert("files/index.json", "c-pc2", "--form", "pc2")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(sorted(json.loads(r.stdout)["outputs"]),
                             ["animation-shading.pc2", "animation.glb", "animation.obj", "animation.pc2"])
            for name in json.loads(r.stdout)["outputs"]:
                self.assertEqual(pathlib.Path(d, "c-pc2", name).read_bytes(), pathlib.Path(d, "pc2", name).read_bytes(), name)
            # files -> files, a frame at a time: the same positions, and index entries for
            # the same frames, times and heights (the frames carry no run key: re-encoded,
            # not computed, so their bytes differ from the run's by that key).
            r = convert("files/index.json", "c-files", "--form", "files")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(self.positions(os.path.join(d, "c-files")), self.positions(os.path.join(d, "files")))
            with open(os.path.join(d, "files", "index.json")) as a, open(os.path.join(d, "c-files", "index.json")) as b:
                ran, converted = json.load(a), json.load(b)
            keys = lambda index: [(e["frame"], e["time"], e["file"], e["height_range_m"]) for e in index["frames"]]
            self.assertEqual(keys(converted), keys(ran))
            self.assertEqual((converted["scene"], converted["loop_frames"]), (ran["scene"], ran["loop_frames"]))
            self.assertNotIn("run_key", converted)
            self.assertEqual(sorted(p.name for p in pathlib.Path(d, "c-files").iterdir()), ["frames", "index.json"])
            reference = self.positions(os.path.join(d, "files"))
            extent = max(max(abs(x) for x in frame) for frame in reference)
            # morph -> files: base + delta in float (one rounding); quantised: two int16
            # steps (base and delta); Draco base: its grid (targets stay float). The skirt
            # reaches 80 km: the Draco grid gains the bits that keep the bay's 100 m on a
            # 14-bit step (6 mm), and float32 decoding 80 km from the grid's origin adds
            # up to 8 mm; 14 bits over the whole reach would be 10 m.
            in_bay = [all(abs(c) < 200 for c in frame[i:i + 3]) for frame in reference[:1] for i in range(0, len(frame), 3)]
            for src, tolerance, bay_tolerance in [("morph/animation.glb", 1e-5 * extent, 1e-5),
                                                  ("quantized/animation.glb", 2.5 * 2 * extent / 65534, None),
                                                  ("draco/animation.glb", 2 * extent / (2 ** 14 - 1), 0.02)]:
                out = "c-" + src.split("/")[0]
                r = convert(src, out, "--form", "files")
                self.assertEqual(r.returncode, 0, r.stderr)
                got = self.positions(os.path.join(d, out))
                self.assertEqual(len(got), 30)  # 5 s at 6 fps
                self.assertEqual([len(g) for g in got], [len(e) for e in reference], src)  # the skirt is there
                worst = max(abs(a - b) for g, e in zip(got, reference) for a, b in zip(g, e))
                self.assertLess(worst, tolerance, src)
                if bay_tolerance:
                    bay = max(abs(a - b) for g, e in zip(got, reference) for i in range(0, len(e), 3) if in_bay[i // 3]
                              for a, b in zip(g[i:i + 3], e[i:i + 3]))
                    self.assertLess(bay, bay_tolerance, src)
                validate_gltf(self, os.path.join(d, out, "frames", "frame-0007.glb"))
            # morph -> nodes (Draco), and a .gltf container: valid files.
            r = convert("morph/animation.glb", "c-nodes", "--form", "nodes", "--draco")
            self.assertEqual(r.returncode, 0, r.stderr)
            validate_gltf(self, os.path.join(d, "c-nodes", "animation.glb"))
            r = convert("morph/animation.glb", "c-gltf", "--container", "gltf", "--quantize")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(sorted(os.listdir(os.path.join(d, "c-gltf"))), ["animation.bin", "animation.gltf"])
            validate_gltf(self, os.path.join(d, "c-gltf", "animation.gltf"))

    def test_draco_frames_carry_the_far_field_on_exact_lattices(self):
        # A Draco frame of its own carries the far field's skirt as a second primitive
        # (docs/far-field.md, "Draco frames"), each on a power-of-two lattice that Draco's
        # float32 arithmetic decodes exactly. Read back, a frame is one mesh of the run's
        # vertices, the seam welded (the plain run's one boundary loop), every coordinate
        # a multiple of 2^-8 m, within half a step of the plain run (the bay: 2^-8 m,
        # 14 bits over 100 m, written in quarter metres so that Draco's six printed
        # decimals keep the step, and the node scaled by ¼; the skirt's 2^-5 m, 80 km each
        # way in fewer than 2^23 steps). Draco orders a frame's points by the triangles
        # alone, so the frames share an order and the files form converts.
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SCENE, f)
            for out, extra in [("plain", ("--codec", "none")), ("draco", ("--draco",))]:
                r = wave("run", scene, "-o", os.path.join(d, out), "-q", "--form", "files", "--frames", "0:3", *extra)
                self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(d, "draco", "report-frames-0-3.json")) as f:
                surface = json.load(f)["surface"]
            self.assertIn("far_field", surface)
            validate_gltf(self, os.path.join(d, "draco", "frames", "frame-0001.glb"))
            looked = {}
            for out in ("plain", "draco"):
                r = wave("inspect", os.path.join(d, out, "frames", "frame-0001.glb"), "--json")
                self.assertEqual(r.returncode, 0, r.stderr)
                looked[out] = json.loads(r.stdout)
            self.assertEqual(looked["draco"]["vertices"], surface["vertices"])
            self.assertEqual(looked["draco"]["triangles"], surface["triangles"])
            self.assertEqual(looked["draco"]["unreferenced_vertices"], 0)
            self.assertEqual([loop["edges"] for loop in looked["draco"]["boundary"]["loops"]],
                             [loop["edges"] for loop in looked["plain"]["boundary"]["loops"]])
            r = wave("convert", os.path.join(d, "draco", "index.json"), "-o", os.path.join(d, "c"), "--form", "files")
            self.assertEqual(r.returncode, 0, r.stderr)
            got, reference = self.positions(os.path.join(d, "c")), self.positions(os.path.join(d, "plain"))
            for frame, want in zip(got, reference):
                self.assertEqual(len(frame), len(want))
                self.assertTrue(all(float(x * 256).is_integer() for x in frame), "a coordinate off the 2^-8 m lattice")
                # Draco reorders: each decoded point against the nearest reference point.
                worst, worst_inside = self.nearest_gaps(frame, want, lambda x, z: 1 < x < 99 and -89 < z < -1)
                self.assertLessEqual(worst, 2 ** -6)
                self.assertLessEqual(worst_inside, 2 ** -9)

    def test_draco_frames_of_a_laboratory_basin_keep_its_millimetre_waves(self):
        # The 1:400 Okushiri basin (5.5 m, waves of 4 mm): Draco takes no step finer than
        # 2^-6 of a file unit, which in metres flattened every wave (one height left in a
        # frame). Its frames are written in units of 2^-6 m and the node scales them back:
        # read back, the domain lies on the 2^-12 m lattice its 14 bits ask for, within half
        # a step of the plain run, and the waves keep their height.
        step = 2.0 ** -12
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(EXAMPLES, "okushiri.json")
            for out, extra in [("plain", ("--codec", "none")), ("draco", ("--draco",))]:
                r = wave("run", scene, "-o", os.path.join(d, out), "-q", "--form", "files", "--frames", "0:2", *extra)
                self.assertEqual(r.returncode, 0, r.stderr)
            validate_gltf(self, os.path.join(d, "draco", "frames", "frame-0001.glb"))
            r = wave("convert", os.path.join(d, "draco", "index.json"), "-o", os.path.join(d, "c"), "--form", "files")
            self.assertEqual(r.returncode, 0, r.stderr)
            got, reference = self.positions(os.path.join(d, "c"))[1], self.positions(os.path.join(d, "plain"))[1]
            inside = lambda x, z: 0.01 < x < 5.47 and -3.39 < z < -0.01  # glTF axes: the basin, off its border
            heights = {}
            for i in range(0, len(reference), 3):
                x, y, z = reference[i:i + 3]
                if inside(x, z):
                    heights[(round(x / step), round(z / step))] = y
            gaps, draco_heights = [], []
            for i in range(0, len(got), 3):
                x, y, z = got[i:i + 3]
                if not inside(x, z):
                    continue
                self.assertTrue(float(x / step).is_integer() and float(y / step).is_integer(), "off the 2^-12 m lattice")
                draco_heights.append(y)
                if (round(x / step), round(z / step)) in heights:
                    gaps.append(abs(y - heights[(round(x / step), round(z / step))]))
            self.assertGreater(len(gaps), len(heights) // 2)
            self.assertLessEqual(max(gaps), step / 2 + 1e-9)
            plain_heights = list(heights.values())
            def spread(v):
                mean = sum(v) / len(v)
                return math.sqrt(sum((h - mean) ** 2 for h in v) / len(v))
            self.assertGreater(spread(plain_heights), 1e-3)  # millimetre waves
            self.assertAlmostEqual(spread(draco_heights) / spread(plain_heights), 1.0, delta=0.03)

    def test_quantised_normals_read_back_as_unit_normals(self):
        # A quantised morph frame's normal is its int8 base plus an int16 delta, a few
        # thousandths off unit length: read back it is scaled to 1, so that a conversion
        # writes unit normals (the validator refused 38 of them in the quantised nodes
        # converted from the default run's 4 frames).
        with tempfile.TemporaryDirectory() as d:
            r = wave("run", "-o", os.path.join(d, "run"), "-q", "--frames", "0:4")  # the default: a quantised morph file
            self.assertEqual(r.returncode, 0, r.stderr)
            source = os.path.join(d, "run", "animation-frames-0-4.glb")
            for out, extra in [("plain", ()), ("quantised", ("--quantize",))]:
                r = wave("convert", source, "-o", os.path.join(d, out), "--form", "files", *extra)
                self.assertEqual(r.returncode, 0, r.stderr)
                validate_gltf(self, os.path.join(d, out, "frames", "frame-0002.glb"))
            with open(os.path.join(d, "plain", "index.json")) as f:
                index = json.load(f)
            for f in index["frames"]:
                doc, binary = read_glb(os.path.join(d, "plain", f["file"]))
                n = floats(doc, binary, doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"])
                worst = max(abs(math.sqrt(n[i] ** 2 + n[i + 1] ** 2 + n[i + 2] ** 2) - 1.0) for i in range(0, len(n), 3))
                self.assertLess(worst, 1e-6, f["file"])

    def test_quantised_frames_carry_the_far_field_as_a_float_skirt(self):
        # KHR_mesh_quantization's frames of their own (nodes, files) carry the skirt too
        # (docs/far-field.md, "Quantised frames"): the domain's primitive on int16 spanning
        # the domain only, the skirt's positions as floats in the same node frame, its seam
        # vertices equal to the domain's decoded int16. Read back, a frame is the plain
        # run's mesh: its vertex count, one boundary loop of the same length, every vertex
        # within half an int16 step of the plain run inside the bay (1.53 mm steps: 16 bits
        # over its 100 m, as without the skirt) and within float32's reach on the skirt
        # (80 km: 1 cm).
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SCENE, f)
            for out, extra in [("plain", ("--no-quantize", "--form", "files")), ("files", ("--quantize", "--form", "files")),
                               ("nodes", ("--quantize", "--form", "nodes"))]:
                r = wave("run", scene, "-o", os.path.join(d, out), "-q", "--frames", "0:3", *extra)
                self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(d, "files", "report-frames-0-3.json")) as f:
                surface = json.load(f)["surface"]
            self.assertIn("far_field", surface)
            files = [os.path.join(d, "files", "frames", "frame-0001.glb"), os.path.join(d, "nodes", "animation-frames-0-3.glb")]
            looked = {}
            for path in files + [os.path.join(d, "plain", "frames", "frame-0001.glb")]:
                validate_gltf(self, path)
                r = wave("inspect", path, "--json")
                self.assertEqual(r.returncode, 0, r.stderr)
                looked[path] = json.loads(r.stdout)
            plain = looked.pop(os.path.join(d, "plain", "frames", "frame-0001.glb"))
            for path, got in looked.items():
                doc, _ = read_glb(path)
                self.assertEqual(len(doc["meshes"][0]["primitives"]), 2, path)
                self.assertEqual((got["vertices"], got["triangles"], got["unreferenced_vertices"]),
                                 (surface["vertices"], surface["triangles"], 0), path)
                self.assertEqual([loop["edges"] for loop in got["boundary"]["loops"]],
                                 [loop["edges"] for loop in plain["boundary"]["loops"]], path)
            r = wave("convert", os.path.join(d, "files", "index.json"), "-o", os.path.join(d, "c"), "--form", "files")
            self.assertEqual(r.returncode, 0, r.stderr)
            got, reference = self.positions(os.path.join(d, "c")), self.positions(os.path.join(d, "plain"))
            for frame, want in zip(got, reference):
                self.assertEqual(len(frame), len(want))
                # The joined mesh lists the domain's vertices first: each against the nearest reference.
                worst, worst_inside = self.nearest_gaps(frame, want, lambda x, z: 0 <= x <= 100 and -90 <= z <= 0)
                self.assertLessEqual(worst, 1e-2)
                self.assertLessEqual(worst_inside, 100 / 65534 / 2 + 2e-5)

    def test_what_cannot_be_converted_exits_2_without_output(self):
        with tempfile.TemporaryDirectory() as d:
            scene = os.path.join(d, "s.json")
            with open(scene, "w") as f:
                json.dump(self.SCENE, f)
            self.assertEqual(wave("run", scene, "-o", os.path.join(d, "df"), "-q", "--form", "files", "--draco").returncode, 0)
            # Draco frames of another mesh (a shorter skirt) in one index: other orders.
            with open(scene, "w") as f:
                json.dump({**self.SCENE, "surface": {"far_field": {"distance": 5000}}}, f)
            self.assertEqual(wave("run", scene, "-o", os.path.join(d, "d3"), "-q", "--form", "files", "--draco",
                                  "--frames", "0:2").returncode, 0)
            with open(os.path.join(d, "df", "index.json")) as f:
                index = json.load(f)
            # (copied into df: an index names only files inside its own folder)
            shutil.copy(os.path.join(d, "d3", index["frames"][1]["file"]), os.path.join(d, "df", "d3-frame-0001.glb"))
            index["frames"][1]["file"] = "d3-frame-0001.glb"
            index["frames"][1]["content"] = [{**c, "file": index["frames"][1]["file"]} for c in index["frames"][1]["content"]]
            mixed = os.path.join(d, "df", "mixed.json")
            with open(mixed, "w") as f:
                json.dump(index, f)
            foreign = os.path.join(d, "foreign.glb")
            with open(os.path.join(d, "df", "frames", "frame-0000.glb"), "rb") as f:
                data = f.read()
            with open(foreign, "wb") as f:  # the same bytes without libwave's asset extras
                f.write(data.replace(b'"extras":{"libwave"', b'"extrax":{"libwave"'))
            for src, part in [(mixed, "Draco-compressed frames of different orders"),
                              (foreign, "not written by libwave"),
                              (os.path.join(d, "missing.glb"), "file not found"),
                              (scene, "not a frame index")]:
                r = wave("convert", src, "-o", os.path.join(d, "out"))
                self.assertEqual(r.returncode, 2, src + r.stderr)
                self.assertIn(part, r.stderr)
                self.assertFalse(os.path.exists(os.path.join(d, "out")))


def plain_array(doc, binary, accessor, code):
    """A tightly packed accessor's values (float32 'f', or an index type) as an array."""
    a = doc["accessors"][accessor]
    view = doc["bufferViews"][a["bufferView"]]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[a["type"]]
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    values = array.array(code)
    values.frombytes(binary[start:start + a["count"] * width * values.itemsize])
    return values


def plan_mesh(doc, binary, name):
    """A mesh's rest positions in plan, libwave's (x, y) from glTF's (x, −z), its heights
    and its triangles; None where the file has no such mesh."""
    mesh = next((m for m in doc["meshes"] if m["name"] == name), None)
    if mesh is None:
        return None
    prim = mesh["primitives"][0]
    g = plain_array(doc, binary, prim["attributes"]["POSITION"], "f")
    code = {5125: "I", 5123: "H"}[doc["accessors"][prim["indices"]]["componentType"]]
    return list(zip(g[0::3], [-v for v in g[2::3]])), g[1::3], plain_array(doc, binary, prim["indices"], code)


def covering(points, plan, triangles, within):
    """For each point on the circle `within` (centre, radius), the barycentric (triangle,
    weights) of a triangle of the mesh that covers it, or None."""
    (cx, cy), radius = within
    found = [None] * len(points)
    # A triangle that covers a point on the circle has a corner on it or beyond.
    beyond = [math.hypot(x - cx, y - cy) >= radius for x, y in plan]
    for t in range(0, len(triangles), 3):
        if not (beyond[triangles[t]] or beyond[triangles[t + 1]] or beyond[triangles[t + 2]]):
            continue
        a, b, c = plan[triangles[t]], plan[triangles[t + 1]], plan[triangles[t + 2]]
        x0, x1 = min(a[0], b[0], c[0]), max(a[0], b[0], c[0])
        y0, y1 = min(a[1], b[1], c[1]), max(a[1], b[1], c[1])
        if math.hypot(min(max(cx, x0), x1) - cx, min(max(cy, y0), y1) - cy) > radius:
            continue
        det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if det == 0.0:
            continue
        for i, (px, py) in enumerate(points):
            if found[i] is None and x0 <= px <= x1 and y0 <= py <= y1:
                u = ((px - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (py - a[1])) / det
                v = ((b[0] - a[0]) * (py - a[1]) - (px - a[0]) * (b[1] - a[1])) / det
                if u >= -1e-9 and v >= -1e-9 and u + v <= 1.0 + 1e-9:
                    found[i] = (t, (1.0 - u - v, u, v))
    return found


def morph_frame(doc, binary, name, frame):
    """A morph mesh's positions at `frame` (libwave's x, y, z: glTF's x, −z, y)."""
    prim = next(m for m in doc["meshes"] if m["name"] == name)["primitives"][0]
    base = floats(doc, binary, prim["attributes"]["POSITION"])
    delta = floats(doc, binary, prim["targets"][frame]["POSITION"])
    return [(base[i] + delta[i], -(base[i + 2] + delta[i + 2]), base[i + 1] + delta[i + 1]) for i in range(0, len(base), 3)]


class MeshHeights:
    """Heights of a triangle mesh under points in plan (None off it): a bucket grid."""

    def __init__(self, plan, height, triangles, cell):
        self.plan, self.height, self.triangles, self.cell, self.buckets = plan, height, triangles, cell, {}
        for t in range(0, len(triangles), 3):
            xs = [plan[triangles[t + i]][0] for i in range(3)]
            ys = [plan[triangles[t + i]][1] for i in range(3)]
            if max(max(xs) - min(xs), max(ys) - min(ys)) > 20 * cell:
                continue  # the apron's far triangles: never under the water's shore
            for i in range(int(min(xs) // cell), int(max(xs) // cell) + 1):
                for j in range(int(min(ys) // cell), int(max(ys) // cell) + 1):
                    self.buckets.setdefault((i, j), []).append(t)

    def at(self, x, y):
        for t in self.buckets.get((int(x // self.cell), int(y // self.cell)), ()):
            (ax, ay), (bx, by), (cx, cy) = (self.plan[self.triangles[t + i]] for i in range(3))
            det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
            if det == 0.0:
                continue
            u = ((x - ax) * (cy - ay) - (cx - ax) * (y - ay)) / det
            v = ((bx - ax) * (y - ay) - (x - ax) * (by - ay)) / det
            if u >= -1e-9 and v >= -1e-9 and u + v <= 1.0 + 1e-9:
                h = self.height
                return (1.0 - u - v) * h[self.triangles[t]] + u * h[self.triangles[t + 1]] + v * h[self.triangles[t + 2]]
        return None


def waterline_defects(glb, frames):
    """Per frame, on the domain's water (the seafloor's grid rectangle) within 1 m of
    still-water depth of the shore: (shore vertices not under the seafloor, wet vertices
    cut off from the sea). The shore vertices are the water mesh's border that is not on
    the rectangle; a vertex is wet when it stands above the exported seafloor at its
    moved position; cut off when no path of wet vertices along the mesh's edges joins it
    to water a metre deep."""
    doc, binary = read_glb(glb)
    water, floor = plan_mesh(doc, binary, "water"), plan_mesh(doc, binary, "seafloor")
    floor_z = MeshHeights(floor[0], floor[1], floor[2], 0.5)
    plan, _, tris = water
    grid = [p for p in floor[0] if abs(p[0]) < 1e4 and abs(p[1]) < 1e4]
    x0, x1 = min(p[0] for p in grid), max(p[0] for p in grid)
    y0, y1 = min(p[1] for p in grid), max(p[1] for p in grid)
    inside = [x0 < x < x1 and y0 < y < y1 for x, y in plan]
    rest_floor = [floor_z.at(x, y) if inside[v] else None for v, (x, y) in enumerate(plan)]
    band = [z is not None and z > -1.0 for z in rest_floor]
    edges, uses = {}, {}
    for t in range(0, len(tris), 3):
        for i in range(3):
            a, b = tris[t + i], tris[t + (i + 1) % 3]
            uses[(min(a, b), max(a, b))] = uses.get((min(a, b), max(a, b)), 0) + 1
            edges.setdefault(a, set()).add(b)
            edges.setdefault(b, set()).add(a)
    shore = sorted({v for e, n in uses.items() if n == 1 for v in e if inside[v]})
    out = []
    for f in frames:
        moved = morph_frame(doc, binary, "water", f)
        wet = {}
        for v in range(len(plan)):
            if band[v]:
                z = floor_z.at(moved[v][0], moved[v][1])
                wet[v] = z is not None and moved[v][2] > z
        exposed = sum(1 for v in shore if band[v] and wet[v])
        # flood from the band's wet vertices next to deeper water
        seen = [v for v in wet if wet[v] and any(u not in wet and rest_floor[u] is not None for u in edges[v])]
        reached = set(seen)
        while seen:
            v = seen.pop()
            for u in edges[v]:
                if wet.get(u) and u not in reached:
                    reached.add(u)
                    seen.append(u)
        out.append((exposed, sum(1 for v in wet if wet[v] and v not in reached)))
    return out


class Waterline(unittest.TestCase):
    """The water meets the beach without a saw-tooth or flakes (issue 66)."""

    def test_the_bays_shore_lies_under_the_sand_and_no_water_is_cut_off(self):
        # The water mesh's shoreline vertices stood level with the sand (within 1e-7 m):
        # the mesh's edge, straight chords between points of the sliced contour, dipped in
        # and out of the seafloor's triangles — a saw-tooth a shore edge long — and in the
        # swash the troughs went under the sand in patches between that edge and the sea,
        # leaving strips of water on the sand (233–257 exposed shore vertices and 7–13
        # vertices of water cut off from the sea per frame; now none).
        with tempfile.TemporaryDirectory() as d:
            scene = write_scene(d, dict(OLD_DEFAULT, animation={"fps": 2}, outputs={}))
            r = wave("run", scene, "-q", "-o", os.path.join(d, "out"), "--codec", "none")
            self.assertEqual(r.returncode, 0, r.stderr)
            defects = waterline_defects(os.path.join(d, "out", "animation.glb"), range(10))
        for f, (exposed, cut_off) in enumerate(defects):
            self.assertEqual(exposed, 0, ("shore vertices above the sand", f))
            self.assertEqual(cut_off, 0, ("water cut off from the sea", f))


class World(unittest.TestCase):
    """A world, not a box (issue 66): the sea and the land round every example."""

    def test_every_example_has_sea_or_land_5_km_round_its_centre(self):
        # Each example's exported seafloor (the grid and the terrain beyond it) has no
        # border above still water within 5 km of its centre: its land goes on, never
        # ending on a cut or a wall in view. And 5 km out in every direction (a point a
        # degree) lies the water mesh (the far field's skirt, or the open ocean's tiles),
        # or land: before, the open ocean's patch ended at 500 m and a laboratory basin's
        # skirt 55 m beyond its walls, and the bay's land apron was a plain that the
        # skirt's cut ended.
        reach = 5000.0
        with tempfile.TemporaryDirectory() as d:
            for example in sorted(os.listdir(EXAMPLES)):
                if not example.endswith(".json"):
                    continue
                with self.subTest(example=example):
                    out = os.path.join(d, example)
                    r = wave("run", os.path.join(EXAMPLES, example), "-q", "-o", out, "--frames", "0:1", "--form", "morph",
                             "--codec", "none")
                    self.assertEqual(r.returncode, 0, example + r.stderr)
                    doc, binary = read_glb(os.path.join(out, "animation-frames-0-1.glb"))
                    water, floor = plan_mesh(doc, binary, "water"), plan_mesh(doc, binary, "seafloor")
                    box = floor[0] if floor else water[0]
                    centre = ((min(p[0] for p in box) + max(p[0] for p in box)) / 2, (min(p[1] for p in box) + max(p[1] for p in box)) / 2)
                    if floor:
                        plan, height, triangles = floor
                        uses = {}
                        for t in range(0, len(triangles), 3):
                            for i in range(3):
                                e = tuple(sorted((triangles[t + i], triangles[t + (i + 1) % 3])))
                                uses[e] = uses.get(e, 0) + 1
                        for e, n in uses.items():
                            if n == 1 and max(height[e[0]], height[e[1]]) > 0.0:
                                near = min(math.dist(plan[v], centre) for v in e)
                                self.assertGreaterEqual(near, reach, (example, plan[e[0]], plan[e[1]]))
                    ring = [(centre[0] + reach * math.cos(math.radians(k)), centre[1] + reach * math.sin(math.radians(k))) for k in range(360)]
                    wet = covering(ring, water[0], water[2], (centre, reach))
                    land = covering(ring, floor[0], floor[2], (centre, reach)) if floor else [None] * len(ring)
                    for k, p in enumerate(ring):
                        if wet[k] is not None:
                            continue
                        self.assertIsNotNone(land[k], (example, k, "neither water nor land"))
                        t, w = land[k]
                        z = sum(w[i] * floor[1][floor[2][t + i]] for i in range(3))
                        self.assertGreater(z, 0.0, (example, k, "sea bottom without water"))


skip_what_the_sanitizers_reach_elsewhere("cli", globals())

if __name__ == "__main__":
    unittest.main(verbosity=2)
