// What the scene's streamed runs share with the export forms (forms.cpp): the names of
// the underwater and whitewater files beside an animation. Internal.
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <string>

namespace wave::detail {

/// Frame k of a chunk's underwater and whitewater files beside the animation, named by
/// loop frame: its caustic map, sunbeam volume and particles (each list empty or one per
/// frame of the chunk), each handed to `file` with its name.
void for_underwater_files(std::size_t first_frame, std::size_t k, std::span<const std::string> caustics,
                          std::span<const std::string> sunbeams, std::span<const std::string> whitewater,
                          const std::function<void(std::string, const std::string&)>& file);

}  // namespace wave::detail
