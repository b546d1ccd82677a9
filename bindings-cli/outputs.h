// How `wave` puts its outputs on disk: the checks of the output folder before a run,
// publication through a staging folder, and the outputs earlier runs recorded
// (docs/hardening.md, "Crash safety"). The files form itself — its frames written a
// chunk at a time into a partial folder a killed run resumes, its index, the folder
// lock — is libwave's (scene.h, write_files_form; export.h, FrameIndexInfo).
#pragma once

#include "libwave/export.h"
#include "libwave/scene.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace wave::cli {

/// (name under the output folder, bytes) pairs (libwave's encode_animation makes them).
using Files = EncodedFiles;

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

}  // namespace wave::cli
