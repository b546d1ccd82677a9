// The files form written a chunk of frames at a time into a hidden partial folder of the
// output folder, with its own index, so that a killed run resumes (`wave run --resume`)
// and slices share one output folder (scene.h, write_files_form; the index's entries and
// the folder lock: export/frame_index.cpp; docs/hardening.md, "Crash safety").
#include "libwave/scene.h"

#include "export/frame_index.h"
#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/version.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace wave {

using nlohmann::json;
namespace fs = std::filesystem;

std::string scene_run_key(const Scene& scene, const ScenePlan& plan, std::string_view source) {
    std::string text = "libwave " + std::string(version()) + "\n";
    text += source;
    char overrides[256];
    const DracoOptions d = scene.draco.value_or(DracoOptions{});
    std::snprintf(overrides, sizeof overrides, "\nfps %a container %d quantize %d draco %d %d %d %d %d %d %d%s\n", scene.fps,
                  static_cast<int>(scene.container), scene.quantize ? 1 : 0, scene.draco ? 1 : 0, d.position_bits,
                  d.normal_bits, d.texcoord_bits, d.color_bits, d.generic_bits, d.encode_speed, scene.meshopt ? " meshopt" : "");
    text += overrides;
    const ElevationGrid& g = plan.seafloor.grid;
    char grid[160];
    std::snprintf(grid, sizeof grid, "grid %zu %zu %a %a %a %a\n", g.nx, g.ny, g.x0, g.y0, g.dx, g.dy);
    text += grid;
    text.append(reinterpret_cast<const char*>(g.z.data()), g.z.size() * sizeof(double));
    return sha256_hex(text);
}

std::vector<std::string> FilesFormRun::stage(const std::string& staging) const {
    // Linked, not moved: if publishing fails the partial folder still holds every frame
    // its index lists, and --resume keeps them.
    const fs::path from(partial), to(staging);
    for (const std::string& name : partial_files) {
        fs::create_directories((to / name).parent_path());
        std::error_code ec;
        fs::create_hard_link(from / name, to / name, ec);
        if (ec) fs::copy_file(from / name, to / name);  // a file system without hard links
    }
    return partial_files;
}

namespace {

// The entries an index lists for frames [first, end) of this animation and run key, each
// with its height range (what the run's summary needs of a frame it keeps).
std::map<std::size_t, json> listed_frames(const fs::path& index_path, const FrameIndexInfo& info, std::size_t first, std::size_t end) {
    std::map<std::size_t, json> frames;
    const auto index = detail::read_index(index_path);
    if (!index || !detail::same_animation(*index, info) || index->value("run_key", "") != info.run_key) return frames;
    for (const json& e : (*index)["frames"])
        if (e.is_object() && e.contains("frame") && e["frame"].is_number_unsigned() && e.contains("height_range_m") &&
            e["height_range_m"].is_array() && e["height_range_m"].size() == 2 && e["height_range_m"][0].is_number() &&
            e["height_range_m"][1].is_number()) {
            const auto f = e["frame"].get<std::size_t>();
            if (f >= first && f < end) frames[f] = e;
        }
    return frames;
}

}  // namespace

FilesFormRun write_files_form(const Scene& scene, const ScenePlan& plan, const std::string& out_dir, const FrameIndexInfo& info,
                              FrameRange range, bool resume, double max_bytes,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
    const fs::path root(out_dir);
    const std::size_t first = range.first, end = std::min(range.end, info.loop_frames);
    const bool whole = first == 0 && end == info.loop_frames;
    // A foreign index is refused before any frame is written.
    detail::merged_index((root / "index.json").string(), info, {}, whole, resume);
    if (first >= end)
        throw InputError("scene: the frame range " + std::to_string(first) + ":" +
                         (range.end == static_cast<std::size_t>(-1) ? std::string() : std::to_string(range.end)) +
                         " holds no frame of the loop's 0:" + std::to_string(info.loop_frames));
    FilesFormRun run;
    run.whole_loop = whole;
    // One partial folder per run key and range: another scene, or another slice of this
    // one, never finds its frames there.
    const fs::path partial = root / (".wave-partial-" + info.run_key.substr(0, 16) + "-" + std::to_string(first) + "-" + std::to_string(end));
    run.partial = partial.string();
    const bool created = !fs::exists(root);
    fs::create_directories(partial);
    run.lock = FolderLock(run.partial, false,
                          out_dir + ": another wave run is writing frames " + std::to_string(first) + ":" + std::to_string(end) +
                              " of this animation there (" + partial.filename().string() + " is locked)");
    const fs::path partial_index = partial / "index.json";
    std::map<std::size_t, json> kept_partial, kept_final;
    if (resume) {
        // Frames are kept only when their files match what the index recorded: a frame
        // file that exists but was truncated, overwritten or belongs to another run is
        // computed again.
        for (auto& [f, e] : listed_frames(partial_index, info, first, end))
            if (detail::entry_intact(e, partial)) kept_partial[f] = std::move(e);
        for (auto& [f, e] : listed_frames(root / "index.json", info, first, end))
            if (!kept_partial.count(f) && detail::entry_intact(e, root)) kept_final[f] = std::move(e);
    } else {
        std::error_code ignored;
        fs::remove_all(partial / "frames", ignored);
        fs::remove(partial_index, ignored);
    }
    run.verified = kept_partial.size() + kept_final.size();
    const auto write_partial_index = [&] {
        std::vector<json> listed;
        for (const auto& [_, e] : kept_partial) listed.push_back(e);
        write_file_atomic(partial_index.string(), detail::frame_index(info, std::move(listed)).dump(2) + "\n");
    };
    try {
        if (resume) write_partial_index();  // lists only what was verified
        std::vector<std::size_t> missing;
        for (std::size_t f = first; f < end; ++f)
            if (!kept_partial.count(f) && !kept_final.count(f)) missing.push_back(f);
        const std::size_t chunk = files_form_chunk(estimate_run(scene, plan), max_bytes);
        const std::size_t total = end - first;
        if (progress && run.verified > 0) progress(run.verified, total);
        SceneAnimation anim;
        for (std::size_t i = 0; i < missing.size();) {
            // Runs of consecutive missing frames, each streamed `chunk` frames at a time.
            const std::size_t a = missing[i];
            std::size_t b = a + 1, j = i + 1;
            while (j < missing.size() && missing[j] == b) ++b, ++j;
            i = j;
            AnimationStream stream(scene, plan, FrameRange{a, b});
            const std::size_t done_before = run.verified + run.computed;
            while (stream.next(anim, chunk, [&](std::size_t done, std::size_t) {
                if (progress) progress(done_before + done, total);
            }) > 0) {
                MorphAnimationView view = anim.view();
                view.run_key = info.run_key;
                const std::size_t n = anim.vertex_count;
                for (std::size_t k = 0; k < anim.frame_count; ++k) {  // each frame encoded and written before the next
                    const auto frame_k = [k](const std::vector<std::string>& each) {  // a frame's underwater file, if any
                        return each.empty() ? std::span<const std::string>() : std::span<const std::string>(each).subspan(k, 1);
                    };
                    const EncodedFiles frame_files = encode_animation(frame_subview(view, k, 1), Scene::Form::files, scene.container, false,
                                                                      frame_k(anim.caustics), frame_k(anim.sunbeams), frame_k(anim.whitewater));
                    for (const auto& [name, bytes] : frame_files) {
                        fs::create_directories((partial / name).parent_path());
                        write_file_atomic((partial / name).string(), bytes);
                    }
                    const std::size_t f = anim.first_frame + k;
                    kept_partial[f] = detail::frame_entry(f, info.fps, frame_files, view.positions.subspan(3 * n * k, 3 * n));
                }
                // The index after its frames: it lists only files already whole on disk.
                write_partial_index();
                run.computed += anim.frame_count;
            }
        }
    } catch (...) {
        std::error_code ignored;
        if (kept_partial.empty()) {  // nothing to resume from: leave no trace
            run.lock.release();
            fs::remove_all(partial, ignored);
            if (created) fs::remove_all(root, ignored);
        } else {
            // The frames of the failed chunk that are whole on disk (a full disk fails a
            // frame, not the ones before it): listed for --resume, which had found frames
            // and no index. A small index still fits where a frame's temporary file was.
            try {
                write_partial_index();
            } catch (...) {
            }
        }
        throw;
    }
    run.z_min = std::numeric_limits<float>::infinity();
    run.z_max = -std::numeric_limits<float>::infinity();
    for (std::size_t f = first; f < end; ++f) {
        const auto p = kept_partial.find(f);
        const json& e = p != kept_partial.end() ? p->second : kept_final.at(f);
        for (const json& c : e["content"]) {
            if (p != kept_partial.end()) run.partial_files.push_back(c["file"].get<std::string>());
            run.files.emplace_back(c["file"].get<std::string>(), c["bytes"].get<std::size_t>());
        }
        run.z_min = std::min(run.z_min, e["height_range_m"][0].get<float>());
        run.z_max = std::max(run.z_max, e["height_range_m"][1].get<float>());
        run.entries.push_back(e.dump());
    }
    return run;
}

std::vector<std::string> remove_files_form_partials(const std::string& out_dir, FilesFormRun& run, const FrameIndexInfo& info) {
    std::error_code ignored;
    fs::remove_all(run.partial, ignored);  // every frame in it is published
    run.lock.release();
    const std::string ours = ".wave-partial-" + info.run_key.substr(0, 16) + "-";
    std::vector<std::string> removed;
    for (const auto& e : fs::directory_iterator(out_dir, ignored)) {
        const std::string name = e.path().filename().string();
        if (!name.starts_with(".wave-partial-") || name.starts_with(ours)) continue;
        try {
            const FolderLock unused(e.path().string(), false, "");
            if (fs::remove_all(e.path(), ignored) > 0 && !ignored) removed.push_back(name);
        } catch (const std::exception&) {  // in use, or not ours to open: left alone
        }
    }
    return removed;
}

std::string publish_files_form(FilesFormRun& run, const std::string& out_dir, const FrameIndexInfo& info, bool resume) {
    const fs::path root(out_dir);
    std::string index;
    {
        // Slices publishing into one folder at once take turns, so no slice's entries are lost.
        const FolderLock index_lock(out_dir, true, "");
        index = merged_frame_index((root / "index.json").string(), info, run.entries, run.whole_loop, resume);
        for (const std::string& name : run.partial_files) path_inside(out_dir, name, out_dir + ": an output");  // before any is moved
        // Frames first: the index is never in place before the frames it lists.
        for (const std::string& name : run.partial_files) {
            fs::create_directories((root / name).parent_path());
            fs::rename(fs::path(run.partial) / name, root / name);
        }
        write_file_atomic((root / "index.json").string(), index);
    }
    remove_files_form_partials(out_dir, run, info);
    return index;
}

}  // namespace wave
