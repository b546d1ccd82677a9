/// \file
/// libwave — export: meshes and animations to files for DCC tools.
///
/// glTF 2.0 binary (.glb) with the animation as one morph target per frame and a STEP
/// `weights` channel (docs/conventions.md, "Export conventions"; Blender turns it into shape
/// keys, three.js plays it); Wavefront OBJ of one frame. libwave is z up; glTF is y up:
/// the glTF writer maps (x, y, z) → (x, z, −y), nothing else converts.
#pragma once

#include "libwave/underwater.h"

#include <cstddef>
#include <cstdint>
#include <array>
#include <memory>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <string_view>
#include <utility>

namespace wave {

/// A frame's sunlight (evaluate_sun_volume) as an OpenVDB file: one fog-volume float
/// grid "sunlight", saved as half floats, voxels of 0 inactive, its transform putting
/// voxel (i, j, k)'s centre at its place in metres, z up. What the sunbeam sequence
/// beside an animation holds. The same bytes for the same light (the archive's identifier is derived from
/// the content).
std::string sun_volume_vdb(const SunVolumePlan& plan, std::span<const float> light);

/// A PC2 point cache (Blender's Mesh Cache modifier, 3ds Max, Maya, Cinema 4D, Houdini):
/// the 12-byte signature "POINTCACHE2\0", version 1, the point count, the start frame and
/// the sampling step (frames), the sample count, then every sample's points as float32
/// x, y, z, little-endian. `points` holds sample_count · point_count · 3 values.
std::string pc2_bytes(std::span<const float> points, std::size_t point_count, std::size_t sample_count, float start_frame);
/// The 32-byte header alone, for writers that append the samples as they come.
std::string pc2_header(std::size_t point_count, std::size_t sample_count, float start_frame);

struct MorphAnimationView;

/// Frame `f` of `view` as a binary little-endian PLY (Houdini, Blender, MeshLab,
/// CloudCompare): vertices with float x, y, z (z up), nx, ny, nz, s, t (TEXCOORD_0: the
/// rest position over the seafloor), and with shading reflect, refract, foam as float
/// properties; faces as uchar-counted uint index lists. InputError for an index out of
/// range or a frame the view does not hold.
std::string ply_frame_bytes(const MorphAnimationView& view, std::size_t f);

/// One triangle mesh as OBJ text: `v x y z` per vertex (3 floats each in `positions`),
/// `f a b c` per triangle (0-based `triangles`, written 1-based), a comment line first.
/// Precondition: every index < positions.size() / 3.
std::string mesh_to_obj(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                        std::string_view comment);

/// Where the per-vertex shading scalars go (docs/conventions.md, "Export conventions").
enum class ScalarLayout {
    custom,     ///< FLOAT attributes `_REFLECT`, `_REFRACT`, `_FOAM` (glTF's custom-attribute rule; Blender >= 3.5, three.js `_foam`)
    blender34,  ///< TEXCOORD_1 = (R, T), TEXCOORD_2 = (foam, 0): Blender 3.4 keeps UV maps (it stores 1 − v)
};

/// Draco compression (KHR_draco_mesh_compression) of the `nodes` and `files` forms:
/// quantisation bits per kind of attribute (more bits, smaller error, bigger files).
struct DracoOptions {
    int position_bits = 14;  ///< error <= extent / 2^15 per axis
    int normal_bits = 10;    ///< octahedral normal bits
    int texcoord_bits = 12;  ///< also the UV-map shading layout
    int color_bits = 8;      ///< COLOR_0
    int generic_bits = 12;   ///< the named `_` scalars
    int encode_speed = 5;    ///< Draco's 0 (smallest) … 10 (fastest)
};

/// What a single-file animation carries beside the water, so that a glTF client (Blender,
/// three.js) opens a scene: the seafloor as a mesh coloured by depth, the camera, the sun
/// (KHR_lights_punctual) and a water material (KHR_materials_transmission, _ior,
/// _volume). Every part is optional; arrays are z up.
struct SceneDressing {
    std::span<const float> seafloor_positions;          ///< 3 per vertex (m)
    std::span<const float> seafloor_colors;             ///< 3 per vertex, linear RGB
    std::span<const std::uint32_t> seafloor_triangles;  ///< counter-clockwise seen from above
    bool camera = false;  ///< write the camera: at camera_position (z up), turned by camera_rotation
    std::array<double, 3> camera_position{};  ///< m, z up
    std::array<double, 4> camera_rotation{0.0, 0.0, 0.0, 1.0};  ///< glTF node rotation (x, y, z, w; glTF axes)
    double camera_yfov = 0.6981317007977318;  ///< vertical field of view (rad)
    double camera_aspect = 16.0 / 9.0;        ///< width / height
    bool sun = false;  ///< write a directional light turned by sun_rotation
    std::array<double, 4> sun_rotation{0.0, 0.0, 0.0, 1.0};  ///< glTF node rotation (the light shines along its −Z)
    bool water_material = false;  ///< write the water material (transmission, IOR 1.333, volume)
    /// Caustic maps beside the file (docs/underwater.md): with texcoords (2 per seafloor
    /// vertex, the maps' frame) the seafloor gets TEXCOORD_0, and with a pattern (e.g.
    /// "caustics/caustics-%04d.png", numbered by loop frame) its material's extras
    /// name the sequence: libwave_caustics {images, frames, fps, texCoord, full_scale}.
    std::span<const float> seafloor_texcoords;
    std::string caustic_images;  ///< printf pattern of the maps' names, by loop frame (empty: none)
    std::size_t caustic_frames = 0;  ///< maps in the sequence
    double caustic_fps = 24.0;  ///< the sequence's frames per second
    double caustic_full_scale = 1.0;  ///< E / I₀ written as white
    /// Sunbeam volumes beside the file (docs/underwater.md): with a pattern (e.g.
    /// "sunbeams/sunbeams-%04d.vdb", by loop frame) the seafloor material's extras name
    /// the sequence: libwave_sunbeams {volumes, frames, fps, grid, attenuation,
    /// direction (glTF axes)}.
    std::string sunbeam_volumes;  ///< printf pattern of the volumes' names, by loop frame (empty: none)
    std::size_t sunbeam_frames = 0;  ///< volumes in the sequence
    double sunbeam_fps = 24.0;       ///< the sequence's frames per second
    double sunbeam_attenuation = 0.15;  ///< c (1/m) of the water they were traced in
    std::array<double, 3> sunbeam_direction{0.0, 0.0, -1.0};  ///< the beam's unit direction under flat water (z up)
};

/// The glTF node rotation (x, y, z, w in glTF's y-up axes) that turns a camera or a
/// directional light at `from` to look (along its −Z) towards `to`, its +Y as close to
/// up as it can be; points z up.
std::array<double, 4> gltf_look_rotation(const std::array<double, 3>& from, const std::array<double, 3>& to);

/// Frames of one mesh with fixed topology (views of caller-owned arrays, z up): what
/// every exporter reads.
struct MorphAnimationView {
    std::span<const std::uint32_t> triangles;  ///< 3 indices per triangle, counter-clockwise
    std::size_t vertex_count = 0;  ///< per frame
    std::size_t frame_count = 0;   ///< frames viewed
    std::span<const float> positions;  ///< frame_count · vertex_count · 3
    std::span<const float> normals;    ///< same layout, unit length
    std::span<const float> texcoords;  ///< vertex_count · 2 (TEXCOORD_0)
    /// Optional shading per frame (frame_count · vertex_count each; empty = not written):
    /// Fresnel reflect and refract weights and foam, and a baked COLOR_0 (3 per vertex).
    std::span<const float> reflect;  ///< Fresnel R
    std::span<const float> refract;  ///< T = 1 − R
    std::span<const float> foam;     ///< in [0, 1]
    std::span<const float> colors;   ///< COLOR_0, 3 per vertex
    ScalarLayout layout = ScalarLayout::custom;  ///< how the scalars are laid out (ScalarLayout)
    double fps = 24.0;  ///< frames per second
    /// Number of the first frame in the whole loop (a slice starts later): key times
    /// and frame names count from it.
    std::size_t first_frame = 0;
    /// Frames in the whole loop (0 = not known); recorded in the file for readers.
    std::size_t loop_frames = 0;
    std::string name = "water";  ///< mesh and node names
    std::string scene;           ///< the scene's name, recorded in the file for readers
    /// The run's key (what decided its bytes), recorded in the file when not empty: the
    /// files form's frames carry it, so that frames of two versions are never merged.
    std::string run_key;
    /// Compress with Draco. In the morph form only the base mesh is compressed (with
    /// Draco's order-keeping sequential method); the targets stay float.
    std::optional<DracoOptions> draco;
    /// KHR_mesh_quantization (not with Draco), the mesh node's transform undoing the
    /// positions' scale: in the nodes and files forms positions are normalised int16
    /// (error <= extent / 65534); morph targets keep the base's positions float and
    /// store deltas as int16 (error <= largest delta / 65534). Normals int8, UV maps
    /// uint16 (morph deltas int16; normal deltas stay float).
    bool quantize = false;
    /// Quantised morph targets: the range of the position deltas from the range's first
    /// frame (the largest |delta| of any coordinate), when known before the frames come
    /// (AnimationFileWriter streams quantised morph targets only with it); none = found
    /// from the frames given. Deltas beyond it are clamped.
    std::optional<double> quantize_range;
    /// EXT_meshopt_compression (not with Draco or quantize; docs/export.md, "Meshopt
    /// compression"): every vertex attribute and index view through meshoptimizer's
    /// codecs, float attributes through its exponential filter with an exponent per
    /// value, so that precision follows each axis: heights within min(2^-17 m, the
    /// horizontal step / 2), horizontal positions within 1/256 of the frame's shortest
    /// edge (and 2^-24 of a coordinate beyond 2^23 steps, a far skirt's), normals 2^-15,
    /// shading 2^-17, TEXCOORD_0 2^-21. Morph targets are dense (zeros cost nearly
    /// nothing in the codec). Decoded by read_animation, three.js's MeshoptDecoder,
    /// gltfpack; not by Blender's own importer.
    bool meshopt = false;
    /// The seafloor, camera, sun and water material (morph and nodes forms; in the files
    /// form the loop's frame 0 carries them).
    std::optional<SceneDressing> dressing;
};

/// A view of any struct holding an animation's arrays under MorphAnimationView's names
/// (SceneAnimation, StoredAnimation): the arrays, counts, layout, fps and frame numbers.
template <class Frames>
MorphAnimationView animation_view(const Frames& a) {
    MorphAnimationView v;
    v.triangles = a.triangles;
    v.vertex_count = a.vertex_count;
    v.frame_count = a.frame_count;
    v.positions = a.positions;
    v.normals = a.normals;
    v.texcoords = a.texcoords;
    v.reflect = a.reflect;
    v.refract = a.refract;
    v.foam = a.foam;
    v.colors = a.colors;
    v.layout = a.layout;
    v.fps = a.fps;
    v.first_frame = a.first_frame;
    v.loop_frames = a.loop_frames;
    v.scene = a.scene;
    if (a.dressing) {
        v.dressing = *a.dressing;
        v.dressing->seafloor_positions = a.seafloor_positions;
        v.dressing->seafloor_colors = a.seafloor_colors;
        v.dressing->seafloor_triangles = a.seafloor_triangles;
        if constexpr (requires { a.seafloor_texcoords; }) v.dressing->seafloor_texcoords = a.seafloor_texcoords;
    }
    return v;
}

/// Frames [first, first + count) of a view as a view of their own (its first_frame
/// advanced; the per-frame arrays cut, the rest shared): e.g. one frame of a chunk
/// encoded and written before the next is. Precondition: first + count <= frame_count.
MorphAnimationView frame_subview(const MorphAnimationView& v, std::size_t first, std::size_t count);

/// The largest float32 <= k / fps: nearest rounding lands some keys just after frame k
/// and Blender then shows the previous frame there (docs/conventions.md, key times).
float key_time(std::size_t k, double fps) noexcept;

/// A .glb holding the animation: the mesh with frame 0 as its base (POSITION, NORMAL,
/// TEXCOORD_0, the shading attributes when given, uint32 indices), one morph target
/// per frame (the differences from frame 0 of every animated attribute, named in
/// mesh.extras.targetNames), and an animation whose `weights` channel is one-hot per
/// frame with STEP interpolation at key_time(k, fps). With weights one-hot, frame k
/// shows base + target k = exactly frame k, for the scalars as for positions.
/// Throws InputError for inconsistent sizes, an index out of range, or a NaN/Inf value
/// (naming the frame and vertex).
std::string gltf_morph_glb(const MorphAnimationView& animation);

/// The `nodes` form: a parent node with one child node and mesh per frame (its own
/// POSITION, NORMAL and shading; indices and TEXCOORD_0 shared), each child's `scale`
/// switched between 0 and 1 by STEP keys at key_time(k, fps) so that one frame shows at
/// a time. Blender imports one object per frame; use it when topology changes or a
/// tool does not play morph targets. Same checks as gltf_morph_glb.
std::string gltf_nodes_glb(const MorphAnimationView& animation);

/// The same model as a text .gltf whose buffer 0 is the external file `bin_uri` (a
/// relative URI, written by the caller next to the .gltf).
struct GltfFiles {
    std::string json;  ///< the .gltf
    std::string bin;   ///< the .bin
};
/// Splits a .glb (from the functions above) into a .gltf and its .bin. Throws
/// InputError for a malformed GLB.
GltfFiles glb_to_gltf(std::string_view glb, const std::string& bin_uri);

/// The morph or nodes form written to a file a chunk of frames at a time, so that
/// memory holds one chunk and never the animation (docs/export.md, "Streamed output"):
/// made with the range's first chunk (its first frame is the morph form's base; its
/// settings and dressing are the file's) and the range's frame count; then `append`
/// every chunk in order, the first one too; then `finish`. The buffer goes to
/// `path` + ".bin-part" while the frames come and is copied behind the header at the
/// end (with `gltf_container`: `path` is the .gltf and the buffer is its .bin). The
/// bytes equal gltf_morph_glb / gltf_nodes_glb (and glb_to_gltf) of the whole range.
/// Destroyed unfinished (an exception), it removes what it wrote.
/// Throws InputError for a quantised view (KHR_mesh_quantization's range spans every
/// frame: write those whole), chunks that differ in mesh or are out of range, and what
/// gltf_morph_glb refuses; LimitError when a .glb would exceed its 4 GiB length field.
class AnimationFileWriter {
public:
    /// The single-file forms a writer streams.
    enum class Form {
        morph,  ///< morph targets
        nodes,  ///< scale-switched nodes
    };
    /// A writer of `frame_count` frames to `path` (.glb, or .gltf + .bin with
    /// gltf_container) whose static parts (triangles, texcoords, dressing) are `first`'s.
    AnimationFileWriter(std::string path, Form form, bool gltf_container, const MorphAnimationView& first,
                        std::size_t frame_count);
    ~AnimationFileWriter();  ///< removes what it wrote unless finished
    AnimationFileWriter(const AnimationFileWriter&) = delete;  ///< not copyable
    AnimationFileWriter& operator=(const AnimationFileWriter&) = delete;  ///< not copyable
    /// The next frames (the chunk's first_frame must follow the last appended).
    void append(const MorphAnimationView& chunk);
    /// Writes the file(s) in place (atomically); returns each one's name (without the
    /// folder) and size in bytes. Throws InputError unless every frame was appended.
    std::vector<std::pair<std::string, std::size_t>> finish();

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// The `files` form: frame `frame` (0-based within the view) as a static .glb.
std::string gltf_frame_glb(const MorphAnimationView& animation, std::size_t frame);

/// An animation read back from libwave's own output (`wave convert`): every frame's
/// arrays, as MorphAnimationView describes them, owned.
struct StoredAnimation {
    std::size_t vertex_count = 0;  ///< per frame
    std::size_t frame_count = 0;   ///< frames read
    std::size_t first_frame = 0;   ///< of the loop
    std::size_t loop_frames = 0;   ///< frames in the loop (0 = not recorded)
    double fps = 24.0;             ///< frames per second
    std::string name = "water";    ///< the mesh's name
    std::string scene;             ///< the scene's name recorded in the file
    std::vector<std::uint32_t> triangles;  ///< 3 per triangle
    std::vector<float> positions;  ///< z up, as written
    std::vector<float> normals;    ///< z up, as written
    std::vector<float> texcoords;  ///< TEXCOORD_0, as written
    std::vector<float> reflect;    ///< as written (empty when the file has none)
    std::vector<float> refract;    ///< as written (empty when the file has none)
    std::vector<float> foam;       ///< as written (empty when the file has none)
    std::vector<float> colors;     ///< as written (empty when the file has none)
    /// What the file carried beside the water (morph and nodes forms), to write it again:
    /// the seafloor's arrays (z up) and the camera, sun and material settings.
    std::vector<float> seafloor_positions;  ///< 3 per vertex (m, z up)
    std::vector<float> seafloor_colors;     ///< 3 per vertex (linear RGB)
    std::vector<std::uint32_t> seafloor_triangles;  ///< 3 per triangle
    std::optional<SceneDressing> dressing;  ///< its spans are set by view()
    ScalarLayout layout = ScalarLayout::custom;  ///< the file's layout of the scalars
    bool draco_frames = false;  ///< read from a Draco-compressed frame (its own point order)

    MorphAnimationView view() const;  ///< a view for the exporters (spans into this)
};

/// Reads a libwave output: a .glb or .gltf of the morph or nodes form or one frame file,
/// or the index.json of the files form (its frame files beside it). Plain, quantised
/// (KHR_mesh_quantization) and Draco-compressed meshes are decoded. Draco frames of the
/// nodes and files forms come back in Draco's point order, which edgebreaker takes
/// from the triangles alone, so the frames of one run share it; a frame's primitives
/// (a Draco frame and its far-field skirt) are joined into one mesh, a later
/// primitive's vertex welded onto the first primitive's vertex at the bit-equal
/// position. Positions come back within the writer's quantisation. Throws InputError
/// naming the file for anything else (not glTF, not written by libwave, frames whose
/// triangles differ).
StoredAnimation read_animation(const std::string& path);

/// Frames [first, first + count) of a .glb/.gltf of the morph or nodes form (counted
/// from the file's first frame), as read_animation reads them: the other frames' views
/// are neither read nor decoded, so a player takes one frame of a compressed file at the
/// cost of that frame (first_frame is the first one read). Throws InputError as
/// read_animation does, and when the file has no frame `first` or `path` is an index.
StoredAnimation read_animation_frames(const std::string& path, std::size_t first, std::size_t count);

/// read_animation a piece at a time, so that memory holds one piece: the files form's
/// frames one by one (each with its frame number, and the index's fps and loop), a
/// .glb/.gltf whole. `piece` gets them in order, with the frames the input lists in all
/// (the index's entries; the file's frames). The files form's checks (consecutive frames,
/// the same triangles) are read_animation's and throw before the offending piece.
void read_animation_pieces(const std::string& path, const std::function<void(StoredAnimation&&, std::size_t)>& piece);

/// A player's reader of one output of wave run (the Blender add-on's): opened once, it
/// keeps what every frame shares — the parsed file, its static views, the triangles;
/// for the files form the index and the decoded indices and rest positions of the frame
/// files, which are not decoded again while a frame file's compressed bytes equal them —
/// so that frame(k) reads and decodes only frame k's own views. Frames come back as
/// read_animation gives them (bit for bit), their arrays alone: a StoredAnimation of one
/// frame without triangles, rest positions or seafloor. Thread-safe (frames are read one
/// at a time). Throws InputError as read_animation does, naming the file.
class FrameReader {
public:
    explicit FrameReader(const std::string& path);  ///< a .glb/.gltf (morph or nodes form, a frame file) or index.json
    ~FrameReader();  ///< closes the file it reads
    FrameReader(FrameReader&&) noexcept;             ///< takes the other's open output
    FrameReader& operator=(FrameReader&&) noexcept;  ///< takes the other's open output

    std::size_t frame_count() const noexcept;   ///< frames in the output
    std::size_t vertex_count() const noexcept;  ///< per frame
    std::size_t first_frame() const noexcept;   ///< of the loop
    std::size_t loop_frames() const noexcept;   ///< frames in the loop (0 = not recorded)
    double fps() const noexcept;                ///< frames per second
    const std::string& scene() const noexcept;  ///< the scene's name recorded in the output
    const std::vector<std::uint32_t>& triangles() const noexcept;  ///< 3 per triangle, shared by every frame

    /// Frame k (0 ≤ k < frame_count()) of the output; without `normals` its normals are
    /// neither read nor decoded (left empty).
    StoredAnimation frame(std::size_t k, bool normals = true);

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// Quantised morph targets' range (MorphAnimationView::quantize_range): the largest
/// |delta| of any position coordinate of `frames` (whole frames of base.size() floats)
/// from `base`, the range's first frame, and `so_far`. Taken chunk by chunk over a range,
/// it is what gltf_morph_glb finds over the whole range.
double position_delta_range(std::span<const float> base, std::span<const float> frames, double so_far = 0.0) noexcept;

/// The caustic maps' names beside an animation, by loop frame (printf pattern).
inline constexpr char kCausticImages[] = "caustics/caustics-%04d.png";
/// The sunbeam volumes' names beside an animation, by loop frame (printf pattern).
inline constexpr char kSunbeamVolumes[] = "sunbeams/sunbeams-%04d.vdb";
/// The whitewater particles' files beside an animation, by loop frame (printf pattern).
inline constexpr char kWhitewaterPoints[] = "whitewater/whitewater-%04d.glb";

/// How an animation is written (docs/export.md): one row of export_forms() each, which
/// the scene files (/outputs/form), `wave`'s --form options, the Python module and the
/// run's size estimate read.
enum class ExportForm {
    morph,  ///< one .glb of morph targets
    nodes,  ///< one .glb of scale-switched nodes
    files,  ///< frames/frame-NNNN.glb and index.json
    pc2,    ///< a base mesh and PC2 point caches
    ply,    ///< ply/frame-NNNN.ply (positions, normals, rest UVs, shading) and ply/index.json
};

/// Binary .glb, or text .gltf with an external .bin.
enum class ExportContainer {
    glb,   ///< binary
    gltf,  ///< JSON and an external .bin
};

/// (name under the output folder, bytes) pairs of an encoded animation.
using EncodedFiles = std::vector<std::pair<std::string, std::string>>;

/// What a form's size estimate reads (estimate_run): bytes of the writer's layout.
struct ExportSizing {
    double frames = 0.0;            ///< frames written
    double vertices = 0.0;          ///< vertices per frame
    double per_frame_vertex = 0.0;  ///< bytes a vertex adds per frame: POSITION, NORMAL, shading, COLOR_0
    double indices = 0.0;           ///< bytes of the triangles' indices
    double uv0 = 0.0;               ///< bytes of TEXCOORD_0
    double draco_frame = 0.0;       ///< bytes of a Draco frame (measured)
    double meshopt_share = 0.5;     ///< EXT_meshopt_compression's bytes over the floats'
    bool draco = false;             ///< Draco-compressed
    bool quantize = false;          ///< KHR_mesh_quantization
    bool meshopt = false;           ///< EXT_meshopt_compression
    bool shaded = false;            ///< with reflect, refract and foam
};

/// One export form: the table export_forms() lists, the one place a form is described.
struct ExportFormInfo {
    ExportForm form;               ///< its value
    std::string_view name;         ///< as /outputs/form and --form spell it
    std::string_view description;  ///< what it writes, for help texts
    /// Its animation is one glTF file (animation.glb): `wave run -o FILE.glb`, the
    /// Python module's glb(), the glTF codecs' choice by size.
    bool single_file;
    /// Each frame's files apart (frames/…), each frame's underwater files after its own.
    bool per_frame;
    /// It writes glTF: the glTF codecs (Draco, quantisation, meshopt) apply, and the
    /// automatic codec (resolve_codec) may choose EXT_meshopt_compression for it.
    bool gltf;
    /// Whether StreamedWriter writes it a chunk of frames at a time (`quantize`: for a
    /// view with KHR_mesh_quantization, whose range may need every frame).
    bool (*streamed)(bool quantize) noexcept;
    /// Its animation's files into `files`, in order: `animation_name` is animation.glb or
    /// a slice's animation-frames-A-B.glb (`whole` false); encode_animation adds the rest.
    void (*encode)(const MorphAnimationView& view, const std::string& animation_name, bool whole, EncodedFiles& files);
    /// The bytes its animation's files take (the seafloor and underwater files apart).
    double (*output_bytes)(const ExportSizing& sizing);
    /// What a run wrote, as its summary names it (`wave run`'s "wrote" line): `{first}`
    /// stands for the first animation file.
    std::string_view summary_files;
    /// What those files hold, as the summary says it: `{n}` stands for the frame count,
    /// `{files}` for the number of animation files.
    std::string_view summary_contents;
};

/// Every export form, in ExportForm's order.
std::span<const ExportFormInfo> export_forms() noexcept;
/// The row of `form`.
const ExportFormInfo& export_form(ExportForm form) noexcept;
/// The form named `name`; InputError naming the valid names ("form: expected one of …").
ExportForm export_form_named(std::string_view name);

/// The one place an animation becomes files in an export form (its export_forms()
/// row): animation.glb (or animation-frames-A-B.glb for a slice, `whole` = false) for
/// morph and nodes, frames/frame-NNNN.glb for files, a base mesh and point caches for
/// pc2; with the gltf container each .glb becomes name.gltf + name.bin. With
/// `caustics` (one PNG per frame of the view), the maps as kCausticImages beside them,
/// with `sunbeams` (one OpenVDB volume per frame) the volumes as kSunbeamVolumes, and
/// with `whitewater` (one POINTS .glb per frame) the particles as kWhitewaterPoints (in
/// a per-frame form after each frame's own files). Used by `wave run`, `wave convert`
/// and the Python module.
EncodedFiles encode_animation(const MorphAnimationView& view, ExportForm form, ExportContainer container, bool whole,
                              std::span<const std::string> caustics = {}, std::span<const std::string> sunbeams = {},
                              std::span<const std::string> whitewater = {});

/// Whether StreamedWriter writes `form` for a view quantised or not (its row's
/// `streamed`): morph (plain or quantised: a first pass finds the deltas' range), nodes
/// and pc2 (not quantised: KHR_mesh_quantization's range of positions spans every
/// frame). The files form writes a chunk of frames at a time by its own index.
bool streamed_form(ExportForm form, bool quantize) noexcept;

/// The files of a form streamed_form accepts, written into `folder` (it must exist) a
/// chunk of frames at a time: made with the range's first chunk (the file's static
/// parts and settings are its) and the range's frame count, then `append` every chunk
/// in order, the first one too, then `finish`, which returns each file's name (under
/// the folder) and bytes, in encode_animation's order. The bytes equal
/// encode_animation's of the whole range (`whole` as there; caustic maps aside). Used
/// by stream_animation and `wave convert`. Throws InputError for a form it does not
/// stream (naming it) and what AnimationFileWriter refuses; destroyed unfinished, it
/// removes what it wrote.
class StreamedWriter {
public:
    /// A writer of `frame_count` frames in `form` into `folder`, whose static parts are `first`'s.
    StreamedWriter(const std::string& folder, ExportForm form, ExportContainer container, bool whole,
                   const MorphAnimationView& first, std::size_t frame_count);
    ~StreamedWriter();  ///< removes what it wrote unless finished
    StreamedWriter(const StreamedWriter&) = delete;  ///< not copyable
    StreamedWriter& operator=(const StreamedWriter&) = delete;  ///< not copyable
    void append(const MorphAnimationView& chunk);  ///< the next frames, in order
    std::vector<std::pair<std::string, std::size_t>> finish();  ///< writes the files in place

private:
    struct State;
    std::unique_ptr<State> state_;
};

/// What the files form's frame index (index.json beside frames/) describes: one
/// animation and the run that computed its frames.
struct FrameIndexInfo {
    std::string scene;            ///< the scene's name ("scene" of the index)
    double fps = 24.0;            ///< frames per second
    double loop_period = 0.0;     ///< the loop's length (s)
    std::size_t loop_frames = 0;  ///< frames in the loop
    /// SHA-256 over what decides the frames' bytes (scene_run_key); empty when unknown
    /// (`wave convert` re-encodes frames it did not compute).
    std::string run_key;
};

/// SHA-256 of `bytes` in lowercase hex (OpenSSL's libcrypto): what the index records
/// per file, and what `sha256sum` prints for it. RuntimeError if OpenSSL fails.
std::string sha256_hex(std::string_view bytes);

/// A frame's index entry as compact JSON text: {"frame", "time" (key_time), "file" (its
/// first file), "content": [{"file", "bytes", "sha256"} per file of `frame_files`, a .gltf
/// frame's .bin after it], and with `positions` (x, y, z per vertex) "height_range_m":
/// [least z, greatest z]}. `frame_files` must not be empty.
std::string frame_entry_json(std::size_t frame, double fps, const EncodedFiles& frame_files, std::span<const float> positions = {});

/// Whether every file the entry (JSON text, as frame_entry_json writes it) lists is
/// under `root` (path_inside: no link out of it) with the size and SHA-256 it records;
/// false for an entry without "content" or text that is not such an entry.
bool frame_entry_intact(std::string_view entry_json, const std::string& root);

/// The frame index at `path` as JSON text (compact), or nothing when there is none or it
/// is not one of libwave's: not JSON, no "frames" array, or "scene", "fps",
/// "loop_frames", "run_key" of another type than libwave writes (an index is read back
/// after crashes and by other tools' hands: a wrong type is "not an index", never an
/// exception).
std::optional<std::string> read_files_form_index(const std::string& path);

/// index.json's bytes (JSON indented by 2, a newline at the end) of an animation
/// holding `entries` (frame_entry_json texts, frames in order). InputError for an entry
/// that is not JSON.
std::string frame_index_json(const FrameIndexInfo& info, std::span<const std::string> entries);

/// index.json's bytes for `entries` (frame_entry_json texts of this run, in order),
/// merged with the index a previous slice of the same animation left at `path`: the
/// entries by frame number, this run's replacing the old ones. Throws InputError when
/// that index belongs to another animation (scene name, fps, loop), or — unless
/// `whole_loop` (this run covers the whole loop and so replaces every entry) — to
/// another run key. An index that cannot be read (truncated, empty, fields of other
/// types) is refused too, unless `rebuild_unreadable` (`--resume`: the frames' own files
/// are checked instead), when it is rebuilt from `entries`. With no entries it checks
/// alone (before any frame is written).
std::string merged_frame_index(const std::string& path, const FrameIndexInfo& info, std::span<const std::string> entries,
                               bool whole_loop, bool rebuild_unreadable = false);

/// An exclusive flock(2) on a folder, released when destroyed or when the process dies
/// (a SIGKILLed run never leaves it held): the files form's partial folders, and the
/// output folder while slices merge their entries into one index.
class FolderLock {
public:
    FolderLock() = default;  ///< holds no lock
    /// Locks `folder` (it must exist). `wait` blocks until the lock is free; otherwise a
    /// held lock throws InputError with the message `busy`. RuntimeError when the
    /// folder cannot be opened or locked.
    FolderLock(const std::string& folder, bool wait, const std::string& busy);
    FolderLock(FolderLock&& o) noexcept;             ///< takes the other's lock
    FolderLock& operator=(FolderLock&& o) noexcept;  ///< releases its own, takes the other's
    FolderLock(const FolderLock&) = delete;             ///< not copyable
    FolderLock& operator=(const FolderLock&) = delete;  ///< not copyable
    ~FolderLock();                                      ///< releases the lock
    void release() noexcept;                            ///< releases the lock now (no-op when none is held)
    bool held() const noexcept;                         ///< whether it holds a lock

private:
    int fd_ = -1;
};

}  // namespace wave
