// Untangling a moved mesh (libwave/motion.h: plan_untangle, untangle_motion) on meshes
// whose answers are known by construction, and on a wave whose offsets fold it.
#include "libwave/errors.h"
#include "libwave/inspect.h"
#include "libwave/motion.h"
#include "libwave/surface.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace {

using namespace wave;

// A flat n × n grid of cells of side h, counter-clockwise from above.
struct Grid {
    std::size_t n;
    std::vector<double> x, y;
    std::vector<std::uint32_t> triangles;
    Grid(std::size_t n_, double h) : n(n_), triangles(grid_triangles(n_, n_)) {
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = 0; i < n; ++i) {
                x.push_back(h * double(i));
                y.push_back(h * double(j));
            }
    }
    std::vector<float> rest() const {
        std::vector<float> p;
        for (std::size_t v = 0; v < x.size(); ++v) p.insert(p.end(), {float(x[v]), float(y[v]), 0.0f});
        return p;
    }
};

// The smallest ratio of a triangle's area in plan to its rest area.
double smallest_area_ratio(const Grid& g, const std::vector<float>& p) {
    double lowest = 1e300;
    for (std::size_t t = 0; t < g.triangles.size() / 3; ++t) {
        const std::uint32_t a = g.triangles[3 * t], b = g.triangles[3 * t + 1], c = g.triangles[3 * t + 2];
        const double rest = (g.x[b] - g.x[a]) * (g.y[c] - g.y[a]) - (g.y[b] - g.y[a]) * (g.x[c] - g.x[a]);
        const double now = (double(p[3 * b]) - p[3 * a]) * (double(p[3 * c + 1]) - p[3 * a + 1]) -
                           (double(p[3 * b + 1]) - p[3 * a + 1]) * (double(p[3 * c]) - p[3 * a]);
        lowest = std::min(lowest, now / rest);
    }
    return lowest;
}

TEST(Untangle, OneTriangleTakesTheAnalyticFactor) {
    // (0,0) (1,0) (0,1): twice the area 1. The top vertex pulled down by 2 m: A(s) = 1 − 2s.
    const std::vector<double> x{0, 1, 0}, y{0, 0, 1};
    const std::vector<std::uint32_t> tri{0, 1, 2};  // no border, no shore (hold_shore would hold its long side)
    {
        // The passes alone: A ≥ 0.1 up to s = 0.45; they stay 2 % inside the root: 0.441.
        const UntanglePlan plan = plan_untangle(x, y, tri, {.pin_border = false, .hold_shore = false, .ramp_slope = 0.0});
        std::vector<float> p{0, 0, 0, 1, 0, 0, 0, -1, 0.5f};
        const UntangleReport r = untangle_motion(plan, {}, p);
        EXPECT_EQ(r.damped_vertices, 1u);
        EXPECT_NEAR(p[7], 1.0 - 2.0 * 0.98 * 0.45, 1e-6);
        EXPECT_EQ(p[6], 0.0f);     // the offset keeps its direction
        EXPECT_EQ(p[8], 0.5f);     // heights are not touched
        EXPECT_EQ(p[0], 0.0f);     // vertices that did not move stay
    }
    // The ramp: the offsets' gradient is diag(0, −2), a compression λ = −2; the bound
    // (1 + sλ)² ≥ 0.3 gives s = (1 − √0.3) / 2, and this one-axis squeeze keeps exactly
    // 1 − 2s = √0.3 of the area (≥ 0.3: no pass needed).
    const UntanglePlan plan = plan_untangle(x, y, tri, {.pin_border = false, .hold_shore = false});
    std::vector<float> p{0, 0, 0, 1, 0, 0, 0, -1, 0.5f};
    const UntangleReport r = untangle_motion(plan, {}, p);
    EXPECT_EQ(r.damped_vertices, 1u);
    EXPECT_EQ(r.passes, 1u);
    EXPECT_NEAR(p[7], std::sqrt(0.3), 1e-6);
    EXPECT_EQ(p[6], 0.0f);
    EXPECT_EQ(p[8], 0.5f);
}

TEST(Untangle, ARigidShiftAndAGentleWaveAreLeftAlone) {
    const Grid g(12, 1.0);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, {.pin_border = false});
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        p[3 * v] += 3.0f + 0.3f * float(std::sin(g.x[v]));  // d(offset)/dx ≥ −0.3: no triangle shrinks below 0.7
        p[3 * v + 1] -= 2.0f;
        p[3 * v + 2] = float(std::cos(g.x[v]));
    }
    const std::vector<float> before = p;
    const UntangleReport r = untangle_motion(plan, {}, p);
    EXPECT_EQ(r.damped_vertices, 0u);
    EXPECT_EQ(r.passes, 1u);
    EXPECT_EQ(p, before);
}

TEST(Untangle, BorderVerticesSlideAlongTheirSideOnly) {
    // A rigid shift by (0.3, −0.2) m of an 8 × 8 grid of 1 m cells: the interior moves,
    // side vertices keep x = 0 / 7 or y = 0 / 7 exactly, corners do not move sideways.
    const Grid g(8, 1.0);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles);
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        p[3 * v] += 0.3f;
        p[3 * v + 1] -= 0.2f;
        p[3 * v + 2] = 0.25f;
    }
    untangle_motion(plan, {}, p);
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        const bool side_x = g.x[v] == 0.0 || g.x[v] == 7.0, side_y = g.y[v] == 0.0 || g.y[v] == 7.0;
        EXPECT_EQ(p[3 * v], side_x ? float(g.x[v]) : float(g.x[v]) + 0.3f) << v;
        EXPECT_EQ(p[3 * v + 1], side_y ? float(g.y[v]) : float(g.y[v]) - 0.2f) << v;
        EXPECT_EQ(p[3 * v + 2], 0.25f);
    }
}

TEST(Untangle, AWholeSideInsideTheDomainIsShoreNotBorder) {
    // The 8 × 8 grid's top row (y = 7) is a straight shore: the domain reaches on to
    // y = 20. Given the domain, that row is held still as shore (flag 4) and the rows by
    // it are the shore's band; the other sides still slide along themselves. Without it
    // the row slid along y = 7 as a side of the bounding rectangle.
    const Grid g(8, 1.0);
    const UntanglePlan bare = plan_untangle(g.x, g.y, g.triangles);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.border_rectangle = {0.0, 0.0, 7.0, 20.0}});
    EXPECT_EQ(plan.y_max, 20.0);
    EXPECT_EQ(plan.x_max, 7.0);
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        if (g.y[v] != 7.0) continue;
        EXPECT_EQ(bare.pinned[v] & 6, 2) << v;
        EXPECT_TRUE(plan.pinned[v] & 4) << v;
        EXPECT_FALSE(plan.pinned[v] & 2) << v;
    }
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) p[3 * v] += 0.3f;
    untangle_motion(plan, {}, p);
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        const bool held = g.y[v] == 7.0 || g.x[v] == 0.0 || g.x[v] == 7.0;  // the shore, and the sides across x
        if (held) {
            EXPECT_EQ(p[3 * v], float(g.x[v])) << v;
        }
    }
    const double nan = NAN;
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.border_rectangle = {0.0, 0.0, 6.0, 20.0}}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.border_rectangle = {0.0, 0.0, 7.0, nan}}), InputError);
}

// A steep Gerstner-like wave on a grid: the offset x + Q·sin(kx) folds where Q·k > 1;
// `shift` moves it along (radians of phase).
std::vector<float> folded_wave(const Grid& g, double qk, double shift = 0.0) {
    const double k = 2.0 * std::numbers::pi / 8.0, q = qk / k;
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        const double phase = k * g.x[v] + 0.3 * g.y[v] - shift;  // crests slanted across the grid
        p[3 * v] = float(g.x[v] - q * std::sin(phase));
        p[3 * v + 2] = float(0.5 * std::cos(phase));
    }
    return p;
}

TEST(Untangle, AFoldingWaveKeepsEveryTriangleUpAndTheCrestsWhereTheyWere) {
    const Grid g(40, 0.5);
    // The passes alone (the ramp's own test follows), for the area only (the angle's
    // tests follow).
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, {.ramp_slope = 0.0, .min_angle_degrees = 0.0});
    std::vector<float> p = folded_wave(g, 1.6);
    ASSERT_LT(smallest_area_ratio(g, p), 0.0);  // folded as moved
    const std::vector<float> moved = p;
    const UntangleReport r = untangle_motion(plan, {}, p);
    EXPECT_GT(r.damped_vertices, 0u);
    EXPECT_LT(r.damped_vertices, g.x.size());  // the troughs keep their offsets
    EXPECT_GE(smallest_area_ratio(g, p), 0.1 - 1e-4);
    std::size_t unchanged = 0;
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        EXPECT_EQ(p[3 * v + 2], moved[3 * v + 2]);  // heights kept
        const double d0 = double(moved[3 * v]) - g.x[v], d1 = double(p[3 * v]) - g.x[v];
        EXPECT_LE(std::abs(d1), std::abs(d0) + 1e-5);  // only ever scaled down …
        EXPECT_GE(d0 * d1, 0.0);                      // … never reversed
        unchanged += moved[3 * v] == p[3 * v];
    }
    // Q·k = 1.6 squeezes a triangle below a tenth of its area where cos φ > 0.56 (31 % of
    // the phases); their vertices and one ring round them are damped, the rest not.
    EXPECT_GT(unchanged, g.x.size() / 8);
    // And the inspection agrees: nothing facing down.
    MorphAnimationView view;
    view.positions = p;
    view.triangles = g.triangles;
    view.vertex_count = g.x.size();
    view.frame_count = view.loop_frames = 1;
    view.fps = 24.0;
    EXPECT_EQ(inspect_animation(view).frames[0].facing_down, 0u);
}

// The wave moving on by 1/96 of a period per step (Q·k = 1.6: 2 m sweeps folding on
// 31 % of the phases). A vertex's untangled position may move per step at most twice
// as far as the fastest moved vertex does: the factors are continuous in the offsets.
// The passes alone fail this: neighbours damped unevenly fold again and take the last
// resort, s = 0, one step and not the next.
double largest_step_ratio(const UntangleOptions& options, double* smallest_area) {
    const Grid g(40, 0.5);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, options);
    std::vector<float> before, moved_before;
    double moved_step = 0.0, step = 0.0;
    *smallest_area = 1e300;
    for (int i = 0; i <= 96; ++i) {
        std::vector<float> moved = folded_wave(g, 1.6, 2.0 * std::numbers::pi * i / 96.0), p = moved;
        untangle_motion(plan, {}, p);
        *smallest_area = std::min(*smallest_area, smallest_area_ratio(g, p));
        for (std::size_t v = 0; i > 0 && v < g.x.size(); ++v) {
            moved_step = std::max(moved_step, std::hypot(double(moved[3 * v]) - moved_before[3 * v],
                                                         double(moved[3 * v + 1]) - moved_before[3 * v + 1]));
            step = std::max(step, std::hypot(double(p[3 * v]) - before[3 * v], double(p[3 * v + 1]) - before[3 * v + 1]));
        }
        before = p;
        moved_before = moved;
    }
    return step / moved_step;
}

TEST(Untangle, TheRampKeepsAMovingWaveSmooth) {
    double area = 0.0;
    const double ramp = largest_step_ratio({}, &area);
    EXPECT_LT(ramp, 2.0);
    EXPECT_GE(area, 0.1 - 1e-4);
    const double passes = largest_step_ratio({.ramp_slope = 0.0}, &area);
    EXPECT_GT(passes, 2.0) << "the passes alone no longer jump: this test lost its witness";
    EXPECT_GE(area, 0.1 - 1e-4);
    std::printf("largest step over the moved wave's: ramp %.2f, passes alone %.2f\n", ramp, passes);
}

TEST(Untangle, FoamyCrestsAreLipsLeftToOverturn) {
    const Grid g(40, 0.5);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, {.pin_border = false});
    std::vector<float> p = folded_wave(g, 1.6);
    const std::vector<float> moved = p;
    const std::vector<float> foam(g.x.size(), 1.0f);  // every vertex breaking, fully foamy
    const UntangleReport r = untangle_motion(plan, foam, p);
    EXPECT_EQ(r.damped_vertices, 0u);
    EXPECT_EQ(p, moved);
    // Half foamy: the passes leave the lips alone, the ramp frees them by half (the
    // smoothstep of (0.55 − 0.1) / 0.9): every offset between the foam-free answer and
    // the motion's own.
    std::vector<float> half = moved, none = moved;
    untangle_motion(plan, std::vector<float>(g.x.size(), 0.55f), half);
    untangle_motion(plan, {}, none);
    std::size_t between = 0;
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        const double d_none = double(none[3 * v]) - g.x[v], d_half = double(half[3 * v]) - g.x[v], d = double(moved[3 * v]) - g.x[v];
        EXPECT_LE(std::abs(d_none), std::abs(d_half) + 1e-5) << v;
        EXPECT_LE(std::abs(d_half), std::abs(d) + 1e-5) << v;
        between += std::abs(d_half) > std::abs(d_none) + 1e-3 && std::abs(d_half) < std::abs(d) - 1e-3;
    }
    EXPECT_GT(between, g.x.size() / 4);
}

// The triangles of a 20 m grid of 0.5 m cells whose land (x + 0.3 y > 14 m) is cut
// out: a staircase shoreline off the rectangle's sides.
std::vector<std::uint32_t> staircase_water(const Grid& g) {
    std::vector<std::uint32_t> water;
    for (std::size_t t = 0; t < g.triangles.size() / 3; ++t) {
        const std::uint32_t* v = &g.triangles[3 * t];
        const double cx = (g.x[v[0]] + g.x[v[1]] + g.x[v[2]]) / 3.0, cy = (g.y[v[0]] + g.y[v[1]] + g.y[v[2]]) / 3.0;
        if (cx + 0.3 * cy <= 14.0) water.insert(water.end(), v, v + 3);
    }
    return water;
}

// The longest of triangle v's edges in plan over its rest length.
double largest_stretch(const Grid& g, const std::vector<float>& p, const std::uint32_t* v) {
    double most = 0.0;
    for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = v[c], b = v[(c + 1) % 3];
        most = std::max(most, std::hypot(double(p[3 * b]) - p[3 * a], double(p[3 * b + 1]) - p[3 * a + 1]) /
                                  std::hypot(g.x[b] - g.x[a], g.y[b] - g.y[a]));
    }
    return most;
}

TEST(Untangle, TheShoreHoldsStillAndNoTriangleFoldsOverIt) {
    // A 20 m square of water whose land (x + 0.3 y > 14 m) is cut out: a staircase
    // shoreline off the rectangle's sides. A steep wave runs onto it, foamy everywhere
    // (every triangle a lip): the vertices next to the shore are carried past it.
    const Grid g(40, 0.5);
    const std::vector<std::uint32_t> water = staircase_water(g);
    const std::vector<float> moved = folded_wave(g, 1.6);
    const std::vector<float> foam(g.x.size(), 1.0f);
    const auto area = [&](const std::vector<float>& p, const std::uint32_t* v) {
        return (double(p[3 * v[1]]) - p[3 * v[0]]) * (double(p[3 * v[2] + 1]) - p[3 * v[0] + 1]) -
               (double(p[3 * v[1] + 1]) - p[3 * v[0] + 1]) * (double(p[3 * v[2]]) - p[3 * v[0]]);
    };
    const std::vector<float> rest = g.rest();
    const UntanglePlan plan = plan_untangle(g.x, g.y, water);
    std::size_t shore = 0;
    for (std::size_t v = 0; v < g.x.size(); ++v) shore += (plan.pinned[v] & 4) != 0;
    // A vertex of a triangle on the shore is one ring from it at most.
    const auto by_shore = [&](std::uint32_t v) { return plan.shore_ring[v] <= 1; };
    EXPECT_GT(shore, 40u);  // the staircase: ~27 m of shore in 0.5 m steps
    // Without holding the shore, the lips fold over it.
    {
        std::vector<float> p = moved;
        untangle_motion(plan_untangle(g.x, g.y, water, {.hold_shore = false}), foam, p);
        std::size_t down = 0;
        for (std::size_t t = 0; t < water.size() / 3; ++t) down += by_shore(water[3 * t]) && area(p, &water[3 * t]) < 0.0;
        EXPECT_GT(down, 10u);
    }
    std::vector<float> p = moved;
    untangle_motion(plan, foam, p);
    std::size_t away = 0;
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        if (plan.pinned[v] & 4) {  // the shore: at rest in plan, its height the wave's
            EXPECT_EQ(p[3 * v], float(g.x[v])) << v;
            EXPECT_EQ(p[3 * v + 1], float(g.y[v])) << v;
            EXPECT_EQ(p[3 * v + 2], moved[3 * v + 2]) << v;
        } else if (plan.shore_ring[v] > plan.options.shore_band_rings && plan.pinned[v] == 0) {
            // beyond the shore's band and off the sides, the lips overturn as moved
            EXPECT_EQ(p[3 * v], std::clamp(moved[3 * v], 0.0f, 19.5f)) << v;  // a lip over a side stops at it
            ++away;
        }
    }
    EXPECT_GT(away, 600u);  // of ~1 100 wet vertices, the band ~3 × 54 wide
    // Every triangle on the shore keeps a tenth of its area, facing up, and its edges
    // at most about twice their rest length (the ramp damps its stretch).
    std::size_t kept = 0;
    double stretch = 0.0;
    for (std::size_t t = 0; t < water.size() / 3; ++t) {
        const std::uint32_t* v = &water[3 * t];
        if (!((plan.pinned[v[0]] | plan.pinned[v[1]] | plan.pinned[v[2]]) & 4)) continue;
        EXPECT_GE(area(p, v), 0.1 * area(rest, v) - 1e-6) << t;
        stretch = std::max(stretch, largest_stretch(g, p, v));
        ++kept;
    }
    EXPECT_GT(kept, 40u);
    std::printf("largest stretch of a shore triangle's edge: %.2f\n", stretch);
    EXPECT_LT(stretch, 2.2);
}

TEST(Untangle, ByTheHeldShoreAStretchIsDampedToo) {
    // The backwash: the water of the test above pulled 1 m seawards, all of it, the
    // shore held. Its triangles' edges (0.5 m) stretched up to 2.3 × their rest length
    // without the damping; the ramp keeps them at 1.15 × and fades out seawards, where
    // the water moves as asked.
    const Grid g(40, 0.5);
    const std::vector<std::uint32_t> water = staircase_water(g);
    const UntanglePlan plan = plan_untangle(g.x, g.y, water);
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) p[3 * v] -= 1.0f;
    untangle_motion(plan, {}, p);
    double stretch = 0.0;
    for (std::size_t t = 0; t < water.size() / 3; ++t) {
        const std::uint32_t* v = &water[3 * t];
        if (!((plan.pinned[v[0]] | plan.pinned[v[1]] | plan.pinned[v[2]]) & 4)) continue;
        stretch = std::max(stretch, largest_stretch(g, p, v));
    }
    std::printf("largest stretch of a shore triangle's edge in the backwash: %.2f\n", stretch);
    EXPECT_LT(stretch, 1.2);
    EXPECT_GT(stretch, 1.1);
    std::size_t far_moved = 0, far = 0;  // 6 m or more from the shore line, 4 m from x = 0 (its own ramp)
    for (std::size_t v = 0; v < g.x.size(); ++v)
        if (plan.pinned[v] == 0 && g.x[v] >= 4.0 && g.x[v] + 0.3 * g.y[v] < 14.0 - 6.0 * std::hypot(1.0, 0.3)) {
            ++far;
            far_moved += p[3 * v] == float(g.x[v]) - 1.0f;
        }
    EXPECT_GT(far, 50u);
    EXPECT_EQ(far_moved, far);
}

TEST(Untangle, ByTheHeldShoreASqueezeKeepsSevenTenthsOfTheArea) {
    // The uprush: the water of the test above pushed 1 m landwards (0.3 of it across the
    // staircase's diagonal shore), all of it, no foam, the shore held. In the shore's
    // band the ramp keeps 0.7 of each triangle's rest area (shore_band_area_ratio): the
    // swash next to the held shore stays clear of slivers. With the band at the open
    // water's 0.3, its triangles keep less (witness), and their smallest angles fall
    // (measured: 0.80 of the area and 33.7° against 0.55 and 24.5°).
    const Grid g(40, 0.5);
    const std::vector<std::uint32_t> water = staircase_water(g);
    const auto run = [&](double band_ratio, double& least_angle) {
        const UntanglePlan plan = plan_untangle(g.x, g.y, water, {.shore_band_area_ratio = band_ratio});
        std::vector<float> p = g.rest();
        for (std::size_t v = 0; v < g.x.size(); ++v) p[3 * v] += 1.0f;
        untangle_motion(plan, {}, p);
        const std::vector<float> rest = g.rest();
        double least = 1e9;
        least_angle = 180.0;
        for (std::size_t t = 0; t < water.size() / 3; ++t) {
            const std::uint32_t* v = &water[3 * t];
            if (std::min({plan.shore_ring[v[0]], plan.shore_ring[v[1]], plan.shore_ring[v[2]]}) >= plan.options.shore_band_rings) continue;
            const auto twice_area = [&](const std::vector<float>& q) {
                return (double(q[3 * v[1]]) - q[3 * v[0]]) * (double(q[3 * v[2] + 1]) - q[3 * v[0] + 1]) -
                       (double(q[3 * v[1] + 1]) - q[3 * v[0] + 1]) * (double(q[3 * v[2]]) - q[3 * v[0]]);
            };
            least = std::min(least, twice_area(p) / twice_area(rest));
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t a = v[c], b = v[(c + 1) % 3], d = v[(c + 2) % 3];
                const double ux = double(p[3 * b]) - p[3 * a], uy = double(p[3 * b + 1]) - p[3 * a + 1];
                const double wx = double(p[3 * d]) - p[3 * a], wy = double(p[3 * d + 1]) - p[3 * a + 1];
                least_angle = std::min(least_angle, std::atan2(std::abs(ux * wy - uy * wx), ux * wx + uy * wy) * 180.0 / std::numbers::pi);
            }
        }
        return least;
    };
    double angle = 0.0, open_angle = 0.0;
    const double kept = run(0.7, angle), open_kept = run(0.3, open_angle);
    std::printf("least area kept in the shore's band: %.3f (0.3: %.3f); smallest angle %.1f° (%.1f°)\n", kept, open_kept,
                angle, open_angle);
    EXPECT_GE(kept, 0.7 - 1e-6);
    EXPECT_LT(open_kept, 0.6);
    EXPECT_GT(angle, open_angle);
    EXPECT_THROW(plan_untangle(g.x, g.y, water, {.shore_band_area_ratio = 0.2}), InputError);  // below ramp_area_ratio
    EXPECT_THROW(plan_untangle(g.x, g.y, water, {.shore_band_area_ratio = 1.0}), InputError);
}

TEST(Untangle, WhereRaysPartTheSeamStretchesAtMostTwoAndAHalfTimes) {
    // Behind an island the rays from its two sides meet, and the water on either side of
    // the line moves along its own rays: here 0.7 m apart across a seam of 0.5 m cells
    // (Gonzato's island: edges 3.5 × their neighbours' there). No foam: no lip.
    const Grid g(40, 0.5);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles);
    std::vector<float> p = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) p[3 * v] += g.x[v] > 9.9 ? 0.7f : -0.7f;
    untangle_motion(plan, {}, p);
    double stretch = 0.0;
    for (std::size_t t = 0; t < g.triangles.size() / 3; ++t) stretch = std::max(stretch, largest_stretch(g, p, &g.triangles[3 * t]));
    std::printf("largest stretch across the seam: %.2f (3.8 unbounded)\n", stretch);
    EXPECT_LT(stretch, 2.55);
    EXPECT_GT(stretch, 2.3);
    // 4 m or more from the seam and from the sides x = const (each with its own ramp:
    // a side slides along itself only), the water moves as asked.
    std::size_t far = 0, far_moved = 0;
    for (std::size_t v = 0; v < g.x.size(); ++v)
        if (std::abs(g.x[v] - 9.95) > 4.0 && g.x[v] > 4.0 && g.x[v] < 15.5 && plan.pinned[v] == 0) {
            ++far;
            far_moved += std::abs(std::abs(double(p[3 * v]) - g.x[v]) - 0.7) < 1e-5;
        }
    EXPECT_GT(far, 100u);
    EXPECT_EQ(far_moved, far);
}

// The smallest angle (degrees, in 3D) over the triangles.
double smallest_angle(const std::vector<std::uint32_t>& triangles, const std::vector<float>& p) {
    double lowest = 180.0;
    for (std::size_t t = 0; t < triangles.size() / 3; ++t)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = triangles[3 * t + c], b = triangles[3 * t + (c + 1) % 3], d = triangles[3 * t + (c + 2) % 3];
            double u[3], w[3];
            for (int k = 0; k < 3; ++k) u[k] = double(p[3 * b + k]) - p[3 * a + k], w[k] = double(p[3 * d + k]) - p[3 * a + k];
            const double dot = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
            const double cross = std::hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]);
            lowest = std::min(lowest, std::atan2(cross, dot) * 180.0 / std::numbers::pi);
        }
    return lowest;
}

TEST(Untangle, AMotionThatThinsTrianglesKeepsSixteenDegrees) {
    // The grid's right isosceles triangles squeezed to 0.55 along x and stretched 2.4 ×
    // along y: within the ramp's area and stretch bounds (0.55 > 1 − √0.3, 2.4 < 2.5),
    // but the 45° angles go to atan(0.55 / 2.4) = 12.9°. Every triangle alike, so every
    // vertex takes the factor s with (1 − 0.45 s) / (1 + 1.4 s) = tan 16°, 2 % inside.
    const Grid g(12, 1.0);
    std::vector<float> moved = g.rest();
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        moved[3 * v] += float(-0.45 * (g.x[v] - 5.5));
        moved[3 * v + 1] += float(1.4 * (g.y[v] - 5.5));
        moved[3 * v + 2] = 0.1f;
    }
    const UntangleOptions free{.pin_border = false, .hold_shore = false};
    std::vector<float> p = moved;
    untangle_motion(plan_untangle(g.x, g.y, g.triangles, {.pin_border = false, .hold_shore = false, .min_angle_degrees = 0.0}), {}, p);
    EXPECT_NEAR(smallest_angle(g.triangles, p), std::atan(0.55 / 2.4) * 180.0 / std::numbers::pi, 1e-3);  // the witness: left alone
    p = moved;
    untangle_motion(plan_untangle(g.x, g.y, g.triangles, free), {}, p);
    const double tan16 = std::tan(16.0 * std::numbers::pi / 180.0), s = 0.98 * (1.0 - tan16) / (0.45 + 1.4 * tan16);
    for (std::size_t v = 0; v < g.x.size(); ++v) {
        EXPECT_NEAR(p[3 * v], g.x[v] - 0.45 * s * (g.x[v] - 5.5), 1e-5) << v;
        EXPECT_NEAR(p[3 * v + 1], g.y[v] + 1.4 * s * (g.y[v] - 5.5), 1e-5) << v;
        EXPECT_EQ(p[3 * v + 2], 0.1f);  // heights kept
    }
    EXPECT_GT(smallest_angle(g.triangles, p), 16.0);
}

TEST(Untangle, AChoppyWaveKeepsSixteenDegrees) {
    // The folding wave (Q·k = 1.6) with its crests also pulled along them: squeezed one way
    // and stretched the other. Over a whole period, no triangle (45° at rest) goes below 16°.
    const Grid g(40, 0.5);
    const auto lowest_over_period = [&](const UntangleOptions& options) {
        const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles, options);
        double lowest = 180.0;
        for (int i = 0; i < 24; ++i) {
            const double shift = 2.0 * std::numbers::pi * i / 24.0;
            std::vector<float> p = folded_wave(g, 1.6, shift);
            for (std::size_t v = 0; v < g.x.size(); ++v)
                p[3 * v + 1] += float(0.6 * std::cos(2.0 * std::numbers::pi / 8.0 * g.x[v] + 0.3 * g.y[v] - shift));
            untangle_motion(plan, {}, p);
            lowest = std::min(lowest, smallest_angle(g.triangles, p));
        }
        return lowest;
    };
    const double with = lowest_over_period({}), without = lowest_over_period({.min_angle_degrees = 0.0});
    std::printf("smallest angle over the period: %.2f° (%.2f° without the angle bound)\n", with, without);
    EXPECT_GT(with, 15.9);
    EXPECT_LT(without, 15.0) << "the ramp alone no longer thins triangles: this test lost its witness";
}

TEST(Untangle, TheRampsOwnShearThinsNoTriangleBelowSixteenDegrees) {
    // Rows of 35°–35°–110° triangles (as the coast's), all moving 1 m down (−y) and
    // squeezed to 0.7 across the rows, except the first rows, which squeeze hard: the
    // ramp damps there and rises upwards by 0.2 × edge / offset per edge. A row's lower
    // vertices are then damped more than its upper ones, which come down onto them: the
    // spread's own shear flattens the 110° triangles. The angle's later rounds and the
    // passes keep 16°.
    const double a = 1.0, b = 0.5 * a * std::tan(35.0 * std::numbers::pi / 180.0);
    const std::uint32_t nx = 24, ny = 16;
    std::vector<double> x, y;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) x.push_back(a * double(i) + (j % 2 ? 0.5 * a : 0.0)), y.push_back(b * double(j));
    std::vector<std::uint32_t> triangles;
    for (std::uint32_t j = 0; j + 1 < ny; ++j)
        for (std::uint32_t i = 0; i + 1 < nx; ++i) {
            const std::uint32_t l0 = j * nx + i, l1 = l0 + 1, u0 = l0 + nx, u1 = u0 + 1;
            if (j % 2 == 0) triangles.insert(triangles.end(), {l0, l1, u0, l1, u1, u0});
            else triangles.insert(triangles.end(), {l0, u1, u0, l0, l1, u1});
        }
    std::vector<float> moved;
    for (std::size_t v = 0; v < x.size(); ++v) {
        const double row = std::round(y[v] / b);
        const double squeeze = row <= 2.0 ? 0.85 * b * row : 0.85 * b * 2.0 + 0.3 * (y[v] - 2.0 * b);
        moved.insert(moved.end(), {float(x[v]), float(y[v] - 1.0 - squeeze), 0.0f});
    }
    const auto lowest = [&](const UntangleOptions& options) {
        std::vector<float> p = moved;
        untangle_motion(plan_untangle(x, y, triangles, options), {}, p);
        return smallest_angle(triangles, p);
    };
    const double with = lowest({.pin_border = false, .hold_shore = false}),
                 without = lowest({.pin_border = false, .hold_shore = false, .min_angle_degrees = 0.0});
    std::printf("smallest angle: %.2f° (%.2f° without the angle bound; %.2f° as moved)\n", with, without,
                smallest_angle(triangles, moved));
    EXPECT_GT(with, 15.9);
    EXPECT_LT(without, 15.0) << "the ramp's spread no longer thins triangles: this test lost its witness";
}

TEST(Untangle, TheSameBitsOnOneThreadAndOnMany) {
    const Grid g(120, 0.25);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles);
    std::vector<float> one = folded_wave(g, 2.5), many = one;
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
        untangle_motion(plan, {}, one);
    }
    {
        tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
        untangle_motion(plan, {}, many);
    }
    EXPECT_EQ(one, many);
    EXPECT_GE(smallest_area_ratio(g, one), 0.1 - 1e-4);
}

TEST(Untangle, WrongSizesAndOptionsAreRefused) {
    const Grid g(3, 1.0);
    EXPECT_THROW(plan_untangle(g.x, std::vector<double>(2), g.triangles), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, std::vector<std::uint32_t>{0, 1, 9}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, std::vector<std::uint32_t>{0, 1}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.min_area_ratio = 1.0}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.shore_band_rings = 255}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.ramp_slope = -1.0}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.ramp_slope = NAN}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.ramp_area_ratio = 0.05}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.ramp_area_ratio = 1.0}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.min_angle_degrees = 60.0}), InputError);
    EXPECT_THROW(plan_untangle(g.x, g.y, g.triangles, UntangleOptions{.min_angle_degrees = -1.0}), InputError);
    const UntanglePlan plan = plan_untangle(g.x, g.y, g.triangles);
    std::vector<float> p(3 * 9 - 1);
    EXPECT_THROW(untangle_motion(plan, {}, p), InputError);
    std::vector<float> ok = g.rest(), foam(4);
    EXPECT_THROW(untangle_motion(plan, foam, ok), InputError);
}

}  // namespace
