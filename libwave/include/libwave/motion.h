/// \file
/// libwave — motion: where the water surface is at time t.
///
/// Gonzato & Le Saëc's vertical-section profile (§2.3–2.5, eq. 7): every surface point
/// turns on a tilted ellipse (Fournier–Reeves / Biesel) whose major axis is limited to
/// the disc of radius 1/k, plus three shaping terms — Stretch (the crest runs ahead),
/// Orientation and Displacement (gravity pulls the lip forward and down) — so that
/// waves plunge near the shore. The horizontal motion is along the local ray
/// direction: lips overhang, the surface is a mesh, not a height field.
///
/// Units: SI. Phase φ in rad; the profile's horizontal axis points along the ray, z up.
#pragma once

#include "libwave/physics.h"
#include "libwave/surface.h"

#include <array>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace wave {

/// The user parameters of Gonzato's profile. K_0, K_x, K_z are the paper's fixed
/// constants (§2.3: "0.1, 0.11 and 0.09 seem to be the best values"); the others are
/// the "intuitive parameters" the paper leaves to the user.
struct GonzatoProfileOptions {
    double k0 = 0.1;   ///< tilt decay: sin α = sin β e^{−K_0 h} (1/m)
    double kx = 0.11;  ///< S_x = 1 / (1 − e^{−K_x h}) (1/m)
    double kz = 0.09;  ///< S_z = S_x (1 − e^{−K_z h}) (1/m)
    /// St_max, the largest crest stretch, as a multiple of the local wave height
    /// H = 2R (the paper gives it in metres; relative to H, flat water stays flat
    /// and one value suits a whole scene).
    double stretch_max = 1.0;
    double stretch_depth_factor = 0.4;       ///< K_s: stretch fades as e^{−K_s h} (1/m)
    double displacement_depth_factor = 0.4;  ///< K_d: displacement fades as e^{−K_d h} (1/m)
    bool limit_to_disc = true;  ///< major semi-axis R S_x <= 1/k (§2.3; off = Fournier–Reeves)
    /// No point of the profile moves faster than this many times the local phase speed
    /// ω/k (≥ 0; 0 = eq. 7 unbounded): where the stretch and the displacement would
    /// carry a point faster, both are scaled down together, by the largest share that
    /// keeps every point within the bound. In the shallowest water the displacement's
    /// rise over the short rear face (a sixteenth of a wave) otherwise threw crest
    /// points forward at up to 1.8 × the phase speed on the default bay; a breaking
    /// crest's water moves at about the phase speed, a plunging jet at up to ~1.5 ×.
    double max_speed_ratio = 1.5;
    /// The surface packs no rest spacing along the ray tighter than this share of itself
    /// (0 ≤ p < 1; 0 = eq. 7's sections as drawn): the offset along the ray (the orbit's,
    /// the stretch's and the displacement's) is scaled by the largest share β ≤ 1 that
    /// keeps |d(x, z)/dx₀| ≥ p at every phase, where x = x₀ + β·forward and z = up; where
    /// the section climbs or falls at least that steeply, any β will do. Heights are not
    /// changed. Near breaking, eq. 7 curls a lip smaller than one spacing of a mesh of 16
    /// vertices to the wavelength and folds a quarter of the wavelength under it, packed
    /// to 0.07 of its rest spacing: on the default bay ~300 slivers (< 15°) a frame on the
    /// lips and vertices at 1.8 × the phase speed, for a curl no render showed. Squeezed
    /// to 0.6 along the ray, a triangle whose angles are all ≥ 25° keeps every angle
    /// above 15°. On a section that turns over, a point moves at (1 + packing) × the
    /// phase speed where the surface faces back, so a curl cannot keep both bounds
    /// (docs/motion.md); with p > 0 the section leans but does not fold.
    double min_packing = 0.6;
};

/// The per-point constants of eq. 7 (everything that does not depend on φ).
struct ProfileShape {
    double major = 0.0;     ///< semi-axis R S_x along the ray (limited to 1/k) (m)
    double minor = 0.0;     ///< semi-axis R S_z, vertical (m)
    double tilt_sin = 0.0;  ///< τ_β = sin α of the major axis' tilt
    double tilt_cos = 1.0;  ///< τ'_β = cos α
    double trough_phase = 0.0;                ///< Φ_min: the phase of the lowest point of the ellipse
    double stretch = 0.0;                     ///< St_max · H · e^{−K_s h} (m)
    double displacement = 0.0;                ///< A = H, times e^{−K_d h} (m)
    /// (stretch and displacement are scaled by the share that keeps max_speed_ratio)
    double bottom_angle = 0.0;                ///< β (rad), >= 0 (§2.4)
    double forward_scale = 1.0;  ///< the share of the offset along the ray kept (min_packing), in [0, 1]
};

/// Shape of the profile at a point: R the local orbit radius (half the wave height,
/// the tracer's amplitude), k the wavenumber, h the depth, `rise` = tan of the bottom
/// slope rising along the ray (negative slopes are clamped to 0 as §2.4 does). Dry
/// points (h <= 0) or R <= 0 give a point that does not move.
ProfileShape gonzato_shape(double R, double k, double depth, double rise, const GonzatoProfileOptions& options);

/// Offset of a surface point from its rest position by eq. 7, at phase φ (any real;
/// wrapped into [Φ_min − π, Φ_min + π)): `forward` along the ray, `up` vertically.
struct ProfileOffset {
    double forward = 0.0;  ///< along the ray (m)
    double up = 0.0;       ///< vertical (m)
};
/// The profile's offset of a point of shape `shape` at phase `phi` (rad).
ProfileOffset gonzato_offset(const ProfileShape& shape, double phi) noexcept;

/// Gonzato's profile on a ray-strip surface, planned once per scene: a shape per
/// vertex (flat arrays) so that a frame costs only the φ-dependent terms.
struct GonzatoMotionPlan {
    std::vector<ProfileShape> shape;  ///< per vertex
    std::vector<double> x;  ///< rest positions (m)
    std::vector<double> y;  ///< rest positions (m)
    std::vector<double> dir_x;  ///< unit ray directions: the profile's forward axis
    std::vector<double> dir_y;  ///< unit ray directions: the profile's forward axis
    std::vector<double> phase;         ///< Σ k Δs along the ray (rad)
    double omega = 0.0;  ///< ω of the train (rad/s): φ = phase − ωt

    std::size_t vertex_count() const noexcept { return x.size(); }  ///< vertices planned
};
/// The plan of Gonzato's profile on `strips`.
GonzatoMotionPlan plan_gonzato_motion(const RayStrips& strips, const GonzatoProfileOptions& options = {});

/// Vertex positions at time t (Φ = −ωt + Σ k Δs) into `positions` (3 floats per
/// vertex, z up). Parallel over vertices; each vertex is computed alone, so the result
/// does not depend on the thread count. Allocates nothing; throws InputError if
/// `positions` is not 3 · vertex_count() floats.
void evaluate_gonzato_motion(const GonzatoMotionPlan& plan, double t, std::span<float> positions);

// ---------------------------------------------------------------------------------
// Untangling: a moved mesh without folds
// ---------------------------------------------------------------------------------

/// A motion model moves vertices sideways (Gonzato's orbits, Jeschke's breakers, a
/// choppy wind sea). Where neighbouring vertices carry different phases or amplitudes —
/// crossing rays, a caustic, a steep shoal — their horizontal offsets can differ by
/// more than the edge between them and a triangle turns over in plan: a fold. Only a
/// breaking crest may overturn (its lip); everywhere else untangling scales the
/// horizontal offsets down, vertex by vertex, just as far as the triangles need.
struct UntangleOptions {
    /// A triangle keeps at least this share of its rest area in plan (0 < r < 1): it
    /// neither turns over nor collapses into a sliver.
    double min_area_ratio = 0.1;
    /// A triangle with a vertex this foamy is a breaking crest's lip: left to overturn
    /// (the same threshold as InspectOptions::lip_foam).
    float lip_foam = 0.1f;
    /// Whether the motion draws crests that turn over (Gonzato's eq. 7 as drawn, Jeschke's
    /// tube): their foamy triangles are lips, left to overturn and freed of the ramp.
    /// false for a motion whose sections never turn over (the bounded sections, the
    /// default): no triangle is a lip, and every one is untangled and ramped, so that
    /// the shear between neighbours whose rays differ turns none over either.
    bool lips_overturn = true;
    /// Vertices at rest on a side of the rest positions' bounding rectangle (the
    /// domain's border, for the water mesh) move only along that side, corners not
    /// sideways at all, and no vertex (a lip included) leaves the rectangle: the
    /// surface's sides stay straight on the border in every frame.
    bool pin_border = true;
    /// The domain's rectangle {x0, y0, x1, y1} (m) that holds every rest position, or
    /// all NaN (the default: the rest positions' bounding rectangle). A side of the
    /// bounding rectangle that lies inside it (by more than 1e-9 of its size) is not a
    /// border: its boundary edges are shore (hold_shore). The scenes give the water's
    /// domain, or the far field's outer rectangle when a skirt surrounds the surface: a
    /// straight shore that is a whole side of the water's rectangle is then held as a
    /// shore, not slid along as a side (one random seafloor kept triangles of 12.7° in
    /// the swash there).
    std::array<double, 4> border_rectangle{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
                                           std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    /// Vertices on the rest mesh's other boundary edges (off the rectangle: the water
    /// mesh's shoreline, an island's coast) keep their rest position in plan, and no
    /// triangle with such a vertex is a lip: the water's edge stays on the shore line in
    /// every frame, and the surface never turns over across it. (A crest carried
    /// landward by its breaker or Gonzato's orbit pushed the vertices next to the shore
    /// past it: 5–10 % of the triangles along every example's shore faced down in every
    /// frame, dark notches in the waterline.) Off for the traced strips themselves,
    /// whose boundary is where rays end.
    bool hold_shore = true;
    /// With hold_shore, the band of this many rings of triangles out from the shore
    /// (≤ 254): its vertices keep the ramp whatever their foam, and there the ramp damps
    /// a stretch beyond 1.15 × the rest length as well as a squeeze, since the held shore
    /// cannot follow its neighbours (no plunging lip at the waterline: the swash).
    std::uint8_t shore_band_rings = 3;
    /// The ramp, before the passes: every triangle compressed so hard that it could
    /// keep less than ramp_area_ratio (> min_area_ratio, < 1) of its rest area gives
    /// its vertices the factor that keeps that much by a bound continuous in the
    /// offsets (the strongest compression λ of the offsets' gradient: area ≥ (1 + sλ)²
    /// of rest), and every triangle stretched beyond 2.5 × its rest length (the largest
    /// eigenvalue λ': 1 + sλ' = 2.5; where rays from two sides of an island part, the
    /// water either side of the seam moved apart and stretched its edges 3.5 ×; a
    /// bounded Gonzato profile stretches at most 1 + 1.5 = 2.5 ×) does the same; from
    /// there the factor rises over the mesh by at most ramp_slope ×
    /// (edge length / the longer offset) per edge, so that neighbours' scaled offsets
    /// differ by about ramp_slope × their edge at most. A vertex's foam frees it of the
    /// ramp (smoothly from lip_foam to foam 1). The factors are then a continuous
    /// function of the offsets and the foam, and the passes seldom find work. 0: no
    /// ramp, the passes alone — which damp neighbours unevenly: a common 2 m sweep
    /// scaled by 1 here and 0.25 next door is a 1.5 m shear that folds again, and on
    /// the default bay vertices jumped by up to 3 m from one frame to the next.
    double ramp_slope = 0.2;
    double ramp_area_ratio = 0.3;  ///< see ramp_slope
    /// In the shore's band (shore_band_rings) the ramp keeps this share of a triangle's
    /// rest area instead (in [ramp_area_ratio, 1)): the held shore squeezes the swash
    /// next to it, and at 0.3 the bay and the island kept ~4 slivers of 13–15° a frame
    /// there; at 0.7, none.
    double shore_band_area_ratio = 0.7;
    /// The smallest angle the motion may leave a triangle (degrees, in 3D with the
    /// heights as moved; in [0, 60); 0: no bound). The ramp seeds where the motion thins
    /// a triangle below it while at rest offsets it would stay above: its vertices take
    /// the largest factor that keeps this angle (bisection). The ramp's spread shears
    /// in turn (neighbours' factors differ by up to ramp_slope × edge / offset), so up
    /// to three more rounds seed the triangles it thinned, and the passes enforce the
    /// bound with the area's. Heights are not changed: a triangle that the heights alone
    /// make thinner is left alone. Without it, the coast's wind sea on the swell
    /// squeezed triangles of 35° at rest to 12.5°.
    double min_angle_degrees = 16.0;
};

/// A breaking crest's foam before the crest arrives, as a share of the foam it leaves:
/// the plunging lip runs ahead of the crest, and its foam rises (smoothstep) from 0 a
/// fifth of a period before the crest to 1 at it. `phase_to_crest`: radians until the
/// crest (≥ 0). Both breakers' foam (breaking_foam, jeschke_foam) take it, so that the
/// foam — and the untangling, which frees foamy vertices — is continuous in time: a
/// step in the foam was a step of metres in position.
double lip_foam_rise(double phase_to_crest) noexcept;

/// Planned once per mesh: the rest positions in plan, the triangles' rest areas (twice
/// the signed area; a triangle facing down at rest is left alone) and the triangles
/// around each vertex.
struct UntanglePlan {
    std::vector<double> rest_x;  ///< rest positions in plan (m)
    std::vector<double> rest_y;  ///< rest positions in plan (m)
    std::vector<std::uint32_t> triangles;  ///< 3 per triangle
    std::vector<double> rest_area;  ///< per triangle: twice its signed area at rest (m²)
    std::vector<std::uint32_t> face_offsets;  ///< vertex v's triangles are faces[face_offsets[v] .. face_offsets[v + 1])
    std::vector<std::uint32_t> faces;         ///< triangle indices, grouped by vertex
    /// per vertex: with pin_border 1 on a side x = const, 2 on a side y = const; with
    /// hold_shore 4 on the shore (a boundary edge off the rectangle)
    std::vector<std::uint8_t> pinned;
    /// per vertex with hold_shore: rings of triangles to the shore (0 on it), 255 beyond
    /// shore_band_rings
    std::vector<std::uint8_t> shore_ring;
    /// the border rectangle: the rest positions' bounding rectangle, a side moved out to
    /// UntangleOptions::border_rectangle's where it lies inside it; lower corner (m)
    double x_min = 0.0;
    double y_min = 0.0;  ///< the border rectangle: lower corner (m)
    double x_max = 0.0;  ///< upper corner (m)
    double y_max = 0.0;  ///< upper corner (m)
    UntangleOptions options;  ///< as planned

    std::size_t vertex_count() const noexcept { return rest_x.size(); }  ///< vertices planned
};
/// Throws InputError when the sizes disagree, an index is out of range, border_rectangle
/// is neither four finite numbers holding every rest position nor all NaN,
/// min_area_ratio is outside (0, 1), ramp_area_ratio outside (min_area_ratio, 1),
/// ramp_slope negative or not finite, shore_band_rings above 254, or
/// min_angle_degrees outside [0, 60).
UntanglePlan plan_untangle(std::span<const double> rest_x, std::span<const double> rest_y,
                           std::span<const std::uint32_t> triangles, const UntangleOptions& options = {});

/// What untangle_motion did to a frame.
struct UntangleReport {
    std::size_t damped_vertices = 0;  ///< vertices whose horizontal offset was scaled down
    std::size_t passes = 0;           ///< passes over the triangles (1: nothing to do)
};

/// Scratch arrays of untangle_motion (offsets, factors, per-triangle factors), kept
/// by a caller that untangles frame after frame so that no frame allocates.
struct UntangleWorkspace {
    std::vector<double> dx;  ///< horizontal offsets per vertex (m)
    std::vector<double> dy;  ///< horizontal offsets per vertex (m)
    std::vector<double> factor;  ///< per vertex: the factor on its offset
    std::vector<double> s;       ///< per triangle: the factor that restores it
    std::vector<double> ramp;    ///< per vertex: the ramp's factor
    std::vector<std::pair<double, std::uint32_t>> queue;  ///< the ramp's heap (factor, vertex)
    /// per vertex: 1 when the last step (the ramp's last round, the last pass) lowered
    /// its factor, 2 when the ramp did in any round: only their triangles' angles are
    /// looked at again
    std::vector<std::uint8_t> lowered;
};

/// Whether the motion draws the triangle of vertices (a, b, c) overturned in the frame
/// being untangled (e.g. jeschke_draws_overturned); called from several threads.
using OverturnTest = std::function<bool(std::uint32_t a, std::uint32_t b, std::uint32_t c)>;

/// Untangles one frame in place: `positions` (3 floats per vertex, z up) are the moved
/// vertices; `foam` (one per vertex, or empty: no lips) marks breaking crests. Pinned
/// border vertices first lose their offset across their side (pin_border), shore
/// vertices all of it (hold_shore). Then the
/// ramp (UntangleOptions::ramp_slope) damps round every squeezed or thinned triangle.
/// Each pass finds, for every triangle below min_area_ratio of its rest area or below
/// min_angle_degrees, the largest factor s ∈ [0, 1] on its vertices' horizontal offsets
/// that restores it (a quadratic in s for the area, bisection for the angle), and
/// scales every vertex by the smallest factor of its triangles; a triangle still short
/// after eight passes takes s = 0 (its vertices back over their rest position, where
/// it faces up). The factors are continuous in the offsets, so a smooth motion stays
/// smooth. Heights are not changed. Afterwards every triangle that faced up at rest and
/// has no foamy vertex (or has a shore vertex) keeps ≥ min_area_ratio of its rest area
/// and, unless its heights alone make it thinner, min_angle_degrees.
/// Parallel over triangles, then over vertices, each a function of the previous pass:
/// the result does not depend on the thread count. Throws InputError on wrong sizes.
/// `workspace`: reused scratch (nullptr: allocated for this call). `may_overturn`
/// (empty: every lip's triangle may turn over): with it, a lip's triangle that would
/// keep less than 2 % of its rest area in plan is restored to that (it may stand
/// vertical, not turn over) unless the test says the motion draws it overturned.
UntangleReport untangle_motion(const UntanglePlan& plan, std::span<const float> foam, std::span<float> positions,
                               UntangleWorkspace* workspace = nullptr, const OverturnTest& may_overturn = {});

// ---------------------------------------------------------------------------------
// The far field: the sea beyond the domain, on the skirt (plan_sea_skirt)
// ---------------------------------------------------------------------------------

/// A periodic component of the surface's motion that continues beyond the domain: a
/// harmonic of a wave train or a Gerstner wave.
struct FarFieldWave {
    double omega = 0.0;        ///< the fundamental's ω (rad/s, > 0); the component's is harmonic · ω
    int harmonic = 1;          ///< 1 the fundamental, 2 its first overtone, … (bound: n ω with n k)
    double direction_x = 1.0;  ///< where it travels (any length > 0)
    double direction_y = 0.0;  ///< where it travels
    /// The fundamental's wavenumber (rad/m), or 0: from the dispersion relation at the
    /// depth under the nearest border point (the seafloor is continued unchanged outwards).
    double k = 0.0;
};

/// Options of plan_far_field.
struct FarFieldOptions {
    /// The border's motion that the waves do not explain (its mean set-up, crest-to-crest
    /// variation, overtones left out) fades out over this many wavelengths of the first
    /// wave beyond the border (> 0).
    double residual_wavelengths = 1.0;
};

/// The skirt's motion: per new vertex and component, complex amplitudes of (x, y, z)
/// carried out from its anchors and faded where the skirt cannot resolve them.
struct FarFieldPlan {
    std::size_t surface_vertices = 0;  ///< the surface's own vertices precede the skirt's in `positions`
    std::vector<double> omega;         ///< per component (rad/s)
    std::vector<double> rest_x;  ///< skirt vertices at rest (m)
    std::vector<double> rest_y;  ///< skirt vertices at rest (m)
    std::vector<float> anchor_weight;   ///< per skirt vertex: its first anchor's share (SeaSkirt::anchor_weight)
    std::vector<float> residual_weight; ///< per skirt vertex: 1 at the border → 0 beyond the residual band
    /// Per skirt vertex and component (vertex-major): Re and Im of x, y, z (6 floats);
    /// the displacement is Σ Re(C e^{−iωt}).
    std::vector<float> amplitude;
    /// The anchors (the surface's border vertices the skirt hangs on): their own fits
    /// (no fade, no travel), 6 floats per anchor and component (anchor-major).
    std::vector<float> anchor_amplitude;
    std::vector<float> anchor_rest;  ///< 3 per anchor: its rest position (m)
    std::vector<std::uint32_t> anchor_vertex;  ///< per anchor: its surface vertex
    std::vector<std::uint32_t> anchor_slot;  ///< per skirt anchor entry (2 per skirt vertex): its anchor number
    std::size_t vertex_count() const noexcept { return rest_x.size(); }  ///< skirt vertices
    std::size_t component_count() const noexcept { return omega.size(); }  ///< components
};

/// The share of a wave of `wavelength` (m) that skirt triangles with edges `edge` (m)
/// long carry: 1 up to a sixth of the wavelength, fading linearly to 0 at a third.
double far_field_share(double wavelength, double edge) noexcept;

/// The times (s) at which the scenes sample a surface for plan_far_field: 2 · components
/// + 5 of them, at the golden ratio's multiples of the loop (modulo the loop), so that
/// no two components alias whatever their frequencies. Throws InputError unless
/// loop_period > 0.
std::vector<double> far_field_sample_times(double loop_period, std::size_t components);

/// Fits each anchor's displacement (its position minus its rest position) in
/// `samples` — the surface at `times`, 3 floats per surface vertex per time — by least
/// squares (LAPACK dgelss) with a mean and a cosine and sine per component, then
/// carries each component out along the skirt vertex's outward direction N: C(d) =
/// C(border) e^{i n k (D̂·N) d} (crests keep their place along the border; waves
/// going in arrive from the open sea, waves going out leave), and fades it where the
/// skirt's edges (SeaSkirt::size) grow from a sixth to a third of its wavelength. The
/// anchors' residual (their displacement less the components: the mean set-up,
/// overtones left out, crest-to-crest variation) is blended out over
/// options.residual_wavelengths, so that the skirt meets the surface without a step. `rest_x`/`rest_y` are the surface's rest positions.
/// Needs at least 2 · components + 1 samples; throws InputError otherwise or on sizes
/// that disagree.
FarFieldPlan plan_far_field(const SeaSkirt& skirt, const ElevationGrid& seafloor, std::span<const FarFieldWave> waves,
                            std::span<const double> rest_x, std::span<const double> rest_y, std::span<const double> times,
                            std::span<const float> samples, const FarFieldOptions& options = {});

/// The skirt's positions at time t into `positions` after the surface's own (3 floats
/// per vertex, surface_vertices + vertex_count() vertices), which must hold the surface's
/// moved vertices already: each skirt vertex is its components' sum plus its anchors'
/// residual faded. Parallel; independent of the thread count. Allocates nothing but
/// `scratch` (resized to 3 floats per anchor).
void evaluate_far_field(const FarFieldPlan& plan, double t, std::span<float> positions, std::vector<float>& scratch);

/// The skirt's foam into `foam` after the surface's own (surface_vertices +
/// vertex_count() values; the surface's must be there already): each skirt vertex takes
/// its anchors' foam as it takes their residual motion, weighted along the border edge
/// and faded with residual_weight. A breaking crest's lip that reaches the border runs
/// on into the skirt there (moved by the residual), and its foam with it: the untangling
/// frees foamy vertices as lips (without it the skirt held back a border lip, and the
/// edges across stretched to 5.4 × their neighbours on the default bay). Throws
/// InputError on sizes that disagree.
void far_field_foam(const FarFieldPlan& plan, std::span<float> foam);

// ---------------------------------------------------------------------------------
// Jeschke, Birkholz & Schumann's procedural breaker (§3–4, table 1)
// ---------------------------------------------------------------------------------

/// The life cycle of a breaking wave (figure 3): round → breaking (the front dents,
/// the top falls over into a tube) → collapsing (flat again); dead afterwards.
enum class BreakerPhase {
    round,       ///< growing from still water to the breaking point
    breaking,    ///< the front dents and the top falls over into a tube
    collapsing,  ///< the tube falls and the crest flattens
    dead,        ///< flat: the breaker has ended
};

/// k1 … k7 of table 1 for one half of the wave (k[0] unused) at time t ∈ [0, 1] of a
/// phase. Entries that table 1 gives as constants are blended linearly over the phase
/// from the previous phase's final value ("the constants k_i are linearly blended over
/// the three phases"), so no k jumps between phases. The breaking phase's k5, printed
/// 3/t², is read as t^{3/2} (0 where the round phase ends, 1 as the collapsing phase
/// holds it; docs/motion.md). `dead` gives the collapsing phase's end (k7 = 0: flat).
struct BreakerConstants {
    std::array<double, 8> k{};  ///< k[1] … k[7] of table 1 (k[0] unused)
};
/// The constants of one half of the wave (`front` or back) at time `t` of `phase`.
BreakerConstants jeschke_constants(BreakerPhase phase, double t, bool front) noexcept;

/// A point of the paper's unit wave shape: y from 1 (back edge, s = 0) to 0 (front
/// edge, s = 1) — the wave runs towards −y —, z up (the round phase's crest is at
/// k7 / 4).
struct BreakerShapePoint {
    double y = 0.0;  ///< across the unit shape: 1 at the back edge, 0 at the front edge
    double z = 0.0;  ///< up
};

/// §4: s ∈ [0, 1] from the back to the front (the lip at s = 0.5), split into s1, s2
/// per half; z1 (cosine + exponential), φ (rotation about (½, 0)), y and z (scaling by
/// k7). `curl` scales the rotation k5 (1 = the paper's plunging tube; smaller for
/// spilling breakers). The edges s = 0 and s = 1 map to (1, 0) and (0, 0) in every phase.
BreakerShapePoint jeschke_shape(double s, const BreakerConstants& back, const BreakerConstants& front,
                                double curl = 1.0) noexcept;

/// The breaker's section at the mesh's scale (BreakerLip::outer). At real steepness the
/// paper's tube is knife-thin: its height is 5H/W ≈ 0.1–0.5 of its width, so the lip,
/// rotated in the unit shape, is thrown a quarter of a wavelength ahead at a fraction
/// of a mesh spacing thick, and the shape's labels crowd into it (k1: the lip is a
/// point where s has no speed). The outer section is what covers the tube: the upper
/// envelope of the paper's curve (the back, over the crest and the lip, down the lip's
/// front to the water ahead), relabelled so that a frozen section moving at c packs
/// every rest spacing to at least `min_packing` and moves no point faster than
/// `frozen_speed` × c (docs/motion.md, "The outer section").
struct BreakerSectionPoint {
    double x = 0.0;  ///< across the section in wavelengths: 0 at the back edge, 1 at the front edge
    double z = 0.0;  ///< up, in the unit shape's units (× the vertical scale 5H)
};

/// The outer sections tabulated once per plan: every life τ (0 … 1 breaking, 1 … 2
/// collapsing) × curl × height ratio 5H/W (log₂-spaced) × label s, each the section at
/// `labels` + 1 equally spaced labels. Empty = the paper's curve as drawn.
struct BreakerSections {
    std::size_t lives = 0;   ///< life samples over [0, 2]
    std::size_t curls = 0;   ///< curl samples from curl_first, curl_step apart
    std::size_t ratios = 0;  ///< ratio samples from 2^log2_ratio_first, log2_ratio_step apart
    std::size_t labels = 0;  ///< label intervals per section
    double curl_first = 0.0;         ///< the first curl sample
    double curl_step = 0.25;         ///< between curl samples
    double log2_ratio_first = -6.0;  ///< log₂ of the first ratio sample
    double log2_ratio_step = 0.5;    ///< between ratio samples (log₂)
    std::vector<float> x;  ///< BreakerSectionPoint::x, [life][curl][ratio][label]
    std::vector<float> z;  ///< BreakerSectionPoint::z, same layout
    bool empty() const noexcept { return x.empty(); }  ///< no table: the paper's curve
};

/// Bounds of the outer section (see BreakerSectionPoint).
struct BreakerSectionBounds {
    double min_packing = 0.6;   ///< least surface spacing over rest spacing of the frozen section
    double frozen_speed = 1.2;  ///< fastest point of the frozen section moving at c (× c); > 1
};

/// Tabulates the outer sections for curls in [curl_min, curl_max] (both in [0, 2]).
/// Throws InputError for curls out of range or bounds out of range (0 ≤ min_packing < 1,
/// frozen_speed in (1, 2]).
/// `overturn`: the curl sections instead (BreakerLip::curl, curl_section), at twice the labels.
BreakerSections plan_breaker_sections(double curl_min, double curl_max, const BreakerSectionBounds& bounds = {},
                                      bool overturn = false);

/// The overturning section (BreakerLip::curl) where the mesh resolves the tube: the
/// outer section with its front pressed to the breaker's own proportions — ahead of the
/// crest the envelope is drawn at the paper's figure's aspect (5H/W = 1) instead of the
/// wavelength's, setting in over the first half of the breaking phase, so that the face
/// is about as wide as it is high — and its wall — the lip hanging over the water ahead —
/// replaced by a tube's mouth: down a quarter of the wall from the lip's top, back under
/// the lip by half the wall's height × plunge, down to the wall's foot; plunge = (curl −
/// 0.6)/0.4 in [0, 1] (the plunging tube 1, collapsing and spilling crests 0: their
/// pressed envelope), opening as the wall stands from 55° to 75°. Relabelled as the outer
/// section is; on the lip's underside, which runs backwards, at the packing p (its points
/// then move at most (1 + p) c frozen). The pressed front's corners on the envelope's
/// columns pack a little tighter than min_packing (0.9 × it at the least, measured).
/// Throws InputError for bounds out of range, no labels, or a ratio not > 0.
void curl_section(double life, double curl, double ratio, const BreakerSectionBounds& bounds, std::size_t labels,
                  std::vector<BreakerSectionPoint>& out);

/// One outer section at life τ ∈ [0, 2] (breaking t, then 1 + collapsing t), straight
/// from the paper's curve (no table): `samples` points of the curve, its envelope on
/// `samples` columns. For tests and plots; plan_breaker_sections tabulates it.
void outer_section(double life, double curl, double ratio, const BreakerSectionBounds& bounds, std::size_t labels,
                   std::vector<BreakerSectionPoint>& out);

/// The tabulated section at life τ, curl, ratio and label s ∈ [0, 1] (multilinear;
/// outside the table's ranges the nearest sample).
BreakerSectionPoint breaker_section(const BreakerSections& table, double life, double curl, double ratio, double s) noexcept;

/// Where a crest is in its life when it stands at phase ψ (rad, Σ k Δs) of a ray that
/// breaks at phase `break_phase` and ends (aground) at `end_phase`: round over the
/// first `rise` radians (coming up from still water), breaking from the break point
/// for `breaking_length` radians, collapsing until the end, dead beyond. `start` is
/// where the life begins (0 on a ray's first surf zone; where the crest re-formed
/// behind a bar on a later one): the round phase rises from still water at `start`.
struct BreakerLife {
    BreakerPhase phase = BreakerPhase::round;  ///< the phase of the crest's life
    double t = 1.0;  ///< time parameter within the phase, 0 … 1
};
/// The life of a crest at phase `psi`, as BreakerLife describes.
BreakerLife jeschke_life(double psi, double rise, double break_phase, double breaking_length, double end_phase,
                         double start = 0.0) noexcept;

/// JeschkeBreakerOptions::lip: the section a breaking crest takes.
enum class BreakerLip {
    outer,  ///< the tube's outer surface at the mesh's scale (BreakerSections)
    tube,   ///< the paper's curve as drawn: a thin tube at real steepness
    curl,   ///< the overturning section, the lip hanging over the water ahead (curl_section)
};

/// The automatic parametrisation (the paper's "future work") and the options of the
/// model. The paper's y_end(x) (coastline and crest alignment) is the traced fronts
/// themselves — every point moves in its ray's phase coordinate, so crests bend with
/// refraction and align with the shore —, and t_break(x) is where each ray first
/// reaches depth-limited breaking H >= γh.
struct JeschkeBreakerOptions {
    double breaker_index = kBreakerIndex;  ///< γ (the scene takes it from trace)
    /// The breaking phase takes this share of each ray's surf zone (break point → end
    /// of the ray), at most `max_breaking_wavelengths`; collapsing takes the rest.
    double breaking_share = 0.4;
    double max_breaking_wavelengths = 1.0;  ///< upper bound of the breaking phase (local wavelengths)
    /// The surf zone (breaking and collapsing) spans at least this many local wavelengths
    /// of a crest's run, even where its ray ends sooner (a steep shore): the crest is still
    /// collapsing when it meets the shore rather than living its whole life in a few
    /// metres, where the shapes changed so fast that lip vertices moved at 13 × the phase
    /// speed. 0 = each ray's own end.
    double min_surf_zone_wavelengths = 0.5;
    /// Round phase: crests come up from still water over this many wavelengths from
    /// the offshore edge (the paper's birth); 0 = they enter fully grown.
    double rise_wavelengths = 1.0;
    /// Γ: a breaking crest stops breaking where its height falls below Γh (the wave
    /// field's stable index: its heights re-form behind a bar). A ray whose height falls
    /// so, and that reaches H >= γh again later, lives one life per surf zone: the crest
    /// collapses (over at least 1.5 local wavelengths from its break, a bore carried on
    /// into the trough: squeezed into a bar's half-wavelength surf zone, its vertices
    /// moved at 2.6 × the phase speed), re-forms from still water and breaks again. In (0, 2].
    double stable_index = 0.4;
    /// A re-formed stretch shorter than this (local wavelengths, between the end of one
    /// surf zone and the next break) is not a re-form: the crest breaks on through it.
    double min_reform_wavelengths = 0.5;
    /// §3.1: foam fades linearly over this time after a broken crest passed (s).
    double foam_fade_time = 6.0;
    /// Foam production ramps up over this share of the breaking phase (no hard line).
    double foam_onset = 0.25;
    /// Rotation (k5) per breaker type from the Iribarren number: the plunging tube of
    /// the paper is 1; spilling crests only tip forward.
    double curl_spilling = 0.3;    ///< rotation k5 of a spilling breaker (0 … 1)
    double curl_plunging = 1.0;    ///< of a plunging one (the paper's tube)
    double curl_collapsing = 0.6;  ///< of a collapsing one
    double curl_surging = 0.3;     ///< of a surging one
    /// Per-wave variation (§3: every wave its own r and y_end, so the set does not look
    /// cloned). The paper's r decides when in its run a wave reaches its break; here the
    /// traced phase is the run, so each crest breaks up to `wave_variation` local
    /// wavelengths earlier or later (at most a quarter of the collapse zone later, never
    /// before it is fully grown), and its y_end, where it dies, comes up to
    /// `wave_variation` of its collapse zone earlier. `varied_waves` crests differ (a
    /// pseudo-random draw from `variation_seed`), then repeat: the loop is that many
    /// swell periods. 0 or 1 wave = every crest alike, the loop one period.
    double wave_variation = 0.25;
    std::uint32_t varied_waves = 3;  ///< crests that differ before the draws repeat (the loop's periods)
    std::uint64_t variation_seed = 1;  ///< seed of the pseudo-random draws
    BreakerThresholds thresholds{};  ///< Iribarren thresholds of the breaker types
    /// The section a breaking crest takes: `outer` (the tube's outer surface at the
    /// mesh's scale, BreakerSections; clean triangles, ≤ 1.5 c) or `tube` (the paper's
    /// curve as drawn: a knife-thin tube at real steepness, slivers and up to 3.4 c).
    BreakerLip lip = BreakerLip::outer;
    BreakerSectionBounds section_bounds{};  ///< the outer section's bounds
};

/// One crest's break and end (rad along its ray) after the per-wave variation.
struct CrestPhases {
    double break_phase = 0.0;      ///< where the crest breaks (rad along its ray)
    double breaking_length = 0.0;  ///< how long it breaks (rad)
    double end_phase = 0.0;        ///< where it dies (rad)
};

/// The variation draw: `break_shift` and `end_shift` in [−1, 1] per varied wave.
struct CrestVariation {
    double break_shift = 0.0;  ///< in [−1, 1]: earlier or later break, × wave_variation wavelengths
    double end_shift = 0.0;    ///< in [−1, 1]: earlier end, × wave_variation of the collapse zone
};

/// Applies a crest's draw to a ray's phases (see JeschkeBreakerOptions::wave_variation):
/// the result keeps rise <= break, break + breaking_length < end, end <= the ray's end,
/// and at least a quarter of the collapse zone. Rays that never break are returned as they are.
CrestPhases vary_crest(double rise, double break_phase, double breaking_length, double end_phase,
                       const CrestVariation& draw, double variation) noexcept;

/// Where one traced ray breaks (for reports and tests).
struct RayBreak {
    std::uint32_t ray = 0;  ///< ray id
    std::uint32_t surf_zone = 0;  ///< 0: the ray's first break; n: its break after re-forming n times
    bool breaks = false;    ///< whether the ray reaches H >= γh
    double break_phase = 0.0;  ///< rad along the ray
    double end_phase = 0.0;    ///< rad along the ray (its end, aground or out)
    double x = 0.0;  ///< break point (m)
    double y = 0.0;  ///< break point (m)
    double depth = 0.0;        ///< h at the break point (m)
    double height = 0.0;       ///< H = 2A there (m)
    double iribarren = 0.0;    ///< ξ of the break (bottom slope over √(H/L∞))
    BreakerType type = BreakerType::spilling;  ///< the type ξ gives
};

/// The breakers on a ray-strip surface, planned once per scene (flat per-vertex arrays).
struct JeschkeMotionPlan {
    std::vector<double> x;  ///< rest positions (m)
    std::vector<double> y;  ///< rest positions (m)
    std::vector<double> dir_x;  ///< unit ray directions
    std::vector<double> dir_y;  ///< unit ray directions
    std::vector<double> phase;         ///< Σ k Δs along the ray (rad)
    /// Per vertex: the unit shape's width W = local wavelength 2π/k (m), its vertical
    /// scale 5H (the round crest k7·k2 = 1/5 is the traced height H = 2A), the mean
    /// level removed (min(k7, 4/5)/8 of the scale: the offshore swell is centred on still water),
    /// and its ray's break/end phases, rise and breaking length (rad) and curl.
    std::vector<float> width;       ///< W = 2π/k (m)
    std::vector<float> scale;       ///< 5H (m)
    std::vector<float> mean_level;  ///< removed from z (m)
    std::vector<float> break_phase;  ///< where its ray breaks (rad)
    std::vector<float> end_phase;    ///< where its crests die (rad): the ray's end, or min_surf_zone_wavelengths past the break; on a ray that re-forms, where this surf zone ends (life_start)
    std::vector<float> rise;                    ///< round-phase growth (rad)
    std::vector<float> breaking_length;         ///< breaking-phase length (rad)
    std::vector<float> curl;                    ///< k5 scale of the ray's breaker type
    std::vector<float> foam_yield;              ///< foam a passing broken crest leaves (0 … 1)
    /// Per vertex, or empty (all 0): where the life the vertex lives begins (rad): 0 on
    /// its ray's first surf zone; past a surf zone where the crest re-formed, the end of
    /// that surf zone (JeschkeBreakerOptions::stable_index).
    std::vector<float> life_start;
    std::vector<RayBreak> rays;  ///< per traced ray its first break, each followed by its breaks after re-forming (RayBreak::surf_zone)
    /// Per vertex, or empty (all 0): how far (rad) the crests at the vertex trail those at
    /// phase `phase`, whose life they live. A skirt vertex (continue_jeschke_breakers)
    /// lives its anchor's life, lag/ω later; a vertex of the surface has none.
    std::vector<double> lag;
    double omega = 0.0;  ///< ω of the train (rad/s)
    double foam_fade_time = 6.0;  ///< s (JeschkeBreakerOptions)
    double foam_onset = 0.25;     ///< share of the breaking phase
    /// Crest n (passing phase ψ at ωt = ψ + 2πn) takes draw n mod size; empty or
    /// `variation` 0 = every crest alike.
    std::vector<CrestVariation> crest_draws;
    double variation = 0.0;  ///< JeschkeBreakerOptions::wave_variation
    /// The outer sections breaking crests take (JeschkeBreakerOptions::lip); empty = the
    /// paper's curve as drawn.
    BreakerSections sections;
    /// BreakerLip::curl: the overturning sections (curl_section), taken by a vertex in
    /// the share `resolve` (0 … 1: where the mesh resolves the tube, resolve_jeschke_lips);
    /// empty = the outer sections everywhere.
    BreakerSections curl_sections;
    std::vector<float> resolve;  ///< per vertex; empty = 0
    /// Per vertex, or empty (all 0): where the mesh resolves a breaker's wall (its face,
    /// about H high: a spacing of twice the tube's), which jeschke_drawn_lips scales by
    /// (resolve_jeschke_lips).
    std::vector<float> wall_resolve;

    std::size_t vertex_count() const noexcept { return x.size(); }  ///< vertices planned
    /// Swell periods after which the breakers repeat.
    std::size_t loop_periods() const noexcept { return variation > 0.0 && !crest_draws.empty() ? crest_draws.size() : 1; }
};

/// Plans the breakers on the strips of a train of deep-water height H0 and
/// wavelength L0 (for the Iribarren number ξ0 = tan β / sqrt(H0/L0), with tan β the
/// mean bottom slope over one local wavelength seaward of the break). Throws
/// InputError naming the option when one is out of range.
JeschkeMotionPlan plan_jeschke_breakers(const RayStrips& strips, double deep_height, double deep_wavelength,
                                        const JeschkeBreakerOptions& options = {});

/// Crest n's phases at vertex v of a plan (the per-wave variation, draw n mod the
/// draws, applied where the vertex lies past the earliest break), as
/// evaluate_jeschke_breakers takes them. Precondition: v < plan.vertex_count().
CrestPhases jeschke_crest_phases(const JeschkeMotionPlan& plan, std::size_t v, long long n) noexcept;

/// Where in its life crest n is when it passes vertex v (at the vertex's own phase):
/// jeschke_life with the crest's phases and the vertex's rise and life start.
/// Precondition: v < plan.vertex_count().
BreakerLife jeschke_vertex_life(const JeschkeMotionPlan& plan, std::size_t v, long long n) noexcept;

/// The foam a crest leaves where it passes at `life`: none while round, rising over the
/// first `onset` of the breaking phase, full while breaking and collapsing.
double jeschke_foam_yield(const BreakerLife& life, double onset) noexcept;

/// The breakers at other points of the water — e.g. a camera grid: every per-vertex
/// field interpolated linearly from the strip triangle holding the point (the first
/// by index where strips overlap at caustics; a ray that never breaks wins over
/// interpolation), points off the strips at rest and without foam. Parallel;
/// independent of the thread count.
JeschkeMotionPlan resample_jeschke_breakers(const JeschkeMotionPlan& plan, std::span<const std::uint32_t> triangles,
                                            std::span<const double> x, std::span<const double> y);

/// Closes the gaps resampling leaves on a water surface (`triangles` over the plan's
/// vertices): where the rays diverge at the domain's sides, a vertex off the strips
/// takes the breakers of the nearest traced vertex u reached through the mesh, its
/// phase continued as a plane wave, Φ = Φ_u + k_u D_u · (x − x_u), if it lies within
/// `reach_wavelengths` of u's wavelength. Farther vertices (the shadows behind islands,
/// which a plane wave would wrongly fill) stay at rest. Nearest by distance to u
/// (Dijkstra over the mesh's edges, ties by index): deterministic. Returns how many
/// vertices it filled. Throws InputError on a bad index or reach <= 0.
std::size_t fill_jeschke_gaps(JeschkeMotionPlan& plan, std::span<const std::uint32_t> triangles,
                              double reach_wavelengths = 1.0);

/// Vertex positions at time t (3 floats per vertex, z up): each vertex lies in the
/// unit shape of the crest nearest to it in phase (crests pass a vertex when
/// ωt − Φ ≡ 0 mod 2π), at s = ½ − δ/2π, moved along its ray by (1 − y − s)·W and up by
/// scale·z − mean. The horizontal move fades with k7 as the wave dies (§4's scaling),
/// so a dead crest leaves the surface at rest. Parallel; independent of the thread count.
void evaluate_jeschke_breakers(const JeschkeMotionPlan& plan, double t, std::span<float> positions);

/// The breakers carried beyond the domain onto the far field's skirt
/// (continue_jeschke_breakers): the skirt vertices near a traced border, each living the
/// life of its nearest anchor (the surface's border vertex it hangs on) as the crest
/// reaches it, lag = k D·(p − p_anchor) later. The seafloor beyond the border is the
/// border's, continued along the outward normal (docs/far-field.md): where it does not
/// change along N, the wave there is the anchor's, delayed by that lag, exactly.
struct SkirtBreakers {
    JeschkeMotionPlan plan;              ///< the carrying skirt vertices (rest positions, anchors' fields, lags)
    std::vector<std::uint32_t> vertex;   ///< per planned vertex: its index among all vertices (surface's, then skirt's), ascending
    std::vector<float> weight;           ///< per planned vertex: the breakers' share against the far field's fit, in (0, 1]
    std::size_t vertex_count() const noexcept { return vertex.size(); }  ///< skirt vertices that carry breakers
};

/// The wet skirt vertices of `skirt` (over `seafloor` continued, depth_at > 0) within
/// band_wavelengths of the border, on traced anchors of `plan` (the surface's breakers:
/// plan.vertex_count() == skirt.surface_vertices), weighted 1 up to a wavelength (the
/// anchor's W) short of the band, smoothstep to 0 at its end. Empty for
/// band_wavelengths 0. Throws InputError on a plan of another surface or a band outside
/// [0, 100].
SkirtBreakers continue_jeschke_breakers(const JeschkeMotionPlan& plan, const SeaSkirt& skirt, const ElevationGrid& seafloor,
                                        double band_wavelengths);

/// `size` held at the border's own edge within band_wavelengths − 1 of the border
/// (where the breakers carry on whole) where the breakers break and water lies beyond
/// (the plan's vertices on its bounding rectangle whose phase lies between a quarter
/// wavelength, and the crests' variation, before their break and their crests' end,
/// with water a centimetre outside them), the wavelength being the nearest border
/// vertex's W; beyond, `size` at the distance to the nearest held band (the fade's
/// wavelength grows as the far field's skirt does), so the sizes grow from the band's
/// sides along the border as from its far end. Elsewhere `size` itself. The band is held
/// over the stretch of the side nearest to each such border vertex.
SkirtSize breaker_skirt_size(SkirtSize size, const JeschkeMotionPlan& plan, const ElevationGrid& seafloor, double band_wavelengths);

/// Per vertex of a plan resampled on a mesh (`triangles`, `boundary` its boundary
/// flags), where the mesh resolves the breaker's section: plan.resolve (with
/// BreakerLip::curl: the share of the overturning section a vertex takes; else all 0)
/// is 1 where the mesh's spacing (the mean edge at the vertex) is at most `fraction` ×
/// H, 0 at twice that, smoothstep between; plan.wall_resolve (which scales
/// jeschke_drawn_lips) the same from 2 × to 4 × `fraction` × H, since a wall about H
/// high needs half the tube's resolution. Both are 0 on the boundary, rising over a
/// wavelength (the far field's skirt and the shore carry the outer section).
void resolve_jeschke_lips(JeschkeMotionPlan& plan, std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> boundary,
                          double fraction);

/// Per vertex at time t, in [0, 1]: how far the surface there is the breaker's own
/// section, drawn where the mesh resolves it — a breaking or collapsing crest's face,
/// lip and back, rising with the section's slope from 0 on flat water to 1 at 8° (a
/// round crest stays below ~6°, so the weight is continuous in time), 1 where the
/// section runs backwards, 0 in the round phase — times the share `wall_resolve` (0
/// everywhere when it is empty). The untangling takes it in place of the foam to tell
/// the walls and lips the motion means from folds (UntangleOptions::lip_foam), so that
/// a resolved breaker keeps its vertical face and its overturning lip. Throws
/// InputError when `weight` does not hold one value per vertex.
void jeschke_drawn_lips(const JeschkeMotionPlan& plan, double t, std::span<float> weight);

/// Whether the breaker draws the triangle (a, b, c) overturned at time t: the section
/// of one of its vertices, on that vertex's crest and life, runs backwards somewhere
/// between the triangle's labels (the lip's underside, which the mesh samples only at
/// its vertices: a triangle across the lip faces down though no vertex lies on the
/// underside). A triangle facing down that this does not hold is a fold. false for an
/// index out of range, a plan without sections, or vertices of different crests.
bool jeschke_draws_overturned(const JeschkeMotionPlan& plan, double t, std::uint32_t a, std::uint32_t b, std::uint32_t c) noexcept;

/// The water mesh over the surf zone (docs/inspect.md, "The water mesh"): a breaker's
/// face and lip need a mesh finer than the tube, about H/4, against W/16 offshore.
struct SurfZoneMesh {
    double height_fraction = 0.25;  ///< edge = this × the local height H where crests break; 0 = off
    double min_edge = 0.2;          ///< never finer (m)
    double grade = 0.3;             ///< the edge grows by this per metre away from the band
    /// The band: from this many wavelengths (plus the crests' variation) before the
    /// break to as far past the end of the breaking phase (at most the crests' end).
    double margin_wavelengths = 0.0;
};

/// Whether vertex v's crests break (or are about to) there: its phase within the band
/// of SurfZoneMesh::margin_wavelengths.
bool in_breaking_band(const JeschkeMotionPlan& plan, std::size_t v, double margin_wavelengths) noexcept;

/// `size` graded down to SurfZoneMesh::height_fraction × H over the band where the
/// plan's crests break (the plan on the traced strips, whose vertices mark the band),
/// and back out by `grade` per metre: min(size, band). `size` itself when the fraction
/// is 0 or no crest breaks. Deterministic (a raster over the seafloor's rectangle).
EdgeSize surf_zone_edge_size(EdgeSize size, const JeschkeMotionPlan& plan, const ElevationGrid& seafloor, const SurfZoneMesh& options = {});

/// The skirt's breakers at time t blended into `positions` (all vertices, 3 floats
/// each, the far field's skirt already evaluated): p = w · breaker + (1 − w) · p.
void evaluate_skirt_breakers(const SkirtBreakers& breakers, double t, std::span<float> positions, std::vector<float>& scratch);

/// Their foam (jeschke_foam) times the weight, the largest with what `foam` (all
/// vertices) holds.
void skirt_breaker_foam(const SkirtBreakers& breakers, double t, std::span<float> foam, std::vector<float>& scratch);

/// §3.1 foam for any time without history: the time since the last crest passed
/// each vertex, whether that crest had broken there (its life at the vertex), and a
/// linear fade; the largest value over the recent waves, and the next crest's lip
/// rising before it arrives (lip_foam_rise). In [0, 1].
void jeschke_foam(const JeschkeMotionPlan& plan, double t, std::span<float> foam);

// ---------------------------------------------------------------------------------
// Tessendorf's FFT ocean (§3.3–3.7) and Gerstner waves (§3.1)
// ---------------------------------------------------------------------------------

/// The wind-wave spectra DCC ocean tools offer.
enum class OceanSpectrumModel {
    phillips,           ///< eq. 23 with the small-wave cutoff of eq. 24
    pierson_moskowitz,  ///< fully developed sea (physics.h)
    jonswap,            ///< fetch-limited sea with peak enhancement
    tma,                ///< JONSWAP × Kitaigorodskii's depth function (finite depth)
};

/// A directional wavenumber spectrum F(k) (m⁴: ∫ F d²k is the elevation variance).
/// Phillips is eq. 23 as printed, F = A e^{−1/(kL)²} k⁻⁴ D(θ) e^{−k²ℓ²}, with
/// L = V²/g. The frequency spectra become F = S(ω(k)) (dω/dk) / k · D(θ)/∫D, so their
/// variance is the spectrum's. D(θ) = |k̂·ŵ|^p, times `against_wind` where k̂·ŵ < 0.
struct OceanSpectrum {
    OceanSpectrumModel model = OceanSpectrumModel::phillips;  ///< which spectrum
    /// V (m/s): Phillips' V, U at 19.5 m for Pierson–Moskowitz, U10 for JONSWAP/TMA.
    double wind_speed = 31.0;
    std::array<double, 2> wind_direction{1.0, 0.0};  ///< ŵ (normalised on use)
    double directional_exponent = 2.0;  ///< p of |k̂·ŵ|^p (eq. 23: 2; figure 8: 6)
    /// Factor on waves running against the wind (k̂·ŵ < 0): 1 is the paper's symmetric
    /// |k̂·ŵ|^p (half the energy runs upwind), 0 a sea that runs with the wind only.
    double against_wind = 1.0;
    /// A of eq. 23 for the continuous spectrum (dimensionless). The default α/(2π),
    /// α = 8.1e-3, gives Pierson–Moskowitz's high-frequency tail α g² ω⁻⁵ with p = 2.
    double phillips_constant = 8.1e-3 / (2.0 * std::numbers::pi);
    double small_wave_cutoff = 0.0;  ///< ℓ of eq. 24 (m); 0 = none (applied to every model)
    double fetch = 100e3;            ///< JONSWAP/TMA fetch (m)
    double peak_enhancement = 3.3;   ///< JONSWAP/TMA γ
    /// Water depth (m): finite-depth dispersion (eq. 15) and the TMA depth function;
    /// +inf = deep water (eq. 14).
    double depth = std::numeric_limits<double>::infinity();
    double capillary_length = 0.0;   ///< L of eq. 16 (m); 0 = gravity waves only
};

/// F(k) at the wavevector (kx, ky) (m⁴); 0 at k = 0. Throws nothing: call
/// validate_ocean_spectrum first.
double ocean_spectrum_density(const OceanSpectrum& spectrum, double kx, double ky) noexcept;

/// ∫ F d²k over all wavevectors (m²), by quadrature in log k (relative error < 1e-6);
/// 4 sqrt of it is the significant wave height H_s.
double ocean_spectrum_variance(const OceanSpectrum& spectrum);

/// The spectrum's peak angular frequency ω_p (rad/s): PM 0.877 g/U, JONSWAP/TMA's ω_p,
/// Phillips' maximum of F k at k = sqrt(2/3)/L (before the cutoff).
double ocean_peak_omega(const OceanSpectrum& spectrum) noexcept;

/// A tileable ocean patch (§3.3): N×N wave components on a patch of L×L metres.
struct OceanOptions {
    std::size_t resolution = 256;  ///< N: a power of two, 16 … 4096
    double size = 1000.0;          ///< L (m)
    OceanSpectrum spectrum{};  ///< the wind sea's spectrum
    /// λ of eq. 29 (>= 0). The surface point moves to x − λD: with eq. 29's D this is
    /// Gerstner's eq. 9 for one wave (crests sharpen); the printed x + λD would fold
    /// the troughs instead (see docs/motion.md).
    double choppiness = 1.0;
    /// T of eqs. 17–18 (s): frequencies quantised so that every frame repeats after T;
    /// 0 = the exact dispersion relation (no loop).
    double repeat_time = 0.0;
    std::uint64_t seed = 1;  ///< h̃0 of eq. 25 is a pure function of (seed, wave index)
};

/// Throws InputError naming the field when an option is out of range (size not a
/// power of two, wind speed <= 0, a cutoff at least the patch size, …); `where` is
/// prefixed to the message (e.g. the scene's JSON pointer).
void validate_ocean_options(const OceanOptions& options, const std::string& where = "ocean");

/// The static half of the FFT ocean: h̃0 (eq. 25) and ω for the N × (N/2 + 1)
/// non-negative-kx half of the wavevector lattice, as FFTW's real transforms read it.
/// Row j is k_y = 2π (j < N/2 ? j : j − N) / L, column i is k_x = 2π i / L.
struct OceanPlan {
    std::size_t n = 0;  ///< N
    double size = 0.0;         ///< L (m)
    double choppiness = 0.0;   ///< λ
    double repeat_time = 0.0;  ///< T (s; 0 = no loop)
    double peak_omega = 0.0;   ///< of the spectrum (for depth factors)
    double expected_variance = 0.0;  ///< Σ F Δk² over the lattice: the mean of the sample variance of h
    std::vector<std::complex<float>> h0;        ///< h̃0(k)
    std::vector<std::complex<float>> h0_minus;  ///< conj(h̃0(−k))
    std::vector<float> kx;  ///< per column (rad/m)
    std::vector<float> ky;  ///< per row (rad/m)
    std::vector<float> inv_k;  ///< 1/|k| per element (0 at k = 0), as float arithmetic gives it
    std::vector<double> omega;                  ///< ω(k), or ω̄(k) when quantised
    std::vector<std::int32_t> omega_steps;      ///< ω̄ / ω0 when quantised (else empty)

    std::size_t half() const noexcept { return n / 2 + 1; }  ///< columns of the half lattice
    double spacing() const noexcept { return size / static_cast<double>(n); }  ///< lattice spacing L/N (m)
};

/// Draws the amplitudes (eq. 25: h̃0 = (ξr + iξi) sqrt(F Δk² / 2)) and the frequencies.
/// k = 0 and the Nyquist row and column are 0 (a real field's Nyquist mode has no
/// direction to travel in). Throws InputError for bad options.
OceanPlan plan_ocean(const OceanOptions& options);

/// One real field of the N×N lattice, row-major (j, i): value q is data[q · stride].
/// evaluate_ocean's fields come in pairs from one complex transform each, interleaved
/// (stride 2).
struct OceanField {
    const float* data = nullptr;  ///< the value at lattice point 0
    std::size_t stride = 1;       ///< floats from one value to the next
    std::size_t count = 0;        ///< N²
    float operator[](std::size_t q) const noexcept { return data[q * stride]; }  ///< value q (q < count)
    std::size_t size() const noexcept { return count; }                          ///< N²
    std::vector<float> values() const;  ///< the N² values, contiguous (a copy)
};

/// One frame of the ocean on the N×N lattice x = (i L/N, j L/N), row-major (j, i):
/// height h (eq. 19), slope ∇h (eq. 20), displacement D (eq. 29) and its derivatives
/// ∂Dx/∂x, ∂Dy/∂y, ∂Dx/∂y (for the Jacobian, eq. 30). Views into an OceanWorkspace,
/// valid until its next evaluation. Each pair that shares a transform is interleaved
/// (stride 2, the second one float after the first): (∂Dx/∂x, ∂Dy/∂y), (∂Dx/∂y, h),
/// (∂h/∂x, ∂h/∂y), (Dx, Dy) — the layout ocean_patch_frame and ocean_jacobian_field read.
struct OceanFields {
    std::size_t n = 0;  ///< N
    OceanField height;   ///< h (m)
    OceanField slope_x;  ///< ∂h/∂x
    OceanField slope_y;  ///< ∂h/∂y
    OceanField disp_x;   ///< Dx (m)
    OceanField disp_y;   ///< Dy (m)
    OceanField disp_xx;  ///< ∂Dx/∂x
    OceanField disp_yy;  ///< ∂Dy/∂y
    OceanField disp_xy;  ///< ∂Dx/∂y
};

/// FFTW plans (made once, from the wisdom libwave ships — FFTW_ESTIMATE where FFTW
/// cannot read it — so the plan, and so every bit of the result, is the same on every
/// run; docs/motion.md) and aligned buffers for one OceanPlan's size. Not thread-safe:
/// one workspace per thread.
class OceanWorkspace {
public:
    explicit OceanWorkspace(std::size_t n);  ///< plans and buffers for N = n
    ~OceanWorkspace();  ///< frees the plans and buffers
    OceanWorkspace(OceanWorkspace&&) noexcept;  ///< moves the plans
    OceanWorkspace& operator=(OceanWorkspace&&) noexcept;  ///< moves the plans
    OceanWorkspace(const OceanWorkspace&) = delete;  ///< not copyable: one per thread
    OceanWorkspace& operator=(const OceanWorkspace&) = delete;  ///< not copyable
    struct Impl;
    Impl& impl() noexcept { return *impl_; }  ///< the FFTW plans and buffers (ocean_fft.cpp)

private:
    std::unique_ptr<Impl> impl_;
};

/// h̃(k, t) = h̃0(k) e^{−iωt} + conj(h̃0(−k)) e^{iωt} (eq. 26 with t → −t, so that h̃0(k)
/// is the wave running along +k), then four inverse complex FFTs, each the transform of
/// two real fields at once (the spectrum A + iB over the whole lattice gives a + ib; in
/// parallel, each one sequential: the result does not depend on the thread count). With
/// a repeat time, t is taken modulo T first, so frame T·fps is bit-identical to frame 0.
OceanFields evaluate_ocean(const OceanPlan& plan, double t, OceanWorkspace& workspace);

/// Only what the Jacobian needs (two transforms instead of four): J₋ (eq. 32) of the
/// map x → x − λD on the lattice, into `j_minus` (N² floats).
void evaluate_ocean_jacobian(const OceanPlan& plan, double t, OceanWorkspace& workspace, std::span<float> j_minus);

/// The Jacobian of x → x − λD at one lattice point: J (eq. 30), its eigenvalues
/// J₋ <= J₊ (eq. 32) and the unit eigenvector ê₋ (eqs. 33–34), the direction of folding.
struct OceanJacobian {
    double j = 1.0;        ///< J (eq. 30)
    double j_minus = 1.0;  ///< J₋ (eq. 32): < 0 where the surface folds
    double j_plus = 1.0;   ///< J₊
    std::array<double, 2> e_minus{1.0, 0.0};  ///< ê₋: the direction of folding
};
/// The Jacobian from the second derivatives of the displacement (dxx, dyy, dxy) and the choppiness λ.
OceanJacobian ocean_jacobian(double dxx, double dyy, double dxy, double choppiness) noexcept;

/// The open-ocean patch surface for one frame: (N+1)² vertices, row-major, the last
/// row and column repeating the first one patch further (so patches tile without a
/// seam). Positions (x − λDx, y − λDy, h), normals exact from the FFT slopes and
/// displacement derivatives (the cross product of the two tangents of the displaced
/// surface: (−∂h/∂x, −∂h/∂y, 1) without chop), J₋ per vertex. Parallel over rows.
/// Reads the fields as evaluate_ocean lays them out (its pairs interleaved; InputError
/// otherwise), as do ocean_patch_rows and ocean_jacobian_field.
void ocean_patch_frame(const OceanPlan& plan, const OceanFields& fields, std::span<float> positions,
                       std::span<float> normals, std::span<float> j_minus);

/// ocean_patch_frame's rows [first_row, first_row + rows) of the (N+1)² lattice alone
/// (the same bits), into spans that hold just those rows: 3 (N+1) floats a row for
/// positions and normals, N+1 for j_minus (or empty). Sequential: for a caller that
/// passes over the patch in blocks of rows and works on each block while it is in
/// cache. Throws InputError on sizes or rows beyond the lattice.
void ocean_patch_rows(const OceanPlan& plan, const OceanFields& fields, std::size_t first_row, std::size_t rows,
                      std::span<float> positions, std::span<float> normals, std::span<float> j_minus);

/// Samples the (periodic) field at arbitrary rest positions (x, y) by bicubic
/// Catmull–Rom interpolation and adds `scale[v]` × (−λDx, −λDy, h) to `positions`
/// (3 per vertex; an empty `scale` is 1 everywhere). Parallel over vertices.
void add_ocean_samples(const OceanPlan& plan, const OceanFields& fields, std::span<const double> x,
                       std::span<const double> y, std::span<const float> scale, std::span<float> positions);

/// J₋ on the lattice of one frame (eq. 32), N² floats.
void ocean_jacobian_field(const OceanPlan& plan, const OceanFields& fields, std::span<float> j_minus);

/// Samples a lattice field (N², periodic) at (x, y) by bicubic Catmull–Rom
/// interpolation; with `scale`, maps J₋ to 1 + s (J₋ − 1) as add_ocean_samples does.
void sample_ocean_field(const OceanPlan& plan, std::span<const float> field, std::span<const double> x,
                        std::span<const double> y, std::span<const float> scale, std::span<float> out);

/// How much of a wind sea of peak frequency ω_p survives in depth h, as an amplitude
/// factor: sqrt of Kitaigorodskii's depth function (the finite-depth dispersion's
/// ratio of energies, physics.h). 1 in deep water, → 0 at the shore.
double wind_sea_depth_factor(double peak_omega, double depth) noexcept;

/// One Gerstner wave (eqs. 9–10): a point at rest x0 moves to
/// x0 − k̂ A sin(k·x0 − ωt + φ), height A cos(k·x0 − ωt + φ).
struct GerstnerWave {
    double kx = 0.0;  ///< wavevector (rad/m), along the direction of travel
    double ky = 0.0;  ///< wavevector (rad/m), along the direction of travel
    double amplitude = 0.0;     ///< A (m)
    double omega = 0.0;         ///< ω (rad/s), from dispersion_omega (quantised for loops)
    double phase = 0.0;         ///< φ (rad)
};

/// Σ k_i A_i: below 1 the sum of eqs. 12–13 cannot loop over itself; at or above 1 the
/// crests may form loops ("the insides of the wave surface are outside", §3.1).
double gerstner_steepness(std::span<const GerstnerWave> waves) noexcept;

/// Adds the Gerstner sum (eqs. 12–13) at time t for rest positions (x, y) to
/// `positions` (3 per vertex). `depth` (optional, one per vertex) scales each wave by
/// wind_sea_depth_factor(ω, h). Parallel over vertices.
void add_gerstner_waves(std::span<const GerstnerWave> waves, std::span<const double> x, std::span<const double> y,
                        std::span<const float> depth, double t, std::span<float> positions);

}  // namespace wave
