// Our glTF re-reader (read_animation, behind `wave convert`): .glb containers, the
// libwave extras, morph targets, quantised and Draco-compressed primitives.
// Seeds: tests/fuzz/seeds/gltf (small outputs of wave run).
#include "fuzz_input.h"
#include "libwave/export.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = wave::fuzz::input_file(data, size, ".glb");
    wave::fuzz::expect_input_error_only([&] { wave::read_animation(path); });
    return 0;
}
