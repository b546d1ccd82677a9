/// \file
/// libwave — shade: per-vertex quantities computed per frame for renderers, written
/// into caller-owned arrays (no allocation per frame).
///
/// * Normals by accumulating area-weighted face normals (Jeschke et al. 2003, §5).
/// * Fresnel weights for a camera: reflect R and refract T = 1 − R (Ts'o & Barsky
///   §4.2.2–4.2.3, Tessendorf §4), exact or Ts'o's parabola.
/// * Foam from depth-limited breaking of the traced waves (H >= γh), released at each
///   crest passage and fading after it.
/// * Optional baked colour R · reflected + T · refracted (Ts'o eq. 4.1), the refracted
///   colour darkening with depth (Ts'o's future work, §5).
#pragma once

#include "libwave/io.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/surface.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>
#include <string>

namespace wave {

/// Unit vertex normals of a triangle mesh: each triangle adds its cross product (twice
/// its area times its unit normal) to its three vertices, then the sums are
/// normalised. A vertex of only degenerate triangles gets (0, 0, 1). Counter-clockwise
/// triangles give normals on the side they face. Writes into `normals` (3 floats per
/// vertex, same size as `positions`); allocates nothing.
void vertex_normals(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                    std::span<float> normals) noexcept;

/// The same normals, bit for bit, in parallel (TBB): the triangles' cross products
/// first (one float triple per triangle, allocated here), then each vertex gathers its
/// own in the order the serial version adds them, so the result does not depend on
/// the thread count either. Throws InputError when `adjacency` is for another size.
void vertex_normals(std::span<const float> positions, std::span<const std::uint32_t> triangles,
                    const VertexFaces& adjacency, std::span<float> normals);

/// How the Fresnel reflectivity R is computed.
enum class FresnelModel {
    exact,  ///< unpolarised Fresnel from cosines (Tessendorf eq. 44)
    tso,    ///< Ts'o–Barsky's parabola in the incidence angle (§4.2.3), air → water only
};

/// Where the viewer is (m, z up) and how reflectivity is computed.
struct FresnelOptions {
    std::array<double, 3> camera{50.0, -60.0, 40.0};  ///< the viewer (m, z up)
    FresnelModel model = FresnelModel::exact;          ///< how R is computed
    double water_index = kWaterRefractiveIndex;  ///< n of water (air is 1)
};

/// Reflect and refract weights per vertex: the incidence angle is between the unit
/// normal and the direction to the camera. A vertex whose normal faces away from the
/// camera (the underside of a plunging lip) is seen from the other side: |cos i| is
/// used, so R and T stay in [0, 1] and R + T = 1. Sizes: one float per vertex
/// (positions and normals 3 per vertex). Allocates nothing; throws InputError on
/// mismatched sizes.
void fresnel_weights(std::span<const float> positions, std::span<const float> normals, const FresnelOptions& options,
                     std::span<float> reflect, std::span<float> refract);

/// Depth-limited breaking foam (docs/shade.md).
struct FoamOptions {
    double breaker_index = kBreakerIndex;  ///< γ
    /// Foam starts where H reaches this share of γh (the tracer caps H at γh), full at γh.
    double onset = 0.9;
    /// Foam released as a crest passes decays as e^{−Δt / τ}, τ = fade_periods · T with T
    /// the passing wave's period: Froude similarity, a 1:400 model's foam lasts 1/20 of
    /// its prototype's, as its periods do (0.3 · 5 s = 1.5 s on the default bay).
    double fade_periods = 0.3;
    double fade_time = 0.0;  ///< s: τ itself when > 0 (then the same for every period)
};

/// The fade's time constant τ of FoamOptions in radians of the wave's phase (ω τ), for
/// a wave of angular frequency ω. Throws InputError unless fade_periods > 0 and
/// fade_time >= 0 (both finite).
double foam_fade_phase(const FoamOptions& options, double omega);

/// Foam in [0, 1] per vertex of Gonzato's ray strips at time t: a vertex whose wave
/// height H = 2A is at the breaking limit γh gets foam each time a crest passes it
/// (phase Φ_min + π of its profile), fading with the time since; sub-breaking
/// vertices get none, and the ramp from `onset`·γh to γh avoids a hard edge. The
/// foam rises (smoothstep) over the fifth of a period before the crest arrives — the
/// plunging lip runs ahead of it — so that it is continuous in time: the untangling
/// frees foamy vertices to overturn, and a step in the foam was a step in position.
/// Allocates nothing; throws InputError on mismatched sizes or bad options.
void breaking_foam(const RayStrips& strips, const GonzatoMotionPlan& motion, double t, const FoamOptions& options,
                   std::span<float> foam);

/// The same foam on Ts'o's height field: at each control node, every train's term
/// whose amplitude reaches the breaking ramp (onset · γh/2 … γh/2, h = `node_depth`)
/// releases foam at its crest (phase π/2 of sin) that fades with time; trains combine
/// by max, and the sampled vertices take the bilinear blend of their span's four
/// nodes. `node_foam` is scratch (control_count() floats); `foam` one float per
/// sampled vertex. Allocates nothing; throws InputError on mismatched sizes.
void height_field_foam(const HeightFieldPlan& plan, std::span<const float> node_depth, double t,
                       const FoamOptions& options, std::span<float> node_foam, std::span<float> foam);

/// Foam from folding (Tessendorf §3.7, docs/shade.md): the choppy map folds
/// where its minimum eigenvalue J₋ (eq. 32) drops below 0. Foam appears below
/// `threshold`, is full at threshold − softness, and fades over time without history:
/// foam(t) = max over τ of coverage(J₋(τ)) · fade(t − τ), τ being t itself and the
/// times of a fixed lattice j · lattice_step in (t − window, t]. J₋ at those times is
/// computable alone (Tessendorf's h̃(k, t) is closed-form in t), so any frame is.
struct FoldFoamOptions {
    /// J₋ at which foam starts. 0 is Tessendorf's strict criterion (only where the map
    /// folds); a linear sea with realistic slopes rarely folds at λ = 1, so the default
    /// starts foam where the surface is compressed to 40 % along ê₋, as DCC ocean tools
    /// bias their foam coverage.
    double threshold = 0.4;
    double softness = 0.3;       ///< full foam at J₋ = threshold − softness (> 0)
    double fade_time = 1.5;      ///< s: e-folding time of the fade
    double window = 4.5;         ///< s: foam older than this is gone (the fade reaches 0 there)
    double lattice_step = 0.25;  ///< s: spacing of the past times looked at (<= window, >= window / 256)
};

/// Most past times a frame's fold foam looks back at (window / lattice_step).
inline constexpr double kMaxFoldLatticeTimes = 256;

/// coverage(J₋) in [0, 1].
double fold_coverage(double j_minus, const FoldFoamOptions& options) noexcept;

/// fade(age) = (e^{−age/τ} − e^{−W/τ}) / (1 − e^{−W/τ}) for 0 <= age < W, else 0:
/// exponential, yet exactly 0 when a lattice time leaves the window (no pop).
double fold_fade(double age, const FoldFoamOptions& options) noexcept;

/// The lattice indices j with j · step in (t − window, t]; with a repeat time T the
/// step used is T / round(T / lattice_step) (so the lattice, and the foam, loops too),
/// returned in `step`.
std::vector<long long> fold_lattice(double t, const FoldFoamOptions& options, double repeat_time, double& step);

/// foam = max(foam, coverage(J₋) · fade(age)) per vertex: call with age 0 for the
/// current frame and with t − τ for each lattice time τ (in any order: max commutes).
/// Combines with breaking foam already in `foam` by max. Throws InputError on sizes.
void accumulate_fold_foam(std::span<const float> j_minus, double age, const FoldFoamOptions& options,
                          std::span<float> foam);

/// The foam-bearing vertices of one lattice time, kept sparse (most of a sea has no
/// foam): ascending vertex indices where J₋ < threshold, and their J₋.
struct FoldSample {
    std::vector<std::uint32_t> vertex;  ///< ascending vertex indices
    std::vector<float> j_minus;         ///< J₋ at each
};
/// The foam-bearing vertices of one lattice time's J₋.
FoldSample fold_sample(std::span<const float> j_minus, const FoldFoamOptions& options);

/// foam = max(foam, coverage · fade(age)) at the sample's vertices; the same result as
/// accumulate_fold_foam on the J₋ the sample was taken from. Throws InputError when the
/// sample's two arrays differ in length, its vertices do not ascend strictly, or a
/// vertex lies beyond `foam` (vertices before the one found may have been written).
void accumulate_fold_foam(const FoldSample& sample, double age, const FoldFoamOptions& options, std::span<float> foam);

/// A fold sample (not owned) and its age at the frame (s).
struct AgedFoldSample {
    const FoldSample* sample = nullptr;  ///< the sample (its owner keeps it alive)
    double age = 0.0;                    ///< s since its lattice time
};

/// A frame's whole window of samples in one parallel pass over blocks of vertices (a
/// pass per sample paid a fork and join each, a fifth of a 256² frame): the same bits
/// as one accumulate_fold_foam per sample, in any order. The same errors.
void accumulate_fold_foam(std::span<const AgedFoldSample> samples, const FoldFoamOptions& options, std::span<float> foam);

/// The J₋ threshold at which fold foam covers `coverage` of a surface (the share of
/// points with foam >= 0.1, the threshold `wave inspect` takes for a lip), the other
/// options kept: `past_j_minus[i]` holds J₋ at the points for the lattice time
/// (count − 1 − i) · step before now (the newest last), as the frames see it. On every
/// `stride`-th point: each point's own threshold (where its foam reaches 0.1), the
/// ⌈coverage · points⌉-th smallest of them selected, a hair above for rounding; the
/// foam grows with the threshold, so the result is the smallest one reaching the
/// coverage, in [−2, 1] (1 when even that falls short; −2 for coverage 0). Throws InputError on empty or unequal arrays or a
/// coverage outside [0, 1].
double fold_threshold_for_coverage(std::span<const std::vector<float>> past_j_minus, double step,
                                   const FoldFoamOptions& options, double coverage, std::size_t stride = 1);

/// Throws InputError naming the field for out-of-range options.
void validate_fold_foam(const FoldFoamOptions& options, const std::string& where = "fold foam");

/// Ts'o eq. 4.1 baked into linear RGB: colour = R · reflected + T · refracted, the
/// refracted colour fading towards `deep` as the depth grows (e^{−depth/attenuation}),
/// and foam mixed in as white. Depth per vertex in m (>= 0). Writes 3 floats per vertex.
struct WaterColours {
    std::array<float, 3> reflected{0.55f, 0.70f, 0.85f};  ///< sky
    std::array<float, 3> shallow{0.10f, 0.55f, 0.50f};    ///< refracted colour over a shallow bottom
    std::array<float, 3> deep{0.01f, 0.08f, 0.15f};       ///< refracted colour in deep water
    double attenuation = 3.0;                             ///< m
};
/// The baked colour (3 floats per vertex into `rgb`) from R, depth and foam per vertex.
void water_colour(std::span<const float> reflect, std::span<const float> depth, std::span<const float> foam,
                  const WaterColours& colours, std::span<float> rgb);

// ---------------------------------------------------------------------------------
// Preview renderer: the sunset ray caster (sunset-bumpmap-raytracer.txt)
// ---------------------------------------------------------------------------------

/// A sine wave of the paper's bump map: the normal tilts towards its direction by
/// atan(A sin((POI − R)·D)), with D = k·direction (rad/m) and R the reference point.
struct BumpWave {
    double amplitude = 0.1;                     ///< A: tangent of the largest tilt
    double direction_x = 1.0;  ///< unit direction (normalised on use)
    double direction_y = 0.0;  ///< unit direction (normalised on use)
    double wavelength = 10.0;                   ///< m
    double phase = 0.0;                         ///< rad
};

/// The preview ray caster's view, sun and colouring (render_preview; the scenes' /preview).
struct PreviewOptions {
    std::array<double, 3> camera{0.0, -50.0, 10.0};   ///< eye (m, z up)
    std::array<double, 3> look_at{0.0, 0.0, 0.0};     ///< where it looks (m)
    double vertical_fov_degrees = 40.0;               ///< vertical field of view
    std::size_t width = 960;                          ///< pixels
    std::size_t height = 540;                         ///< pixels
    double sun_azimuth_degrees = 90.0;    ///< from +x towards +y
    double sun_elevation_degrees = 10.0;  ///< above the horizon
    /// The paper's colouring: white where the reflected ray meets the sun (0°), dark
    /// blue from 90°; in between (1 − angle/90°)^glitter_exponent (1 = the paper's
    /// linear blend; the default 64 gives a sun glitter of a few degrees).
    double glitter_exponent = 64.0;
    /// Mix in Fresnel: colour = R·(sky + 30·glitter·white) + T·deep water — the sun
    /// is far brighter than the sky — (false = the paper's white/blue only).
    bool fresnel = true;
    std::vector<BumpWave> bump;  ///< analytic normals added at each hit (none = the mesh's)
    std::array<double, 2> bump_reference{0.0, 0.0};  ///< R of the paper
    /// Rays that miss the mesh but meet z = 0 below the horizon see flat water (with
    /// the bump normals): the paper's sea to the horizon.
    bool sea_to_horizon = true;
};

/// Ray-casts a triangle mesh (positions 3 per vertex, z up; Embree's BVH) with
/// per-vertex normals interpolated at the hit (or none: face normals), bump normals
/// evaluated analytically at every hit point, the sky (a gradient and the sun's disc)
/// where rays miss. Parallel over pixel rows; the image does not depend on the thread
/// count. An empty mesh renders the paper's flat sea. Throws InputError on sizes.
Image render_preview(std::span<const float> positions, std::span<const float> normals,
                     std::span<const std::uint32_t> triangles, const PreviewOptions& options);

/// Images side by side in a grid of `columns` (a contact sheet); all the same size.
Image contact_sheet(std::span<const Image> images, std::size_t columns);

}  // namespace wave
