// The files form's frame index (index.json) as JSON values, for the writer of the
// files form (scene/files_form.cpp): export.h gives the same as JSON text. Internal.
#pragma once

#include "libwave/export.h"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace wave::detail {

/// frame_entry_json's entry as a JSON value.
nlohmann::json frame_entry(std::size_t frame, double fps, const EncodedFiles& frame_files, std::span<const float> positions = {});

/// frame_entry_intact of an entry as a JSON value.
bool entry_intact(const nlohmann::json& entry, const std::filesystem::path& root);

/// read_files_form_index's index as a JSON value.
std::optional<nlohmann::json> read_index(const std::filesystem::path& path);

/// Whether an index (read_index's) describes the animation `info` names: scene, fps, loop.
bool same_animation(const nlohmann::json& index, const FrameIndexInfo& info);

/// frame_index_json's index as a JSON value.
nlohmann::json frame_index(const FrameIndexInfo& info, std::vector<nlohmann::json> entries);

/// merged_frame_index's index as a JSON value.
nlohmann::json merged_index(const std::string& path, const FrameIndexInfo& info, const std::vector<nlohmann::json>& entries,
                            bool whole_loop, bool rebuild_unreadable);

}  // namespace wave::detail
