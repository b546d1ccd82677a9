// Shared by the libFuzzer targets: our readers take paths (GDAL, CGAL and tinygltf
// open files themselves), so each input is written to a per-process file first. An
// InputError is the expected answer to bad bytes; anything else escaping a reader —
// another exception, a crash, a leak, a sanitizer report — is a finding.
#pragma once

#include "libwave/errors.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <typeinfo>

#include <unistd.h>

namespace wave::fuzz {

// Grids stay small: a fuzzer must not spend its time allocating a legal 10⁸-node grid.
constexpr std::size_t kMaxNodes = 1u << 20;

// The file lives in memory where the system has one (/dev/shm): the disk's write-back
// was a third of the time per input, and GDAL lists the file's directory for sibling
// files on every open, so the directory is kept small — each input's file is removed
// when its run ends (libFuzzer leaves by _Exit: no atexit clean-up would run).
struct InputFile {
    std::string path;
    InputFile(const uint8_t* data, size_t size, const char* extension) {
        const char* base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        path = std::string(base) + "/libwave-fuzz-" + std::to_string(getpid()) + extension;
        std::FILE* f = std::fopen(path.c_str(), "wb");
        if (!f) std::abort();
        if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
        std::fclose(f);
    }
    ~InputFile() { std::remove(path.c_str()); }
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
};

// Runs a reader: InputError is fine, any other exception aborts with its message.
template <class Read>
void expect_input_error_only(Read&& read) {
    try {
        read();
    } catch (const wave::InputError&) {
    } catch (const std::exception& e) {
        std::fprintf(stderr, "finding: a reader threw %s instead of InputError: %s\n", typeid(e).name(), e.what());
        std::abort();
    }
}

}  // namespace wave::fuzz
