// Internal: questions about input paths that must not throw. std::filesystem's
// throwing overloads turn a path the system refuses (too long, a loop of links) into
// filesystem_error, which escaped as a crash (tests/fuzz/fuzz_scene): such a path
// simply does not name a readable file.
#pragma once

#include <cstdint>
#include <string>

namespace wave::detail {

/// Whether `path` names something that exists; false for any path the system refuses.
bool path_exists(const std::string& path) noexcept;

/// Throws InputError unless `path` names a regular file: "file not found", "a directory,
/// not a file" (which std::ifstream opens and then reads as empty, so readers reported
/// an empty or malformed file instead), or a FIFO, socket or device (whose open blocked
/// for ever): wave::require_input_file (libwave/io.h).
void require_input_file(const std::string& path);

/// The size of the file at `path` in bytes; InputError naming the path and the system's
/// reason if it cannot be told. Readers bound counts read from a header by it.
std::uintmax_t input_file_bytes(const std::string& path);

}  // namespace wave::detail
