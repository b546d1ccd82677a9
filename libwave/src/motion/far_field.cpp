// The far field (motion.h): the surface's border motion fitted by its periodic
// components and carried out over the sea skirt (docs/far-field.md).
#include "libwave/motion.h"

#include "core/smoothstep.h"
#include "libwave/errors.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <numbers>
#include <string>

extern "C" {
// LAPACK: minimum-norm least-squares solution of A X = B by the SVD (rank-deficient
// A allowed: components of equal frequency share their fit).
void dgelss_(const int* m, const int* n, const int* nrhs, double* a, const int* lda, double* b, const int* ldb, double* s,
             const double* rcond, int* rank, double* work, const int* lwork, int* info);
}

namespace wave {
namespace {

using Complex = std::complex<double>;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Least-squares fit of each anchor's displacement: columns [1, cos ω_c t, sin ω_c t …],
// right-hand sides x, y, z per anchor. Returns the solution, (1 + 2W) rows per rhs.
std::vector<double> fit_components(std::span<const double> omega, std::span<const double> times, std::span<const float> samples,
                                   std::span<const std::uint32_t> anchors, std::span<const double> rest_x,
                                   std::span<const double> rest_y, std::size_t surface_vertices) {
    const int m = static_cast<int>(times.size()), n = static_cast<int>(1 + 2 * omega.size());
    const int nrhs = static_cast<int>(3 * anchors.size());
    std::vector<double> a(static_cast<std::size_t>(m * n)), b(static_cast<std::size_t>(m) * static_cast<std::size_t>(nrhs));
    for (int s = 0; s < m; ++s) {
        a[static_cast<std::size_t>(s)] = 1.0;
        for (std::size_t c = 0; c < omega.size(); ++c) {
            const std::size_t rows = static_cast<std::size_t>(m), row = static_cast<std::size_t>(s);
            a[(1 + 2 * c) * rows + row] = std::cos(omega[c] * times[row]);
            a[(2 + 2 * c) * rows + row] = std::sin(omega[c] * times[row]);
        }
        const float* frame = &samples[static_cast<std::size_t>(s) * 3 * surface_vertices];
        for (std::size_t k = 0; k < anchors.size(); ++k) {
            const std::uint32_t v = anchors[k];
            const double rest[3] = {rest_x[v], rest_y[v], 0.0};
            for (std::size_t axis = 0; axis < 3; ++axis)
                b[(3 * k + axis) * static_cast<std::size_t>(m) + static_cast<std::size_t>(s)] = frame[3 * v + axis] - rest[axis];
        }
    }
    std::vector<double> sv(static_cast<std::size_t>(n));
    const double rcond = 1e-9;
    int rank = 0, info = 0, lwork = -1;
    double query = 0.0;
    dgelss_(&m, &n, &nrhs, a.data(), &m, b.data(), &m, sv.data(), &rcond, &rank, &query, &lwork, &info);
    lwork = static_cast<int>(query);
    std::vector<double> work(static_cast<std::size_t>(std::max(1, lwork)));
    dgelss_(&m, &n, &nrhs, a.data(), &m, b.data(), &m, sv.data(), &rcond, &rank, work.data(), &lwork, &info);
    if (info != 0) throw Error("far field: the least-squares fit failed (LAPACK dgelss info " + std::to_string(info) + ")");
    std::vector<double> x(static_cast<std::size_t>(n * nrhs));
    for (int r = 0; r < nrhs; ++r)
        for (int i = 0; i < n; ++i) {
            const std::size_t column = static_cast<std::size_t>(r), at = static_cast<std::size_t>(i);
            x[column * static_cast<std::size_t>(n) + at] = b[column * static_cast<std::size_t>(m) + at];
        }
    return x;
}

// Between the two anchors of an edge: modulus and phase each linear (a wave running
// along the border keeps its phase gradient; C linear would shrink it between nodes).
Complex along_edge(Complex a, Complex b, double wa) {
    if (wa >= 1.0 || b == a) return a;
    const double turn = std::remainder(std::arg(b) - std::arg(a), kTwoPi);
    return std::polar(wa * std::abs(a) + (1.0 - wa) * std::abs(b), std::arg(a) + (1.0 - wa) * turn);
}

}  // namespace

std::vector<double> far_field_sample_times(double loop_period, std::size_t components) {
    if (!(loop_period > 0.0) || !std::isfinite(loop_period))
        throw InputError("far field: the loop period must be > 0 s");
    std::vector<double> t(2 * components + 5);
    for (std::size_t s = 0; s < t.size(); ++s) t[s] = loop_period * std::fmod(0.6180339887498949 * static_cast<double>(s), 1.0);
    return t;
}

double far_field_share(double wavelength, double edge) noexcept {
    if (!(wavelength > 0.0)) return 0.0;
    return std::clamp((wavelength / 3.0 - edge) / (wavelength / 6.0), 0.0, 1.0);
}

FarFieldPlan plan_far_field(const SeaSkirt& skirt, const ElevationGrid& seafloor, std::span<const FarFieldWave> waves,
                            std::span<const double> rest_x, std::span<const double> rest_y, std::span<const double> times,
                            std::span<const float> samples, const FarFieldOptions& options) {
    const std::size_t n = skirt.surface_vertices, W = waves.size();
    if (rest_x.size() != n || rest_y.size() != n)
        throw InputError("far field: the rest positions hold " + std::to_string(rest_x.size()) + " vertices, the skirt's surface " +
                         std::to_string(n));
    if (samples.size() != 3 * n * times.size())
        throw InputError("far field: the samples hold " + std::to_string(samples.size()) + " floats, expected 3 · " +
                         std::to_string(n) + " per time");
    if (times.size() < 2 * W + 1)
        throw InputError("far field: " + std::to_string(times.size()) + " samples cannot fit " + std::to_string(W) +
                         " components (at least " + std::to_string(2 * W + 1) + ")");
    if (!(options.residual_wavelengths > 0.0)) throw InputError("far field: residual_wavelengths must be > 0");
    for (const FarFieldWave& w : waves)
        if (!(w.omega > 0.0) || w.harmonic < 1 || !(std::hypot(w.direction_x, w.direction_y) > 0.0) || !(w.k >= 0.0))
            throw InputError("far field: a component needs ω > 0, a harmonic >= 1, a direction and k >= 0");

    FarFieldPlan p;
    p.surface_vertices = n;
    for (const FarFieldWave& w : waves) p.omega.push_back(w.omega * w.harmonic);
    p.rest_x = skirt.x;
    p.rest_y = skirt.y;
    p.anchor_weight = skirt.anchor_weight;
    // Anchors, numbered by first use.
    std::map<std::uint32_t, std::uint32_t> number;
    p.anchor_slot.reserve(skirt.anchor.size());
    for (std::uint32_t v : skirt.anchor) {
        const auto [it, added] = number.emplace(v, static_cast<std::uint32_t>(p.anchor_vertex.size()));
        if (added) p.anchor_vertex.push_back(v);
        p.anchor_slot.push_back(it->second);
    }
    const std::size_t A = p.anchor_vertex.size(), M = 1 + 2 * W;
    const std::vector<double> fit = A > 0 ? fit_components(p.omega, times, samples, p.anchor_vertex, rest_x, rest_y, n)
                                          : std::vector<double>();
    // fit: per anchor and axis, M coefficients [mean, a_1, b_1, …].
    p.anchor_rest.resize(3 * A);
    p.anchor_amplitude.resize(6 * W * A);
    for (std::size_t k = 0; k < A; ++k)
        for (std::size_t axis = 0; axis < 3; ++axis) {
            const double* c = &fit[(3 * k + axis) * M];
            // The fitted mean only keeps the components unbiased: near the border the
            // skirt follows the anchors whole (mean set-up included), as a residual.
            p.anchor_rest[3 * k + axis] = static_cast<float>(axis == 0 ? rest_x[p.anchor_vertex[k]] : axis == 1 ? rest_y[p.anchor_vertex[k]] : 0.0);
            for (std::size_t w = 0; w < W; ++w) {
                p.anchor_amplitude[6 * (k * W + w) + 2 * axis] = static_cast<float>(c[1 + 2 * w]);
                p.anchor_amplitude[6 * (k * W + w) + 2 * axis + 1] = static_cast<float>(c[2 + 2 * w]);
            }
        }
    // Each skirt vertex: its anchors' amplitudes, carried out and faded.
    const std::size_t S = skirt.vertex_count();
    p.amplitude.assign(6 * W * S, 0.0f);
    p.residual_weight.resize(S);
    for (std::size_t v = 0; v < S; ++v) {
        const double d = skirt.distance[v], nx = skirt.normal_x[v], ny = skirt.normal_y[v];
        const double depth = depth_at(seafloor, skirt.x[v] - d * nx, skirt.y[v] - d * ny);
        const std::uint32_t a0 = p.anchor_slot[2 * v], a1 = p.anchor_slot[2 * v + 1];
        const double wa = skirt.anchor_weight[v];
        double first_wavelength = 0.0;
        // The depth half a skirt edge either way along the border (the foot's where dry).
        const double step = 0.5 * skirt.size[v];
        const double depth_minus = depth_at(seafloor, skirt.x[v] - d * nx + step * ny, skirt.y[v] - d * ny - step * nx);
        const double depth_plus = depth_at(seafloor, skirt.x[v] - d * nx - step * ny, skirt.y[v] - d * ny + step * nx);
        for (std::size_t w = 0; w < W; ++w) {
            const FarFieldWave& c = waves[w];
            const auto wavenumber = [&](double h) {
                return c.harmonic * (c.k > 0.0 ? c.k : h > 0.0 ? wavenumber_for_period(kTwoPi / c.omega, h) : 0.0);
            };
            const double k = wavenumber(depth);
            if (w == 0) first_wavelength = k > 0.0 ? kTwoPi / k : 0.0;
            if (!(k > 0.0)) continue;
            const double len = std::hypot(c.direction_x, c.direction_y);
            const double along_n = (c.direction_x * nx + c.direction_y * ny) / len, along_t = (c.direction_x * -ny + c.direction_y * nx) / len;
            // The carried phase k(s) (D̂·N) d varies along the border where the depth does:
            // its gradient there is (dk/ds)(D̂·N) d, which shortens the wave the skirt must
            // carry (on a beach met by the border, k ∝ 1/√h scrambled the phase between
            // neighbours a few centimetres apart).
            const double k_minus = depth_minus > 0.0 ? wavenumber(depth_minus) : k;
            const double k_plus = depth_plus > 0.0 ? wavenumber(depth_plus) : k;
            const double dk_ds = (k_plus - k_minus) / (2.0 * step);
            const double wavelength = kTwoPi / std::hypot(k * along_n, k * along_t + dk_ds * along_n * d);
            const double fade = far_field_share(wavelength, skirt.size[v]);
            if (fade == 0.0) continue;
            const Complex travel = std::polar(fade, k * along_n * d);
            for (std::size_t axis = 0; axis < 3; ++axis) {
                const auto at = [&](std::uint32_t anchor) {
                    const float* q = &p.anchor_amplitude[6 * (anchor * W + w) + 2 * axis];
                    return Complex(q[0], q[1]);
                };
                const Complex cv = along_edge(at(a0), at(a1), wa) * travel;
                p.amplitude[6 * (v * W + w) + 2 * axis] = static_cast<float>(cv.real());
                p.amplitude[6 * (v * W + w) + 2 * axis + 1] = static_cast<float>(cv.imag());
            }
        }
        const double band = first_wavelength > 0.0 ? options.residual_wavelengths * first_wavelength : 4.0 * skirt.size[v];
        p.residual_weight[v] = static_cast<float>(1.0 - detail::smoothstep(0.0, band, d));
    }
    return p;
}

void evaluate_far_field(const FarFieldPlan& p, double t, std::span<float> positions, std::vector<float>& scratch) {
    const std::size_t n = p.surface_vertices, S = p.vertex_count(), W = p.component_count(), A = p.anchor_vertex.size();
    if (positions.size() != 3 * (n + S))
        throw InputError("far field: positions hold " + std::to_string(positions.size()) + " floats, expected " +
                         std::to_string(3 * (n + S)));
    if (S == 0) return;
    double phase[64][2];  // cos, sin of ω t per component
    std::vector<double> many;
    double* cs = W <= 64 ? &phase[0][0] : (many.resize(2 * W), many.data());
    for (std::size_t w = 0; w < W; ++w) {
        const double wt = std::fmod(p.omega[w] * t, kTwoPi);
        cs[2 * w] = std::cos(wt);
        cs[2 * w + 1] = std::sin(wt);
    }
    // Re(C e^{−iωt}) = Re C cos ωt + Im C sin ωt.
    const auto wave_sum = [&](const float* amplitude, std::size_t axis) {
        double sum = 0.0;
        for (std::size_t w = 0; w < W; ++w) sum += amplitude[6 * w + 2 * axis] * cs[2 * w] + amplitude[6 * w + 2 * axis + 1] * cs[2 * w + 1];
        return sum;
    };
    // The anchors' residuals: their displacement less their components.
    scratch.resize(3 * A);
    for (std::size_t k = 0; k < A; ++k) {
        const std::uint32_t v = p.anchor_vertex[k];
        for (std::size_t axis = 0; axis < 3; ++axis)
            scratch[3 * k + axis] = static_cast<float>(positions[3 * v + axis] - p.anchor_rest[3 * k + axis] -
                                                       wave_sum(p.anchor_amplitude.data() + 6 * k * W, axis));
    }
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, S, 2048), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            const std::uint32_t a0 = p.anchor_slot[2 * v], a1 = p.anchor_slot[2 * v + 1];
            const double wa = p.anchor_weight[v], beta = p.residual_weight[v];
            const double rest[3] = {p.rest_x[v], p.rest_y[v], 0.0};
            for (std::size_t axis = 0; axis < 3; ++axis) {
                const double residual = wa * scratch[3 * a0 + axis] + (1.0 - wa) * scratch[3 * a1 + axis];
                positions[3 * (n + v) + axis] = static_cast<float>(rest[axis] + wave_sum(p.amplitude.data() + 6 * v * W, axis) + beta * residual);
            }
        }
    });
}

void far_field_foam(const FarFieldPlan& p, std::span<float> foam) {
    const std::size_t n = p.surface_vertices, S = p.vertex_count();
    if (foam.size() != n + S)
        throw InputError("far field: foam holds " + std::to_string(foam.size()) + " values, expected " + std::to_string(n + S));
    for (std::size_t v = 0; v < S; ++v) {
        const double wa = p.anchor_weight[v];
        const float a0 = foam[p.anchor_vertex[p.anchor_slot[2 * v]]], a1 = foam[p.anchor_vertex[p.anchor_slot[2 * v + 1]]];
        foam[n + v] = static_cast<float>(p.residual_weight[v] * (wa * a0 + (1.0 - wa) * a1));
    }
}

}  // namespace wave
