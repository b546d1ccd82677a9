// Our glTF re-reader (read_animation, behind `wave convert`): .glb containers, the
// libwave extras, morph targets, quantised, Draco- and meshopt-compressed primitives
// (EXT_meshopt_compression: its views, counts and streams).
// Seeds: tests/fuzz/seeds/gltf (small outputs of wave run).
#include "fuzz_input.h"
#include "libwave/export.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const wave::fuzz::InputFile file(data, size, ".glb");
    const std::string& path = file.path;
    wave::fuzz::expect_input_error_only([&] { wave::read_animation(path); });
    return 0;
}
