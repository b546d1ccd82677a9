// Kernel benchmarks of the bathymetry stage: bicubic depth + gradient queries, as the
// gradient-mode tracer will issue them once per ray step.
#include "libwave/bathymetry.h"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace {

void BM_sample_depth(benchmark::State& state) {
    const wave::Seafloor bay = wave::make_gonzato_bay();
    std::mt19937_64 rng(42);
    std::uniform_real_distribution<double> u(0.0, 100.0);
    std::vector<double> xy(2 * 4096);
    for (double& v : xy) v = u(rng);
    for (auto _ : state)
        for (std::size_t i = 0; i < xy.size(); i += 2)
            benchmark::DoNotOptimize(wave::sample_depth(bay.grid, xy[i], xy[i + 1]));
    state.SetItemsProcessed(state.iterations() * 4096);
}
BENCHMARK(BM_sample_depth);

void BM_read_okushiri(benchmark::State& state) {
    const std::string path = std::string(LIBWAVE_DATA_DIR) + "/bathymetry/okushiri_monai_lab1to400_1p4cm.asc";
    for (auto _ : state) benchmark::DoNotOptimize(wave::read_seafloor(path).grid.z.data());
}
BENCHMARK(BM_read_okushiri)->Unit(benchmark::kMillisecond);

}  // namespace
