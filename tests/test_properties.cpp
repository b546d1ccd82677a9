// Property tests (issue 11): random procedural seafloors, random wave trains and random
// seeds through tracing, ray strips, Gonzato's motion and Jeschke's breakers. For every
// draw: tracing ends within its guard rails, every traced and moved value is finite,
// strip triangles are non-degenerate in plan, no strip vertex lies on dry land, and
// the motion stays finite at every sampled time. The draws are fixed by the seeds (reproducible).
#include <gtest/gtest.h>

#include "libwave/bathymetry.h"
#include "libwave/motion.h"
#include "libwave/surface.h"
#include "libwave/trace.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace wave;

namespace {

struct Draw {
    Seafloor seafloor;
    WaveTrain train;
    FrontOptions fronts;
    std::string label;
};

Draw draw(std::uint32_t seed) {
    std::mt19937 rng(seed);
    const auto u = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    Draw d;
    switch (seed % 3) {
        case 0: {
            PlanarBeachParams p;
            p.slope = u(0.01, 0.2);
            p.max_depth = u(3.0, 15.0);
            p.spacing = 2.0;
            d.seafloor = make_planar_beach(p);
            d.label = "planar beach, slope " + std::to_string(p.slope);
            break;
        }
        case 1: {
            GonzatoBayParams p;
            p.slope = u(0.05, 0.2);
            p.max_depth = u(2.0, 8.0);
            p.headland_y = u(40.0, 70.0);
            p.spacing = 1.0;
            d.seafloor = make_gonzato_bay(p);
            d.label = "bay, slope " + std::to_string(p.slope);
            break;
        }
        default: {
            GonzatoIslandParams p;
            p.semi_axis_x = u(6.0, 20.0);
            p.semi_axis_y = u(6.0, 20.0);
            p.slope = u(0.08, 0.3);
            p.spacing = 1.0;
            d.seafloor = make_gonzato_island(p);
            d.label = "island, axes " + std::to_string(p.semi_axis_x) + " x " + std::to_string(p.semi_axis_y);
            break;
        }
    }
    const double heading = u(0.25, 0.75) * std::numbers::pi;  // towards +y, ±45°
    d.train = {.period = u(3.0, 12.0), .amplitude = u(0.05, 1.0), .direction_x = std::cos(heading), .direction_y = std::sin(heading)};
    d.fronts.ray_spacing = u(2.0, 5.0);
    d.fronts.step = u(0.5, 2.0);
    d.fronts.split_distance = 3.0 * d.fronts.ray_spacing;
    d.label += ", T " + std::to_string(d.train.period) + " s, A " + std::to_string(d.train.amplitude) + " m";
    return d;
}

bool finite(const std::vector<double>& v) {
    for (double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

}  // namespace

TEST(Properties, RandomSeafloorsAndTrainsTraceAndMoveCleanly) {
    for (std::uint32_t seed = 1; seed <= 24; ++seed) {
        const Draw d = draw(seed);
        SCOPED_TRACE("seed " + std::to_string(seed) + ": " + d.label);
        const FrontSet fronts = trace_fronts(d.seafloor, d.train, d.fronts);
        ASSERT_GT(fronts.front_count(), 1u);
        ASSERT_LT(fronts.front_count(), d.fronts.max_steps);  // ended, not cut by the guard rail
        for (const auto* v : {&fronts.x, &fronts.y, &fronts.phase, &fronts.k, &fronts.amplitude, &fronts.depth})
            ASSERT_TRUE(finite(*v));

        const RayStrips strips = build_ray_strips(fronts);
        ASSERT_GT(strips.triangles.size(), 0u);
        std::size_t folded = 0;  // clockwise in plan (see below)
        for (std::size_t t = 0; t < strips.triangles.size(); t += 3) {
            const auto a = strips.triangles[t], b = strips.triangles[t + 1], c = strips.triangles[t + 2];
            ASSERT_TRUE(a != b && b != c && a != c) << "triangle " << t / 3 << " repeats a vertex";
            const double area = 0.5 * ((strips.x[b] - strips.x[a]) * (strips.y[c] - strips.y[a]) -
                                       (strips.x[c] - strips.x[a]) * (strips.y[b] - strips.y[a]));
            const double e2 = std::max({std::hypot(strips.x[b] - strips.x[a], strips.y[b] - strips.y[a]),
                                        std::hypot(strips.x[c] - strips.x[b], strips.y[c] - strips.y[b]),
                                        std::hypot(strips.x[a] - strips.x[c], strips.y[a] - strips.y[c])});
            ASSERT_GT(std::abs(area), 1e-9 * e2 * e2) << "triangle " << t / 3 << " is degenerate (collinear in plan)";
            folded += area < 0.0;
        }

        // Every vertex is in the water or on the shoreline, never on dry land: a ray that
        // steps across the shore ends on it (depth interpolated along the step), like the
        // aground rays that follow it. Before, it ended up to a step inland, and the
        // strip's last cells folded over the shore (this test's first finding: 100–220
        // folded triangles per planar beach, ~1 %; now 6–180, the rest below).
        // Tolerance: exact on a plane; 50 mm of elevation elsewhere, for a shoreline that
        // leaves the grid at the domain's edge (19 mm measured on one bay; before the
        // Newton iterations onto the shore, curved shores left vertices 2 m inland).
        double driest = 0.0;
        for (double h : strips.depth) driest = std::min(driest, h);
        EXPECT_GT(driest, seed % 3 == 0 ? -1e-9 : -0.05) << "a strip vertex lies on dry land";
        // Folded (clockwise) triangles remain: behind islands and headlands rays cross
        // (caustics), and aground rays sliding along the shore can pass a neighbour still
        // in the water (on planar beaches too, where no ray crosses). Recorded, not
        // asserted: clamping the slide removed them on planar beaches but made the
        // strips overlap more on Okushiri (docs/hardening.md).
        RecordProperty("folded_seed_" + std::to_string(seed), static_cast<int>(folded));
        const GonzatoMotionPlan motion = plan_gonzato_motion(strips, {});
        const JeschkeMotionPlan breakers = plan_jeschke_breakers(strips, 2.0 * d.train.amplitude,
                                                                 9.81 * d.train.period * d.train.period / (2.0 * std::numbers::pi));
        std::vector<float> p(3 * strips.vertex_count()), foam(strips.vertex_count());
        for (double t : {0.0, 0.37 * d.train.period, 1.9 * d.train.period}) {
            evaluate_gonzato_motion(motion, t, p);
            for (float x : p) ASSERT_TRUE(std::isfinite(x)) << "Gonzato at t = " << t;
            evaluate_jeschke_breakers(breakers, t, p);
            for (float x : p) ASSERT_TRUE(std::isfinite(x)) << "Jeschke at t = " << t;
            jeschke_foam(breakers, t, foam);
            for (float f : foam) ASSERT_TRUE(f >= 0.0f && f <= 1.0f);
        }
    }
}
