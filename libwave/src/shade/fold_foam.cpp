// Foam from the folding of Tessendorf's choppy map (§3.7, eqs. 30–32), faded over time
// without history: the past is looked up on a fixed time lattice, not remembered.
#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/shade.h"
#include "core/vector_clones.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <vector>

namespace wave {

double fold_coverage(double j_minus, const FoldFoamOptions& o) noexcept {
    return std::clamp((o.threshold - j_minus) / o.softness, 0.0, 1.0);
}

double fold_fade(double age, const FoldFoamOptions& o) noexcept {
    if (age < 0.0 || age >= o.window) return 0.0;
    const double floor = std::exp(-o.window / o.fade_time);
    return (std::exp(-age / o.fade_time) - floor) / (1.0 - floor);
}

std::vector<long long> fold_lattice(double t, const FoldFoamOptions& o, double repeat_time, double& step) {
    step = o.lattice_step;
    if (repeat_time > 0.0) step = repeat_time / std::max(1.0, std::round(repeat_time / o.lattice_step));
    const auto last = static_cast<long long>(std::floor(t / step + 1e-9));
    std::vector<long long> out;
    for (long long j = last; static_cast<double>(j) * step > t - o.window; --j) out.push_back(j);
    return out;
}

namespace {

// fold_coverage(J₋) · w of `count` values (its expression: the same bits), for both
// accumulate_fold_foam: a loop without calls or branches, vectorised
// (core/vector_clones.h), apart from the maxima it feeds.
LIBWAVE_VECTOR_CLONES void weighted_coverage(const float* __restrict j_minus, std::size_t count, double threshold,
                                             double softness, double w, float* __restrict out) {
    for (std::size_t i = 0; i < count; ++i)
        out[i] = static_cast<float>(std::clamp((threshold - j_minus[i]) / softness, 0.0, 1.0) * w);
}

// out[vertex[q]] = max(out[vertex[q]], value[q]) for distinct vertices: the maxima
// gathered first, then stored unconditionally (a store only where the value is larger
// made a branch the CPU could not predict).
LIBWAVE_VECTOR_CLONES void scatter_max(const std::uint32_t* __restrict vertex, float* __restrict value, std::size_t count,
                                       float* out) {
    for (std::size_t q = 0; q < count; ++q) value[q] = std::max(out[vertex[q]], value[q]);
    for (std::size_t q = 0; q < count; ++q) out[vertex[q]] = value[q];
}

// Whether `count` (> 0) vertex indices ascend strictly from above `previous` and stay
// below `end`: the ends against the bounds, each neighbour against the next.
LIBWAVE_VECTOR_CLONES bool ascending_below(const std::uint32_t* __restrict vertex, std::size_t count,
                                           std::int64_t previous, std::int64_t end) {
    unsigned out_of_order = 0;
    for (std::size_t q = 0; q + 1 < count; ++q) out_of_order |= vertex[q] >= vertex[q + 1] ? 1u : 0u;
    return out_of_order == 0 && static_cast<std::int64_t>(vertex[0]) > previous &&
           static_cast<std::int64_t>(vertex[count - 1]) < end;
}

}  // namespace

void accumulate_fold_foam(std::span<const float> j_minus, double age, const FoldFoamOptions& o, std::span<float> foam) {
    if (j_minus.size() != foam.size())
        throw InputError("shade: j_minus holds " + std::to_string(j_minus.size()) + " values, foam " +
                         std::to_string(foam.size()));
    const double w = fold_fade(age, o);
    if (w <= 0.0) return;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, foam.size(), 4096), [&](const auto& r) {
        float value[256];
        for (std::size_t v0 = r.begin(); v0 < r.end(); v0 += std::size(value)) {
            const std::size_t size = std::min(std::size(value), r.end() - v0);
            weighted_coverage(j_minus.data() + v0, size, o.threshold, o.softness, w, value);
            for (std::size_t q = 0; q < size; ++q) foam[v0 + q] = std::max(foam[v0 + q], value[q]);
        }
    });
}

FoldSample fold_sample(std::span<const float> j_minus, const FoldFoamOptions& o) {
    FoldSample s;
    for (std::size_t v = 0; v < j_minus.size(); ++v) {
        if (!(j_minus[v] < o.threshold)) continue;  // coverage 0 (also for NaN)
        s.vertex.push_back(static_cast<std::uint32_t>(v));
        s.j_minus.push_back(j_minus[v]);
    }
    return s;
}


void accumulate_fold_foam(std::span<const AgedFoldSample> samples, const FoldFoamOptions& o, std::span<float> foam) {
    struct Live {
        const FoldSample* sample;
        double w;
    };
    std::vector<Live> live;
    for (const AgedFoldSample& a : samples) {
        if (!a.sample) throw InputError("shade: a null fold sample");
        const std::size_t count = a.sample->vertex.size();
        if (a.sample->j_minus.size() != count)
            throw InputError("shade: a fold sample holds " + std::to_string(count) + " vertices and " +
                             std::to_string(a.sample->j_minus.size()) + " J₋ values");
        live.push_back({a.sample, fold_fade(a.age, o)});  // w = 0 (out of the window): checked, adds nothing
    }
    // Blocks of vertices, in parallel; each sample's entries in a block found by binary
    // search, and checked where they are used (ascending, inside the block, below the
    // foam's end) rather than in a pass of their own. The boundaries of one sample are
    // found first: they must not decrease, so that every entry lies in exactly one block.
    // Max commutes: the same bits for any thread count and any order of the samples.
    constexpr std::size_t kBlock = 16384;
    const std::size_t blocks = std::max<std::size_t>(1, (foam.size() + kBlock - 1) / kBlock);
    std::vector<std::size_t> bounds(live.size() * (blocks + 1));
    for (std::size_t i = 0; i < live.size(); ++i) {
        const auto& vertex = live[i].sample->vertex;
        std::size_t* const b = bounds.data() + i * (blocks + 1);
        b[0] = 0;
        b[blocks] = vertex.size();
        for (std::size_t k = 1; k < blocks; ++k)
            b[k] = static_cast<std::size_t>(std::lower_bound(vertex.begin(), vertex.end(), k * kBlock) - vertex.begin());
        for (std::size_t k = 0; k < blocks; ++k)
            if (b[k + 1] < b[k]) throw InputError("shade: a fold sample's vertices do not ascend");
    }
    std::atomic<bool> bad{false};
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t k) {
        const auto first = static_cast<std::int64_t>(k * kBlock);
        const auto end = static_cast<std::int64_t>(k + 1 == blocks ? foam.size() : (k + 1) * kBlock);
        float value[256];
        for (std::size_t i = 0; i < live.size(); ++i) {
            const FoldSample& sample = *live[i].sample;
            const std::size_t* const b = bounds.data() + i * (blocks + 1);
            std::int64_t previous = first - 1;
            for (std::size_t e = b[k]; e < b[k + 1]; e += std::size(value)) {
                const std::size_t size = std::min(std::size(value), b[k + 1] - e);
                const std::uint32_t* const vertex = sample.vertex.data() + e;
                if (!ascending_below(vertex, size, previous, end)) {
                    bad = true;
                    return;
                }
                previous = vertex[size - 1];
                if (live[i].w <= 0.0) continue;
                weighted_coverage(sample.j_minus.data() + e, size, o.threshold, o.softness, live[i].w, value);
                scatter_max(vertex, value, size, foam.data());
            }
        }
    });
    if (bad) throw InputError("shade: a fold sample's vertices do not ascend, or lie beyond the foam array");
}

void accumulate_fold_foam(const FoldSample& sample, double age, const FoldFoamOptions& o, std::span<float> foam) {
    const AgedFoldSample one{&sample, age};
    accumulate_fold_foam(std::span<const AgedFoldSample>(&one, 1), o, foam);
}

double fold_threshold_for_coverage(std::span<const std::vector<float>> past, double step, const FoldFoamOptions& options,
                                   double coverage, std::size_t stride) {
    if (past.empty() || past.back().empty()) throw InputError("fold foam: no J₋ samples to calibrate the threshold on");
    if (!(coverage >= 0.0 && coverage <= 1.0))
        throw InputError("fold foam: coverage must be in [0, 1], got " + detail::format_number(coverage));
    const std::size_t n = past.back().size(), times = past.size();
    for (const auto& j : past)
        if (j.size() != n) throw InputError("fold foam: J₋ samples of different sizes");
    stride = std::max<std::size_t>(1, stride);
    std::vector<double> fade(times);
    for (std::size_t i = 0; i < times; ++i) fade[i] = fold_fade(static_cast<double>(times - 1 - i) * step, options);
    const auto covered = [&](double threshold) {
        FoldFoamOptions o = options;
        o.threshold = threshold;
        std::size_t count = 0, total = 0;
        for (std::size_t v = 0; v < n; v += stride, ++total) {
            double foam = 0.0;
            for (std::size_t i = 0; i < times && foam < 0.1; ++i) foam = std::max(foam, fold_coverage(past[i][v], o) * fade[i]);
            count += foam >= 0.1 ? 1 : 0;
        }
        return static_cast<double>(count) / static_cast<double>(total);
    };
    double lo = -2.0, hi = 1.0;
    if (coverage <= 0.0) return lo;
    if (covered(hi) < coverage) return hi;
    // A point has foam ≥ 0.1 from the threshold J + 0.1 · softness / fade of its most
    // favourable past time on (one whose fade reaches 0.1; coverage is at most 1): the
    // answer is the k-th smallest of these, k = ⌈coverage · points⌉ — one pass and a
    // selection, where bisection took 40 passes (a 4096² lattice: half a minute).
    std::vector<double> critical;
    critical.reserve(n / stride + 1);
    for (std::size_t v = 0; v < n; v += stride) {
        double c = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < times; ++i)
            if (fade[i] >= 0.1 && past[i][v] == past[i][v]) c = std::min(c, past[i][v] + 0.1 * options.softness / fade[i]);
        critical.push_back(c);
    }
    const auto k = static_cast<std::size_t>(std::ceil(coverage * static_cast<double>(critical.size()))) - 1;
    std::nth_element(critical.begin(), critical.begin() + static_cast<std::ptrdiff_t>(std::min(k, critical.size() - 1)), critical.end());
    double threshold = std::clamp(critical[std::min(k, critical.size() - 1)], lo, hi);
    // Rounding in the frames' own expression (covered) may leave that point a hair under
    // 0.1: nudge up, and fall back to bisection above if that does not do it.
    threshold = std::min(hi, threshold + 1e-9 * (1.0 + std::abs(threshold)));
    if (covered(threshold) >= coverage) return threshold;
    lo = threshold;
    for (int halving = 0; halving < 40; ++halving) {
        const double mid = 0.5 * (lo + hi);
        (covered(mid) >= coverage ? hi : lo) = mid;
    }
    return hi;
}

void validate_fold_foam(const FoldFoamOptions& o, const std::string& where) {
    const auto fail = [&](const char* field, const std::string& what) { throw InputError(where + "/" + field + ": " + what); };
    const auto f = [](double v) { return detail::format_number(v); };
    if (!std::isfinite(o.threshold)) fail("fold_threshold", "expected a finite J₋");
    if (!(o.softness > 0.0) || !std::isfinite(o.softness)) fail("fold_softness", "expected a number > 0, got " + f(o.softness));
    if (!(o.fade_time > 0.0) || !std::isfinite(o.fade_time)) fail("foam_fade_time", "expected a time > 0 s, got " + f(o.fade_time));
    if (!(o.window > 0.0) || !std::isfinite(o.window)) fail("fold_window", "expected a time > 0 s, got " + f(o.window));
    if (!(o.lattice_step > 0.0) || o.lattice_step > o.window)
        fail("fold_lattice_step", "expected a time in (0, window], got " + f(o.lattice_step));
    // Each frame looks back at window / lattice_step past times per vertex: bounded, so
    // a tiny step is refused here rather than computed for hours.
    if (o.window / o.lattice_step > kMaxFoldLatticeTimes)
        fail("fold_lattice_step", "window / lattice_step = " + f(o.window / o.lattice_step) + " past times per frame; at most " +
                                      std::to_string(kMaxFoldLatticeTimes) + " (raise fold_lattice_step or lower fold_window)");
}

}  // namespace wave
