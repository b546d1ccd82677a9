// libwave — export: meshes and animations to files for DCC tools.
//
// Today: Wavefront OBJ of one frame (positions z up, as everywhere in libwave; OBJ has
// no axis convention, Blender's importer asks). The animated glTF / Draco exporter of
// DESIGN.md is not written yet.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace wave {

/// One triangle mesh as OBJ text: `v x y z` per vertex (3 floats each in `positions`),
/// `f a b c` per triangle (0-based `triangles`, written 1-based), a comment line first.
/// Precondition: every index < positions.size() / 3.
std::string mesh_to_obj(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                        std::string_view comment);

}  // namespace wave
