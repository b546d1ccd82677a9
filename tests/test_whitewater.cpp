// Whitewater particles: the closed forms against Newton's ballistics, determinism for any
// thread count, a frame computed alone equal to the same frame of a run, the loop closing,
// emission only where the crest breaks, foam conserved by advection alone.
#include <gtest/gtest.h>

#include "libwave/errors.h"
#include "libwave/motion.h"
#include "libwave/physics.h"
#include "libwave/scene.h"
#include "libwave/whitewater.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

using namespace wave;

namespace {

// One event at the origin: a 1 m crest running +x at 5 m/s, 4 m of crest, at t = 0.
WhitewaterEvents one_event(float spray, float foam, float bubbles) {
    WhitewaterEvents e;
    e.add(0.0f, 0.0f, 0.75f, 1.0f, 0.0f, 5.0f, 1.0f, 4.0f, 0.0, spray, foam, bubbles, 42, 0);
    return e;
}

bool same(const WhitewaterPoints& a, const WhitewaterPoints& b) {
    const auto eq = [](const auto& x, const auto& y) {
        return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]) == 0);
    };
    return eq(a.positions, b.positions) && eq(a.velocities, b.velocities) && eq(a.age, b.age) && eq(a.size, b.size) &&
           eq(a.kind, b.kind);
}

// The planar beach (slope 0.05), an 8 s swell at normal incidence, Jeschke's breakers.
const char* kWhitewaterBeach = R"({"name": "whitewater beach", "seafloor": {"source": "planar-beach"},
  "isobaths": {"spacing": 0.5}, "waves": [{"period": 8, "amplitude": 0.4, "direction": [0, 1]}],
  "trace": {"ray_spacing": 4}, "breakers": "jeschke", "animation": {"fps": 4},
  "surface": {"water_mesh": false}, "whitewater": true})";

}  // namespace

TEST(Whitewater, SprayFollowsNewtonsBallisticsWithoutDrag) {
    WhitewaterOptions o;
    o.foam = o.bubbles = false;
    o.spray_drag = 0.0;
    const WhitewaterEvents e = one_event(1.0f, 0.0f, 0.0f);
    // Particle j at ages a − h, a, a + h: z'' = −g, x'' = 0, v = dp/da.
    const double h = 0.01, a = 0.3;
    WhitewaterPoints before, now, after;
    evaluate_whitewater(e, o, a - h, before);
    evaluate_whitewater(e, o, a, now);
    evaluate_whitewater(e, o, a + h, after);
    ASSERT_GT(now.count(), 10u);
    ASSERT_EQ(before.count(), now.count());  // none lands within 10 ms of 0.3 s here
    ASSERT_EQ(after.count(), now.count());
    for (std::size_t k = 0; k < now.count(); ++k) {
        EXPECT_EQ(now.kind[k], static_cast<std::uint8_t>(WhitewaterKind::spray));
        const double zdd = (after.positions[3 * k + 2] - 2.0 * now.positions[3 * k + 2] + before.positions[3 * k + 2]) / (h * h);
        const double xdd = (after.positions[3 * k] - 2.0 * now.positions[3 * k] + before.positions[3 * k]) / (h * h);
        EXPECT_NEAR(zdd, -kGravity, 0.05) << k;  // float positions: ~1e-6 m over h² = 1e-4
        EXPECT_NEAR(xdd, 0.0, 0.05) << k;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR((after.positions[3 * k + c] - before.positions[3 * k + c]) / (2 * h), now.velocities[3 * k + c], 1e-2) << k;
        EXPECT_NEAR(now.age[k], a, 1e-6);
    }
}

TEST(Whitewater, DragSlowsTheSprayAsItsClosedFormSays) {
    WhitewaterOptions o;
    o.foam = o.bubbles = false;
    o.spray_drag = 2.0;
    const WhitewaterEvents e = one_event(1.0f, 0.0f, 0.0f);
    const double h = 0.005, a = 0.2;
    WhitewaterPoints before, now, after;
    evaluate_whitewater(e, o, a - h, before);
    evaluate_whitewater(e, o, a, now);
    evaluate_whitewater(e, o, a + h, after);
    ASSERT_EQ(before.count(), now.count());
    ASSERT_EQ(after.count(), now.count());
    ASSERT_GT(now.count(), 10u);
    for (std::size_t k = 0; k < now.count(); ++k) {
        // dv/da = −k v − g ẑ, with v from the central difference of the positions.
        for (int c = 0; c < 3; ++c) {
            const double acc = (after.positions[3 * k + c] - 2.0 * now.positions[3 * k + c] + before.positions[3 * k + c]) / (h * h);
            EXPECT_NEAR(acc, -o.spray_drag * now.velocities[3 * k + c] - (c == 2 ? kGravity : 0.0), 0.3) << k << " " << c;
        }
    }
}

TEST(Whitewater, SprayDiesWhereItLands) {
    WhitewaterOptions o;
    o.foam = o.bubbles = false;
    const WhitewaterEvents e = one_event(1.0f, 0.0f, 0.0f);
    WhitewaterPoints p;
    for (double t = 0.0; t < 3.0; t += 0.1) {
        evaluate_whitewater(e, o, t, p);
        // The still-water level under the crest: its top (0.75 m) less 0.75 H.
        for (std::size_t k = 0; k < p.count(); ++k) EXPECT_GE(p.positions[3 * k + 2], -1e-5f) << t;
    }
    evaluate_whitewater(e, o, o.spray_life + 0.01, p);
    EXPECT_EQ(p.count(), 0u);
}

TEST(Whitewater, TheSameBitsForAnyThreadCountAndTheLoopClosesWithoutAPop) {
    WhitewaterEvents e;
    for (int i = 0; i < 2000; ++i)
        e.add(static_cast<float>(i % 50), static_cast<float>(i / 50), 0.6f, 0.0f, 1.0f, 6.0f, 0.8f, 1.5f, 0.013 * i, 0.5f, 1.0f,
              0.7f, static_cast<std::uint64_t>(i), static_cast<std::uint32_t>(i % 3));
    e.period = 24.0;
    const WhitewaterOptions o;
    WhitewaterPoints all, one, later;
    evaluate_whitewater(e, o, 7.25, all);
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        evaluate_whitewater(e, o, 7.25, one);
    }
    ASSERT_GT(all.count(), 1000u);
    EXPECT_TRUE(same(all, one));
    evaluate_whitewater(e, o, 7.25 + 24.0, later);  // one loop on
    EXPECT_EQ(all.count(), later.count());
    for (std::size_t k = 0; k < std::min(all.count(), later.count()); ++k)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(all.positions[3 * k + c], later.positions[3 * k + c], 2e-4) << k;
}

TEST(Whitewater, FoamIsConservedByAdvectionAloneWithoutDecay) {
    WhitewaterOptions o;
    o.spray = o.bubbles = false;
    o.foam_life = 0.0;  // no decay
    o.foam_lace = 0.0;  // no holes
    const WhitewaterEvents e = one_event(0.0f, 1.0f, 0.0f);
    WhitewaterPoints p;
    std::size_t count = 0;
    double area = 0.0;
    double mean_x0 = 0.0, mean_x_last = 0.0;
    for (double t : {0.1, 1.0, 5.0, 30.0, 300.0}) {
        evaluate_whitewater(e, o, t, p);
        double a = 0.0, mean_x = 0.0;
        for (std::size_t k = 0; k < p.count(); ++k) a += p.size[k] * p.size[k], mean_x += p.positions[3 * k];
        mean_x /= static_cast<double>(p.count());
        if (count == 0) {
            count = p.count(), area = a, mean_x0 = mean_x;
            EXPECT_NEAR(static_cast<double>(count), o.foam_density * 4.0 * 1.0, 1.0);  // density · length · H
        }
        EXPECT_EQ(p.count(), count) << t;
        EXPECT_NEAR(a, area, 1e-9 * area) << t;
        EXPECT_GE(mean_x, mean_x0 - 1e-3) << t;  // pushed on by the bore, never back
        mean_x_last = mean_x;
    }
    // The bore's push settles at push · c · τ (each patch 0.6 … 1.4 of it), from 0.1 s on:
    // 0.5 · 5 m/s · 1.5 s · e^{−0.1/1.5}; the spreading's mean is within half a metre.
    const double push = 0.5 * 5.0 * 1.5 * std::exp(-0.1 / 1.5);
    EXPECT_GT(mean_x_last - mean_x0, 0.6 * push - 0.5);
    EXPECT_LT(mean_x_last - mean_x0, 1.4 * push + 0.5);
}

TEST(Whitewater, RefusesOptionsOutOfRange) {
    WhitewaterOptions o;
    o.spray_drag = -1.0;
    WhitewaterPoints p;
    EXPECT_THROW(evaluate_whitewater(one_event(1, 1, 1), o, 0.5, p), InputError);
    WhitewaterOptions forever;
    forever.foam_life = 0.0;
    WhitewaterEvents periodic = one_event(0, 1, 0);
    periodic.period = 8.0;  // would pile up for ever
    EXPECT_THROW(evaluate_whitewater(periodic, forever, 0.5, p), InputError);
    WhitewaterEvents ragged = one_event(1, 1, 1);
    ragged.key.push_back(1);
    EXPECT_THROW(evaluate_whitewater(ragged, WhitewaterOptions{}, 0.5, p), InputError);
}

TEST(Whitewater, TheBoundHoldsEveryParticleAliveAndNotEveryOneALoopEmits) {
    // A 110 m beach of 5 500 events a crest passes, 3 crests in a 24 s loop, every kind at
    // full strength (bench_whitewater's beach, an eighth as long). whitewater_bound is the
    // most alive at once: never under the particles alive at any time of the loop (0.25 s
    // steps), and within 3 × of the most. It counted every particle a loop emits
    // (⌈life / period⌉ per emission), 7.6 × the most on the bench's beach, which it
    // refused at the default max_points.
    WhitewaterEvents e;
    e.period = 24.0;
    for (int crest = 0; crest < 3; ++crest)
        for (int i = 0; i < 55; ++i)
            for (int j = 0; j < 100; ++j)
                e.add(static_cast<float>(2 * i), static_cast<float>(0.5 * j), 0.6f, 0.0f, 1.0f, 5.0f, 0.8f, 1.2f, 8.0 * crest + 0.1 * j,
                      1.0f, 1.0f, 1.0f, static_cast<std::uint64_t>((crest * 55 + i) * 100 + j), static_cast<std::uint32_t>(crest));
    const WhitewaterOptions o;
    const std::size_t bound = whitewater_bound(e, o);
    std::size_t most = 0;
    WhitewaterPoints p;
    for (int k = 0; k < 96; ++k) {
        evaluate_whitewater(e, o, 0.25 * k, p);
        most = std::max(most, p.count());
    }
    EXPECT_GE(bound, most);
    EXPECT_LE(static_cast<double>(bound), 3.0 * static_cast<double>(most));
    RecordProperty("bound", std::to_string(bound));
    RecordProperty("most_alive", std::to_string(most));
    // Lives longer than the loop: every emission of the last ⌊life / P⌋ periods is alive.
    WhitewaterOptions short_lived, long_lived;
    short_lived.foam_life = 4.0;
    long_lived.foam_life = 60.0;
    WhitewaterEvents foam = one_event(0, 1, 0);
    foam.period = 8.0;
    const std::size_t one = whitewater_bound(foam, short_lived);
    EXPECT_GT(one, 0u);
    EXPECT_EQ(whitewater_bound(foam, long_lived), 8 * one);  // 60 s = 7 periods + 4 s: 7 + 1 ages at most
}

TEST(Whitewater, BreakersEmitOnlyWhereAndWhenTheirCrestsBreak) {
    const Scene scene = parse_scene(kWhitewaterBeach, "beach", ".");
    const ScenePlan plan = plan_scene(scene);
    const JeschkeMotionPlan& b = plan.breakers;
    const WhitewaterEvents& e = plan.whitewater;
    ASSERT_GT(e.size(), 100u);
    EXPECT_NEAR(e.period, plan.loop_period, 1e-9);
    // Each event stands on a vertex (its rest position) that lies in the surf zone, at a
    // moment the crest stands over it: ω t − Φ ≡ 0 (mod 2π).
    std::size_t matched = 0;
    std::size_t v = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        while (v < b.vertex_count() && (static_cast<float>(b.x[v]) != e.x[i] || static_cast<float>(b.y[v]) != e.y[i])) ++v;
        ASSERT_LT(v, b.vertex_count()) << "event " << i << " is on no vertex (events come in vertex order)";
        ++matched;
        EXPECT_TRUE(std::isfinite(b.break_phase[v]));
        EXPECT_GE(b.phase[v], b.break_phase[v] - b.variation * 2 * std::numbers::pi - 1e-9) << "offshore of the break";
        const double turns = (b.omega * e.time[i] - b.phase[v]) / (2 * std::numbers::pi);
        EXPECT_NEAR(turns, std::round(turns), 1e-6) << i;
        if (e.spray[i] > 0.0f) {
            EXPECT_LE(b.phase[v], b.end_phase[v] + 1e-9);
        }
    }
    EXPECT_EQ(matched, e.size());
}

TEST(Whitewater, AFrameComputedAloneEqualsTheSameFrameOfARun) {
    const Scene scene = parse_scene(kWhitewaterBeach, "beach", ".");
    const ScenePlan plan = plan_scene(scene);
    const SceneAnimation run = animate_scene(scene, plan, 4e9, FrameRange{0, 6});
    const SceneAnimation alone = animate_scene(scene, plan, 4e9, FrameRange{4, 5});
    ASSERT_EQ(run.whitewater.size(), 6u);
    ASSERT_EQ(alone.whitewater.size(), 1u);
    EXPECT_EQ(run.whitewater[4], alone.whitewater[0]);
    EXPECT_GT(run.whitewater[4].size(), 1000u);
    // And for any thread count.
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    const SceneAnimation serial = animate_scene(scene, plan, 4e9, FrameRange{4, 5});
    EXPECT_EQ(serial.whitewater[0], alone.whitewater[0]);
}

TEST(Whitewater, TheGlbHoldsOnePointsPrimitive) {
    WhitewaterPoints p;
    evaluate_whitewater(one_event(1, 1, 1), WhitewaterOptions{}, 0.4, p);
    ASSERT_GT(p.count(), 0u);
    const std::string glb = whitewater_glb(p, 7, 24.0);
    ASSERT_GE(glb.size(), 20u);
    EXPECT_EQ(glb.substr(0, 4), "glTF");
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 8, 4);
    EXPECT_EQ(length, glb.size());
    EXPECT_NE(glb.find("\"mode\":0"), std::string::npos);
    EXPECT_NE(glb.find("\"frame\":7"), std::string::npos);
    const std::string empty = whitewater_glb(WhitewaterPoints{}, 0, 24.0);
    EXPECT_EQ(empty.find("meshes"), std::string::npos);
}

TEST(Whitewater, GonzatosBreakersEmitAsTheirCrestsPassWhereTheyNearBreaking) {
    std::string text = kWhitewaterBeach;
    text.replace(text.find("\"breakers\": \"jeschke\", "), 23, "");
    const Scene scene = parse_scene(text, "beach", ".");
    ASSERT_FALSE(scene.breakers);
    const ScenePlan plan = plan_scene(scene);
    const WhitewaterEvents& e = plan.whitewater;
    ASSERT_GT(e.size(), 100u);
    EXPECT_NEAR(e.period, 8.0, 1e-9);  // the swell's period
    const RayStrips& s = plan.water_strips.vertex_count() > 0 ? plan.water_strips : plan.strips;
    std::size_t v = 0;
    for (std::size_t i = 0; i < e.size(); ++i) {
        while (v < s.vertex_count() && (static_cast<float>(s.x[v]) != e.x[i] || static_cast<float>(s.y[v]) != e.y[i])) ++v;
        ASSERT_LT(v, s.vertex_count()) << "event " << i << " is on no vertex";
        // Near breaking: H ≥ onset · γ h; and the crest (Φ_min + π) over the vertex then.
        EXPECT_GE(2.0 * s.amplitude[v], scene.foam.onset * scene.foam.breaker_index * s.depth[v] * (1 - 1e-9));
        const double turns = (plan.motion.phase[v] - plan.motion.shape[v].trough_phase - std::numbers::pi -
                              plan.motion.omega * e.time[i]) / (2 * std::numbers::pi);
        EXPECT_NEAR(turns, std::round(turns), 1e-6) << i;
        EXPECT_LE(e.spray[i], e.foam[i]);  // spray only as the wave reaches the limit
    }
}
