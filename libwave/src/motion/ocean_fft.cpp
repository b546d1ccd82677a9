// Tessendorf §3.3–3.7 per frame: h̃(k, t) (eq. 26), height, slope (eq. 20),
// choppy displacement (eq. 29) and the Jacobian (eqs. 30–34) by inverse real FFTs.
#include "core/memory.h"
#include "core/vector_clones.h"
#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/physics.h"

#include <fftw3.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <numbers>

namespace wave {

namespace {
// FFTW's planner is not thread-safe; execution with the new-array interface is.
std::mutex& planner_mutex() {
    static std::mutex m;
    return m;
}

// The inverse N² transform's plan, under the planner's lock. FFTW_ESTIMATE picks by a
// model of the machine and FFTW_MEASURE by timing (fastest, but another plan, so other
// bits, from run to run). The wisdom shipped with libwave holds, for every ocean
// resolution, the plan FFTW's patient planner found once (bench/fftw_wisdom.cpp): every
// run that finds it there computes the same bits, 1.7× faster at 1024² than the
// estimate. An FFTW that cannot read it (another version) falls back to the estimate.
// It is imported before every plan (~0.1 ms): a host that made FFTW forget its wisdom
// still gets the same bits.
fftwf_plan plan_inverse(std::size_t n, fftwf_complex* in, float* out) {
    const bool imported = fftwf_import_wisdom_from_string(
#include "ocean_fft_wisdom.inc"
                          ) != 0;
    const int size = static_cast<int>(n);
    fftwf_plan plan = imported ? fftwf_plan_dft_c2r_2d(size, size, in, out, FFTW_MEASURE | FFTW_WISDOM_ONLY) : nullptr;
    return plan ? plan : fftwf_plan_dft_c2r_2d(size, size, in, out, FFTW_ESTIMATE);
}

enum Field { kHeight, kSlopeX, kSlopeY, kDispX, kDispY, kDispXX, kDispYY, kDispXY, kFieldCount };
}  // namespace

struct OceanWorkspace::Impl {
    std::size_t n = 0, half = 0;
    fftwf_complex* spectrum[kFieldCount]{};
    float* field[kFieldCount]{};
    fftwf_plan plan = nullptr;
    std::vector<std::complex<float>> phase_table;  // e^{−i m ω0 t} of the frame
    std::vector<std::complex<float>> h;            // h̃(k, t) of the frame

    explicit Impl(std::size_t size) : n(size), half(size / 2 + 1), h(size * (size / 2 + 1)) {
        for (int f = 0; f < kFieldCount; ++f) {
            spectrum[f] = fftwf_alloc_complex(n * half);
            field[f] = fftwf_alloc_real(n * n);
            if (!spectrum[f] || !field[f]) release(), throw RuntimeError("ocean: out of memory for the FFT buffers");
            detail::advise_huge_pages(spectrum[f], n * half * sizeof(fftwf_complex));  // first touched by a frame
            detail::advise_huge_pages(field[f], n * n * sizeof(float));
        }
        const std::lock_guard lock(planner_mutex());
        plan = plan_inverse(n, spectrum[0], field[0]);
        if (!plan) release(), throw RuntimeError("ocean: FFTW could not plan a " + std::to_string(n) + "² transform");
    }
    ~Impl() { release(); }
    void release() noexcept {
        const std::lock_guard lock(planner_mutex());
        if (plan) fftwf_destroy_plan(plan);
        plan = nullptr;
        for (int f = 0; f < kFieldCount; ++f) {
            fftwf_free(spectrum[f]);
            fftwf_free(field[f]);
            spectrum[f] = nullptr;
            field[f] = nullptr;
        }
    }
};

OceanWorkspace::OceanWorkspace(std::size_t n) : impl_(std::make_unique<Impl>(n)) {}
OceanWorkspace::~OceanWorkspace() = default;
OceanWorkspace::OceanWorkspace(OceanWorkspace&&) noexcept = default;
OceanWorkspace& OceanWorkspace::operator=(OceanWorkspace&&) noexcept = default;

namespace {

double loop_time(const OceanPlan& plan, double t) {
    if (!(plan.repeat_time > 0.0)) return t;
    double r = std::fmod(t, plan.repeat_time);  // t = T gives exactly 0: frame T·fps is frame 0
    if (r < 0.0) r += plan.repeat_time;
    return r;
}

void check(const OceanPlan& plan, OceanWorkspace& ws) {
    if (plan.n == 0) throw InputError("ocean: the plan is empty (plan_ocean first)");
    if (plan.inv_k.size() != plan.n * plan.half() || plan.h0.size() != plan.inv_k.size())
        throw InputError("ocean: the plan's arrays do not hold N × (N/2 + 1) elements (plan_ocean makes them)");
    if (ws.impl().n != plan.n)
        throw InputError("ocean: a workspace for " + std::to_string(ws.impl().n) + "² used with a " +
                         std::to_string(plan.n) + "² plan");
}

// A run of one spectrum row: h̃(k, t) and 1/|k| (the plan's) at columns kx[0, count) of the row ky.
struct SpectrumChunk {
    std::size_t count = 0;
    const float* kx = nullptr;
    float ky = 0.0f;
    const std::complex<float>* h = nullptr;  // h̃(k, t), (re, im)
    const float* inv_k = nullptr;            // 1/|k|, 0 at k = 0
};

// One field's spectrum over a chunk, interleaved (re, im): a loop without calls or
// branches per field, vectorised (core/vector_clones.h).
LIBWAVE_VECTOR_CLONES void fill_spectrum(int field, const SpectrumChunk& c, float* __restrict out) {
    const float* __restrict kxs = c.kx;
    const float* __restrict h = reinterpret_cast<const float*>(c.h);
    const float* __restrict inverse_k = c.inv_k;
    const float ky = c.ky;
    // out = factor(kx, 1/k) · h̃, or · i h̃ = (−Im h̃, Re h̃), as the equations write it
    const auto fill = [&](bool times_i, auto factor) {
        for (std::size_t q = 0; q < c.count; ++q) {
            const float s = factor(kxs[q], inverse_k[q]);
            out[2 * q] = s * (times_i ? -h[2 * q + 1] : h[2 * q]);
            out[2 * q + 1] = s * (times_i ? h[2 * q] : h[2 * q + 1]);
        }
    };
    switch (field) {
        case kHeight: fill(false, [](float, float) { return 1.0f; }); break;  // eq. 19
        case kSlopeX: fill(true, [](float kx, float) { return kx; }); break;   // eq. 20
        case kSlopeY: fill(true, [ky](float, float) { return ky; }); break;
        case kDispX: fill(true, [](float kx, float inv_k) { return -kx * inv_k; }); break;  // eq. 29
        case kDispY: fill(true, [ky](float, float inv_k) { return -ky * inv_k; }); break;
        case kDispXX: fill(false, [](float kx, float inv_k) { return kx * kx * inv_k; }); break;  // ∂/∂x of eq. 29
        case kDispYY: fill(false, [ky](float, float inv_k) { return ky * ky * inv_k; }); break;
        default: fill(false, [ky](float kx, float inv_k) { return kx * ky * inv_k; }); break;
    }
}

// Eq. 26 over a chunk of a quantised lattice: h̃ = h̃0 e + h̃0₋ ē with e = e^{−i m ω0 t}
// from the table (re, im) at each element's m; complex products written out in float
// (as std::complex<float> computes them, without its NaN fallback call).
LIBWAVE_VECTOR_CLONES void evolve_quantised(const std::int32_t* __restrict steps, const float* __restrict table,
                                            const float* __restrict h0, const float* __restrict h0m, std::size_t count,
                                            float* __restrict h) {
    for (std::size_t q = 0; q < count; ++q) {
        const std::size_t m = static_cast<std::size_t>(steps[q]);
        const float c = table[2 * m], d = table[2 * m + 1];
        const float a = h0[2 * q], b = h0[2 * q + 1], e = h0m[2 * q], f = h0m[2 * q + 1];
        h[2 * q] = (a * c - b * d) + (e * c + f * d);
        h[2 * q + 1] = (a * d + b * c) + (f * c - e * d);
    }
}

// h̃(k, t) (eq. 26) over the half lattice into w.h.
void fill_h(const OceanPlan& plan, double t, OceanWorkspace::Impl& w) {
    const std::size_t n = plan.n, half = plan.half();
    const double tt = loop_time(plan, t);
    const bool quantised = !plan.omega_steps.empty();
    if (quantised) {
        // Every ω̄ is a multiple of ω0 (eq. 18): e^{−i m ω0 t} for the few m in use.
        const auto top = *std::max_element(plan.omega_steps.begin(), plan.omega_steps.end());
        const double omega0 = 2.0 * std::numbers::pi / plan.repeat_time;
        w.phase_table.resize(static_cast<std::size_t>(top) + 1);
        for (std::size_t m = 0; m < w.phase_table.size(); ++m)
            w.phase_table[m] = std::complex<float>(std::polar(1.0, -static_cast<double>(m) * omega0 * tt));
    }
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
        const std::size_t e0 = j * half;
        if (quantised) {
            evolve_quantised(plan.omega_steps.data() + e0, reinterpret_cast<const float*>(w.phase_table.data()),
                             reinterpret_cast<const float*>(plan.h0.data() + e0),
                             reinterpret_cast<const float*>(plan.h0_minus.data() + e0), half,
                             reinterpret_cast<float*>(w.h.data() + e0));
            return;
        }
        for (std::size_t e = e0; e < e0 + half; ++e) {
            const std::complex<float> ef(std::polar(1.0, -plan.omega[e] * tt));
            w.h[e] = plan.h0[e] * ef + plan.h0_minus[e] * std::conj(ef);  // eq. 26
        }
    });
}

// Fills the spectra of the fields in `fields` at time t and transforms them: h̃ once,
// then each field's spectrum and its transform in one task, so that the spectrum is
// still in cache when FFTW reads it (a frame's eight spectra together, 34 MB at 1024²,
// were not).
template <class Fields>
void transform(const OceanPlan& plan, double t, OceanWorkspace::Impl& w, const Fields& fields) {
    const std::size_t n = plan.n, half = plan.half();
    fill_h(plan, t, w);
    // One sequential fill and transform per field, the fields in parallel: bits
    // independent of threads.
    tbb::parallel_for(std::size_t{0}, std::size(fields), [&](std::size_t q) {
        const int f = fields[q];
        for (std::size_t j = 0; j < n; ++j) {
            const SpectrumChunk c{half, plan.kx.data(), plan.ky[j], w.h.data() + j * half, plan.inv_k.data() + j * half};
            fill_spectrum(f, c, reinterpret_cast<float*>(w.spectrum[f] + j * half));
        }
        fftwf_execute_dft_c2r(w.plan, w.spectrum[f], w.field[f]);
    });
}

std::span<const float> view(const OceanWorkspace::Impl& w, int f) { return {w.field[f], w.n * w.n}; }

}  // namespace

OceanFields evaluate_ocean(const OceanPlan& plan, double t, OceanWorkspace& ws) {
    check(plan, ws);
    static constexpr int all[] = {kHeight, kSlopeX, kSlopeY, kDispX, kDispY, kDispXX, kDispYY, kDispXY};
    auto& w = ws.impl();
    transform(plan, t, w, all);
    return {plan.n,           view(w, kHeight), view(w, kSlopeX), view(w, kSlopeY), view(w, kDispX),
            view(w, kDispY),  view(w, kDispXX), view(w, kDispYY), view(w, kDispXY)};
}

OceanJacobian ocean_jacobian(double dxx, double dyy, double dxy, double lambda) noexcept {
    // The map x → x − λD (eq. 30 with the sign of Gerstner's eq. 9).
    const double jxx = 1.0 - lambda * dxx, jyy = 1.0 - lambda * dyy, jxy = -lambda * dxy;
    OceanJacobian J;
    J.j = jxx * jyy - jxy * jxy;
    const double mean = 0.5 * (jxx + jyy), root = 0.5 * std::sqrt((jxx - jyy) * (jxx - jyy) + 4.0 * jxy * jxy);
    J.j_minus = mean - root;  // eq. 32
    J.j_plus = mean + root;
    if (std::abs(jxy) > 1e-12 * (std::abs(jxx) + std::abs(jyy) + 1e-300)) {
        const double q = (J.j_minus - jxx) / jxy;  // eq. 34
        const double len = std::sqrt(1.0 + q * q);
        J.e_minus = {1.0 / len, q / len};          // eq. 33
    } else {
        J.e_minus = jxx <= jyy ? std::array<double, 2>{1.0, 0.0} : std::array<double, 2>{0.0, 1.0};
    }
    return J;
}

void evaluate_ocean_jacobian(const OceanPlan& plan, double t, OceanWorkspace& ws, std::span<float> j_minus) {
    check(plan, ws);
    if (j_minus.size() != plan.n * plan.n) throw InputError("ocean: j_minus must hold N² values");
    static constexpr int three[] = {kDispXX, kDispYY, kDispXY};
    auto& w = ws.impl();
    transform(plan, t, w, three);
    OceanFields f;
    f.n = plan.n;
    f.disp_xx = view(w, kDispXX);
    f.disp_yy = view(w, kDispYY);
    f.disp_xy = view(w, kDispXY);
    ocean_jacobian_field(plan, f, j_minus);
}

namespace {

// The Jacobian of x → x − λD (eq. 30) at a point, and its J₋ (eq. 32), in float: the
// patch's vertices and the lattice's J₋ for the fold foam's past compute it alike
// (ocean_jacobian gives the same in double, with the eigenvector).
struct FloatJacobian {
    float xx, yy, xy;
    FloatJacobian(float lambda, float dxx, float dyy, float dxy) : xx(1.0f - lambda * dxx), yy(1.0f - lambda * dyy), xy(-lambda * dxy) {}
    float minus() const { return 0.5f * (xx + yy) - 0.5f * std::sqrt((xx - yy) * (xx - yy) + 4.0f * xy * xy); }
};

LIBWAVE_VECTOR_CLONES void j_minus_row(const float* __restrict dxx, const float* __restrict dyy,
                                       const float* __restrict dxy, std::size_t count, float lambda,
                                       float* __restrict out) {
    for (std::size_t i = 0; i < count; ++i) out[i] = FloatJacobian(lambda, dxx[i], dyy[i], dxy[i]).minus();
}

}  // namespace

void ocean_jacobian_field(const OceanPlan& plan, const OceanFields& f, std::span<float> j_minus) {
    const std::size_t n = plan.n;
    if (f.n != n || j_minus.size() != n * n) throw InputError("ocean: j_minus must hold N² values");
    const auto lambda = static_cast<float>(plan.choppiness);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
        const std::size_t i = j * n;
        j_minus_row(f.disp_xx.data() + i, f.disp_yy.data() + i, f.disp_xy.data() + i, n, lambda, j_minus.data() + i);
    });
}

namespace {

// One row of ocean_patch_frame's lattice: its fields from `in` on.
struct PatchRow {
    const float *height, *slope_x, *slope_y, *disp_x, *disp_y, *disp_xx, *disp_yy, *disp_xy;
};

// `count` vertices of a row from column `col0` on: positions (in double, then rounded),
// exact normals and (when jm is not null) J₋ (in float: eight lanes of roots and
// divisions instead of four). A loop without calls or branches, vectorised
// (core/vector_clones.h).
LIBWAVE_VECTOR_CLONES void patch_row(const PatchRow& f, std::size_t count, double d, double row, double lambda,
                                     float* __restrict positions, float* __restrict normals, float* __restrict jm,
                                     std::size_t col0 = 0) {
    const float *__restrict height = f.height, *__restrict sx = f.slope_x, *__restrict sy = f.slope_y;
    const float *__restrict dx = f.disp_x, *__restrict dy = f.disp_y;
    const float *__restrict dxx = f.disp_xx, *__restrict dyy = f.disp_yy, *__restrict dxy = f.disp_xy;
    const int first = static_cast<int>(col0);  // int: its conversion to double vectorises (N ≤ 4096)
    const auto l = static_cast<float>(lambda);
    for (std::size_t c = 0; c < count; ++c) {
        positions[3 * c] = static_cast<float>(d * static_cast<double>(first + static_cast<int>(c)) - lambda * dx[c]);
        positions[3 * c + 1] = static_cast<float>(d * row - lambda * dy[c]);
        positions[3 * c + 2] = height[c];
        // ∂P/∂x0 = (Jxx, Jxy, ∂h/∂x), ∂P/∂y0 = (Jxy, Jyy, ∂h/∂y): their cross product.
        const FloatJacobian J(l, dxx[c], dyy[c], dxy[c]);
        const float nx = J.xy * sy[c] - sx[c] * J.yy, ny = sx[c] * J.xy - J.xx * sy[c], nz = J.xx * J.yy - J.xy * J.xy;
        const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
        const float inv = len > 0.0f ? 1.0f / len : 0.0f;
        normals[3 * c] = nx * inv;
        normals[3 * c + 1] = ny * inv;
        normals[3 * c + 2] = len > 0.0f ? nz * inv : 1.0f;
    }
    if (!jm) return;
    for (std::size_t c = 0; c < count; ++c) jm[c] = FloatJacobian(l, dxx[c], dyy[c], dxy[c]).minus();
}

// Row `row` of the (N+1)² lattice into p, nr, jm (that row's own storage).
void patch_lattice_row(const OceanPlan& plan, const OceanFields& f, std::size_t row, float* p, float* nr, float* jm) {
    const std::size_t n = plan.n;
    const double d = plan.spacing(), lambda = plan.choppiness;
    const std::size_t src = (row == n ? 0 : row) * n;  // the last row repeats the first
    const PatchRow in{f.height.data() + src,  f.slope_x.data() + src, f.slope_y.data() + src,
                      f.disp_x.data() + src,  f.disp_y.data() + src,  f.disp_xx.data() + src,
                      f.disp_yy.data() + src, f.disp_xy.data() + src};
    patch_row(in, n, d, static_cast<double>(row), lambda, p, nr, jm);
    // the last column repeats the first (its x one patch further)
    patch_row(in, 1, d, static_cast<double>(row), lambda, p + 3 * n, nr + 3 * n, jm ? jm + n : nullptr, n);
}

void check_patch(const OceanPlan& plan, const OceanFields& f, std::size_t rows, std::span<float> positions,
                 std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1, count = rows * side;
    if (f.n != plan.n || positions.size() != 3 * count || normals.size() != 3 * count ||
        (!j_minus.empty() && j_minus.size() != count))
        throw InputError("ocean: the patch frame needs (N+1) vertices a row: 3 floats each for positions and normals");
}

}  // namespace

void ocean_patch_frame(const OceanPlan& plan, const OceanFields& f, std::span<float> positions,
                       std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1;
    check_patch(plan, f, side, positions, normals, j_minus);
    tbb::parallel_for(std::size_t{0}, side, [&](std::size_t row) {
        patch_lattice_row(plan, f, row, positions.data() + 3 * row * side, normals.data() + 3 * row * side,
                          j_minus.empty() ? nullptr : j_minus.data() + row * side);
    });
}

void ocean_patch_rows(const OceanPlan& plan, const OceanFields& f, std::size_t first_row, std::size_t rows,
                      std::span<float> positions, std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1;
    if (first_row > side || rows > side - first_row)
        throw InputError("ocean: rows " + std::to_string(first_row) + " + " + std::to_string(rows) + " beyond the patch's " +
                         std::to_string(side));
    check_patch(plan, f, rows, positions, normals, j_minus);
    for (std::size_t r = 0; r < rows; ++r)
        patch_lattice_row(plan, f, first_row + r, positions.data() + 3 * r * side, normals.data() + 3 * r * side,
                          j_minus.empty() ? nullptr : j_minus.data() + r * side);
}

namespace {

// Catmull–Rom weights for the fraction u in [0, 1).
std::array<double, 4> catmull_rom(double u) noexcept {
    const double u2 = u * u, u3 = u2 * u;
    return {0.5 * (-u3 + 2.0 * u2 - u), 0.5 * (3.0 * u3 - 5.0 * u2 + 2.0), 0.5 * (-3.0 * u3 + 4.0 * u2 + u),
            0.5 * (u3 - u2)};
}

struct Taps {
    std::size_t index[16];
    double weight[16];
};

Taps periodic_taps(std::size_t n, double spacing, double x, double y) noexcept {
    const double u = x / spacing, v = y / spacing;
    const double fu = std::floor(u), fv = std::floor(v);
    const auto wu = catmull_rom(u - fu), wv = catmull_rom(v - fv);
    const long long N = static_cast<long long>(n);
    // The lattice row and column of each tap, wrapped (c is a whole number: c mod N by
    // integers, as fmod would give it, once per row and column rather than per tap).
    const auto wrap = [N](double c, long long o) {
        const long long q = (static_cast<long long>(c) % N + o) % N;
        return static_cast<std::size_t>(q < 0 ? q + N : q);
    };
    std::array<std::size_t, 4> row{}, col{};
    for (int k = 0; k < 4; ++k) row[static_cast<std::size_t>(k)] = wrap(fv, k - 1) * n, col[static_cast<std::size_t>(k)] = wrap(fu, k - 1);
    Taps t{};
    for (std::size_t b = 0; b < 4; ++b)
        for (std::size_t a = 0; a < 4; ++a) {
            t.index[4 * b + a] = row[b] + col[a];
            t.weight[4 * b + a] = wu[a] * wv[b];
        }
    return t;
}

double tap_sum(const Taps& t, std::span<const float> field) noexcept {
    double s = 0.0;
    for (int q = 0; q < 16; ++q) s += t.weight[q] * field[t.index[q]];
    return s;
}

}  // namespace

void add_ocean_samples(const OceanPlan& plan, const OceanFields& f, std::span<const double> x, std::span<const double> y,
                       std::span<const float> scale, std::span<float> positions) {
    const std::size_t count = x.size();
    if (f.n != plan.n || y.size() != count || positions.size() != 3 * count || (!scale.empty() && scale.size() != count))
        throw InputError("ocean: add_ocean_samples needs x, y (and scale) per vertex and 3 floats of positions per vertex");
    const double lambda = plan.choppiness, d = plan.spacing();
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t v) {
        const double s = scale.empty() ? 1.0 : static_cast<double>(scale[v]);
        if (s == 0.0) return;
        const Taps t = periodic_taps(plan.n, d, x[v], y[v]);
        positions[3 * v] += static_cast<float>(-s * lambda * tap_sum(t, f.disp_x));
        positions[3 * v + 1] += static_cast<float>(-s * lambda * tap_sum(t, f.disp_y));
        positions[3 * v + 2] += static_cast<float>(s * tap_sum(t, f.height));
    });
}

void sample_ocean_field(const OceanPlan& plan, std::span<const float> field, std::span<const double> x,
                        std::span<const double> y, std::span<const float> scale, std::span<float> out) {
    const std::size_t count = x.size();
    if (field.size() != plan.n * plan.n || y.size() != count || out.size() != count ||
        (!scale.empty() && scale.size() != count))
        throw InputError("ocean: sample_ocean_field needs an N² field and x, y, out (and scale) per point");
    const double d = plan.spacing();
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t v) {
        const double value = tap_sum(periodic_taps(plan.n, d, x[v], y[v]), field);
        // J₋ of x → x − sλD is 1 + s (J₋ − 1) for a constant s.
        out[v] = static_cast<float>(scale.empty() ? value : 1.0 + static_cast<double>(scale[v]) * (value - 1.0));
    });
}

double wind_sea_depth_factor(double peak_omega, double depth) noexcept {
    return std::sqrt(kitaigorodskii_depth_factor(peak_omega, depth));
}

double gerstner_steepness(std::span<const GerstnerWave> waves) noexcept {
    double s = 0.0;
    for (const auto& w : waves) s += std::hypot(w.kx, w.ky) * w.amplitude;
    return s;
}

void add_gerstner_waves(std::span<const GerstnerWave> waves, std::span<const double> x, std::span<const double> y,
                        std::span<const float> depth, double t, std::span<float> positions) {
    const std::size_t count = x.size();
    if (y.size() != count || positions.size() != 3 * count || (!depth.empty() && depth.size() != count))
        throw InputError("gerstner: x, y (and depth) per vertex and 3 floats of positions per vertex");
    tbb::parallel_for(std::size_t{0}, count, [&](std::size_t v) {
        double dx = 0.0, dy = 0.0, dz = 0.0;
        for (const auto& w : waves) {
            const double k = std::hypot(w.kx, w.ky);
            if (!(k > 0.0)) continue;
            const double a = w.amplitude * (depth.empty() ? 1.0 : wind_sea_depth_factor(w.omega, depth[v]));
            const double theta = w.kx * x[v] + w.ky * y[v] - w.omega * t + w.phase;
            const double s = std::sin(theta), c = std::cos(theta);
            dx -= w.kx / k * a * s;  // eq. 12
            dy -= w.ky / k * a * s;
            dz += a * c;             // eq. 13
        }
        positions[3 * v] += static_cast<float>(dx);
        positions[3 * v + 1] += static_cast<float>(dy);
        positions[3 * v + 2] += static_cast<float>(dz);
    });
}

}  // namespace wave
