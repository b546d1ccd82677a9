"""`import libwave`: the Python module against the C++ pipeline and the CLI it mirrors.
Run by ctest (`python` test) with PYTHONPATH at the built module and WAVE_EXE at the CLI."""
import hashlib
import json
import math
import os
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import libwave

SMALL = {"waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
         "fronts": {"step": 0.8, "split_distance": 2.4}}


@pytest.fixture(scope="module")
def small():
    scene = libwave.parse_scene(SMALL, "small.json")
    return scene, libwave.plan(scene)


def test_version_matches_the_cli():
    out = subprocess.run([os.environ["WAVE_EXE"], "--version"], capture_output=True, text=True, check=True).stdout
    assert out.split()[1] == libwave.__version__


def test_arrays_are_read_only_views_with_the_right_shapes(small):
    scene, plan = small
    anim = libwave.animate(scene, plan, 0, 4)
    n = plan.vertex_count
    assert anim.positions.shape == (4, n, 3) and anim.positions.dtype == np.float32
    assert anim.normals.shape == (4, n, 3)
    assert anim.foam.shape == (4, n) and anim.reflect.shape == (4, n)
    assert anim.triangles.dtype == np.uint32 and anim.triangles.max() < n
    assert anim.positions.base is not None  # a view of libwave's buffer, not a copy
    with pytest.raises(ValueError):
        anim.positions[0, 0, 0] = 1.0
    np.testing.assert_allclose(np.linalg.norm(anim.normals, axis=2), 1.0, atol=1e-5)
    np.testing.assert_allclose(anim.reflect + anim.refract, 1.0, atol=1e-6)
    # The rest positions are the frames' horizontal positions for flat water far out.
    assert plan.rest_positions.shape == (n, 2)
    # Views outlive the Animation object that owns them.
    positions = anim.positions
    del anim
    assert np.isfinite(positions).all()


def test_a_frame_alone_equals_the_same_frame_of_a_run(small):
    scene, plan = small
    whole = libwave.animate(scene, plan)
    one = libwave.animate(scene, plan, 7, 8)
    assert whole.frame_count == whole.loop_frames == 120
    assert np.array_equal(one.positions[0], whole.positions[7])
    assert np.array_equal(one.foam[0], whole.foam[7])


def wave_run_small(tmp_path):
    """SMALL written to s.json and run by the CLI into out/: (scene path, output folder)."""
    path = tmp_path / "s.json"
    path.write_text(json.dumps(SMALL))
    out = tmp_path / "out"
    subprocess.run([os.environ["WAVE_EXE"], "run", str(path), "-o", str(out), "-q"], check=True)
    return path, out


def test_the_glb_is_byte_identical_to_wave_run(small, tmp_path):
    path, out = wave_run_small(tmp_path)
    anim = libwave.animate(libwave.read_scene(str(path)), libwave.plan(libwave.read_scene(str(path))))
    assert anim.glb("morph") == (out / "animation.glb").read_bytes()
    anim.write_glb(str(tmp_path / "py.glb"), "nodes")
    assert (tmp_path / "py.glb").read_bytes()[:4] == b"glTF"
    assert anim.frame_glb(3)[:4] == b"glTF"


def test_write_animation_streams_the_same_files_as_wave_run(small, tmp_path):
    scene, plan = small
    _, out = wave_run_small(tmp_path)
    files = libwave.write_animation(scene, plan, str(tmp_path / "py"), chunk=7)  # 120 frames, 7 at a time
    assert files == [("animation.glb", (out / "animation.glb").stat().st_size)]
    assert (tmp_path / "py" / "animation.glb").read_bytes() == (out / "animation.glb").read_bytes()
    # A slice, and a form the stream does not write
    files = libwave.write_animation(scene, plan, str(tmp_path / "slice"), first=10, end=14)
    assert [f[0] for f in files] == ["animation-frames-10-14.glb"]
    quantised = libwave.parse_scene(dict(SMALL, outputs={"form": "nodes", "quantize": True}))
    with pytest.raises(libwave.InputError, match="not streamed"):
        libwave.write_animation(quantised, plan, str(tmp_path / "q"))


def test_write_files_form_indexes_every_frame_with_its_size_and_sha256(small, tmp_path):
    scene, plan = small
    folder = tmp_path / "files"
    # Two slices into one folder: one index of both, as `wave run --slice` leaves it.
    first = libwave.write_files_form(scene, plan, str(folder), first=0, end=60)
    assert first["computed_frames"] == 60 and first["kept_frames"] == 0
    assert [f[0] for f in first["files"]][:2] == ["frames/frame-0000.glb", "frames/frame-0001.glb"]
    out = libwave.write_files_form(scene, plan, str(folder), first=60)
    index = out["index"]
    assert index == json.loads((folder / "index.json").read_text())
    assert index["scene"] == scene.name and index["loop_frames"] == 120 and len(index["run_key"]) == 64
    assert [e["frame"] for e in index["frames"]] == list(range(120))
    for entry in index["frames"]:
        assert entry["file"] == f"frames/frame-{entry['frame']:04d}.glb"
        for content in entry["content"]:
            data = (folder / content["file"]).read_bytes()
            assert len(data) == content["bytes"]
            assert hashlib.sha256(data).hexdigest() == content["sha256"]
    second = [e["height_range_m"] for e in index["frames"][60:]]
    assert out["height_range_m"] == pytest.approx((min(r[0] for r in second), max(r[1] for r in second)))
    # The frames are the animation's, and no partial folder is left.
    anim = libwave.animate(scene, plan, 5, 6)
    glb = (folder / "frames" / "frame-0005.glb").read_bytes()
    assert glb[:4] == b"glTF" and len(glb) == index["frames"][5]["content"][0]["bytes"]
    stored = libwave.read_animation(str(folder / "index.json"))
    np.testing.assert_allclose(stored["positions"][5], anim.positions[0], atol=0.01)  # within meshopt's precision (auto above 32 MB)
    assert not [p for p in folder.iterdir() if p.name.startswith(".wave-")]
    # Resumed, every frame whose files still match is kept; a changed one is computed again.
    with open(folder / "frames" / "frame-0007.glb", "ab") as f:
        f.write(b"x")
    again = libwave.write_files_form(scene, plan, str(folder), resume=True)
    assert again["kept_frames"] == 119 and again["computed_frames"] == 1
    assert again["index"] == index
    assert hashlib.sha256((folder / "frames" / "frame-0007.glb").read_bytes()).hexdigest() == \
        index["frames"][7]["content"][0]["sha256"]
    # Another animation's index is refused before any frame is written.
    other = libwave.parse_scene(dict(SMALL, animation={"fps": 12}))
    with pytest.raises(libwave.InputError, match="another animation"):
        libwave.write_files_form(other, libwave.plan(other), str(folder), first=0, end=1)


def test_dict_and_json_text_give_the_same_scene():
    a = libwave.plan(libwave.parse_scene(SMALL))
    b = libwave.plan(libwave.parse_scene(json.dumps(SMALL)))
    assert a.vertex_count == b.vertex_count and a.loop_period == b.loop_period == 5.0


def test_errors_carry_libwave_messages():
    with pytest.raises(libwave.InputError, match=r"bad\.json: /waves/0/period: expected a number in \[0\.01, 3600\] \(s\), got -1"):
        libwave.parse_scene({"waves": [{"period": -1}]}, "bad.json")
    with pytest.raises(ValueError):  # InputError is a ValueError
        libwave.parse_scene({"waves": [{"period": 5}], "fronts": {"stpe": 1}})
    with pytest.raises(libwave.InputError, match="file not found"):
        libwave.read_scene("/nonexistent/scene.json")
    # A guard rail, refused before any allocation, is a LimitError (an InputError).
    huge = libwave.parse_scene({"surface": {"kind": "ocean"}, "ocean": {"resolution": 2048, "repeat_time": 60}})
    with pytest.raises(libwave.LimitError, match="frames of"):
        libwave.animate(huge, libwave.plan(huge))
    with pytest.raises(libwave.InputError, match="form"):
        libwave.animate(*small_pair(), 0, 1).glb("files")
    # The hierarchy is C++'s: `except libwave.Error` catches bad input and limits too.
    assert issubclass(libwave.InputError, libwave.Error) and issubclass(libwave.LimitError, libwave.InputError)
    assert issubclass(libwave.Error, RuntimeError) and issubclass(libwave.InputError, ValueError)
    with pytest.raises(libwave.Error, match="file not found"):
        libwave.read_scene("/nonexistent/scene.json")


def small_pair():
    scene = libwave.parse_scene(SMALL)
    return scene, libwave.plan(scene)


def test_the_gil_is_released_during_long_work():
    scene = libwave.parse_scene({"surface": {"kind": "ocean"}, "ocean": {"resolution": 256, "repeat_time": 4}})
    plan = libwave.plan(scene)
    ticks, done = [0], threading.Event()

    def work():
        libwave.animate(scene, plan, 0, 24)
        done.set()

    worker = threading.Thread(target=work)
    start = time.perf_counter()
    worker.start()
    while not done.is_set():
        ticks[0] += 1
    worker.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.05  # the work is long enough to tell
    assert ticks[0] > 10000, f"the main thread ran only {ticks[0]} loops in {elapsed:.2f} s"


def test_linear_wave():
    w = libwave.linear_wave(10.0, 5.0)
    assert abs(w["wavelength"] / (9.81 * 100 / (2 * np.pi)) - 0.4335) < 2e-3  # SPM Table C-1


def test_preview_renders_a_frame_as_an_rgb_array():
    # The sunset example: the sun's glitter column stands under the sun (image centre).
    scene = libwave.parse_scene(json.load(open(os.path.join(os.path.dirname(__file__), "..", "..", "examples", "sunset.json"))))
    plan = libwave.plan(scene)
    anim = libwave.animate(scene, plan, 0, 1)
    rgb = libwave.preview(scene, plan, anim, 0, 200, 100)
    assert rgb.shape == (100, 200, 3) and rgb.dtype == np.uint8
    water = rgb[60:, :, :].astype(int).sum(axis=2)
    glitter_columns = np.nonzero((water > 3 * 235).any(axis=0))[0]
    assert len(glitter_columns) > 0 and abs(glitter_columns.mean() - 100) < 15
    with pytest.raises(ValueError, match="frame 3 of 1"):
        libwave.preview(scene, plan, anim, 3)


def test_caustics_of_a_frame_equal_the_maps_wave_run_writes(tmp_path):
    # The breaking beach's frame 0: the array libwave.caustics gives, written as wave run
    # writes it (16-bit, full scale 4), is the PNG wave run wrote, value for value.
    path = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "breaking-beach.json")
    scene = libwave.read_scene(path)
    plan = libwave.plan(scene)
    anim = libwave.animate(scene, plan, 0, 1)
    e = libwave.caustics(scene, plan, anim, 0)
    assert e.shape == (256, 256) and e.dtype == np.float32
    lit = e[e > 0]
    assert lit.size > 0.5 * e.size and 0.05 < float(np.median(lit)) < 1.0  # coastal water, 0.5–8 m deep, sun at 50°
    subprocess.run([os.environ["WAVE_EXE"], "run", path, "-o", str(tmp_path), "--frames", "0:1", "-q"], check=True)
    import zlib
    data = (tmp_path / "caustics" / "caustics-0000.png").read_bytes()
    chunks, pos = {}, 8
    while pos < len(data):
        length, kind = int.from_bytes(data[pos:pos + 4], "big"), data[pos + 4:pos + 8]
        chunks[kind] = chunks.get(kind, b"") + data[pos + 8:pos + 8 + length]
        pos += 12 + length
    raw = np.frombuffer(zlib.decompress(chunks[b"IDAT"]), np.uint8).reshape(256, 1 + 512)
    rows = np.zeros((256, 512), np.int64)
    for j in range(256):  # undo the Sub filter (type 1) or none (0), 2 bytes a pixel
        line = raw[j, 1:].astype(np.int64)
        if raw[j, 0] == 1:
            for i in range(2, 512):
                line[i] = (line[i] + line[i - 2]) & 255
        else:
            assert raw[j, 0] == 0
        rows[j] = line
    grey = rows[:, 0::2] * 256 + rows[:, 1::2]
    expected = np.rint(65535 * np.clip(e / 4.0, 0, 1))
    assert np.abs(grey - expected).max() <= 1
    with pytest.raises(libwave.InputError):
        libwave.caustics(scene, plan, anim, 5)
    small = libwave.caustics(scene, plan, anim, 0, map_size=64)
    assert small.shape == (64, 64)
    assert abs(float(small.mean()) - float(e.mean())) < 0.02 * float(e.mean())  # flux kept at any resolution
    # Several frames at once (the seafloor and the mesh's edges planned once): each map
    # is the one frame's, bit for bit, in the order asked.
    three = libwave.animate(scene, plan, 0, 3)
    maps = libwave.caustics(scene, plan, three, [2, 0, 1])
    assert maps.shape == (3, 256, 256)
    assert np.array_equal(maps[1], e)
    assert np.array_equal(maps[0], libwave.caustics(scene, plan, three, 2))
    assert not np.array_equal(maps[0], maps[1])
    with pytest.raises(libwave.InputError, match="frame 3 of 3"):
        libwave.caustics(scene, plan, three, [0, 3])


def test_sunbeams_dim_with_depth_as_the_water_attenuates_the_beam():
    # The breaking beach (coastal water, c = 0.15 /m; sun 50° up): its long swell hardly
    # focuses light, so from level to level the mean light of the columns wet at both
    # falls as e^(−c Δd / cos θt), θt the beam's angle under the water.
    path = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "breaking-beach.json")
    scene = libwave.read_scene(path)
    plan = libwave.plan(scene)
    anim = libwave.animate(scene, plan, 0, 2)
    v = libwave.sunbeams(scene, plan, anim, 0, voxels=(32, 32, 8))
    light, (x0, y0, z0), (dx, dy, dz) = v["light"], v["origin"], v["voxel_size"]
    assert light.shape == (8, 32, 32) and light.dtype == np.float32
    assert (x0, y0) == (0.0, 0.0) and abs(dx - 200.0 / 32) < 1e-12 and abs(z0 + 8 * dz) < 1e-12
    cos_t = math.sqrt(1.0 - (math.cos(math.radians(50.0)) / 1.33) ** 2)
    for upper, lower in [(7, 5), (5, 3)]:
        wet = (light[upper] > 0) & (light[lower] > 0)
        wet[:, :4] = wet[:, -4:] = False  # away from the sides, whose light comes from beyond the domain
        assert wet.sum() > 100
        ratio = float(light[lower][wet].mean() / light[upper][wet].mean())
        assert abs(ratio / math.exp(-0.15 * (upper - lower) * dz / cos_t) - 1.0) < 0.03, (upper, lower, ratio)
    assert (light[0] == 0).mean() > 0.5  # the bottom level lies under the beach's floor but offshore
    both = libwave.sunbeams(scene, plan, anim, [1, 0], voxels=(32, 32, 8))["light"]
    assert both.shape == (2, 8, 32, 32) and np.array_equal(both[1], light)
    with pytest.raises(libwave.InputError, match="frame 2 of 2"):
        libwave.sunbeams(scene, plan, anim, 2)
    with pytest.raises(libwave.InputError, match="nz = 0"):
        libwave.sunbeams(scene, plan, anim, 0, voxels=(8, 8, 0))


def test_wave_field_matches_wave_field_cli(tmp_path):
    # The Berkhoff shoal: the field's arrays equal the GeoTIFF `wave field` writes.
    path = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "berkhoff-shoal.json")
    f = libwave.wave_field(libwave.read_scene(path))
    ratio = f["height_ratio"]
    assert ratio.dtype == np.float32 and ratio.ndim == 2 and ratio.shape == f["phase"].shape
    assert abs(f["incident_height"] - 0.0464) < 2e-4  # the scene's H0 at the wavemaker
    assert 2.0 < np.nanmax(ratio) < 3.0  # the focus behind the shoal
    assert abs(np.nanmedian(ratio[:, : ratio.shape[1] // 8]) - 1.0) < 0.02  # undisturbed before the shoal
    with pytest.raises(libwave.InputError):
        libwave.wave_field(libwave.read_scene(path), train=3)
    summary = json.loads(subprocess.run([os.environ["WAVE_EXE"], "field", path, "--json"], capture_output=True,
                                        text=True, check=True).stdout)
    assert abs(summary["height_ratio_max"] - float(np.nanmax(ratio))) < 1e-6


def test_inspect_an_animation_in_memory_and_on_disk(tmp_path):
    # The same numbers for the Animation and for its .glb read back (positions within
    # float32); a height field over the seafloor rectangle: no folds, one loop on it.
    scene = libwave.parse_scene({"surface": {"kind": "height-field"}, "waves": [{"period": 5, "amplitude": 0.3}],
                                 "animation": {"fps": 4}})
    anim = libwave.animate(scene, libwave.plan(scene))
    memory = libwave.inspect(anim)
    path = tmp_path / "a.glb"
    anim.write_glb(str(path))
    disk = libwave.inspect(str(path), per_frame=False)
    assert memory["frames"] == anim.frame_count and len(memory["per_frame"]) == anim.frame_count
    assert "per_frame" not in disk
    assert memory["worst"]["folds"] == disk["worst"]["folds"] == 0
    assert memory["unreferenced_vertices"] == 0 and memory["non_manifold_edges"] == 0
    assert len(memory["boundary"]["loops"]) == 1
    assert abs(memory["worst"]["max_speed_m_s"] - disk["worst"]["max_speed_m_s"]) < 1e-3
    with pytest.raises(libwave.InputError):
        libwave.inspect(str(tmp_path / "missing.glb"))
