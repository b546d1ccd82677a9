// The preview renderer: the sunset ray caster of sunset-bumpmap-raytracer.txt — rays
// from the eye through every pixel, the colour from the angle between the reflected ray
// and the sun (white at 0°, dark blue from 90°), normals from the mesh or from the
// paper's analytic sum of sine waves at the hit point — with Fresnel weights for sky
// and deep water. Embree finds the hits; the only translation unit that includes it.
#include "libwave/errors.h"
#include "libwave/io.h"
#include "libwave/physics.h"
#include "libwave/shade.h"

#include <embree3/rtcore.h>


#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace wave {
namespace {

constexpr double pi = std::numbers::pi;
using Colour = std::array<double, 3>;

struct V3 {
    double x, y, z;
};
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator*(double s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 unit(V3 a) {
    const double l = std::sqrt(dot(a, a));
    return l > 0.0 ? (1.0 / l) * a : V3{0.0, 0.0, 1.0};
}

Colour mix(const Colour& a, const Colour& b, double w) {
    return {a[0] + (b[0] - a[0]) * w, a[1] + (b[1] - a[1]) * w, a[2] + (b[2] - a[2]) * w};
}

const Colour kWhite{1.0, 0.97, 0.9}, kDeepBlue{0.01, 0.05, 0.16};
constexpr double kSunRadiance = 30.0;  // relative to the sky's brightest

// Sky: warm at the horizon, blue at the zenith, the sun's disc (0.6° across, drawn 1°).
Colour sky(V3 r, V3 sun) {
    const double up = std::clamp(r.z, 0.0, 1.0);
    Colour c = mix({0.85, 0.5, 0.28}, {0.12, 0.22, 0.48}, std::sqrt(up));
    if (dot(r, sun) > std::cos(0.5 * pi / 180.0)) c = kWhite;
    return c;
}

struct Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

}  // namespace

Image render_preview(std::span<const float> positions, std::span<const float> normals, std::span<const std::uint32_t> triangles,
                     const PreviewOptions& o) {
    const std::size_t nv = positions.size() / 3, nt = triangles.size() / 3;
    if (positions.size() % 3 || triangles.size() % 3 || (!normals.empty() && normals.size() != positions.size()))
        throw InputError("preview: positions, normals and triangles must come in triples of matching sizes");
    for (std::uint32_t v : triangles)
        if (v >= nv) throw InputError("preview: triangle index " + std::to_string(v) + " >= " + std::to_string(nv));
    if (o.width < 1 || o.height < 1 || o.width * o.height > 100'000'000)
        throw InputError("preview: the image must have 1 … 10⁸ pixels");
    if (!(o.vertical_fov_degrees > 0.0 && o.vertical_fov_degrees < 170.0))
        throw InputError("preview: vertical_fov_degrees must be in (0, 170)");

    // One BVH over the frame's triangles; built by one thread so it is the same each run.
    Embree bvh;
    if (nt > 0) {
        bvh.device = rtcNewDevice("threads=1");
        if (!bvh.device) throw RuntimeError("preview: Embree could not start (rtcNewDevice)");
        bvh.scene = rtcNewScene(bvh.device);
        rtcSetSceneFlags(bvh.scene, RTC_SCENE_FLAG_ROBUST);
        RTCGeometry g = rtcNewGeometry(bvh.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
        std::copy(positions.begin(), positions.end(), vb);
        std::copy(triangles.begin(), triangles.end(), ib);
        rtcCommitGeometry(g);
        rtcAttachGeometry(bvh.scene, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(bvh.scene);
    }

    // The view frame (no roll) and the sun.
    const V3 eye{o.camera[0], o.camera[1], o.camera[2]};
    const V3 f = unit(V3{o.look_at[0], o.look_at[1], o.look_at[2]} - eye);
    V3 r{f.y, -f.x, 0.0};
    if (dot(r, r) < 1e-18) throw InputError("preview: the camera looks straight up or down");
    r = unit(r);
    const V3 u{r.y * f.z - r.z * f.y, r.z * f.x - r.x * f.z, r.x * f.y - r.y * f.x};
    const double tan_v = std::tan(o.vertical_fov_degrees * pi / 360.0);
    const double tan_h = tan_v * static_cast<double>(o.width) / static_cast<double>(o.height);
    const double az = o.sun_azimuth_degrees * pi / 180.0, el = o.sun_elevation_degrees * pi / 180.0;
    const V3 sun{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};

    // The water's colour at a hit: bump normals (the paper's sine sum), the reflected
    // ray's angle to the sun, Fresnel between the reflection and the deep water.
    const auto water = [&](V3 hit, V3 n, V3 d) {
        double gx = 0.0, gy = 0.0;
        for (const BumpWave& b : o.bump) {
            const double dl = std::hypot(b.direction_x, b.direction_y);
            if (!(dl > 0.0) || !(b.wavelength > 0.0)) continue;
            const double dx = b.direction_x / dl, dy = b.direction_y / dl, k = 2.0 * pi / b.wavelength;
            const double s = b.amplitude * std::sin(k * ((hit.x - o.bump_reference[0]) * dx + (hit.y - o.bump_reference[1]) * dy) + b.phase);
            gx += s * dx;  // tilt towards the wave's direction: tan θ = A sin((POI − R)·D)
            gy += s * dy;
        }
        if (dot(n, d) > 0.0) n = -1.0 * n;  // seen from below (under a lip): the side facing the eye
        n = unit(n + V3{gx, gy, 0.0});
        const double cos_i = std::clamp(-dot(d, n), 0.0, 1.0);
        V3 refl = d + (2.0 * cos_i) * n;
        if (refl.z < 0.0) refl.z = -refl.z;  // steep bumps: the reflection stays in the sky
        refl = unit(refl);
        const double angle = std::acos(std::clamp(dot(refl, sun), -1.0, 1.0));
        const double glitter = std::pow(std::max(0.0, 1.0 - angle / (0.5 * pi)), o.glitter_exponent);
        if (!o.fresnel) return mix(kDeepBlue, kWhite, glitter);
        // The sun is far brighter than the sky (kSunRadiance): its glitter survives the
        // small Fresnel reflectance, the sky's reflection does not wash it out.
        const double R = fresnel_reflectivity(cos_i);
        const Colour s = sky(refl, sun);
        const Colour reflected{s[0] + kSunRadiance * glitter * kWhite[0], s[1] + kSunRadiance * glitter * kWhite[1],
                               s[2] + kSunRadiance * glitter * kWhite[2]};
        return mix(kDeepBlue, reflected, R);
    };

    Image img;
    img.width = o.width;
    img.height = o.height;
    img.rgb.resize(3 * o.width * o.height);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, o.height), [&](const tbb::blocked_range<std::size_t>& rows) {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        for (std::size_t j = rows.begin(); j != rows.end(); ++j)
            for (std::size_t i = 0; i < o.width; ++i) {
                const double nx = 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(o.width) - 1.0;
                const double ny = 1.0 - 2.0 * (static_cast<double>(j) + 0.5) / static_cast<double>(o.height);
                const V3 d = unit(f + (nx * tan_h) * r + (ny * tan_v) * u);
                Colour c = sky(d, sun);
                bool hit = false;
                if (bvh.scene) {
                    RTCRayHit rh{};
                    rh.ray.org_x = static_cast<float>(eye.x);
                    rh.ray.org_y = static_cast<float>(eye.y);
                    rh.ray.org_z = static_cast<float>(eye.z);
                    rh.ray.dir_x = static_cast<float>(d.x);
                    rh.ray.dir_y = static_cast<float>(d.y);
                    rh.ray.dir_z = static_cast<float>(d.z);
                    rh.ray.tnear = 0.0f;
                    rh.ray.tfar = std::numeric_limits<float>::infinity();
                    rh.ray.mask = 0xFFFFFFFFu;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(bvh.scene, &ctx, &rh);
                    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
                        hit = true;
                        const std::size_t t = rh.hit.primID;
                        const std::size_t a = triangles[3 * t], b = triangles[3 * t + 1], e = triangles[3 * t + 2];
                        V3 n;
                        if (!normals.empty()) {  // Embree's (u, v) weigh the second and third vertices
                            const double wu = rh.hit.u, wv = rh.hit.v, wa = 1.0 - wu - wv;
                            n = unit(V3{wa * normals[3 * a] + wu * normals[3 * b] + wv * normals[3 * e],
                                        wa * normals[3 * a + 1] + wu * normals[3 * b + 1] + wv * normals[3 * e + 1],
                                        wa * normals[3 * a + 2] + wu * normals[3 * b + 2] + wv * normals[3 * e + 2]});
                        } else {
                            n = unit(V3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
                        }
                        c = water(eye + static_cast<double>(rh.ray.tfar) * d, n, d);
                    }
                }
                if (!hit && o.sea_to_horizon && d.z < 0.0) c = water(eye + (-eye.z / d.z) * d, V3{0.0, 0.0, 1.0}, d);
                for (int k = 0; k < 3; ++k)  // sRGB-ish gamma
                    img.rgb[3 * (j * o.width + i) + static_cast<std::size_t>(k)] =
                        static_cast<std::uint8_t>(std::lround(255.0 * std::pow(std::clamp(c[static_cast<std::size_t>(k)], 0.0, 1.0), 1.0 / 2.2)));
            }
    });
    return img;
}

Image contact_sheet(std::span<const Image> images, std::size_t columns) {
    if (images.empty() || columns == 0) throw InputError("contact sheet: no images");
    const std::size_t w = images[0].width, h = images[0].height;
    for (const Image& im : images)
        if (im.width != w || im.height != h) throw InputError("contact sheet: the images differ in size");
    const std::size_t rows = (images.size() + columns - 1) / columns;
    Image sheet;
    sheet.width = w * columns;
    sheet.height = h * rows;
    sheet.rgb.assign(3 * sheet.width * sheet.height, 255);
    for (std::size_t k = 0; k < images.size(); ++k)
        for (std::size_t y = 0; y < h; ++y)
            std::copy_n(&images[k].rgb[3 * y * w], 3 * w,
                        &sheet.rgb[3 * ((k / columns * h + y) * sheet.width + k % columns * w)]);
    return sheet;
}

}  // namespace wave
