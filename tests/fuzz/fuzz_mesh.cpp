// Triangle-mesh seafloors (CGAL I/O, then resampled to a grid). The first byte picks
// the format (OFF, OBJ, PLY, STL); the rest is the file. Seeds: tests/fuzz/seeds/mesh.
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* const extensions[] = {".off", ".obj", ".ply", ".stl"};
    wave::ReadOptions o;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const std::string path = wave::fuzz::input_file(data + 1, size - 1, extensions[data[0] % 4]);
    wave::fuzz::expect_input_error_only([&] { wave::read_mesh_file(path, o); });
    return 0;
}
