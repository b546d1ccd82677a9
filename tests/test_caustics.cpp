// Caustics on the seafloor (libwave/underwater.h) against closed forms: flat water's
// uniform transmitted irradiance, a sine crest's paraxial focus (lens-maker's law for
// one refracting surface) and its magnification before the focus, flux conservation.
#include "libwave/errors.h"
#include "libwave/physics.h"
#include "libwave/surface.h"
#include "libwave/underwater.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

namespace {

using namespace wave;


// An nx × ny grid of spacing dx × dy from the origin, elevation z(i, j) at node (i, j).
template <class Elevation>
ElevationGrid grid_of(std::size_t nx, std::size_t ny, double dx, double dy, Elevation z) {
    ElevationGrid g;
    g.nx = nx;
    g.ny = ny;
    g.dx = dx;
    g.dy = dy;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) g.z.push_back(z(double(i), double(j)));
    return g;
}

// A flat seafloor grid of depth h over [0, w] × [0, d].
ElevationGrid flat_floor(double w, double d, double h) {
    return grid_of(9, 9, w / 8.0, d / 8.0, [h](double, double) { return -h; });
}

// A surface z = a sin(k x) over [0, w] × [0, d], nx × ny vertices, exact unit normals.
struct SineSurface {
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> triangles;
};
SineSurface sine_surface(double w, double d, std::size_t nx, std::size_t ny, double a, double k) {
    SineSurface s;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            const double x = w * double(i) / double(nx - 1), y = d * double(j) / double(ny - 1);
            const double slope = a * k * std::cos(k * x), len = std::hypot(slope, 1.0);
            s.positions.insert(s.positions.end(), {float(x), float(y), float(a * std::sin(k * x))});
            s.normals.insert(s.normals.end(), {float(-slope / len), 0.0f, float(1.0 / len)});
        }
    s.triangles = grid_triangles(nx, ny);
    return s;
}

std::vector<float> caustics(const CausticPlan& plan, const SineSurface& s) {
    std::vector<float> map(plan.options.width * plan.options.height);
    evaluate_caustics(plan, s.positions, s.normals, s.triangles, map);
    return map;
}

TEST(Caustics, FlatWaterLightsAFlatFloorUniformlyWithTheTransmittedAttenuatedIrradiance) {
    const double h = 6.0, c = 0.12, elevation = 55.0 * std::numbers::pi / 180.0, azimuth = 30.0 * std::numbers::pi / 180.0;
    CausticOptions o;
    o.sun = {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
    o.attenuation = c;
    o.surface_irradiance = 2.5;
    o.width = 100;
    o.height = 80;
    const CausticPlan plan = plan_caustics(flat_floor(100.0, 80.0, h), o);
    const std::vector<float> map = caustics(plan, sine_surface(100.0, 80.0, 51, 41, 0.0, 1.0));
    const double cos_i = std::sin(elevation), sin_t = std::sqrt(1.0 - cos_i * cos_i) / kWaterRefractiveIndex;
    const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
    const double expected = fresnel_transmissivity(cos_i) * 2.5 * std::exp(-c * h / cos_t);
    // The light is displaced by h·tan θ_t ≈ 2.6 m away from the sun: pixels 5 m inside
    // the border receive it from the surface.
    double worst = 0.0;
    for (std::size_t j = 5; j < 75; ++j)
        for (std::size_t i = 5; i < 95; ++i) worst = std::max(worst, std::abs(map[j * 100 + i] / expected - 1.0));
    EXPECT_LT(worst, 0.01) << "expected " << expected;
    EXPECT_LT(worst, 1e-5);  // exact up to float positions
    // The up-sun border (x large: the light travels towards −x) took its light from
    // beyond the surface: flat water there gives the same irradiance ...
    for (std::size_t i = 0; i < 100; ++i) EXPECT_NEAR(map[40 * 100 + i], expected, 0.01 * expected) << i;
    for (std::size_t j = 0; j < 80; ++j) EXPECT_NEAR(map[j * 100 + 50], expected, 0.01 * expected) << j;
    // ... and without the water beyond, it is dark.
    o.flat_water_beyond = false;
    const std::vector<float> alone = caustics(plan_caustics(flat_floor(100.0, 80.0, h), o), sine_surface(100.0, 80.0, 51, 41, 0.0, 1.0));
    EXPECT_LT(alone[40 * 100 + 99], 0.01 * expected);
    EXPECT_NEAR(alone[40 * 100 + 0], expected, 0.01 * expected);
}

// The sine crest z = a sin(kx) is a cylindrical lens: near it the surface slope is
// −a k² ξ, a vertical ray refracts by (1 − 1/n) a k² ξ towards the crest's axis, and
// the rays meet a distance D = n / ((n − 1) a k²) below the crest (at z = a − D).
// Before the focus, at distance s below the crest, the beam under the crest is narrowed
// by 1 − s/D: the irradiance there is that many times brighter than the mean.
struct SineCase {
    double a = 0.05, wavelength = 4.0, k = 2.0 * std::numbers::pi / 4.0;
    double focus() const { return kWaterRefractiveIndex / ((kWaterRefractiveIndex - 1.0) * a * k * k); }
    // The map of the sine surface over a floor of depth h: 8 wavelengths, 200 pixels each.
    std::vector<float> map(double h, double attenuation = 0.0) const {
        CausticOptions o;
        o.attenuation = attenuation;
        o.width = 1600;
        o.height = 4;
        const CausticPlan plan = plan_caustics(flat_floor(8.0 * wavelength, 1.0, h), o);
        return caustics(plan, sine_surface(8.0 * wavelength, 1.0, 3201, 3, a, k));
    }
    // The brightest pixel and the mean over the middle four wavelengths (row 1).
    std::pair<double, double> peak_and_mean(const std::vector<float>& m) const {
        const auto first = m.begin() + 1600 + 400, last = first + 800;
        return {*std::max_element(first, last), std::accumulate(first, last, 0.0) / 800.0};
    }
};

TEST(Caustics, ASineCrestMagnifiesTheLightBeforeItsFocusAsTheLensLawSays) {
    const SineCase sine;
    ASSERT_NEAR(sine.focus(), 32.67, 0.01);  // n = 1.33
    for (double fraction : {0.25, 0.5, 0.75}) {
        const double s = fraction * sine.focus(), h = s - sine.a;
        const auto [peak, mean] = sine.peak_and_mean(sine.map(h));
        EXPECT_NEAR(peak / mean, 1.0 / (1.0 - fraction), 0.05 / (1.0 - fraction)) << "at " << fraction << " of the focal depth";
        // ... and the brightest pixel lies under a crest (x = λ/4 + j λ).
        const std::vector<float> m = sine.map(h);
        const auto first = m.begin() + 1600 + 400;
        const double x = (double(std::max_element(first, first + 800) - (m.begin() + 1600)) + 0.5) * sine.wavelength / 200.0;
        const double from_crest = std::remainder(x - 0.25 * sine.wavelength, sine.wavelength);
        EXPECT_LT(std::abs(from_crest), 0.02) << x;
    }
}

// Where the rays meet, measured from the maps alone: mean/peak = 1 − s/D before the
// focus is a straight line in s whose root is the focal depth D. Beyond it the light
// has folded into a line many times brighter than the mean (off-axis rays of a sine
// crest focus a little deeper than the paraxial ones, so the brightest line lies
// just past D).
TEST(Caustics, ASineCrestFocusesIntoABrightLineAtThePredictedDepth) {
    const SineCase sine;
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, count = 0.0;
    for (double fraction = 0.3; fraction < 0.71; fraction += 0.1) {
        const double s = fraction * sine.focus();
        const auto [peak, mean] = sine.peak_and_mean(sine.map(s - sine.a));
        const double y = mean / peak;
        sx += s, sy += y, sxx += s * s, sxy += s * y, count += 1.0;
    }
    const double slope = (count * sxy - sx * sy) / (count * sxx - sx * sx), intercept = (sy - slope * sx) / count;
    const double measured = -intercept / slope;
    EXPECT_NEAR(measured / sine.focus(), 1.0, 0.05) << "the rays meet " << measured << " m below the crest";
    double brightest = 0.0, where = 0.0;
    for (double fraction = 0.9; fraction < 1.301; fraction += 0.02) {
        const auto [peak, mean] = sine.peak_and_mean(sine.map(fraction * sine.focus() - sine.a));
        if (peak / mean > brightest) brightest = peak / mean, where = fraction;
    }
    EXPECT_GT(brightest, 20.0) << "at " << where << " of the focal depth";
    EXPECT_GE(where, 1.0);
    EXPECT_LE(where, 1.2);
    const auto [peak, mean] = sine.peak_and_mean(sine.map(0.8 * sine.focus() - sine.a));
    EXPECT_LT(peak / mean, 6.0);  // before the focus: no line yet
}

TEST(Caustics, TheMeanIrradianceIsTheFlatWatersWhereverTheLightFocuses) {
    const SineCase sine;
    SineCase flat;
    flat.a = 0.0;
    for (double h : {10.0, 32.4, 60.0}) {
        const double flat_mean = flat.peak_and_mean(flat.map(h, 0.1)).second;
        const double wavy_mean = sine.peak_and_mean(sine.map(h, 0.1)).second;
        EXPECT_NEAR(wavy_mean / flat_mean, 1.0, 0.01) << "floor at " << h << " m";
    }
}

TEST(Caustics, TheSameBitsOnOneThreadAndOnFour) {
    const SineCase sine;
    std::vector<float> one, four;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = sine.map(40.0, 0.1);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
        four = sine.map(40.0, 0.1);
    }
    EXPECT_EQ(one, four);
}

TEST(Caustics, ASlopingFloorIsFoundWhereTheRayMeetsIt) {
    // Floor z = −2 − 0.5 x rising towards x = 0; a flat surface under a zenith sun:
    // every ray goes straight down, path h(x), so the map is I₀ T e^{−c h(x)}.
    const ElevationGrid g = grid_of(21, 3, 1.0, 5.0, [](double i, double) { return -2.0 - 0.5 * i; });
    CausticOptions o;
    o.attenuation = 0.2;
    o.width = 20;
    o.height = 2;
    const CausticPlan plan = plan_caustics(g, o);
    const std::vector<float> map = caustics(plan, sine_surface(20.0, 10.0, 81, 5, 0.0, 1.0));
    const double t = fresnel_transmissivity(1.0);
    for (std::size_t i = 0; i < 20; ++i) {
        // The pixel's mean of e^{−c(2 + x/2)} over [i, i + 1].
        const double mean = (std::exp(-0.2 * (2.0 + 0.5 * double(i))) - std::exp(-0.2 * (2.0 + 0.5 * double(i + 1)))) / (0.2 * 0.5);
        EXPECT_NEAR(map[20 + i], t * mean, 2e-3 * t * mean) << i;
    }
}

TEST(Caustics, AnInclinedFloorUnderAnInclinedSunGetsTheLightItsSlopeSpreads) {
    // Flat water over the plane z = −H − αx, the sun in the x–z plane: a ray refracted to
    // t meets the floor point x' after s = (H + αx') / −t_z, and a strip dx of surface
    // lands on dx · −t_z / (−t_z − α t_x) of floor, so E(x') = T I₀ e^{−c s} (−t_z − α t_x) / −t_z.
    // The rays are found by the search's secant steps (no closed form on a slope).
    const double H = 5.0, alpha = 0.2, c = 0.1, elevation = 60.0 * std::numbers::pi / 180.0;
    const ElevationGrid g = grid_of(51, 6, 1.0, 1.0, [&](double i, double) { return -H - alpha * i; });
    CausticOptions o;
    o.sun = {std::cos(elevation), 0.0, std::sin(elevation)};
    o.attenuation = c;
    o.width = 100;
    o.height = 10;
    const CausticPlan plan = plan_caustics(g, o);
    const std::vector<float> map = caustics(plan, sine_surface(50.0, 5.0, 201, 21, 0.0, 1.0));
    const double eta = 1.0 / kWaterRefractiveIndex, tx = -eta * std::cos(elevation), tz = -std::sqrt(1.0 - tx * tx);
    const double T = fresnel_transmissivity(std::sin(elevation));
    for (std::size_t j = 2; j < 8; ++j)
        for (std::size_t i = 20; i < 80; ++i) {
            const double x = 0.5 * (double(i) + 0.5), s = (H + alpha * x) / -tz;
            const double expected = T * std::exp(-c * s) * (-tz - alpha * tx) / -tz;
            EXPECT_NEAR(map[j * 100 + i], expected, 2e-3 * expected) << i << ", " << j;
        }
}

TEST(Caustics, ANarrowRidgeCastsItsShadowOnTheFloorBehindIt) {
    // A floor 4 m down with a ridge two cells wide rising to 1 m below the surface, the
    // sun at 45° straight up the x axis: light travelling towards −x meets the ridge's
    // face, and the floor behind it is dark for about 3 m · tan θₜ (but for the light the
    // footprints spread across a shadow's edge, below). The rays that meet the face start
    // over the flat floor of the next tile of cells up-sun: a slope bound blind to the
    // ridge's tile beside theirs would let them step through it and light the shadow.
    // The ridge's nodes at x = 23 and 23.5 m: the last cells of tile 5.
    const ElevationGrid g = grid_of(81, 9, 0.5, 0.5, [](double i, double) { return i == 46.0 || i == 47.0 ? -1.0 : -4.0; });
    CausticOptions o;
    const double elevation = 45.0 * std::numbers::pi / 180.0;
    o.sun = {std::cos(elevation), 0.0, std::sin(elevation)};
    o.attenuation = 0.0;
    o.width = 160;
    o.height = 16;
    const CausticPlan plan = plan_caustics(g, o);
    ASSERT_GT(plan.max_slope, 5.0);
    ASSERT_LT(plan.tile_slope.front(), 1e-6);  // the tiles away from the ridge are flat
    const std::vector<float> map = caustics(plan, sine_surface(40.0, 4.0, 321, 33, 0.0, 1.0));
    const double sin_t = std::cos(elevation) / kWaterRefractiveIndex, tan_t = sin_t / std::sqrt(1.0 - sin_t * sin_t);
    const double flat = fresnel_transmissivity(std::sin(elevation));
    const auto column_mean = [&](double x) {  // the map's middle rows at x (m)
        const auto i = static_cast<std::size_t>(x / 0.25);
        double sum = 0.0;
        for (std::size_t j = 4; j < 12; ++j) sum += map[j * 160 + i];
        return sum / 8.0;
    };
    // The footprints of the surface triangles whose rays part between the ridge's face
    // and the floor beyond the shadow bridge it: one row of surface cells (0.125 m)
    // spread over its ~1.9 m, twice (two triangles a cell), a tenth of flat water's light.
    for (double x = 23.0 - 0.6 * 3.0 * tan_t; x < 22.5; x += 0.25) EXPECT_LT(column_mean(x), 0.15 * flat) << "shadow at x = " << x;
    for (double x : {5.0, 10.0, 15.0, 26.0, 30.0, 35.0}) EXPECT_NEAR(column_mean(x), flat, 0.01 * flat) << "open floor at x = " << x;
}

TEST(Caustics, AFootprintFarBeyondTheMapEndsAtOnce) {
    // A triangle reaching 10¹⁷ m left of the map beside a small one inside it: no walk of
    // 10¹⁷ pixels towards the map (steps of 1 could never get there), and the part of
    // the huge triangle over the map — x in [0, 5], y in [1, 9]: 40 m² — lights it as
    // flat water does, exactly (no cancellation between huge numbers), with the small
    // triangle's 2 m² on top.
    ElevationGrid g = flat_floor(10.0, 10.0, 2.0);
    CausticOptions o;
    o.width = o.height = 10;
    o.flat_water_beyond = false;
    const CausticPlan plan = plan_caustics(g, o);
    const std::vector<float> positions{-1e17f, 5.0f, 0.0f, 5.0f, 1.0f, 0.0f, 5.0f, 9.0f, 0.0f,
                                       2.0f, 2.0f, 0.0f, 4.0f, 2.0f, 0.0f, 2.0f, 4.0f, 0.0f};
    std::vector<float> normals(18, 0.0f);
    for (std::size_t v = 0; v < 6; ++v) normals[3 * v + 2] = 1.0f;
    const std::vector<std::uint32_t> triangles{0, 1, 2, 3, 4, 5};
    std::vector<float> map(100);
    evaluate_caustics(plan, positions, normals, triangles, map);
    double total = 0.0;
    for (float e : map) total += e;
    const double expected = fresnel_transmissivity(1.0) * std::exp(-0.15 * 2.0) * 42.0;  // 1 m² pixels
    EXPECT_NEAR(total, expected, 1e-3 * expected);
}

// Every triangle's three edges appear exactly once among the mesh's edges, each on the
// side it walks them: the triangle on an edge's first side walks a → b, the one on
// its second side b → a.
void expect_every_walk_once(const CausticMesh& mesh) {
    const std::size_t nt = mesh.triangles.size() / 3;
    std::vector<int> seen(3 * nt, 0);
    const auto mark = [&](std::uint32_t t, std::uint32_t a, std::uint32_t b) {
        bool found = false;
        for (std::size_t c = 0; c < 3; ++c)
            if (mesh.triangles[3 * t + c] == a && mesh.triangles[3 * t + (c + 1) % 3] == b) ++seen[3 * t + c], found = true;
        EXPECT_TRUE(found) << "triangle " << t << " does not walk " << a << " → " << b;
    };
    for (std::size_t e = 0; e < mesh.edges.size() / 4; ++e) {
        const std::uint32_t a = mesh.edges[4 * e], b = mesh.edges[4 * e + 1];
        mark(mesh.edges[4 * e + 2], a, b);
        if (mesh.edges[4 * e + 3] != CausticMesh::kNone) mark(mesh.edges[4 * e + 3], b, a);
    }
    for (std::size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], 1) << "walk " << i;
}

TEST(Caustics, AMeshListsEachEdgeOnceWithTheTrianglesOnItsTwoSides) {
    const std::size_t nx = 7, ny = 5;
    const CausticMesh mesh = plan_caustic_mesh(grid_triangles(nx, ny), nx * ny);
    const std::size_t edges = (nx - 1) * ny + nx * (ny - 1) + (nx - 1) * (ny - 1);
    ASSERT_EQ(mesh.edges.size(), 4 * edges);
    std::size_t border = 0;
    for (std::size_t e = 0; e < edges; ++e) border += mesh.edges[4 * e + 3] == CausticMesh::kNone;
    EXPECT_EQ(border, 2 * (nx - 1) + 2 * (ny - 1));
    expect_every_walk_once(mesh);
}

TEST(Caustics, AnEdgeOfThreeTrianglesOrOfTwoWalkingItAlikeIsListedOncePerExtraTriangle) {
    // Triangles 0 and 1 share 0–1 the usual way; triangle 2 also walks 0 → 1 (a third
    // sheet on the edge, turned like triangle 0); triangle 3 walks 1 → 0 and pairs with it.
    const std::vector<std::uint32_t> triangles{0, 1, 2, 1, 0, 3, 0, 1, 4, 1, 0, 5};
    const CausticMesh mesh = plan_caustic_mesh(triangles, 6);
    expect_every_walk_once(mesh);
    std::size_t on_01 = 0, paired = 0;
    for (std::size_t e = 0; e < mesh.edges.size() / 4; ++e)
        if (std::min(mesh.edges[4 * e], mesh.edges[4 * e + 1]) == 0 && std::max(mesh.edges[4 * e], mesh.edges[4 * e + 1]) == 1)
            ++on_01, paired += mesh.edges[4 * e + 3] != CausticMesh::kNone;
    EXPECT_EQ(on_01, 2u);
    EXPECT_EQ(paired, 2u);
    // A crowd of 20 000 triangles on one edge (a degenerate mesh) is planned at once:
    // past a few unpaired sides, each is an edge of its own.
    std::vector<std::uint32_t> crowd;
    for (std::uint32_t k = 0; k < 20000; ++k) crowd.insert(crowd.end(), {0, 1, 2 + k});
    const CausticMesh crowded = plan_caustic_mesh(crowd, 20002);
    expect_every_walk_once(crowded);
    EXPECT_THROW(plan_caustic_mesh(std::vector<std::uint32_t>{0, 1}, 6), InputError);
    EXPECT_THROW(plan_caustic_mesh(std::vector<std::uint32_t>{0, 1, 6}, 6), InputError);
}

TEST(Caustics, APlannedMeshGivesTheSameBitsAsTheTrianglesGivenWithTheFrame) {
    // A crest past its focus over a sloping floor: footprints turned over, rays found by
    // the search rather than in closed form.
    const ElevationGrid g = grid_of(33, 9, 1.0, 1.0, [](double i, double j) { return -30.0 - 0.3 * i + 0.4 * std::sin(j); });
    CausticOptions o;
    o.sun = {0.2, -0.1, 0.97};
    o.width = 256;
    o.height = 64;
    const CausticPlan plan = plan_caustics(g, o);
    ASSERT_FALSE(plan.flat);
    const SineSurface s = sine_surface(32.0, 8.0, 161, 41, 0.05, 2.0 * std::numbers::pi / 4.0);
    const CausticMesh mesh = plan_caustic_mesh(s.triangles, s.positions.size() / 3);
    std::vector<float> planned(256 * 64), given(256 * 64);
    CausticWorkspace workspace;
    evaluate_caustics(plan, mesh, s.positions, s.normals, planned, &workspace);
    evaluate_caustics(plan, s.positions, s.normals, s.triangles, given);
    EXPECT_EQ(planned, given);
    EXPECT_GT(*std::max_element(planned.begin(), planned.end()), 3.0 * std::accumulate(planned.begin(), planned.end(), 0.0) / 16384.0);
    std::vector<float> again(256 * 64);
    evaluate_caustics(plan, mesh, s.positions, s.normals, again, &workspace);  // the workspace reused
    EXPECT_EQ(again, planned);
    std::vector<float> fewer(s.positions.begin(), s.positions.end() - 3);
    EXPECT_THROW(evaluate_caustics(plan, mesh, fewer, fewer, planned), InputError);
}

TEST(Caustics, BadOptionsAndSizesAreRefused) {
    const ElevationGrid floor = flat_floor(10.0, 10.0, 2.0);
    CausticOptions o;
    o.sun = {1.0, 0.0, 0.0};
    EXPECT_THROW(plan_caustics(floor, o), InputError);
    o = {};
    o.width = 0;
    EXPECT_THROW(plan_caustics(floor, o), InputError);
    o = {};
    o.attenuation = -1.0;
    EXPECT_THROW(plan_caustics(floor, o), InputError);
    o = {};
    o.water_index = 0.9;
    EXPECT_THROW(plan_caustics(floor, o), InputError);
    o = {};
    o.width = 4;
    o.height = 4;
    const CausticPlan plan = plan_caustics(floor, o);
    SineSurface s = sine_surface(10.0, 10.0, 3, 3, 0.0, 1.0);
    std::vector<float> map(16), small(15);
    EXPECT_THROW(evaluate_caustics(plan, s.positions, s.normals, s.triangles, small), InputError);
    s.triangles[4] = 9;
    EXPECT_THROW(evaluate_caustics(plan, s.positions, s.normals, s.triangles, map), InputError);
    EXPECT_THROW(parse_water_type("murky", "/underwater/water_type"), InputError);
    EXPECT_EQ(parse_water_type("harbour", "x"), WaterType::harbour);
}

TEST(Caustics, AMapBecomesASixteenBitGreyPng) {
    const std::vector<float> map{0.0f, 1.0f, 2.0f, 8.0f};
    const std::string png = caustic_png(map, 2, 2, 4.0);
    ASSERT_GT(png.size(), 40u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_EQ(static_cast<unsigned char>(png[24]), 16u);  // IHDR bit depth
    EXPECT_EQ(static_cast<unsigned char>(png[25]), 0u);   // colour type: grey
}

}  // namespace
