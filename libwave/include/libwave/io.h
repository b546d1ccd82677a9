/// \file
/// libwave — crash-safe output files (docs/conventions.md), paths read from files, and
/// images as PNG bytes: the core every stage uses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wave {

/// Writes `bytes` to `path` through a temporary file in the same folder, flushed and
/// then renamed over `path`: an interrupted run never leaves a truncated file under
/// the final name and never replaces a good file with a broken one.
/// Throws RuntimeError (naming the path and the system's reason) when the folder
/// does not exist or cannot be written.
/// With `then_file`, that file's contents follow `bytes` (copied by the kernel, never
/// held in memory: a streamed animation's buffer after its header).
void write_file_atomic(const std::string& path, std::string_view bytes, const std::string& then_file = {});

/// Throws InputError unless `path` names a regular file (or, with `directory`, a
/// folder), links followed: "file not found", "a directory, not a file", "a FIFO (named
/// pipe), not a regular file", a device or a socket. Checked before any open, so that
/// a FIFO or a device never blocks a reader (docs/hardening.md, "Special files").
void require_input_file(const std::string& path, bool directory = false);

/// The whole contents of the regular file at `path` (links followed), or nothing when
/// it is not one (missing, a folder, a FIFO, a device: never opened, so a FIFO cannot
/// block) or cannot be read whole. Never throws for the file's sake: for readers of
/// what an earlier run may have left (an index, a report), where "not there" is an
/// answer.
std::optional<std::string> read_regular_file(const std::string& path);

/// `text` (a message, a name read from a file) with what a terminal would act on shown
/// as escapes: control characters (C0 but the tab, DEL, C1) as `\xHH`, bidirectional
/// formatting characters (U+061C, U+200E/F, U+202A–E, U+2066–9) as `\u{XXXX}`, invalid
/// UTF-8 bytes as `\xHH`. `wave` and the Python module show every message through it
/// (docs/hardening.md, "Messages").
std::string printable(std::string_view text);

/// The path of `name`, a path read from a file in `folder` (an index entry, a glTF
/// buffer URI, a frame of `wave merge`, a file an output form writes), checked to stay
/// inside `folder`: relative, no `..` part, and its real path (every existing link
/// resolved) inside the folder's real path. InputError naming `what` and `name`
/// otherwise (docs/hardening.md, "Paths read from files"). The same rule as
/// `--resume`'s and the viewer's.
std::string path_inside(const std::string& folder, const std::string& name, const std::string& what);

/// An 8-bit RGB image.
struct Image {
    std::size_t width = 0;   ///< pixels
    std::size_t height = 0;  ///< pixels
    std::vector<std::uint8_t> rgb;  ///< row-major from the top, 3 bytes per pixel
};

/// The image as PNG bytes (stb_image_write); write_png writes them atomically.
/// Throw RuntimeError on failure.
std::string png_bytes(const Image& image);
/// png_bytes(image) written to `path` atomically (RuntimeError on failure).
void write_png(const Image& image, const std::string& path);

}  // namespace wave
