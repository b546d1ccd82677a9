// The scene JSON parser (parse_scene): every key, value and nesting of hand-written
// scenes. Seeds: examples/*.json.
#include "fuzz_input.h"
#include "libwave/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    wave::fuzz::expect_input_error_only([&] { wave::parse_scene(text, "fuzz.json", "/nonexistent"); });
    return 0;
}
