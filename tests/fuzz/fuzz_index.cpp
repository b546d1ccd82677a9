// The files form's index.json as `wave run --resume`, `wave merge` and a slice's run read
// it back — after a crash, or after a hand or another tool edited it
// (libwave/src/export/frame_index.cpp): read_files_form_index, the merge of a slice's entries
// into it, and each listed entry checked against its files. A wrong type once escaped as
// a JSON library exception (exit 1); "not an index" is the expected answer. Seeds:
// tests/fuzz/seeds/index (a small run's index).
#include "fuzz_input.h"
#include "libwave/export.h"

#include <nlohmann/json.hpp>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const wave::fuzz::InputFile file(data, size, ".json");
    // The seed's animation; the entries name files under a folder that does not exist,
    // so each check reads no file (names that climb out of it are refused first).
    const wave::FrameIndexInfo info{"fuzz", 2.0, 5.0, 10, "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef"};
    wave::fuzz::expect_input_error_only([&] {
        if (const auto index = wave::read_files_form_index(file.path)) {
            const nlohmann::json parsed = nlohmann::json::parse(*index);  // held: a range-for over a temporary's member dangles before C++23
            for (const auto& entry : parsed["frames"]) wave::frame_entry_intact(entry.dump(), "/nonexistent/libwave-fuzz");
        }
        for (const bool whole_loop : {false, true})
            for (const bool rebuild : {false, true}) wave::merged_frame_index(file.path, info, {}, whole_loop, rebuild);
    });
    return 0;
}
