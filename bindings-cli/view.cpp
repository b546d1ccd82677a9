// `wave view`: serves the three.js viewer (bundled at build time from npm, installed
// with the CLI) and one output folder on 127.0.0.1 with cpp-httplib. Nothing is
// fetched from outside: the page, three.js and the Draco decoder come from here.
#include "commands.h"
#include "libwave/errors.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace wave::cli {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

httplib::Server* running = nullptr;  // for the signal handler

void stop_server(int) {
    if (running) running->stop();
}

// The viewer's files: $LIBWAVE_VIEWER_DIR, else <bin>/../share/libwave/viewer (the
// build tree and an installed prefix have the same layout).
fs::path viewer_dir() {
    if (const char* env = std::getenv("LIBWAVE_VIEWER_DIR"); env && *env) return env;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path("share/libwave/viewer") : exe.parent_path().parent_path() / "share" / "libwave" / "viewer";
}

bool is_animation_file(const fs::path& p) {
    const std::string ext = p.extension().string();
    return (ext == ".glb" || ext == ".gltf") && p.filename().string().rfind("animation", 0) == 0;
}

}  // namespace

ViewerOutputs find_viewer_outputs(const std::string& path) {
    ViewerOutputs v;
    std::error_code ec;
    const fs::path p = fs::absolute(path, ec);
    if (ec || !fs::exists(p)) throw InputError("view: no such file or folder '" + path + "'");
    const auto add = [&](const fs::path& file) {
        const bool index = file.filename() == "index.json";
        v.outputs.push_back({file.filename().string(), index ? "index" : "gltf"});
    };
    if (fs::is_regular_file(p)) {
        const std::string ext = p.extension().string();
        if (ext != ".glb" && ext != ".gltf" && p.filename() != "index.json")
            throw InputError("view: '" + path + "' is not a libwave output (expected a .glb, a .gltf or the files form's index.json)");
        v.root = p.parent_path();
        add(p);
        return v;
    }
    v.root = p;
    if (fs::exists(p / "index.json")) add(p / "index.json");
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(p))
        if (e.is_regular_file() && is_animation_file(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) add(f);
    if (v.outputs.empty())
        throw InputError("view: no libwave output in '" + path + "' (expected animation*.glb / .gltf or index.json)");
    return v;
}

int run_view(const ViewArgs& a) {
    const ViewerOutputs outputs = find_viewer_outputs(a.path);
    const fs::path assets = viewer_dir();
    if (!fs::exists(assets / "index.html") || !fs::exists(assets / "viewer.js"))
        throw std::runtime_error("view: the viewer's page is not installed at " + assets.string() +
                                 " (built from bindings-cli/viewer with npm; scripts/install-deps.sh installs it)");
    if (a.port < 0 || a.port > 65535) throw InputError("view: --port must be in [0, 65535], got " + std::to_string(a.port));

    httplib::Server server;
    for (const auto& [ext, type] : std::vector<std::pair<const char*, const char*>>{
             {"html", "text/html; charset=utf-8"}, {"js", "text/javascript"}, {"wasm", "application/wasm"},
             {"json", "application/json"}, {"glb", "model/gltf-binary"}, {"gltf", "model/gltf+json"},
             {"bin", "application/octet-stream"}, {"png", "image/png"}})
        server.set_file_extension_and_mimetype_mapping(ext, type);
    // SO_REUSEADDR only: cpp-httplib's default also sets SO_REUSEPORT, with which a
    // second `wave view` would silently share a port already serving another folder.
    server.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    json list = json::array();
    for (const auto& o : outputs.outputs) list.push_back({{"name", o.name}, {"kind", o.kind}, {"url", "/out/" + o.name}});
    const std::string body = json{{"root", outputs.root.string()}, {"outputs", list}}.dump();
    server.Get("/api/outputs", [body](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        res.set_content(body, "application/json");
    });
    // cpp-httplib refuses paths that climb out of a mount point ("..").
    if (!server.set_mount_point("/out", outputs.root.string()) || !server.set_mount_point("/", assets.string()))
        throw std::runtime_error("view: cannot serve " + outputs.root.string());

    int port = a.port;
    if (port == 0) {
        port = server.bind_to_any_port(a.host);
    } else if (!server.bind_to_port(a.host, port)) {
        if (a.port_given) throw InputError("view: port " + std::to_string(port) + " on " + a.host + " is in use; choose another with --port (0 = any free port)");
        port = server.bind_to_any_port(a.host);  // the default was taken: any free one
    }
    if (port <= 0) throw std::runtime_error("view: cannot listen on " + a.host);

    const std::string url = "http://" + a.host + ":" + std::to_string(port) + "/";
    std::cout << "wave view: " << outputs.root.string() << " (" << outputs.outputs.size() << " output"
              << (outputs.outputs.size() == 1 ? "" : "s") << ") at " << url << "  — Ctrl-C stops" << std::endl;
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if (a.open && ((display && *display) || (wayland && *wayland))) {
        // A display: hand the URL to the desktop's browser (not waited for).
        std::string opener = "xdg-open";
        char* argv[] = {opener.data(), const_cast<char*>(url.c_str()), nullptr};
        pid_t pid = 0;
        if (posix_spawnp(&pid, "xdg-open", nullptr, nullptr, argv, environ) != 0)
            std::cout << "wave view: no xdg-open here; open " << url << " in a browser" << std::endl;
    }
    running = &server;
    std::signal(SIGINT, stop_server);
    std::signal(SIGTERM, stop_server);
    std::signal(SIGCHLD, SIG_IGN);  // xdg-open is not waited for
    const bool ok = server.listen_after_bind();
    running = nullptr;
    return ok ? 0 : 1;
}

}  // namespace wave::cli
