// Jeschke, Birkholz & Schumann's procedural breaker: the shape of table 1 against its
// closed forms, continuity in s and in time, the automatic parametrisation on the
// planar beach against the analytic shoaling, and the history-free foam.
#include <gtest/gtest.h>

#include "grid_seafloor.h"
#include "planar_beach_wave.h"
#include "libwave/errors.h"
#include "libwave/inspect.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/scene.h"
#include "libwave/shade.h"
#include "libwave/surface.h"
#include "libwave/trace.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <vector>

using namespace wave;

namespace {

const BreakerPhase kPhases[] = {BreakerPhase::round, BreakerPhase::breaking, BreakerPhase::collapsing};

BreakerShapePoint shape(BreakerPhase phase, double t, double s, double curl = 1.0) {
    return jeschke_shape(s, jeschke_constants(phase, t, false), jeschke_constants(phase, t, true), curl);
}

// The planar beach (slope 0.05, waves running +y at normal incidence), 8 s swell.
const char* kBeach = R"({"name": "jeschke beach", "seafloor": {"source": "planar-beach"},
  "isobaths": {"spacing": 0.5}, "waves": [{"period": 8, "amplitude": 0.4, "direction": [0, 1]}],
  "trace": {"ray_spacing": 4}, "breakers": "jeschke", "animation": {"fps": 8},
  "surface": {"water_mesh": false}})";  // the breakers on the traced strips themselves

// The same beach with every crest alike (no per-wave variation): one period loops.
std::string alike_beach() {
    std::string s = kBeach;
    s.replace(s.find("\"breakers\": \"jeschke\""), 21, R"("breakers": {"wave_variation": 0})");
    return s;
}

}  // namespace

TEST(JeschkeShape, RoundPhaseIsARaisedCosine) {
    // k1 = 1, k2 = 1/4, k3 = k5 = 0: y = 1 − s and z = k7 (1 − cos 2πs) / 8 exactly.
    for (double t : {0.3, 1.0})
        for (int i = 0; i <= 100; ++i) {
            const double s = i / 100.0;
            const BreakerShapePoint p = shape(BreakerPhase::round, t, s);
            EXPECT_NEAR(p.y, 1.0 - s, 1e-12) << s;
            EXPECT_NEAR(p.z, 0.8 * t * (1.0 - std::cos(2 * std::numbers::pi * s)) / 8.0, 1e-12) << s;
        }
}

TEST(JeschkeShape, EdgesRestOnStillWaterInEveryPhase) {
    // Neighbouring crests meet at s = 0 / s = 1: both edges must be at rest whatever
    // the phase, so a vertex passing from one crest's shape to the next does not jump.
    for (BreakerPhase ph : kPhases)
        for (double t : {0.0, 0.1, 0.5, 0.9, 1.0})
            for (double curl : {0.3, 1.0}) {
                const BreakerShapePoint back = shape(ph, t, 0.0, curl), front = shape(ph, t, 1.0, curl);
                EXPECT_NEAR(back.y, 1.0, 1e-12);
                EXPECT_NEAR(back.z, 0.0, 1e-12);
                EXPECT_NEAR(front.y, 0.0, 1e-12);
                EXPECT_NEAR(front.z, 0.0, 1e-12);
            }
}

TEST(JeschkeConstants, NoJumpBetweenPhasesAndTheMisprintReadContinuously) {
    for (bool front : {false, true}) {
        const auto r1 = jeschke_constants(BreakerPhase::round, 1.0, front);
        const auto b0 = jeschke_constants(BreakerPhase::breaking, 0.0, front);
        const auto b1 = jeschke_constants(BreakerPhase::breaking, 1.0, front);
        const auto c0 = jeschke_constants(BreakerPhase::collapsing, 0.0, front);
        for (int i = 1; i <= 7; ++i) {
            EXPECT_NEAR(r1.k[i], b0.k[i], 1e-12) << "k" << i << (front ? " front" : " back");
            EXPECT_NEAR(b1.k[i], c0.k[i], 1e-12) << "k" << i << (front ? " front" : " back");
        }
        // Table 1's values at the phases' ends: breaking front k1 = 2, k6 = 16, k7 = 1;
        // collapsing ends flat (k7 = 0); dead is the collapsing end.
        EXPECT_DOUBLE_EQ(b1.k[7], 1.0);
        EXPECT_DOUBLE_EQ(jeschke_constants(BreakerPhase::collapsing, 1.0, front).k[7], 0.0);
        EXPECT_EQ(jeschke_constants(BreakerPhase::dead, 0.2, front).k, jeschke_constants(BreakerPhase::collapsing, 1.0, front).k);
        // k5 (printed 3/t², infinite at t = 0) read as t^{3/2}: finite and rising.
        for (double t : {0.0, 0.25, 0.5, 1.0})
            EXPECT_NEAR(jeschke_constants(BreakerPhase::breaking, t, front).k[5], std::pow(t, 1.5), 1e-12);
    }
    EXPECT_DOUBLE_EQ(jeschke_constants(BreakerPhase::breaking, 1.0, true).k[1], 2.0);
    EXPECT_DOUBLE_EQ(jeschke_constants(BreakerPhase::breaking, 1.0, true).k[6], 16.0);
    EXPECT_DOUBLE_EQ(jeschke_constants(BreakerPhase::breaking, 1.0, false).k[1], 0.7);
}

TEST(JeschkeShape, BreakingEndsInAClosedTubeAndSpillingOnlyTips) {
    // Figure 3b: at the end of the breaking phase the lip has fallen onto the water ahead
    // of the crest, closing a tube; the front overhangs (1 − y, the distance along the
    // travel, runs backwards somewhere on the front half).
    const auto crest_and_lip = [](double curl) {
        double z_max = 0.0, x_crest = 0.0;
        for (int i = 0; i <= 1000; ++i) {
            const BreakerShapePoint p = shape(BreakerPhase::breaking, 1.0, i / 1000.0, curl);
            if (p.z > z_max) z_max = p.z, x_crest = 1.0 - p.y;
        }
        const BreakerShapePoint lip = shape(BreakerPhase::breaking, 1.0, 0.5, curl);
        return std::array<double, 4>{z_max, x_crest, lip.z, 1.0 - lip.y};
    };
    const auto plunging = crest_and_lip(1.0);
    EXPECT_LT(plunging[2], 0.05 * plunging[0]) << "the lip reaches the water";
    EXPECT_GT(plunging[3], plunging[1] + 0.1) << "ahead of the crest";
    bool overhang = false;
    double prev = 1.0 - shape(BreakerPhase::breaking, 1.0, 0.5).y;
    for (int i = 1; i <= 500; ++i) {
        const double x = 1.0 - shape(BreakerPhase::breaking, 1.0, 0.5 + i / 1000.0).y;
        overhang |= x < prev - 1e-6;
        prev = x;
    }
    EXPECT_TRUE(overhang);
    const auto spilling = crest_and_lip(0.3);
    EXPECT_GT(spilling[2], 0.5 * spilling[0]) << "a spilling crest only tips forward";
}

TEST(JeschkeShape, NoTearAlongTheWave) {
    // Consecutive points 1e-4 apart in s stay close in every phase: the halves meet at
    // the lip (the seam joins the collapsing phase's two different lip points).
    for (BreakerPhase ph : kPhases)
        for (double t : {0.0, 0.3, 0.6, 1.0}) {
            double worst = 0.0;
            BreakerShapePoint prev = shape(ph, t, 0.0);
            for (int i = 1; i <= 10000; ++i) {
                const BreakerShapePoint p = shape(ph, t, i / 10000.0);
                worst = std::max(worst, std::hypot(p.y - prev.y, p.z - prev.z));
                prev = p;
            }
            EXPECT_LT(worst, 0.01) << "phase " << static_cast<int>(ph) << " t " << t;
        }
}

// Per label step of a section at `ratio` (5H/W): the packing |d(x, ratio z)/ds| and the
// speed c |(1 − dx/ds, ratio dz/ds)| of a point of the section moving at c, as extremes.
struct SectionExtremes {
    double least_packing = 1e9, fastest = 0.0, least_dx = 1e9;
};
SectionExtremes section_extremes(const std::vector<BreakerSectionPoint>& q, double ratio) {
    SectionExtremes e;
    const double ds = 1.0 / static_cast<double>(q.size() - 1);
    for (std::size_t m = 0; m + 1 < q.size(); ++m) {
        const double tx = (q[m + 1].x - q[m].x) / ds, tz = ratio * (q[m + 1].z - q[m].z) / ds;
        e.least_packing = std::min(e.least_packing, std::hypot(tx, tz));
        e.fastest = std::max(e.fastest, std::hypot(1.0 - tx, tz));
        e.least_dx = std::min(e.least_dx, tx);
    }
    return e;
}

// The section's highest point over x (a wall holds several).
double section_top(const std::vector<BreakerSectionPoint>& q, double x) {
    auto m = static_cast<std::size_t>(std::lower_bound(q.begin(), q.end(), x, [](const BreakerSectionPoint& a, double v) { return a.x < v; }) - q.begin());
    m = std::max<std::size_t>(m, 1) - 1;
    double top = -1e9;
    for (; m + 1 < q.size() && q[m].x <= x + 1e-12; ++m) {
        if (q[m + 1].x < x) continue;
        const double w = q[m + 1].x > q[m].x ? (x - q[m].x) / (q[m + 1].x - q[m].x) : 1.0;
        top = std::max({top, q[m].z + w * (q[m + 1].z - q[m].z), q[m + 1].x == q[m].x ? q[m].z : -1e9});
    }
    return top;
}

// Its highest point within h of x.
double section_top_near(const std::vector<BreakerSectionPoint>& q, double x, double h) {
    double top = std::max(section_top(q, std::max(0.0, x - h)), section_top(q, std::min(1.0, x + h)));
    for (const BreakerSectionPoint& p : q)
        if (std::abs(p.x - x) <= h) top = std::max(top, p.z);
    return top;
}

TEST(BreakerSections, TheOuterSectionCoversTheTubeFacesNoWayDownPacksAndKeepsItsSpeed) {
    // Over the whole life (breaking τ ∈ [0, 1], collapsing [1, 2]), three curls and
    // height ratios 5H/W from 0.05 to 1, each section at 2 000 labels:
    // * its edges are the paper's (x 0 and 1 at z 0: a vertex passes from one crest to
    //   the next without a jump);
    // * it never runs backwards (no triangle faces down) and covers the paper's curve
    //   from above to within one of the envelope's 512 columns (the tube is inside it;
    //   at a hanging lip's tip the chord between two columns passes under it by up to
    //   0.013 of the unit shape, 6 % of H over W/512);
    // * frozen and moving at c, it packs every rest spacing to ≥ 0.6 (less the
    //   columns' rounding: 0.58 measured) and moves no point faster than 1.5 c
    //   (measured 1.49 c: the labels' spread κ above the 1.2 c asked of each column);
    // * witness: the paper's curve there packs below 0.05.
    const BreakerSectionBounds bounds;
    std::vector<BreakerSectionPoint> q;
    double least = 1e9, fastest = 0.0, paper_least = 1e9;
    for (int i = 0; i <= 40; ++i)
        for (double curl : {0.3, 0.6, 1.0})
            for (double ratio : {0.05, 0.2, 0.5, 1.0}) {
                const double life = i / 20.0;
                outer_section(life, curl, ratio, bounds, 2000, q);
                SCOPED_TRACE(::testing::Message() << "life " << life << " curl " << curl << " ratio " << ratio);
                EXPECT_EQ(q.front().x, 0.0);
                EXPECT_EQ(q.back().x, 1.0);
                EXPECT_NEAR(q.front().z, 0.0, 1e-12);
                EXPECT_NEAR(q.back().z, 0.0, 1e-12);
                const SectionExtremes e = section_extremes(q, ratio);
                EXPECT_GE(e.least_dx, 0.0);
                least = std::min(least, e.least_packing);
                fastest = std::max(fastest, e.fastest);
                // Above the paper's curve: its points inside (0, 1) lie on or under the section.
                const BreakerPhase phase = life < 1.0 ? BreakerPhase::breaking : BreakerPhase::collapsing;
                const double t = std::min(1.0, life < 1.0 ? life : life - 1.0);
                const double fade = std::min(1.0, 1.25 * jeschke_constants(phase, t, false).k[7]);
                for (int k = 0; k <= 400; ++k) {
                    const double s = k / 400.0;
                    const BreakerShapePoint p = shape(phase, t, s, curl);
                    const double x = s + fade * (1.0 - p.y - s);
                    if (x <= 0.0 || x >= 1.0) continue;
                    EXPECT_GE(section_top_near(q, x, 1.0 / 512.0), p.z - 1e-3) << "at x " << x;
                    if (k > 0) {
                        const BreakerShapePoint b = shape(phase, t, (k - 1) / 400.0, curl);
                        const double bx = (k - 1) / 400.0 + fade * (1.0 - b.y - (k - 1) / 400.0);
                        if (life > 0.2 && life < 1.8) paper_least = std::min(paper_least, std::hypot(x - bx, ratio * (p.z - b.z)) * 400.0);
                    }
                }
            }
    EXPECT_GE(least, 0.6 * 0.95);
    EXPECT_LE(fastest, 1.5);
    EXPECT_LT(paper_least, 0.05);
    RecordProperty("least_packing", std::to_string(least));
    RecordProperty("fastest", std::to_string(fastest));
    RecordProperty("paper_least_packing", std::to_string(paper_least));
}

TEST(BreakerSections, TheCurlSectionOverturnsOnlyPlungingLipsPacksAndKeepsItsJetBelowThreeAndAHalfC) {
    // BreakerLip::curl (issue 65): the outer section whose wall curls back under the lip.
    // * plunging crests (curl 1) at the breaking beach's ratio 5H/W ≈ 0.2: while the lip
    //   hangs the section runs backwards (the lip's underside: triangles facing down);
    // * collapsing (0.6) and spilling (0.3) crests never run backwards;
    // * every section packs the rest spacing to ≥ 0.6 (less rounding) and moves no point
    //   faster than 3.5 c frozen (the lip's jet; the underside at most (1 + 0.6) κ c),
    //   and the parts that run forwards no faster than 1.5 c.
    const BreakerSectionBounds bounds;
    std::vector<BreakerSectionPoint> q;
    int overturned = 0;
    double least = 1e9, fastest = 0.0, fastest_forward = 0.0;
    for (int i = 0; i <= 40; ++i)
        for (double curl : {0.3, 0.6, 1.0})
            for (double ratio : {0.1, 0.2, 0.5}) {
                const double life = i / 20.0;
                curl_section(life, curl, ratio, bounds, 2000, q);
                SCOPED_TRACE(::testing::Message() << "life " << life << " curl " << curl << " ratio " << ratio);
                EXPECT_EQ(q.front().x, 0.0);
                EXPECT_EQ(q.back().x, 1.0);
                const SectionExtremes e = section_extremes(q, ratio);
                least = std::min(least, e.least_packing);
                fastest = std::max(fastest, e.fastest);
                if (curl < 0.9) {
                    EXPECT_GE(e.least_dx, 0.0);
                }
                if (curl > 0.9 && ratio == 0.2 && life < 1.0 && e.least_dx < 0.0) ++overturned;
                const double ds = 1.0 / static_cast<double>(q.size() - 1);
                for (std::size_t m = 0; m + 1 < q.size(); ++m) {
                    const double tx = (q[m + 1].x - q[m].x) / ds, tz = ratio * (q[m + 1].z - q[m].z) / ds;
                    if (tx >= 0.0) fastest_forward = std::max(fastest_forward, std::hypot(1.0 - tx, tz));
                }
            }
    EXPECT_GE(overturned, 8);  // of the 20 breaking lives
    // Less than the outer section's rounding: the pressed front's corners on the
    // envelope's 512 columns (0.54 measured, a collapsing spilling crest at its top).
    EXPECT_GE(least, 0.6 * 0.85);
    EXPECT_LE(fastest, 3.5);
    EXPECT_LE(fastest_forward, 1.5);
    RecordProperty("overturned_lives", std::to_string(overturned));
    RecordProperty("least_packing", std::to_string(least));
    RecordProperty("fastest", std::to_string(fastest));
    RecordProperty("fastest_forward", std::to_string(fastest_forward));
}

TEST(BreakerSections, TheCurlSectionsFrontHasTheBreakersOwnProportions) {
    // BreakerLip::curl ahead of the crest is pressed to the paper's figure's proportions
    // (issue 65: a face about as high as it is wide, not a quarter of a wavelength long).
    // At real steepness 5H/W = 0.1 … 0.4, through the breaking phase and the start of the
    // collapse (τ = 0.5 … 1.1):
    // * the front from the crest to its foot (the first point ahead below a tenth of the
    //   crest) falls on average ≥ 25° (measured 28–43°), for plunging (curl 1) and
    //   spilling (0.3) crests alike; witness: the outer section's front ≤ 20° (3–20°);
    // * a plunging crest overturns (its steepest drop past 90°: the lip's underside);
    // * a spilling crest's face reaches ≥ 30° (44–88°).
    const auto front = [](const std::vector<BreakerSectionPoint>& q, double ratio) {
        std::size_t crest = 0;
        for (std::size_t m = 0; m < q.size(); ++m)
            if (q[m].z > q[crest].z) crest = m;
        std::size_t foot = crest;
        while (foot + 1 < q.size() && q[foot].z > 0.1 * q[crest].z) ++foot;
        double steepest = 0.0;
        for (std::size_t m = 0; m + 1 < q.size(); ++m)
            if (q[m + 1].z < q[m].z) steepest = std::max(steepest, std::atan2(ratio * (q[m].z - q[m + 1].z), q[m + 1].x - q[m].x));
        const double deg = 180.0 / std::numbers::pi;
        return std::pair{std::atan2(ratio * (q[crest].z - q[foot].z), q[foot].x - q[crest].x) * deg, steepest * deg};
    };
    const BreakerSectionBounds bounds;
    std::vector<BreakerSectionPoint> q;
    double least_mean = 1e9, outer_most = 0.0, least_spilling = 1e9;
    for (double ratio : {0.1, 0.2, 0.4})
        for (double life : {0.5, 0.7, 0.9, 1.1}) {
            SCOPED_TRACE(::testing::Message() << "life " << life << " ratio " << ratio);
            curl_section(life, 1.0, ratio, bounds, 2000, q);
            const auto [plunging_mean, plunging_steepest] = front(q, ratio);
            EXPECT_GT(plunging_steepest, 90.0);
            curl_section(life, 0.3, ratio, bounds, 2000, q);
            const auto [spilling_mean, spilling_steepest] = front(q, ratio);
            least_spilling = std::min(least_spilling, spilling_steepest);
            least_mean = std::min({least_mean, plunging_mean, spilling_mean});
            outer_section(life, 1.0, ratio, bounds, 2000, q);
            outer_most = std::max(outer_most, front(q, ratio).first);
        }
    EXPECT_GE(least_mean, 25.0);
    EXPECT_LE(outer_most, 20.0);
    EXPECT_GE(least_spilling, 30.0);
    RecordProperty("least_mean_front_degrees", std::to_string(least_mean));
    RecordProperty("outer_steepest_mean_front_degrees", std::to_string(outer_most));
    RecordProperty("least_spilling_face_degrees", std::to_string(least_spilling));
}

TEST(BreakerSections, TheCurlSectionNeverJumpsMoreThanATableStepAllows) {
    // The curl section through its whole life in steps of 1/1024 (a table holds 1/64): no
    // label moves more than 0.005 W between two steps, for plunging and nearly spilling
    // crests (the mouth opening as the wall stands from 55° to 75°). What is left are the
    // wall's columns chosen anew (0.0021–0.0044 W measured, curl 0.85 included, at any
    // step: jumps the table's interpolation smooths); the mouth was a straight line from
    // the wall's top to its foot, which replaced the envelope's curved wall at once as
    // the mouth opened: up to 0.0076 W.
    std::vector<BreakerSectionPoint> before, after;
    double worst = 0.0;
    for (double curl : {0.65, 1.0})
        for (double ratio : {0.1, 0.2, 0.4}) {
            curl_section(0.0, curl, ratio, {}, 400, before);
            for (int i = 1; i <= 2048; ++i) {
                curl_section(i / 1024.0, curl, ratio, {}, 400, after);
                for (std::size_t m = 0; m < after.size(); ++m)
                    worst = std::max(worst, std::hypot(after[m].x - before[m].x, ratio * (after[m].z - before[m].z)));
                std::swap(before, after);
            }
        }
    EXPECT_LE(worst, 0.005);
    RecordProperty("largest_step_wavelengths", std::to_string(worst));
    EXPECT_THROW(curl_section(0.5, 1.0, 0.0, {}, 100, after), InputError);
    EXPECT_THROW(outer_section(0.5, 1.0, std::nan(""), {}, 100, after), InputError);
}

TEST(BreakerSections, TheTableMeetsTheRoundShapeAndStillWaterAndHoldsItsBoundsBetweenSamples) {
    // τ = 0 is the round crest fully grown (x = s: the paper's round phase moves no point
    // sideways), τ = 2 still water. Between samples (τ, curl and ratio off the grid) the
    // interpolated sections never run backwards and keep the speed bound; they pack
    // less (0.425 measured): where one sample's label lies on a wall and its
    // neighbour's already past it, the mean of the two tangents is shorter than either.
    const BreakerSections table = plan_breaker_sections(0.3, 1.0);
    EXPECT_EQ(table.curl_first, 0.25);
    EXPECT_EQ(table.curls, 4u);
    // The curl sections' table too (BreakerLip::curl): its front is pressed only from
    // τ = 0 on, so where breaking starts it is the round crest as well.
    const BreakerSections curls = plan_breaker_sections(0.3, 1.0, {}, true);
    for (const BreakerSections* t : {&table, &curls})
        for (double ratio : {0.1, 0.4})
            for (int i = 0; i <= 100; ++i) {
                const double s = i / 100.0;
                const BreakerSectionPoint r = breaker_section(*t, 0.0, 1.0, ratio, s), d = breaker_section(*t, 2.0, 1.0, ratio, s);
                EXPECT_NEAR(r.x, s, 1e-5);
                EXPECT_NEAR(r.z, shape(BreakerPhase::round, 1.0, s).z, 3e-4);  // the 64 labels' chords: 1.1e-4 of a 0.2 crest
                EXPECT_NEAR(d.x, s, 1e-6);
                EXPECT_NEAR(d.z, 0.0, 1e-6);
            }
    double least = 1e9, fastest = 0.0;
    std::vector<BreakerSectionPoint> q(641);
    for (int i = 0; i < 200; ++i)
        for (double curl : {0.3, 0.6, 0.85})
            for (double ratio : {0.07, 0.23, 0.61}) {
                const double life = (i + 0.37) / 100.0;
                for (std::size_t m = 0; m < q.size(); ++m) q[m] = breaker_section(table, life, curl, ratio, static_cast<double>(m) / 640.0);
                const SectionExtremes e = section_extremes(q, ratio);
                EXPECT_GE(e.least_dx, 0.0);
                least = std::min(least, e.least_packing);
                fastest = std::max(fastest, e.fastest);
            }
    EXPECT_GE(least, 0.4);
    EXPECT_LE(fastest, 1.5);
    RecordProperty("least_packing", std::to_string(least));
    RecordProperty("fastest", std::to_string(fastest));
    EXPECT_THROW(plan_breaker_sections(0.3, 2.5), InputError);
    EXPECT_THROW(plan_breaker_sections(0.3, 1.0, {.min_packing = 1.0}), InputError);
    EXPECT_THROW(plan_breaker_sections(0.3, 1.0, {.frozen_speed = 1.0}), InputError);
}

TEST(JeschkeBreakers, PlanarBeachBreaksWhereShoalingReachesGamma) {
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    // The analytic answer: linear shoaling at normal incidence on the same 1:20 slope.
    std::vector<double> depth;
    for (double h = 10.0; h > 0.0; h -= 0.01) depth.push_back(h);
    const double omega = 2 * std::numbers::pi / 8.0;
    const ShoalingProfile analytic = shoal_profile(omega, 0.8, depth, 0.01 / 0.05);
    ASSERT_GE(analytic.break_index, 0);
    std::size_t central = 0;
    for (const RayBreak& rb : plan.breakers.rays) {
        if (std::abs(rb.x - 100.0) > 50.0) continue;  // away from the side walls
        ++central;
        ASSERT_TRUE(rb.breaks) << "ray " << rb.ray;
        EXPECT_NEAR(rb.height / rb.depth, kBreakerIndex, 1e-6) << "ray " << rb.ray;
        EXPECT_NEAR(rb.depth, analytic.break_depth, 0.03 * analytic.break_depth) << "ray " << rb.ray;
        // ξ0 = 0.05 / sqrt(0.8 / 99.9) = 0.56: plunging (Battjes: 0.5 … 3.3).
        EXPECT_NEAR(rb.iribarren, 0.05 / std::sqrt(0.8 / (kGravity * 64 / (2 * std::numbers::pi))), 0.02);
        EXPECT_EQ(rb.type, BreakerType::plunging);
        EXPECT_GT(rb.end_phase, rb.break_phase);
    }
    EXPECT_GE(central, 20u);
}

TEST(JeschkeBreakers, NoVertexJumpsBetweenFrames) {
    // Over a whole period every vertex passes through round, breaking, collapsing and
    // crest changes. A continuous motion moves 4× less in a 4× shorter step; a jump
    // would not shrink. Stated bound: at 60 fps no vertex moves more than 0.5 m
    // (measured: 0.20 m, the collapsing jet at 12 m/s; 0.05 m at 240 fps).
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    const std::size_t n = b.vertex_count();
    std::vector<float> p0(3 * n), p1(3 * n);
    const auto worst_step = [&](double dt) {  // over a quarter period: 10⁴ vertices in transitions
        double worst = 0.0;
        evaluate_jeschke_breakers(b, 0.0, p1);
        for (double t = 0.0; t < 2.0; t += dt) {
            p0.swap(p1);
            evaluate_jeschke_breakers(b, t + dt, p1);
            for (std::size_t i = 0; i < 3 * n; i += 3)
                worst = std::max(worst, static_cast<double>(std::hypot(p1[i] - p0[i], p1[i + 1] - p0[i + 1], p1[i + 2] - p0[i + 2])));
        }
        return worst;
    };
    const double coarse = worst_step(1.0 / 60.0), fine = worst_step(1.0 / 240.0);
    EXPECT_LT(coarse, 0.5);
    EXPECT_LT(fine, 0.35 * coarse) << "a jump does not shrink with the time step";
    for (float v : p1) ASSERT_TRUE(std::isfinite(v));
}

// The fastest vertex of `b` over a period (steps of T/960), in units of its local phase
// speed c = W/T; vertices at rest (W = 0 where a ray ends) and float noise aside.
double fastest_over_phase_speed(const JeschkeMotionPlan& b) {
    const std::size_t n = b.vertex_count();
    const double period = 2 * std::numbers::pi / b.omega, dt = period / 960;
    std::vector<float> p0(3 * n), p1(3 * n);
    evaluate_jeschke_breakers(b, 0.0, p1);
    double worst = 0.0;
    for (double t = 0.0; t < period; t += dt) {
        p0.swap(p1);
        evaluate_jeschke_breakers(b, t + dt, p1);
        for (std::size_t v = 0; v < n; ++v) {
            const double speed = std::hypot(p1[3 * v] - p0[3 * v], p1[3 * v + 1] - p0[3 * v + 1], p1[3 * v + 2] - p0[3 * v + 2]) / dt;
            if (b.width[v] == 0.0f || speed < 0.01) continue;
            worst = std::max(worst, speed * period / b.width[v]);
        }
    }
    return worst;
}

// The beach's breakers with the given "lip" (outer or tube).
JeschkeMotionPlan beach_breakers(const char* lip) {
    std::string doc = kBeach;
    doc.replace(doc.find("\"breakers\": \"jeschke\""), 21, std::string(R"("breakers": {"lip": ")") + lip + "\"}");
    return plan_scene(parse_scene(doc, "beach.json", ".")).breakers;
}

TEST(JeschkeBreakers, NoVertexOutrunsOneAndAHalfTimesItsPhaseSpeed) {
    // Motion-made defects: every vertex, breaking crests included, against c = W/T, its
    // local phase speed, in steps of T/960 (120 fps on this 8 s swell) over a period.
    // The outer section (the default) bounds its frozen section at 1.2 c; the crest's
    // change through its life adds the rest. Witness: the paper's tube sweeps its lip
    // round at up to 2.7 c with the shape held still (3.38 c in all). Table 1 read
    // literally — a fixed 0.03 lip seam across the collapsing jet's gap and powers below
    // 1 with infinite slopes at the wave's edges and at the phases' starts — reached
    // 7.29 c here.
    const double outer = fastest_over_phase_speed(beach_breakers("outer"));
    const double tube = fastest_over_phase_speed(beach_breakers("tube"));
    EXPECT_LE(outer, 1.5);
    EXPECT_GT(tube, 3.0);
    EXPECT_LE(tube, 3.5);
    RecordProperty("outer", std::to_string(outer));
    RecordProperty("tube", std::to_string(tube));
}

TEST(JeschkeBreakers, ASteepShoreDoesNotThrowItsLipsFasterThanAGentleOne) {
    // Breaking Okushiri's islet in miniature: 12 m deep, then a 1:4 slope to the shore,
    // T = 12 s. The ray ends a few metres past its break; a crest living its whole life
    // in that run throws its lip at 6 c here (13 c by the islet). With the surf zone spanning at least half a local
    // wavelength (the default) the shore cuts the crest's life short instead: as on the
    // gentle beach above (≤ 3.5 c).
    const Seafloor steep = test::grid_seafloor(120.0, 300.0, 2.0, [](double, double y) { return std::min(12.0, 0.25 * (250.0 - y)); });
    const WaveTrain swell{.period = 12.0, .amplitude = 0.5, .direction_x = 0.0, .direction_y = 1.0};
    FrontOptions fronts;
    fronts.ray_spacing = 4.0;
    const RayStrips strips = build_ray_strips(trace_fronts(steep, swell, fronts));
    const double deep_length = deep_water_wavelength(swell.period);
    // The paper's tube shows it; the outer section, whose frozen shape is bounded, keeps
    // even the squeezed life below 1.5 c.
    JeschkeBreakerOptions o;
    o.wave_variation = 0.0;
    o.lip = BreakerLip::tube;
    const JeschkeMotionPlan floored = plan_jeschke_breakers(strips, 2 * swell.amplitude, deep_length, o);
    ASSERT_FALSE(floored.rays.empty());
    EXPECT_TRUE(std::any_of(floored.rays.begin(), floored.rays.end(), [](const RayBreak& r) { return r.breaks; }));
    o.min_surf_zone_wavelengths = 0.0;  // each ray's own end: the life squeezed into the last metres
    const JeschkeMotionPlan squeezed = plan_jeschke_breakers(strips, 2 * swell.amplitude, deep_length, o);
    const double with_floor = fastest_over_phase_speed(floored), without = fastest_over_phase_speed(squeezed);
    EXPECT_GT(without, 5.0) << "the case does not squeeze the crest's life";  // measured 6.03 c
    EXPECT_LE(with_floor, 3.5);  // measured 3.45 c
    o.lip = BreakerLip::outer;
    const double outer_squeezed = fastest_over_phase_speed(plan_jeschke_breakers(strips, 2 * swell.amplitude, deep_length, o));
    EXPECT_LE(outer_squeezed, 1.5);
    RecordProperty("with_floor", std::to_string(with_floor));
    RecordProperty("without_floor", std::to_string(without));
    RecordProperty("outer_squeezed", std::to_string(outer_squeezed));
}

TEST(JeschkeFoam, NoneBeforeTheBreakThenDecayingUntilTheNextCrest) {
    const Scene scene = parse_scene(alike_beach(), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    const std::size_t n = b.vertex_count();
    const double period = 8.0, dt = period / 400.0;
    std::vector<std::vector<float>> foam(401, std::vector<float>(n));
    for (std::size_t f = 0; f <= 400; ++f) jeschke_foam(b, static_cast<double>(f) * dt, foam[f]);
    std::size_t seaward = 0, surf = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (b.phase[v] < b.break_phase[v]) {  // no crest has broken here yet
            ++seaward;
            for (std::size_t f = 0; f <= 400; ++f) ASSERT_EQ(foam[f][v], 0.0f) << "vertex " << v;
            continue;
        }
        if (b.foam_yield[v] < 1.0f || b.phase[v] >= b.end_phase[v]) continue;
        ++surf;
        // Within a period: the lip's foam rising over the fifth of a period before the
        // crest (lip_foam_rise), then the linear fade from its passage; rising only in
        // that window, and as one stretch of frames.
        int rise_starts = 0;
        const auto rising = [&](std::size_t f) { return foam[f][v] > foam[(f + 399) % 400][v]; };  // frame 400 is frame 0
        for (std::size_t f = 0; f < 400; ++f) {
            const double since = std::fmod(b.omega * static_cast<double>(f) * dt - b.phase[v] + 100 * std::numbers::pi, 2 * std::numbers::pi) / b.omega;
            const double lip = lip_foam_rise(2 * std::numbers::pi - b.omega * since);
            EXPECT_NEAR(foam[f][v], std::max({0.0, 1.0 - since / b.foam_fade_time, lip}), 1e-3);
            if (!rising(f)) continue;
            EXPECT_TRUE(lip > 0.0 || since < dt + 1e-9) << "vertex " << v;  // before the crest, or at it
            rise_starts += rising((f + 399) % 400) ? 0 : 1;
        }
        EXPECT_EQ(rise_starts, 1) << "vertex " << v;
    }
    EXPECT_GT(seaward, 1000u);
    EXPECT_GT(surf, 100u);
}

namespace {

// Two rays 4 m apart over a barred beach (1:30 to the shore at x = 180 m, a bar 2.3 m
// high at x = 70 m, σ 10 m), an 8 s swell of H = 1.2 m, with the heights a wave field
// with breaking gives them: capped at γh on the bar, fallen to 0.8 m behind it (below
// Γh = 0.4 h in the trough), capped again on the beach. Vertices every 0.5 m.
constexpr double kBarCrest = 70.0;
double barred_depth(double x) { return 6.0 - x / 30.0 - 2.3 * std::exp(-0.5 * std::pow((x - kBarCrest) / 10.0, 2)); }
RayStrips barred_strips() {
    RayStrips s;
    const double omega = 2.0 * std::numbers::pi / 8.0, step = 0.5;
    const auto n = static_cast<std::uint32_t>(178.0 / step);
    for (std::uint32_t ray = 0; ray < 2; ++ray) {
        double phase = 0.0;
        for (std::uint32_t i = 0; i < n; ++i) {
            const double x = step * i, h = barred_depth(x);
            const double k = solve_dispersion(omega, h).k;
            if (i > 0) phase += 0.5 * (k + s.k.back()) * step;
            const double height = x < 84.0 ? std::min(1.2, kBreakerIndex * h) : std::min(0.8, kBreakerIndex * h);
            s.ray.push_back(ray), s.step.push_back(i), s.x.push_back(x), s.y.push_back(4.0 * ray);
            s.dir_x.push_back(1.0), s.dir_y.push_back(0.0), s.phase.push_back(phase), s.k.push_back(k);
            s.amplitude.push_back(height / 2.0), s.depth.push_back(h), s.slope.push_back(0.0);
            s.rise.push_back((h - barred_depth(x + 0.01)) / 0.01);
            s.flag.push_back(RayFlag::alive), s.caustic.push_back(0);
        }
    }
    for (std::uint32_t i = 0; i + 1 < n; ++i) {
        const std::uint32_t a = i, b = i + 1, c = n + i + 1, d = n + i;
        for (std::uint32_t v : {a, b, c, a, c, d}) s.triangles.push_back(v);
    }
    s.omega = omega;
    return s;
}

}  // namespace

TEST(JeschkeBreakers, ACrestBreakingOnABarReFormsInTheTroughAndBreaksAgainOnTheBeach) {
    // The wave field re-forms a wave behind a bar (its heights fall below Γh); the
    // breakers follow it, one life per surf zone: breaking on the bar and collapsing over
    // 1.5 wavelengths (a bore carried on into the trough), a round crest rising from
    // still water behind it, breaking again on the beach.
    // With a single life per ray (before), the crest collapsed from the bar all the way
    // to the shore and never broke on the beach.
    const RayStrips s = barred_strips();
    const double h0 = 1.2, l0 = deep_water_wavelength(8.0);
    const JeschkeMotionPlan p = plan_jeschke_breakers(s, h0, l0);
    ASSERT_EQ(p.rays.size(), 4u);  // two breaks on each ray
    for (const RayBreak& r : p.rays) {
        ASSERT_TRUE(r.breaks);
        // Onset H = γh: on the bar at h = 1.2/γ, on the beach at 0.8/γ.
        EXPECT_NEAR(r.depth, (r.surf_zone == 0 ? 1.2 : 0.8) / kBreakerIndex, 0.02) << "surf zone " << r.surf_zone;
        EXPECT_LT(r.surf_zone, 2u);
        if (r.surf_zone == 0) {
            EXPECT_LT(r.x, kBarCrest);
        } else {
            EXPECT_GT(r.x, 140.0);
        }
    }
    ASSERT_EQ(p.life_start.size(), p.vertex_count());
    // Along ray 0, every crest (the three varied ones) at each vertex as it passes.
    const std::size_t n = p.vertex_count() / 2;
    std::size_t on_bar = 0, in_trough = 0, on_beach = 0;
    for (std::size_t v = 0; v < n; ++v) {
        const double x = p.x[v];
        for (long long crest = 0; crest < 3; ++crest) {
            const BreakerLife life = jeschke_vertex_life(p, v, crest);
            const bool broken = life.phase == BreakerPhase::breaking || life.phase == BreakerPhase::collapsing;
            if (x > 71.0 && x < 80.0) {
                on_bar += broken ? 1 : 0;
                EXPECT_TRUE(broken) << "x " << x;
            }
            if (x > 126.0 && x < 138.0) {  // the broken crest collapses over 1.5 wavelengths, to 122 m
                ++in_trough;
                EXPECT_TRUE(life.phase == BreakerPhase::round) << "x " << x;
                EXPECT_GT(p.life_start[v], 0.0f);
                EXPECT_EQ(p.foam_yield[v], 0.0f) << "x " << x;  // clear water between the surf zones
            }
            if (x > 153.0 && x < 162.0) {
                on_beach += broken ? 1 : 0;
                EXPECT_TRUE(broken) << "x " << x;
            }
        }
    }
    EXPECT_GT(on_bar, 50u);
    EXPECT_GT(in_trough, 60u);
    EXPECT_GT(on_beach, 50u);
    // The new life rises from still water where the old one died: no vertex moves faster
    // than the breakers do anywhere (1.5 c, NoVertexOutrunsOneAndAHalfTimesItsPhaseSpeed).
    EXPECT_LE(fastest_over_phase_speed(p), 1.5);
    // A trough shorter than min_reform_wavelengths is broken through: one life per ray,
    // the crest collapsing from the bar to the shore (as every ray lived before).
    JeschkeBreakerOptions through;
    through.min_reform_wavelengths = 5.0;
    const JeschkeMotionPlan q = plan_jeschke_breakers(s, h0, l0, through);
    EXPECT_EQ(q.rays.size(), 2u);
    EXPECT_TRUE(q.life_start.empty());
    for (std::size_t v = 0; v < n; ++v)
        if (q.x[v] > 100.0) {
            EXPECT_FALSE(jeschke_vertex_life(q, v, 0).phase == BreakerPhase::round) << "x " << q.x[v];
        }
}

TEST(JeschkeBreakers, AMeshResampledAcrossAReFormTakesTheLifeThatHoldsThere) {
    // A water mesh's vertices between two strip vertices either side of the re-form take
    // the life that holds at their phase: the old one collapsing, or the new one rising —
    // never a blend of the two (a break phase half-way, a breaker standing in the trough).
    const RayStrips s = barred_strips();
    const JeschkeMotionPlan p = plan_jeschke_breakers(s, 1.2, deep_water_wavelength(8.0));
    std::vector<double> x, y;
    for (double xm = 0.25; xm < 177.0; xm += 0.5) x.push_back(xm), y.push_back(1.0);
    const JeschkeMotionPlan r = resample_jeschke_breakers(p, s.triangles, x, y);
    std::size_t in_trough = 0;
    for (std::size_t v = 0; v < r.vertex_count(); ++v) {
        if (x[v] > 126.0 && x[v] < 138.0) {
            ++in_trough;
            for (long long crest = 0; crest < 3; ++crest)
                EXPECT_TRUE(jeschke_vertex_life(r, v, crest).phase == BreakerPhase::round) << "x " << x[v];
        }
        // Each point's life is one of its corners': its start is a strip vertex's start.
        const bool known = std::any_of(p.life_start.begin(), p.life_start.end(), [&](float st) { return std::abs(st - r.life_start[v]) < 1e-3f; });
        EXPECT_TRUE(known) << "x " << x[v] << " starts at " << r.life_start[v];
    }
    EXPECT_GT(in_trough, 20u);
}

TEST(JeschkeBreakers, SameBytesForAnyThreadCount) {
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const std::size_t n = plan.breakers.vertex_count();
    std::vector<float> many(3 * n), one(3 * n);
    evaluate_jeschke_breakers(plan.breakers, 3.3, many);
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        evaluate_jeschke_breakers(plan.breakers, 3.3, one);
    }
    EXPECT_EQ(std::memcmp(many.data(), one.data(), many.size() * sizeof(float)), 0);
}

TEST(JeschkeBreakers, SceneErrorsNameTheKey) {
    const auto message = [](const std::string& text) {
        try {
            parse_scene(text, "s.json", ".");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "surface": {"kind": "height-field"}, "breakers": "jeschke"})")
                  .find("s.json: /breakers: only for the ray-strips surface"),
              std::string::npos);
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "breakers": "gonzato"})").find("expected one of jeschke"),
              std::string::npos);
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "breakers": {"breaking_share": 2}})")
                  .find("/breakers/breaking_share: expected a number in [0.01, 0.99] (share of the surf zone), got 2"),
              std::string::npos);
    EXPECT_NE(message(R"({"waves": [{"period": 5, "amplitude": 0.3}], "breakers": {"curl": 1}})").find("/breakers/curl: unknown key"),
              std::string::npos);
}

TEST(CameraGrid, PixelRaysMeetTheWaterWhereTheCameraLooks) {
    GridCamera c;
    c.position = {10.0, -40.0, 40.0};
    c.look_at = {10.0, 20.0, 0.0};
    c.image_width = c.image_height = 101;  // the middle pixel looks straight at look_at
    c.pixel_step = 1;
    const CameraGrid g = camera_grid(c);
    ASSERT_EQ(g.columns, 101u);
    ASSERT_EQ(g.rows, 101u);  // 34° down, 25° half field: every row sees the water
    const std::size_t mid = 50 * 101 + 50;
    EXPECT_NEAR(g.x[mid], 10.0, 1e-9);
    EXPECT_NEAR(g.y[mid], 20.0, 1e-9);
    // Far rows first, each row further than the next; triangles counter-clockwise from +z.
    for (std::size_t row = 1; row < g.rows; ++row) EXPECT_GT(g.y[(row - 1) * 101 + 50], g.y[row * 101 + 50]);
    for (std::size_t t = 0; t < g.triangles.size() / 3; ++t) {
        const auto a = g.triangles[3 * t], b = g.triangles[3 * t + 1], e = g.triangles[3 * t + 2];
        ASSERT_GT((g.x[b] - g.x[a]) * (g.y[e] - g.y[a]) - (g.x[e] - g.x[a]) * (g.y[b] - g.y[a]), 0.0) << t;
    }
    // Looking at the horizon: the upper half of the image sees sky and is left out.
    c.look_at = {10.0, 20.0, 40.0};
    c.image_height = 100;
    EXPECT_EQ(camera_grid(c).rows, 50u);
    c.max_distance = 200.0;  // and the far water too
    EXPECT_LT(camera_grid(c).rows, 50u);
    c.position[2] = -1.0;
    EXPECT_THROW(camera_grid(c), InputError);
}

TEST(CameraGrid, BreakersResampledAtTheStripVerticesAreTheStrips) {
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    std::vector<double> x = b.x, y = b.y;
    x.push_back(-500.0);  // off the strips: at rest, no foam
    y.push_back(-500.0);
    const JeschkeMotionPlan r = resample_jeschke_breakers(b, plan.strips.triangles, x, y);
    const std::size_t n = b.vertex_count();
    std::vector<float> ps(3 * n), pr(3 * (n + 1)), fs(n), fr(n + 1);
    std::size_t checked = 0;
    for (double t : {1.0, 4.5}) {
        evaluate_jeschke_breakers(b, t, ps);
        evaluate_jeschke_breakers(r, t, pr);
        jeschke_foam(b, t, fs);
        jeschke_foam(r, t, fr);
        for (std::size_t v = 0; v < n; ++v) {
            if (!std::isfinite(b.break_phase[v])) continue;  // interpolated rays that never break stay round
            ++checked;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(pr[3 * v + k], ps[3 * v + k], 2e-3) << "vertex " << v;
            ASSERT_NEAR(fr[v], fs[v], 1e-4);
        }
        EXPECT_EQ(pr[3 * n], -500.0f);
        EXPECT_EQ(pr[3 * n + 2], 0.0f);
        EXPECT_EQ(fr[n], 0.0f);
    }
    EXPECT_GT(checked, 10000u);
}

TEST(VertexNormals, ParallelGatherEqualsTheSerialSumBitForBit) {
    // Jeschke §5's accumulated face normals on the breaking beach (overhanging lips,
    // folded faces): the parallel version adds the same floats in the same order.
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const std::size_t n = plan.breakers.vertex_count();
    std::vector<float> p(3 * n), serial(3 * n), parallel(3 * n);
    const VertexFaces adjacency = vertex_faces(n, plan.strips.triangles);
    for (double t : {0.0, 2.7, 5.1}) {
        evaluate_jeschke_breakers(plan.breakers, t, p);
        vertex_normals(p, plan.strips.triangles, serial);
        vertex_normals(p, plan.strips.triangles, adjacency, parallel);
        ASSERT_EQ(std::memcmp(serial.data(), parallel.data(), serial.size() * sizeof(float)), 0) << "t = " << t;
    }
    EXPECT_THROW(vertex_normals(p, plan.strips.triangles, vertex_faces(n - 1, std::span(plan.strips.triangles).first(0)), parallel),
                 InputError);
}

TEST(JeschkeVariation, EveryCrestKeepsAWholeLifeCycle) {
    // Any draw leaves rise <= break, a breaking phase, at least a quarter of the collapse
    // zone, and an end no further than the ray's (the aground point).
    const double rise = 6.0, b = 20.0, len = 5.0, e = 40.0, collapse = e - b - len;
    for (double u1 = -1.0; u1 <= 1.0; u1 += 0.125)
        for (double u2 = -1.0; u2 <= 1.0; u2 += 0.125)
            for (double v : {0.1, 0.25, 0.5}) {
                const CrestPhases c = vary_crest(rise, b, len, e, {u1, u2}, v);
                ASSERT_GE(c.break_phase, rise);
                ASSERT_LE(c.end_phase, e);
                ASSERT_GE(c.end_phase - c.break_phase - c.breaking_length, 0.25 * collapse - 1e-12);
                ASSERT_NEAR(c.break_phase, std::clamp(b + u1 * v * 2 * std::numbers::pi, rise, b + 0.25 * collapse), 1e-12);
            }
    const CrestPhases never = vary_crest(rise, INFINITY, 0.0, INFINITY, {1.0, 1.0}, 0.5);
    EXPECT_TRUE(std::isinf(never.break_phase));
    const CrestPhases none = vary_crest(rise, b, len, e, {1.0, 1.0}, 0.0);
    EXPECT_EQ(none.break_phase, b);
    EXPECT_EQ(none.end_phase, e);
}

TEST(JeschkeVariation, CrestsDifferAndTheLoopIsTheirCount) {
    // Three varied crests: the surface repeats after 3 periods, not after one, and the
    // scene's loop holds the 3 periods (frames = 3 T fps).
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    ASSERT_EQ(b.loop_periods(), 3u);
    EXPECT_DOUBLE_EQ(plan.loop_period, 24.0);
    const std::size_t n = b.vertex_count();
    std::vector<float> a(3 * n), one(3 * n), three(3 * n);
    const double period = 2 * std::numbers::pi / b.omega;
    evaluate_jeschke_breakers(b, 1.7, a);
    evaluate_jeschke_breakers(b, 1.7 + period, one);
    evaluate_jeschke_breakers(b, 1.7 + 3 * period, three);
    double differ = 0.0, loop = 0.0;
    for (std::size_t i = 0; i < 3 * n; ++i) {
        differ = std::max(differ, static_cast<double>(std::abs(one[i] - a[i])));
        loop = std::max(loop, static_cast<double>(std::abs(three[i] - a[i])));
    }
    // The next crest breaks elsewhere (m): 0.125 m apart at most with the outer section
    // (measured), ~0.4 m with the paper's tube, whose lips fly further.
    EXPECT_GT(differ, 0.08) << "the next crest breaks elsewhere (m)";
    EXPECT_LT(loop, 1e-3) << "the loop repeats after 3 periods (m, float rounding of ωt)";

    // Where each crest breaks along one central ray: not all alike, each within the
    // stated ±0.25 local wavelengths of the traced break (k from the ray).
    std::vector<double> breaks;
    const RayBreak* ray = nullptr;
    for (const RayBreak& rb : b.rays) {
        if (rb.breaks && std::abs(rb.x - 100.0) < 50.0) ray = &rb;
    }
    ASSERT_NE(ray, nullptr);
    std::size_t v0 = n;
    for (std::size_t v = 0; v < n && v0 == n; ++v)
        if (b.break_phase[v] == static_cast<float>(ray->break_phase)) v0 = v;
    ASSERT_LT(v0, n);
    for (const CrestVariation& d : b.crest_draws)
        breaks.push_back(vary_crest(b.rise[v0], b.break_phase[v0], b.breaking_length[v0], b.end_phase[v0], d, b.variation).break_phase);
    const auto [lo, hi] = std::minmax_element(breaks.begin(), breaks.end());
    EXPECT_GT(*hi - *lo, 0.1 * 2 * std::numbers::pi) << "crests break at least a tenth of a wavelength apart";
    for (double x : breaks) EXPECT_LE(std::abs(x - ray->break_phase), 0.25 * 2 * std::numbers::pi + 1e-4);
}

TEST(JeschkeVariation, FoamOnlyWhereSomeCrestBrokeAndBoundedByTheFade) {
    // §3.1 with varied crests: no foam seaward of the earliest break of any crest; the
    // largest faded value over the recent crests never rises except when a crest passes.
    const Scene scene = parse_scene(kBeach, "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    const std::size_t n = b.vertex_count();
    const double loop = plan.loop_period, dt = loop / 600.0;
    std::vector<float> prev(n), cur(n);
    jeschke_foam(b, 0.0, prev);
    std::size_t foamy = 0, alike_differs = 0;
    std::vector<float> alike(n);
    const ScenePlan alike_plan = plan_scene(parse_scene(alike_beach(), "beach.json", "."));
    for (std::size_t f = 1; f <= 600; ++f) {
        const double t = static_cast<double>(f) * dt;
        jeschke_foam(b, t, cur);
        jeschke_foam(alike_plan.breakers, t, alike);
        for (std::size_t v = 0; v < n; ++v) {
            ASSERT_GE(cur[v], 0.0f);
            ASSERT_LE(cur[v], 1.0f);
            double earliest = INFINITY;
            for (const CrestVariation& d : b.crest_draws)
                earliest = std::min(earliest, vary_crest(b.rise[v], b.break_phase[v], b.breaking_length[v], b.end_phase[v], d,
                                                         b.variation).break_phase);
            if (b.phase[v] < earliest) {
                ASSERT_EQ(cur[v], 0.0f) << "vertex " << v;
            }
            if (cur[v] > prev[v]) {
                // A rise only when a crest has just passed (within one step), or before
                // the next one as its lip's foam rises (never above that curve).
                const double since = std::fmod(b.omega * t - b.phase[v] + 1000 * std::numbers::pi, 2 * std::numbers::pi) / b.omega;
                const double rise = lip_foam_rise(2 * std::numbers::pi - b.omega * since);
                if (since >= dt + 1e-9) {
                    ASSERT_GT(rise, 0.0) << "vertex " << v << " t " << t;
                    ASSERT_LE(cur[v], rise + 1e-6) << "vertex " << v << " t " << t;
                }
            }
            foamy += cur[v] > 0.0f;
            alike_differs += std::abs(cur[v] - alike[v]) > 0.05f;
        }
        prev.swap(cur);
    }
    EXPECT_GT(foamy, 1000u);
    EXPECT_GT(alike_differs, 1000u) << "the varied crests leave other foam than identical ones";
}

TEST(JeschkeGaps, OffStripVerticesContinueTheNearestTracedWaveWithinAWavelength) {
    // An 11 × 3 grid, 1 m apart; the rays cover x <= 5 (a wave along +x, W = 4 m,
    // Φ = k x), the rest is a gap such as rays leave at a domain's downwave side.
    constexpr std::uint32_t nx = 11, ny = 3;
    JeschkeMotionPlan p;
    const double W = 4.0, k = 2.0 * std::numbers::pi / W;
    for (std::uint32_t j = 0; j < ny; ++j)
        for (std::uint32_t i = 0; i < nx; ++i) {
            const bool traced = i <= 5;
            p.x.push_back(double(i));
            p.y.push_back(double(j));
            p.dir_x.push_back(1.0);
            p.dir_y.push_back(0.0);
            p.phase.push_back(traced ? k * double(i) : 0.0);
            p.width.push_back(traced ? float(W) : 0.0f);
            p.scale.push_back(traced ? 0.5f + 0.01f * float(j) : 0.0f);
            p.mean_level.push_back(traced ? 0.05f : 0.0f);
            p.break_phase.push_back(traced ? 30.0f : std::numeric_limits<float>::infinity());
            p.end_phase.push_back(traced ? 60.0f : std::numeric_limits<float>::infinity());
            for (auto* f : {&p.rise, &p.breaking_length, &p.curl, &p.foam_yield}) f->push_back(traced ? 0.25f : 0.0f);
        }
    std::vector<std::uint32_t> triangles;
    for (std::uint32_t j = 0; j + 1 < ny; ++j)
        for (std::uint32_t i = 0; i + 1 < nx; ++i) {
            const std::uint32_t a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
            triangles.insert(triangles.end(), {a, b, d, a, d, c});
        }
    JeschkeMotionPlan filled = p;
    // Within 4 m (one wavelength) of x = 5: x = 6 … 9 on every row; x = 10 is 5 m away.
    EXPECT_EQ(fill_jeschke_gaps(filled, triangles), 4u * ny);
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 6; i < nx; ++i) {
            const std::size_t v = j * nx + i;
            if (i == 10) {
                EXPECT_EQ(filled.width[v], 0.0f) << "beyond the reach: at rest";
                continue;
            }
            EXPECT_NEAR(filled.phase[v], k * double(i), 1e-12) << "the plane wave continued";
            EXPECT_EQ(filled.width[v], float(W));
            EXPECT_EQ(filled.scale[v], 0.5f + 0.01f * float(j)) << "the same row's traced vertex is nearest";
            EXPECT_EQ(filled.break_phase[v], 30.0f);
        }
    // The traced vertices are untouched, and a filled vertex moves as the traced one a
    // wavelength before it (the same phase mod 2π, the same row's breakers) does.
    for (std::size_t v = 0; v < p.vertex_count(); ++v)
        if (p.width[v] > 0.0f) {
            EXPECT_EQ(filled.phase[v], p.phase[v]);
        }
    std::vector<float> positions(3 * p.vertex_count());
    for (double t : {0.0, 0.7, 3.1}) {
        evaluate_jeschke_breakers(filled, t, positions);
        for (std::uint32_t j = 0; j < ny; ++j) {
            const float* a = &positions[3 * (j * nx + 2)];
            const float* b = &positions[3 * (j * nx + 6)];
            EXPECT_NEAR(b[0] - a[0], W, 1e-5) << "t " << t;
            EXPECT_NEAR(b[2], a[2], 1e-5) << "t " << t;
        }
    }
    // A longer reach fills x = 10 too; a bad reach or index is refused.
    JeschkeMotionPlan wide = p;
    EXPECT_EQ(fill_jeschke_gaps(wide, triangles, 2.0), 5u * ny);
    EXPECT_THROW(fill_jeschke_gaps(wide, triangles, 0.0), InputError);
    std::vector<std::uint32_t> bad = triangles;
    bad[0] = 999;
    EXPECT_THROW(fill_jeschke_gaps(wide, bad), InputError);
}

namespace {

// The breaking beach as shipped (oblique 8 s swell, the water mesh, the far field), at
// 8 fps: the breakers reach the domain's right side, x = 200 m, inside the surf zone.
std::string oblique_beach(double breaker_wavelengths) {
    return R"({"name": "oblique beach", "seafloor": {"source": "planar-beach"}, "isobaths": {"spacing": 0.5},
      "waves": [{"period": 8, "amplitude": 0.4, "direction": [0.34, 0.94]}], "trace": {"ray_spacing": 4},
      "breakers": "jeschke", "animation": {"fps": 8},
      "surface": {"far_field": {"breaker_wavelengths": )" + std::to_string(breaker_wavelengths) + "}}}";
}

// The anchor a carried skirt vertex lives the life of (the nearer of its two).
std::uint32_t carried_anchor(const SeaSkirt& skirt, std::size_t s) {
    return skirt.anchor_weight[s] >= 0.5f ? skirt.anchor[2 * s] : skirt.anchor[2 * s + 1];
}

}  // namespace

TEST(SkirtBreakers, ASkirtVertexLivesItsAnchorsLifeLagLater) {
    // The seafloor beyond a side is the border's continued along the outward normal, so
    // the wave there is the anchor's plane wave: the crest reaches a point p of the skirt
    // k D·(p − p_a)/ω after it passed the anchor, and the point moves as the anchor did
    // then. Checked against the surface's own breakers evaluated at the anchor at that
    // earlier time, and the lag against the domain's own phases next to the anchor.
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const SkirtBreakers& b = plan.skirt_breakers;
    const JeschkeMotionPlan& own = plan.breakers;
    ASSERT_GT(b.vertex_count(), 500u);
    std::size_t surf = 0;
    for (std::size_t i = 0; i < b.vertex_count(); ++i) {
        const std::size_t s = b.vertex[i] - plan.skirt.surface_vertices;
        const double W = own.width[carried_anchor(plan.skirt, s)], d = plan.skirt.distance[s];
        ASSERT_LT(d, 2.0 * W) << "beyond the band";
        if (d <= W) {
            ASSERT_EQ(b.weight[i], 1.0f) << "a wavelength short of the band's end: the breakers whole";
        }
        ASSERT_GT(b.weight[i], 0.0f);
        surf += own.foam_yield[carried_anchor(plan.skirt, s)] > 0.0f;
    }
    EXPECT_GT(surf, 100u) << "the surf zone reaches the side";
    // Every 37th carried vertex against its anchor at the earlier time.
    std::vector<float> anchor_frame(3 * own.vertex_count()), anchor_foam(own.vertex_count());
    std::vector<float> carried(3 * b.vertex_count()), carried_foam(b.vertex_count());
    double worst = 0.0, worst_foam = 0.0, largest = 0.0;
    for (double t : {0.3, 5.1, 13.7}) {
        evaluate_jeschke_breakers(b.plan, t, carried);
        jeschke_foam(b.plan, t, carried_foam);
        for (std::size_t i = 0; i < b.vertex_count(); i += 37) {
            const std::uint32_t a = carried_anchor(plan.skirt, b.vertex[i] - plan.skirt.surface_vertices);
            const double earlier = t - b.plan.lag[i] / own.omega;
            evaluate_jeschke_breakers(own, earlier, anchor_frame);
            jeschke_foam(own, earlier, anchor_foam);
            const double moved[3] = {carried[3 * i] - b.plan.x[i], carried[3 * i + 1] - b.plan.y[i], carried[3 * i + 2]};
            const double anchor_moved[3] = {anchor_frame[3 * a] - own.x[a], anchor_frame[3 * a + 1] - own.y[a], anchor_frame[3 * a + 2]};
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(moved[c] - anchor_moved[c]));
                largest = std::max(largest, std::abs(anchor_moved[c]));
            }
            worst_foam = std::max(worst_foam, static_cast<double>(std::abs(carried_foam[i] - anchor_foam[a])));
        }
    }
    EXPECT_GT(largest, 0.3) << "the anchors move";
    EXPECT_LT(worst, 1e-3) << "m: float positions of the same shape";
    EXPECT_LT(worst_foam, 1e-5);
    // The lag is the anchor's plane wave, k D·(p − p_a), and it continues the domain's
    // own phase field where the waves leave it (D·N > 0; on the upwave sides the rays
    // start at the border): Φ's gradient fitted by least squares on the surface's
    // vertices within half a wavelength of the anchor (where W changes by at most a
    // fifth: not next to the shore, where W ∝ √h shrinks fast), carried out to the skirt
    // vertex, gives its lag to 0.1 rad + 35 %. (Measured: 0.45 rad on a lag of 2.1, 30 %
    // over 5 m of sea beside the shore: a traced ray turns at each isobath, 0.5 m of
    // depth apart, and runs straight between, while the phases between are interpolated;
    // the sign or a factor of two would fail.)
    double worst_lag = 0.0;
    std::size_t compared = 0;
    for (std::size_t i = 0; i < b.vertex_count(); i += 7) {
        const std::size_t s = b.vertex[i] - plan.skirt.surface_vertices;
        const std::uint32_t a = carried_anchor(plan.skirt, s);
        if (own.dir_x[a] * plan.skirt.normal_x[s] + own.dir_y[a] * plan.skirt.normal_y[s] < 0.05) continue;
        double sxx = 0.0, sxy = 0.0, syy = 0.0, sxp = 0.0, syp = 0.0;
        std::size_t points = 0;
        for (std::size_t u = 0; u < own.vertex_count(); ++u) {
            const double dx = own.x[u] - own.x[a], dy = own.y[u] - own.y[a], dp = own.phase[u] - own.phase[a];
            if (std::abs(own.width[u] - own.width[a]) > 0.2f * own.width[a] || std::hypot(dx, dy) > 0.5 * own.width[a]) continue;
            sxx += dx * dx, sxy += dx * dy, syy += dy * dy, sxp += dx * dp, syp += dy * dp;
            ++points;
        }
        const double det = sxx * syy - sxy * sxy;
        if (points < 6 || !(det > 0.0)) continue;
        const double gx = (syy * sxp - sxy * syp) / det, gy = (sxx * syp - sxy * sxp) / det;
        const double expected = gx * (b.plan.x[i] - own.x[a]) + gy * (b.plan.y[i] - own.y[a]);
        const double plane = 2.0 * std::numbers::pi / own.width[a] * (own.dir_x[a] * (b.plan.x[i] - own.x[a]) + own.dir_y[a] * (b.plan.y[i] - own.y[a]));
        ASSERT_NEAR(b.plan.lag[i], plane, 1e-9 * (1.0 + std::abs(plane)));
        worst_lag = std::max(worst_lag, std::abs(b.plan.lag[i] - expected) / (0.1 + 0.35 * std::abs(expected)));
        ++compared;
    }
    EXPECT_GT(compared, 50u);
    EXPECT_LT(worst_lag, 1.0) << "the lag's error over its tolerance";
}

TEST(SkirtBreakers, TheSurfZoneCarriesOnBeyondTheSideWithoutFolds) {
    // Frames of the whole pipeline: skirt vertices within half a wavelength of the border
    // foam as the surf zone inside does (none did before: the fit carries no foam), and
    // no frame folds. With breaker_wavelengths 0, the fit alone, and the border's foam
    // with its residual motion (far_field_foam): less, fading within the residual band.
    for (const double band : {0.0, 2.0}) {
        const Scene scene = parse_scene(oblique_beach(band), "beach.json", ".");
        const ScenePlan plan = plan_scene(scene);
        const SceneAnimation a = animate_scene(scene, plan, 2e9, FrameRange{0, 24});
        const std::size_t n = a.vertex_count, own = plan.skirt.surface_vertices;
        ASSERT_EQ(n, own + plan.skirt.vertex_count());
        double skirt_foam = 0.0, border_foam = 0.0;
        for (std::size_t f = 0; f < a.frame_count; ++f)
            for (std::size_t s = 0; s < plan.skirt.vertex_count(); ++s) {
                const std::uint32_t anchor = carried_anchor(plan.skirt, s);
                if (plan.skirt.distance[s] > 0.5 * plan.breakers.width[anchor]) continue;
                skirt_foam = std::max(skirt_foam, static_cast<double>(a.foam[f * n + own + s]));
                border_foam = std::max(border_foam, static_cast<double>(a.foam[f * n + anchor]));
            }
        EXPECT_GT(border_foam, 0.9) << "the surf zone reaches the border";
        if (band > 0.0) {
            EXPECT_GT(skirt_foam, 0.8 * border_foam) << "the surf carries on beyond the side";
        } else {
            EXPECT_GT(skirt_foam, 0.0) << "the border's foam with its residual";
            EXPECT_LE(skirt_foam, border_foam) << "faded, never more than the border's";
        }
        const MeshInspection m = inspect_animation(a.view());
        EXPECT_EQ(m.worst.folds, 0u) << "breaker_wavelengths " << band;
        EXPECT_EQ(m.unreferenced_vertices, 0u);
    }
}

TEST(SkirtBreakers, SizesGrowFromTheHeldBandsSidesAsFromItsEnd) {
    // Along a line 2 m beyond the oblique beach's west side, across the surf zone's end:
    // the size is held inside the band and grows by 0.3 m per metre of the distance to
    // it, also along the side. It used to step from 1 m to 1.6 m between two points a few
    // centimetres apart (the size at 2 m beyond the border, not at the band): edges
    // 3.11 × their neighbours on breaking Okushiri's skirt.
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const SkirtSize size =
        breaker_skirt_size([](const SkirtSite& s) { return 1.0 + 0.3 * s.d; }, plan.breakers, plan.seafloor.grid, 2.0);
    const double x0 = *std::min_element(plan.breakers.x.begin(), plan.breakers.x.end());
    const double y0 = *std::min_element(plan.breakers.y.begin(), plan.breakers.y.end());
    const double y1 = *std::max_element(plan.breakers.y.begin(), plan.breakers.y.end());
    constexpr double kOut = 2.0, kStep = 0.05;
    const auto at = [&](double y) { return size(SkirtSite{x0 - kOut, y, x0, y, kOut, 1.0}); };
    double steepest = 0.0, first_held = NAN, last_held = NAN;
    std::size_t held = 0, free = 0;
    for (double y = y0; y <= y1; y += kStep) {
        const double here = at(y);
        if (y > y0) steepest = std::max(steepest, std::abs(here - at(y - kStep)) / kStep);
        if (here == 1.0) {
            ++held;
            if (std::isnan(first_held)) first_held = y;
            last_held = y;
        } else {
            ++free;
        }
    }
    ASSERT_GT(held, 10u) << "the surf zone reaches the west side";
    ASSERT_GT(free, 10u) << "and ends on it";
    EXPECT_LE(steepest, 0.3 * (1.0 + 1e-9));
    // Beyond the held band's ends along the side: the distance to it is the gap along the
    // side (below kOut, the distance to the rectangle).
    for (double gap : {0.5, 1.5}) {
        if (first_held - gap > y0) {
            EXPECT_NEAR(at(first_held - gap), 1.0 + 0.3 * gap, 0.3 * kStep + 1e-9);
        }
        if (last_held + gap < y1) {
            EXPECT_NEAR(at(last_held + gap), 1.0 + 0.3 * gap, 0.3 * kStep + 1e-9);
        }
    }
}

TEST(JeschkeBreakers, WavesEnteringBrokenAcrossAnUpwaveSideAreMidLife) {
    // The oblique beach's west side runs into the surf zone. Over the apron beyond it the
    // waves broke before they reach the side (the tracer's EntryPoint::break_phase), so
    // the border's vertices foam as those a little inside do. Rays entering there used to
    // begin a new life on their first vertex: no foam on the border, and the skirt beyond
    // it carried none either.
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    double border = 0.0, inside = 0.0;
    std::size_t on_border = 0, in_band = 0;
    for (std::size_t v = 0; v < b.vertex_count(); ++v) {
        if (b.y[v] < 140.0 || b.y[v] > 155.0) continue;  // the surf zone: breaking at 134 m on the west side
        if (b.x[v] == 0.0) border += b.foam_yield[v], ++on_border;
        if (b.x[v] > 4.0 && b.x[v] < 8.0) inside += b.foam_yield[v], ++in_band;
    }
    ASSERT_GT(on_border, 5u);
    ASSERT_GT(in_band, 5u);
    border /= static_cast<double>(on_border);
    inside /= static_cast<double>(in_band);
    EXPECT_GT(inside, 0.3);
    EXPECT_GT(border, 0.7 * inside) << "border " << border << ", inside " << inside;
}

TEST(JeschkeBreakers, ARayInsertedInTheSurfZoneBreaksWhereItsNeighboursBroke) {
    // A ray inserted where its neighbours drifted apart in the surf zone is capped on its
    // first vertex: its wave broke before, where the rays beside it broke. It used to
    // start a new breaker there (a lip and a foam streak rising from nothing).
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const RayStrips& s = plan.strips;
    std::map<std::uint32_t, std::uint32_t> first;  // ray → its first vertex
    for (std::uint32_t v = 0; v < s.vertex_count(); ++v)
        if (auto [it, fresh] = first.emplace(s.ray[v], v); !fresh && s.step[v] < s.step[it->second]) it->second = v;
    std::map<std::uint32_t, double> broke;  // ray → break phase
    for (const RayBreak& r : plan.breakers.rays)
        if (r.breaks && r.surf_zone == 0) broke[r.ray] = r.break_phase;  // its first break (later ones follow a re-form)
    std::size_t inherited = 0;
    for (const auto& [ray, v] : first) {
        if (!(2.0 * s.amplitude[v] >= kBreakerIndex * s.depth[v]) || !broke.count(ray)) continue;  // unbroken on its first vertex
        bool neighbour_broke_before = false;
        for (std::size_t t = 0; t < s.triangles.size(); t += 3)
            for (std::size_t c = 0; c < 3; ++c)
                if (s.triangles[t + c] == v)
                    for (std::size_t d = 1; d < 3; ++d) {
                        const std::uint32_t other = s.ray[s.triangles[t + (c + d) % 3]];
                        neighbour_broke_before |= other != ray && broke.count(other) && broke[other] < s.phase[v] - 1e-9;
                    }
        if (!neighbour_broke_before) continue;
        EXPECT_LT(broke[ray], s.phase[v]) << "ray " << ray << " starts a new breaker on its first vertex";
        ++inherited;
    }
    EXPECT_GT(inherited, 3u);
}

TEST(JeschkeBreakers, TheBeachsWaterMeshCarriesTheExactPhaseUpToItsSides) {
    // Every wet vertex (deeper than 0.3 m) of the oblique beach's water mesh — resampled
    // from the rays, or filled from the wave field where the rays leave gaps (modulo 2π:
    // the field gives its phase so) — against the planar beach's exact phase from the
    // up-wave corner. Rays entering across the west side used to
    // start on the deep edge's plane wave: up to 54 rad ahead at the shore, and the
    // field's fill inherited the mismatch there (vertices at 90–110 rad among traced ones
    // at 44).
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const RayStrips& s = plan.water_strips;
    ASSERT_GT(s.vertex_count(), 1000u);
    const test::BeachWave exact(plan.seafloor, s.omega, 0.34 / std::hypot(0.34, 0.94));
    double worst = 0.0;
    std::size_t wet = 0, west = 0, off = 0;
    for (std::size_t v = 0; v < s.vertex_count(); ++v) {
        if (!(s.depth[v] > 0.3) || !(s.k[v] > 0.0)) continue;
        const double gap = std::abs(std::remainder(s.phase[v] - exact.phase(s.x[v], s.y[v]), 2.0 * std::numbers::pi));
        ++wet;
        west += s.x[v] < 20.0;
        worst = std::max(worst, gap);
        off += gap > 0.3;
    }
    EXPECT_GT(wet, 10000u);
    EXPECT_GT(west, 1000u);
    // Measured: 0.68 rad at worst, on 4 vertices in the west corner's last 10 m before the
    // shore (0.3–0.6 m deep); every other vertex within 0.3 rad.
    EXPECT_LT(worst, 0.75);
    EXPECT_LE(off, 10u);
}

TEST(JeschkeBreakers, EveryRayOfAPlaneSlopeBreaksAsOneType) {
    // On the planar beach (1:20) every crest meets the same slope: Battjes' class is the
    // same for every ray, plunging (ξ0 = 0.05 / √(0.8 / 99.9) = 0.56 at normal incidence),
    // including the rays capped on their first vertex — entering broken
    // across the west side, or inserted in the surf zone — which have no vertex seaward
    // of their break. Those used to count the slope as 0: spilling, their lips curled
    // less than their neighbours', a notch in the breaking crest where they run.
    const Scene scene = parse_scene(oblique_beach(2.0), "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    std::size_t breaking = 0, at_start = 0;
    std::map<std::uint32_t, std::uint32_t> first;  // ray → its first vertex
    for (std::uint32_t v = 0; v < plan.strips.vertex_count(); ++v)
        if (auto [it, fresh] = first.emplace(plan.strips.ray[v], v); !fresh && plan.strips.step[v] < plan.strips.step[it->second])
            it->second = v;
    for (const RayBreak& rb : plan.breakers.rays) {
        if (!rb.breaks || rb.depth <= 0.0) continue;  // breaking in the water (not reaching the shore unbroken)
        ++breaking;
        const std::uint32_t v = first.at(rb.ray);
        at_start += 2.0 * plan.strips.amplitude[v] >= kBreakerIndex * plan.strips.depth[v];
        EXPECT_EQ(rb.type, BreakerType::plunging) << "ray " << rb.ray << " at (" << rb.x << ", " << rb.y << "), xi " << rb.iribarren;
    }
    EXPECT_GT(breaking, 30u);
    EXPECT_GT(at_start, 3u);  // the rays this is about
}

TEST(SurfZoneMesh, AResolvedPlungingCrestStandsVerticalAndOverturnsOnlyWhereTheModelDrawsIt) {
    // The oblique beach's plunging crests on a surf-zone mesh at 0.75 H with the curl
    // (the breaking beach's settings), the whole pipeline, over one period at 4 fps. The
    // untangling takes the breakers' drawn sections (jeschke_drawn_lips) as its lips:
    // every 10 m of the surf zone (a wavelength clear of the sides, whose skirt and
    // shore carry the outer section) sees its crest's face reach 60° (measured: 90–100°,
    // overturned), some triangles face down (the lip), and every one that does has a
    // vertex the model draws overturned — none is a fold. Before the drawn lips the
    // untangling, which took the foam (still rising while the wall stands), held the
    // faces to 40–47° on a mesh at H/4.
    const Scene scene = parse_scene(R"({"name": "oblique beach", "seafloor": {"source": "planar-beach"}, "isobaths": {"spacing": 0.5},
      "waves": [{"period": 8, "amplitude": 0.4, "direction": [0.34, 0.94]}], "trace": {"ray_spacing": 4},
      "breakers": {"model": "jeschke", "lip": "curl"}, "animation": {"fps": 4},
      "surface": {"far_field": false, "water_mesh": {"surf_zone": 0.75}}})",
                                    "beach.json", ".");
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation a = animate_scene(scene, plan, 2e9, FrameRange{0, 32});
    const JeschkeMotionPlan& b = plan.breakers;
    const std::size_t n = a.vertex_count;
    ASSERT_EQ(n, b.vertex_count());
    const double x0 = *std::min_element(b.x.begin(), b.x.end()), x1 = *std::max_element(b.x.begin(), b.x.end());
    const double wavelength = 28.0;  // at the break (8 s, ~1.2 m deep)
    constexpr double kBin = 10.0;
    const auto bins = static_cast<std::size_t>((x1 - x0) / kBin) + 1;
    std::vector<double> steepest(bins, 0.0);
    std::size_t facing_down = 0, folds = 0;
    for (std::size_t f = 0; f < a.frame_count; ++f) {
        const float* p = &a.positions[3 * n * f];
        for (std::size_t t = 0; t < a.triangles.size(); t += 3) {
            const std::uint32_t i = a.triangles[t], j = a.triangles[t + 1], k = a.triangles[t + 2];
            const double ux = p[3 * j] - p[3 * i], uy = p[3 * j + 1] - p[3 * i + 1], uz = p[3 * j + 2] - p[3 * i + 2];
            const double wx = p[3 * k] - p[3 * i], wy = p[3 * k + 1] - p[3 * i + 1], wz = p[3 * k + 2] - p[3 * i + 2];
            const double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
            const double slope = std::atan2(std::hypot(nx, ny), nz) * 180.0 / std::numbers::pi;
            if (nz < 0.0) {
                ++facing_down;
                folds += !jeschke_draws_overturned(b, static_cast<double>(f) / a.fps, i, j, k);
            }
            const double cx = (b.x[i] + b.x[j] + b.x[k]) / 3.0;
            if (cx < x0 + wavelength || cx > x1 - wavelength) continue;
            double& s = steepest[static_cast<std::size_t>((cx - x0) / kBin)];
            s = std::max(s, slope);
        }
    }
    std::size_t faced = 0, crests = 0;
    for (std::size_t i = 0; i < bins; ++i) {
        const double lo = x0 + kBin * static_cast<double>(i);
        if (lo < x0 + wavelength || lo + kBin > x1 - wavelength) continue;
        ++crests;
        faced += steepest[i] >= 60.0;
        EXPECT_GE(steepest[i], 60.0) << "the crest's face at x = " << lo << " … " << lo + kBin;
    }
    EXPECT_GE(crests, 8u);
    EXPECT_GT(facing_down, 10u) << "the plunging lip overturns";
    EXPECT_EQ(folds, 0u) << "triangles facing down where the model draws no overturned lip";
    RecordProperty("facing_down", std::to_string(facing_down));
    RecordProperty("crests_at_60", std::to_string(faced));
}

TEST(SurfZoneMesh, TheWaterMeshGradesDownToAFractionOfHWhereCrestsBreakAndBackOut) {
    // /surface/water_mesh/surf_zone (issue 65) on the oblique beach, at H/2 (H/4 takes
    // 20 s to mesh): every vertex of the band where crests break has edges of at most
    // H/2 (the mesher's bound at the centroids, 10 % for the mean over a vertex's edges),
    // the offshore water (deeper than 4 m) keeps the wavelength's spacing, and the
    // overturning lips (lip "curl") are taken where the mesh resolves them, not on the
    // boundary. (Measured: 13 455 → 203 563 vertices, 167 562 in the band; where H/2 is
    // below 0.2 m the band holds 0.2 m.)
    const std::string base = R"({"name": "graded beach", "seafloor": {"source": "planar-beach"}, "isobaths": {"spacing": 0.5},
      "waves": [{"period": 8, "amplitude": 0.4, "direction": [0.34, 0.94]}], "trace": {"ray_spacing": 4},
      "breakers": {"model": "jeschke", "lip": "curl"}, "animation": {"fps": 8}, "surface": {"far_field": false)";
    const ScenePlan plain = plan_scene(parse_scene(base + "}}", "beach.json", "."), PlanStages::surface);
    const ScenePlan graded =
        plan_scene(parse_scene(base + R"(, "water_mesh": {"surf_zone": 0.5}}})", "beach.json", "."), PlanStages::surface);
    const WaterMesh& m = graded.water_mesh;
    const JeschkeMotionPlan& b = graded.breakers;
    ASSERT_EQ(b.vertex_count(), m.vertex_count());
    EXPECT_TRUE(plain.breakers.resolve.empty() || *std::max_element(plain.breakers.resolve.begin(), plain.breakers.resolve.end()) == 0.0f);
    std::vector<double> sum(m.vertex_count(), 0.0);
    std::vector<int> count(m.vertex_count(), 0);
    for (std::size_t t = 0; t < m.triangles.size(); t += 3)
        for (std::size_t i = 0; i < 3; ++i) {
            const std::uint32_t a = m.triangles[t + i], c = m.triangles[t + (i + 1) % 3];
            const double e = std::hypot(m.x[a] - m.x[c], m.y[a] - m.y[c]);
            sum[a] += e, sum[c] += e, ++count[a], ++count[c];
        }
    std::size_t band = 0, coarse = 0, resolved = 0, offshore = 0, offshore_coarse = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        const double spacing = sum[v] / count[v];
        if (in_breaking_band(b, v, 0.0) && !m.boundary[v]) {
            ++band;
            coarse += spacing > 1.1 * std::max(0.2, 0.5 * b.scale[v] / 5.0);
            resolved += b.resolve[v] > 0.5f;
        }
        if (m.boundary[v]) {
            EXPECT_EQ(b.resolve[v], 0.0f);
        }
        if (depth_at(graded.seafloor.grid, m.x[v], m.y[v]) > 4.0) ++offshore, offshore_coarse += spacing > 1.0;
    }
    EXPECT_GT(band, 5000u);
    EXPECT_LE(coarse, band / 100);
    EXPECT_GE(resolved, band * 3 / 4);  // 81 %: the rest within a wavelength of the sides (the skirt's outer section)
    EXPECT_GE(offshore_coarse, offshore * 9 / 10);
    EXPECT_GT(m.vertex_count(), 3 * plain.water_mesh.vertex_count());
    RecordProperty("vertices", std::to_string(m.vertex_count()));
    RecordProperty("plain_vertices", std::to_string(plain.water_mesh.vertex_count()));
    RecordProperty("band_vertices", std::to_string(band));
}
