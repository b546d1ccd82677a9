// Loading libwave's glTF outputs (gltf_load.cpp) for the reader (gltf_read.cpp): the file's
// layout checked before tinygltf parses it, EXT_meshopt_compression's views unpacked, and
// the views only the frames use left in the file until a frame is decoded.
#pragma once

#include "gltf_library.h"
#include <nlohmann/json.hpp>

#include "meshopt_codec.h"

#include <cstddef>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace wave::detail {

// The most frames a loop of libwave's has (the schema's /animation/max_frames).
inline constexpr double kMaxStoredFrames = 1e7;

// A view compressed by EXT_meshopt_compression, as its extension describes it (the
// view itself then points at the compressed bytes: unpack_meshopt).
struct MeshoptView {
    detail::MeshoptMode mode = detail::MeshoptMode::attributes;
    detail::MeshoptFilter filter = detail::MeshoptFilter::none;
    std::size_t count = 0, stride = 0;
};

// A compressed view decoded once and kept for the next file of a files form (a player's
// FrameReader): the frames' files hold the same triangles and rest positions, so a view
// whose compressed bytes and codec equal the kept ones decodes to the kept bytes (the
// codecs are deterministic) and is not decoded again.
struct KeptView {
    MeshoptView codec;
    std::vector<unsigned char> compressed, decoded;
};
using ViewMemo = std::map<int, KeptView>;

// The buffer views a file's frames alone use (morph targets, the nodes form's later
// meshes), left in the file: each is read when its frame is decoded and dropped after
// it, so a reader holds the file's static parts and one frame, not the whole buffer.
struct LazyViews {
    std::string file;      // where buffer 0's bytes are: the .glb, or a .gltf's .bin
    std::size_t base = 0;  // the file offset of buffer 0's first byte
    std::map<int, std::pair<std::size_t, std::size_t>> where{};  // view → (byteOffset, byteLength) in buffer 0
    std::map<int, MeshoptView> meshopt{};  // the views of `where` that are compressed
    ViewMemo* memo = nullptr;  // kept decodings of the views in `kept` (a FrameReader's), if any
    std::set<int> kept{};
    mutable std::ifstream in{};
    mutable std::map<int, std::vector<unsigned char>> loaded{};

    // The bytes of `view` (decoded when compressed), read from the file on first use;
    // nullptr when the view is not left in the file.
    const std::vector<unsigned char>* bytes(int view, const std::string& path) const;
};

// asset.extras.libwave's numbers, checked in the file's JSON before tinygltf converts
// them: it casts an integer to int, so a loop of 2^40 frames became 0 in the output's
// extras, and a negative one wrapped round (docs/hardening.md).
void check_extras(const std::string& path, const nlohmann::json& doc);

// Loads one of libwave's glTF files into `m`. When buffer 0 is a .glb's BIN chunk or a
// .gltf's external .bin (every layout libwave writes), tinygltf parses the JSON with a
// buffer of the static views alone, moved together, and the frames' views stay in the
// file for `lazy`; otherwise it loads the whole file, as it would.
// With `memo` (a FrameReader's files form), every view stays in the file until it is
// asked for, and the shared ones (shared_views) decode through the memo.
void load_model(const std::string& path, tinygltf::Model& m, LazyViews& lazy, ViewMemo* memo = nullptr);

}  // namespace wave::detail
