// `wave view`: serves the three.js viewer (bundled at build time from npm, installed
// with the CLI) and one output folder on 127.0.0.1 with cpp-httplib. Nothing is
// fetched from outside: the page, three.js and the Draco decoder come from here.
#include "commands.h"
#include "libwave/errors.h"
#include "libwave/io.h"
#include "view_server.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
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

std::atomic<bool> stopping{false};  // set by SIGINT / SIGTERM (lock-free: safe in a handler)

void stop_server(int) { stopping = true; }

// The viewer's files: $LIBWAVE_VIEWER_DIR, else <bin>/../share/libwave/viewer (the
// build tree and an installed prefix have the same layout).
fs::path viewer_dir() {
    if (const char* env = std::getenv("LIBWAVE_VIEWER_DIR"); env && *env) return env;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return ec ? fs::path("share/libwave/viewer") : exe.parent_path().parent_path() / "share" / "libwave" / "viewer";
}

// The file a request for /out/<relative> names, if it is a regular file whose real
// path (every symlink resolved) lies inside the served folder's real path; nothing
// otherwise. Output folders are shared (farm storage, downloads), so their links are
// not trusted: a link that stays inside the folder is served, one that leaves it is not.
std::optional<fs::path> served_file(const fs::path& root_real, const std::string& relative) {
    if (relative.empty() || relative.find('\0') != std::string::npos) return std::nullopt;
    const fs::path rel(relative);
    if (rel.is_absolute()) return std::nullopt;
    for (const auto& part : rel)
        if (part == "..") return std::nullopt;
    std::error_code ec;
    const fs::path real = fs::canonical(root_real / rel, ec);
    if (ec || !fs::is_regular_file(real, ec)) return std::nullopt;
    auto p = real.begin();
    for (auto r = root_real.begin(); r != root_real.end(); ++r, ++p)
        if (p == real.end() || *p != *r) return std::nullopt;
    return real;
}

// Host headers a page of this machine sends: 127.0.0.1, localhost or [::1] with our
// port. A page of another site that rebinds its name to 127.0.0.1 sends its own name.
bool local_host(const std::string& host, int port) {
    const std::size_t colon = host.rfind(':');
    if (colon == std::string::npos || host.substr(colon + 1) != std::to_string(port)) return false;
    const std::string name = host.substr(0, colon);
    return name == "127.0.0.1" || name == "localhost" || name == "[::1]";
}

// 128 random bits as hex: the token of this `wave view` (docs/viewer.md).
std::string random_token() {
    unsigned char bytes[16] = {};
    std::ifstream urandom("/dev/urandom", std::ios::binary);
    if (!urandom.read(reinterpret_cast<char*>(bytes), sizeof bytes)) throw std::runtime_error("view: cannot read /dev/urandom");
    static const char* hex = "0123456789abcdef";
    std::string token;
    for (unsigned char b : bytes) token += {hex[b >> 4], hex[b & 15]};
    return token;
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
    // A FIFO or device is never listed, served or opened (it made the folder listing fail
    // with the file system's message, exit 1): the argument a file or folder, an
    // index.json a regular file.
    require_input_file(p.string(), fs::is_directory(p, ec));
    if (fs::is_directory(p, ec) && fs::exists(fs::symlink_status(p / "index.json", ec))) require_input_file((p / "index.json").string());
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
    // The whitewater beside them (/whitewater), by loop frame: the page asks only for these.
    const fs::path points = v.root / "whitewater";
    if (fs::is_directory(points, ec) && !fs::is_symlink(points, ec))
        for (const auto& e : fs::directory_iterator(points, ec)) {
            const std::string name = e.path().filename().string();
            if (e.is_regular_file() && name.size() == 19 && name.starts_with("whitewater-") && name.ends_with(".glb") &&
                std::all_of(name.begin() + 11, name.begin() + 15, [](char c) { return c >= '0' && c <= '9'; }))
                v.whitewater_frames.push_back(std::stoi(name.substr(11, 4)));
        }
    std::sort(v.whitewater_frames.begin(), v.whitewater_frames.end());
    return v;
}

int run_view(const ViewArgs& a) {
    const ViewerOutputs outputs = find_viewer_outputs(a.path);
    const fs::path assets = viewer_dir();
    if (!fs::exists(assets / "index.html") || !fs::exists(assets / "viewer.js"))
        throw std::runtime_error("view: the viewer's page is not installed at " + assets.string() +
                                 " (built from bindings-cli/viewer with npm; scripts/install-deps.sh installs it)");
    if (a.port < 0 || a.port > 65535) throw InputError("view: --port must be in [0, 65535], got " + std::to_string(a.port));

    ViewServer server;
    const std::map<std::string, std::string> types{
        {".html", "text/html; charset=utf-8"}, {".js", "text/javascript"}, {".wasm", "application/wasm"},
        {".json", "application/json"}, {".glb", "model/gltf-binary"}, {".gltf", "model/gltf+json"},
        {".bin", "application/octet-stream"}, {".png", "image/png"}};
    for (const auto& [ext, type] : types) server.set_file_extension_and_mimetype_mapping(ext.substr(1), type);
    server.set_default_headers({{"X-Content-Type-Options", "nosniff"}, {"Referrer-Policy", "no-referrer"}});
    // SO_REUSEADDR only: cpp-httplib's default also sets SO_REUSEPORT, with which a
    // second `wave view` would silently share a port already serving another folder.
    server.set_socket_options([](socket_t sock) {
        int yes = 1;
        setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    json list = json::array();
    for (const auto& o : outputs.outputs) list.push_back({{"name", o.name}, {"kind", o.kind}, {"url", "/out/" + o.name}});
    const std::string body =
        json{{"root", outputs.root.string()}, {"outputs", list}, {"whitewater_frames", outputs.whitewater_frames}}.dump();
    server.Get("/api/outputs", [body](const httplib::Request&, httplib::Response& res) {
        res.set_header("Cache-Control", "no-store");
        res.set_content(body, "application/json");
    });
    // The output folder: only files whose real path lies inside its real path.
    std::error_code ec;
    const fs::path root_real = fs::canonical(outputs.root, ec);
    if (ec) throw InputError("view: cannot resolve " + outputs.root.string() + " (" + ec.message() + ")");
    std::atomic<bool> warned{false};  // handlers run on several workers
    server.Get(R"(/out/(.+))", [&, root_real](const httplib::Request& req, httplib::Response& res) {
        const auto file = served_file(root_real, req.matches[1].str());
        if (!file) {
            if (!warned.exchange(true))
                std::cerr << "wave view: refused " << req.path << " (outside " << root_real.string()
                          << ", a link leaving it, or no such file); further refusals are not reported" << std::endl;
            res.status = 404;
            res.set_header("Connection", "close");
            ViewServer::close_after_this_answer();
            return;
        }
        std::error_code size_error;
        const auto size = static_cast<std::size_t>(fs::file_size(*file, size_error));
        const auto type = types.find(file->extension().string());
        auto in = std::make_shared<std::ifstream>(*file, std::ios::binary);
        res.set_content_provider(size, type == types.end() ? "application/octet-stream" : type->second,
                                 [in](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                                     std::vector<char> buffer(std::min<std::size_t>(length, 1 << 20));
                                     in->seekg(static_cast<std::streamoff>(offset));
                                     if (!in->read(buffer.data(), static_cast<std::streamsize>(buffer.size()))) return false;
                                     sink.write(buffer.data(), buffer.size());
                                     return true;
                                 });
    });
    // The page itself: the viewer's installed files (libwave's own).
    if (!server.set_mount_point("/", assets.string())) throw std::runtime_error("view: cannot serve " + assets.string());

    // Every request: GET or HEAD, from a page of this machine (the Host it names), with
    // this run's token — in the printed URL's query, then in a cookie the page keeps.
    const std::string token = random_token();
    int port = a.port;
    // A refused request ends its connection (no pipelined requests from a client without
    // the token); its body, if any, is never read.
    server.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
        const auto refused = [&](int status) {
            res.status = status;
            res.set_header("Connection", "close");
            ViewServer::close_after_this_answer();
            return httplib::Server::HandlerResponse::Handled;
        };
        if (req.method != "GET" && req.method != "HEAD") return refused(405);
        if (!local_host(req.get_header_value("Host"), port)) {
            res.set_content("wave view answers pages of this machine only (Host 127.0.0.1, localhost or [::1])\n", "text/plain");
            return refused(403);
        }
        const std::string cookie = "wave_view=" + token;
        if (req.get_param_value("token") == token) {
            res.set_header("Set-Cookie", cookie + "; Path=/; HttpOnly; SameSite=Strict");
        } else if (req.get_header_value("Cookie").find(cookie) == std::string::npos) {
            res.set_content("wave view: open the URL it printed (it carries this run's token)\n", "text/plain");
            return refused(403);
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });

    if (port == 0) {
        port = server.bind_to_any_port(a.host);
    } else if (!server.bind_to_port(a.host, port)) {
        if (a.port_given) throw InputError("view: port " + std::to_string(port) + " on " + a.host + " is in use; choose another with --port (0 = any free port)");
        port = server.bind_to_any_port(a.host);  // the default was taken: any free one
    }
    if (port <= 0 || !server.prepare()) throw std::runtime_error("view: cannot listen on " + a.host);

    const std::string url = "http://" + a.host + ":" + std::to_string(port) + "/?token=" + token;
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
    std::signal(SIGINT, stop_server);
    std::signal(SIGTERM, stop_server);
    std::signal(SIGCHLD, SIG_IGN);  // xdg-open is not waited for
    return server.serve(stopping) ? 0 : 1;
}

}  // namespace wave::cli
