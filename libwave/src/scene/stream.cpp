// The scene's streamed run: stream_animation evaluates a chunk of frames at a time and
// hands each to the form's StreamedWriter (export/forms.cpp), the underwater and
// whitewater files written beside it as they come.
#include "libwave/scene.h"

#include "export/forms.h"
#include "libwave/errors.h"
#include "libwave/io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace wave {

using detail::for_underwater_files;

bool streamed_form(const Scene& scene) { return streamed_form(scene.form, scene.quantize); }

StreamedAnimation stream_animation(AnimationStream& stream, const Scene& scene, const std::string& folder, bool whole,
                                   std::size_t chunk, const std::function<void(std::size_t, std::size_t)>& progress) {
    if (!streamed_form(scene))
        throw InputError("scene: the files form and quantised nodes or pc2 files are not streamed by stream_animation");
    StreamedAnimation out;
    out.z_min = std::numeric_limits<float>::infinity();
    out.z_max = -std::numeric_limits<float>::infinity();
    const std::size_t frames = stream.frame_count();
    std::optional<StreamedWriter> writer;
    std::vector<std::string> maps;  // caustic maps and sunbeam volumes written, in order
    SceneAnimation a;
    // Quantised morph targets need their delta range before the first target: a pass
    // over the frames' positions alone finds it.
    const std::optional<double> quantize_range =
        scene.quantize ? std::optional<double>(stream.position_delta_range(chunk)) : std::nullopt;
    try {
        // The range's first frame alone first (the file's settings, and the frame kept
        // for the caller), then `chunk` frames at a time.
        while (stream.next(a, stream.frames_left() == frames ? 1 : std::max<std::size_t>(1, chunk), progress) > 0) {
            MorphAnimationView view = a.view();
            view.quantize_range = quantize_range;
            if (a.first_frame == stream.first_frame()) {
                writer.emplace(folder, scene.form, scene.container, whole, view, frames);
                out.first = a;
            }
            writer->append(view);
            for (std::size_t k = 0; k < a.frame_count; ++k)
                for_underwater_files(a.first_frame, k, a.caustics, a.sunbeams, a.whitewater, [&](std::string name, const std::string& bytes) {
                    maps.push_back(std::move(name));
                    std::filesystem::create_directories((std::filesystem::path(folder) / maps.back()).parent_path());
                    write_file_atomic(folder + "/" + maps.back(), bytes);
                });
            out.z_min = std::min(out.z_min, a.z_min);
            out.z_max = std::max(out.z_max, a.z_max);
        }
    } catch (...) {
        for (const std::string& m : maps) std::remove((folder + "/" + m).c_str());
        throw;
    }
    out.files = writer->finish();
    for (const std::string& m : maps) out.files.emplace_back(m, std::filesystem::file_size(std::filesystem::path(folder) / m));
    return out;
}

MorphAnimationView SceneAnimation::view() const {
    MorphAnimationView v = animation_view(*this);
    v.draco = draco;
    v.quantize = quantize;
    v.meshopt = meshopt;
    return v;
}

}  // namespace wave
