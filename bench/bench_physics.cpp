// Kernel benchmarks of the physics stage.
#include "libwave/physics.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace {

std::vector<double> depths(std::size_t n) {  // log-spaced over h/L0 = 1e-4 … 10 at T = 8 s
    const double L0 = wave::kGravity * 64.0 / (2.0 * std::numbers::pi);
    std::vector<double> h(n);
    for (std::size_t i = 0; i < n; ++i) h[i] = L0 * std::pow(10.0, -4.0 + 5.0 * double(i) / double(n - 1));
    return h;
}

void BM_solve_dispersion(benchmark::State& state) {
    const auto h = depths(4096);
    const double omega = 2.0 * std::numbers::pi / 8.0;
    for (auto _ : state)
        for (double d : h) benchmark::DoNotOptimize(wave::solve_dispersion(omega, d).k);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(h.size()));
}
BENCHMARK(BM_solve_dispersion);

// Peer: plain bisection on the same relation to the same tolerance, the textbook
// alternative to Newton (Ts'o cites Newton's iteration for this).
void BM_bisection_peer(benchmark::State& state) {
    const auto h = depths(4096);
    const double omega = 2.0 * std::numbers::pi / 8.0;
    for (auto _ : state)
        for (double d : h) {
            double lo = omega * omega / wave::kGravity, hi = lo + omega / std::sqrt(wave::kGravity * d) + 1.0;
            while (hi - lo > 1e-14 * hi) {
                const double m = 0.5 * (lo + hi);
                (wave::kGravity * m * std::tanh(m * d) < omega * omega ? lo : hi) = m;
            }
            benchmark::DoNotOptimize(lo);
        }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(h.size()));
}
BENCHMARK(BM_bisection_peer);

void BM_fresnel_exact(benchmark::State& state) {
    std::vector<double> c(4096);
    for (std::size_t i = 0; i < c.size(); ++i) c[i] = double(i) / double(c.size() - 1);
    for (auto _ : state)
        for (double x : c) benchmark::DoNotOptimize(wave::fresnel_reflectivity(x));
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(c.size()));
}
BENCHMARK(BM_fresnel_exact);

void BM_fresnel_tso(benchmark::State& state) {
    std::vector<double> a(4096);
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = std::numbers::pi / 2 * double(i) / double(a.size() - 1);
    for (auto _ : state)
        for (double x : a) benchmark::DoNotOptimize(wave::fresnel_reflectivity_tso(x));
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(a.size()));
}
BENCHMARK(BM_fresnel_tso);

}  // namespace
