/// \file
/// libwave — whitewater: the spray, foam and bubbles of breaking water as particles.
///
/// Every frame stays computable on its own, as every other stage of libwave: a
/// particle is a closed form of the event that threw it (where and when a crest broke
/// or the wind sea folded) and its age. Events are periodic in the loop (a breaking
/// crest passes a point once a swell period) or, for the wind sea's folds, taken on the
/// fold foam's lattice of past times, so a frame computed alone equals the same frame of
/// a whole run, for any thread count (docs/whitewater.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace wave {

struct JeschkeMotionPlan;
struct GonzatoMotionPlan;
struct RayStrips;
struct FoamOptions;
struct FoldSample;
struct FoldFoamOptions;

/// What a particle is, by where it lives (Houdini's and the FLIP Fluids add-on's
/// vocabulary): above the water, on it, under it.
enum class WhitewaterKind : std::uint8_t {
    spray = 0,   ///< thrown from a lip: ballistic under gravity with linear drag
    foam = 1,    ///< on the surface: pushed by the bore, then riding the water, spreading
    bubble = 2,  ///< under the surface: dragged along, rising, dissolving
};

/// The options of the particles (scene key /whitewater). Counts are per metre of crest
/// that an event stands for, per metre of its wave height, at full strength.
struct WhitewaterOptions {
    /// spray particles per m of crest per m of height, per row of vertices a sixteenth of
    /// a wavelength apart (a finer mesh's events each throw their share)
    double spray_density = 40.0;
    double foam_density = 60.0;    ///< foam particles
    double bubble_density = 25.0;  ///< bubbles
    double spray_life = 2.5;       ///< s: the longest a droplet flies (it dies on landing)
    double foam_life = 12.0;       ///< s: the longest a foam particle lives (each draws its own, ≥ 30 %); 0: for ever (no decay)
    double bubble_life = 3.0;      ///< s: the longest a bubble lives (it dies at the surface)
    double spray_drag = 0.6;       ///< 1/s: linear drag of the droplets
    double spray_lift = 1.0;       ///< the lip's upward throw, × sqrt(g H)
    double foam_push = 0.5;        ///< the bore's push on fresh foam, × the crest speed
    double foam_push_time = 1.5;   ///< s: e-folding time of that push
    double foam_spread = 0.25;     ///< m/√s: a foam patch's growth (streaks twice as long along the crest)
    std::uint32_t foam_patch = 24; ///< foam particles per patch (they spread from one centre)
    /// Foam is torn: a noise field per wave (foam_lace_scale across the crest, 2.5 times
    /// that along it) leaves this share of the broken water without foam patches, so the
    /// foam lies in streaks and lace with holes, different for every wave. 0: no holes.
    double foam_lace = 0.45;
    double foam_lace_scale = 2.5;  ///< m: the lace's size across the crest
    std::uint64_t seed = 1;        ///< the particles' draws
    /// The most particles a frame may hold (whitewater_bound), checked before any is made:
    /// about 70 bytes each while a frame is made.
    std::size_t max_points = 10'000'000;
    bool spray = true;    ///< make spray
    bool foam = true;     ///< make foam
    bool bubbles = true;  ///< make bubbles
};

/// Where and when breaking water throws whitewater: one event per point of a breaking
/// crest as it passes (flat arrays, one entry per event).
struct WhitewaterEvents {
    std::vector<float> x;      ///< the crest's top (m)
    std::vector<float> y;      ///< the crest's top (m)
    std::vector<float> z;      ///< the crest's top (m, z up)
    std::vector<float> dir_x;  ///< unit direction the crest runs
    std::vector<float> dir_y;  ///< unit direction the crest runs
    std::vector<float> speed;         ///< the crest's speed c (m/s)
    std::vector<float> height;        ///< its wave height H (m)
    std::vector<float> length;        ///< the stretch of crest the event stands for (m)
    std::vector<double> time;         ///< when (s)
    std::vector<float> spray;    ///< spray's strength in [0, 1]
    std::vector<float> foam;     ///< foam's strength in [0, 1]
    std::vector<float> bubbles;  ///< bubbles' strength in [0, 1]
    std::vector<std::uint64_t> key;   ///< the draws' key: the same event, the same particles
    std::vector<std::uint32_t> wave;  ///< the wave that threw it (a crest, a fold's lattice time): one lace per wave
    /// Events repeat after this (s): an event at time τ also happens at τ + n · period
    /// for every integer n. 0: each event happens once.
    double period = 0.0;
    std::size_t size() const noexcept { return x.size(); }  ///< events held
    void add(float ex, float ey, float ez, float dx, float dy, float c, float h, float len, double when, float s, float f,
             float b, std::uint64_t k, std::uint32_t w);  ///< appends one event
};

/// One frame's particles (flat arrays, one entry per particle; reused frame to frame).
struct WhitewaterPoints {
    std::vector<float> positions;   ///< 3 per particle (m, z up)
    std::vector<float> velocities;  ///< 3 per particle (m/s)
    std::vector<float> age;         ///< s since it was thrown
    std::vector<float> size;        ///< radius (m) a renderer gives it
    std::vector<std::uint8_t> kind; ///< WhitewaterKind
    std::size_t count() const noexcept { return age.size(); }  ///< particles held
};

/// The events of Jeschke's breakers (plan_jeschke_breakers, on the surface whose
/// triangles are `triangles`): every vertex a breaking crest passes, once per crest of
/// the loop (plan.loop_periods() of them, the events' period that many swell periods),
/// at the moment the crest stands over it. Spray while the crest breaks (most as its
/// lip falls, sin(π t) of the breaking phase), foam as the crest leaves foam
/// (jeschke_foam's yield), bubbles where the lip plunges and the bore collapses. An
/// event stands for the vertex's share of the surface (the square root of a third of
/// its triangles' area). Throws InputError on sizes that disagree.
WhitewaterEvents jeschke_whitewater_events(const JeschkeMotionPlan& plan, std::span<const std::uint32_t> triangles);

/// The events of Gonzato's profile on ray strips (`strips`, their motion `motion`, the
/// surface's `triangles`): every vertex whose wave nears the breaking limit, as its
/// breaking foam says (weight w from `foam.onset` · γh to γh, breaking_foam), once per
/// swell period as the crest (Φ_min + π) passes it: foam and bubbles w, spray w². The
/// events' period is the swell's. Throws InputError on sizes that disagree or bad
/// foam options.
WhitewaterEvents gonzato_whitewater_events(const RayStrips& strips, const GonzatoMotionPlan& motion, const FoamOptions& foam,
                                           std::span<const std::uint32_t> triangles);

/// The events of the wind sea's folds at one past lattice time (fold_sample, taken at
/// `time` over the vertices at rest positions `rest_x`, `rest_y`): a whitecap at every
/// vertex of the sample, its strength rising from 0 at the fold threshold to 1 a
/// softness below (spray only where it is full), running `wind` (unit) at `speed`, of
/// height `height`, standing for `spacing` metres; its top 0.75 H above the surface
/// (ride_whitewater with spray_rides puts the spray over the water). Appended to `events`. Throws
/// InputError on a vertex index beyond the rest positions.
void fold_whitewater_events(const FoldSample& sample, double time, const FoldFoamOptions& fold, std::span<const double> rest_x,
                            std::span<const double> rest_y, std::array<double, 2> wind, double speed, double height,
                            double spacing, long long lattice_index, WhitewaterEvents& events);

/// A bound on the particles of `events` alive at any time: per kind, every emission's
/// ages within the kind's life (⌊life / period⌋ of them) plus the largest sum of counts
/// whose emission phases (time mod period) fall within one window of the life's
/// remainder, found over 4 096 phase bins (a bin more generous); summed over the kinds.
/// Period 0: every count once.
std::size_t whitewater_bound(const WhitewaterEvents& events, const WhitewaterOptions& options);

/// Throws LimitError naming /whitewater/max_points and the keys that lower the count
/// when whitewater_bound exceeds options.max_points (InputError on options out of range).
void check_whitewater_bound(const WhitewaterEvents& events, const WhitewaterOptions& options);

/// The particles alive at time t into `out` (resized), each a closed form of its event
/// and age (docs/whitewater.md): spray ballistic with drag from the lip, alive while
/// above the still-water level under it; foam and bubbles at their drift position (x, y)
/// with z their height relative to the water surface (ride_whitewater puts them on it).
/// Particles come event by event, in the events' order, then by draw: the same output for
/// any thread count. Throws InputError on options out of range, LimitError as
/// check_whitewater_bound.
void evaluate_whitewater(const WhitewaterEvents& events, const WhitewaterOptions& options, double t, WhitewaterPoints& out);

/// evaluate_whitewater's buffers between the particles' making and their copy into the
/// output, kept from one frame to the next: a run of frames passes the same workspace
/// and allocates (and faults in) none of them again. One per thread that evaluates.
class WhitewaterWorkspace {
public:
    WhitewaterWorkspace();   ///< empty: grown by the first evaluation
    ~WhitewaterWorkspace();  ///< frees the buffers
    WhitewaterWorkspace(WhitewaterWorkspace&&) noexcept;             ///< moves the buffers (the moved-from one may only be assigned or destroyed)
    WhitewaterWorkspace& operator=(WhitewaterWorkspace&&) noexcept;  ///< moves the buffers
    WhitewaterWorkspace(const WhitewaterWorkspace&) = delete;             ///< not copyable: one per thread
    WhitewaterWorkspace& operator=(const WhitewaterWorkspace&) = delete;  ///< not copyable
    struct Impl;
    Impl& impl() noexcept { return *impl_; }  ///< the buffers (whitewater.cpp)

private:
    std::unique_ptr<Impl> impl_;
};

/// evaluate_whitewater with its buffers from `workspace` (the same output, bit for bit).
void evaluate_whitewater(const WhitewaterEvents& events, const WhitewaterOptions& options, double t, WhitewaterPoints& out,
                         WhitewaterWorkspace& workspace);

/// The surface the particles ride: its rest positions and triangles (kept by reference:
/// the spans must outlive it), located once.
struct WhitewaterRide {
    std::span<const double> rest_x;  ///< the surface's rest positions (m)
    std::span<const double> rest_y;  ///< the surface's rest positions (m)
    std::shared_ptr<const void> locator;  ///< the rest triangles' point locator (internal)
};
/// The ride on the surface of rest positions (`rest_x`, `rest_y`) and `triangles`.
WhitewaterRide plan_whitewater_ride(std::span<const double> rest_x, std::span<const double> rest_y,
                                    std::span<const std::uint32_t> triangles);

/// Puts foam on and bubbles under the moved surface (`surface_positions`, 3 floats per
/// rest vertex): each takes the displacement and height of the point of the moved
/// surface over its drift position (barycentric in the rest triangle holding it), and
/// its velocity the surface's orbital motion is left out of. Particles over no water
/// (on land, beyond the surface) are dropped, keeping the others' order. Spray is left
/// as it is, unless `spray_rides`: then its height is taken above the surface under it
/// (the wind sea's whitecaps, whose events do not know where the surface stood). Throws
/// InputError when `surface_positions` does not hold 3 per rest vertex.
void ride_whitewater(const WhitewaterRide& ride, std::span<const float> surface_positions, WhitewaterPoints& points,
                     bool spray_rides = false);

/// Splats foam particles onto the surface's vertices (the rest triangle holding each,
/// barycentric weights): foam[v] = max(foam[v] · (1 − texture), min(1, splat / full)),
/// where `full` is the weight a vertex gets from `full` particles. The model's smooth
/// foam band takes the particles' patches and streaks. Throws InputError on sizes.
void splat_whitewater_foam(const WhitewaterRide& ride, const WhitewaterPoints& points, double full, double texture,
                           std::span<float> foam);

/// A frame's particles as a glTF 2.0 binary: one mesh of one POINTS primitive with
/// POSITION (glTF's y up: (x, z, −y)), _VELOCITY (VEC3, glTF axes), _AGE, _SIZE and
/// _KIND (SCALAR float), all float32; the scene's extras say libwave_whitewater with
/// the frame and fps. An empty frame is a valid file with no mesh.
std::string whitewater_glb(const WhitewaterPoints& points, std::size_t frame, double fps);

}  // namespace wave
