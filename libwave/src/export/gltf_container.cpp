// .glb → .gltf + .bin: the same model as a JSON file whose buffer is an external
// binary file (no base64: the buffer of an animation is hundreds of MB).
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/export.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>

namespace wave {

GltfFiles glb_to_gltf(std::string_view glb, const std::string& bin_uri) {
    const auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        if (at + 4 > glb.size()) throw InputError("glb_to_gltf: truncated GLB");
        std::memcpy(&v, glb.data() + at, 4);
        return v;
    };
    if (glb.size() < 20 || glb.substr(0, 4) != "glTF" || u32(4) != 2) throw InputError("glb_to_gltf: not a glTF 2.0 GLB");
    const std::uint32_t json_length = u32(12);
    if (u32(16) != 0x4E4F534Au) throw InputError("glb_to_gltf: the first chunk is not JSON");
    nlohmann::json doc = nlohmann::json::parse(glb.substr(20, json_length));
    GltfFiles out;
    const std::size_t bin_at = 20 + json_length;
    if (bin_at + 8 <= glb.size()) {
        const std::uint32_t bin_length = u32(bin_at);
        if (u32(bin_at + 4) != 0x004E4942u || bin_at + 8 + bin_length > glb.size())
            throw InputError("glb_to_gltf: malformed BIN chunk");
        out.bin.assign(glb.substr(bin_at + 8, bin_length));
        // The GLB pads the chunk to 4 bytes; the buffer's byteLength is what counts.
        out.bin.resize(doc.at("buffers").at(0).at("byteLength").get<std::size_t>());
        doc["buffers"][0]["uri"] = bin_uri;
    }
    out.json = doc.dump(1) + "\n";
    return out;
}

}  // namespace wave
