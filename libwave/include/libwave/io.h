// libwave — crash-safe output files (docs/conventions.md).
#pragma once

#include <string>
#include <string_view>

namespace wave {

/// Writes `bytes` to `path` through a temporary file in the same folder, flushed and
/// then renamed over `path`: an interrupted run never leaves a truncated file under
/// the final name and never replaces a good file with a broken one.
/// Throws RuntimeError (naming the path and the system's reason) when the folder
/// does not exist or cannot be written.
/// With `then_file`, that file's contents follow `bytes` (copied by the kernel, never
/// held in memory: a streamed animation's buffer after its header).
void write_file_atomic(const std::string& path, std::string_view bytes, const std::string& then_file = {});

}  // namespace wave
