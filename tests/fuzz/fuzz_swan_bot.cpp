// The SWAN .bot reader: a bare list of numbers whose grid is given outside the file.
// Input: a first line "NX NY" (the grid the reader is told), then the file's bytes.
// Seeds: data/bathymetry/*.bot with its grid line (tests/fuzz/run.sh).
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const void* eol = std::memchr(data, '\n', size);
    if (!eol) return 0;
    const std::size_t head = static_cast<std::size_t>(static_cast<const uint8_t*>(eol) - data);
    unsigned long nx = 0, ny = 0;
    if (std::sscanf(std::string(reinterpret_cast<const char*>(data), head).c_str(), "%lu %lu", &nx, &ny) != 2) return 0;
    wave::ReadOptions o;
    o.swan_nx = nx;
    o.swan_ny = ny;
    o.swan_dx = 250.0;
    o.nodata_value = -99.0;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const wave::fuzz::InputFile file(data + head + 1, size - head - 1, ".bot");
    const std::string& path = file.path;
    wave::fuzz::expect_input_error_only([&] { wave::read_swan_bot(path, o); });
    return 0;
}
