// Internal to the export stage: one mesh primitive through Draco's encoder
// (KHR_draco_mesh_compression). Draco's types stay in draco_encode.cpp.
#pragma once

#include "libwave/export.h"

#include <array>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace wave::detail {

/// One vertex attribute to compress: `components` floats per vertex.
struct DracoInput {
    std::string name;  ///< glTF attribute name (POSITION, NORMAL, TEXCOORD_n, COLOR_0, _FOAM, …)
    int components = 3;
    std::span<const float> values;
};

/// Draco's explicit quantisation of POSITION: the grid `origin` + q · step per axis,
/// q in [0, 2^bits − 1], step = range / (2^bits − 1). The caller puts the positions on
/// the grid's points beforehand when it wants them decoded exactly.
struct DracoGrid {
    std::array<float, 3> origin{};
    float range = 0.0f;
    int bits = 0;
};

struct DracoOutput {
    std::string bytes;                ///< the Draco bitstream (one bufferView)
    std::map<std::string, int> ids;   ///< glTF attribute name → Draco attribute unique id
};

/// Encodes the triangles and attributes with the chosen quantisation bits per kind of
/// attribute: edgebreaker (smallest; the decoder reorders points), or with
/// `keep_order` Draco's sequential method, whose decoded points keep the input order
/// (what uncompressed morph targets beside a compressed base need).
/// With `position_grid`, positions are quantised on that grid instead of one spanning
/// their bounding box with `options.position_bits`.
/// Throws RuntimeError if Draco refuses.
DracoOutput draco_encode(std::span<const std::uint32_t> triangles, std::size_t vertex_count,
                         const std::vector<DracoInput>& attributes, const DracoOptions& options,
                         bool keep_order = false, const DracoGrid* position_grid = nullptr);

}  // namespace wave::detail
