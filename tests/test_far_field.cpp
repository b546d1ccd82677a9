// The far field (surface.h plan_sea_skirt; motion.h plan_far_field, evaluate_far_field):
// the skirt's geometry against areas known by construction, and its motion against a
// plane wave that must continue unchanged beyond the border.
#include "libwave/errors.h"
#include "libwave/field.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/surface.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <map>
#include <numbers>
#include <vector>

namespace {

using namespace wave;

constexpr double kSide = 10.0, kReach = 200.0;

// A flat grid of 11 × 11 nodes over [0, 10]², optionally without its top-right quarter
// (x > 5 and y > 5): its border then leaves the rectangle there, like a shore; `graded`:
// the columns at x = i²/10, so that the border's edges grow from 0.1 m to 1.9 m.
struct Surface {
    std::vector<double> x, y;
    std::vector<std::uint32_t> triangles;
    explicit Surface(bool notch, bool graded = false) {
        for (std::size_t j = 0; j <= 10; ++j)
            for (std::size_t i = 0; i <= 10; ++i) {
                x.push_back(graded ? double(i * i) / 10.0 : double(i));
                y.push_back(double(j));
            }
        const std::vector<std::uint32_t> all = grid_triangles(11, 11);
        for (std::size_t t = 0; t < all.size(); t += 3) {
            const double cx = (x[all[t]] + x[all[t + 1]] + x[all[t + 2]]) / 3.0, cy = (y[all[t]] + y[all[t + 1]] + y[all[t + 2]]) / 3.0;
            if (notch && cx > 5.0 && cy > 5.0) continue;
            triangles.insert(triangles.end(), {all[t], all[t + 1], all[t + 2]});
        }
    }
};

// Edges grow with the distance (1 m at the border).
SeaSkirtOptions options() {
    SeaSkirtOptions o;
    o.distance = kReach;
    o.size = [](const SkirtSite& s) { return std::max(s.border_edge, 1.0 + 0.25 * s.d); };
    return o;
}

// A site d m below the bottom side's point (bx, 0), on a border edge `edge` long.
SkirtSite below(double bx, double d, double edge) { return {bx, -d, bx, 0.0, d, edge}; }

struct Corner {
    double x, y;
};

Corner at(const SeaSkirt& s, std::uint32_t v, const Surface& m) {
    return v < s.surface_vertices ? Corner{m.x[v], m.y[v]} : Corner{s.x[v - s.surface_vertices], s.y[v - s.surface_vertices]};
}

double signed_area(Corner a, Corner b, Corner c) { return 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)); }

double smallest_angle_deg(Corner a, Corner b, Corner c) {
    const auto angle = [](Corner p, Corner q, Corner r) {
        const double ux = q.x - p.x, uy = q.y - p.y, vx = r.x - p.x, vy = r.y - p.y;
        return std::acos(std::clamp((ux * vx + uy * vy) / std::hypot(ux, uy) / std::hypot(vx, vy), -1.0, 1.0));
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)}) * 180.0 / std::numbers::pi;
}

TEST(SeaSkirt, SurroundsAnAllWaterSurfaceOutToTheFarRectangle) {
    const Surface m(false);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    ASSERT_GT(s.vertex_count(), 0u);
    double area = 0.0, smallest = 180.0;
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
        const Corner a = at(s, s.triangles[t], m), b = at(s, s.triangles[t + 1], m), c = at(s, s.triangles[t + 2], m);
        const double A = signed_area(a, b, c);
        EXPECT_GT(A, 0.0) << "triangle " << t / 3 << " is not counter-clockwise";
        area += A;
        smallest = std::min(smallest, smallest_angle_deg(a, b, c));
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t p = s.triangles[t + e], q = s.triangles[t + (e + 1) % 3];
            ++edges[{std::min(p, q), std::max(p, q)}];
        }
    }
    // The annulus between [0, 10]² and [−R, 10 + R]², exactly.
    const double full = (kSide + 2.0 * kReach) * (kSide + 2.0 * kReach) - kSide * kSide;
    EXPECT_NEAR(area, full, 1e-9 * full);
    // The refinement's 20° everywhere, also on the border edges it cannot split (each
    // has its equilateral apex; 17° on the coast before).
    EXPECT_GE(smallest, 20.0);
    // New vertices lie outside the rectangle; the surface's own ones the skirt uses are
    // on its border; every boundary edge of the skirt lies on the rectangle or the far one.
    for (std::size_t v = 0; v < s.vertex_count(); ++v)
        EXPECT_TRUE(s.x[v] < 0.0 || s.x[v] > kSide || s.y[v] < 0.0 || s.y[v] > kSide) << v;
    std::size_t inner = 0;
    for (const auto& [e, n] : edges) {
        if (n != 1) continue;
        const Corner a = at(s, e.first, m), b = at(s, e.second, m);
        const bool on_inner = e.first < s.surface_vertices && e.second < s.surface_vertices;
        const auto on_far = [](Corner p) {
            return std::abs(p.x + kReach) < 1e-9 || std::abs(p.x - kSide - kReach) < 1e-9 || std::abs(p.y + kReach) < 1e-9 ||
                   std::abs(p.y - kSide - kReach) < 1e-9;
        };
        EXPECT_TRUE(on_inner || (on_far(a) && on_far(b))) << a.x << "," << a.y << " – " << b.x << "," << b.y;
        inner += on_inner;
    }
    EXPECT_EQ(inner, 40u);  // each of the grid's 40 border edges, shared once
}

// The apexes are left out where neighbouring border edges differ by more than 2.5 ×
// (here 3 × at x = 0): two apexes would make 19° there.
TEST(SeaSkirt, KeepsItsSmallestAngleOnAGradedBorder) {
    const Surface m(false, true);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    double smallest = 180.0;
    for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
        const Corner a = at(s, s.triangles[t], m), b = at(s, s.triangles[t + 1], m), c = at(s, s.triangles[t + 2], m);
        smallest = std::min(smallest, smallest_angle_deg(a, b, c));
    }
    EXPECT_GE(smallest, 20.0);
}

TEST(SeaSkirt, SizesFollowTheBorderSpacingWithoutSteps) {
    // Columns 1 m apart up to x = 5, then 0.5 m (a border edge halved, as the water
    // mesh's refinement does): the border's spacing at a vertex is the mean of its two
    // edges (0.75 m at x = 5), linear along each edge. The sizes used to step from 1 m to
    // 0.5 m there: a 2.7 m border edge met triangles sized for its 1.4 m neighbour.
    Surface m(false);
    m.x.clear(), m.y.clear();
    std::vector<double> columns;
    for (int i = 0; i <= 5; ++i) columns.push_back(i);
    for (int i = 11; i <= 20; ++i) columns.push_back(0.5 * i);
    for (std::size_t j = 0; j <= 10; ++j)
        for (double c : columns) m.x.push_back(c), m.y.push_back(double(j));
    m.triangles = grid_triangles(columns.size(), 11);
    SeaSkirtOptions o = options();
    o.size = [](const SkirtSite& site) { return site.border_edge + 0.25 * site.d; };
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, o);
    const auto spacing = [](double x) {  // along the bottom side
        if (x <= 4.0) return 1.0;
        if (x <= 5.0) return 1.0 - 0.25 * (x - 4.0);
        if (x <= 5.5) return 0.75 - 0.5 * (x - 5.0);
        return 0.5;
    };
    std::size_t checked = 0;
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        if (s.y[v] >= 0.0 || s.x[v] <= 0.5 || s.x[v] >= 9.5) continue;  // below the bottom side, away from its corners
        EXPECT_NEAR(s.size[v], spacing(s.x[v]) + 0.25 * s.distance[v], 1e-9) << s.x[v] << ", " << s.y[v];
        checked += s.x[v] > 4.0 && s.x[v] < 5.5;
    }
    EXPECT_GT(checked, 3u);
}

TEST(SeaSkirt, EndsOnStraightCutsWhereTheBorderIsDry) {
    const Surface m(true);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    double area = 0.0, smallest = 180.0;
    for (std::size_t t = 0; t < s.triangles.size(); t += 3) {
        const Corner a = at(s, s.triangles[t], m), b = at(s, s.triangles[t + 1], m), c = at(s, s.triangles[t + 2], m);
        area += signed_area(a, b, c);
        smallest = std::min(smallest, smallest_angle_deg(a, b, c));
        const double cx = (a.x + b.x + c.x) / 3.0, cy = (a.y + b.y + c.y) / 3.0;
        // Nothing beyond the dry border (the right side above y = 5, the top right of x = 5, their corner).
        EXPECT_FALSE((cx > kSide && cy > 5.0) || (cy > kSide && cx > 5.0)) << cx << ", " << cy;
    }
    const double full = (kSide + 2.0 * kReach) * (kSide + 2.0 * kReach) - kSide * kSide;
    const double dry = 5.0 * kReach + 5.0 * kReach + kReach * kReach;
    EXPECT_NEAR(area, full - dry, 1e-9 * full);
    // In the corners where a cut leaves the border too (its first step as long as the
    // border edge beside it; a quarter of the size made 14°).
    EXPECT_GE(smallest, 20.0);
    // The anchors are the nearest border edge's ends, weights on [0, 1].
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        const double bx = std::clamp(s.x[v], 0.0, kSide), by = std::clamp(s.y[v], 0.0, kSide);
        EXPECT_NEAR(s.distance[v], std::hypot(s.x[v] - bx, s.y[v] - by), 1e-9);
        const std::uint32_t a = s.anchor[2 * v], b = s.anchor[2 * v + 1];
        const double w = s.anchor_weight[v];
        EXPECT_NEAR(w * m.x[a] + (1.0 - w) * m.x[b], bx, 1e-6);
        EXPECT_NEAR(w * m.y[a] + (1.0 - w) * m.y[b], by, 1e-6);
    }
}

TEST(SeaSkirt, StopsAtAShoreThatIsAWholeSide) {
    // The surface reaches the waterline y = 10 along its whole top side, with land
    // beyond (a planar beach meshed up to its shore). Given the seafloor, the skirt ends
    // on cuts along the shore's line at the top corners: no sea beyond the top side.
    // Without it, the skirt carried the sea on over the land.
    Seafloor beach;
    beach.grid.nx = beach.grid.ny = 3;
    beach.grid.dx = beach.grid.dy = kSide;
    beach.grid.z = {-1.0, -1.0, -1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0};  // rows y = 0, 10, 20: elevation
    const Surface m(false);
    SeaSkirtOptions o = options();
    const SeaSkirt sea_everywhere = plan_sea_skirt(m.x, m.y, m.triangles, o);
    o.seafloor = &beach.grid;
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, o);
    const auto highest = [](const SeaSkirt& k) { return *std::max_element(k.y.begin(), k.y.end()); };
    EXPECT_GT(highest(sea_everywhere), kSide + 100.0);
    EXPECT_LE(highest(s), kSide);
    std::size_t on_cut = 0, beyond_sides = 0;
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        on_cut += s.y[v] == kSide;
        beyond_sides += s.y[v] > 0.0 && (s.x[v] < 0.0 || s.x[v] > kSide);
    }
    EXPECT_GT(on_cut, 10u) << "the cuts along the shore's line";
    EXPECT_GT(beyond_sides, 100u) << "the sea beyond the wet sides is kept";
}

TEST(SeaSkirt, SizesReadTheDepthNoShallowerThanTheBreakingDepth) {
    // A border point 1 mm deep (a beach met by the border): an 8 s wave's λ there is
    // 0.79 m, at the breaking depth of a 0.4 m swell (γ = 0.78: 1.03 m) 25 m. The sizes
    // read the latter, as the water mesh's do: λ/6 over the swell band, then the growth.
    Seafloor beach;
    beach.grid.nx = beach.grid.ny = 2;
    beach.grid.dx = beach.grid.dy = kSide;
    beach.grid.z.assign(4, -1e-3);
    const double floor = 2.0 * 0.4 / 0.78, lambda = linear_wave(2.0 * std::numbers::pi / 8.0, floor).wavelength;
    const SkirtSize size = swell_skirt_size(beach, 8.0, 2.0, floor);
    EXPECT_DOUBLE_EQ(size(below(5.0, 0.0, 1.0)), 1.0);                       // the border edge at the border
    EXPECT_DOUBLE_EQ(size(below(5.0, 10.0, 1.0)), 4.0);                      // growing by 0.3 d …
    EXPECT_NEAR(size(below(5.0, 30.0, 1.0)), lambda / 6.0, 1e-12);           // … to λ/6
    const double out = 10.0;
    EXPECT_NEAR(size(below(5.0, 2.0 * lambda + out, 1.0)), lambda / 6.0 + 0.08 * out + 0.3 * out * out / (out + 2.0 * lambda), 1e-9);
    // Without the floor the swell band is 2 × 0.79 m wide and 30 m out the edges have
    // grown to 11 m (against 4.2 m: the jump the floor removes beside a deeper border).
    const double shallow = linear_wave(2.0 * std::numbers::pi / 8.0, 1e-3).wavelength, past = 30.0 - 2.0 * shallow;
    EXPECT_NEAR(swell_skirt_size(beach, 8.0, 2.0)(below(5.0, 30.0, 1.0)), 1.0 + 0.08 * past + 0.3 * past * past / (past + 2.0 * shallow), 1e-9);
    EXPECT_THROW(swell_skirt_size(beach, 8.0, 2.0, 0.0), InputError);
    EXPECT_THROW(swell_skirt_size(beach, 8.0, 2.0, NAN), InputError);
}

// A flat floor 100 m down under the grid's square.
ElevationGrid deep_floor() {
    ElevationGrid g;
    g.nx = g.ny = 2;
    g.dx = g.dy = kSide;
    g.z.assign(4, -100.0);
    return g;
}

// The surface moving as a deep-water Gerstner wave travelling along +x at times t.
std::vector<float> gerstner_frame(const Surface& m, double A, double k, double omega, double t) {
    std::vector<float> p;
    for (std::size_t v = 0; v < m.x.size(); ++v) {
        const double phi = k * m.x[v] - omega * t;
        p.insert(p.end(), {float(m.x[v] - A * std::sin(phi)), float(m.y[v]), float(A * std::cos(phi))});
    }
    return p;
}

// The same at each of `times`, one after another (plan_far_field's samples).
std::vector<float> gerstner_frames(const Surface& m, double A, double k, double omega, const std::vector<double>& times) {
    std::vector<float> out;
    for (double t : times) {
        const std::vector<float> f = gerstner_frame(m, A, k, omega, t);
        out.insert(out.end(), f.begin(), f.end());
    }
    return out;
}

TEST(FarField, APlaneWaveRunsOnUnchangedBeyondEveryWetSide) {
    const Surface m(true);
    const double A = 0.05, k = 2.0 * std::numbers::pi / 8.0, omega = std::sqrt(9.81 * k);
    SeaSkirtOptions o = options();
    o.size = [](const SkirtSite& s) { return s.d < 30.0 ? std::max(s.border_edge, 0.5) : 0.5 + 0.3 * (s.d - 30.0); };
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, o);
    const std::vector<double> times{0.0, 0.37, 0.74, 1.11, 1.48, 1.85, 2.22};
    const std::vector<float> samples = gerstner_frames(m, A, k, omega, times);
    const FarFieldWave wave{.omega = omega, .direction_x = 1.0, .direction_y = 0.0, .k = k};
    const ElevationGrid flat = deep_floor();
    const FarFieldPlan p = plan_far_field(s, flat, std::span(&wave, 1), m.x, m.y, times, samples);
    std::vector<float> scratch;
    std::size_t checked = 0;
    for (double t : {0.1, 1.3, 2.9}) {
        std::vector<float> pos = gerstner_frame(m, A, k, omega, t);
        pos.resize(3 * (m.x.size() + s.vertex_count()));
        evaluate_far_field(p, t, pos, scratch);
        for (std::size_t v = 0; v < s.vertex_count(); ++v) {
            if (s.size[v] > (2.0 * std::numbers::pi / k) / 6.0) continue;  // fading out: not resolved there
            const double phi = k * s.x[v] - omega * t;
            const float* q = &pos[3 * (m.x.size() + v)];
            ASSERT_NEAR(q[0], s.x[v] - A * std::sin(phi), 2e-5 + 1e-7 * std::abs(s.x[v])) << s.x[v] << ", " << s.y[v];
            ASSERT_NEAR(q[1], s.y[v], 2e-5 + 1e-7 * std::abs(s.y[v]));
            ASSERT_NEAR(q[2], A * std::cos(phi), 2e-5);
            ++checked;
        }
    }
    EXPECT_GT(checked, 1000u);
    // Far out the skirt is still water.
    std::vector<float> pos = gerstner_frame(m, A, k, omega, 0.5);
    pos.resize(3 * (m.x.size() + s.vertex_count()));
    evaluate_far_field(p, 0.5, pos, scratch);
    for (std::size_t v = 0; v < s.vertex_count(); ++v)
        if (s.distance[v] > 100.0) {
            ASSERT_EQ(pos[3 * (m.x.size() + v) + 2], 0.0f);
        }
}

// The far field of a surface whose border stands still at height z in every sample (no
// wave moves it), for an 8 m wave, with a residual band of 16 m; `at_rest` gets the
// surface's positions.
FarFieldPlan still_border_plan(const Surface& m, const SeaSkirt& s, float z, std::vector<float>& at_rest) {
    const double k = 2.0 * std::numbers::pi / 8.0, omega = std::sqrt(9.81 * k);
    const std::vector<double> times{0.0, 0.5, 1.0, 1.5, 2.0};
    at_rest.clear();
    for (std::size_t v = 0; v < m.x.size(); ++v) at_rest.insert(at_rest.end(), {float(m.x[v]), float(m.y[v]), z});
    std::vector<float> samples;
    for (std::size_t i = 0; i < times.size(); ++i) samples.insert(samples.end(), at_rest.begin(), at_rest.end());
    const FarFieldWave wave{.omega = omega, .direction_x = 1.0, .direction_y = 0.0, .k = k};
    FarFieldOptions o;
    o.residual_wavelengths = 2.0;  // 16 m
    return plan_far_field(s, deep_floor(), std::span(&wave, 1), m.x, m.y, times, samples, o);
}

TEST(FarField, WhatTheWavesDoNotExplainFadesOutOverTheResidualBand) {
    const Surface m(false);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    // The border stands 0.2 m up (a set-up no wave explains) and no wave moves it.
    std::vector<float> one;
    const FarFieldPlan p = still_border_plan(m, s, 0.2f, one);
    std::vector<float> pos = one, scratch;
    pos[2] = 0.5f;  // now one anchor rises by a further 0.3 m: the skirt follows it near the border
    pos.resize(3 * (m.x.size() + s.vertex_count()));
    evaluate_far_field(p, 0.7, pos, scratch);
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        const float z = pos[3 * (m.x.size() + v) + 2];
        if (s.distance[v] >= 16.0) {
            EXPECT_NEAR(z, 0.0f, 1e-6f);
        }
        const bool touches_corner = s.anchor[2 * v] == 0 || s.anchor[2 * v + 1] == 0;
        if (s.distance[v] < 0.5 && !touches_corner) {
            EXPECT_NEAR(z, 0.2f, 0.01f);
        }
    }
}

TEST(FarField, TheBordersFoamRunsOnWithItsResidual) {
    // A breaking crest reaches the border: its foam (1 on every border vertex) is carried
    // into the skirt as its residual motion is, full at the border, none beyond the band.
    const Surface m(false);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    std::vector<float> at_rest;
    const FarFieldPlan p = still_border_plan(m, s, 0.0f, at_rest);
    std::vector<float> foam(m.x.size() + s.vertex_count(), 0.5f);  // the skirt's old values are overwritten
    for (std::size_t v = 0; v < m.x.size(); ++v) foam[v] = 1.0f;
    far_field_foam(p, foam);
    std::size_t near = 0, far = 0;
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        const float f = foam[m.x.size() + v];
        EXPECT_NEAR(f, p.residual_weight[v], 1e-6f);
        if (s.distance[v] >= 16.0) {
            EXPECT_EQ(f, 0.0f);
            ++far;
        }
        if (s.distance[v] < 2.0) {  // an eighth of the band
            EXPECT_GT(f, 0.9f);
            ++near;
        }
    }
    EXPECT_GT(near, 5u);
    EXPECT_GT(far, 10u);
    std::vector<float> short_foam(m.x.size());
    EXPECT_THROW(far_field_foam(p, short_foam), InputError);
}

TEST(FarField, ABeachMetByTheBorderDoesNotScrambleTheCarriedPhase) {
    // The border's right side (x = 10) crosses a beach: the depth beyond it rises from
    // 5 cm at y = 0 to 0.5 m at y = 10, so a 6 s wave's k there falls from 1.5 to
    // 0.47 rad/m along the side. Carried out along x, its phase k(y)·d varies along y by
    // (dk/dy)·d: 13 rad/m 20 m out at y = 0, more than the skirt's 0.3 m edges there can
    // carry. No skirt edge may then join vertices whose carried phases differ by more
    // than a third of a turn (the fade's limit: three edges a wavelength, the wave's
    // length taken from the phase's gradient, along the border too).
    const Surface m(false);
    SeaSkirtOptions o = options();
    o.size = [](const SkirtSite& s) { return s.bx == kSide && s.d < 25.0 ? 0.3 : std::max(s.border_edge, 1.0 + 0.25 * s.d); };
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, o);
    ElevationGrid beach;
    beach.nx = 2, beach.ny = 11;
    beach.x0 = -kReach, beach.dx = 2.0 * kReach + kSide, beach.y0 = 0.0, beach.dy = 1.0;
    for (std::size_t j = 0; j < 11; ++j)
        for (int i = 0; i < 2; ++i) beach.z.push_back(-(0.05 + 0.045 * double(j)));
    const double omega = 2.0 * std::numbers::pi / 6.0, k = wavenumber_for_period(6.0, 0.26);
    const std::vector<double> times{0.0, 0.9, 1.8, 2.7, 3.6, 4.5, 5.4};
    const std::vector<float> samples = gerstner_frames(m, 0.05, k, omega, times);
    const FarFieldWave wave{.omega = omega, .direction_x = 1.0, .direction_y = 0.0};
    const FarFieldPlan p = plan_far_field(s, beach, std::span(&wave, 1), m.x, m.y, times, samples);
    const auto z_of = [&](std::uint32_t v) -> std::complex<double> {
        if (v < s.surface_vertices) return 0.0;
        const float* a = &p.amplitude[6 * (v - s.surface_vertices) + 4];
        return {a[0], a[1]};
    };
    double worst = 0.0;
    std::size_t carried = 0;
    for (std::size_t t = 0; t < s.triangles.size(); t += 3)
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t u = s.triangles[t + c], v = s.triangles[t + (c + 1) % 3];
            const std::complex<double> a = z_of(u), b = z_of(v);
            if (std::abs(a) < 1e-6 || std::abs(b) < 1e-6 || std::min(at(s, u, m).x, at(s, v, m).x) < kSide) continue;
            worst = std::max(worst, std::abs(std::arg(a * std::conj(b))));
            ++carried;
        }
    std::printf("beyond the beach: %zu edges carry the wave, largest phase step %.2f rad\n", carried / 2, worst);
    EXPECT_GT(carried, 100u);
    EXPECT_LT(worst, 2.0 * std::numbers::pi / 3.0);
}

TEST(FarField, RefusesTooFewSamplesAndMismatchedSizes) {
    const Surface m(false);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    const FarFieldWave waves[2] = {{.omega = 1.0}, {.omega = 2.0}};
    const ElevationGrid flat = deep_floor();
    const std::vector<double> times{0.0, 1.0, 2.0, 3.0};  // 2 components need 5
    const std::vector<float> samples(3 * m.x.size() * times.size(), 0.0f);
    EXPECT_THROW(plan_far_field(s, flat, waves, m.x, m.y, times, samples), InputError);
    EXPECT_THROW(plan_far_field(s, flat, std::span(waves, 1), m.x, m.y, times, std::span(samples).first(10)), InputError);
    SeaSkirtOptions o = options();
    o.distance = -1.0;
    EXPECT_THROW(plan_sea_skirt(m.x, m.y, m.triangles, o), InputError);
    const std::vector<std::uint32_t> bad{0, 1, 9999};
    EXPECT_THROW(plan_sea_skirt(m.x, m.y, bad, options()), InputError);
}

TEST(FarField, TheSameBitsOnAnyThreadCount) {
    const Surface m(true);
    const SeaSkirt s = plan_sea_skirt(m.x, m.y, m.triangles, options());
    const double k = 0.7, omega = std::sqrt(9.81 * k);
    const std::vector<double> times{0.0, 0.3, 0.6, 0.9, 1.2};
    const std::vector<float> samples = gerstner_frames(m, 0.1, k, omega, times);
    const FarFieldWave wave{.omega = omega, .direction_x = 1.0, .direction_y = 0.5, .k = k};
    const ElevationGrid flat = deep_floor();
    const FarFieldPlan p = plan_far_field(s, flat, std::span(&wave, 1), m.x, m.y, times, samples);
    std::vector<std::vector<float>> out;
    for (std::size_t threads : {1u, 4u}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
        std::vector<float> pos = gerstner_frame(m, 0.1, k, omega, 0.77), scratch;
        pos.resize(3 * (m.x.size() + s.vertex_count()));
        evaluate_far_field(p, 0.77, pos, scratch);
        out.push_back(pos);
    }
    EXPECT_EQ(out[0], out[1]);
}

}  // namespace
