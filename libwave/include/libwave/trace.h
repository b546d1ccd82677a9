/// \file
/// libwave — trace: wave trains decomposed into rays (wave orthogonals) and traced
/// over the seafloor, refracted by Snell's law at exact isobath crossings
/// (Ts'o & Barsky 1987, §3.1.3, §3.2).
///
/// Units: SI (m, s, rad). Depth positive down. Directions are unit 2-vectors in the
/// horizontal plane. Amplitudes are half wave heights (m).
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/isobath.h"
#include "libwave/physics.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace wave {

/// A train of regular waves arriving from the open sea.
struct WaveTrain {
    double period = 8.0;       ///< T (s), > 0
    double amplitude = 0.5;    ///< deep-water amplitude A∞ (m), > 0
    double direction_x = 0.0;  ///< direction of travel (need not be unit; not zero)
    double direction_y = 1.0;  ///< direction of travel
};

/// Options of trace_rays, with their defaults.
struct TraceOptions {
    /// Distance between neighbouring rays where they enter the domain (m), > 0.
    double ray_spacing = 1.0;
    /// Guard rails: more rays than this (over all trains) or more crossings on one ray
    /// raise LimitError naming the option.
    std::size_t max_rays = 1'000'000;      ///< rays over all trains
    std::size_t max_crossings = 100'000;  ///< isobath crossings on one ray
    /// Breaker index γ: at caustics the amplitude is capped at γ h / 2 (H <= γ h).
    double breaker_index = kBreakerIndex;
    /// Le Méhauté's rule of thumb (quoted by Ts'o §3.1.3): refraction alone is doubtful
    /// where K_r leaves [1/doubt_factor, doubt_factor]; such points are flagged.
    double doubt_factor = 2.0;
    DispersionOptions dispersion{};  ///< how k(ω, h) is solved
};

/// What happened at a ray point.
enum class RayEvent : std::uint8_t {
    start,        ///< where the ray enters the domain
    refracted,    ///< crossed an isobath and turned by Snell's law
    reflected,    ///< sin r > 1 at an isobath: total reflection (Ts'o's future work)
    aground,      ///< reached the shoreline (h = 0): the ray ends
    left_domain,  ///< left the seafloor's rectangle: the ray ends
};
/// The event's name ("start", "refracted", "reflected", "aground", "left_domain").
const char* to_string(RayEvent e) noexcept;

/// Bit flags on a ray point.
enum RayPointFlag : std::uint8_t {
    kAmplitudeCapped = 1,  ///< A∞ K_s K_r exceeded γ h / 2 (breaking, or a caustic where rays converge): capped
    kRefractionDoubtful = 2,  ///< K_r outside [1/doubt_factor, doubt_factor]
};

/// Traced rays as a structure of arrays. Ray r owns points offsets[r] .. offsets[r+1]−1
/// in order along the ray. A point's k, celerity, … describe the wave *after* it,
/// i.e. on the straight leg that starts there (Ts'o recalculates at every crossing).
struct RaySet {
    std::vector<std::size_t> offsets{0};  ///< size rays + 1
    std::vector<std::uint32_t> train;     ///< wave train of each ray
    std::vector<double> spacing_start;    ///< b0 of each ray: its tube's width where the train is a plane wave (m)

    std::vector<double> x;  ///< point (m)
    std::vector<double> y;  ///< point (m)
    std::vector<double> dir_x;  ///< unit direction of the leg after the point
    std::vector<double> dir_y;  ///< unit direction of the leg after the point
    std::vector<double> arc_length;       ///< distance travelled from the start (m)
    std::vector<double> phase;            ///< Σ k Δs plus the phase on entry (rad; 0 at the up-wave corner)
    std::vector<double> depth;            ///< depth the leg is computed with (m)
    std::vector<double> k;               ///< wavenumber (rad/m)
    std::vector<double> omega;           ///< ω of the ray's train (rad/s)
    std::vector<double> celerity;        ///< C (m/s)
    std::vector<double> group_velocity;  ///< C_g (m/s)
    std::vector<double> shoaling;         ///< K_s
    std::vector<double> refraction;       ///< K_r from the spacing of neighbouring rays
    std::vector<double> amplitude;        ///< A = A∞ K_s K_r, capped at caustics (m)
    std::vector<RayEvent> event;          ///< what happened at the point
    std::vector<std::uint8_t> flags;      ///< RayPointFlag bits

    std::size_t ray_count() const noexcept { return offsets.size() - 1; }  ///< rays traced
    std::size_t point_count() const noexcept { return x.size(); }         ///< points over all rays
};

/// Traces every train over the seafloor in Ts'o–Barsky's isobath mode: a ray runs
/// straight to its next exact isobath crossing (IsobathIndex over `isobaths`), where
/// Snell's law sin i / C_i = sin r / C_r turns it (i, r from the contour normal); if
/// sin r > 1 it reflects. Which depth represents a band between two isobaths: the
/// depth of the isobath the ray crossed last (before the first crossing, the seafloor
/// depth where the ray entered) — Ts'o's "recalculated as a wave orthogonal is traced
/// over different contour lines". Rays enter across the up-wave side of the grid's
/// rectangle, `ray_spacing` apart, with the phase of a plane wave; a ray entering on
/// land is not traced. Rays end aground at an isobath of depth <= 0 or where they
/// leave the rectangle.
/// Amplitude: A = A∞ · K_s · K_r with K_r = sqrt(b0 / b), b the distance to the
/// neighbouring rays' crossings of the same isobath measured across the ray (energy
/// flux between rays is conserved; Gonzato eq. 9 is printed inverted).
/// Throws InputError for an invalid train or option, LimitError at the guard rails.
RaySet trace_rays(const Seafloor& seafloor, const DepthContours& isobaths,
                  std::span<const WaveTrain> trains, const TraceOptions& options = {});

// ---------------------------------------------------------------------------------
// Gonzato & Le Saëc's adaptive wave fronts (§3.3), gradient refraction mode
// ---------------------------------------------------------------------------------

/// Gonzato's ray flags.
enum class RayFlag : std::uint8_t {
    alive,    ///< propagating
    flat,     ///< amplitude below FrontOptions::flat_amplitude: no new rays between two flat ones
    aground,  ///< touched the shore (h <= 0) and now follows it
    dead,     ///< left the domain, or aground between two aground rays: removed
};
/// The flag's name ("alive", "flat", "aground", "dead").
const char* to_string(RayFlag f) noexcept;

/// How the adaptive fronts refract.
enum class FrontRefraction {
    gradient,  ///< Gonzato: the contour direction from the bicubic depth gradient, Snell per step
    isobath,   ///< Ts'o–Barsky: exact crossings of the isobaths inside each step, Snell at each
};

/// Options of trace_fronts (the scenes' /fronts, with ray_spacing, breaker_index and
/// max_rays from /trace).
struct FrontOptions {
    FrontRefraction refraction = FrontRefraction::gradient;  ///< how rays turn
    double ray_spacing = 1.0;     ///< initial distance between rays (m); Gonzato's bay: 1
    double step = 0.4;            ///< step length along every ray per front (m); bay: 0.4
    double split_distance = 1.2;  ///< insert a ray where neighbours are farther apart (m); bay: 1.2
    double flat_amplitude = 0.005;  ///< FLAT below this amplitude (m)
    /// A ray that has turned through more than this (degrees, as the scene key
    /// /fronts/max_turn_degrees) is removed as trapped: refraction round an island's
    /// shelf sends rays into closed orbits (360: a full circle; 180: once it heads back
    /// out to sea). In (0, 720].
    double max_turn_degrees = 360.0;
    std::size_t max_rays = 1'000'000;  ///< guard rail on live + inserted rays (as /trace/max_rays)
    std::size_t max_steps = 100'000;  ///< guard rail on fronts
    /// Guard rail on the points of all fronts together (the strips' vertices): rays ×
    /// steps, which max_rays and max_steps bound only one at a time (~100 bytes each).
    std::size_t max_points = 10'000'000;
    /// The memory a run may take (bytes; `wave run --max-memory-gb`, 2 GB by default):
    /// max_points is lowered to the points a run of them fits in (kRunBytesPerFrontPoint
    /// each), checked before the points are reserved.
    double max_bytes = 2e9;
    double breaker_index = kBreakerIndex;  ///< amplitude cap γ h / 2
    DispersionOptions dispersion{};  ///< how k(ω, h) is solved
};

/// What a run of the ray-strips surface holds for each front point at its peak: the point
/// in FrontSet (89 bytes), the strip vertex and motion plan made of it and the frames'
/// arrays (estimate_run has 440 on the bay's fronts; a little less, so that no run its
/// estimate accepts is refused). At the default 2 GB: 5 M points, which `wave validate`
/// plans in < 1 GB.
inline constexpr double kRunBytesPerFrontPoint = 400.0;

/// Fronts as rows: front f holds the live rays after f steps, in order along the
/// front, at points front_offsets[f] .. front_offsets[f+1]−1 (structure of arrays).
struct FrontSet {
    std::vector<std::size_t> front_offsets{0};  ///< front f at points front_offsets[f] .. front_offsets[f+1]−1
    std::vector<std::uint32_t> ray;  ///< stable ray id (initial rays 0…n−1, inserted rays after)
    std::vector<double> x;  ///< point (m)
    std::vector<double> y;  ///< point (m)
    std::vector<double> dir_x;  ///< unit direction of travel
    std::vector<double> dir_y;  ///< unit direction of travel
    std::vector<double> phase;       ///< the phase on entry + Σ k Δs (rad; 0 at the up-wave corner)
    std::vector<double> k;      ///< wavenumber (rad/m)
    std::vector<double> depth;  ///< h (m)
    std::vector<double> slope;  ///< |∇h| (bottom slope)
    std::vector<double> rise;        ///< −∇h · direction: tan β of the bottom rising along the ray (< 0 where it deepens)
    std::vector<double> amplitude;   ///< A∞ K_s K_r, K_r from the spacing of the neighbours
    std::vector<RayFlag> flag;       ///< the ray's state at the point
    std::vector<std::uint8_t> caustic;  ///< 1 where the ray has crossed a neighbour (order flipped): kept, amplitude capped
    /// Per ray id: the phase where its wave broke before it entered the domain (over the
    /// apron beyond an up-wave side that runs into the surf zone), NaN where it entered
    /// unbroken or was inserted. docs/conventions.md ("Where rays enter").
    std::vector<double> entry_break_phase;
    double omega = 0.0;                ///< ω of the train (rad/s)
    std::size_t caustic_points = 0;    ///< points with caustic set
    std::size_t initial_rays = 0;      ///< rays started on the upwave side
    std::size_t inserted_rays = 0;     ///< rays inserted where neighbours drifted apart
    std::size_t rays_aground = 0;      ///< rays that reached the shore
    std::size_t rays_trapped = 0;    ///< removed after turning max_turn_degrees (orbiting an island's shelf) or three domain crossings

    std::size_t front_count() const noexcept { return front_offsets.size() - 1; }  ///< fronts traced
};

/// Gonzato's adaptive tracing of one train (§3.3): every ray advances `step` per front.
/// Gradient mode: at each step the local contour direction comes from the bicubic
/// depth gradient and Snell's law sin i / C(h) = sin r / C(h') turns the ray between
/// the depth here and one step ahead (total reflection if sin r > 1). Isobath mode:
/// the step is cut at every exact crossing of `isobaths` (CGAL, as trace_rays), where
/// Snell's law turns the ray between the band's depth and the crossed isobath's, and
/// the phase is Σ k(band) Δs; rays crossing the shoreline isobath go AGROUND. Rays touching
/// land become AGROUND and follow the shoreline; a ray between two AGROUND rays, or
/// leaving the domain, is DEAD and removed; where neighbours are farther apart than
/// split_distance (and not both FLAT) a ray is inserted, interpolated from them.
/// A ray that has turned through more than max_turn (refraction can trap rays in
/// orbit round an island), or is still moving after three straight crossings of the
/// domain along the swell (guided along a coast or round a cove, its turns cancel), is
/// removed and counted in rays_trapped; neighbours that have
/// crossed (a caustic) get no ray inserted between them.
/// Amplitude A = A∞ K_s √(b0 / b): b the local spacing to the neighbours, b0 the
/// deep-water width of the same ray tube (halved at each insertion), so energy flux is
/// conserved (Gonzato eq. 9 printed inverted). Tracing stops when no ray is ALIVE or
/// FLAT. Throws InputError for bad options (or isobath mode without isobaths),
/// LimitError at the guard rails.
FrontSet trace_fronts(const Seafloor& seafloor, const WaveTrain& train, const FrontOptions& options = {},
                      const DepthContours* isobaths = nullptr);

/// The fronts as CSV, one row per ray per front, with the header
/// `front,ray,x,y,dir_x,dir_y,phase,k,depth,slope,rise,amplitude,flag`, full double precision.
std::string fronts_to_csv(const FrontSet& fronts);

/// The rays as CSV with the header
/// `ray,step,x,y,dir_x,dir_y,depth,k,omega,celerity,group_velocity,amplitude,flag`
/// (flag = the event name, plus "+capped" / "+doubtful"), full double precision.
std::string rays_to_csv(const RaySet& rays);

}  // namespace wave
