// Whitewater particles: each a closed form of its event and its age (docs/whitewater.md).

#include "libwave/whitewater.h"

#include "core/splitmix.h"
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/shade.h"
#include "libwave/surface.h"
#include "surface/triangle_locator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace wave {

void WhitewaterEvents::add(float ex, float ey, float ez, float dx, float dy, float c, float h, float len, double when, float s,
                           float f, float b, std::uint64_t k, std::uint32_t w) {
    x.push_back(ex), y.push_back(ey), z.push_back(ez);
    dir_x.push_back(dx), dir_y.push_back(dy);
    speed.push_back(c), height.push_back(h), length.push_back(len);
    time.push_back(when);
    spray.push_back(s), foam.push_back(f), bubbles.push_back(b);
    key.push_back(k);
    wave.push_back(w);
}

namespace {

using detail::splitmix64;
constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;

// Each vertex's share of a surface: the square root of a third of its triangles' area.
std::vector<double> vertex_spacing(std::span<const double> x, std::span<const double> y, std::span<const std::uint32_t> triangles,
                                   const char* what) {
    const std::size_t n = x.size();
    if (triangles.size() % 3 != 0) throw InputError(std::string(what) + ": the triangles' indices are not a multiple of 3");
    std::vector<double> area(n, 0.0);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
        if (a >= n || b >= n || c >= n)
            throw InputError(std::string(what) + ": triangle index out of range for " + std::to_string(n) + " vertices");
        const double twice = std::abs((x[b] - x[a]) * (y[c] - y[a]) - (x[c] - x[a]) * (y[b] - y[a]));
        for (const std::uint32_t v : {a, b, c}) area[v] += twice / 6.0;
    }
    for (double& a : area) a = std::sqrt(a);
    return area;
}

// The share of its crest's throw an event at a vertex of spacing `spacing` makes, under
// a crest of wavelength `wavelength`: an event stands for its crest length and for the
// strip of sea the crest sweeps to the next row of vertices, a sixteenth of a
// wavelength on the water mesh's default spacing (kEventsPerWavelength); where the mesh
// is finer (a surf-zone mesh at H/4 has ~7 × as many rows) the crest passes more
// vertices, each throwing its share, so that the particles per metre of crest do not
// grow with the mesh.
constexpr double kEventsPerWavelength = 16.0;
double event_share(double spacing, double wavelength) noexcept {
    return wavelength > 0.0 ? std::min(1.0, kEventsPerWavelength * spacing / wavelength) : 1.0;
}


// The i-th uniform draw in [0, 1) of a particle whose key is `h`.
inline double draw(std::uint64_t h, std::uint64_t i) noexcept {
    return static_cast<double>(splitmix64(h + 0x632BE59BD9B4E019ull * (i + 1)) >> 11) * 0x1.0p-53;
}

// A bell-shaped draw in (−1, 1): the mean of two uniforms, centred (a triangle).
inline double bell(std::uint64_t h, std::uint64_t i) noexcept { return draw(h, i) + draw(h, i + 101) - 1.0; }

void check(const WhitewaterOptions& o, const WhitewaterEvents& e) {
    const auto in = [](double v, double lo, double hi, const char* name) {
        if (!(v >= lo && v <= hi))
            throw InputError(std::string("whitewater: ") + name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                             "], got " + std::to_string(v));
    };
    in(o.spray_density, 0.0, 1e4, "spray_density");
    in(o.foam_density, 0.0, 1e4, "foam_density");
    in(o.bubble_density, 0.0, 1e4, "bubble_density");
    in(o.spray_life, 0.0, 60.0, "spray_life");
    in(o.foam_life, 0.0, 600.0, "foam_life");
    in(o.bubble_life, 0.0, 60.0, "bubble_life");
    in(o.spray_drag, 0.0, 100.0, "spray_drag");
    in(o.spray_lift, 0.0, 10.0, "spray_lift");
    in(o.foam_push, 0.0, 2.0, "foam_push");
    in(o.foam_push_time, 1e-3, 100.0, "foam_push_time");
    in(o.foam_spread, 0.0, 10.0, "foam_spread");
    in(static_cast<double>(o.foam_patch), 1.0, 1024.0, "foam_patch");
    in(o.foam_lace, 0.0, 0.95, "foam_lace");
    in(o.foam_lace_scale, 0.01, 1000.0, "foam_lace_scale");
    if (o.foam && o.foam_life == 0.0 && e.period > 0.0)
        throw InputError("whitewater: foam_life 0 (no decay) needs events that happen once (period 0), got a period of " +
                         std::to_string(e.period) + " s");
    const std::size_t n = e.size();
    for (const std::size_t m : {e.y.size(), e.z.size(), e.dir_x.size(), e.dir_y.size(), e.speed.size(), e.height.size(),
                                e.length.size(), e.time.size(), e.spray.size(), e.foam.size(), e.bubbles.size(), e.key.size(), e.wave.size()})
        if (m != n) throw InputError("whitewater: the events' arrays differ in length");
    if (!(e.period >= 0.0) || !std::isfinite(e.period)) throw InputError("whitewater: the events' period must be >= 0");
}

// How many particles of a kind an event throws: density · length · H · strength, the
// fraction rounded by a draw of its own (so the mean count is exact).
std::uint32_t particle_count(double density, double length, double height, double strength, std::uint64_t h,
                             std::uint64_t kind) noexcept {
    const double mean = density * std::max(0.0, length) * std::max(0.0, height) * std::clamp(strength, 0.0, 1.0);
    if (!(mean > 0.0)) return 0;
    const double whole = std::floor(mean);
    return static_cast<std::uint32_t>(std::min(1e6, whole + (draw(h, 900 + kind) < mean - whole ? 1.0 : 0.0)));
}

// One event's counts per kind (the same for every age).
struct Counts {
    std::uint32_t spray = 0, foam = 0, bubbles = 0;
    std::uint32_t total() const noexcept { return spray + foam + bubbles; }
};

// Event i's key, which its draws start from.
std::uint64_t event_key(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i) noexcept {
    return splitmix64(e.key[i] ^ splitmix64(o.seed));
}

Counts event_counts(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, std::uint64_t h) noexcept {
    Counts c;
    const double len = e.length[i], height = e.height[i];
    if (o.spray) c.spray = particle_count(o.spray_density, len, height, e.spray[i], h, 0);
    if (o.foam) c.foam = particle_count(o.foam_density, len, height, e.foam[i], h, 1);
    if (o.bubbles) c.bubbles = particle_count(o.bubble_density, len, height, e.bubbles[i], h, 2);
    return c;
}

// The ages (s) at which an event's emissions are alive at t: t − τ − n · period in
// [0, life) for every n (one age when the period is 0), newest first.
template <class F>
void for_each_age(const WhitewaterEvents& e, std::size_t i, double t, double life, F&& f) {
    const double since = t - e.time[i];
    if (e.period <= 0.0) {
        if (since >= 0.0 && since < life) f(since);
        return;
    }
    for (double a = since - e.period * std::floor(since / e.period); a < life; a += e.period) f(a);
}

// A particle as it is written.
struct Particle {
    float p[3], v[3], age, size;
    WhitewaterKind kind;
};

// What every spray particle of an event at one age shares: the event's throw and the
// drag's decay over the age (`fall`: the speed gravity took, against the drag).
struct SprayAge {
    double a, lift, decay, reach, drop, fall;
};

SprayAge spray_age(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, double a) noexcept {
    // Linear drag k: v = v0 e^{−ka} − (g/k)(1 − e^{−ka}) ẑ, its integral for p.
    // decay = e^{−ka}, reach = ∫ e^{−ks} ds over [0, a], drop = g ∫ (1 − e^{−ks})/k ds;
    // without drag plain ballistics.
    const double k = o.spray_drag;
    const bool dragged = k > 1e-9;
    const double decay = dragged ? std::exp(-k * a) : 1.0;
    const double reach = dragged ? (1.0 - decay) / k : a;
    const double drop = dragged ? kGravity / k * (a - reach) : 0.5 * kGravity * a * a;
    const double fall = dragged ? kGravity / k * (1.0 - decay) : kGravity * a;
    return {a, o.spray_lift * std::sqrt(kGravity * std::max(0.0, static_cast<double>(e.height[i]))), decay, reach, drop, fall};
}

// Spray j of event i at an age (false: it has landed or lived its life).
bool spray_particle(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, std::uint64_t h, const SprayAge& age,
                    Particle& out) noexcept {
    const double a = age.a;
    const double life = o.spray_life * (0.5 + 0.5 * draw(h, 7));
    if (a >= life) return false;
    const double c = e.speed[i], height = e.height[i], len = e.length[i];
    const double dx = e.dir_x[i], dy = e.dir_y[i];
    // Thrown from the lip: forward at 0.7 … 1.3 c (a plunging jet reaches ~1.3 c), up
    // by spray_lift · sqrt(g H), a little sideways; spread along the crest.
    const double along = (draw(h, 1) - 0.5) * len, ahead = draw(h, 2) * 0.3 * height;
    const double forward = c * (0.7 + 0.6 * draw(h, 3)), side = 0.15 * c * bell(h, 4);
    const double up = age.lift * (0.25 + 0.75 * draw(h, 5));
    const double v0[3] = {forward * dx - side * dy, forward * dy + side * dx, up};
    const double p0[3] = {e.x[i] + ahead * dx - along * dy, e.y[i] + ahead * dy + along * dx, e.z[i] + 0.1 * height * draw(h, 6)};
    const double z = p0[2] + v0[2] * age.reach - age.drop;
    const double still = e.z[i] - 0.75 * height;  // the still-water level under the crest
    if (z < still) return false;                  // landed
    const double vz = v0[2] * age.decay - age.fall;
    out.p[0] = static_cast<float>(p0[0] + v0[0] * age.reach), out.p[1] = static_cast<float>(p0[1] + v0[1] * age.reach);
    out.p[2] = static_cast<float>(z);
    out.v[0] = static_cast<float>(v0[0] * age.decay), out.v[1] = static_cast<float>(v0[1] * age.decay), out.v[2] = static_cast<float>(vz);
    out.age = static_cast<float>(a);
    out.size = static_cast<float>(0.04 + 0.08 * draw(h, 8));  // a clump of droplets, as a renderer draws it
    out.kind = WhitewaterKind::spray;
    return true;
}

// Value noise in [0, 1) on the unit lattice, smoothstep between the corners' draws, one
// pattern per seed; two octaves.
double value_noise(double u, double v, std::uint64_t seed) noexcept {
    double sum = 0.0, weight = 0.0, amp = 1.0;
    for (int octave = 0; octave < 2; ++octave, u *= 2.03, v *= 2.03, amp *= 0.5) {
        const double fu = std::floor(u), fv = std::floor(v);
        const auto i = static_cast<std::int64_t>(fu), j = static_cast<std::int64_t>(fv);
        const auto corner = [&](std::int64_t a, std::int64_t b) {
            const std::uint64_t k = splitmix64(seed + static_cast<std::uint64_t>(octave) * 0xA24BAED4963EE407ull) ^
                                    (static_cast<std::uint64_t>(a) * 0x9FB21C651E98DF25ull) ^ (static_cast<std::uint64_t>(b) * 0xC13FA9A902A6328Full);
            return static_cast<double>(splitmix64(k) >> 11) * 0x1.0p-53;
        };
        const double s = u - fu, t = v - fv;
        const double su = s * s * (3.0 - 2.0 * s), tv = t * t * (3.0 - 2.0 * t);
        const double top = corner(i, j) + su * (corner(i + 1, j) - corner(i, j));
        const double bottom = corner(i, j + 1) + su * (corner(i + 1, j + 1) - corner(i, j + 1));
        sum += amp * (top + tv * (bottom - top));
        weight += amp;
    }
    return sum / weight;
}

// The bore's push on what the crest leaves: distance and speed along the crest's run
// after age a (push · c · τ (1 − e^{−a/τ})).
struct Push {
    double distance, speed;
};
Push bore_push(double c, double push, double tau, double a) noexcept {
    const double decay = std::exp(-a / tau);
    return {push * c * tau * (1.0 - decay), push * c * decay};
}

// What every foam particle of an event at one age shares: the bore's push and the
// patches' spread.
struct FoamAge {
    double a, push_distance, push_speed, spread, rate, fade_life;
};

FoamAge foam_age(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, double a) noexcept {
    const double decay = std::exp(-a / o.foam_push_time);
    const double c = o.foam_push * e.speed[i];
    const double r0 = 0.08 + 0.02 * std::sqrt(static_cast<double>(o.foam_patch));
    return {a, c * o.foam_push_time * (1.0 - decay), c * decay, r0 + o.foam_spread * std::sqrt(a),
            0.5 * o.foam_spread / std::sqrt(std::max(a, 0.25)),  // d spread / da (held below a quarter second)
            0.0};
}

// Foam patch `patch` of event i: its centre (along and across the crest, from the
// event) and its share of the bore's push; false where the wave's lace has a hole.
struct FoamPatch {
    double along, across, push_share;
};

bool foam_patch(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, std::uint64_t event_key,
                std::uint32_t patch, FoamPatch& out) noexcept {
    const std::uint64_t h = splitmix64(event_key ^ (0xBA7C4ull + patch));
    const double len = e.length[i], dx = e.dir_x[i], dy = e.dir_y[i];
    // Anywhere on the event's stretch; pushed on unevenly by the bore (the foam tears).
    out = {(draw(h, 1) - 0.5) * len, (draw(h, 2) - 0.5) * len, 0.6 + 0.8 * draw(h, 3)};
    if (o.foam_lace <= 0.0) return true;
    const double cx = e.x[i] + out.across * dx - out.along * dy, cy = e.y[i] + out.across * dy + out.along * dx;
    const double u = (cx * dx + cy * dy) / o.foam_lace_scale, v = (cy * dx - cx * dy) / (2.5 * o.foam_lace_scale);
    // The two-octave noise is bunched round ½: stretched so that foam_lace is the share left bare.
    const double n = std::clamp(0.5 + 1.6 * (value_noise(u, v, e.wave[i] ^ o.seed) - 0.5), 0.0, 1.0);
    return n >= o.foam_lace;
}

// Foam particle j of event i in its patch at an age.
bool foam_particle(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, std::uint64_t event_key,
                   std::uint32_t j, const FoamPatch& patch, const FoamAge& age, Particle& out) noexcept {
    const std::uint64_t h = splitmix64(event_key ^ (0xF0A4ull + j));
    const double a = age.a;
    const double life = o.foam_life > 0.0 ? o.foam_life * (0.3 + 0.7 * draw(h, 1)) : std::numeric_limits<double>::infinity();
    if (a >= life) return false;
    const double dx = e.dir_x[i], dy = e.dir_y[i];
    // In its patch: a bell round the centre growing with √a, twice as long along the
    // crest as across it (streaks).
    const double u = 2.0 * bell(h, 2), w = bell(h, 3);
    const double s_along = patch.along + u * age.spread, s_across = patch.across + patch.push_share * age.push_distance + w * age.spread;
    out.p[0] = static_cast<float>(e.x[i] + s_across * dx - s_along * dy);
    out.p[1] = static_cast<float>(e.y[i] + s_across * dy + s_along * dx);
    out.p[2] = 0.0f;  // on the surface (ride_whitewater)
    const double va = u * age.rate, vc = patch.push_share * age.push_speed + w * age.rate;
    out.v[0] = static_cast<float>(vc * dx - va * dy), out.v[1] = static_cast<float>(vc * dy + va * dx), out.v[2] = 0.0f;
    out.age = static_cast<float>(a);
    // Fresh foam is thick; older foam thins as it spreads, before it dies.
    const double fade = std::isfinite(life) ? std::clamp(1.25 - a / life, 0.35, 1.0) : 1.0;
    out.size = static_cast<float>((0.07 + 0.11 * draw(h, 4)) * fade);
    out.kind = WhitewaterKind::foam;
    return true;
}

// What every bubble of an event at one age shares: the bore's push and the spread's
// scale.
struct BubbleAge {
    double a;
    Push push;
    double spread;
};

BubbleAge bubble_age(const WhitewaterEvents& e, std::size_t i, double a) noexcept {
    return {a, bore_push(e.speed[i], 0.8, 1.0, a), 0.1 * std::sqrt(a)};
}

// Bubble j of event i at an age: carried under the breaking crest, rising, dissolving.
bool bubble_particle(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, std::uint64_t h, const BubbleAge& age,
                     Particle& out) noexcept {
    const double a = age.a;
    const double life = o.bubble_life * (0.4 + 0.6 * draw(h, 1));
    const double depth0 = std::max(0.0, static_cast<double>(e.height[i])) * (0.15 + 0.65 * draw(h, 2));
    const double rise = 0.1 + 0.25 * draw(h, 3);
    const double depth = depth0 - rise * a;
    if (a >= life || depth <= 0.0) return false;
    const double len = e.length[i], dx = e.dir_x[i], dy = e.dir_y[i];
    const double along = (draw(h, 4) - 0.5) * len, across = (draw(h, 5) - 0.5) * len;
    const Push& push = age.push;
    const double s_across = across + push.distance + age.spread * bell(h, 6);
    out.p[0] = static_cast<float>(e.x[i] + s_across * dx - along * dy);
    out.p[1] = static_cast<float>(e.y[i] + s_across * dy + along * dx);
    out.p[2] = static_cast<float>(-depth);  // below the surface (ride_whitewater)
    out.v[0] = static_cast<float>(push.speed * dx), out.v[1] = static_cast<float>(push.speed * dy), out.v[2] = static_cast<float>(rise);
    out.age = static_cast<float>(a);
    out.size = static_cast<float>(0.01 + 0.03 * draw(h, 7));
    out.kind = WhitewaterKind::bubble;
    return true;
}

// Every particle of event i alive at t, in order (spray, foam, bubbles, each by draw,
// for each age newest first), handed to `f`.
// `key` and `c`: the event's (event_key, event_counts).
template <class F>
void event_particles(const WhitewaterEvents& e, const WhitewaterOptions& o, std::size_t i, double t, std::uint64_t key,
                     const Counts& c, F&& f) {
    if (c.total() == 0) return;
    Particle q;
    const double foam_life = o.foam_life > 0.0 ? o.foam_life : std::numeric_limits<double>::infinity();
    if (c.spray > 0)
        for_each_age(e, i, t, o.spray_life, [&](double a) {
            const SprayAge age = spray_age(e, o, i, a);
            for (std::uint32_t j = 0; j < c.spray; ++j)
                if (spray_particle(e, o, i, splitmix64(key ^ (0x5B7A7ull + j)), age, q)) f(q);
        });
    if (c.foam > 0) {
        const std::uint32_t per_patch = std::max<std::uint32_t>(1, o.foam_patch);
        for_each_age(e, i, t, foam_life, [&](double a) {
            const FoamAge age = foam_age(e, o, i, a);
            FoamPatch patch{};
            for (std::uint32_t first = 0; first < c.foam; first += per_patch) {
                if (!foam_patch(e, o, i, key, first / per_patch, patch)) continue;
                for (std::uint32_t j = first; j < std::min(c.foam, first + per_patch); ++j)
                    if (foam_particle(e, o, i, key, j, patch, age, q)) f(q);
            }
        });
    }
    if (c.bubbles > 0)
        for_each_age(e, i, t, o.bubble_life, [&](double a) {
            const BubbleAge age = bubble_age(e, i, a);
            for (std::uint32_t j = 0; j < c.bubbles; ++j)
                if (bubble_particle(e, o, i, splitmix64(key ^ (0xB0BB1Eull + j)), age, q)) f(q);
        });
}

void resize_points(WhitewaterPoints& out, std::size_t n) {
    out.positions.resize(3 * n);
    out.velocities.resize(3 * n);
    out.age.resize(n);
    out.size.resize(n);
    out.kind.resize(n);
}

void put(WhitewaterPoints& out, std::size_t k, const Particle& q) noexcept {
    std::memcpy(&out.positions[3 * k], q.p, sizeof q.p);
    std::memcpy(&out.velocities[3 * k], q.v, sizeof q.v);
    out.age[k] = q.age;
    out.size[k] = q.size;
    out.kind[k] = static_cast<std::uint8_t>(q.kind);
}

const detail::TriangleLocator& locator_of(const WhitewaterRide& r) {
    if (!r.locator) throw InputError("whitewater: a ride that was not planned (plan_whitewater_ride)");
    return *static_cast<const detail::TriangleLocator*>(r.locator.get());
}

// The most particles of each kind alive at once, each event emitting its counts once a
// period (or once, period 0) that live at most the kind's life. At time t event i holds
// w ages and one more while its phase since emission, (t − tᵢ) mod P, lies in [0, r),
// where life = w P + r: so a kind's most is w × all its counts plus the largest sum of
// its counts whose emission phases tᵢ mod P fall in one window of length r. Summed over
// the kinds (each kind's most may come at its own time). It was every count ×
// ⌈life / P⌉: every particle a loop emits, 7.6 × those alive at once on the whitewater
// bench's beach, which refused scenes far under max_points.
double most_alive(const WhitewaterEvents& e, const WhitewaterOptions& o, std::span<const Counts> counts) {
    const double lives[3] = {o.spray_life, o.foam_life > 0.0 ? o.foam_life : std::numeric_limits<double>::infinity(), o.bubble_life};
    const auto count = [](const Counts& c, int k) { return static_cast<double>(k == 0 ? c.spray : k == 1 ? c.foam : c.bubbles); };
    double total[3] = {0.0, 0.0, 0.0};
    for (const Counts& c : counts)
        for (int k = 0; k < 3; ++k) total[k] += count(c, k);
    if (!(e.period > 0.0)) return total[0] + total[1] + total[2];
    const double period = e.period;
    // Each kind's counts summed into kBins bins of emission phase tᵢ mod P; a window of
    // length r covers at most ⌈r / bin⌉ + 1 consecutive bins (round the loop): their
    // largest sum holds the window's (a bin's width more generous; no sort: a frame of the
    // bench's 2 M particles paid 35 ms for one).
    constexpr std::size_t kBins = 4096;
    const double bin = period / static_cast<double>(kBins);
    std::vector<double> sums(3 * kBins, 0.0);
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (counts[i].total() == 0) continue;
        const double phase = e.time[i] - period * std::floor(e.time[i] / period);
        const std::size_t b = std::min(kBins - 1, static_cast<std::size_t>(phase / bin));
        for (int k = 0; k < 3; ++k) sums[static_cast<std::size_t>(k) * kBins + b] += count(counts[i], k);
    }
    double most = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (!(total[k] > 0.0)) continue;
        if (!std::isfinite(lives[k])) return 1e18;
        const double whole = std::floor(lives[k] / period), rest = lives[k] - whole * period;
        const std::size_t width = std::min(kBins, static_cast<std::size_t>(std::ceil(rest / bin)) + 1);
        const double* s_k = &sums[static_cast<std::size_t>(k) * kBins];
        double window = 0.0;
        for (std::size_t b = 0; b < width; ++b) window += s_k[b];
        double widest = window;
        for (std::size_t b = width; b < kBins + width; ++b) {  // slide round the loop
            window += s_k[b % kBins] - s_k[(b - width) % kBins];
            widest = std::max(widest, window);
        }
        most += whole * total[k] + std::min(widest, total[k]);
    }
    return most;
}

// The bound of whitewater_bound from each event's counts.
std::size_t bound_of(const WhitewaterEvents& e, const WhitewaterOptions& o, std::span<const Counts> counts) {
    return static_cast<std::size_t>(std::min(most_alive(e, o, counts), 1e18));
}

// Every event's counts, in parallel (each alone).
std::vector<Counts> all_counts(const WhitewaterEvents& e, const WhitewaterOptions& o) {
    std::vector<Counts> counts(e.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, e.size(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) counts[i] = event_counts(e, o, i, event_key(e, o, i));
    });
    return counts;
}

void refuse_over_bound(std::size_t most, const WhitewaterOptions& o) {
    if (most > o.max_points)
        throw LimitError("whitewater: up to " + std::to_string(most) + " particles alive at once, over the limit of " +
                         std::to_string(o.max_points) + " (/whitewater/max_points); lower /whitewater/foam_density, "
                         "spray_density, bubble_density or the lives (foam_life, spray_life, bubble_life)");
}

}  // namespace

std::size_t whitewater_bound(const WhitewaterEvents& e, const WhitewaterOptions& o) {
    check(o, e);
    return bound_of(e, o, all_counts(e, o));
}

void check_whitewater_bound(const WhitewaterEvents& e, const WhitewaterOptions& o) { refuse_over_bound(whitewater_bound(e, o), o); }

struct WhitewaterWorkspace::Impl {
    std::vector<std::vector<Particle>> blocks;  // each block's particles, before they are copied out
};
WhitewaterWorkspace::WhitewaterWorkspace() : impl_(std::make_unique<Impl>()) {}
WhitewaterWorkspace::~WhitewaterWorkspace() = default;
WhitewaterWorkspace::WhitewaterWorkspace(WhitewaterWorkspace&&) noexcept = default;
WhitewaterWorkspace& WhitewaterWorkspace::operator=(WhitewaterWorkspace&&) noexcept = default;

void evaluate_whitewater(const WhitewaterEvents& e, const WhitewaterOptions& o, double t, WhitewaterPoints& out) {
    WhitewaterWorkspace workspace;
    evaluate_whitewater(e, o, t, out, workspace);
}

void evaluate_whitewater(const WhitewaterEvents& e, const WhitewaterOptions& o, double t, WhitewaterPoints& out,
                         WhitewaterWorkspace& workspace) {
    // The events' counts once (the bound, the blocks' room and their particles use them).
    check(o, e);
    const std::vector<Counts> counts = all_counts(e, o);
    refuse_over_bound(bound_of(e, o, counts), o);
    if (!std::isfinite(t)) throw InputError("whitewater: the time must be finite");
    const std::size_t n = e.size();
    // One pass: each fixed block of events (not the scheduler's) writes its particles to
    // a buffer of its own (the workspace's, kept between frames); then the buffers are
    // copied out at their offsets. The order is the events' for any thread count.
    constexpr std::size_t block = 512;
    const std::size_t blocks = (n + block - 1) / block;
    std::vector<std::vector<Particle>>& made = workspace.impl().blocks;
    made.resize(blocks);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        std::vector<Particle>& mine = made[b];
        mine.clear();
        // Room for every particle the block's events can have alive (their counts, once
        // per age the loop allows): no growth while they are made.
        std::size_t most = 0;
        for (std::size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) {
            const Counts& c = counts[i];
            const auto ages = [&](double life) {
                if (e.period <= 0.0) return std::size_t{1};
                return static_cast<std::size_t>(std::min(1e6, std::ceil(life / e.period)));
            };
            most += c.spray * ages(o.spray_life) + c.foam * ages(o.foam_life > 0.0 ? o.foam_life : 1.0) + c.bubbles * ages(o.bubble_life);
        }
        mine.reserve(most);
        for (std::size_t i = b * block; i < std::min(n, (b + 1) * block); ++i)
            event_particles(e, o, i, t, event_key(e, o, i), counts[i], [&](const Particle& q) { mine.push_back(q); });
    });
    std::vector<std::size_t> offset(blocks + 1, 0);
    for (std::size_t b = 0; b < blocks; ++b) offset[b + 1] = offset[b] + made[b].size();
    resize_points(out, offset[blocks]);
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
        std::size_t k = offset[b];
        for (const Particle& q : made[b]) put(out, k++, q);
    });
}

void fold_whitewater_events(const FoldSample& sample, double time, const FoldFoamOptions& fold, std::span<const double> rest_x,
                            std::span<const double> rest_y, std::array<double, 2> wind, double speed, double height,
                            double spacing, long long lattice_index, WhitewaterEvents& events) {
    if (sample.j_minus.size() != sample.vertex.size()) throw InputError("whitewater: a fold sample's arrays differ in length");
    const double norm = std::hypot(wind[0], wind[1]);
    const double dx = norm > 0.0 ? wind[0] / norm : 1.0, dy = norm > 0.0 ? wind[1] / norm : 0.0;
    for (std::size_t s = 0; s < sample.vertex.size(); ++s) {
        const std::uint32_t v = sample.vertex[s];
        if (v >= rest_x.size() || v >= rest_y.size())
            throw InputError("whitewater: fold sample vertex " + std::to_string(v) + " beyond " + std::to_string(rest_x.size()) +
                             " rest positions");
        const double strength = std::clamp((fold.threshold - sample.j_minus[s]) / fold.softness, 0.0, 1.0);
        if (strength <= 0.0) continue;
        const std::uint64_t key = splitmix64(static_cast<std::uint64_t>(lattice_index) * 0x9E3779B97F4A7C15ull ^ v);
        events.add(static_cast<float>(rest_x[v]), static_cast<float>(rest_y[v]), static_cast<float>(0.75 * height),
                   static_cast<float>(dx), static_cast<float>(dy), static_cast<float>(speed), static_cast<float>(height),
                   static_cast<float>(spacing), time, static_cast<float>(strength >= 1.0 ? 1.0 : 0.25 * strength),
                   static_cast<float>(strength), static_cast<float>(strength), key,
                   static_cast<std::uint32_t>(lattice_index));
    }
}

WhitewaterRide plan_whitewater_ride(std::span<const double> rest_x, std::span<const double> rest_y,
                                    std::span<const std::uint32_t> triangles) {
    if (rest_x.size() != rest_y.size()) throw InputError("whitewater: rest x and y differ in length");
    for (const std::uint32_t v : triangles)
        if (v >= rest_x.size()) throw InputError("whitewater: triangle index " + std::to_string(v) + " out of range");
    WhitewaterRide r{rest_x, rest_y, std::make_shared<const detail::TriangleLocator>(rest_x, rest_y, triangles)};
    return r;
}

void ride_whitewater(const WhitewaterRide& ride, std::span<const float> surface, WhitewaterPoints& points, bool spray_rides) {
    const detail::TriangleLocator& locator = locator_of(ride);
    if (surface.size() != 3 * ride.rest_x.size())
        throw InputError("whitewater: " + std::to_string(surface.size()) + " surface floats for " + std::to_string(ride.rest_x.size()) +
                         " rest vertices");
    const std::size_t n = points.count();
    std::vector<std::uint8_t> keep(n, 1);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k != r.end(); ++k) {
            if (!spray_rides && points.kind[k] == static_cast<std::uint8_t>(WhitewaterKind::spray)) continue;
            float* p = &points.positions[3 * k];
            detail::TriangleLocator::Hit hit;
            if (!locator.locate(p[0], p[1], hit)) {
                keep[k] = 0;
                continue;
            }
            double d[3];
            for (int c = 0; c < 3; ++c) {
                const auto rest = [&](std::uint32_t v) { return c == 0 ? ride.rest_x[v] : c == 1 ? ride.rest_y[v] : 0.0; };
                d[c] = hit.wa * (surface[3 * hit.a + c] - rest(hit.a)) + hit.wb * (surface[3 * hit.b + c] - rest(hit.b)) +
                       hit.wc * (surface[3 * hit.c + c] - rest(hit.c));
            }
            p[0] = static_cast<float>(p[0] + d[0]), p[1] = static_cast<float>(p[1] + d[1]), p[2] = static_cast<float>(p[2] + d[2]);
        }
    });
    std::size_t m = 0;
    for (std::size_t k = 0; k < n; ++k) {
        if (!keep[k]) continue;
        if (m != k) {
            std::memmove(&points.positions[3 * m], &points.positions[3 * k], 3 * sizeof(float));
            std::memmove(&points.velocities[3 * m], &points.velocities[3 * k], 3 * sizeof(float));
            points.age[m] = points.age[k], points.size[m] = points.size[k], points.kind[m] = points.kind[k];
        }
        ++m;
    }
    resize_points(points, m);
}

void splat_whitewater_foam(const WhitewaterRide& ride, const WhitewaterPoints& points, double full, double texture,
                           std::span<float> foam) {
    const detail::TriangleLocator& locator = locator_of(ride);
    if (foam.size() != ride.rest_x.size())
        throw InputError("whitewater: " + std::to_string(foam.size()) + " foam values for " + std::to_string(ride.rest_x.size()) +
                         " vertices");
    if (!(full > 0.0) || !(texture >= 0.0 && texture <= 1.0)) throw InputError("whitewater: splat full must be > 0, texture in [0, 1]");
    // Where each foam particle lies at rest: its position less the surface's displacement
    // is not known here, so the rest triangle under its ridden position is taken (the
    // displacement is a fraction of a triangle away from the crests).
    const std::size_t n = points.count();
    std::vector<detail::TriangleLocator::Hit> hits(n);
    std::vector<std::uint8_t> found(n, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k != r.end(); ++k)
            if (points.kind[k] == static_cast<std::uint8_t>(WhitewaterKind::foam))
                found[k] = locator.locate(points.positions[3 * k], points.positions[3 * k + 1], hits[k]) ? 1 : 0;
    });
    std::vector<float> weight(foam.size(), 0.0f);
    for (std::size_t k = 0; k < n; ++k) {  // in particle order: the same sums for any thread count
        if (!found[k]) continue;
        weight[hits[k].a] += static_cast<float>(hits[k].wa);
        weight[hits[k].b] += static_cast<float>(hits[k].wb);
        weight[hits[k].c] += static_cast<float>(hits[k].wc);
    }
    for (std::size_t v = 0; v < foam.size(); ++v)
        foam[v] = std::max(static_cast<float>(foam[v] * (1.0 - texture)), static_cast<float>(std::min(1.0, weight[v] / full)));
}

namespace {

void append_float(std::string& s, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(v));
    s.append(buf, r.ptr);
}

void pad4(std::string& s, char fill) {
    while (s.size() % 4 != 0) s.push_back(fill);
}

void put_u32(std::string& s, std::uint32_t v) {
    for (int b = 0; b < 4; ++b) s.push_back(static_cast<char>((v >> (8 * b)) & 0xFF));
}

}  // namespace

std::string whitewater_glb(const WhitewaterPoints& pts, std::size_t frame, double fps) {
    const std::size_t n = pts.count();
    if (pts.positions.size() != 3 * n || pts.velocities.size() != 3 * n || pts.size.size() != n || pts.kind.size() != n)
        throw InputError("whitewater: the points' arrays differ in length");
    // glTF's axes: (x, y, z) z up → (x, z, −y).
    std::string bin;
    bin.reserve(n * 4 * 9);
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    const auto push = [&bin](float v) {
        char b[4];
        std::memcpy(b, &v, 4);
        bin.append(b, 4);
    };
    for (std::size_t k = 0; k < n; ++k) {
        const float g[3] = {pts.positions[3 * k], pts.positions[3 * k + 2], -pts.positions[3 * k + 1]};
        for (int c = 0; c < 3; ++c) {
            if (!std::isfinite(g[c])) throw InputError("whitewater: particle " + std::to_string(k) + " has a non-finite position");
            lo[c] = k == 0 ? g[c] : std::min(lo[c], g[c]);
            hi[c] = k == 0 ? g[c] : std::max(hi[c], g[c]);
            push(g[c]);
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        push(pts.velocities[3 * k]), push(pts.velocities[3 * k + 2]), push(-pts.velocities[3 * k + 1]);
    }
    for (std::size_t k = 0; k < n; ++k) push(pts.age[k]);
    for (std::size_t k = 0; k < n; ++k) push(pts.size[k]);
    for (std::size_t k = 0; k < n; ++k) push(static_cast<float>(pts.kind[k]));

    std::string json = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"libwave whitewater\"},\"scene\":0,\"scenes\":[{\"nodes\":[";
    json += n > 0 ? "0" : "";
    json += "],\"extras\":{\"libwave_whitewater\":{\"frame\":" + std::to_string(frame) + ",\"fps\":";
    append_float(json, fps);
    json += ",\"points\":" + std::to_string(n) + ",\"kinds\":[\"spray\",\"foam\",\"bubble\"]}}}]";
    if (n > 0) {
        const std::size_t f = 4 * n;
        json += ",\"nodes\":[{\"name\":\"whitewater\",\"mesh\":0}],\"meshes\":[{\"name\":\"whitewater\",\"primitives\":[{\"mode\":0,"
                "\"attributes\":{\"POSITION\":0,\"_VELOCITY\":1,\"_AGE\":2,\"_SIZE\":3,\"_KIND\":4}}]}]";
        json += ",\"buffers\":[{\"byteLength\":" + std::to_string(bin.size()) + "}],\"bufferViews\":[";
        const std::size_t views[5][2] = {{0, 3 * f}, {3 * f, 3 * f}, {6 * f, f}, {7 * f, f}, {8 * f, f}};
        for (int v = 0; v < 5; ++v)
            json += std::string(v ? "," : "") + "{\"buffer\":0,\"byteOffset\":" + std::to_string(views[v][0]) +
                    ",\"byteLength\":" + std::to_string(views[v][1]) + "}";
        json += "],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":" + std::to_string(n) + ",\"type\":\"VEC3\",\"min\":[";
        for (int c = 0; c < 3; ++c) append_float(json, lo[c]), json += c < 2 ? "," : "],\"max\":[";
        for (int c = 0; c < 3; ++c) append_float(json, hi[c]), json += c < 2 ? "," : "]}";
        json += ",{\"bufferView\":1,\"componentType\":5126,\"count\":" + std::to_string(n) + ",\"type\":\"VEC3\"}";
        for (int v = 2; v < 5; ++v)
            json += ",{\"bufferView\":" + std::to_string(v) + ",\"componentType\":5126,\"count\":" + std::to_string(n) + ",\"type\":\"SCALAR\"}";
        json += "]";
    }
    json += "}";
    pad4(json, ' ');
    pad4(bin, '\0');
    std::string glb;
    const std::size_t total = 12 + 8 + json.size() + (n > 0 ? 8 + bin.size() : 0);
    if (total > 0xFFFFFFFFull) throw LimitError("whitewater: a frame's points exceed a .glb's 4 GiB");
    glb.reserve(total);
    glb += "glTF";
    put_u32(glb, 2);
    put_u32(glb, static_cast<std::uint32_t>(total));
    put_u32(glb, static_cast<std::uint32_t>(json.size()));
    glb += "JSON";
    glb += json;
    if (n > 0) {
        put_u32(glb, static_cast<std::uint32_t>(bin.size()));
        glb += std::string("BIN\0", 4);
        glb += bin;
    }
    return glb;
}

}  // namespace wave

namespace wave {

// The breakers' events: see whitewater.h.
WhitewaterEvents jeschke_whitewater_events(const JeschkeMotionPlan& p, std::span<const std::uint32_t> triangles) {
    const std::size_t n = p.vertex_count();
    if (!p.lag.empty() && p.lag.size() != n) throw InputError("jeschke whitewater: the lags differ in length from the vertices");
    const std::vector<double> spacing = vertex_spacing(p.x, p.y, triangles, "jeschke whitewater");
    WhitewaterEvents e;
    if (!(p.omega > 0.0)) return e;
    const auto crests = static_cast<long long>(p.loop_periods());
    e.period = static_cast<double>(crests) * two_pi / p.omega;
    for (std::size_t v = 0; v < n; ++v) {
        if (!std::isfinite(p.break_phase[v]) || p.width[v] <= 0.0f || spacing[v] <= 0.0) continue;
        if (p.phase[v] < static_cast<double>(p.break_phase[v]) - p.variation * two_pi) continue;
        const double height = p.scale[v] / 5.0, c = p.omega * p.width[v] / two_pi;
        const double curl = std::min(1.0, static_cast<double>(p.curl[v]));
        for (long long k = 0; k < crests; ++k) {
            const BreakerLife life = jeschke_vertex_life(p, v, k);
            double spray = 0.0, foam = jeschke_foam_yield(life, p.foam_onset), bubbles = 0.0, top = 0.75;
            if (life.phase == BreakerPhase::breaking) {
                spray = std::sin(pi * life.t) * (0.35 + 0.65 * curl);
                bubbles = std::clamp((life.t - 0.3) / 0.5, 0.0, 1.0);
            } else if (life.phase == BreakerPhase::collapsing) {
                spray = 0.25 * std::max(0.0, 1.0 - 4.0 * life.t) * (0.35 + 0.65 * curl);
                bubbles = 1.0 - life.t;
                foam *= 1.0 - 0.6 * life.t;
                top = 0.75 - 0.5 * life.t;
            }
            if (spray <= 0.0 && foam <= 0.0 && bubbles <= 0.0) continue;
            const double share = event_share(spacing[v], static_cast<double>(p.width[v]));
            spray *= share, foam *= share, bubbles *= share;
            const double when = (p.phase[v] + (p.lag.empty() ? 0.0 : p.lag[v]) + two_pi * static_cast<double>(k)) / p.omega;
            e.add(static_cast<float>(p.x[v]), static_cast<float>(p.y[v]), static_cast<float>(top * height),
                  static_cast<float>(p.dir_x[v]), static_cast<float>(p.dir_y[v]), static_cast<float>(c), static_cast<float>(height),
                  static_cast<float>(spacing[v]), when - e.period * std::floor(when / e.period), static_cast<float>(spray),
                  static_cast<float>(foam), static_cast<float>(bubbles),
                  splitmix64(static_cast<std::uint64_t>(v) * 0x100000001B3ull + static_cast<std::uint64_t>(k)),
                  static_cast<std::uint32_t>(k));
        }
    }
    return e;
}

}  // namespace wave

namespace wave {

WhitewaterEvents gonzato_whitewater_events(const RayStrips& s, const GonzatoMotionPlan& m, const FoamOptions& o,
                                           std::span<const std::uint32_t> triangles) {
    const std::size_t n = s.vertex_count();
    if (m.vertex_count() != n)
        throw InputError("gonzato whitewater: " + std::to_string(m.vertex_count()) + " motion vertices for " + std::to_string(n) +
                         " strip vertices");
    if (!(o.breaker_index > 0.0) || !(o.onset > 0.0 && o.onset < 1.0))
        throw InputError("gonzato whitewater: foam needs breaker_index > 0 and 0 < onset < 1");
    const std::vector<double> spacing = vertex_spacing(s.x, s.y, triangles, "gonzato whitewater");
    WhitewaterEvents e;
    if (!(m.omega > 0.0)) return e;
    e.period = two_pi / m.omega;
    for (std::size_t v = 0; v < n; ++v) {
        const double h = s.depth[v], height = 2.0 * s.amplitude[v];
        if (!(h > 0.0) || !(height > 0.0) || !(s.k[v] > 0.0) || spacing[v] <= 0.0) continue;
        const double w = std::clamp((height / (o.breaker_index * h) - o.onset) / (1.0 - o.onset), 0.0, 1.0);
        if (w <= 0.0) continue;
        const double share = event_share(spacing[v], two_pi / s.k[v]);
        // Φ = Σ k Δs − ω t: the crest (Φ_min + π) stands over the vertex at that time.
        const double when = (m.phase[v] - m.shape[v].trough_phase - pi) / m.omega;
        e.add(static_cast<float>(s.x[v]), static_cast<float>(s.y[v]), static_cast<float>(0.6 * height), static_cast<float>(s.dir_x[v]),
              static_cast<float>(s.dir_y[v]), static_cast<float>(m.omega / s.k[v]), static_cast<float>(height),
              static_cast<float>(spacing[v]), when - e.period * std::floor(when / e.period), static_cast<float>(w * w * share),
              static_cast<float>(w * share), static_cast<float>(w * share), splitmix64(0x60A2A70ull ^ (static_cast<std::uint64_t>(v) * 0x100000001B3ull)), 0);
    }
    return e;
}

}  // namespace wave
