// The contour-file reader (depth-tagged polylines in JSON) and the gridding of the
// contours it returns. Seeds: tests/fuzz/seeds/contours.
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    wave::ReadOptions o;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const wave::fuzz::InputFile file(data, size, ".json");
    const std::string& path = file.path;
    wave::fuzz::expect_input_error_only([&] { wave::read_contour_file(path, o); });
    return 0;
}
