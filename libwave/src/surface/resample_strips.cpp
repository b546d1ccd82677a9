// The ray strips' fields resampled at other points (surface.h, resample_ray_strips).
#include "libwave/errors.h"
#include "libwave/surface.h"
#include "surface/triangle_locator.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>

namespace wave {

RayStrips resample_ray_strips(const RayStrips& s, const Seafloor& seafloor, std::span<const double> x,
                              std::span<const double> y, std::span<const std::uint32_t> triangles) {
    if (x.size() != y.size()) throw InputError("resample strips: x and y differ in length");
    const std::size_t n = x.size();
    RayStrips r;
    r.omega = s.omega;
    r.x.assign(x.begin(), x.end());
    r.y.assign(y.begin(), y.end());
    r.triangles.assign(triangles.begin(), triangles.end());
    r.ray.assign(n, 0);
    r.step.assign(n, 0);
    r.dir_x.assign(n, 1.0);
    r.dir_y.assign(n, 0.0);
    for (auto* f : {&r.phase, &r.k, &r.amplitude, &r.depth, &r.slope, &r.rise}) f->assign(n, 0.0);
    r.flag.assign(n, RayFlag::alive);
    r.caustic.assign(n, 0);
    r.entry_break_phase = s.entry_break_phase;  // per ray id, as the resampled vertices' ray ids
    const detail::TriangleLocator locator(s.x, s.y, s.triangles);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t v = range.begin(); v != range.end(); ++v) {
            detail::TriangleLocator::Hit h;
            if (!locator.locate(x[v], y[v], h)) {
                r.depth[v] = depth_at(seafloor.grid, x[v], y[v]);
                continue;
            }
            const auto mix = [&](const std::vector<double>& f) { return h.wa * f[h.a] + h.wb * f[h.b] + h.wc * f[h.c]; };
            for (auto [to, from] : {std::pair{&r.amplitude, &s.amplitude}, {&r.depth, &s.depth}, {&r.slope, &s.slope},
                                    {&r.rise, &s.rise}})
                (*to)[v] = mix(*from);
            // The wave's own fields (phase, k, direction) from the corners that carry a
            // wave (k > 0): a dry corner's k = 0 would shrink k towards 0 and blow up the
            // profile's orbit (limited to 1/k), its phase is none.
            const double wa = s.k[h.a] > 0.0 ? h.wa : 0.0, wb = s.k[h.b] > 0.0 ? h.wb : 0.0, wc = s.k[h.c] > 0.0 ? h.wc : 0.0;
            const double sum = wa + wb + wc;
            if (!(sum > 0.0)) {
                r.amplitude[v] = 0.0;
                continue;
            }
            const auto wave_mix = [&](const std::vector<double>& f) { return (wa * f[h.a] + wb * f[h.b] + wc * f[h.c]) / sum; };
            r.phase[v] = wave_mix(s.phase);
            r.k[v] = wave_mix(s.k);
            const double dx = wave_mix(s.dir_x), dy = wave_mix(s.dir_y), dl = std::hypot(dx, dy);
            if (dl > 0.0) {
                r.dir_x[v] = dx / dl;
                r.dir_y[v] = dy / dl;
            }
            const std::uint32_t nearest = h.wa >= h.wb && h.wa >= h.wc ? h.a : h.wb >= h.wc ? h.b : h.c;
            r.ray[v] = s.ray[nearest];
            r.step[v] = s.step[nearest];
            r.flag[v] = s.flag[nearest];
            r.caustic[v] = s.caustic[h.a] | s.caustic[h.b] | s.caustic[h.c];
        }
    });
    return r;
}

}  // namespace wave
