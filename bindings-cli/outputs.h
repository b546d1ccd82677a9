// How `wave` puts its outputs on disk: the animation's files in each form, the files
// form's frame index (each frame's files with size and SHA-256), a chunk-at-a-time
// writer for the files form that a killed run can resume, and publication through a
// staging folder (docs/hardening.md, "Crash safety").
#pragma once

#include "libwave/export.h"
#include "libwave/scene.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wave::cli {

/// (name under the output folder, bytes) pairs (libwave's encode_animation makes them).
using Files = EncodedFiles;

/// SHA-256 of `bytes` in lowercase hex (OpenSSL): what the index records per file, and
/// what `sha256sum` prints for it.
std::string sha256_hex(std::string_view bytes);


/// What a frame index describes: one animation (name, fps, loop) and the run that
/// computed its frames.
struct IndexInfo {
    std::string name;
    double fps = 24.0, loop_period = 0.0;
    std::size_t loop_frames = 0;
    /// SHA-256 over what decides the frames' bytes (libwave's version, the scene file,
    /// the command-line overrides, the seafloor's heights); empty when unknown (`wave
    /// convert` re-encodes frames it did not compute).
    std::string run_key;
};

/// A frame's index entry: its number, key time, file, each of its files ("content":
/// file, bytes, sha256 — a .gltf frame has its .bin beside it) and, when its positions
/// (x, y, z per vertex) are given, its height range.
nlohmann::json frame_entry(std::size_t frame, double fps, const Files& frame_files, std::span<const float> positions = {});

/// Whether every file an entry lists is under `root` with the size and SHA-256 the
/// entry records (an entry without "content" cannot be verified: false).
bool entry_intact(const nlohmann::json& entry, const std::filesystem::path& root);

/// The frame index at `path`, or nothing when there is none or it is not one of ours:
/// not JSON, no "frames" array, or "scene", "fps", "loop_frames", "run_key" of another
/// type than libwave writes (an index is read back after crashes and by other tools'
/// hands: a wrong type is "not an index", never an exception from deep inside).
std::optional<nlohmann::json> read_index(const std::filesystem::path& path);

/// The bytes of a file the user's folder holds (a frame, a scene): InputError naming the
/// path for a directory or a file that cannot be read (never the stream's own error).
std::string read_input_bytes(const std::filesystem::path& path);

/// Refuses (InputError, before any work) an output folder that is a file, or lies
/// below one: `-o` names a folder.
void check_out_dir(const std::string& out_dir);

/// Refuses (InputError, before any frame is computed) a folder whose index.json is not a
/// file, whose frames is not a folder, or either a link out of the folder (path_inside):
/// the files form writes there.
void check_files_form_places(const std::string& out_dir);

/// For a run of another form than files into `out_dir` (without --overwrite): whether
/// the folder holds a files form's index.json or frames/ that this run would leave stale
/// beside its own output (wave merge, convert and the readers would pick them up).
/// True when an earlier libwave run recorded them (a report lists index.json): the run
/// then removes both once it has published. Throws InputError, before anything is
/// computed, when they are there but no report claims them (not ours to remove).
bool files_form_left_over(const std::string& out_dir, const std::string& form);

/// index.json of an animation holding `entries` (frames in order).
nlohmann::json frame_index(const IndexInfo& info, std::vector<nlohmann::json> entries);

/// index.json for `entries` (frames of this run, in order), merged with the index a
/// previous slice of the same animation left at `path`. Throws InputError when that
/// index belongs to another animation (scene name, fps, loop), or — unless this run
/// covers the whole loop and so replaces every entry — to another run key. An index
/// that cannot be read (truncated, empty, fields of other types) is refused too, unless
/// `rebuild_unreadable` (`--resume`: the frames' own files are checked instead), when
/// it is rebuilt from this run's entries.
nlohmann::json merged_index(const std::string& path, const IndexInfo& info, const std::vector<nlohmann::json>& entries,
                            bool whole_loop, bool rebuild_unreadable = false);

/// Writes `files` into a staging folder inside `out_dir` and then renames them into
/// place: a failing run leaves neither partial files nor a half-replaced set of
/// outputs. `write_more` puts files that are not held as bytes into the staging folder
/// (the strips PLY, the files form's frames) and returns their names; they are renamed
/// first, so an index is never in place before the frames it lists.
/// Returns the names published (relative to out_dir).
std::vector<std::string> publish(const std::string& out_dir, const Files& files,
                                 const std::function<std::vector<std::string>(const std::filesystem::path&)>& write_more = {});

/// The outputs an earlier run recorded in `out_dir/report_name` ("outputs" of its
/// report; names inside the folder only, frame files excluded: the index owns those),
/// plus the report itself; empty when there is none or it is unreadable.
std::vector<std::string> recorded_outputs(const std::string& out_dir, const std::string& report_name);

// Refuses (InputError, naming it) a FIFO, folder, link or device where this run writes its
// report (`report_name` in `out_dir`): before any frame is computed, not at the run's end.
void check_report_place(const std::string& out_dir, const std::string& report_name);

/// Every output a libwave run recorded in `out_dir` (each report*.json's outputs and
/// the reports), and the files form's index.json and frames/ folder: what
/// `wave run --overwrite` removes before it publishes.
std::vector<std::string> every_recorded_output(const std::string& out_dir);

/// Removes the files of `earlier` that are not in `published` (a rerun's stale outputs:
/// another container, no preview this time); returns their names.
std::vector<std::string> remove_stale_outputs(const std::string& out_dir, const std::vector<std::string>& earlier,
                                              const std::vector<std::string>& published);

/// The staging folder publish uses in `out_dir` for this process (hidden, named by host
/// and pid: one that a killed run left is swept by the next publish on the host).
/// Streamed animations are written there as their frames come, then published.
std::filesystem::path staging_folder(const std::string& out_dir);

/// Removes the staging folders that runs killed on this host left in `out_dir` (their
/// process is gone: nothing in them was published) and returns their names. `wave run`,
/// `wave convert` and `wave merge` call it as they start, before anything can fail, and
/// publish again: a killed run's staging does not outlive the next command on the folder.
std::vector<std::string> remove_dead_staging(const std::string& out_dir);

/// An exclusive flock(2) on a folder, released when destroyed or when the process dies
/// (a SIGKILLed run never leaves it held). `wait` blocks until the lock is free;
/// otherwise a held lock throws InputError with `busy`.
class FolderLock {
public:
    FolderLock() = default;
    FolderLock(const std::filesystem::path& folder, bool wait, const std::string& busy);
    FolderLock(FolderLock&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
    FolderLock& operator=(FolderLock&& o) noexcept {
        if (this != &o) {
            release();
            fd_ = std::exchange(o.fd_, -1);
        }
        return *this;
    }
    ~FolderLock() { release(); }
    void release() noexcept;

private:
    int fd_ = -1;
};

/// The files form of frames [range.first, range.end), computed `files_form_chunk`
/// frames at a time. Each chunk's frame files go into a hidden partial folder of the
/// output folder (named by the run key and the range) and are listed, with their sizes
/// and SHA-256, in that folder's own index.json; a run killed at any moment leaves
/// every frame it listed whole. With `resume`, frames the partial index (or the output
/// folder's index.json, same run key) lists and whose files still match it are kept;
/// the others are computed. Without `resume` the partial folder starts empty.
struct FilesFormRun {
    std::vector<nlohmann::json> entries;  ///< one per frame of the range, in order
    float z_min = 0.0f, z_max = 0.0f;     ///< height range over the range's frames
    std::size_t verified = 0, computed = 0;
    std::filesystem::path partial;        ///< the partial folder (removed once published)
    std::vector<std::string> partial_files;  ///< frame files in it, to publish
    FolderLock lock;                      ///< on the partial folder while the run holds it
    /// Links the partial frames into `staging` (publish's write_more) and returns their names.
    std::vector<std::string> stage(const std::filesystem::path& staging) const;
};
FilesFormRun write_files_form(const Scene& scene, const ScenePlan& plan, const std::string& out_dir, const IndexInfo& info,
                              FrameRange range, bool resume, double max_bytes,
                              const std::function<void(std::size_t, std::size_t)>& progress);

}  // namespace wave::cli
