// Jeschke's breakers at the paper's scale and at the issue's: the paper drew 10 breaking
// waves on ~50 000 screen-space points at 35 frames/s (Pentium 4, 2003); the target here
// is 1 000 000 points with 10 waves at >= 30 frames/s on 2 cores (positions + normals +
// foam). The scene: the planar beach (1:20) with a 4 s swell — about ten crests between
// the offshore edge and the shore — sampled by Hinsinger's camera grid.
#include <benchmark/benchmark.h>

#include "libwave/motion.h"
#include "libwave/scene.h"
#include "libwave/shade.h"

#include <string>
#include <vector>

namespace {

struct Fixture {
    wave::Scene scene;
    wave::ScenePlan plan;
};

// pixel_step 1 on 1280 × 800: ~1 M points; step 4 on 1024 × 768 is the paper's ~50 000.
const Fixture& fixture(int points) {
    static Fixture big, small;
    Fixture& f = points > 100000 ? big : small;
    if (f.plan.rest_x.empty()) {
        const std::string image = points > 100000 ? "[1280, 800], \"pixel_step\": 1" : "[1024, 768], \"pixel_step\": 4";
        f.scene = wave::parse_scene(R"({"seafloor": {"source": "planar-beach"}, "isobaths": {"spacing": 0.5},
            "waves": [{"period": 4, "amplitude": 0.3, "direction": [0, 1]}], "trace": {"ray_spacing": 2},
            "breakers": "jeschke", "camera": {"position": [100, -40, 70]},
            "surface": {"kind": "ray-strips", "camera_grid": {"look_at": [100, 90, 0], "vertical_fov_degrees": 60,
            "image": )" + image + "}}}",
                                    "bench.json", ".");
        f.plan = wave::plan_scene(f.scene);
    }
    return f;
}

// Runs `frame(t)` once per iteration at 30 frames/s of animation time and reports the
// points and the frame rate.
template <class Frame>
void frames_at_30fps(benchmark::State& state, std::size_t points, Frame&& frame) {
    double t = 0.0;
    for (auto _ : state) {
        frame(t);
        t += 1.0 / 30.0;
    }
    state.counters["points"] = static_cast<double>(points);
    state.counters["frames/s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_jeschke_positions(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    const std::size_t n = f.plan.breakers.vertex_count();
    std::vector<float> p(3 * n);
    frames_at_30fps(state, n, [&](double t) {
        wave::evaluate_jeschke_breakers(f.plan.breakers, t, p);
        benchmark::DoNotOptimize(p.data());
    });
}
BENCHMARK(BM_jeschke_positions)->Arg(50000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The peer of BM_jeschke_positions: the same plan on the paper's curve (breakers.lip
// "tube": no outer sections), in the same run.
void BM_jeschke_positions_tube(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    wave::JeschkeMotionPlan tube = f.plan.breakers;
    tube.sections = {};
    std::vector<float> p(3 * tube.vertex_count());
    frames_at_30fps(state, tube.vertex_count(), [&](double t) {
        wave::evaluate_jeschke_breakers(tube, t, p);
        benchmark::DoNotOptimize(p.data());
    });
}
BENCHMARK(BM_jeschke_positions_tube)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The peer of BM_jeschke_positions with per-vertex life starts (a plan whose rays re-form
// behind a bar reads one per vertex; here all 0, the same positions), in the same run.
void BM_jeschke_positions_life_starts(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    wave::JeschkeMotionPlan lives = f.plan.breakers;
    lives.life_start.assign(lives.vertex_count(), 0.0f);
    std::vector<float> p(3 * lives.vertex_count());
    frames_at_30fps(state, lives.vertex_count(), [&](double t) {
        wave::evaluate_jeschke_breakers(lives, t, p);
        benchmark::DoNotOptimize(p.data());
    });
}
BENCHMARK(BM_jeschke_positions_life_starts)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Tabulating the outer sections once per plan (the default curls: 0.25 … 1).
void BM_breaker_sections(benchmark::State& state) {
    for (auto _ : state) benchmark::DoNotOptimize(wave::plan_breaker_sections(0.3, 1.0).x.data());
}
BENCHMARK(BM_breaker_sections)->Unit(benchmark::kMillisecond)->UseRealTime();

// §3.1 foam alone (with the per-wave variation: the recent crests' lives at each point).
void BM_jeschke_foam(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    const std::size_t n = f.plan.breakers.vertex_count();
    std::vector<float> foam(n);
    frames_at_30fps(state, n, [&](double t) {
        wave::jeschke_foam(f.plan.breakers, t, foam);
        benchmark::DoNotOptimize(foam.data());
    });
}
BENCHMARK(BM_jeschke_foam)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// §5 normals alone on the breakers' surface (accumulated face normals, parallel gather).
void BM_jeschke_normals(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    const std::size_t n = f.plan.breakers.vertex_count();
    std::vector<float> p(3 * n), nr(3 * n);
    const wave::VertexFaces adjacency = wave::vertex_faces(n, f.plan.camera_grid.triangles);
    wave::evaluate_jeschke_breakers(f.plan.breakers, 2.0, p);
    frames_at_30fps(state, n, [&](double) {
        wave::vertex_normals(p, f.plan.camera_grid.triangles, adjacency, nr);
        benchmark::DoNotOptimize(nr.data());
    });
}
BENCHMARK(BM_jeschke_normals)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// What a renderer needs each frame: positions, area-weighted normals (§5) and foam (§3.1).
void BM_jeschke_frame(benchmark::State& state) {
    const Fixture& f = fixture(static_cast<int>(state.range(0)));
    const std::size_t n = f.plan.breakers.vertex_count();
    std::vector<float> p(3 * n), nr(3 * n), foam(n);
    const wave::VertexFaces adjacency = wave::vertex_faces(n, f.plan.camera_grid.triangles);  // once per topology
    frames_at_30fps(state, n, [&](double t) {
        wave::evaluate_jeschke_breakers(f.plan.breakers, t, p);
        wave::vertex_normals(p, f.plan.camera_grid.triangles, adjacency, nr);
        wave::jeschke_foam(f.plan.breakers, t, foam);
        benchmark::DoNotOptimize(nr.data());
        benchmark::DoNotOptimize(foam.data());
    });
}
BENCHMARK(BM_jeschke_frame)->Arg(50000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

// Gonzato's profile on its own strips, per point, for comparison.
void BM_gonzato_positions_strips(benchmark::State& state) {
    const Fixture& f = fixture(1000000);
    const std::size_t n = f.plan.motion.vertex_count();
    std::vector<float> p(3 * n);
    frames_at_30fps(state, n, [&](double t) {
        wave::evaluate_gonzato_motion(f.plan.motion, t, p);
        benchmark::DoNotOptimize(p.data());
    });
}
BENCHMARK(BM_gonzato_positions_strips)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
