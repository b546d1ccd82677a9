// Streamed output (docs/export.md, "Streamed output"): frames evaluated a chunk at a
// time equal the whole range's, and the files written as they come equal, byte for
// byte, what encode_animation makes of the whole range in memory — every streamed form,
// both containers, Draco, caustic maps, a slice that starts inside the loop.
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/scene.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

using namespace wave;
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

struct TempDir {
    fs::path path = fs::temp_directory_path() / ("libwave-test-stream-" + std::to_string(::getpid()));
    TempDir() {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::size_t entries() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), {})); }
};

// The default bay with a caustic map small enough to be quick.
struct Bay {
    // The built-in default scene until issue 66: Gonzato's bay, ray strips on the water mesh.
    Scene scene = parse_scene(R"({"seafloor": {"source": "gonzato-bay"}, "waves": [{"period": 5, "amplitude": 0.3, "direction": [0, 1]}],
    "trace": {"ray_spacing": 1}, "fronts": {"step": 0.4, "split_distance": 1.2}})", "the bay", ".");
    ScenePlan plan;
    Bay() {
        scene.quantize = false;  // float frames: each test chooses its encoding
        scene.underwater = UnderwaterOptions{.map_size = 48};
        plan = plan_scene(scene);
    }
};

const Bay& bay() {
    static const Bay b;
    return b;
}

TEST(AnimationStream, ChunksEqualTheWholeRangeBitForBit) {
    const Bay& b = bay();
    const FrameRange range{5, 12};
    const SceneAnimation whole = animate_scene(b.scene, b.plan, 2e9, range);
    AnimationStream stream(b.scene, b.plan, range);
    EXPECT_EQ(stream.frame_count(), 7u);
    SceneAnimation chunk;
    std::size_t at = 0;
    const std::size_t n = whole.vertex_count;
    while (std::size_t k = stream.next(chunk, 3)) {
        ASSERT_EQ(chunk.first_frame, range.first + at);
        for (std::size_t i = 0; i < 3 * n * k; ++i) {
            ASSERT_EQ(chunk.positions[i], whole.positions[3 * n * at + i]) << i;
            ASSERT_EQ(chunk.normals[i], whole.normals[3 * n * at + i]) << i;
        }
        for (std::size_t i = 0; i < n * k; ++i) ASSERT_EQ(chunk.foam[i], whole.foam[n * at + i]) << i;
        for (std::size_t f = 0; f < k; ++f) ASSERT_EQ(chunk.caustics[f], whole.caustics[at + f]);
        EXPECT_EQ(chunk.seafloor_positions, whole.seafloor_positions);  // the static parts, not appended twice
        EXPECT_EQ(chunk.triangles, whole.triangles);
        EXPECT_EQ(chunk.texcoords, whole.texcoords);
        at += k;
    }
    EXPECT_EQ(at, 7u);
    EXPECT_EQ(stream.frames_left(), 0u);
    EXPECT_THROW(AnimationStream(b.scene, b.plan, FrameRange{500, 501}), InputError);
}

// Below 2^18 vertices a chunk's frames run side by side, each lane on a run of its own
// (model state, FFT workspace, fold-foam samples; docs/motion.md "Frames side by
// side"). A frame must compute the same bits on any lane as one after another on one
// thread: the default bay (untangled strips, breaking foam) and an FFT ocean whose
// fold foam fades over past lattice times that each lane samples for itself.
TEST(AnimationStream, FramesSideBySideEqualFramesOneAfterAnother) {
    Scene bay = default_scene();
    bay.quantize = false;
    Scene ocean = parse_scene(R"({"surface": {"kind": "ocean"}, "animation": {"fps": 12},
      "ocean": {"resolution": 64, "size": 200, "wind_speed": 18, "repeat_time": 4, "choppiness": 1.6}})",
                              "ocean.json", ".");
    for (const Scene* scene : {&bay, &ocean}) {
        const ScenePlan plan = plan_scene(*scene);
        std::vector<SceneAnimation> runs;
        std::vector<std::vector<std::size_t>> counts;
        for (int threads : {1, 4}) {  // one lane; four lanes, on any machine
            const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
            tbb::task_arena arena(threads);
            AnimationStream stream(*scene, plan, FrameRange{3, 14});
            SceneAnimation a;
            counts.emplace_back();
            arena.execute([&] {
                ASSERT_EQ(stream.next(a, 11, [&](std::size_t done, std::size_t total) {
                    EXPECT_EQ(total, 11u);
                    counts.back().push_back(done);
                }), 11u);
            });
            runs.push_back(std::move(a));
        }
        const SceneAnimation &one = runs[0], &side = runs[1];
        EXPECT_EQ(one.positions, side.positions) << scene->name;
        EXPECT_EQ(one.normals, side.normals);
        EXPECT_EQ(one.foam, side.foam);
        EXPECT_EQ(one.reflect, side.reflect);
        EXPECT_EQ(one.colors, side.colors);
        EXPECT_EQ(one.z_min, side.z_min);
        EXPECT_EQ(one.z_max, side.z_max);
        EXPECT_GT(*std::max_element(one.foam.begin(), one.foam.end()), 0.5f) << "no foam to compare";
        // Progress counts every frame once, in order, from either.
        for (const auto& c : counts) {
            ASSERT_EQ(c.size(), 11u);
            for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i], i + 1);
        }
    }
}

TEST(AnimationStream, StaticPartsAreSetAgainIntoAReplacedAnimation) {
    // Later chunks into the same animation leave its triangles, texture coordinates and
    // seafloor as the first chunk set them (no copy a chunk); an animation whose
    // triangles or texture coordinates were replaced in between, or another animation,
    // gets them again.
    const Bay& b = bay();
    const SceneAnimation whole = animate_scene(b.scene, b.plan, 2e9, FrameRange{0, 6});
    AnimationStream stream(b.scene, b.plan, FrameRange{0, 6});
    SceneAnimation chunk, other;
    ASSERT_EQ(stream.next(chunk, 2), 2u);
    chunk.triangles.clear();
    ASSERT_EQ(stream.next(chunk, 2), 2u);
    EXPECT_EQ(chunk.triangles, whole.triangles);
    std::vector<float>().swap(chunk.texcoords);
    chunk.seafloor_positions.clear();
    ASSERT_EQ(stream.next(other, 1), 1u);
    EXPECT_EQ(other.triangles, whole.triangles);
    EXPECT_EQ(other.seafloor_positions, whole.seafloor_positions);
    ASSERT_EQ(stream.next(chunk, 1), 1u);
    EXPECT_EQ(chunk.texcoords, whole.texcoords);
    EXPECT_EQ(chunk.seafloor_positions, whole.seafloor_positions);
    EXPECT_EQ(chunk.triangles, whole.triangles);
}

TEST(AnimationStream, AnErrorMidChunkWaitsForTheMapsStillBeingEncoded) {
    // The caustic maps' PNGs are encoded on tasks of their own while the frames go on;
    // a frame that fails (here the progress callback) must not leave one writing into
    // the chunk it unwinds (the sanitizer suite runs this too), and the stream reports
    // the frame's own error. A stream started again gives the same maps.
    const Bay& b = bay();
    const FrameRange range{0, 6};
    {
        AnimationStream stream(b.scene, b.plan, range);
        SceneAnimation chunk;
        const auto stop = [](std::size_t done, std::size_t) {
            if (done == 3) throw RuntimeError("stopped at frame 3");
        };
        EXPECT_THROW(stream.next(chunk, 6, stop), RuntimeError);
    }
    const SceneAnimation whole = animate_scene(b.scene, b.plan, 2e9, range);
    AnimationStream again(b.scene, b.plan, range);
    SceneAnimation chunk;
    ASSERT_EQ(again.next(chunk, 6), 6u);
    for (std::size_t f = 0; f < 6; ++f) {
        EXPECT_FALSE(chunk.caustics[f].empty());
        EXPECT_EQ(chunk.caustics[f], whole.caustics[f]);
    }
}

TEST(StreamAnimation, EveryStreamedFormEqualsTheWholeEncodingByteForByte) {
    const Bay& b = bay();
    const FrameRange range{3, 10};
    for (Scene::Form form : {Scene::Form::morph, Scene::Form::nodes, Scene::Form::pc2})
        for (Scene::Container container : {Scene::Container::glb, Scene::Container::gltf})
            for (int compression : {0, 1, 2}) {  // none, Draco, quantised (morph targets only)
                const bool draco = compression == 1, quantize = compression == 2;
                if ((draco && form == Scene::Form::pc2) || (quantize && form != Scene::Form::morph)) continue;
                Scene scene = b.scene;
                scene.form = form;
                scene.container = container;
                if (draco) scene.draco = DracoOptions{};
                scene.quantize = quantize;
                SCOPED_TRACE(std::to_string(static_cast<int>(form)) + " container " + std::to_string(static_cast<int>(container)) +
                             (draco ? " draco" : "") + (quantize ? " quantised" : ""));
                const SceneAnimation whole = animate_scene(scene, b.plan, 2e9, range);
                const EncodedFiles expected = encode_animation(whole.view(), form, container, false, whole.caustics);
                TempDir dir;
                AnimationStream stream(scene, b.plan, range);
                const StreamedAnimation out = stream_animation(stream, scene, dir.path.string(), false, 2);
                ASSERT_EQ(out.files.size(), expected.size());
                for (std::size_t i = 0; i < expected.size(); ++i) {
                    EXPECT_EQ(out.files[i].first, expected[i].first);
                    EXPECT_EQ(out.files[i].second, expected[i].second.size()) << expected[i].first;
                    EXPECT_TRUE(slurp(dir.path / expected[i].first) == expected[i].second) << expected[i].first;
                }
                EXPECT_EQ(out.z_min, whole.z_min);
                EXPECT_EQ(out.z_max, whole.z_max);
                EXPECT_EQ(out.first.frame_count, 1u);
                EXPECT_TRUE(std::equal(out.first.positions.begin(), out.first.positions.end(), whole.positions.begin()));
                EXPECT_EQ(dir.entries(), expected.size() - whole.caustics.size() + 1);  // no temporary file left; the maps in caustics/
            }
}

TEST(AnimationFileWriter, RefusesQuantisedAndUnfinishedFilesAndLeavesNothingBehind) {
    const Bay& b = bay();
    const SceneAnimation a = animate_scene(b.scene, b.plan, 2e9, FrameRange{0, 3});
    TempDir dir;
    const std::string path = (dir.path / "animation.glb").string();
    MorphAnimationView quantised = a.view();
    quantised.quantize = true;
    // Quantised morph targets stream only with their range given; nodes never.
    EXPECT_THROW(AnimationFileWriter(path, AnimationFileWriter::Form::morph, false, quantised, 3), InputError);
    quantised.quantize_range = 1.0;
    EXPECT_THROW(AnimationFileWriter(path, AnimationFileWriter::Form::nodes, false, quantised, 3), InputError);
    {
        AnimationFileWriter w(path, AnimationFileWriter::Form::morph, false, a.view(), 4);  // one frame never comes
        w.append(a.view());
        EXPECT_THROW(w.finish(), InputError);
    }
    EXPECT_EQ(dir.entries(), 0u);
    {
        AnimationFileWriter w(path, AnimationFileWriter::Form::nodes, false, a.view(), 3);
        w.append(a.view());  // an exception here would leave it unfinished: the destructor cleans up
    }
    EXPECT_EQ(dir.entries(), 0u);
    AnimationFileWriter w(path, AnimationFileWriter::Form::nodes, false, a.view(), 3);
    w.append(a.view());
    const auto files = w.finish();
    ASSERT_EQ(files.size(), 1u);
    EXPECT_EQ(files[0].second, fs::file_size(path));
    EXPECT_EQ(slurp(path), gltf_nodes_glb(a.view()));
    EXPECT_EQ(dir.entries(), 1u);
}

}  // namespace

// An internal invariant is an InternalError (exit 1, "please report"), never bad input;
// the export forms' table names every form and refuses an unknown name as bad input.
TEST(ExportForms, TheTableNamesEveryFormAndInvariantsAreInternalErrors) {
    for (const wave::ExportFormInfo& f : wave::export_forms()) {
        EXPECT_EQ(wave::export_form_named(f.name), f.form);
        EXPECT_EQ(&wave::export_form(f.form), &f);
        EXPECT_EQ(wave::form_from_name(wave::form_name(f.form)), f.form);
    }
    EXPECT_THROW(wave::export_form_named("gif"), wave::InputError);
    try {
        (void)wave::surface_kind_name(static_cast<wave::SurfaceKind>(99));
        FAIL() << "an unregistered surface kind was named";
    } catch (const wave::InputError&) {
        FAIL() << "an internal invariant reported as bad input";
    } catch (const wave::InternalError&) {
    }
}

// The PLY form: a binary PLY per frame with the frame's positions, normals, rest UVs and
// shading as vertex properties, and an index of the frames.
TEST(ExportForms, PlyFramesHoldEachFramesVerticesAndAnIndex) {
    const wave::Scene scene = wave::default_scene();
    const wave::ScenePlan plan = wave::plan_scene(scene);
    const wave::SceneAnimation a = wave::animate_scene(scene, plan, 2e9, wave::FrameRange{3, 5});
    const wave::EncodedFiles files = wave::encode_animation(a.view(), wave::ExportForm::ply, wave::ExportContainer::glb, false);
    ASSERT_EQ(files.size(), 3u);
    EXPECT_EQ(files[0].first, "ply/frame-0003.ply");
    EXPECT_EQ(files[1].first, "ply/frame-0004.ply");
    EXPECT_EQ(files[2].first, "ply/animation-frames-3-5.json");
    const std::size_t n = a.vertex_count, t = a.triangles.size() / 3;
    for (std::size_t k = 0; k < 2; ++k) {
        const std::string& ply = files[k].second;
        const std::size_t body = ply.find("end_header\n") + 11;
        ASSERT_NE(body, std::string::npos + 11);
        EXPECT_NE(ply.find("element vertex " + std::to_string(n) + "\n"), std::string::npos);
        EXPECT_NE(ply.find("property float foam\n"), std::string::npos);
        ASSERT_EQ(ply.size(), body + n * 11 * sizeof(float) + t * 13);
        float v[11];
        std::memcpy(v, ply.data() + body + (n - 1) * sizeof v, sizeof v);  // the last vertex
        EXPECT_EQ(v[0], a.positions[3 * (k * n + n - 1)]);
        EXPECT_EQ(v[2], a.positions[3 * (k * n + n - 1) + 2]);
        EXPECT_EQ(v[5], a.normals[3 * (k * n + n - 1) + 2]);
        EXPECT_EQ(v[10], a.foam[k * n + n - 1]);
        std::uint32_t face[3];
        std::memcpy(face, ply.data() + body + n * sizeof v + 1, sizeof face);
        EXPECT_EQ(static_cast<unsigned char>(ply[body + n * sizeof v]), 3);
        EXPECT_EQ(face[2], a.triangles[2]);
    }
    EXPECT_NE(files[2].second.find("\"frame_count\": 2"), std::string::npos);
    EXPECT_NE(files[2].second.find("ply/frame-0004.ply"), std::string::npos);
}

// The files form (scene.h, write_files_form): frames written into a partial folder with
// their own index, the bytes encode_animation makes of each frame (with the run key),
// published into place; --resume keeps the frames whose files still match their entries.
TEST(FilesForm, FramesAreEncodeAnimationsAndTheIndexListsTheirSha256) {
    const Bay& b = bay();
    Scene scene = b.scene;
    scene.form = Scene::Form::files;
    const FrameRange range{3, 7};
    const std::size_t loop = scene_loop_frames(scene, b.plan);
    const FrameIndexInfo info{scene.name, scene.fps, b.plan.loop_period, loop, scene_run_key(scene, b.plan, scene.document)};
    EXPECT_EQ(info.run_key.size(), 64u);
    EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const SceneAnimation whole = animate_scene(scene, b.plan, 2e9, range);
    MorphAnimationView view = whole.view();
    view.run_key = info.run_key;
    const EncodedFiles expected = encode_animation(view, Scene::Form::files, scene.container, false, whole.caustics);
    TempDir dir;
    const std::string out = (dir.path / "out").string();
    FilesFormRun run = write_files_form(scene, b.plan, out, info, range, false, 2e9);
    EXPECT_EQ(run.computed, 4u);
    EXPECT_EQ(run.verified, 0u);
    EXPECT_EQ(run.z_min, whole.z_min);
    EXPECT_EQ(run.z_max, whole.z_max);
    ASSERT_EQ(run.entries.size(), 4u);
    ASSERT_EQ(run.files.size(), expected.size());
    ASSERT_EQ(run.partial_files.size(), expected.size());
    for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(run.files[i].first, expected[i].first);
        EXPECT_EQ(run.files[i].second, expected[i].second.size());
        EXPECT_TRUE(slurp(fs::path(run.partial) / expected[i].first) == expected[i].second) << expected[i].first;
        const std::string& entry = run.entries[i / (expected.size() / 4)];
        EXPECT_NE(entry.find(sha256_hex(expected[i].second)), std::string::npos) << expected[i].first;
    }
    EXPECT_TRUE(frame_entry_intact(run.entries[0], run.partial));
    // A second run of the same range and key finds the partial folder locked.
    try {
        (void)write_files_form(scene, b.plan, out, info, range, true, 2e9);
        ADD_FAILURE() << "a locked partial folder was written";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("is locked"), std::string::npos) << e.what();
    }
    const std::string index = publish_files_form(run, out, info, false);
    EXPECT_FALSE(fs::exists(run.partial));
    EXPECT_EQ(slurp(dir.path / "out" / "index.json"), index);
    EXPECT_EQ(index, frame_index_json(info, run.entries));
    for (const auto& [name, bytes] : expected) EXPECT_TRUE(slurp(dir.path / "out" / name) == bytes) << name;
    // Resumed: every frame kept; one frame file changed is computed again.
    FilesFormRun kept = write_files_form(scene, b.plan, out, info, range, true, 2e9);
    EXPECT_EQ(kept.verified, 4u);
    EXPECT_EQ(kept.computed, 0u);
    EXPECT_EQ(kept.entries, run.entries);
    EXPECT_TRUE(kept.partial_files.empty());
    kept.lock.release();
    std::ofstream(dir.path / "out" / expected[0].first, std::ios::app) << "x";
    FilesFormRun again = write_files_form(scene, b.plan, out, info, range, true, 2e9);
    EXPECT_EQ(again.verified, 3u);
    EXPECT_EQ(again.computed, 1u);
    EXPECT_EQ(again.entries, run.entries);
    EXPECT_EQ(publish_files_form(again, out, info, true), index);
    EXPECT_TRUE(slurp(dir.path / "out" / expected[0].first) == expected[0].second);
    // Another animation's index is refused before any frame is written.
    FrameIndexInfo other = info;
    other.fps = 30.0;
    EXPECT_THROW((void)write_files_form(scene, b.plan, out, other, range, false, 2e9), InputError);
    EXPECT_THROW((void)merged_frame_index((dir.path / "out" / "index.json").string(), other, {}, false), InputError);
    EXPECT_TRUE(read_files_form_index((dir.path / "out" / "index.json").string()).has_value());
    EXPECT_FALSE(read_files_form_index((dir.path / "out" / expected[0].first).string()).has_value());
}

TEST(FilesForm, AFolderLockIsExclusiveUntilReleased) {
    TempDir dir;
    FolderLock held(dir.path.string(), false, "busy");
    EXPECT_TRUE(held.held());
    try {
        const FolderLock second(dir.path.string(), false, "the folder is busy");
        ADD_FAILURE() << "two locks held";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "the folder is busy");
    }
    FolderLock moved = std::move(held);
    EXPECT_FALSE(held.held());
    moved.release();
    EXPECT_NO_THROW(FolderLock(dir.path.string(), false, "busy"));
    EXPECT_THROW(FolderLock((dir.path / "absent").string(), false, "busy"), RuntimeError);
}
