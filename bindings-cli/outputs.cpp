// How `wave` puts its outputs on disk (outputs.h).
#include "outputs.h"

#include "libwave/errors.h"
#include "libwave/io.h"

#include <openssl/evp.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>

namespace wave::cli {

using nlohmann::json;
namespace fs = std::filesystem;

std::string sha256_hex(std::string_view bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
        throw RuntimeError("OpenSSL: SHA-256 failed");
    static constexpr char hex[] = "0123456789abcdef";
    std::string out(2 * length, '0');
    for (unsigned int i = 0; i < length; ++i) {
        out[2 * i] = hex[digest[i] >> 4];
        out[2 * i + 1] = hex[digest[i] & 15];
    }
    return out;
}

json frame_entry(std::size_t frame, double fps, const Files& frame_files, std::span<const float> positions) {
    json entry{{"frame", frame}, {"time", key_time(frame, fps)}, {"file", frame_files.front().first}, {"content", json::array()}};
    for (const auto& [name, bytes] : frame_files)
        entry["content"].push_back({{"file", name}, {"bytes", bytes.size()}, {"sha256", sha256_hex(bytes)}});
    if (!positions.empty()) {
        float z_min = std::numeric_limits<float>::infinity(), z_max = -z_min;
        for (std::size_t i = 2; i < positions.size(); i += 3) {
            z_min = std::min(z_min, positions[i]);
            z_max = std::max(z_max, positions[i]);
        }
        entry["height_range_m"] = {z_min, z_max};
    }
    return entry;
}

namespace {

// The file's bytes, or nothing when it cannot be read (a directory included: reading
// one through a stream throws basic_filebuf's own error).
std::optional<std::string> read_bytes(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return std::nullopt;
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    try {
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) return std::nullopt;
        return bytes;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace

std::string read_input_bytes(const fs::path& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError(path.string() + ": a directory, not a file");
    auto bytes = read_bytes(path);
    if (!bytes) throw InputError(path.string() + ": cannot read the file (" + (fs::exists(path, ec) ? "not a regular file or unreadable" : "file not found") + ")");
    return std::move(*bytes);
}

void check_out_dir(const std::string& out_dir) {
    std::error_code ec;
    for (fs::path p = fs::path(out_dir).lexically_normal(); !p.empty(); p = p.parent_path()) {
        if (fs::exists(p, ec)) {
            if (!fs::is_directory(p, ec)) {
                const std::string kind = fs::is_regular_file(p, ec) ? "a file" : fs::is_fifo(p, ec) ? "a FIFO (named pipe)" : "not a regular file";
                throw InputError(out_dir + ": " + (p == fs::path(out_dir).lexically_normal() ? kind : p.string() + " is " + kind) +
                                 ", not a folder; -o names the output folder");
            }
            return;
        }
        if (p == p.parent_path()) return;
    }
}

void check_report_place(const std::string& out_dir, const std::string& report_name) {
    std::error_code ec;
    const std::string at = path_inside(out_dir, report_name, out_dir + ": the run's report");
    const auto status = fs::symlink_status(at, ec);
    if (ec || !fs::exists(status) || fs::is_regular_file(status)) return;
    throw InputError(at + ": " + (fs::is_directory(status) ? "a folder" : fs::is_fifo(status) ? "a FIFO (named pipe)" : fs::is_symlink(status) ? "a link" : "not a regular file") +
                     ", where this run writes its report; remove it or use another output folder");
}

void check_files_form_places(const std::string& out_dir) {
    std::error_code ec;
    for (const char* name : {"index.json", "frames"}) {
        const std::string at = path_inside(out_dir, name, out_dir + ": the files form's");
        const bool folder = std::string_view(name) == "frames";
        const auto status = fs::status(at, ec);
        if (ec || !fs::exists(status)) continue;
        if (folder ? !fs::is_directory(status) : !fs::is_regular_file(status))
            throw InputError(at + ": " + (fs::is_directory(status) ? "a folder" : fs::is_regular_file(status) ? "a file" : "not a regular file") +
                             ", where the files form writes its " + (folder ? "frames' folder" : "index") +
                             "; remove it or use another output folder");
    }
}

bool files_form_left_over(const std::string& out_dir, const std::string& form) {
    std::error_code ec;
    std::vector<std::string> present;
    for (const char* name : {"index.json", "frames"})
        if (fs::exists(fs::symlink_status(fs::path(out_dir) / name, ec))) present.emplace_back(name);
    if (present.empty()) return false;
    for (const auto& e : fs::directory_iterator(out_dir, ec)) {
        const std::string name = e.path().filename().string();
        if (!name.starts_with("report") || !name.ends_with(".json") || !e.is_regular_file()) continue;
        const std::vector<std::string> recorded = recorded_outputs(out_dir, name);
        if (std::find(recorded.begin(), recorded.end(), "index.json") != recorded.end()) return true;
    }
    std::string what = (fs::path(out_dir) / present[0]).string();
    if (present.size() > 1) what += " and " + present[1];
    throw InputError(what + ": a files form's " + (present.size() > 1 ? "index and frames" : present[0] == "frames" ? "frames" : "index") +
                     " that no report of this folder claims; a " + form + " run here would leave them beside its own output, "
                     "where wave merge, wave convert and the readers would take them for the animation: remove them, run with "
                     "--overwrite (which does), or use another output folder");
}

// An index that cannot be read is a reason to recompute, not to stop a resumed run.
std::optional<json> read_index(const fs::path& path) {
    const auto bytes = read_bytes(path);
    if (!bytes) return std::nullopt;
    json index = json::parse(*bytes, nullptr, false);
    if (index.is_discarded() || !index.is_object() || !index.contains("frames") || !index["frames"].is_array())
        return std::nullopt;
    const auto typed = [&](const char* key, bool (json::*is)() const noexcept) { return !index.contains(key) || (index[key].*is)(); };
    if (!typed("scene", &json::is_string) || !typed("fps", &json::is_number) ||
        !typed("loop_frames", &json::is_number_unsigned) || !typed("run_key", &json::is_string))
        return std::nullopt;
    return index;
}

namespace {

bool same_animation(const json& index, const IndexInfo& info) {
    return index.value("scene", "") == info.name && index.value("fps", 0.0) == info.fps &&
           index.value("loop_frames", std::size_t{0}) == info.loop_frames;
}

}  // namespace

bool entry_intact(const json& entry, const fs::path& root) {
    if (!entry.is_object() || !entry.contains("content") || !entry["content"].is_array() || entry["content"].empty())
        return false;
    for (const json& c : entry["content"]) {
        if (!c.is_object() || !c.contains("file") || !c["file"].is_string() || !c.contains("bytes") ||
            !c["bytes"].is_number_unsigned() || !c.contains("sha256") || !c["sha256"].is_string())
            return false;
        const std::string name = c["file"].get<std::string>();
        std::string file;
        try {
            file = path_inside(root.string(), name, root.string());  // stays inside root, links included
        } catch (const InputError&) {
            return false;
        }
        std::error_code ec;
        const auto size = fs::file_size(file, ec);
        if (ec || size != c["bytes"].get<std::uintmax_t>()) return false;  // cheap check first
        const auto bytes = read_bytes(file);
        if (!bytes || sha256_hex(*bytes) != c["sha256"].get<std::string>()) return false;
    }
    return true;
}

json frame_index(const IndexInfo& info, std::vector<json> entries) {
    json index{{"scene", info.name}, {"fps", info.fps}, {"loop_period_s", info.loop_period}, {"loop_frames", info.loop_frames}};
    if (!info.run_key.empty()) index["run_key"] = info.run_key;
    index["frames"] = std::move(entries);
    return index;
}

json merged_index(const std::string& path, const IndexInfo& info, const std::vector<json>& entries, bool whole_loop,
                  bool rebuild_unreadable) {
    std::map<std::size_t, json> frames;
    std::error_code ec;
    const auto old = fs::exists(path, ec) ? read_index(path) : std::nullopt;
    if (fs::exists(path, ec) && (old || !rebuild_unreadable)) {
        if (!old) throw InputError(path + ": not a frame index of libwave (invalid JSON, or fields of other types); use another output folder");
        if (!same_animation(*old, info))
            throw InputError(path + ": the index there belongs to another animation (scene, fps or loop differ); "
                             "use another output folder");
        if (old->value("run_key", "") != info.run_key && !whole_loop)
            throw InputError(path + ": its frames were computed from another version of the scene, its seafloor or "
                             "libwave (run key differs); run the whole loop into it, or use another output folder");
        if (!whole_loop)
            for (const json& f : (*old)["frames"])
                if (f.is_object() && f.contains("frame") && f["frame"].is_number_unsigned())
                    frames[f["frame"].get<std::size_t>()] = f;
    }
    for (const json& e : entries) frames[e.at("frame").get<std::size_t>()] = e;
    std::vector<json> merged;
    for (auto& [_, f] : frames) merged.push_back(std::move(f));
    return frame_index(info, std::move(merged));
}

namespace {

// Slices on several hosts may publish into one shared folder: host and pid name the staging.
std::string staging_prefix() {
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
    return ".wave-staging-" + std::string(host) + "-";
}

}  // namespace

fs::path staging_folder(const std::string& out_dir) {
    return fs::path(out_dir) / (staging_prefix() + std::to_string(getpid()));
}

std::vector<std::string> remove_dead_staging(const std::string& out_dir) {
    const std::string mine = staging_prefix();
    std::vector<std::string> removed;
    std::error_code scan_error;
    for (const auto& e : fs::directory_iterator(out_dir, scan_error)) {
        const std::string name = e.path().filename().string();
        if (!name.starts_with(mine)) continue;
        const std::string pid_text = name.substr(mine.size());
        if (pid_text.empty() || pid_text.size() > 9 || pid_text.find_first_not_of("0123456789") != std::string::npos) continue;
        const auto pid = static_cast<pid_t>(std::stol(pid_text));
        if (pid != getpid() && ::kill(pid, 0) != 0 && errno == ESRCH) {
            std::error_code ignored;
            if (fs::remove_all(e.path(), ignored) > 0 && !ignored) removed.push_back(name);
        }
    }
    return removed;
}

std::vector<std::string> publish(const std::string& out_dir, const Files& files,
                                 const std::function<std::vector<std::string>(const fs::path&)>& write_more) {
    const bool created = !fs::exists(out_dir);
    fs::create_directories(out_dir);
    const fs::path staging = staging_folder(out_dir);
    // A run killed on this host (SIGKILL, power) left its staging folder: nothing in it
    // was published, so it goes (every run and convert also sweeps them as it starts).
    remove_dead_staging(out_dir);
    for (const auto& [name, _] : files) path_inside(out_dir, name, out_dir + ": an output");  // nothing written through a link out
    try {
        fs::create_directories(staging);
        std::vector<std::string> names;
        if (write_more) names = write_more(staging);
        for (const auto& [name, bytes] : files) {
            fs::create_directories((staging / name).parent_path());
            write_file_atomic((staging / name).string(), bytes);
            names.push_back(name);
        }
        for (const std::string& name : names) path_inside(out_dir, name, out_dir + ": an output");  // before any is moved
        for (const std::string& name : names) {
            fs::create_directories((fs::path(out_dir) / name).parent_path());
            fs::rename(staging / name, fs::path(out_dir) / name);
        }
        fs::remove_all(staging);
        return names;
    } catch (...) {
        std::error_code ignored;
        fs::remove_all(staging, ignored);
        if (created) fs::remove_all(out_dir, ignored);  // it was ours and holds nothing finished
        throw;
    }
}

namespace {

// A name a report may list: relative, inside the folder, not a frame file.
bool own_output_name(const std::string& name) {
    const fs::path p(name);
    if (name.empty() || p.is_absolute() || name.starts_with("frames/")) return false;
    for (const auto& part : p)
        if (part == "..") return false;
    return true;
}

}  // namespace

std::vector<std::string> recorded_outputs(const std::string& out_dir, const std::string& report_name) {
    const auto bytes = read_bytes(fs::path(out_dir) / report_name);  // a regular file only: a FIFO there blocked the run's end
    if (!bytes) return {};
    const json report = json::parse(*bytes, nullptr, false);
    if (report.is_discarded() || !report.is_object() || !report.contains("outputs") || !report["outputs"].is_array()) return {};
    std::vector<std::string> names{report_name};
    for (const json& n : report["outputs"])
        if (n.is_string() && own_output_name(n.get<std::string>())) names.push_back(n.get<std::string>());
    return names;
}

std::vector<std::string> every_recorded_output(const std::string& out_dir) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out_dir, ec)) {
        const std::string name = e.path().filename().string();
        if (e.is_regular_file() && name.starts_with("report") && name.ends_with(".json")) {
            const std::vector<std::string> more = recorded_outputs(out_dir, name);
            names.insert(names.end(), more.begin(), more.end());
        }
    }
    names.emplace_back("index.json");
    names.emplace_back("frames");
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
}

std::vector<std::string> remove_stale_outputs(const std::string& out_dir, const std::vector<std::string>& earlier,
                                              const std::vector<std::string>& published) {
    std::vector<std::string> removed;
    for (const std::string& name : earlier) {
        if (std::find(published.begin(), published.end(), name) != published.end()) continue;
        std::error_code ec;
        if (fs::remove_all(fs::path(out_dir) / name, ec) > 0 && !ec) removed.push_back(name);
    }
    return removed;
}

FolderLock::FolderLock(const fs::path& folder, bool wait, const std::string& busy) {
    fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) throw RuntimeError(folder.string() + ": cannot open the folder to lock it: " + std::strerror(errno));
    int rc = 0;
    while ((rc = ::flock(fd_, LOCK_EX | (wait ? 0 : LOCK_NB))) != 0 && errno == EINTR) {}
    if (rc != 0) {
        const int error = errno;
        release();
        if (error == EWOULDBLOCK) throw InputError(busy);
        throw RuntimeError(folder.string() + ": cannot lock: " + std::strerror(error));
    }
}

void FolderLock::release() noexcept {
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

std::vector<std::string> FilesFormRun::stage(const fs::path& staging) const {
    // Linked, not moved: if publishing fails the partial folder still holds every frame
    // its index lists, and --resume keeps them.
    for (const std::string& name : partial_files) {
        fs::create_directories((staging / name).parent_path());
        std::error_code ec;
        fs::create_hard_link(partial / name, staging / name, ec);
        if (ec) fs::copy_file(partial / name, staging / name);  // a file system without hard links
    }
    return partial_files;
}

FilesFormRun write_files_form(const Scene& scene, const ScenePlan& plan, const std::string& out_dir, const IndexInfo& info,
                              FrameRange range, bool resume, double max_bytes,
                              const std::function<void(std::size_t, std::size_t)>& progress) {
    const fs::path root(out_dir);
    const std::size_t first = range.first, end = std::min(range.end, info.loop_frames);
    if (first >= end)
        throw InputError("scene: the frame range " + std::to_string(first) + ":" +
                         (range.end == static_cast<std::size_t>(-1) ? std::string() : std::to_string(range.end)) +
                         " holds no frame of the loop's 0:" + std::to_string(info.loop_frames));
    FilesFormRun run;
    // One partial folder per run key and range: another scene, or another slice of this
    // one, never finds its frames there.
    run.partial = root / (".wave-partial-" + info.run_key.substr(0, 16) + "-" + std::to_string(first) + "-" + std::to_string(end));
    const bool created = !fs::exists(root);
    fs::create_directories(run.partial);
    run.lock = FolderLock(run.partial, false,
                        out_dir + ": another wave run is writing frames " + std::to_string(first) + ":" + std::to_string(end) +
                            " of this animation there (" + run.partial.filename().string() + " is locked)");
    const fs::path partial_index = run.partial / "index.json";
    std::map<std::size_t, json> kept_partial, kept_final;
    if (resume) {
        // Frames are kept only when their files match what the index recorded: a frame
        // file that exists but was truncated, overwritten or belongs to another run is
        // computed again.
        const auto listed = [&](const fs::path& index_path) {
            std::map<std::size_t, json> frames;
            const auto index = read_index(index_path);
            if (!index || !same_animation(*index, info) || index->value("run_key", "") != info.run_key) return frames;
            for (const json& e : (*index)["frames"])
                if (e.is_object() && e.contains("frame") && e["frame"].is_number_unsigned() && e.contains("height_range_m") &&
                    e["height_range_m"].is_array() && e["height_range_m"].size() == 2 && e["height_range_m"][0].is_number() &&
                    e["height_range_m"][1].is_number()) {
                    const auto f = e["frame"].get<std::size_t>();
                    if (f >= first && f < end) frames[f] = e;
                }
            return frames;
        };
        for (auto& [f, e] : listed(partial_index))
            if (entry_intact(e, run.partial)) kept_partial[f] = std::move(e);
        for (auto& [f, e] : listed(root / "index.json"))
            if (!kept_partial.count(f) && entry_intact(e, root)) kept_final[f] = std::move(e);
    } else {
        std::error_code ignored;
        fs::remove_all(run.partial / "frames", ignored);
        fs::remove(partial_index, ignored);
    }
    run.verified = kept_partial.size() + kept_final.size();
    const auto write_partial_index = [&] {
        std::vector<json> listed;
        for (const auto& [_, e] : kept_partial) listed.push_back(e);
        write_file_atomic(partial_index.string(), frame_index(info, std::move(listed)).dump(2) + "\n");
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
                    const Files frame_files = encode_animation(frame_subview(view, k, 1), Scene::Form::files, scene.container, false,
                                                               frame_k(anim.caustics), frame_k(anim.sunbeams), frame_k(anim.whitewater));
                    for (const auto& [name, bytes] : frame_files) {
                        fs::create_directories((run.partial / name).parent_path());
                        write_file_atomic((run.partial / name).string(), bytes);
                    }
                    const std::size_t f = anim.first_frame + k;
                    kept_partial[f] = frame_entry(f, info.fps, frame_files, view.positions.subspan(3 * n * k, 3 * n));
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
            fs::remove_all(run.partial, ignored);
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
        json e = p != kept_partial.end() ? p->second : kept_final.at(f);
        if (p != kept_partial.end())
            for (const json& c : e["content"]) run.partial_files.push_back(c["file"].get<std::string>());
        run.z_min = std::min(run.z_min, e["height_range_m"][0].get<float>());
        run.z_max = std::max(run.z_max, e["height_range_m"][1].get<float>());
        run.entries.push_back(std::move(e));
    }
    return run;
}

}  // namespace wave::cli
