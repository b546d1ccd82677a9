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
#include <utility>

namespace wave {

namespace {
// FFTW's planner is not thread-safe; execution with the new-array interface is.
std::mutex& planner_mutex() {
    static std::mutex m;
    return m;
}

// The inverse N² complex transform's plan (in place), under the planner's lock.
// FFTW_ESTIMATE picks by a model of the machine and FFTW_MEASURE by timing (fastest,
// but another plan, so other bits, from run to run). The wisdom shipped with libwave
// holds, for every ocean resolution, the plan FFTW's patient planner found once
// (bench/fftw_wisdom.cpp): every run that finds it there computes the same bits. An
// FFTW that cannot read it (another version) falls back to the estimate. It is
// imported before every plan (~0.1 ms): a host that made FFTW forget its wisdom still
// gets the same bits.
fftwf_plan plan_inverse(std::size_t n, fftwf_complex* data) {
    const bool imported = fftwf_import_wisdom_from_string(
#include "ocean_fft_wisdom.inc"
                          ) != 0;
    const int size = static_cast<int>(n);
    fftwf_plan plan = imported ? fftwf_plan_dft_2d(size, size, data, data, FFTW_BACKWARD, FFTW_MEASURE | FFTW_WISDOM_ONLY) : nullptr;
    return plan ? plan : fftwf_plan_dft_2d(size, size, data, data, FFTW_BACKWARD, FFTW_ESTIMATE);
}

// The eight real fields in four pairs, each pair one complex transform: the spectrum
// A + iB of fields a, b transforms to a + ib (both real), so the output holds a and b
// interleaved. The Jacobian's three fields are the first two pairs.
enum Pair { kJacobianPair, kShearHeightPair, kSlopePair, kDisplacementPair, kPairCount };
}  // namespace

struct OceanWorkspace::Impl {
    std::size_t n = 0, half = 0;
    fftwf_complex* pair[kPairCount]{};  // N² each: a pair's spectrum, then (in place) its two fields
    std::vector<float> mirror[kPairCount];  // a spectrum row's mirror, before it is written in reverse
    fftwf_plan plan = nullptr;
    std::vector<std::complex<float>> phase_table;  // e^{−i m ω0 t} of the frame
    std::vector<std::complex<float>> h;            // h̃(k, t) of the frame

    explicit Impl(std::size_t size) : n(size), half(size / 2 + 1), h(size * (size / 2 + 1)) {
        for (int f = 0; f < kPairCount; ++f) {
            mirror[f].resize(2 * half);
            pair[f] = fftwf_alloc_complex(n * n);
            if (!pair[f]) release(), throw RuntimeError("ocean: out of memory for the FFT buffers");
            detail::advise_huge_pages(pair[f], n * n * sizeof(fftwf_complex));  // first touched by a frame
        }
        const std::lock_guard lock(planner_mutex());
        plan = plan_inverse(n, pair[0]);
        if (!plan) release(), throw RuntimeError("ocean: FFTW could not plan a " + std::to_string(n) + "² transform");
    }
    ~Impl() { release(); }
    void release() noexcept {
        const std::lock_guard lock(planner_mutex());
        if (plan) fftwf_destroy_plan(plan);
        plan = nullptr;
        for (int f = 0; f < kPairCount; ++f) {
            fftwf_free(pair[f]);
            pair[f] = nullptr;
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

// One row of a pair's spectrum, interleaved (re, im): a loop without calls or branches
// per pair, vectorised (core/vector_clones.h). Fields a, b have the spectra A = s_a h̃,
// B = s_b h̃ (or i s_a h̃, i s_b h̃, as the equations write them) with real factors s of
// k; their pair's spectrum C = A + iB = z h̃ with z = s_a + i s_b (or i z). C holds the
// whole lattice: row j's columns [0, count) from h̃ there, and, for the columns
// strictly between 0 and the Nyquist column, the mirror C(−k) = conj(A) + i conj(B) =
// ±z conj(h̃) at column N − q of row −j (`mirror`, that row's start). Column 0's rows
// j and −j are both in the half lattice; the Nyquist column and row are 0 (plan_ocean).
LIBWAVE_VECTOR_CLONES void fill_pair_row(int pair, const SpectrumChunk& c, float* __restrict row, float* __restrict mirror,
                                         float* __restrict scratch) {
    const float* __restrict kxs = c.kx;
    const float* __restrict h = reinterpret_cast<const float*>(c.h);
    const float* __restrict inverse_k = c.inv_k;
    const float ky = c.ky;
    const std::size_t n = 2 * (c.count - 1);
    // z(kx, 1/k) as (re, im); `sign` is +1 for fields of real factors (even in k), −1 for i·s (odd).
    const auto fill = [&](float sign, auto z) {
        for (std::size_t q = 0; q < c.count; ++q) {
            const auto [zr, zi] = z(kxs[q], inverse_k[q]);
            row[2 * q] = zr * h[2 * q] - zi * h[2 * q + 1];
            row[2 * q + 1] = zr * h[2 * q + 1] + zi * h[2 * q];
            scratch[2 * q] = sign * (zr * h[2 * q] + zi * h[2 * q + 1]);
            scratch[2 * q + 1] = sign * (zi * h[2 * q] - zr * h[2 * q + 1]);
        }
        for (std::size_t col = c.count; col < n; ++col) {  // from q = N/2 − 1 down to 1
            mirror[2 * col] = scratch[2 * (n - col)];
            mirror[2 * col + 1] = scratch[2 * (n - col) + 1];
        }
    };
    using Z = std::pair<float, float>;
    switch (pair) {
        case kJacobianPair:  // ∂/∂x of eq. 29's Dx, ∂/∂y of its Dy
            fill(1.0f, [ky](float kx, float inv_k) { return Z{kx * kx * inv_k, ky * ky * inv_k}; });
            break;
        case kShearHeightPair:  // ∂Dx/∂y, and h (eq. 19)
            fill(1.0f, [ky](float kx, float inv_k) { return Z{kx * ky * inv_k, 1.0f}; });
            break;
        case kSlopePair:  // eq. 20: i kx h̃, i ky h̃
            fill(-1.0f, [ky](float kx, float) { return Z{-ky, kx}; });
            break;
        default:  // eq. 29: D = −i k/|k| h̃, both components
            fill(-1.0f, [ky](float kx, float inv_k) { return Z{ky * inv_k, -kx * inv_k}; });
            break;
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

// Fills the spectra of the pairs in `pairs` at time t and transforms them: h̃ once, then
// each pair's spectrum and its transform in one task, so that the spectrum is still in
// cache when FFTW reads it.
template <class Pairs>
void transform(const OceanPlan& plan, double t, OceanWorkspace::Impl& w, const Pairs& pairs) {
    const std::size_t n = plan.n, half = plan.half();
    fill_h(plan, t, w);
    // One sequential fill and transform per pair, the pairs in parallel: bits
    // independent of threads.
    tbb::parallel_for(std::size_t{0}, std::size(pairs), [&](std::size_t q) {
        const int p = pairs[q];
        float* out = reinterpret_cast<float*>(w.pair[p]);
        for (std::size_t j = 0; j < n; ++j) {
            const SpectrumChunk c{half, plan.kx.data(), plan.ky[j], w.h.data() + j * half, plan.inv_k.data() + j * half};
            fill_pair_row(p, c, out + 2 * j * n, out + 2 * ((n - j) % n) * n, w.mirror[p].data());
        }
        fftwf_execute_dft(w.plan, w.pair[p], w.pair[p]);
    });
}

// Field `second` (0: a, 1: b) of a pair's output.
OceanField view(const OceanWorkspace::Impl& w, int pair, std::size_t second) {
    return {reinterpret_cast<const float*>(w.pair[pair]) + second, 2, w.n * w.n};
}

// The four pairs' outputs, (a, b) interleaved, as evaluate_ocean lays the fields out —
// the layout the lattice passes read (the Jacobian's two pairs alone unless `whole`);
// `what` names the caller in the refusal.
struct PairRows {
    const float* jacobian;      // ∂Dx/∂x, ∂Dy/∂y
    const float* shear_height;  // ∂Dx/∂y, h
    const float* slope;         // ∂h/∂x, ∂h/∂y
    const float* displacement;  // Dx, Dy
};
PairRows pair_rows(const OceanFields& f, const char* what, bool whole) {
    const auto pair = [&](const OceanField& a, const OceanField& b) {
        const std::size_t cells = f.n * f.n;
        return a.data && a.stride == 2 && b.stride == 2 && b.data == a.data + 1 && a.count == cells && b.count == cells;
    };
    if (!pair(f.disp_xx, f.disp_yy) || !pair(f.disp_xy, f.height) || (whole && (!pair(f.slope_x, f.slope_y) || !pair(f.disp_x, f.disp_y))))
        throw InputError(std::string("ocean: ") + what + " reads the fields as evaluate_ocean lays them out (pairs interleaved)");
    return {f.disp_xx.data, f.disp_xy.data, f.slope_x.data, f.disp_x.data};
}

}  // namespace

std::vector<float> OceanField::values() const {
    std::vector<float> v(count);
    for (std::size_t q = 0; q < count; ++q) v[q] = data[q * stride];
    return v;
}

OceanFields evaluate_ocean(const OceanPlan& plan, double t, OceanWorkspace& ws) {
    check(plan, ws);
    static constexpr int all[] = {kJacobianPair, kShearHeightPair, kSlopePair, kDisplacementPair};
    auto& w = ws.impl();
    transform(plan, t, w, all);
    return {plan.n,
            view(w, kShearHeightPair, 1),
            view(w, kSlopePair, 0),
            view(w, kSlopePair, 1),
            view(w, kDisplacementPair, 0),
            view(w, kDisplacementPair, 1),
            view(w, kJacobianPair, 0),
            view(w, kJacobianPair, 1),
            view(w, kShearHeightPair, 0)};
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
    static constexpr int two[] = {kJacobianPair, kShearHeightPair};
    auto& w = ws.impl();
    transform(plan, t, w, two);
    OceanFields f;
    f.n = plan.n;
    f.disp_xx = view(w, kJacobianPair, 0);
    f.disp_yy = view(w, kJacobianPair, 1);
    f.disp_xy = view(w, kShearHeightPair, 0);
    f.height = view(w, kShearHeightPair, 1);
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

// J₋ from a row of the Jacobian's pair (∂Dx/∂x, ∂Dy/∂y) and of (∂Dx/∂y, h).
LIBWAVE_VECTOR_CLONES void j_minus_row(const float* __restrict jacobian, const float* __restrict shear, std::size_t count,
                                       float lambda, float* __restrict out) {
    for (std::size_t i = 0; i < count; ++i)
        out[i] = FloatJacobian(lambda, jacobian[2 * i], jacobian[2 * i + 1], shear[2 * i]).minus();
}

}  // namespace

void ocean_jacobian_field(const OceanPlan& plan, const OceanFields& f, std::span<float> j_minus) {
    const std::size_t n = plan.n;
    if (f.n != n || j_minus.size() != n * n) throw InputError("ocean: j_minus must hold N² values");
    const PairRows in = pair_rows(f, "ocean_jacobian_field", false);
    const auto lambda = static_cast<float>(plan.choppiness);
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t j) {
        const std::size_t i = j * n;
        j_minus_row(in.jacobian + 2 * i, in.shear_height + 2 * i, n, lambda, j_minus.data() + i);
    });
}

namespace {

// `count` vertices of a row from column `col0` on, its pairs from `in` on: positions
// (in double, then rounded), exact normals and (when jm is not null) J₋ (in float: eight
// lanes of roots and divisions instead of four). A loop without calls or branches,
// vectorised (core/vector_clones.h); each pair read as one interleaved stream.
LIBWAVE_VECTOR_CLONES void patch_row(const PairRows& in, std::size_t count, double d, double row, double lambda,
                                     float* __restrict positions, float* __restrict normals, float* __restrict jm,
                                     std::size_t col0 = 0) {
    const float *__restrict jac = in.jacobian, *__restrict sh = in.shear_height;
    const float *__restrict slope = in.slope, *__restrict disp = in.displacement;
    const int first = static_cast<int>(col0);  // int: its conversion to double vectorises (N ≤ 4096)
    const auto l = static_cast<float>(lambda);
    for (std::size_t c = 0; c < count; ++c) {
        const std::size_t q = 2 * c;
        const float dx = disp[q], dy = disp[q + 1], sx = slope[q], sy = slope[q + 1], height = sh[q + 1];
        positions[3 * c] = static_cast<float>(d * static_cast<double>(first + static_cast<int>(c)) - lambda * dx);
        positions[3 * c + 1] = static_cast<float>(d * row - lambda * dy);
        positions[3 * c + 2] = height;
        // ∂P/∂x0 = (Jxx, Jxy, ∂h/∂x), ∂P/∂y0 = (Jxy, Jyy, ∂h/∂y): their cross product.
        const FloatJacobian J(l, jac[q], jac[q + 1], sh[q]);
        const float nx = J.xy * sy - sx * J.yy, ny = sx * J.xy - J.xx * sy, nz = J.xx * J.yy - J.xy * J.xy;
        const float len = std::sqrt(nx * nx + ny * ny + nz * nz);
        const float inv = len > 0.0f ? 1.0f / len : 0.0f;
        normals[3 * c] = nx * inv;
        normals[3 * c + 1] = ny * inv;
        normals[3 * c + 2] = len > 0.0f ? nz * inv : 1.0f;
    }
    if (!jm) return;
    for (std::size_t c = 0; c < count; ++c) jm[c] = FloatJacobian(l, jac[2 * c], jac[2 * c + 1], sh[2 * c]).minus();
}

// Row `row` of the (N+1)² lattice into p, nr, jm (that row's own storage).
void patch_lattice_row(const OceanPlan& plan, const PairRows& pairs, std::size_t row, float* p, float* nr, float* jm) {
    const std::size_t n = plan.n;
    const double d = plan.spacing(), lambda = plan.choppiness;
    const std::size_t src = 2 * (row == n ? 0 : row) * n;  // the last row repeats the first
    const PairRows in{pairs.jacobian + src, pairs.shear_height + src, pairs.slope + src, pairs.displacement + src};
    patch_row(in, n, d, static_cast<double>(row), lambda, p, nr, jm);
    // the last column repeats the first (its x one patch further)
    patch_row(in, 1, d, static_cast<double>(row), lambda, p + 3 * n, nr + 3 * n, jm ? jm + n : nullptr, n);
}

PairRows check_patch(const OceanPlan& plan, const OceanFields& f, std::size_t rows, std::span<float> positions,
                     std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1, count = rows * side;
    if (f.n != plan.n || positions.size() != 3 * count || normals.size() != 3 * count ||
        (!j_minus.empty() && j_minus.size() != count))
        throw InputError("ocean: the patch frame needs (N+1) vertices a row: 3 floats each for positions and normals");
    return pair_rows(f, "the patch", true);
}

}  // namespace

void ocean_patch_frame(const OceanPlan& plan, const OceanFields& f, std::span<float> positions,
                       std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1;
    const PairRows pairs = check_patch(plan, f, side, positions, normals, j_minus);
    tbb::parallel_for(std::size_t{0}, side, [&](std::size_t row) {
        patch_lattice_row(plan, pairs, row, positions.data() + 3 * row * side, normals.data() + 3 * row * side,
                          j_minus.empty() ? nullptr : j_minus.data() + row * side);
    });
}

void ocean_patch_rows(const OceanPlan& plan, const OceanFields& f, std::size_t first_row, std::size_t rows,
                      std::span<float> positions, std::span<float> normals, std::span<float> j_minus) {
    const std::size_t side = plan.n + 1;
    if (first_row > side || rows > side - first_row)
        throw InputError("ocean: rows " + std::to_string(first_row) + " + " + std::to_string(rows) + " beyond the patch's " +
                         std::to_string(side));
    const PairRows pairs = check_patch(plan, f, rows, positions, normals, j_minus);
    for (std::size_t r = 0; r < rows; ++r)
        patch_lattice_row(plan, pairs, first_row + r, positions.data() + 3 * r * side, normals.data() + 3 * r * side,
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

template <class Field>
double tap_sum(const Taps& t, const Field& field) noexcept {
    double s = 0.0;
    for (int q = 0; q < 16; ++q) s += t.weight[q] * field[t.index[q]];
    return s;
}

}  // namespace

void add_ocean_samples(const OceanPlan& plan, const OceanFields& f, std::span<const double> x, std::span<const double> y,
                       std::span<const float> scale, std::span<float> positions) {
    const std::size_t count = x.size();
    const std::size_t cells = plan.n * plan.n;
    if (f.n != plan.n || y.size() != count || positions.size() != 3 * count || (!scale.empty() && scale.size() != count))
        throw InputError("ocean: add_ocean_samples needs x, y (and scale) per vertex and 3 floats of positions per vertex");
    if (!f.disp_x.data || !f.disp_y.data || !f.height.data || f.disp_x.size() != cells || f.disp_y.size() != cells ||
        f.height.size() != cells)
        throw InputError("ocean: add_ocean_samples needs the frame's fields of N² values");
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
