// The preview ray caster: properties the sunset paper's model must show — a calm sea
// mirrors the sun at the mirror angle, waves spread the reflection into a glitter
// column under the sun — and the mesh path (Embree) agreeing with the analytic sea.
#include <gtest/gtest.h>

#include "libwave/errors.h"
#include "libwave/scene.h"
#include "libwave/shade.h"

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

using namespace wave;

namespace {


// Eye 10 m up at the origin looking along +y (azimuth 90°), horizon in the picture.
PreviewOptions sunset_view() {
    PreviewOptions o;
    o.camera = {0.0, 0.0, 10.0};
    o.look_at = {0.0, 100.0, 10.0 - 100.0 * std::tan(8.0 * std::numbers::pi / 180.0)};  // 8° down
    o.vertical_fov_degrees = 30.0;
    o.width = 201;
    o.height = 151;
    o.sun_azimuth_degrees = 90.0;
    o.sun_elevation_degrees = 6.0;
    return o;
}

double brightness(const Image& im, std::size_t i, std::size_t j) {
    const std::uint8_t* p = &im.rgb[3 * (j * im.width + i)];
    return p[0] + p[1] + p[2];
}

}  // namespace

TEST(Preview, CalmSeaMirrorsTheSunAtTheMirrorAngle) {
    PreviewOptions o = sunset_view();
    o.fresnel = false;
    o.glitter_exponent = 200.0;  // a sharp highlight
    const Image im = render_preview({}, {}, {}, o);
    // The pixel rows: row j looks at pitch −8° + 15°·(1 − 2(j + ½)/151) (small-angle
    // form of the pinhole's tan). The reflection of a sun 6° up comes from 6° down.
    std::size_t best_i = 0, best_j = 0;
    double best = -1.0;
    const double tan_v = std::tan(15.0 * std::numbers::pi / 180.0);
    for (std::size_t j = 0; j < im.height; ++j)
        for (std::size_t i = 0; i < im.width; ++i) {
            // Only the water: rays below the horizon.
            const double ny = 1.0 - 2.0 * (static_cast<double>(j) + 0.5) / static_cast<double>(im.height);
            const double pitch = -8.0 * std::numbers::pi / 180.0 + std::atan(ny * tan_v);
            if (pitch >= 0.0) continue;
            if (brightness(im, i, j) > best) best = brightness(im, i, j), best_i = i, best_j = j;
        }
    EXPECT_EQ(best_i, 100u) << "under the sun (straight ahead)";
    const double ny = 1.0 - 2.0 * (static_cast<double>(best_j) + 0.5) / static_cast<double>(im.height);
    const double pitch_deg = (-8.0 * std::numbers::pi / 180.0 + std::atan(ny * tan_v)) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(pitch_deg, -6.0, 0.25) << "the mirror angle (one pixel is 0.2°)";
    EXPECT_GT(best, 3 * 200.0) << "white at 0°";
}

TEST(Preview, WavesSpreadTheSunIntoAGlitterColumnUnderIt) {
    PreviewOptions o = sunset_view();
    o.glitter_exponent = 64.0;
    // Five superposed sine waves (the paper's count), a few metres long.
    o.bump = {{0.12, 0.0, 1.0, 7.0, 0.0}, {0.10, 0.6, 0.8, 4.3, 1.0}, {0.08, -0.5, 0.9, 3.1, 2.0},
              {0.06, 0.9, 0.4, 2.2, 0.5}, {0.05, -0.8, 0.6, 1.7, 1.5}};
    const Image im = render_preview({}, {}, {}, o);
    std::vector<double> column(im.width, 0.0);
    for (std::size_t j = im.height / 2 + 10; j < im.height; ++j)  // well below the horizon
        for (std::size_t i = 0; i < im.width; ++i) column[i] += brightness(im, i, j);
    std::size_t peak = 0;
    for (std::size_t i = 0; i < im.width; ++i)
        if (column[i] > column[peak]) peak = i;
    EXPECT_NEAR(static_cast<double>(peak), 100.0, 12.0) << "the column stands under the sun";
    // Sun glitter (near-white pixels) lies in the column, none towards the sides.
    std::size_t centre = 0, edges = 0;
    for (std::size_t j = im.height / 2 + 10; j < im.height; ++j)
        for (std::size_t i = 0; i < im.width; ++i) {
            if (brightness(im, i, j) < 3 * 235.0) continue;
            if (i >= 80 && i <= 120) ++centre;
            if (i < 40 || i > 160) ++edges;
        }
    EXPECT_GT(centre, 30u);
    EXPECT_GT(centre, 10 * (edges + 1));
}

TEST(Preview, AFlatMeshLooksLikeTheAnalyticSeaAndThreadsDoNotMatter) {
    PreviewOptions o = sunset_view();
    o.glitter_exponent = 8.0;
    o.sea_to_horizon = false;
    const std::vector<float> p{-500, 5, 0, 500, 5, 0, 500, 400, 0, -500, 400, 0};
    const std::vector<float> n{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<std::uint32_t> t{0, 1, 2, 0, 2, 3};
    const Image mesh = render_preview(p, n, t, o);
    o.sea_to_horizon = true;
    const Image sea = render_preview({}, {}, {}, o);
    std::size_t compared = 0;
    for (std::size_t k = 0; k < mesh.rgb.size(); ++k)
        if (mesh.rgb[k] != sea.rgb[k]) {
            // Only pixels off the quad (beyond 400 m or nearer than 5 m) may differ.
            const std::size_t j = k / 3 / mesh.width;
            ASSERT_TRUE(j < 68 || j > 140) << "row " << j;
        } else {
            ++compared;
        }
    EXPECT_GT(compared, mesh.rgb.size() / 3);
    Image one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = render_preview(p, n, t, o);
    }
    const Image many = render_preview(p, n, t, o);
    EXPECT_EQ(one.rgb, many.rgb);
    const std::string png = png_bytes(contact_sheet(std::vector<Image>{one, many, one}, 2));
    EXPECT_EQ(png.substr(1, 3), "PNG");
    EXPECT_EQ(contact_sheet(std::vector<Image>{one, many, one}, 2).height, 2 * one.height);
    EXPECT_THROW(render_preview(p, n, std::vector<std::uint32_t>{0, 1, 9}, o), InputError);
}
