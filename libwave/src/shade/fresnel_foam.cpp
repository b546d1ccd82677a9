// Fresnel weights per vertex (Ts'o & Barsky §4.2; Tessendorf §4), foam from
// depth-limited breaking, and Ts'o's baked colour (eq. 4.1).
#include "libwave/errors.h"
#include "libwave/shade.h"
#include "core/vector_clones.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace wave {
namespace {

void require_size(std::size_t got, std::size_t want, const char* what) {
    if (got != want)
        throw InputError(std::string("shade: ") + what + " holds " + std::to_string(got) + " floats, expected " +
                         std::to_string(want));
}

// |cos i| between the unit normal and the direction to the camera: the underside of
// a lip is seen from its other side; 1 for a vertex at the camera.
inline double cos_to_camera(const float* p, const float* n, const std::array<double, 3>& camera) noexcept {
    const double ex = camera[0] - p[0], ey = camera[1] - p[1], ez = camera[2] - p[2];
    const double len = std::sqrt(ex * ex + ey * ey + ez * ez);
    const double along = ex * n[0] + ey * n[1] + ez * n[2];
    return std::min(std::abs(len > 0.0 ? along / len : 1.0), 1.0);
}

// The exact model's weights of `count` vertices, in float (the inputs and the weights
// are float; eight lanes of roots and divisions where double had four): a loop without
// calls or branches, vectorised (core/vector_clones.h). The direction to the camera is
// taken from the vertex (float differences: < 1e-7 of the distance off), and R is
// fresnel_reflectivity's expression from air (n_i = 1) into water.
LIBWAVE_VECTOR_CLONES void exact_weights(const float* __restrict p, const float* __restrict n, std::size_t count,
                                         const std::array<double, 3>& camera, double water_index,
                                         float* __restrict reflect, float* __restrict refract) {
    const auto cx = static_cast<float>(camera[0]), cy = static_cast<float>(camera[1]), cz = static_cast<float>(camera[2]);
    const auto nt = static_cast<float>(water_index);
    // cos²θt = 1 − η² sin²θi = (1 − η²) + η² cos²θi, η = 1/n: written so, it keeps its
    // digits at grazing incidence, where 1 − sin²θt cancels them.
    const double eta2 = 1.0 / (water_index * water_index);
    const auto far = static_cast<float>(1.0 - eta2), near = static_cast<float>(eta2);
    for (std::size_t v = 0; v < count; ++v) {
        const float ex = cx - p[3 * v], ey = cy - p[3 * v + 1], ez = cz - p[3 * v + 2];
        const float len = std::sqrt(ex * ex + ey * ey + ez * ez);
        const float along = ex * n[3 * v] + ey * n[3 * v + 1] + ez * n[3 * v + 2];
        const float cos_i = std::min(std::abs(len > 0.0f ? along / len : 1.0f), 1.0f);
        const float cos_t2 = far + near * (cos_i * cos_i);  // Snell
        const float cos_t = std::sqrt(cos_t2);
        const float rs = (cos_i - nt * cos_t) / (cos_i + nt * cos_t);
        const float rp = (nt * cos_i - cos_t) / (nt * cos_i + cos_t);
        // grazing with n = 1 (0/0 above): total reflection, as fresnel_reflectivity says
        const float r = cos_t2 > 0.0f ? 0.5f * (rs * rs + rp * rp) : 1.0f;
        reflect[v] = r;
        refract[v] = 1.0f - r;
    }
}

void tso_weights(const float* p, const float* n, std::size_t count, const std::array<double, 3>& camera,
                 float* reflect, float* refract) {
    for (std::size_t v = 0; v < count; ++v) {
        const double r = fresnel_reflectivity_tso(std::acos(cos_to_camera(p + 3 * v, n + 3 * v, camera)));
        reflect[v] = static_cast<float>(r);
        refract[v] = static_cast<float>(1.0 - r);
    }
}

}  // namespace

void fresnel_weights(std::span<const float> p, std::span<const float> n, const FresnelOptions& o,
                     std::span<float> reflect, std::span<float> refract) {
    const std::size_t count = p.size() / 3;
    require_size(p.size(), 3 * count, "positions");
    require_size(n.size(), 3 * count, "normals");
    require_size(reflect.size(), count, "reflect");
    require_size(refract.size(), count, "refract");
    if (!(o.water_index >= 1.0)) throw InputError("shade: water_index must be >= 1");
    // Per vertex alone: parallel, and the same bits for any thread count (and CPU).
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const tbb::blocked_range<std::size_t>& b) {
        const std::size_t first = b.begin(), size = b.size();
        if (o.model == FresnelModel::exact)
            exact_weights(p.data() + 3 * first, n.data() + 3 * first, size, o.camera, o.water_index,
                          reflect.data() + first, refract.data() + first);
        else
            tso_weights(p.data() + 3 * first, n.data() + 3 * first, size, o.camera, reflect.data() + first,
                        refract.data() + first);
    });
}

double foam_fade_phase(const FoamOptions& o, double omega) {
    if (!(o.fade_periods > 0.0) || !std::isfinite(o.fade_periods) || !(o.fade_time >= 0.0) || !std::isfinite(o.fade_time))
        throw InputError("shade: foam needs fade_periods > 0 and fade_time >= 0 s");
    return o.fade_time > 0.0 ? omega * o.fade_time : 2.0 * std::numbers::pi * o.fade_periods;
}

void breaking_foam(const RayStrips& s, const GonzatoMotionPlan& m, double t, const FoamOptions& o,
                   std::span<float> foam) {
    const std::size_t count = s.vertex_count();
    require_size(m.vertex_count(), count, "motion plan vertices");
    require_size(foam.size(), count, "foam");
    if (!(o.breaker_index > 0.0) || !(o.onset > 0.0 && o.onset < 1.0))
        throw InputError("shade: foam needs breaker_index > 0 and 0 < onset < 1");
    const double two_pi = 2.0 * std::numbers::pi;
    const double fade = foam_fade_phase(o, m.omega);
    for (std::size_t v = 0; v < count; ++v) {
        const double h = s.depth[v];
        if (!(h > 0.0) || !(s.amplitude[v] > 0.0)) {
            foam[v] = 0.0f;
            continue;
        }
        // How close the wave is to breaking: H / (γ h), 1 once the tracer capped it.
        const double ratio = 2.0 * s.amplitude[v] / (o.breaker_index * h);
        const double weight = std::clamp((ratio - o.onset) / (1.0 - o.onset), 0.0, 1.0);
        if (weight == 0.0) {
            foam[v] = 0.0f;
            continue;
        }
        // Φ = −ωt + Σ k Δs falls with time; the crest (Φ_min + π) passed Δt ago with
        // ω Δt = (Φ_crest − Φ) mod 2π.
        const double phi = m.phase[v] - m.omega * t;
        double since = std::fmod(m.shape[v].trough_phase + std::numbers::pi - phi, two_pi);
        if (since < 0.0) since += two_pi;
        foam[v] = static_cast<float>(weight * std::max(std::exp(-since / fade), lip_foam_rise(two_pi - since)));
    }
}

void height_field_foam(const HeightFieldPlan& plan, std::span<const float> node_depth, double t, const FoamOptions& o,
                       std::span<float> node_foam, std::span<float> foam) {
    require_size(node_depth.size(), plan.control_count(), "node depth");
    require_size(node_foam.size(), plan.control_count(), "node foam");
    require_size(foam.size(), plan.vertex_count(), "foam");
    if (!(o.breaker_index > 0.0) || !(o.onset > 0.0 && o.onset < 1.0))
        throw InputError("shade: foam needs breaker_index > 0 and 0 < onset < 1");
    const double two_pi = 2.0 * std::numbers::pi;
    (void)foam_fade_phase(o, 1.0);  // checks the options even where no term breaks
    for (std::size_t v = 0; v < plan.control_count(); ++v) {
        double f = 0.0;
        const double h = node_depth[v];
        for (std::size_t i = plan.term_offsets[v]; h > 0.0 && i < plan.term_offsets[v + 1]; ++i) {
            const double ratio = 2.0 * plan.term_amplitude[i] / (o.breaker_index * h);
            const double weight = std::clamp((ratio - o.onset) / (1.0 - o.onset), 0.0, 1.0);
            if (weight == 0.0) continue;
            // a sin(φ − ω t) crests at φ − ω t ≡ π/2, a value that falls with time: the
            // crest passed Δt ago with ω Δt = (π/2 − (φ − ω t)) mod 2π.
            const double omega = plan.term_omega[i];
            double since = std::fmod(0.5 * std::numbers::pi - (plan.term_phase[i] - omega * t), two_pi);
            if (since < 0.0) since += two_pi;
            f = std::max(f, weight * std::exp(-since / foam_fade_phase(o, omega)));
        }
        node_foam[v] = static_cast<float>(f);
    }
    // Sampled vertex (row, col) lies at control coordinates (col, row) / samples.
    const auto s = static_cast<std::size_t>(plan.samples_per_span);
    for (std::size_t row = 0; row < plan.vertex_ny; ++row)
        for (std::size_t col = 0; col < plan.vertex_nx; ++col) {
            const std::size_t i = std::min(col / s, plan.nx - 2), j = std::min(row / s, plan.ny - 2);
            const double u = static_cast<double>(col) / static_cast<double>(s) - static_cast<double>(i);
            const double w = static_cast<double>(row) / static_cast<double>(s) - static_cast<double>(j);
            const auto at = [&](std::size_t a, std::size_t b) { return double{node_foam[b * plan.nx + a]}; };
            foam[row * plan.vertex_nx + col] = static_cast<float>(
                (1 - w) * ((1 - u) * at(i, j) + u * at(i + 1, j)) + w * ((1 - u) * at(i, j + 1) + u * at(i + 1, j + 1)));
        }
}

void water_colour(std::span<const float> reflect, std::span<const float> depth, std::span<const float> foam,
                  const WaterColours& c, std::span<float> rgb) {
    const std::size_t count = reflect.size();
    require_size(depth.size(), count, "depth");
    require_size(foam.size(), count, "foam");
    require_size(rgb.size(), 3 * count, "rgb");
    if (!(c.attenuation > 0.0)) throw InputError("shade: colour attenuation must be > 0 m");
    for (std::size_t v = 0; v < count; ++v) {
        const double fade = std::exp(-std::max(double{depth[v]}, 0.0) / c.attenuation);  // Ts'o §5: deeper is darker
        const double r = reflect[v], f = std::clamp(double{foam[v]}, 0.0, 1.0);
        for (int i = 0; i < 3; ++i) {
            const double refracted = c.deep[i] + (c.shallow[i] - c.deep[i]) * fade;
            const double water = r * c.reflected[i] + (1.0 - r) * refracted;  // Ts'o eq. 4.1
            rgb[3 * v + i] = static_cast<float>(water + (1.0 - water) * f);
        }
    }
}

}  // namespace wave
