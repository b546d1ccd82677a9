// The glTF writer's precision: KHR_mesh_quantization's grid, Draco's bits and lattices
// (a far-field skirt's part on a lattice of its own), EXT_meshopt_compression's position
// steps and encoded triangles.
#include "gltf_model.h"

#include <cmath>

namespace wave::detail {

namespace {

// The largest power of two ≤ x, the smallest ≥ x (x > 0), exactly.
double power_of_two_below(double x) {
    int e = 0;
    std::frexp(x, &e);  // x = m · 2^e, m in [½, 1)
    return std::ldexp(1.0, e - 1);
}
double power_of_two_above(double x) {
    int e = 0;
    const double m = std::frexp(x, &e);
    return std::ldexp(1.0, m == 0.5 ? e - 1 : e);
}

constexpr double kExactSteps = 8388607.0;  // 2^23 − 1: Draco's float32 `q + ½` stays exact below it
// Draco hands an explicit grid's origin and range through text with six decimals
// (std::to_string in its Options): multiples of 2^-6 print exactly, finer steps do not.
constexpr double kDecimalStep = 0.015625;

}  // namespace

// Draco's grids span a primitive's whole extent. A far-field skirt reaches tens of km
// beyond the domain (docs/far-field.md), whose rest positions TEXCOORD_0 spans [0, 1]²:
// positions gain the bits that keep the domain's vertices on the step the options give
// over the domain's own extent, and the UV maps the bits that keep [0, 1]'s step (at
// most Draco's 30). Without a skirt nothing changes.
DracoOptions draco_bits_for_reach(const DracoOptions& o, std::span<const float> texcoords,
                                  const std::vector<detail::DracoInput>& inputs) {
    std::array<double, 2> uv_lo{0.0, 0.0}, uv_hi{1.0, 1.0};
    for (std::size_t i = 0; i < texcoords.size(); ++i)
        uv_lo[i % 2] = std::min(uv_lo[i % 2], double{texcoords[i]}), uv_hi[i % 2] = std::max(uv_hi[i % 2], double{texcoords[i]});
    const double uv_span = std::max(uv_hi[0] - uv_lo[0], uv_hi[1] - uv_lo[1]);
    if (!(uv_span > 1.0)) return o;
    const auto position = std::find_if(inputs.begin(), inputs.end(), [](const detail::DracoInput& in) { return in.name == "POSITION"; });
    double all = 0.0, domain = 0.0;  // the largest side of the bounding box: of every vertex, of the domain's
    if (position != inputs.end()) {
        std::array<double, 3> lo, hi, dlo, dhi;
        lo.fill(std::numeric_limits<double>::infinity()), dlo = lo;
        hi.fill(-std::numeric_limits<double>::infinity()), dhi = hi;
        for (std::size_t v = 0; 3 * v + 2 < position->values.size() && 2 * v + 1 < texcoords.size(); ++v) {
            const bool inside = texcoords[2 * v] >= 0.0f && texcoords[2 * v] <= 1.0f && texcoords[2 * v + 1] >= 0.0f &&
                                texcoords[2 * v + 1] <= 1.0f;
            for (std::size_t c = 0; c < 3; ++c) {
                const double x = position->values[3 * v + c];
                lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
                if (inside) dlo[c] = std::min(dlo[c], x), dhi[c] = std::max(dhi[c], x);
            }
        }
        for (std::size_t c = 0; c < 3; ++c) all = std::max(all, hi[c] - lo[c]), domain = std::max(domain, dhi[c] - dlo[c]);
    }
    const auto widen = [](int bits, double ratio) {
        return ratio > 1.0 ? std::min(30, bits + static_cast<int>(std::ceil(std::log2(ratio)))) : bits;
    };
    DracoOptions wide = o;
    wide.texcoord_bits = widen(o.texcoord_bits, uv_span);
    if (domain > 0.0) wide.position_bits = widen(o.position_bits, all / domain);
    return wide;
}

// The domain's part (a triangle whose corners' rest positions, TEXCOORD_0, all lie in
// [0, 1]²) and the skirt's (every other triangle). None without a skirt.
std::optional<std::array<SkirtPart, 2>> split_skirt(std::span<const float> texcoords, std::span<const std::uint32_t> triangles,
                                                    std::size_t n) {
    std::vector<char> inside(n);
    for (std::size_t v = 0; v < n; ++v)
        inside[v] = texcoords[2 * v] >= 0.0f && texcoords[2 * v] <= 1.0f && texcoords[2 * v + 1] >= 0.0f && texcoords[2 * v + 1] <= 1.0f;
    std::array<std::vector<char>, 2> used{std::vector<char>(n, 0), std::vector<char>(n, 0)};
    std::vector<char> part_of(triangles.size() / 3);
    for (std::size_t t = 0; t < part_of.size(); ++t) {
        const std::uint32_t* c = &triangles[3 * t];
        part_of[t] = inside[c[0]] && inside[c[1]] && inside[c[2]] ? 0 : 1;
        for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(part_of[t])][c[k]] = 1;
    }
    if (std::find(part_of.begin(), part_of.end(), 1) == part_of.end()) return std::nullopt;
    for (std::size_t v = 0; v < n; ++v)  // a vertex no triangle uses goes where its rest position lies
        if (!used[0][v] && !used[1][v]) used[inside[v] ? 0 : 1][v] = 1;
    std::array<SkirtPart, 2> parts;
    std::vector<std::uint32_t> local(n);
    for (std::size_t k = 0; k < 2; ++k) {
        for (std::size_t v = 0; v < n; ++v)
            if (used[k][v]) {
                local[v] = static_cast<std::uint32_t>(parts[k].vertices.size());
                parts[k].vertices.push_back(static_cast<std::uint32_t>(v));
                parts[k].seam.push_back(used[1 - k][v]);
            }
        for (std::size_t t = 0; t < part_of.size(); ++t)
            if (static_cast<std::size_t>(part_of[t]) == k)
                for (int c = 0; c < 3; ++c) parts[k].triangles.push_back(local[triangles[3 * t + static_cast<std::size_t>(c)]]);
    }
    return parts;
}

// The two parts' steps: the domain's the largest power of two at most its extent over
// 2^bits − 1 (the options' step), in units that make it at least 2^-6; the skirt's the
// smallest that keeps its reach under 2^23 steps and never finer than the domain's, so
// that the seam's points lie on both.
DracoLattice split_steps(std::span<const float> positions, const std::array<SkirtPart, 2>& parts, int bits) {
    std::array<double, 2> span{}, magnitude{};
    for (std::size_t k = 0; k < 2; ++k) {
        std::array<double, 3> lo, hi;
        lo.fill(std::numeric_limits<double>::infinity());
        hi.fill(-std::numeric_limits<double>::infinity());
        for (const std::uint32_t v : parts[k].vertices)
            for (std::size_t c = 0; c < 3; ++c) {
                const double x = positions[3 * v + c];
                lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
                magnitude[k] = std::max(magnitude[k], std::abs(x));
            }
        for (std::size_t c = 0; c < 3; ++c) span[k] = std::max(span[k], hi[c] - lo[c]);
    }
    DracoLattice l;
    const double wanted = power_of_two_below(std::max(span[0], 1e-6) / (std::ldexp(1.0, std::clamp(bits, 1, 30)) - 1.0));
    l.unit = std::min(1.0, wanted / kDecimalStep);
    for (std::size_t k = 0; k < 2; ++k) span[k] /= l.unit, magnitude[k] /= l.unit;
    l.domain = std::max(kDecimalStep, wanted / l.unit);
    l.skirt = std::max(l.domain, power_of_two_above(std::max(span[1], magnitude[1]) / (kExactSteps - 2.0)));
    // Snapping the seam to the skirt's step widens the domain's extent by up to one of them.
    while ((std::max(span[0], magnitude[0]) + l.skirt) / l.domain >= kExactSteps - 1.0) {
        l.domain *= 2.0;
        l.skirt = std::max(l.skirt, l.domain);
    }
    return l;
}

// Puts a part's positions (3 per vertex) on the lattice of `step` (the seam's on the
// lattice of `seam_step`, a multiple of it) and returns the grid that holds them.
detail::DracoGrid snap_to_lattice(std::span<float> positions, const std::vector<char>& seam, double step, double seam_step) {
    std::array<double, 3> lo, hi;
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < seam.size(); ++v) {
        const double s = seam[v] ? seam_step : step;
        for (std::size_t c = 0; c < 3; ++c) {
            const double x = std::round(double{positions[3 * v + c]} / s) * s;
            positions[3 * v + c] = static_cast<float>(x);  // exact: fewer than 2^24 steps from 0
            lo[c] = std::min(lo[c], x), hi[c] = std::max(hi[c], x);
        }
    }
    detail::DracoGrid grid;
    double steps = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        grid.origin[c] = static_cast<float>(lo[c]);
        steps = std::max(steps, (hi[c] - lo[c]) / step);
    }
    grid.bits = 1;
    while (std::ldexp(1.0, grid.bits) - 1.0 < steps) ++grid.bits;
    if (grid.bits > 23) throw InternalError("glTF export: a Draco lattice needs more than 23 bits");  // split_steps prevents it
    grid.range = static_cast<float>((std::ldexp(1.0, grid.bits) - 1.0) * step);
    return grid;
}

// `domain`: the vertices whose frames the grid spans (empty: all of them). Frames of
// their own with a far-field skirt span the domain's part only: the skirt's positions
// are floats in the same node frame (docs/far-field.md, "Quantised frames").
Quantization quantization_for(const MorphAnimationView& a, bool morph_targets, std::span<const std::uint32_t> domain) {
    std::array<double, 3> lo{}, hi{};
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    const std::size_t n = a.vertex_count;
    float p[3], p0[3];
    double delta = a.quantize_range.value_or(0.0);
    const bool scan_deltas = morph_targets && !a.quantize_range;
    const std::size_t per_frame = domain.empty() ? n : domain.size();
    for (std::size_t k = 0; n > 0 && k < a.positions.size() / 3 / n * per_frame; ++k) {
        const std::size_t i = domain.empty() ? k : k / per_frame * n + domain[k % per_frame];
        to_y_up(&a.positions[3 * i], p);
        for (std::size_t c = 0; c < 3; ++c) lo[c] = std::min(lo[c], double{p[c]}), hi[c] = std::max(hi[c], double{p[c]});
        if (scan_deltas && i >= n) {
            to_y_up(&a.positions[3 * (i % n)], p0);  // the base is the range's first frame
            for (std::size_t c = 0; c < 3; ++c) delta = std::max(delta, std::abs(double{p[c]} - double{p0[c]}));
        }
    }
    Quantization q;
    double half = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
        q.origin[c] = 0.5 * (lo[c] + hi[c]);
        half = std::max(half, 0.5 * (hi[c] - lo[c]));
    }
    q.float_base = morph_targets;
    // Float base positions keep the run's own coordinates (an extent's centre can lie
    // tens of km from the coast when a skirt reaches out on the sea side only).
    if (morph_targets) q.origin = {0.0, 0.0, 0.0};
    // A still animation keeps a 1 mm range (its deltas are all 0).
    q.scale = morph_targets ? std::max(delta, 1e-3) : std::max(half, 1e-6);
    return q;
}

// EXT_meshopt_compression's exponential filter: the step (log2 of metres) of each
// POSITION component in glTF axes. Horizontally the largest power of two at most
// 1/256 of the shortest horizontal edge of the view's first frame (the error, half a
// step, under 0.2 % of any edge); heights the finer of 2^-16 m and that step. A value
// too large for 24 bits at its step gets a coarser exponent of its own (a far skirt).
std::array<int, 3> meshopt_position_steps(const MorphAnimationView& a) {
    double shortest = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t + 2 < a.triangles.size(); t += 3)
        for (std::size_t k = 0; k < 3; ++k) {
            const float* p = &a.positions[3 * std::size_t{a.triangles[t + k]}];
            const float* q = &a.positions[3 * std::size_t{a.triangles[t + (k + 1) % 3]}];
            const double dx = double{p[0]} - q[0], dy = double{p[1]} - q[1], d2 = dx * dx + dy * dy;
            if (d2 > 0.0) shortest = std::min(shortest, d2);
        }
    shortest = std::sqrt(shortest);
    const int h = std::isfinite(shortest) ? std::clamp(static_cast<int>(std::floor(std::log2(shortest / 256.0))), -60, 40) : -12;
    const int z = std::min(-16, h);
    return {h, z, h};
}

// The triangles through meshoptimizer's index codec, encoded once for the frames of a
// files form that share them (the last list seen by this thread, compared whole).
const std::string& encoded_triangles(std::span<const std::uint32_t> triangles) {
    thread_local std::vector<std::uint32_t> last;
    thread_local std::string encoded;
    if (last.size() != triangles.size() || !std::equal(last.begin(), last.end(), triangles.begin())) {
        encoded = detail::meshopt_encode_triangles(triangles);
        last.assign(triangles.begin(), triangles.end());
    }
    return encoded;
}

}  // namespace wave::detail
