// `wave batch`: many scenes, each run by its own `wave run` process (a failure or a
// crash stays inside its scene), up to --jobs at a time, and a summary.
#include "commands.h"
#include "libwave/errors.h"
#include "libwave/io.h"
#include "outputs.h"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <glob.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

extern char** environ;

namespace wave::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Folders give their *.json files, patterns their matches, files themselves; sorted,
// without repeats. An input that names nothing goes to `missing`: that scene fails, the
// others still run.
std::vector<std::string> expand_inputs(const std::vector<std::string>& inputs, std::vector<std::string>& missing) {
    std::vector<std::string> scenes;
    for (const std::string& in : inputs) {
        if (fs::is_directory(in)) {
            for (const auto& e : fs::directory_iterator(in))
                if (e.is_regular_file() && e.path().extension() == ".json") scenes.push_back(e.path().string());
            continue;
        }
        if (fs::exists(in)) {
            scenes.push_back(in);
            continue;
        }
        glob_t g{};
        const int rc = glob(in.c_str(), 0, nullptr, &g);
        if (rc == 0)
            for (std::size_t i = 0; i < g.gl_pathc; ++i) scenes.emplace_back(g.gl_pathv[i]);
        globfree(&g);
        if (rc != 0) missing.push_back(in);
    }
    std::sort(scenes.begin(), scenes.end());
    scenes.erase(std::unique(scenes.begin(), scenes.end()), scenes.end());
    if (scenes.empty() && missing.empty()) throw InputError("batch: no scene files (*.json) in the inputs");
    return scenes;
}

struct Job {
    std::string scene, out, err_file, report_file;  // the run's messages and its report (stdout, --json)
    json report;                                    // what it printed there
    pid_t pid = -1;
    Clock::time_point start;
    int exit_code = -1;
    std::string error;
    double seconds = 0.0;
};

std::string tail_of(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const auto last = text.rfind('\n');  // the error line is the last one
    std::string line = last == std::string::npos ? text : text.substr(last + 1);
    if (line.rfind("error: ", 0) == 0) line.erase(0, 7);
    return line;
}

// What a scene's run left in its folder: every file (relative path, bytes), their total,
// and the frames its report names (surface.frames; 0 when it has none). The report is
// the one the run printed (--json), not a file of the folder: a slice (--frames) writes
// report-frames-A-B.json, and earlier runs may have left other reports there.
void describe_outputs(const std::string& folder, const json& report, json& r) {
    json files = json::array();
    std::uintmax_t total = 0;
    std::vector<fs::path> paths;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->is_regular_file()) paths.push_back(it->path());
    std::sort(paths.begin(), paths.end());
    for (const fs::path& p : paths) {
        const std::uintmax_t bytes = fs::file_size(p, ec);
        total += ec ? 0 : bytes;
        files.push_back({{"file", fs::relative(p, folder).string()}, {"bytes", ec ? 0 : bytes}});
    }
    r["outputs"] = std::move(files);
    r["bytes"] = total;
    r["frames"] = 0;
    if (report.is_object() && report.contains("surface") && report["surface"].contains("frames"))
        r["frames"] = report["surface"]["frames"];
}

}  // namespace

int run_batch(const BatchArgs& a) {
    if (a.jobs < 1) throw InputError("batch: --jobs must be >= 1");
    std::vector<std::string> missing;
    const std::vector<std::string> scenes = expand_inputs(a.inputs, missing);
    // Each scene's outputs go to OUT/<file stem>: two scenes with one stem would collide.
    std::map<std::string, std::string> by_stem;
    for (const std::string& s : scenes) {
        const std::string stem = fs::path(s).stem().string();
        if (auto [it, fresh] = by_stem.emplace(stem, s); !fresh)
            throw InputError("batch: " + it->second + " and " + s + " would both write " + (fs::path(a.out_dir) / stem).string() +
                             "; rename one");
    }
    check_out_dir(a.out_dir);
    fs::create_directories(a.out_dir);
    {  // each scene's messages go to a file in the output folder: it must take one
        const fs::path probe = fs::path(a.out_dir) / (".batch-" + std::to_string(getpid()) + "-probe");
        const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0) throw RuntimeError("batch: cannot write in the output folder " + a.out_dir + " (" + std::strerror(errno) + ")");
        ::close(fd);
        std::error_code ignored;
        fs::remove(probe, ignored);
    }
    const std::string self = fs::read_symlink("/proc/self/exe").string();
    std::vector<Job> jobs;
    for (const std::string& s : missing) {  // failed before they start: bad input (2)
        Job j;
        j.scene = s;
        j.exit_code = 2;
        j.error = "batch: " + s + ": no such scene file, folder or matching pattern";
        if (!a.quiet && !a.json) std::cout << "[" << jobs.size() + 1 << "/" << missing.size() + scenes.size() << "] FAILED " << s << ": " << j.error << '\n';
        jobs.push_back(std::move(j));
    }
    for (const std::string& s : scenes) {
        Job j;
        j.scene = s;
        j.out = (fs::path(a.out_dir) / fs::path(s).stem()).string();
        j.err_file = (fs::path(a.out_dir) / (".batch-" + std::to_string(getpid()) + "-" + fs::path(s).stem().string() + ".err")).string();
        j.report_file = j.err_file.substr(0, j.err_file.size() - 4) + ".json";
        jobs.push_back(std::move(j));
    }

    const auto spawn = [&](Job& j) {
        std::vector<std::string> args{self, "run", j.scene, "-o", j.out, "--json"};  // the report on stdout, no progress bar
        for (const auto& extra : a.run_args) args.push_back(extra);
        std::vector<char*> argv;
        for (auto& s : args) argv.push_back(s.data());
        argv.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, j.err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, j.report_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        j.start = Clock::now();
        const int rc = posix_spawn(&j.pid, self.c_str(), &actions, nullptr, argv.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0)
            throw RuntimeError("batch: cannot start " + self + " for " + j.scene + " (" + std::strerror(rc) +
                               "; its messages go to " + j.err_file + ")");
    };

    std::size_t next = missing.size(), running = 0, done = missing.size();  // the missing ones have failed
    std::map<pid_t, std::size_t> by_pid;
    while (done < jobs.size()) {
        while (running < static_cast<std::size_t>(a.jobs) && next < jobs.size()) {
            spawn(jobs[next]);
            by_pid[jobs[next].pid] = next;
            ++next, ++running;
        }
        int status = 0;
        const pid_t pid = waitpid(-1, &status, 0);
        if (pid < 0) throw RuntimeError("batch: waitpid failed");
        const auto it = by_pid.find(pid);
        if (it == by_pid.end()) continue;
        Job& j = jobs[it->second];
        j.seconds = std::chrono::duration<double>(Clock::now() - j.start).count();
        j.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        j.error = j.exit_code == 0 ? "" : tail_of(j.err_file);
        if (j.error.empty() && j.exit_code != 0) j.error = "terminated by signal " + std::to_string(WTERMSIG(status));
        std::error_code ignored;
        fs::remove(j.err_file, ignored);
        if (j.exit_code == 0) {
            std::ifstream in(j.report_file);
            j.report = json::parse(in, nullptr, false);
        }
        fs::remove(j.report_file, ignored);
        --running, ++done;
        if (!a.quiet && !a.json)
            std::cout << "[" << done << "/" << jobs.size() << "] " << (j.exit_code == 0 ? "ok     " : "FAILED ") << j.scene
                      << (j.exit_code == 0 ? " -> " + j.out : ": " + j.error) << '\n'
                      << std::flush;
    }

    json summary{{"scenes", jobs.size()}, {"ok", 0}, {"failed", 0}, {"results", json::array()}};
    int worst = 0;
    for (const Job& j : jobs) {
        const bool ok = j.exit_code == 0;
        summary[ok ? "ok" : "failed"] = summary[ok ? "ok" : "failed"].get<int>() + 1;
        json r{{"scene", j.scene}, {"status", ok ? "ok" : "failed"}, {"exit_code", j.exit_code}, {"seconds", j.seconds}};
        if (ok) {
            r["output"] = j.out;
            describe_outputs(j.out, j.report, r);
        } else {
            r["error"] = j.error;
        }
        summary["results"].push_back(r);
        // Bad input (2) outranks a runtime failure (1) and a crash counts as a runtime failure.
        const int code = ok ? 0 : j.exit_code == 2 ? 2 : 1;
        worst = std::max(worst, code);
    }
    write_file_atomic((fs::path(a.out_dir) / "batch-summary.json").string(), summary.dump(2) + "\n");
    if (a.json) std::cout << summary.dump(2) << '\n';
    else if (!a.quiet)
        std::cout << summary["ok"].get<int>() << " of " << jobs.size() << " scenes ok; summary in "
                  << (fs::path(a.out_dir) / "batch-summary.json").string() << '\n';
    return worst;
}

}  // namespace wave::cli
