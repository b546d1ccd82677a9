// How `wave` puts its outputs on disk (outputs.h).
#include "outputs.h"

#include "libwave/errors.h"
#include "libwave/io.h"

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <fstream>
#include <iterator>
#include <optional>
#include <string_view>

namespace wave::cli {

using nlohmann::json;
namespace fs = std::filesystem;


std::string read_input_bytes(const fs::path& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw InputError(path.string() + ": a directory, not a file");
    auto bytes = read_regular_file(path.string());
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
    const auto bytes = read_regular_file((fs::path(out_dir) / report_name).string());  // a regular file only: a FIFO there blocked the run's end
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

}  // namespace wave::cli
