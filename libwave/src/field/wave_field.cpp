// The wide-angle parabolic mild-slope model (docs/wave-field.md).
//
// With p = C·C_g, the mild-slope equation ∇·(p∇φ) + k²pφ = 0 becomes, for the
// energy-flux amplitude u = √(ω C_g)·η̂ (|u|² ∝ the flux), the one-way equation
// u_x = i·k̄·√(1 + X)·u,  X = ((k² − k̄²) + ∂_yy) / k̄²,
// marched along the swell (x). With u = B·e^{i∫k̄dx} and √(1+X) ≈ (1 + ¾X)/(1 + ¼X)
// (Padé (1,1), Booij 1981; Kirby 1986's wide-angle form):
// (1 + ¼X)·B_x = i·k̄·(½X)·B, stepped with Crank–Nicolson: one tridiagonal system per
// column, solved by LAPACK's zgtsv.
#include "libwave/field.h"

#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/physics.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

extern "C" {
// LAPACK: solves a complex tridiagonal system (dl, d, du) x = b in place (Gaussian
// elimination with partial pivoting).
void zgtsv_(const int* n, const int* nrhs, std::complex<double>* dl, std::complex<double>* d, std::complex<double>* du,
            std::complex<double>* b, const int* ldb, int* info);
}

namespace wave {
namespace {

using cd = std::complex<double>;
// √(1+X) ≈ 1 + ½X/(1 + bX), b = ¼: Padé (1,1). With b = ¼(1 − iδ) the pole at X = −4
// leaves the real axis: evanescent modes (X < −1), which the real form turns into
// spurious waves at steep angles (near a breakwater's tip), decay instead.
// δ = 0.1 acts on the transverse derivative only (the medium's k² − k̄² is exact):
// a plane wave at 30° to the march loses < 0.1 % per wavelength, a mode at the pole
// decays within a wavelength.
constexpr double kDamping = 0.1;

// The depth at a point, the seafloor's edge depths extended outside its rectangle.
double depth_clamped(const ElevationGrid& g, double x, double y) {
    return depth_at(g, std::clamp(x, g.x0, g.x_max()), std::clamp(y, g.y0, g.y_max()));
}

// The marching grid: the seafloor's rectangle seen along the swell.
WaveField field_grid(const ElevationGrid& g, const WaveTrain& train, double spacing, std::size_t max_nodes, double max_bytes) {
    WaveField f;
    const double len = std::hypot(train.direction_x, train.direction_y);
    f.ux = train.direction_x / len;
    f.uy = train.direction_y / len;
    double s0 = 1e300, s1 = -1e300, t0 = 1e300, t1 = -1e300;
    for (double cx : {g.x0, g.x_max()})
        for (double cy : {g.y0, g.y_max()}) {
            const double s = cx * f.ux + cy * f.uy, t = -cx * f.uy + cy * f.ux;
            s0 = std::min(s0, s), s1 = std::max(s1, s), t0 = std::min(t0, t), t1 = std::max(t1, t);
        }
    const double nx = std::ceil((s1 - s0) / spacing) + 1.0, ny = std::ceil((t1 - t0) / spacing) + 1.0;
    if (!(nx * ny <= static_cast<double>(max_nodes)))
        throw LimitError("wave field: " + detail::format_number(nx) + " x " + detail::format_number(ny) +
                         " nodes at a spacing of " + detail::format_number(spacing) + " m, more than the limit of " +
                         std::to_string(max_nodes) + "; lower /field/nodes_per_wavelength or raise /field/max_nodes");
    if (!(nx * ny * kFieldNodeBytes <= max_bytes))
        throw LimitError("wave field: " + detail::format_number(nx) + " x " + detail::format_number(ny) + " nodes at a spacing of " +
                         detail::format_number(spacing) + " m need about " + detail::format_number(std::ceil(nx * ny * kFieldNodeBytes / 1e7) / 100.0) +
                         " GB (" + detail::format_number(kFieldNodeBytes) + " bytes a node), over the " +
                         detail::format_number(max_bytes / 1e9) + " GB it may take (the memory limit, shared among a scene's wave trains); lower /field/nodes_per_wavelength or /field/max_nodes, "
                         "or raise the limit (--max-memory-gb)");
    f.nx = static_cast<std::size_t>(nx);
    f.ny = static_cast<std::size_t>(ny);
    f.dx = f.dy = spacing;
    f.x0 = s0 * f.ux - t0 * f.uy;
    f.y0 = s0 * f.uy + t0 * f.ux;
    return f;
}

// Per node of one column: the wavenumber and the flux factor √(ω C_g) (0 on land),
// and the coefficients of Kirby & Dalrymple's composite dispersion at the linear kh:
// f1·D and f2 (see nonlinear_k).
struct Column {
    std::vector<double> k, flux, depth, f1d, f2;
};

Column column_at(const ElevationGrid& g, const WaveField& f, double s, double omega) {
    Column c;
    c.k.resize(f.ny), c.flux.resize(f.ny), c.depth.resize(f.ny), c.f1d.resize(f.ny), c.f2.resize(f.ny);
    for (std::size_t j = 0; j < f.ny; ++j) {
        const double t = static_cast<double>(j) * f.dy;
        const double x = f.x0 + s * f.ux - t * f.uy, y = f.y0 + s * f.uy + t * f.ux;
        const double h = depth_clamped(g, x, y);
        c.depth[j] = h;
        if (h <= 0.0) continue;
        const LinearWave w = linear_wave(omega, h);
        c.k[j] = w.k;
        c.flux[j] = std::sqrt(omega * w.group_velocity);
        // Kirby & Dalrymple (1986): f1 = tanh⁵ kh, f2 = (kh / sinh kh)⁴,
        // D = (cosh 4kh + 8 − 2 tanh² kh) / (8 sinh⁴ kh). Deep water (kh > 10): f1 D → 1
        // (Stokes), f2 → 0 (and cosh 4kh would overflow further out).
        const double kh = w.k * h;
        if (kh > 10.0) {
            c.f1d[j] = 1.0;
            c.f2[j] = 0.0;
            continue;
        }
        const double th = std::tanh(kh), sh = std::sinh(kh), sh2 = sh * sh, th2 = th * th;
        c.f1d[j] = th2 * th2 * th * (std::cosh(4.0 * kh) + 8.0 - 2.0 * th2) / (8.0 * sh2 * sh2);
        const double r = kh / sh;
        c.f2[j] = r * r * r * r;
    }
    return c;
}

// The wavenumber of Kirby & Dalrymple (1986)'s composite dispersion relation
// ω² = g k [1 + f1 (k|A|)² D] tanh(k h + f2 k|A|) for amplitude a = |A| (f1 D and f2 at
// the linear kh, as in REF/DIF). The height adds to ω at a fixed k, so the root lies in
// (0, k_linear]: Newton's iteration from `guess` (a neighbour's root), kept inside that
// bracket.
double nonlinear_k(double omega, double h, double k_linear, double f1d, double f2, double a, double guess) {
    if (!(a > 0.0) || !(k_linear > 0.0)) return k_linear;
    const double c1 = f1d * a * a, c2 = f2 * a, w2 = omega * omega;
    double lo = 0.0, hi = k_linear, k = guess > 0.0 && guess < k_linear ? guess : k_linear;
    for (int it = 0; it < 20; ++it) {
        const double s = 1.0 + c1 * k * k, t = std::tanh(k * (h + c2));
        const double g = kGravity * k * s * t - w2;
        (g > 0.0 ? hi : lo) = k;
        const double dg = kGravity * ((1.0 + 3.0 * c1 * k * k) * t + k * s * (1.0 - t * t) * (h + c2));
        double next = dg > 0.0 ? k - g / dg : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        const bool done = std::abs(next - k) <= 1e-9 * k;
        k = next;
        if (done) break;
    }
    return k;
}

// Dally, Dean & Dalrymple (1985) over a distance dx of a breaking row: the flux
// F = |u|² ∝ E C_g relaxes towards the stable flux F_s (H_s = Γh) by
// dF/dx = −(K/h)(F − F_s), integrated exactly for the node's h: F − F_s shrinks by
// e^{−K dx / h}. Below F_s nothing happens (breaking stops there).
void dissipate(cd& u, double flux, double h, double stable_index, double decay, double dx) {
    if (!(h > 0.0) || decay <= 0.0) return;
    const double f = std::norm(u), hs = 0.5 * stable_index * h, fs = flux * flux * hs * hs;
    if (!(f > fs)) return;
    const double after = fs + (f - fs) * std::exp(-decay * dx / h);
    u *= std::sqrt(after / f);
}

// The sponge's damping per metre at node j (absorbing edges): 0 inside, rising
// quadratically to ~ k over the outer `width` metres.
double sponge(const WaveField& f, std::size_t j, double width, double k) {
    const double t = static_cast<double>(j) * f.dy, w = static_cast<double>(f.ny - 1) * f.dy;
    const double d = std::min(t, w - t);
    if (d >= width) return 0.0;
    const double r = 1.0 - d / width;
    return 0.5 * k * r * r;
}

// One Crank–Nicolson step of the envelope B from column i to i + 1 (mid-column
// wavenumbers km, reference wavenumber kbar). Neighbours j and j + 1 are coupled when
// both are water on both columns (link[j]); an uncoupled face is a wall (∂_y B = 0,
// finite-volume form), as are the grid's edges.
void step(const WaveField& f, std::span<const double> km, std::span<const std::uint8_t> link, double kbar,
          std::vector<cd>& b, std::vector<cd>& dl, std::vector<cd>& d, std::vector<cd>& du, std::vector<cd>& rhs) {
    const std::size_t n = f.ny;
    const double inv = 1.0 / (kbar * kbar), ry = inv / (f.dy * f.dy);
    const cd c(0.0, 0.5 * kbar * f.dx);  // i k̄ dx / 2
    // X = X_k + X_t: X_k = (k² − k̄²)/k̄² (the medium), X_t = ∂_yy/k̄² (the transverse
    // derivative, where the damping acts).
    const cd bt(0.25, -0.25 * kDamping), h = 0.5 * c;
    for (std::size_t j = 0; j < n; ++j) {
        const double lo = j > 0 && link[j - 1] ? ry : 0.0, hi = j + 1 < n && link[j] ? ry : 0.0;
        const double xk = (km[j] * km[j] - kbar * kbar) * inv, xt = -lo - hi;
        const cd xb_k = xk * b[j];
        const cd xb_t = xt * b[j] + (j > 0 ? lo * b[j - 1] : cd()) + (j + 1 < n ? hi * b[j + 1] : cd());
        // [1 + ¼X_k + b_t X_t − ½c X] B⁺ = [1 + ¼X_k + b_t X_t + ½c X] B
        d[j] = 1.0 + (0.25 - h) * xk + (bt - h) * xt;
        rhs[j] = b[j] + (0.25 + h) * xb_k + (bt + h) * xb_t;
        if (j > 0) dl[j - 1] = (bt - h) * lo;
        if (j + 1 < n) du[j] = (bt - h) * hi;
    }
    const int nn = static_cast<int>(n), one = 1;
    int info = 0;
    zgtsv_(&nn, &one, dl.data(), d.data(), du.data(), rhs.data(), &nn, &info);
    if (info != 0) throw Error("wave field: the tridiagonal system is singular (LAPACK zgtsv info " + std::to_string(info) + ")");
    b.swap(rhs);
}

// The surf zone's onset and stop at a node of depth h > 0 (u in flux units, surf the
// row's state): a row starts breaking where H > γh, and H never exceeds γh (the onset,
// or a slope too steep for the decay to keep up); it stops where H < Γh.
void surf_zone(cd& u, double flux, double h, const FieldOptions& o, std::uint8_t& surf) {
    const double a = std::abs(u) / flux, limit = 0.5 * o.breaker_index * h;
    if (a > limit) {
        u *= limit / a;
        surf = 1;
    } else if (surf && 2.0 * a < o.stable_index * h) {
        surf = 0;  // the wave re-forms (behind a bar, in a trough)
    }
}

}  // namespace

WaveField solve_wave_field(const Seafloor& seafloor, const WaveTrain& train, const FieldOptions& options) {
    // Breaking stops at Γ ≤ γ: a scene that lowers the onset γ below Γ lowers Γ with it.
    FieldOptions o = options;
    o.stable_index = std::min(o.stable_index, o.breaker_index);
    if (!(o.nodes_per_wavelength >= 4.0 && o.nodes_per_wavelength <= 200.0))
        throw InputError("wave field: nodes_per_wavelength must be in [4, 200], got " + detail::format_number(o.nodes_per_wavelength));
    if (!(o.breaker_index > 0.0 && o.breaker_index <= 2.0))
        throw InputError("wave field: breaker_index must be in (0, 2], got " + detail::format_number(o.breaker_index));
    if (!(options.stable_index > 0.0 && options.stable_index <= 2.0))
        throw InputError("wave field: stable_index must be in (0, 2], got " + detail::format_number(options.stable_index));
    if (!(o.breaking_decay >= 0.0 && o.breaking_decay <= 1.0))
        throw InputError("wave field: breaking_decay must be in [0, 1], got " + detail::format_number(o.breaking_decay));
    if (!(train.period > 0.0 && train.amplitude > 0.0 && std::hypot(train.direction_x, train.direction_y) > 0.0))
        throw InputError("wave field: a wave train needs a period > 0, an amplitude > 0 and a direction");
    const ElevationGrid& g = seafloor.grid;
    const SeafloorStats st = seafloor_stats(seafloor);
    if (!(st.depth_max > 0.0)) throw InputError("wave field: " + seafloor.source + " has no water");
    const double omega = 2.0 * std::numbers::pi / train.period;
    // The resolved depth: where the incident wave breaks (H∞ = γh), or deeper.
    const double resolved = std::min(st.depth_max, std::max({o.min_resolved_depth, 2.0 * train.amplitude / o.breaker_index,
                                                             1e-2 * st.depth_max}));
    const double spacing = linear_wave(omega, resolved).wavelength / o.nodes_per_wavelength;
    WaveField f = field_grid(g, train, spacing, o.max_nodes, o.max_bytes);
    f.omega = omega;
    f.incident_amplitude = train.amplitude;
    f.envelope.assign(f.nx * f.ny, {});
    f.flags.assign(f.nx * f.ny, 0);
    f.phase_ref.assign(f.nx, 0.0);

    const double flux_deep = std::sqrt(omega * linear_wave(omega, 1e6).group_velocity);
    const double sponge_width = 2.0 * linear_wave(omega, st.depth_max).wavelength;
    std::vector<cd> b(f.ny, cd(train.amplitude * flux_deep)), dl(f.ny), d(f.ny), du(f.ny), rhs(f.ny);
    std::vector<double> km(f.ny);
    std::vector<std::uint8_t> link(f.ny, 0);
    // The undisturbed wave at each row: shoaled along the march, neither refracted nor
    // diffracted; the absorbing edges relax towards it.
    std::vector<cd> reference = b;
    // Per row: breaking now (between the onset H > γh and the stop H < Γh); the same
    // for the undisturbed wave, which breaks as the field does.
    std::vector<std::uint8_t> surf(f.ny, 0), reference_surf(f.ny, 0);
    // The wavenumbers of the column the step leaves (nonlinear for its own |A|) and
    // of the one it reaches (for the amplitude of the last pass).
    std::vector<double> k_here(f.ny), k_next(f.ny);
    std::vector<cd> b_start(f.ny), reference_start(f.ny);
    // Per row: cos φ, φ the angle between the wave's local direction and the march (from
    // the phase the last step advanced). Dally, Dean & Dalrymple's loss acts per unit
    // area, (K/h) C_g (E − E_s), along the wave's own direction: per metre of the march
    // it is (K/h)/cos φ, whatever direction the march takes.
    std::vector<double> cos_dir(f.ny, 1.0);
    Column here = column_at(g, f, 0.0, omega);
    const auto amplitude_k = [&](const Column& c, std::size_t j, double a, double guess) {
        return o.amplitude_dispersion ? nonlinear_k(omega, c.depth[j], c.k[j], c.f1d[j], c.f2[j], a, guess) : c.k[j];
    };
    const auto store = [&](std::size_t i, const Column& c) {
        for (std::size_t j = 0; j < f.ny; ++j) {
            const std::size_t n = j * f.nx + i;
            if (c.depth[j] <= 0.0) {  // land: the wave is absorbed
                b[j] = 0.0;
                surf[j] = 0;
                continue;
            }
            f.flags[n] = kFieldWet;
            surf_zone(b[j], c.flux[j], c.depth[j], o, surf[j]);
            const cd a = b[j] / c.flux[j];
            if (surf[j]) {
                f.flags[n] |= kFieldBroken;
                ++f.broken_nodes;
            }
            f.envelope[n] = std::complex<float>(a);
        }
    };
    store(0, here);
    for (std::size_t j = 0; j < f.ny; ++j) {
        f.incident_height = std::max(f.incident_height, 2.0 * static_cast<double>(std::abs(f.envelope[j * f.nx])));
        k_here[j] = here.k[j] > 0.0 ? amplitude_k(here, j, std::abs(b[j]) / here.flux[j], here.k[j]) : 0.0;
        if (here.depth[j] > 0.0) surf_zone(reference[j], here.flux[j], here.depth[j], o, reference_surf[j]);
    }
    // With amplitude dispersion, a predictor (column i+1's k from column i's |A|) and a
    // corrector (from the predicted |A| at i+1).
    const int passes = o.amplitude_dispersion ? 2 : 1;
    for (std::size_t i = 0; i + 1 < f.nx; ++i) {
        const Column next = column_at(g, f, static_cast<double>(i + 1) * f.dx, omega);
        // Breaking rows lose energy over the step, half before it and half after
        // (Strang splitting around the step's shoaling and refraction).
        for (std::size_t j = 0; j < f.ny; ++j)
            if (surf[j]) dissipate(b[j], here.flux[j], here.depth[j], o.stable_index, o.breaking_decay, 0.5 * f.dx / cos_dir[j]);
        for (std::size_t j = 0; j < f.ny; ++j)
            k_next[j] = next.k[j] > 0.0 && here.k[j] > 0.0
                            ? amplitude_k(next, j, std::abs(b[j]) / here.flux[j], next.k[j] * (k_here[j] / here.k[j]))
                            : next.k[j];
        b_start = b;
        reference_start = reference;
        double kbar = 0.0;
        for (int pass = 0; pass < passes; ++pass) {
            if (pass > 0) {
                for (std::size_t j = 0; j < f.ny; ++j)
                    if (next.k[j] > 0.0 && here.k[j] > 0.0) k_next[j] = amplitude_k(next, j, std::abs(b[j]) / next.flux[j], k_next[j]);
                b = b_start;
                reference = reference_start;
            }
            double ksum = 0.0;
            std::size_t wet = 0;
            for (std::size_t j = 0; j < f.ny; ++j) {
                const bool water = here.k[j] > 0.0 && next.k[j] > 0.0;
                km[j] = water ? 0.5 * (k_here[j] + k_next[j]) : 0.0;
                if (water) ksum += km[j], ++wet;
            }
            for (std::size_t j = 0; j + 1 < f.ny; ++j) link[j] = km[j] > 0.0 && km[j + 1] > 0.0;
            kbar = wet > 0 ? ksum / static_cast<double>(wet) : 2.0 * std::numbers::pi / spacing;
            for (std::size_t j = 0; j < f.ny; ++j) {
                if (km[j] == 0.0) {  // land: its nodes are reset to zero after the step
                    km[j] = kbar;
                    reference[j] = 0.0;  // the undisturbed wave stops here too
                }
                reference[j] *= std::polar(1.0, (km[j] - kbar) * f.dx);
                // Open edges: the disturbance (B − reference) is damped, the undisturbed wave kept.
                if (!o.reflecting_edges) b[j] = reference[j] + (b[j] - reference[j]) * std::exp(-sponge(f, j, sponge_width, kbar) * f.dx);
            }
            step(f, km, link, kbar, b, dl, d, du, rhs);
        }
        for (std::size_t j = 0; j < f.ny; ++j) {
            if (!(next.depth[j] > 0.0 && here.depth[j] > 0.0)) {
                reference_surf[j] = 0;
                cos_dir[j] = 1.0;
                continue;
            }
            // The wavenumber along the march, k̄ + ∂_x arg B, over the local k: cos φ,
            // kept within the wide-angle form's reach (φ ≤ 60°).
            if (std::norm(b[j]) > 0.0 && std::norm(b_start[j]) > 0.0)
                cos_dir[j] = std::clamp((kbar + std::arg(b[j] * std::conj(b_start[j])) / f.dx) / km[j], 0.5, 1.0);
            if (surf[j]) dissipate(b[j], next.flux[j], next.depth[j], o.stable_index, o.breaking_decay, 0.5 * f.dx / cos_dir[j]);
            if (reference_surf[j])
                dissipate(reference[j], next.flux[j], 0.5 * (here.depth[j] + next.depth[j]), o.stable_index, o.breaking_decay, f.dx);
            surf_zone(reference[j], next.flux[j], next.depth[j], o, reference_surf[j]);
        }
        f.phase_ref[i + 1] = f.phase_ref[i] + kbar * f.dx;
        store(i + 1, next);
        for (std::size_t j = 0; j < f.ny; ++j)
            k_here[j] = next.k[j] > 0.0 ? amplitude_k(next, j, std::abs(b[j]) / next.flux[j], k_next[j]) : 0.0;
        here = next;
    }
    return f;
}

FieldSample sample_wave_field(const WaveField& f, double x, double y) noexcept {
    FieldSample out;
    if (f.nx < 2 || f.ny < 2) return out;
    const double rx = x - f.x0, ry = y - f.y0;
    double s = (rx * f.ux + ry * f.uy) / f.dx, t = (-rx * f.uy + ry * f.ux) / f.dy;
    // Points on the grid's edge by construction (the domain's corners, which the swell's
    // rotated grid just covers) may land a rounding error outside it: taken as on it.
    // (The corner of one random seafloor took no wave and stood still in a 1 m sea.)
    constexpr double kEdge = 1e-9;  // in cells
    const double last_s = static_cast<double>(f.nx - 1), last_t = static_cast<double>(f.ny - 1);
    if (!(s >= -kEdge && t >= -kEdge && s <= last_s + kEdge && t <= last_t + kEdge)) return out;
    s = std::clamp(s, 0.0, last_s);
    t = std::clamp(t, 0.0, last_t);
    const std::size_t i = std::min(static_cast<std::size_t>(s), f.nx - 2), j = std::min(static_cast<std::size_t>(t), f.ny - 2);
    const double fs = s - static_cast<double>(i), ft = t - static_cast<double>(j);
    const auto at = [&](std::size_t ii, std::size_t jj) { return std::complex<double>(f.envelope[jj * f.nx + ii]); };
    const cd a00 = at(i, j), a10 = at(i + 1, j), a01 = at(i, j + 1), a11 = at(i + 1, j + 1);
    const cd a = (1 - fs) * (1 - ft) * a00 + fs * (1 - ft) * a10 + (1 - fs) * ft * a01 + fs * ft * a11;
    const double phase = (1 - fs) * f.phase_ref[i] + fs * f.phase_ref[i + 1];
    out.eta = a * std::polar(1.0, phase);
    // Direction: ∇ arg η̂ = (k̄ + ∂_s arg A, ∂_t arg A) in the swell's frame.
    const cd as = ((1 - ft) * (a10 - a00) + ft * (a11 - a01)) / f.dx, at_ = ((1 - fs) * (a01 - a00) + fs * (a11 - a10)) / f.dy;
    const double mag2 = std::norm(a);
    const double kbar = (f.phase_ref[i + 1] - f.phase_ref[i]) / f.dx;
    const double gs = kbar + (mag2 > 0.0 ? std::imag(std::conj(a) * as) / mag2 : 0.0);
    const double gt = mag2 > 0.0 ? std::imag(std::conj(a) * at_) / mag2 : 0.0;
    const double len = std::hypot(gs, gt);
    if (len > 0.0) {
        out.dir_x = (gs * f.ux - gt * f.uy) / len;
        out.dir_y = (gs * f.uy + gt * f.ux) / len;
    }
    const std::size_t ni = fs < 0.5 ? i : i + 1, nj = ft < 0.5 ? j : j + 1;
    const std::uint8_t flag = f.flags[nj * f.nx + ni];
    out.wet = (flag & kFieldWet) != 0;
    out.broken = (flag & kFieldBroken) != 0;
    return out;
}

std::size_t take_field_amplitudes(const WaveField& field, FrontSet& fronts) noexcept {
    std::size_t taken = 0;
    for (std::size_t i = 0; i < fronts.x.size(); ++i) {
        const FieldSample s = sample_wave_field(field, fronts.x[i], fronts.y[i]);
        // An aground ray stands on the shoreline: its depth is 0 give or take rounding
        // (±1e-16), and the sign of that rounding must not decide its amplitude.
        if (!s.wet || fronts.depth[i] <= 0.0 || fronts.flag[i] == RayFlag::aground) continue;
        // In the surf zone the field holds H at γh; the ray's own (shoaled, capped)
        // amplitude says how far past breaking the wave is, which the breakers read.
        fronts.amplitude[i] = s.broken ? std::max(std::abs(s.eta), fronts.amplitude[i]) : std::abs(s.eta);
        ++taken;
    }
    return taken;
}

std::size_t take_field_amplitudes(std::span<const WaveField> fields, RaySet& rays) noexcept {
    std::size_t taken = 0;
    for (std::size_t r = 0; r < rays.ray_count(); ++r) {
        if (rays.train[r] >= fields.size()) continue;
        const WaveField& field = fields[rays.train[r]];
        for (std::size_t i = rays.offsets[r]; i < rays.offsets[r + 1]; ++i) {
            const FieldSample s = sample_wave_field(field, rays.x[i], rays.y[i]);
            if (!s.wet || rays.depth[i] <= 0.0) continue;
            rays.amplitude[i] = s.broken ? std::max(std::abs(s.eta), rays.amplitude[i]) : std::abs(s.eta);
            ++taken;
        }
    }
    return taken;
}

}  // namespace wave
