"""`import libwave` stage by stage: the stage functions give `wave run`'s frame bit for
bit (examples/pipeline.py), the Scene round-trips through a dict and is edited key by key
with the scene file's checks, every exception is a libwave.Error, and the stubs match the
module (mypy's stubtest, Debian's python3-mypy)."""
import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import libwave

REPO = pathlib.Path(__file__).resolve().parents[2]
OKUSHIRI = REPO / "data" / "bathymetry" / "okushiri_monai_lab1to400_1p4cm.asc"


def run_example(tmp_path, frame):
    out = tmp_path / "frame.glb"
    r = subprocess.run([sys.executable, str(REPO / "examples" / "pipeline.py"), str(OKUSHIRI), str(out), str(frame)],
                       capture_output=True, text=True, env=os.environ)
    return r, out


def test_the_pipeline_example_equals_wave_run_frame_bit_for_bit(tmp_path):
    r, out = run_example(tmp_path, 3)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "bit for bit" in r.stdout
    # The same scene through `wave run`, frame 3 alone in the files form.
    spec = {"name": "pipeline example", "seafloor": {"source": str(OKUSHIRI)}, "isobaths": {"spacing": 0.01},
            "waves": [{"period": 0.6, "amplitude": 0.004, "direction": [1.0, 0.15]}], "trace": {"ray_spacing": 0.02},
            "fronts": {"step": 0.01, "split_distance": 0.03}, "camera": {"position": [2.5, -2.0, 1.2]},
            "animation": {"fps": 25}, "outputs": {"form": "files"}}
    (tmp_path / "s.json").write_text(json.dumps(spec))
    subprocess.run([os.environ["WAVE_EXE"], "run", str(tmp_path / "s.json"), "-o", str(tmp_path / "run"), "--frames", "3:4",
                    "--codec", "none"], check=True, capture_output=True)  # floats, as the stages write them
    frames = sorted((tmp_path / "run").rglob("frame-*.glb"))
    assert len(frames) == 1, frames
    theirs, ours = libwave.read_animation(str(frames[0])), libwave.read_animation(str(out))
    for key in ("positions", "foam", "reflect", "refract", "triangles"):
        assert theirs[key].tobytes() == ours[key].tobytes(), key
    assert ours["first_frame"] == 3 and theirs["first_frame"] == 3


def test_stage_objects_expose_their_arrays():
    sea = libwave.procedural_seafloor("gonzato-bay")
    assert sea.elevation.ndim == 2 and sea.elevation.dtype == np.float64
    st = sea.stats()
    assert st["depth_max"] > 0 and 0 < st["land_fraction"] < 1
    assert np.allclose(sea.depth_at(np.array([50.0]), np.array([10.0])), -sea.elevation[10, 50], atol=1e-9)
    iso = libwave.extract_isobaths(sea, spacing=1.0)
    assert len(iso) > 0 and iso.polyline(0).shape[1] == 2 and 0.0 in list(iso.depths)
    fronts = libwave.trace_fronts(sea, 5.0, 0.3, (0, 1), ray_spacing=2, step=0.8, split_distance=2.4)
    assert fronts.front_count > 10 and len(fronts.x) == fronts.front_offsets[-1]
    # Per ray id; the bay's swell enters across its deep edge unbroken.
    assert len(fronts.entry_break_phase) == fronts.initial_rays + fronts.inserted_rays
    assert np.isnan(fronts.entry_break_phase).all()
    strips = libwave.build_ray_strips(fronts)
    assert strips.triangles.shape[1] == 3 and strips.triangles.max() < strips.vertex_count
    motion = libwave.plan_gonzato_motion(strips)
    out = np.zeros((strips.vertex_count, 3), np.float32)
    assert motion.evaluate(1.0, out) is not None and np.abs(out).max() > 0
    assert np.array_equal(out, motion.evaluate(1.0))  # into a caller's buffer, the same values
    # A buffer of the wrong type or size: libwave's errors (still a TypeError and a
    # ValueError), naming the argument.
    with pytest.raises(libwave.ArgumentTypeError, match="evaluate out: expected a writable C-contiguous float32 array, got float64"):
        motion.evaluate(1.0, np.zeros((strips.vertex_count, 3)))  # float64: not a frame buffer
    with pytest.raises(libwave.ArgumentTypeError, match="evaluate out: .*, got list"):
        motion.evaluate(1.0, [0.0] * (3 * strips.vertex_count))
    with pytest.raises(libwave.InputError, match=r"evaluate out: expected \d+ values, got 9 \(shape \(3, 3\)\)"):
        motion.evaluate(1.0, np.zeros((3, 3), np.float32))


def test_untangling_holds_the_water_meshs_shore():
    # The bay's water mesh pushed towards the beach (+y), foamy: the water 1 m, its edge
    # 0.3 m. A breaking crest may overturn, but the shore vertices keep their rest
    # position in plan and no triangle with one faces down; with hold_shore=False the
    # edge moves and the water runs over it.
    sea = libwave.procedural_seafloor("gonzato-bay")
    mesh = libwave.mesh_water(sea, 5.0, 0.3, per_wavelength=8)
    x, y, tri = mesh.x, mesh.y, mesh.triangles
    side = (x == x.min()) | (x == x.max()) | (y == y.min()) | (y == y.max())
    shore = (mesh.boundary != 0) & ~side
    assert shore.sum() > 50
    rest = np.stack([x, y, np.zeros_like(x)], axis=1).astype(np.float32)
    foam = np.ones(len(x), np.float32)
    held = {}
    for hold in (True, False):
        p = rest.copy()
        p[:, 1] += np.where(shore, 0.3, 1.0).astype(np.float32)
        libwave.plan_untangle(x, y, tri, hold_shore=hold).apply(p, foam)
        a = p[tri]
        area = (a[:, 1, 0] - a[:, 0, 0]) * (a[:, 2, 1] - a[:, 0, 1]) - (a[:, 1, 1] - a[:, 0, 1]) * (a[:, 2, 0] - a[:, 0, 0])
        on_shore = shore[tri].any(axis=1)
        held[hold] = (np.array_equal(p[shore, :2], rest[shore, :2]), int((area[on_shore] < 0).sum()))
    assert held[True] == (True, 0)
    assert held[False][0] is False and held[False][1] > 0


def _smallest_angles(p, tri):
    a = p[tri].astype(np.float64)
    out = []
    for i in range(3):
        u, w = a[:, (i + 1) % 3] - a[:, i], a[:, (i + 2) % 3] - a[:, i]
        out.append(np.degrees(np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), (u * w).sum(axis=1))))
    return np.min(out, axis=0)


def test_untangling_keeps_the_smallest_angle_it_is_given():
    # A 0.5 m grid squeezed to 0.55 along x and stretched 2.4 × along y about its centre:
    # within the area's and the stretch's bounds, but its 45° angles go to 12.9°. With
    # the default bound every triangle keeps 16°; with 0, none is touched.
    n = 12
    x, y = [a.ravel().astype(np.float64) for a in np.meshgrid(np.arange(n), np.arange(n))]
    tri = libwave.grid_triangles(n, n)
    rest = np.stack([x, y, np.full_like(x, 0.1)], axis=1).astype(np.float32)
    moved = rest.copy()
    moved[:, 0] -= (0.45 * (x - 5.5)).astype(np.float32)
    moved[:, 1] += (1.4 * (y - 5.5)).astype(np.float32)
    free = moved.copy()
    libwave.plan_untangle(x, y, tri, pin_border=False, hold_shore=False, min_angle_degrees=0).apply(free)
    assert np.array_equal(free, moved)
    assert abs(_smallest_angles(free, tri).min() - np.degrees(np.arctan(0.55 / 2.4))) < 1e-3
    bounded = moved.copy()
    libwave.plan_untangle(x, y, tri, pin_border=False, hold_shore=False).apply(bounded)
    assert _smallest_angles(bounded, tri).min() > 16.0
    assert np.array_equal(bounded[:, 2], moved[:, 2])  # heights kept
    with pytest.raises(libwave.InputError, match="min_angle_degrees"):
        libwave.plan_untangle(x, y, tri, min_angle_degrees=60)


def test_a_whole_side_inside_the_given_domain_is_held_as_shore():
    # A 1 m grid shifted 0.3 m along x: its top row (y = 7) slides along itself as a side
    # of its bounding rectangle, but with the domain reaching on to y = 20 it is a shore
    # and holds still.
    n = 8
    x, y = [a.ravel().astype(np.float64) for a in np.meshgrid(np.arange(n), np.arange(n))]
    tri = libwave.grid_triangles(n, n)
    moved = np.stack([x + 0.3, y, np.zeros_like(x)], axis=1).astype(np.float32)
    top = y == 7
    side = moved.copy()
    libwave.plan_untangle(x, y, tri).apply(side)
    inner = top & (x > 0) & (x < 7)  # the corners do not move sideways either way
    assert np.all(side[inner, 0] != x[inner])
    shore = moved.copy()
    libwave.plan_untangle(x, y, tri, border_rectangle=(0.0, 0.0, 7.0, 20.0)).apply(shore)
    assert np.array_equal(shore[top, 0], x[top].astype(np.float32))
    with pytest.raises(libwave.InputError, match="border_rectangle"):
        libwave.plan_untangle(x, y, tri, border_rectangle=(0.0, 0.0, 6.0, 20.0))


def test_scene_round_trips_through_a_dict_and_is_edited_with_the_files_checks():
    doc = {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2}}
    s = libwave.Scene(doc)
    assert s.to_dict() == doc
    again = libwave.Scene(s.to_dict(), s.base_dir)
    assert again.to_dict() == doc and again.name == s.name
    s.set("/waves/0/period", 8.0)
    assert s.get("/waves/0/period") == 8.0 and s.to_dict()["waves"][0]["period"] == 8.0
    s.set("/animation", {"fps": 12})
    assert s.fps == 12
    # A str is the JSON string it says (the docstring's own example), not JSON text.
    s.set("/outputs/form", "files")
    assert s.get("/outputs/form") == "files" and s.to_dict()["outputs"]["form"] == "files"
    s.set("/outputs/codec", "meshopt")
    assert s.to_dict()["outputs"]["codec"] == "meshopt"
    with pytest.raises(libwave.InputError, match="/outputs/codec"):
        s.set("/outputs/codec", "zip")
    with pytest.raises(libwave.InputError, match=r"/waves/0/period.*-1"):
        s.set("/waves/0/period", -1)
    assert s.get("/waves/0/period") == 8.0  # unchanged by the refused edit
    with pytest.raises(libwave.InputError, match="not set"):
        s.get("/refine")
    # The default scene is a document too.
    d = libwave.default_scene()
    assert d.to_dict()["seafloor"]["source"] == "gonzato-bay"
    assert libwave.Scene(d.to_dict()).name == d.name


def test_every_failure_is_a_libwave_error():
    assert issubclass(libwave.InputError, libwave.Error) and issubclass(libwave.LimitError, libwave.Error)
    assert issubclass(libwave.InputError, ValueError)
    with pytest.raises(libwave.Error):
        libwave.read_seafloor("/nonexistent/seafloor.asc")
    with pytest.raises(libwave.Error, match="refraction"):
        libwave.trace_fronts(libwave.procedural_seafloor("gonzato-bay"), 5, 0.3, (0, 1), refraction="snell")
    with pytest.raises(libwave.Error, match="max_turn_degrees"):
        libwave.trace_fronts(libwave.procedural_seafloor("gonzato-bay"), 5, 0.3, (0, 1), max_turn_degrees=1000)


@pytest.mark.skipif(shutil.which("stubgen") is None and subprocess.run([sys.executable, "-c", "import mypy"]).returncode,
                    reason="mypy (python3-mypy) is not installed")
def test_stubs_match_the_module_and_type_check_the_example(tmp_path):
    env = dict(os.environ, MYPYPATH=os.environ["PYTHONPATH"])
    stubtest = subprocess.run([sys.executable, "-m", "mypy.stubtest", "libwave._libwave", "--allowlist",
                               str(pathlib.Path(__file__).with_name("stubtest-allowlist.txt"))],
                              capture_output=True, text=True, env=env)
    assert stubtest.returncode == 0, stubtest.stdout + stubtest.stderr
    mypy = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", "/dev/null",
                           str(REPO / "examples" / "pipeline.py")], capture_output=True, text=True, env=env)
    assert mypy.returncode == 0, mypy.stdout + mypy.stderr
    # What the stubs say: arrays with their dtypes (none is NDArray[Any]), array arguments
    # as ArrayLike and arrays written in place as float32 arrays, static methods as such,
    # and a class without a constructor refused by the type checker as at run time.
    stubs = (pathlib.Path(os.environ["PYTHONPATH"]) / "libwave" / "_libwave.pyi").read_text()
    assert "NDArray[Any]" not in stubs
    assert "def plan_untangle(x: numpy.typing.ArrayLike, y: numpy.typing.ArrayLike, triangles: numpy.typing.ArrayLike," in stubs
    assert "def apply(self, positions: numpy.typing.NDArray[numpy.float32]) -> None:" in stubs  # Waterline.apply writes
    assert "    @staticmethod\n    def from_grid(values: numpy.typing.ArrayLike," in stubs
    probe = tmp_path / "probe.py"
    probe.write_text("import libwave\nfloor = libwave.Seafloor()\n")
    mypy = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir", "/dev/null", str(probe)],
                          capture_output=True, text=True, env=env)
    assert 'probe.py:2: error: Too few arguments for "Seafloor"' in mypy.stdout, mypy.stdout + mypy.stderr
    with pytest.raises(TypeError, match="No constructor"):
        libwave.Seafloor()


def test_every_function_and_method_has_a_signature():
    """inspect.signature reads every public function and method (it failed on all of
    them: pybind11 writes signatures only into the docstring's first line), with
    pybind11's names and defaults; __doc__ keeps that typed line."""
    import inspect
    checked = 0
    for name, obj in vars(libwave._libwave).items():
        if name.startswith("_"):
            continue
        members = [obj]
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            members = [getattr(obj, k) for k, v in vars(obj).items() if (k == "__init__" or not k.startswith("_")) and not isinstance(v, property)]
        for f in members:
            if callable(f) and not inspect.isclass(f):
                inspect.signature(f)  # raises ValueError without one
                checked += 1
    assert checked > 70
    assert str(inspect.signature(libwave.plan)) == "(scene, seafloor=None)"
    assert str(inspect.signature(libwave.Scene.set)) == "(self, pointer, value)"
    assert str(inspect.signature(libwave.default_scene().set)) == "(pointer, value)"
    assert str(inspect.signature(libwave.Seafloor.from_triangles)) == "(vertices, indices, spacing=0.0, sign=None, vertical_offset=0.0, name='')"
    assert "frame=0" in str(inspect.signature(libwave.frame_glb))
    assert str(inspect.signature(libwave.Scene)) == "(document, base_dir='.')"
    assert libwave.plan.__doc__.startswith("plan(scene: libwave._libwave.Scene, seafloor:")


def test_the_ocean_patch_stage_equals_the_ocean_scenes_frame():
    scene = libwave.Scene({"surface": {"kind": "ocean"}, "animation": {"fps": 10},
                           "ocean": {"resolution": 32, "size": 100, "wind_speed": 12, "repeat_time": 4},
                           "outputs": {"attributes": "none"}})
    anim = libwave.animate(scene, libwave.plan(scene), 3, 4)
    patch = libwave.plan_ocean_patch(resolution=32, size=100, wind_speed=12, repeat_time=4)
    positions, normals, j_minus = patch.evaluate(0.3)
    assert positions.shape == (33 * 33, 3) and j_minus.shape == (33 * 33,)
    # The scene's surface is the patch, then the skirt that carries it to the horizon.
    assert positions.tobytes() == np.asarray(anim.positions[0])[:33 * 33].tobytes()
    triangles = libwave.grid_triangles(33, 33)
    assert np.array_equal(triangles, np.asarray(anim.triangles)[:len(triangles)])
    # The patch tiles: the last column repeats the first, one patch further along x.
    grid = positions.reshape(33, 33, 3)
    assert np.allclose(grid[:, 32, 0] - grid[:, 0, 0], 100.0, atol=1e-3)
    assert np.array_equal(grid[:, 32, 2], grid[:, 0, 2])


def test_jeschke_breakers_and_rays_as_stages():
    beach = libwave.procedural_seafloor("planar-beach")
    fronts = libwave.trace_fronts(beach, 8.0, 0.5, (0, 1), ray_spacing=4, step=2, split_distance=8)
    strips = libwave.build_ray_strips(fronts)
    breakers = libwave.plan_jeschke_breakers(strips, 8.0, 0.5)
    assert breakers.vertex_count == strips.vertex_count and breakers.loop_periods == 3
    p = breakers.evaluate(2.0)
    foam = breakers.foam(30.0)
    assert p.shape == (strips.vertex_count, 3) and np.isfinite(p).all()
    assert 0.0 <= foam.min() and foam.max() <= 1.0 and foam.max() > 0.5  # broken crests leave foam
    # A breaking crest stands higher than the offshore swell (shoaling, then the breaker).
    assert p[:, 2].max() > 0.5
    # The outer section (the default) moves vertices along their rays only on steep faces:
    # at most 0.30 m over the 24 s loop, where the paper's tube ("lip": "tube") throws its
    # lips 3.5 m ahead.
    tube = libwave.plan_jeschke_breakers(strips, 8.0, 0.5, lip="tube")
    rest = np.stack([strips.x, strips.y], 1)
    def farthest(b):
        return max(np.hypot(*(b.evaluate(t)[:, :2] - rest).T).max() for t in np.arange(0.0, 24.0, 0.25))
    assert farthest(breakers) < 0.5 and farthest(tube) > 3.0
    with pytest.raises(libwave.InputError, match="lip"):
        libwave.plan_jeschke_breakers(strips, 8.0, 0.5, lip="barrel")
    # Their whitewater: the same particles for the same time, thrown in the surf zone only.
    w = breakers.whitewater(strips.triangles, 30.0)
    again = breakers.whitewater(strips.triangles, 30.0)
    assert len(w["kind"]) > 100 and w["positions"].tobytes() == again["positions"].tobytes()
    assert set(np.unique(w["kind"])) <= {0, 1, 2} and (w["size"] > 0).all() and (w["age"] >= 0).all()
    assert w["positions"][:, 1].min() > strips.y.min() + 0.3 * (strips.y.max() - strips.y.min())  # not offshore
    iso = libwave.extract_isobaths(beach, spacing=1.0)
    rays = libwave.trace_rays(beach, iso, 8.0, 0.5, (0, 1), ray_spacing=10)
    assert rays.ray_count > 5 and len(rays.x) == rays.offsets[-1]
    assert np.nanmax(rays.amplitude) > 0.5  # shoaling raises the deep-water amplitude before the break


def test_a_seafloor_from_arrays_equals_the_one_read_from_its_file():
    # The Okushiri basin read from its ESRI grid, and the same values handed over as a
    # NumPy array with the reader's origin and spacing: the same depths everywhere (no
    # half-cell shift), as a depth grid too; a mesh from vertex/index arrays resamples
    # as a mesh file does; bad arrays are libwave errors naming what is wrong.
    read = libwave.read_seafloor(str(OKUSHIRI))
    z = np.array(read.elevation)
    mine = libwave.seafloor_from_grid(z, origin=read.origin, spacing=read.spacing)
    depths = libwave.seafloor_from_grid(-z, origin=read.origin, spacing=read.spacing[0], sign="depth")
    rng = np.random.default_rng(1)
    (x0, y0), (dx, dy) = read.origin, read.spacing
    x = rng.uniform(x0, x0 + dx * (z.shape[1] - 1), 500)
    y = rng.uniform(y0, y0 + dy * (z.shape[0] - 1), 500)
    assert np.array_equal(mine.depth_at(x, y), read.depth_at(x, y))
    assert np.array_equal(depths.depth_at(x, y), read.depth_at(x, y))
    masked = libwave.seafloor_from_grid(z, origin=read.origin, spacing=read.spacing, mask=z > 0.1)
    assert masked.stats()["nodata_count"] == int((z > 0.1).sum()) > 0
    # A plane as a mesh of two triangles: the grid it resamples to holds the plane.
    vertices = np.array([[0, 0, -2.0], [10, 0, -1.0], [10, 10, -1.0], [0, 10, -2.0]])
    plane = libwave.seafloor_from_mesh(vertices, [[0, 1, 2], [0, 2, 3]], spacing=1.0)
    assert np.allclose(plane.depth_at(np.array([2.5, 7.5]), np.array([5.0, 1.0])), [1.75, 1.25])
    for call, match in [(lambda: libwave.seafloor_from_grid(z[0]), "2-D"),
                        (lambda: libwave.seafloor_from_grid(z, spacing=0.0), "spacing along x"),
                        (lambda: libwave.seafloor_from_grid(z, spacing="a"), "spacing"),
                        (lambda: libwave.seafloor_from_grid(np.full((3, 3), np.nan)), "not a finite elevation"),
                        (lambda: libwave.seafloor_from_grid(z, mask=np.zeros((2, 2), bool)), "mask"),
                        (lambda: libwave.seafloor_from_mesh(vertices[:, :2], [[0, 1, 2]]), r"\(n, 3\)"),
                        (lambda: libwave.seafloor_from_mesh(vertices, [[0, 1, 7]]), "names vertex 7")]:
        with pytest.raises(libwave.InputError, match=match):
            call()


def test_array_arguments_of_a_wrong_shape_or_type_raise_libwave_errors_naming_them():
    """Shapes and types of the stage functions' arrays are the caller's input: an
    InputError (a ValueError) for a shape or length, an ArgumentTypeError (an InputError
    that is also a TypeError) for what is not an array of numbers — each naming the
    function and the argument — never pybind11's bare TypeError or a silent reshape."""
    assert issubclass(libwave.ArgumentTypeError, libwave.InputError) and issubclass(libwave.ArgumentTypeError, TypeError)
    pos = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    tri = np.array([[0, 1, 2]], np.uint32)
    assert libwave.vertex_normals(pos, tri).shape == (3, 3)
    assert libwave.vertex_normals(pos.ravel(), tri.ravel().tolist()).shape == (3, 3)  # flat and lists still do
    bad = [
        (lambda: libwave.vertex_normals([["a", "b", "c"]] * 3, tri), libwave.ArgumentTypeError,
         "vertex_normals positions: expected an array of numbers, got list"),
        (lambda: libwave.vertex_normals(np.array([["1", "2", "3"]] * 3), tri), libwave.ArgumentTypeError,
         "vertex_normals positions: expected an array of numbers, got an array of <U1"),
        (lambda: libwave.vertex_normals(pos, {"x": 1}), libwave.ArgumentTypeError,
         "vertex_normals triangles: expected an array of numbers, got dict"),
        (lambda: libwave.vertex_normals(pos, None), libwave.ArgumentTypeError, "vertex_normals triangles: expected an array of numbers"),
        # (2, 6) holds a multiple of 3 values: it was read as four (x, y, z) in silence.
        (lambda: libwave.vertex_normals(np.zeros((2, 6), np.float32), tri), libwave.InputError,
         r"vertex_normals positions: expected shape \(n, 3\) or a flat array, got \(2, 6\)"),
        (lambda: libwave.vertex_normals(pos, np.array([[0, 1, 2, 0]])), libwave.InputError,
         r"vertex_normals triangles: expected shape \(n, 3\) or a flat array, got \(1, 4\)"),
        (lambda: libwave.vertex_normals(pos.ravel()[:8], tri), libwave.InputError,
         "vertex_normals positions: expected 3 values per item, got 8 values"),
        (lambda: libwave.fresnel_weights(pos, np.zeros((3, 3, 1)), (0, 0, 5), "exact"), libwave.InputError,
         r"fresnel_weights normals: expected shape \(n, 3\) or a flat array, got \(3, 3, 1\)"),
        (lambda: libwave.frame_glb(pos, pos, tri, foam=["x", "y", "z"]), libwave.ArgumentTypeError, "frame_glb foam"),
        # pybind11's own refusals (no overload takes the arguments: a bare TypeError before).
        (lambda: libwave.fresnel_weights(pos, pos, (0, 0)), libwave.ArgumentTypeError,
         r"fresnel_weights\(\): incompatible function arguments"),
        (lambda: libwave.grid_triangles(-1, 3), libwave.ArgumentTypeError, r"grid_triangles\(\): incompatible function arguments"),
        (lambda: libwave.Scene(3, 4), libwave.ArgumentTypeError, r"__init__\(\): incompatible constructor arguments"),
        (lambda: libwave.default_scene().set(3, 4), libwave.ArgumentTypeError, r"set\(\): incompatible function arguments"),
    ]
    for call, error, message in bad:
        with pytest.raises(error, match=message):
            call()


def test_frame_glb_without_its_optional_arrays_and_sizes_named(tmp_path):
    """texcoords, foam, reflect and refract are optional: without texcoords the UV map
    lies over the positions' own rectangle in plan (the writer refused it, saying "array
    sizes do not match 1 frames of 3 vertices"); a per-vertex array of another count is
    named against positions; shading is all three or none."""
    pos = np.array([[0, 0, 0.5], [2, 0, 0], [0, 4, 0]], np.float32)
    nor = np.tile(np.array([0, 0, 1], np.float32), (3, 1))
    tri = np.array([[0, 1, 2]], np.uint32)
    out = tmp_path / "f.glb"
    out.write_bytes(libwave.frame_glb(pos, nor, tri))
    a = libwave.read_animation(str(out))
    assert np.array_equal(a["positions"][0], pos)
    data = out.read_bytes()  # TEXCOORD_0 by hand (read_animation does not return it)
    length = int.from_bytes(data[12:16], "little")
    doc, binary = json.loads(data[20:20 + length]), data[20 + length + 8:]
    accessor = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"]]
    view = doc["bufferViews"][accessor["bufferView"]]
    at = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    texcoords = np.frombuffer(binary, np.float32, 2 * accessor["count"], at).reshape(-1, 2)
    np.testing.assert_array_equal(texcoords, [[0, 1], [1, 1], [0, 0]])  # u along +x, v down
    validate_glb(out)
    uv = np.array([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]], np.float32)
    assert libwave.frame_glb(pos, nor, tri, texcoords=uv) != libwave.frame_glb(pos, nor, tri)
    ones = np.ones(3, np.float32)
    libwave.frame_glb(pos, nor, tri, foam=ones, reflect=ones, refract=ones)
    bad = [
        (lambda: libwave.frame_glb(pos, nor[:2], tri), "frame_glb normals: 2 vertices, positions has 3"),
        (lambda: libwave.frame_glb(pos, nor, tri, texcoords=uv[:2]), "frame_glb texcoords: 2 vertices, positions has 3"),
        (lambda: libwave.frame_glb(pos, nor, tri, foam=ones, reflect=ones, refract=np.ones(4)),
         "frame_glb refract: 4 vertices, positions has 3"),
        (lambda: libwave.frame_glb(pos, nor, tri, foam=ones), "frame_glb: give foam, reflect and refract together"),
    ]
    for call, message in bad:
        with pytest.raises(libwave.InputError, match=message):
            call()


def validate_glb(path):
    """The Khronos validator's verdict on a file (skipped without its npm packages)."""
    validator = REPO / "scripts" / "gltf-validator" / "validate.mjs"
    if shutil.which("node") and (validator.parent / "node_modules").exists():
        r = subprocess.run(["node", str(validator), str(path)], capture_output=True, text=True, timeout=120)
        assert r.returncode == 0 and json.loads(r.stdout.splitlines()[-1])["numErrors"] == 0, r.stdout + r.stderr


def test_stage_arrays_make_a_multi_frame_animation(tmp_path):
    """animation_glb writes frames of stage arrays as one morph or nodes .glb (there was
    no multi-frame writer: frame_glb files merged, then converted); frame_glb records the
    loop's length for wave merge, which said "indexed 8 of 0 frames" without it."""
    frames, fps = 8, 4.0
    rest = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [10, 10, 0]], np.float32)
    tri = np.array([[0, 1, 2], [1, 3, 2]], np.uint32)
    pos = np.repeat(rest[None], frames, axis=0)
    pos[:, :, 2] = 0.3 * np.sin(2 * np.pi * np.arange(frames)[:, None] / frames + rest[None, :, 0] / 5)
    nor = np.stack([libwave.vertex_normals(p, tri) for p in pos])
    foam = np.linspace(0, 1, frames * 4, dtype=np.float32).reshape(frames, 4)
    for form in ("morph", "nodes"):
        out = tmp_path / f"{form}.glb"
        out.write_bytes(libwave.animation_glb(pos, nor, tri, foam=foam, reflect=foam, refract=1 - foam, fps=fps, form=form,
                                              loop_frames=frames))
        validate_glb(out)
        a = libwave.read_animation(str(out))
        assert a["frame_count"] == frames and a["loop_frames"] == frames and a["fps"] == fps
        np.testing.assert_allclose(a["positions"], pos, atol=1e-6)
        np.testing.assert_allclose(a["foam"], foam, atol=1e-6)
    bad = [
        (lambda: libwave.animation_glb(pos, nor[:7], tri), r"animation_glb normals: 7 frames of 4 vertices, positions has 8 of 4"),
        (lambda: libwave.animation_glb(pos, nor, tri, foam=foam, reflect=foam, refract=foam[:7]),
         "animation_glb refract: 28 values, positions has 32"),
        (lambda: libwave.animation_glb(pos[:, :, :2], nor, tri), r"animation_glb positions: expected shape \(frames, vertices, 3\)"),
        (lambda: libwave.animation_glb(pos, nor, tri, form="files"), 'animation_glb: form must be "morph" or "nodes"'),
        (lambda: libwave.animation_glb(pos, nor, tri, first_frame=4, loop_frames=8), "run past loop_frames 8"),
    ]
    for call, message in bad:
        with pytest.raises(libwave.InputError, match=message):
            call()
    # Frame files with their loop's length merge into a whole loop's index.
    for loop in (frames, 0):
        folder = tmp_path / f"files-{loop}"
        (folder / "frames").mkdir(parents=True)
        for k in range(frames):
            (folder / "frames" / f"frame-{k:04d}.glb").write_bytes(libwave.frame_glb(pos[k], nor[k], tri, fps=fps, frame=k, loop_frames=loop))
        r = subprocess.run([os.environ["WAVE_EXE"], "merge", str(folder)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        assert ("indexed 8 of 8 frames" if loop else "indexed 8 frames") in r.stdout, r.stdout
        assert json.loads((folder / "index.json").read_text())["loop_frames"] == loop


def test_seafloor_from_grid_and_from_triangles_hold_an_analytic_plane_and_plan_as_the_file_does(tmp_path):
    # z = −4 + 0.03 x + 0.05 y, with the water level at 0.7 m as a vertical offset: the
    # depth at any point inside is 0.7 − z, from a grid (node (0, 0) at the origin) and
    # from world-space triangles (a DCC's terrain); bad arguments are InputErrors naming
    # the argument; and a scene planned on the in-memory seafloor is the scene whose
    # /seafloor reads the same triangles from a mesh file with that offset.
    def plane(x, y):
        return -4.0 + 0.03 * x + 0.05 * y
    ys, xs = np.mgrid[0:31, 0:41]
    x, y = -3.0 + 0.5 * xs, 2.0 + 0.25 * ys
    grid = libwave.Seafloor.from_grid(plane(x, y), origin=(-3.0, 2.0), spacing=(0.5, 0.25), vertical_offset=-0.7)
    corners = np.array([[-3, 2, 0], [17, 2, 0], [17, 9.5, 0], [-3, 9.5, 0]], float)
    corners[:, 2] = plane(corners[:, 0], corners[:, 1])
    mesh = libwave.Seafloor.from_triangles(corners, np.array([[0, 1, 2], [0, 2, 3]], np.int32), spacing=0.4,
                                           vertical_offset=-0.7, name="terrain")
    rng = np.random.default_rng(3)
    px, py = rng.uniform(-3, 17, 200), rng.uniform(2, 9.5, 200)
    assert np.allclose(grid.depth_at(px, py), 0.7 - plane(px, py), atol=1e-12)
    assert np.allclose(mesh.depth_at(px, py), 0.7 - plane(px, py), atol=1e-12)
    assert grid.origin == (-3.0, 2.0) and grid.spacing == (0.5, 0.25) and mesh.source == "terrain"
    for call, kind, match in [
            (lambda: libwave.Seafloor.from_grid(plane(x, y)[0]), libwave.InputError, "values must be a 2-D array"),
            (lambda: libwave.Seafloor.from_grid(plane(x, y), spacing=(1.0, 0.0)), libwave.InputError, "spacing along y"),
            (lambda: libwave.Seafloor.from_grid(plane(x, y), origin=(0, 0, 0)), libwave.InputError, "origin"),
            (lambda: libwave.Seafloor.from_grid(np.array([["a", "b"]])), libwave.ArgumentTypeError, "values"),
            (lambda: libwave.Seafloor.from_triangles(corners[:, :2], [[0, 1, 2]]), libwave.InputError, "vertices"),
            (lambda: libwave.Seafloor.from_triangles(corners, [[0, 1, 4]]), libwave.InputError, "indices row 0 names vertex 4"),
            (lambda: libwave.Seafloor.from_triangles(corners, [[0, 1.5, 2]]), libwave.ArgumentTypeError, "indices must be integers"),
            (lambda: libwave.Seafloor.from_triangles(corners, [0, 1, 2]), libwave.InputError, "indices must be a \\(t, 3\\)"),
            (lambda: libwave.Seafloor.from_triangles(corners, np.zeros((0, 3), int)), libwave.InputError, "no triangles")]:
        with pytest.raises(kind, match=match):
            call()
    # A small sloping beach as triangles; planned in memory and from its OBJ file.
    gx, gy = np.meshgrid(np.linspace(0, 60, 13), np.linspace(0, 60, 13))
    verts = np.stack([gx.ravel(), gy.ravel(), (-3.0 + 0.08 * gy).ravel() + 0.5], 1)
    quads = [(j * 13 + i, j * 13 + i + 1, (j + 1) * 13 + i + 1, (j + 1) * 13 + i) for j in range(12) for i in range(12)]
    tris = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))])
    with open(tmp_path / "beach.obj", "w") as f:
        f.writelines(f"v {a!r} {b!r} {c!r}\n" for a, b, c in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)
    doc = {"seafloor": {"source": "beach.obj", "spacing": 1.0, "vertical_offset": -0.5},
           "waves": [{"period": 5.0, "amplitude": 0.3, "direction": [0, 1]}], "trace": {"ray_spacing": 2.0},
           "isobaths": {"spacing": 0.5}, "fronts": {"step": 0.5, "split_distance": 2.5}, "animation": {"fps": 4},
           "surface": {"far_field": False}}
    scene = libwave.Scene(doc, str(tmp_path))
    from_file = libwave.plan(scene)
    in_memory = libwave.plan(scene, seafloor=libwave.Seafloor.from_triangles(verts, tris, spacing=1.0, vertical_offset=-0.5))
    assert in_memory.vertex_count == from_file.vertex_count > 100
    assert np.array_equal(in_memory.rest_positions, from_file.rest_positions)
    a, b = libwave.animate(scene, from_file, 0, 2), libwave.animate(scene, in_memory, 0, 2)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.foam, b.foam)
    with pytest.raises(libwave.InputError, match="flat bottom"):
        libwave.plan(libwave.Scene({"surface": {"kind": "ocean"}}), seafloor=mesh)
