// The contour-file reader (depth-tagged polylines in JSON) and the gridding of the
// contours it returns. Seeds: tests/fuzz/seeds/contours.
#include "fuzz_input.h"
#include "libwave/bathymetry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    wave::ReadOptions o;
    o.max_nodes = wave::fuzz::kMaxNodes;
    const std::string path = wave::fuzz::input_file(data, size, ".json");
    wave::fuzz::expect_input_error_only([&] { wave::read_contour_file(path, o); });
    return 0;
}
