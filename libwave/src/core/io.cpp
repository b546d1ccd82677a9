// Atomic file output: write to a unique temporary name, fsync, rename.
#include "libwave/io.h"

#include "libwave/errors.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace wave {

void write_file_atomic(const std::string& path, std::string_view bytes, const std::string& then_file) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
    // (built piecewise: GCC 12 reports a false -Wrestrict on "." + name + "…")
    std::string name = ".";
    name += target.filename().string();
    name += ".tmp-XXXXXX";
    std::string tmp = (dir / name).string();
    const int fd = ::mkstemp(tmp.data());
    if (fd < 0)
        throw RuntimeError(path + ": cannot create a file in " + dir.string() + " (" +
                           std::strerror(errno) + ")");
    const auto fail = [&](const char* step) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        ::unlink(tmp.c_str());
        throw RuntimeError(path + ": " + step + " failed (" + reason + ")");
    };
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            fail("writing");
        }
        done += static_cast<std::size_t>(n);
    }
    if (!then_file.empty()) {
        const int in = ::open(then_file.c_str(), O_RDONLY | O_CLOEXEC);
        if (in < 0) fail(("opening " + then_file).c_str());
        bool by_kernel = true;  // else (a file system or kernel without it) through a small buffer
        std::string buffer;
        for (;;) {
            ssize_t n = -1;
            if (by_kernel) {
                n = ::copy_file_range(in, nullptr, fd, nullptr, std::size_t{1} << 30, 0);
                if (n < 0 && (errno == ENOSYS || errno == EXDEV || errno == EINVAL || errno == EOPNOTSUPP)) {
                    by_kernel = false;
                    buffer.resize(std::size_t{1} << 20);
                    continue;
                }
            } else if ((n = ::read(in, buffer.data(), buffer.size())) > 0) {
                for (ssize_t at = 0; at < n;) {
                    const ssize_t w = ::write(fd, buffer.data() + at, static_cast<std::size_t>(n - at));
                    if (w < 0 && errno != EINTR) {
                        ::close(in);
                        fail("writing");
                    }
                    if (w > 0) at += w;
                }
            }
            if (n == 0) break;
            if (n > 0 || errno == EINTR) continue;
            const int error = errno;
            ::close(in);
            errno = error;
            fail(("copying " + then_file).c_str());
        }
        ::close(in);
    }
    if (::fchmod(fd, 0644) != 0) fail("setting permissions");
    if (::fsync(fd) != 0) fail("flushing to disk");
    if (::close(fd) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw RuntimeError(path + ": closing failed (" + reason + ")");
    }
    if (::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        ::unlink(tmp.c_str());
        throw RuntimeError(path + ": renaming the finished file into place failed (" + reason + ")");
    }
}

namespace {

// What a path is, for a message: "a FIFO (named pipe)", "a socket", …
std::string file_kind(std::filesystem::file_type type) {
    using std::filesystem::file_type;
    switch (type) {
        case file_type::directory: return "a directory";
        case file_type::fifo: return "a FIFO (named pipe)";
        case file_type::socket: return "a socket";
        case file_type::character: return "a character device";
        case file_type::block: return "a block device";
        default: return "not a regular file";
    }
}

}  // namespace

void require_input_file(const std::string& path, bool directory) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);  // links followed; nothing opened
    if (ec || !std::filesystem::exists(status)) throw InputError(path + ": file not found");
    const auto type = status.type();
    if (directory && type == std::filesystem::file_type::directory) return;
    if (!directory && type == std::filesystem::file_type::regular) return;
    if (directory) throw InputError(path + ": " + (type == std::filesystem::file_type::regular ? std::string("a file") : file_kind(type)) + ", not a folder");
    if (type == std::filesystem::file_type::directory) throw InputError(path + ": a directory, not a file");
    throw InputError(path + ": " + file_kind(type) + ", not a regular file");
}

std::string printable(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    const auto hex = [&](unsigned value, int digits) {
        static constexpr char h[] = "0123456789ABCDEF";
        for (int d = digits - 1; d >= 0; --d) out += h[(value >> (4 * d)) & 15];
    };
    for (std::size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x80) {
            if ((c < 0x20 && c != '\t') || c == 0x7F) {
                out += "\\x";
                hex(c, 2);
            } else {
                out += static_cast<char>(c);
            }
            ++i;
            continue;
        }
        // A UTF-8 sequence: its length and code point (an invalid one byte by byte).
        const std::size_t n = c >= 0xF0 && c < 0xF5 ? 4 : c >= 0xE0 && c < 0xF0 ? 3 : c >= 0xC2 && c < 0xE0 ? 2 : 0;
        unsigned cp = n == 4 ? c & 0x07u : n == 3 ? c & 0x0Fu : c & 0x1Fu;
        bool valid = n > 0 && i + n <= text.size();
        for (std::size_t k = 1; valid && k < n; ++k) {
            const auto b = static_cast<unsigned char>(text[i + k]);
            valid = (b & 0xC0) == 0x80;
            cp = (cp << 6) | (b & 0x3Fu);
        }
        if (valid && ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)) || (cp >= 0xD800 && cp < 0xE000)))
            valid = false;  // overlong, beyond Unicode, or a surrogate
        if (!valid) {
            out += "\\x";
            hex(c, 2);
            ++i;
            continue;
        }
        const bool control = cp >= 0x80 && cp < 0xA0;
        const bool bidi = cp == 0x061C || cp == 0x200E || cp == 0x200F || (cp >= 0x202A && cp <= 0x202E) || (cp >= 0x2066 && cp <= 0x2069);
        if (control || bidi) {
            out += "\\u{";
            hex(cp, 4);
            out += '}';
        } else {
            out.append(text.substr(i, n));
        }
        i += n;
    }
    return out;
}

std::string path_inside(const std::string& folder, const std::string& name, const std::string& what) {
    namespace fs = std::filesystem;
    const auto refuse = [&](const std::string& why) {
        throw InputError(what + " '" + name + "': " + why + " (it must stay inside " +
                         (folder.empty() ? std::string(".") : folder) + ")");
    };
    if (name.empty()) refuse("an empty path");
    if (name.find('\0') != std::string::npos) refuse("a path with a NUL byte");
    const fs::path rel(name);
    if (rel.is_absolute() || rel.has_root_name() || rel.has_root_directory()) refuse("an absolute path");
    for (const auto& part : rel)
        if (part == "..") refuse("a path that goes up a folder (..)");
    const fs::path base = folder.empty() ? fs::path(".") : fs::path(folder);
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(base, ec);
    if (ec) refuse("its folder cannot be resolved (" + ec.message() + ")");
    const fs::path real = fs::weakly_canonical(base / rel, ec);  // links of the existing part resolved
    if (ec) refuse("it cannot be resolved (" + ec.message() + ")");
    auto p = real.begin();
    for (auto r = root.begin(); r != root.end(); ++r, ++p)
        if (p == real.end() || *p != *r) refuse("a link leads out of the folder, to " + real.string());
    return folder.empty() ? rel.string() : (base / rel).string();
}

std::optional<std::string> read_regular_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    try {  // a folder through a stream throws basic_filebuf's own error: answered by the check above
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) return std::nullopt;
        return bytes;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace wave

namespace wave::detail {

bool path_exists(const std::string& path) noexcept {
    std::error_code ec;
    return std::filesystem::exists(path, ec) && !ec;
}

void require_input_file(const std::string& path) { wave::require_input_file(path, false); }

std::uintmax_t input_file_bytes(const std::string& path) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(path + ": cannot tell its size (" + ec.message() + ")");
    return bytes;
}


}  // namespace wave::detail
