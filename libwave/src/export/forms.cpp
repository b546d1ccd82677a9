// The export forms behind one table (export_forms): each form's name, encoder, whether
// it is streamed and its size estimate; encode_animation (a chunk of frames as the files
// of its form, .glb or .gltf + .bin, the underwater and whitewater files beside it) and
// the streamed writers that write a long run as its chunks come. Adding a form: its
// ExportForm value, its row and encoder here, its name in the schema's /outputs/form.
#include "libwave/export.h"

#include "core/json_input.h"
#include "export/forms.h"
#include "libwave/errors.h"
#include "libwave/io.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace wave {

namespace detail {

// A frame's file of an underwater sequence (kCausticImages, kSunbeamVolumes).
std::string underwater_file_name(const char* pattern, std::size_t frame) {
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, pattern, static_cast<int>(frame));
    return buffer;
}

// Frame k of a chunk's underwater files beside the animation, named by loop frame: its
// caustic map, then its sunbeam volume (each list empty or one per frame of the chunk).
void for_underwater_files(std::size_t first_frame, std::size_t k, std::span<const std::string> caustics,
                          std::span<const std::string> sunbeams, std::span<const std::string> whitewater,
                          const std::function<void(std::string, const std::string&)>& file) {
    if (!caustics.empty()) file(underwater_file_name(kCausticImages, first_frame + k), caustics[k]);
    if (!sunbeams.empty()) file(underwater_file_name(kSunbeamVolumes, first_frame + k), sunbeams[k]);
    if (!whitewater.empty()) file(underwater_file_name(kWhitewaterPoints, first_frame + k), whitewater[k]);
}

}  // namespace detail

namespace {

using detail::for_underwater_files;

// The caustic maps and sunbeam volumes beside the animation: in a per-frame form after
// each frame's own files (a frame's entry lists them together), else after the file.
void add_underwater_files(const MorphAnimationView& view, std::span<const std::string> caustics, std::span<const std::string> sunbeams,
                          std::span<const std::string> whitewater, ExportForm form, EncodedFiles& files) {
    if (caustics.empty() && sunbeams.empty() && whitewater.empty()) return;
    const std::size_t per_frame = export_form(form).per_frame ? files.size() / view.frame_count : 0;
    EncodedFiles grouped;
    if (per_frame == 0) grouped.swap(files);  // the animation's files first, whole
    for (std::size_t k = 0; k < view.frame_count; ++k) {
        for (std::size_t i = 0; i < per_frame; ++i) grouped.push_back(std::move(files[k * per_frame + i]));
        for_underwater_files(view.first_frame, k, caustics, sunbeams, whitewater,
                             [&](std::string name, const std::string& bytes) { grouped.emplace_back(std::move(name), bytes); });
    }
    files.swap(grouped);
}

// animation.glb, or animation-frames-A-B.glb for a slice.
std::string animation_file_name(std::size_t first_frame, std::size_t frame_count, bool whole) {
    char slice_name[64];
    std::snprintf(slice_name, sizeof slice_name, "animation-frames-%zu-%zu.glb", first_frame, first_frame + frame_count);
    return whole ? "animation.glb" : slice_name;
}

// The pc2 form's base mesh (frame 0 of the view) as .glb and .obj beside the caches.
void add_pc2_base(const MorphAnimationView& view, const std::string& base, EncodedFiles& files) {
    files.emplace_back(base + ".glb", gltf_frame_glb(view, 0));
    files.emplace_back(base + ".obj", mesh_to_obj(view.positions.first(3 * view.vertex_count), view.triangles,
                                                  "libwave: base mesh of " + base + ".pc2, z up"));
}

// The pc2 form's shading "points" of frames: (reflect, refract, foam) per vertex.
std::vector<float> pc2_shading(const MorphAnimationView& view) {
    std::vector<float> shading(3 * view.vertex_count * view.frame_count);
    for (std::size_t i = 0; i < view.vertex_count * view.frame_count; ++i) {
        shading[3 * i] = view.reflect[i];
        shading[3 * i + 1] = view.refract[i];
        shading[3 * i + 2] = view.foam[i];
    }
    return shading;
}

// Each .glb becomes name.gltf + name.bin (the .bin named relative to the .gltf).
void split_gltf_container(EncodedFiles& files) {
    EncodedFiles split;
    for (auto& [name, bytes] : files) {
        if (!name.ends_with(".glb")) {
            split.emplace_back(std::move(name), std::move(bytes));
            continue;
        }
        const std::string base = name.substr(0, name.size() - 4);  // without ".glb"
        const std::string bin = base + ".bin";
        GltfFiles g = glb_to_gltf(bytes, std::filesystem::path(bin).filename().string());
        split.emplace_back(base + ".gltf", std::move(g.json));
        split.emplace_back(bin, std::move(g.bin));
    }
    files.swap(split);
}

// The forms' rows (export_forms): how each is encoded, streamed and estimated.
void encode_morph(const MorphAnimationView& view, const std::string& animation_name, bool, EncodedFiles& files) {
    files.emplace_back(animation_name, gltf_morph_glb(view));
}

void encode_nodes(const MorphAnimationView& view, const std::string& animation_name, bool, EncodedFiles& files) {
    files.emplace_back(animation_name, gltf_nodes_glb(view));
}

void encode_frames(const MorphAnimationView& view, const std::string&, bool, EncodedFiles& files) {
    for (std::size_t k = 0; k < view.frame_count; ++k) {
        char name[48];
        std::snprintf(name, sizeof name, "frames/frame-%04zu.glb", view.first_frame + k);
        files.emplace_back(name, gltf_frame_glb(view, k));
    }
}

// Point caches beside a base mesh (frame 0 of the range) as .glb and .obj, z up as
// written; the shading as a second cache of (reflect, refract, foam) "points".
void encode_pc2(const MorphAnimationView& view, const std::string& animation_name, bool whole, EncodedFiles& files) {
    const std::string base = whole ? "animation" : animation_name.substr(0, animation_name.size() - 4);
    const std::size_t n = view.vertex_count;
    add_pc2_base(view, base, files);
    const auto start = static_cast<float>(view.first_frame);
    files.emplace_back(base + ".pc2", pc2_bytes(view.positions, n, view.frame_count, start));
    if (!view.foam.empty()) files.emplace_back(base + "-shading.pc2", pc2_bytes(pc2_shading(view), n, view.frame_count, start));
}

// A PLY per frame and an index of them (ply/index.json: the frames' files, fps, range).
void encode_ply(const MorphAnimationView& view, const std::string& animation_name, bool whole, EncodedFiles& files) {
    nlohmann::json frames = nlohmann::json::array();
    for (std::size_t k = 0; k < view.frame_count; ++k) {
        char name[48];
        std::snprintf(name, sizeof name, "ply/frame-%04zu.ply", view.first_frame + k);
        files.emplace_back(name, ply_frame_bytes(view, k));
        frames.push_back(name);
    }
    const nlohmann::json index{{"form", "ply"}, {"scene", view.scene}, {"fps", view.fps}, {"first_frame", view.first_frame},
                               {"frame_count", view.frame_count}, {"loop_frames", view.loop_frames}, {"z_up", true},
                               {"frames", std::move(frames)}};
    const std::string stem = animation_name.substr(0, animation_name.size() - 4);  // animation or animation-frames-A-B
    files.emplace_back(whole ? "ply/index.json" : "ply/" + stem + ".json", index.dump(2) + "\n");
}

// Per frame: the header, 32 or 44 bytes a vertex, 13 a triangle.
double ply_bytes(const ExportSizing& s) {
    return s.frames * (400.0 + s.vertices * (32.0 + (s.shaded ? 12.0 : 0.0)) + s.indices / 12.0 * 13.0);
}

bool streamed_always(bool) noexcept { return true; }
bool streamed_unless_quantised(bool quantize) noexcept { return !quantize; }
bool streamed_never(bool) noexcept { return false; }

double morph_bytes(const ExportSizing& s) {
    return (s.draco ? s.draco_frame : s.vertices * s.per_frame_vertex + s.uv0 + s.indices) +
           s.frames * s.vertices * s.per_frame_vertex * (s.quantize ? 0.6 : s.meshopt ? s.meshopt_share : 1.0);
}

// The meshes share the indices and TEXCOORD_0.
double nodes_bytes(const ExportSizing& s) {
    return s.draco ? s.frames * s.draco_frame
                   : s.indices + s.uv0 + s.frames * s.vertices * s.per_frame_vertex * (s.quantize ? 0.7 : s.meshopt ? s.meshopt_share : 1.0);
}

double frames_bytes(const ExportSizing& s) {
    return s.frames * (s.draco ? s.draco_frame
                               : s.indices + s.uv0 + s.vertices * s.per_frame_vertex * (s.quantize ? 0.7 : s.meshopt ? s.meshopt_share : 1.0));
}

// Positions and the shading as float triples per frame, the base mesh twice.
double pc2_form_bytes(const ExportSizing& s) {
    return s.frames * s.vertices * (12.0 + (s.shaded ? 12.0 : 0.0)) + 2.0 * (s.vertices * s.per_frame_vertex + s.uv0 + s.indices);
}

constexpr std::array<ExportFormInfo, 5> kForms{{
    {ExportForm::morph, "morph", "one .glb of shape keys", true, false, true, streamed_always, encode_morph, morph_bytes,
     "{first}", "{n} frames as morph targets, STEP weights"},
    {ExportForm::nodes, "nodes", "one object per frame", true, false, true, streamed_unless_quantised, encode_nodes,
     nodes_bytes, "{first}", "{n} scale-switched nodes"},
    {ExportForm::files, "files", "one .glb per frame + index.json", false, true, true, streamed_never, encode_frames, frames_bytes,
     "frames/ + index.json", "{files} files"},
    {ExportForm::pc2, "pc2", "a base .glb/.obj + PC2 point caches for Blender's Mesh Cache modifier, Maya, 3ds Max, Houdini", false, false,
     false, streamed_unless_quantised, encode_pc2, pc2_form_bytes, "{first} + .obj + .pc2", "{n} point-cache samples"},
    {ExportForm::ply, "ply", "one binary PLY per frame + ply/index.json: positions, normals, UVs, shading as vertex properties (Houdini, Blender, MeshLab)",
     false, false, false, streamed_never, encode_ply, ply_bytes, "{first}", "{n} binary PLY frames"},
}};

}  // namespace

std::span<const ExportFormInfo> export_forms() noexcept { return kForms; }

const ExportFormInfo& export_form(ExportForm form) noexcept { return kForms[static_cast<std::size_t>(form)]; }

ExportForm export_form_named(std::string_view name) {
    std::string list;
    for (const ExportFormInfo& f : kForms) {
        if (f.name == name) return f.form;
        list += (list.empty() ? "" : ", ") + std::string(f.name);
    }
    throw InputError("form: expected one of " + list + ", got " + detail::brief_json(nlohmann::json(std::string(name))));
}

EncodedFiles encode_animation(const MorphAnimationView& view, ExportForm form, ExportContainer container, bool whole,
                              std::span<const std::string> caustics, std::span<const std::string> sunbeams,
                              std::span<const std::string> whitewater) {
    EncodedFiles files;
    export_form(form).encode(view, animation_file_name(view.first_frame, view.frame_count, whole), whole, files);
    if (container == ExportContainer::gltf) split_gltf_container(files);
    add_underwater_files(view, caustics, sunbeams, whitewater, form, files);
    return files;
}

namespace {

// A file written as the frames come, removed unless it was finished.
struct PartialFile {
    std::string path;
    std::FILE* file = nullptr;
    explicit PartialFile(std::string p) : path(std::move(p)), file(std::fopen(path.c_str(), "wb")) {
        if (!file) throw RuntimeError(path + ": cannot create: " + std::strerror(errno));
    }
    ~PartialFile() {
        if (file) {
            std::fclose(file);
            std::remove(path.c_str());
        }
    }
    void write(const void* data, std::size_t n) {
        if (n > 0 && std::fwrite(data, 1, n, file) != n) throw RuntimeError(path + ": cannot write: " + std::strerror(errno));
    }
    void close() {
        if (std::fclose(std::exchange(file, nullptr)) != 0) {
            std::remove(path.c_str());
            throw RuntimeError(path + ": cannot write: " + std::strerror(errno));
        }
    }
};

// The pc2 form streamed: the base mesh from the first chunk, then the caches' samples.
struct Pc2Stream {
    std::string folder, base;
    std::optional<PartialFile> positions{}, shading{};

    void start(const MorphAnimationView& first, std::size_t frames, ExportContainer container, EncodedFiles& files) {
        add_pc2_base(first, base, files);
        if (container == ExportContainer::gltf) split_gltf_container(files);
        const std::string header = pc2_header(first.vertex_count, frames, static_cast<float>(first.first_frame));
        positions.emplace(folder + "/" + base + ".pc2");
        positions->write(header.data(), header.size());
        if (first.foam.empty()) return;
        shading.emplace(folder + "/" + base + "-shading.pc2");
        shading->write(header.data(), header.size());
    }
    void add(const MorphAnimationView& chunk) {
        positions->write(chunk.positions.data(), chunk.positions.size_bytes());
        if (!shading) return;
        const std::vector<float> s = pc2_shading(chunk);
        shading->write(s.data(), s.size() * sizeof(float));
    }
    void finish(std::vector<std::pair<std::string, std::size_t>>& written) {
        for (std::optional<PartialFile>* f : {&positions, &shading}) {
            if (!*f) continue;
            const auto bytes = static_cast<std::size_t>(std::ftell((*f)->file));
            (*f)->close();
            written.emplace_back(std::filesystem::path((*f)->path).filename().string(), bytes);
        }
    }
};

}  // namespace

bool streamed_form(ExportForm form, bool quantize) noexcept { return export_form(form).streamed(quantize); }

struct StreamedWriter::State {
    std::optional<AnimationFileWriter> glb;
    Pc2Stream pc2;
    EncodedFiles small;  // the pc2 form's base mesh
    std::string folder;
};

StreamedWriter::StreamedWriter(const std::string& folder, ExportForm form, ExportContainer container, bool whole,
                               const MorphAnimationView& first, std::size_t frame_count)
    : state_(std::make_unique<State>()) {
    if (!streamed_form(form, first.quantize))
        throw InputError("export: the files form and quantised nodes or pc2 files are not streamed");
    const std::string name = animation_file_name(first.first_frame, frame_count, whole);
    state_->folder = folder;
    if (form == ExportForm::pc2) {
        state_->pc2.folder = folder;
        state_->pc2.base = whole ? "animation" : name.substr(0, name.size() - 4);
        state_->pc2.start(first, frame_count, container, state_->small);
        return;
    }
    const bool gltf = container == ExportContainer::gltf;
    const std::string path = folder + "/" + (gltf ? name.substr(0, name.size() - 4) + ".gltf" : name);
    state_->glb.emplace(path, form == ExportForm::morph ? AnimationFileWriter::Form::morph : AnimationFileWriter::Form::nodes,
                        gltf, first, frame_count);
}

StreamedWriter::~StreamedWriter() = default;

void StreamedWriter::append(const MorphAnimationView& chunk) {
    if (state_->glb) state_->glb->append(chunk);
    else state_->pc2.add(chunk);
}

std::vector<std::pair<std::string, std::size_t>> StreamedWriter::finish() {
    if (state_->glb) return state_->glb->finish();
    std::vector<std::pair<std::string, std::size_t>> written;
    for (const auto& [file, bytes] : state_->small) {
        write_file_atomic(state_->folder + "/" + file, bytes);
        written.emplace_back(file, bytes.size());
    }
    state_->pc2.finish(written);
    return written;
}

}  // namespace wave
