// Triangle-mesh seafloors through CGAL's polygon-soup readers (then resampled to a
// grid). The first byte picks the format — OBJ, PLY, STL, or with FUZZ_MESH_OFF defined
// (the fuzz_mesh_off target) OFF alone —; the rest is the file. Seeds:
// tests/fuzz/seeds/mesh. OFF has its own target because CGAL 5.5's OFF scanner has
// undefined behaviour on malformed files: it found what read_mesh.cpp's OFF check now
// refuses first (tests/fuzz/regressions/fuzz_mesh_off, docs/hardening.md).
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
#ifdef FUZZ_MESH_OFF
    const char* extension = ".off";
#else
    static const char* const extensions[] = {".obj", ".ply", ".stl"};
    const char* extension = extensions[data[0] % 3];
#endif
    wave::ReadOptions o;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const wave::fuzz::InputFile file(data + 1, size - 1, extension);
    const std::string& path = file.path;
    wave::fuzz::expect_input_error_only([&] { wave::read_mesh_file(path, o); });
    return 0;
}
