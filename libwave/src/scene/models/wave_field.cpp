// The refraction–diffraction field itself as the surface: each train's complex
// amplitude η̂ (a wide-angle parabolic mild-slope solution, field.h) on a regular grid
// over the seafloor, animated as Σ Re(η̂ e^{−iωt}), every ω a whole multiple of the
// loop's (the first train's period). Heights stay finite behind shoals and islands,
// where rays cross; foam rides the crests where the field broke (H = γh).
#include "../surface_model.h"

#include "libwave/physics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

namespace wave::detail {
namespace {

// Vertices per local wavelength of the shortest train (a crest and a trough of four
// edges each: the sine's shape within 8 % in height).
constexpr double kVerticesPerWavelength = 8.0;

void read_before(const Node& root, Scene&) {
    refuse_height_field_options(root, "wave-field\" (set /field instead)");
    refuse_ray_strip_keys(root);
    for (const char* key : {"fronts", "motion"})
        if (root.has(key)) root[key].fail("only for the ray-strips surface (the wave field moves as its own η̂ e^{−iωt})");
}

// The vertices: the water mesh (surface.h), bounded by the domain rectangle and the
// shoreline, its edges an eighth of the local wavelength of the shortest train, and no
// shorter than the finest field's node spacing (what the field resolves).
void plan(const Scene& scene, ScenePlan& p, PlanStages stages) {
    p.isobaths = extract_isobaths(p.seafloor, scene.isobaths);
    FieldOptions share = scene.field;  // every train's grid is held: the memory limit is shared
    share.max_bytes /= static_cast<double>(scene.waves.size());
    for (const WaveTrain& w : scene.waves) p.wave_fields.push_back(solve_wave_field(p.seafloor, w, share));
    // A field the swell never entered (its up-wave side is land) is still water: heights
    // 0 .. 0 m used to follow. Say why, naming the train's direction.
    for (std::size_t i = 0; i < p.wave_fields.size(); ++i) {
        const WaveField& f = p.wave_fields[i];
        float largest = 0.0f;
        for (const std::complex<float>& e : f.envelope) largest = std::max(largest, std::abs(e));
        if (largest > 1e-6f * static_cast<float>(scene.waves[i].amplitude)) continue;
        const WaveTrain& w = scene.waves[i];
        throw InputError("scene: no wave enters the water over " + p.seafloor.source + " from /waves/" + std::to_string(i) +
                         ": the swell travels towards [" + fmt(w.direction_x) + ", " + fmt(w.direction_y) +
                         "] (/waves/" + std::to_string(i) + "/direction) and its up-wave side is land; a direction points where the "
                         "waves go, from the open sea towards the shore");
    }
    if (stages == PlanStages::trace) return;
    double shortest = scene.waves[0].period;
    for (const WaveTrain& w : scene.waves) shortest = std::min(shortest, w.period);
    double finest = std::numeric_limits<double>::infinity();
    for (const WaveField& f : p.wave_fields) finest = std::min({finest, f.dx, f.dy});
    const double omega = 2.0 * std::numbers::pi / shortest;
    const ElevationGrid& grid = p.seafloor.grid;
    const EdgeSize size = [&](double x, double y) {
        return std::max(linear_wave(omega, depth_at(grid, x, y)).wavelength / kVerticesPerWavelength, finest);
    };
    WaterMeshOptions o;
    o.max_vertices = scene.surface.max_vertices;
    WaterMesh mesh;
    try {
        mesh = mesh_water(p.seafloor, size, o);
    } catch (const LimitError& e) {
        throw LimitError(std::string("scene: the wave-field surface: ") + e.what() +
                         " (/surface/max_vertices); raise /field/min_resolved_depth or lower the resolution");
    }
    p.patch_triangles = std::move(mesh.triangles);
    p.rest_x = std::move(mesh.x);
    p.rest_y = std::move(mesh.y);
    p.loop_period = scene.waves[0].period;
}

struct State : ModelState {
    std::vector<std::complex<float>> eta;  // trains × vertices: η̂ at the rest vertices
    std::vector<float> broken;             // 1 where a train broke at the vertex
    std::vector<double> omega;             // per train, quantised to the loop
};

std::unique_ptr<ModelState> start(const Scene& scene, const ScenePlan& p, bool) {
    auto s = std::make_unique<State>();
    const std::size_t n = p.rest_x.size();
    s->eta.resize(p.wave_fields.size() * n);
    s->broken.assign(n, 0.0f);
    for (std::size_t t = 0; t < p.wave_fields.size(); ++t) {
        s->omega.push_back(quantize_frequency(2.0 * std::numbers::pi / scene.waves[t].period, p.loop_period));
        for (std::size_t v = 0; v < n; ++v) {
            const FieldSample f = sample_wave_field(p.wave_fields[t], p.rest_x[v], p.rest_y[v]);
            if (!f.wet || p.rest_depth[v] <= 0.0f) continue;
            s->eta[t * n + v] = std::complex<float>(f.eta);
            if (f.broken) s->broken[v] = 1.0f;
        }
    }
    return s;
}

bool move(const Scene&, const ScenePlan& p, double t, ModelState* state, ModelFrame& frame) {
    const State& s = *static_cast<const State*>(state);
    const std::size_t n = p.rest_x.size();
    for (std::size_t v = 0; v < n; ++v) {
        frame.positions[3 * v] = static_cast<float>(p.rest_x[v]);
        frame.positions[3 * v + 1] = static_cast<float>(p.rest_y[v]);
        frame.positions[3 * v + 2] = 0.0f;
    }
    for (std::size_t tr = 0; tr < s.omega.size(); ++tr) {
        // Re(η̂ e^{−iωt}) = Re η̂ cos ωt + Im η̂ sin ωt
        const float c = static_cast<float>(std::cos(s.omega[tr] * t)), sn = static_cast<float>(std::sin(s.omega[tr] * t));
        const std::complex<float>* eta = &s.eta[tr * n];
        for (std::size_t v = 0; v < n; ++v) frame.positions[3 * v + 2] += eta[v].real() * c + eta[v].imag() * sn;
    }
    return false;
}

// Foam where the field broke, on the crests: the share of the local amplitude the
// surface stands above its mean.
void foam(const Scene&, const ScenePlan& p, double t, ModelState* state, std::span<float> out) {
    const State& s = *static_cast<const State*>(state);
    const std::size_t n = p.rest_x.size();
    for (std::size_t v = 0; v < n; ++v) {
        if (s.broken[v] == 0.0f) continue;
        float z = 0.0f, a = 0.0f;
        for (std::size_t tr = 0; tr < s.omega.size(); ++tr) {
            const std::complex<float> e = s.eta[tr * n + v];
            z += e.real() * static_cast<float>(std::cos(s.omega[tr] * t)) + e.imag() * static_cast<float>(std::sin(s.omega[tr] * t));
            a += std::abs(e);
        }
        out[v] = a > 0.0f ? std::clamp(0.5f + 0.5f * z / a, 0.0f, 1.0f) : 0.0f;
    }
}

}  // namespace

extern const SurfaceModel kWaveFieldModel{
    .kind = SurfaceKind::wave_field,
    .name = "wave-field",
    .traced = Traced::field,
    .loop_keys = "/waves/0/period",
    .size_keys = "lower /field/nodes_per_wavelength or /animation/fps",
    .untangle = false,
    .overturns = nullptr,
    .far_field_harmonics = 1,
    .read_before = read_before,
    .read_after = [](const Node&, Scene&) {},
    .seafloor = [](const Scene& s) { return load_seafloor(s.seafloor); },
    .plan = plan,
    .triangles = [](const ScenePlan& p) -> const std::vector<std::uint32_t>& { return p.patch_triangles; },
    .start = start,
    .move = move,
    .foam = foam,
    .lips = nullptr,
    .draws_overturned = nullptr,
    .skirt_size = nullptr,
    .plan_skirt = nullptr,
    .foam_of_time_alone = false,
    .wind_sea_patch = false,
    .holds_boundary = nullptr,
    .whitewater = nullptr,
    .whitewater_source = {},
    .long_shot_keys = kWindSeaLoopKeys,
};

}  // namespace wave::detail
