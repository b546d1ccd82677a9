// The files form's frame index (export.h, "FrameIndexInfo" on): each frame's files with
// their sizes and SHA-256 (OpenSSL), read back and checked after a crash (`--resume`),
// merged slice by slice into one index.json; and the folder lock the slices share.
#include "export/frame_index.h"

#include "libwave/errors.h"
#include "core/limits.h"
#include "libwave/io.h"

#include <openssl/evp.h>
#include <sys/file.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <utility>

namespace wave {

using nlohmann::json;
namespace fs = std::filesystem;

std::string sha256_hex(std::string_view bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
        throw RuntimeError("OpenSSL: SHA-256 failed");
    static constexpr char hex[] = "0123456789abcdef";
    std::string out(2 * length, '0');
    for (unsigned int i = 0; i < length; ++i) {
        out[2 * i] = hex[digest[i] >> 4];
        out[2 * i + 1] = hex[digest[i] & 15];
    }
    return out;
}


namespace detail {

json frame_entry(std::size_t frame, double fps, const EncodedFiles& frame_files, std::span<const float> positions) {
    if (frame_files.empty()) throw InputError("files form: frame " + std::to_string(frame) + " has no file");
    json entry{{"frame", frame}, {"time", key_time(frame, fps)}, {"file", frame_files.front().first}, {"content", json::array()}};
    for (const auto& [name, bytes] : frame_files)
        entry["content"].push_back({{"file", name}, {"bytes", bytes.size()}, {"sha256", sha256_hex(bytes)}});
    if (!positions.empty()) {
        float z_min = std::numeric_limits<float>::infinity(), z_max = -z_min;
        for (std::size_t i = 2; i < positions.size(); i += 3) {
            z_min = std::min(z_min, positions[i]);
            z_max = std::max(z_max, positions[i]);
        }
        entry["height_range_m"] = {z_min, z_max};
    }
    return entry;
}

// An index that cannot be read is a reason to recompute, not to stop a resumed run.
std::optional<json> read_index(const fs::path& path) {
    const auto bytes = read_regular_file(path.string());
    if (!bytes) return std::nullopt;
    try {  // nested deeper than any index of ours: not one (its entries' dump would recurse that deep)
        detail::check_json_nesting(*bytes, path.string());
    } catch (const InputError&) {
        return std::nullopt;
    }
    json index = json::parse(*bytes, nullptr, false);
    if (index.is_discarded() || !index.is_object() || !index.contains("frames") || !index["frames"].is_array())
        return std::nullopt;
    const auto typed = [&](const char* key, bool (json::*is)() const noexcept) { return !index.contains(key) || (index[key].*is)(); };
    if (!typed("scene", &json::is_string) || !typed("fps", &json::is_number) ||
        !typed("loop_frames", &json::is_number_unsigned) || !typed("run_key", &json::is_string))
        return std::nullopt;
    return index;
}

bool same_animation(const json& index, const FrameIndexInfo& info) {
    return index.value("scene", "") == info.scene && index.value("fps", 0.0) == info.fps &&
           index.value("loop_frames", std::size_t{0}) == info.loop_frames;
}

bool entry_intact(const json& entry, const fs::path& root) {
    if (!entry.is_object() || !entry.contains("content") || !entry["content"].is_array() || entry["content"].empty())
        return false;
    for (const json& c : entry["content"]) {
        if (!c.is_object() || !c.contains("file") || !c["file"].is_string() || !c.contains("bytes") ||
            !c["bytes"].is_number_unsigned() || !c.contains("sha256") || !c["sha256"].is_string())
            return false;
        const std::string name = c["file"].get<std::string>();
        std::string file;
        try {
            file = path_inside(root.string(), name, root.string());  // stays inside root, links included
        } catch (const InputError&) {
            return false;
        }
        std::error_code ec;
        const auto size = fs::file_size(file, ec);
        if (ec || size != c["bytes"].get<std::uintmax_t>()) return false;  // cheap check first
        const auto bytes = read_regular_file(file);
        if (!bytes || sha256_hex(*bytes) != c["sha256"].get<std::string>()) return false;
    }
    return true;
}

json frame_index(const FrameIndexInfo& info, std::vector<json> entries) {
    json index{{"scene", info.scene}, {"fps", info.fps}, {"loop_period_s", info.loop_period}, {"loop_frames", info.loop_frames}};
    if (!info.run_key.empty()) index["run_key"] = info.run_key;
    index["frames"] = std::move(entries);
    return index;
}

json merged_index(const std::string& path, const FrameIndexInfo& info, const std::vector<json>& entries, bool whole_loop,
                  bool rebuild_unreadable) {
    std::map<std::size_t, json> frames;
    std::error_code ec;
    const auto old = fs::exists(path, ec) ? read_index(path) : std::nullopt;
    if (fs::exists(path, ec) && (old || !rebuild_unreadable)) {
        if (!old) throw InputError(path + ": not a frame index of libwave (invalid JSON, or fields of other types); use another output folder");
        if (!same_animation(*old, info))
            throw InputError(path + ": the index there belongs to another animation (scene, fps or loop differ); "
                             "use another output folder");
        if (old->value("run_key", "") != info.run_key && !whole_loop)
            throw InputError(path + ": its frames were computed from another version of the scene, its seafloor or "
                             "libwave (run key differs); run the whole loop into it, or use another output folder");
        if (!whole_loop)
            for (const json& f : (*old)["frames"])
                if (f.is_object() && f.contains("frame") && f["frame"].is_number_unsigned())
                    frames[f["frame"].get<std::size_t>()] = f;
    }
    for (const json& e : entries) frames[e.at("frame").get<std::size_t>()] = e;
    std::vector<json> merged;
    for (auto& [_, f] : frames) merged.push_back(std::move(f));
    return frame_index(info, std::move(merged));
}

}  // namespace detail

namespace {

// Entries given as JSON text (frame_entry_json's), parsed: InputError for other text.
std::vector<json> parsed_entries(std::span<const std::string> entries) {
    std::vector<json> parsed;
    parsed.reserve(entries.size());
    for (const std::string& e : entries) {
        json j = json::parse(e, nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("frame") || !j["frame"].is_number_unsigned())
            throw InputError("files form: an index entry that is not one of frame_entry_json's");
        parsed.push_back(std::move(j));
    }
    return parsed;
}

}  // namespace

std::string frame_entry_json(std::size_t frame, double fps, const EncodedFiles& frame_files, std::span<const float> positions) {
    return detail::frame_entry(frame, fps, frame_files, positions).dump();
}

bool frame_entry_intact(std::string_view entry_json, const std::string& root) {
    const json entry = json::parse(entry_json, nullptr, false);
    return !entry.is_discarded() && detail::entry_intact(entry, root);
}

std::optional<std::string> read_files_form_index(const std::string& path) {
    const auto index = detail::read_index(path);
    if (!index) return std::nullopt;
    return index->dump();
}

std::string frame_index_json(const FrameIndexInfo& info, std::span<const std::string> entries) {
    return detail::frame_index(info, parsed_entries(entries)).dump(2) + "\n";
}

std::string merged_frame_index(const std::string& path, const FrameIndexInfo& info, std::span<const std::string> entries,
                               bool whole_loop, bool rebuild_unreadable) {
    return detail::merged_index(path, info, parsed_entries(entries), whole_loop, rebuild_unreadable).dump(2) + "\n";
}

FolderLock::FolderLock(const std::string& folder, bool wait, const std::string& busy) {
    fd_ = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) throw RuntimeError(folder + ": cannot open the folder to lock it: " + std::strerror(errno));
    int rc = 0;
    while ((rc = ::flock(fd_, LOCK_EX | (wait ? 0 : LOCK_NB))) != 0 && errno == EINTR) {}
    if (rc != 0) {
        const int error = errno;
        release();
        if (error == EWOULDBLOCK) throw InputError(busy);
        throw RuntimeError(folder + ": cannot lock: " + std::strerror(error));
    }
}

FolderLock::FolderLock(FolderLock&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}

FolderLock& FolderLock::operator=(FolderLock&& o) noexcept {
    if (this != &o) {
        release();
        fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
}

FolderLock::~FolderLock() { release(); }

void FolderLock::release() noexcept {
    if (fd_ >= 0) ::close(std::exchange(fd_, -1));
}

bool FolderLock::held() const noexcept { return fd_ >= 0; }

}  // namespace wave
