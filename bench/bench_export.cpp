// Export speed per frame at the sizes of the Blender figures (66 k and 1 M
// vertices): the morph form (per frame of a 10-frame file), one static frame file,
// and a Draco-compressed frame file; bytes per vertex are reported as counters.
#include "libwave/export.h"
#include "libwave/shade.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace {

// A wavy grid of side × side vertices with `frames` frames, normals and shading.
struct Grid {
    std::size_t side, n, frames;
    std::vector<std::uint32_t> tri;
    std::vector<float> pos, nrm, uv, r, t, foam;
    Grid(std::size_t side_, std::size_t frames_) : side(side_), n(side_ * side_), frames(frames_) {
        for (std::size_t j = 0; j + 1 < side; ++j)
            for (std::size_t i = 0; i + 1 < side; ++i) {
                const auto a = static_cast<std::uint32_t>(j * side + i), s = static_cast<std::uint32_t>(side);
                tri.insert(tri.end(), {a, a + 1, a + s + 1, a, a + s + 1, a + s});
            }
        pos.resize(3 * n * frames);
        nrm.resize(pos.size());
        for (std::size_t f = 0; f < frames; ++f) {
            for (std::size_t v = 0; v < n; ++v) {
                const double x = static_cast<double>(v % side) * 0.1, y = static_cast<double>(v / side) * 0.1;
                pos[3 * (f * n + v)] = static_cast<float>(x);
                pos[3 * (f * n + v) + 1] = static_cast<float>(y);
                pos[3 * (f * n + v) + 2] = static_cast<float>(0.3 * std::sin(0.8 * x + 0.3 * y - 0.5 * static_cast<double>(f)));
            }
            wave::vertex_normals(std::span(pos).subspan(3 * n * f, 3 * n), tri, std::span(nrm).subspan(3 * n * f, 3 * n));
        }
        uv.resize(2 * n);
        for (std::size_t v = 0; v < n; ++v) {
            uv[2 * v] = static_cast<float>(v % side) / static_cast<float>(side - 1);
            uv[2 * v + 1] = static_cast<float>(v / side) / static_cast<float>(side - 1);
        }
        r.assign(n * frames, 0.05f);
        t.assign(n * frames, 0.95f);
        foam.assign(n * frames, 0.0f);
    }
    wave::MorphAnimationView view() const {
        wave::MorphAnimationView a;
        a.triangles = tri;
        a.vertex_count = n;
        a.frame_count = frames;
        a.positions = pos;
        a.normals = nrm;
        a.texcoords = uv;
        a.reflect = r;
        a.refract = t;
        a.foam = foam;
        return a;
    }
};

std::size_t side_for(std::int64_t vertices) { return static_cast<std::size_t>(std::lround(std::sqrt(double(vertices)))); }

// Morph form: one file of 10 frames; time and bytes per frame.
void BM_export_morph(benchmark::State& state) {
    const Grid g(side_for(state.range(0)), 10);
    wave::MorphAnimationView v = g.view();
    v.quantize = state.range(1) != 0;
    std::size_t bytes = 0;
    for (auto _ : state) bytes = wave::gltf_morph_glb(v).size();
    state.SetLabel(v.quantize ? "quantized" : "float");
    state.counters["frames_per_s"] = benchmark::Counter(10.0, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["bytes_per_vertex_frame"] = static_cast<double>(bytes) / static_cast<double>(g.n * 10);
    state.counters["vertices"] = static_cast<double>(g.n);
}
BENCHMARK(BM_export_morph)->Args({66'049, 0})->Args({66'049, 1})->Args({1'000'000, 0})->Args({1'000'000, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

// Files form: one static frame, plain or Draco (default bits).
void BM_export_frame_file(benchmark::State& state) {
    const Grid g(side_for(state.range(0)), 1);
    wave::MorphAnimationView v = g.view();
    if (state.range(1)) v.draco = wave::DracoOptions{};
    std::size_t bytes = 0;
    for (auto _ : state) bytes = wave::gltf_frame_glb(v, 0).size();
    state.counters["frames_per_s"] = benchmark::Counter(1.0, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["bytes_per_vertex"] = static_cast<double>(bytes) / static_cast<double>(g.n);
    state.SetLabel(state.range(1) ? "draco" : "plain");
}
BENCHMARK(BM_export_frame_file)
    ->Args({66'049, 0})->Args({66'049, 1})->Args({1'000'000, 0})->Args({1'000'000, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
