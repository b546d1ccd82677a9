// Where the rays cannot give the wave — the gaps they leave, and the tears where one
// layer of rays gives way to another — the refraction–diffraction field gives it
// (surface.h, fill_strip_gaps; docs/wave-field.md, "Where the rays leave off").
#include "libwave/surface.h"

#include "libwave/field.h"
#include "libwave/physics.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <tuple>
#include <vector>

namespace wave {
namespace {

using cd = std::complex<double>;

// What each vertex of the resampled strips takes.
enum class Source : std::uint8_t {
    still,  // no wave (land, or outside the field's water)
    ray,    // the rays' own wave; anchors the phase offset
    field,  // the field's wave: a gap or a tear's band
};

// The rays' phase offsets φ_ray − arg η̂ relative to their circular mean, unwrapped
// along the mesh's edges between the rays' vertices (breadth first from the lowest
// index of each connected group): continuous within a group, so that two groups half a
// wave apart (a tear) get offsets that differ by about π rather than a mix of ±π.
std::vector<double> unwrapped_offsets(const RayStrips& s, const std::vector<Source>& source, const std::vector<cd>& offset,
                                      cd mean, const VertexFaces& around) {
    const std::size_t n = s.vertex_count();
    std::vector<double> out(n, 0.0);
    std::vector<std::uint8_t> seen(n, 0);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t start = 0; start < n; ++start) {
        if (source[start] != Source::ray || seen[start]) continue;
        out[start] = std::arg(offset[start] / mean);
        seen[start] = 1;
        queue.assign(1, start);
        for (std::size_t q = 0; q < queue.size(); ++q) {
            const std::uint32_t v = queue[q];
            for (std::uint32_t f = around.offsets[v]; f < around.offsets[v + 1]; ++f)
                for (int c = 0; c < 3; ++c) {
                    const std::uint32_t u = s.triangles[3 * around.faces[f] + c];
                    if (source[u] != Source::ray || seen[u]) continue;
                    out[u] = out[v] + std::arg(offset[u] / offset[v]);
                    seen[u] = 1;
                    queue.push_back(u);
                }
        }
    }
    return out;
}

// The rays' values continued over the field's vertices by a screened Laplace equation
// on the mesh: Σ_j w_ij (u_i − u_j) + σ_i (u_i − target_i) = 0, w_ij = 1/|e_ij|²,
// σ_i = deg_i/(16 λ_i²) (λ_i the local wavelength: a screening length of about 2λ).
// Next to the rays u is theirs, so crests run on across the seam; far from them it
// relaxes to the target, smoothed over wavelengths (the field's own direction varies
// from node to node where two trains cross). A shorter screening (λ) pulled the offset
// back to the mean within a tear's band and stepped it by 0.46 rad along an edge. Two quantities share one sparse Cholesky factorisation (Eigen's
// SimplicialLDLT: symmetric, positive definite): the unwrapped phase offset (target 0,
// the mean) and the direction as a complex number (target the field's), made unit.
struct Continued {
    std::vector<double> offset;  // rad, relative to the mean
    std::vector<cd> direction;   // unit
};
Continued continued_values(const RayStrips& s, const std::vector<Source>& source, const Continued& ray,
                           const std::vector<cd>& target_direction, const std::vector<double>& wavelength) {
    const std::size_t n = s.vertex_count();
    std::vector<std::int64_t> unknown(n, -1);
    std::int64_t count = 0;
    for (std::size_t v = 0; v < n; ++v)
        if (source[v] == Source::field) unknown[v] = count++;
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> diagonal(static_cast<std::size_t>(count), 0.0);
    std::vector<int> degree(static_cast<std::size_t>(count), 0);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(count, 3);
    const auto add = [&](std::int64_t row, double w, double offset, cd direction) {
        rhs(row, 0) += w * offset;
        rhs(row, 1) += w * direction.real();
        rhs(row, 2) += w * direction.imag();
    };
    // Each triangle's edges; an interior edge is met twice, so each meeting counts half.
    for (std::size_t t = 0; t < s.triangle_count(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = s.triangles[3 * t + c], b = s.triangles[3 * t + (c + 1) % 3];
            const double w = 0.5 / (std::pow(s.x[a] - s.x[b], 2) + std::pow(s.y[a] - s.y[b], 2));
            if (!std::isfinite(w)) continue;
            for (auto [i, j] : {std::pair{a, b}, std::pair{b, a}}) {
                if (unknown[i] < 0 || source[j] == Source::still) continue;
                const auto row = static_cast<std::size_t>(unknown[i]);
                diagonal[row] += w;
                ++degree[row];
                if (unknown[j] >= 0) entries.emplace_back(unknown[i], unknown[j], -w);
                else add(unknown[i], w, ray.offset[j], ray.direction[j]);
            }
        }
    for (std::size_t v = 0; v < n; ++v) {
        if (unknown[v] < 0) continue;
        const auto row = static_cast<std::size_t>(unknown[v]);
        // deg counts each edge twice (once per triangle): halve it as the weights were.
        const double screen = 0.5 * std::max(degree[row], 2) / (16.0 * wavelength[v] * wavelength[v]);
        entries.emplace_back(unknown[v], unknown[v], diagonal[row] + screen);
        add(unknown[v], screen, 0.0, target_direction[v]);
    }
    Eigen::SparseMatrix<double> system(count, count);
    system.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
    const Eigen::MatrixXd u = solver.solve(rhs);
    Continued out = ray;
    for (std::size_t v = 0; v < n; ++v)
        if (unknown[v] >= 0) {
            out.offset[v] = u(unknown[v], 0);
            const cd d(u(unknown[v], 1), u(unknown[v], 2));
            out.direction[v] = std::abs(d) > 1e-9 ? d / std::abs(d) : target_direction[v];
        }
    return out;
}

// Where the first strip by index changes from one layer of rays to another (rays that
// wrapped round an island over rays that did not), the resampled phase jumps: an edge
// whose phases differ by more than k̄|e| + π/4 (a smooth wave changes by k̄|e| at most
// along it). Marks every vertex within a local wavelength of such an edge's ends (along
// the mesh's edges), so that the field's wave bridges the tear over two wavelengths
// (over one, a tear of half a wave still stepped 0.46 rad along an edge).
std::vector<std::uint8_t> tear_band(const RayStrips& s, const VertexFaces& around) {
    const std::size_t n = s.vertex_count();
    std::vector<std::uint8_t> band(n, 0);
    const auto length = [&](std::uint32_t a, std::uint32_t b) { return std::hypot(s.x[a] - s.x[b], s.y[a] - s.y[b]); };
    // (distance, vertex, reach) in a min-heap: a multi-source Dijkstra, each source
    // reaching its own wavelength.
    using Entry = std::tuple<double, std::uint32_t, double>;
    std::vector<Entry> heap;
    std::vector<double> best(n, std::numeric_limits<double>::infinity());
    for (std::size_t t = 0; t < s.triangle_count(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = s.triangles[3 * t + c], b = s.triangles[3 * t + (c + 1) % 3];
            if (!(s.k[a] > 0.0 && s.k[b] > 0.0)) continue;
            const double k = 0.5 * (s.k[a] + s.k[b]);
            const double jump = std::abs(std::remainder(s.phase[a] - s.phase[b], 2.0 * std::numbers::pi));
            if (jump <= k * length(a, b) + 0.25 * std::numbers::pi) continue;
            for (std::uint32_t v : {a, b})
                if (best[v] > 0.0) {
                    best[v] = 0.0;
                    heap.emplace_back(0.0, v, 2.0 * std::numbers::pi / s.k[v]);
                }
        }
    const auto later = std::greater<>();
    std::make_heap(heap.begin(), heap.end(), later);
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), later);
        const auto [d, v, reach] = heap.back();
        heap.pop_back();
        if (d > best[v]) continue;
        band[v] = 1;
        for (std::uint32_t f = around.offsets[v]; f < around.offsets[v + 1]; ++f)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t u = s.triangles[3 * around.faces[f] + c];
                const double du = d + length(u, v);
                if (u == v || du > reach || du >= best[u]) continue;
                best[u] = du;
                heap.emplace_back(du, u, reach);
                std::push_heap(heap.begin(), heap.end(), later);
            }
    }
    return band;
}

}  // namespace

std::size_t fill_strip_gaps(const WaveField& field, const Seafloor& seafloor, RayStrips& strips) {
    const std::size_t n = strips.vertex_count();
    const double period = 2.0 * std::numbers::pi / field.omega;
    const VertexFaces around = vertex_faces(n, strips.triangles);
    const std::vector<std::uint8_t> torn = tear_band(strips, around);
    std::vector<FieldSample> at(n);
    std::vector<DepthSample> depth(n);
    std::vector<Source> source(n, Source::still);
    std::vector<double> wavelength(n, 0.0);
    std::vector<cd> offset(n), direction(n), field_direction(n);
    cd sum(0.0, 0.0);
    std::size_t fill = 0;
    for (std::size_t v = 0; v < n; ++v) {
        at[v] = sample_wave_field(field, strips.x[v], strips.y[v]);
        const bool field_wave = at[v].wet && std::abs(at[v].eta) > 0.0;
        if (strips.k[v] > 0.0 && !torn[v]) {
            if (!field_wave) continue;  // the rays' wave, but no offset to take from it
            source[v] = Source::ray;
            offset[v] = std::polar(1.0, strips.phase[v] - std::arg(at[v].eta));
            direction[v] = cd(strips.dir_x[v], strips.dir_y[v]);
            sum += offset[v];
            continue;
        }
        if (!field_wave || !(strips.k[v] > 0.0 || strips.depth[v] > 0.0)) continue;
        depth[v] = sample_depth(seafloor.grid, strips.x[v], strips.y[v]);
        if (!(depth[v].depth > 0.0)) continue;
        source[v] = Source::field;
        wavelength[v] = 2.0 * std::numbers::pi / wavenumber_for_period(period, depth[v].depth);
        field_direction[v] = cd(at[v].dir_x, at[v].dir_y);
        ++fill;
    }
    if (fill == 0 || std::abs(sum) == 0.0) return 0;
    const cd mean = sum / std::abs(sum);  // the circular mean of the offsets
    const Continued ray{unwrapped_offsets(strips, source, offset, mean, around), std::move(direction)};
    const Continued c = continued_values(strips, source, ray, field_direction, wavelength);
    for (std::size_t v = 0; v < n; ++v) {
        if (source[v] != Source::field) continue;
        const DepthSample& d = depth[v];
        const double dir_x = c.direction[v].real(), dir_y = c.direction[v].imag();
        strips.amplitude[v] = std::abs(at[v].eta);
        strips.phase[v] = std::arg(at[v].eta) + std::arg(mean) + c.offset[v];
        strips.k[v] = 2.0 * std::numbers::pi / wavelength[v];
        strips.depth[v] = d.depth;
        strips.dir_x[v] = dir_x;
        strips.dir_y[v] = dir_y;
        strips.slope[v] = std::hypot(d.dh_dx, d.dh_dy);
        strips.rise[v] = -(d.dh_dx * dir_x + d.dh_dy * dir_y);
    }
    return fill;
}

}  // namespace wave
