// Scene files: JSON → validated Scene, with JSON-pointer error messages; and the
// wiring of the static stages.
#include "libwave/scene.h"

#include "core/format.h"
#include "libwave/errors.h"
#include "libwave/shade.h"
#include "core/files.h"
#include "core/json_input.h"
#include "core/limits.h"
#include "scene_schema.h"
#include "surface_model.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <tuple>

namespace wave {
namespace {

using detail::fmt;
using detail::json;
using detail::Node;

// An image size [width, height] (the preview's, the camera grid's), at most 10⁸ pixels, the
// product taken without wrap-around.
void read_image(const Node& n, std::size_t& width, std::size_t& height) {
    constexpr std::size_t kMaxPixels = 100'000'000;
    const auto im = n.count_pair("[width, height] in pixels");
    width = im[0];
    height = im[1];
    const std::size_t pixels = detail::mul_sat(width, height);
    if (pixels > kMaxPixels)
        n.fail(detail::format_count(pixels) + " pixels; at most " + detail::format_count(kMaxPixels));
}

void read_seafloor_spec(const Node& n, SeafloorSource& s, const std::string& base_dir) {
    n.require_object({"source", "sign", "vertical_scale", "vertical_offset", "horizontal_scale", "nodata",
                      "nodata_policy", "nodata_elevation", "swan_grid", "swan_spacing", "swan_origin", "spacing",
                      "max_nodes"});
    if (n.has("source")) {
        s.source = n["source"].string();
        const auto& names = procedural_seafloor_names();
        const bool procedural = std::find(names.begin(), names.end(), s.source) != names.end();
        const std::filesystem::path p(s.source);
        if (!procedural && p.is_relative()) s.source = (std::filesystem::path(base_dir) / p).string();
        if (!procedural && !detail::path_exists(s.source))
            n["source"].fail("no such file '" + s.source + "' and not a procedural seafloor");
    }
    ReadOptions& r = s.read;
    if (n.has("sign")) r.sign = n["sign"].choice<ValueSign>({{"elevation", ValueSign::elevation}, {"depth", ValueSign::depth}});
    if (n.has("vertical_scale")) r.vertical_scale = n["vertical_scale"].number("scale");
    if (n.has("vertical_offset")) r.vertical_offset = n["vertical_offset"].number("m");
    if (n.has("horizontal_scale")) r.horizontal_scale = n["horizontal_scale"].number("scale");
    if (n.has("nodata")) r.nodata_value = n["nodata"].number("value");
    if (n.has("nodata_policy"))
        r.nodata_policy = n["nodata_policy"].choice<NodataPolicy>({{"land", NodataPolicy::land}, {"error", NodataPolicy::error}});
    if (n.has("nodata_elevation")) r.nodata_elevation = n["nodata_elevation"].number("m");
    if (n.has("swan_grid")) {
        const auto g = n["swan_grid"].count_pair("[nx, ny]");
        r.swan_nx = g[0];
        r.swan_ny = g[1];
    }
    if (n.has("swan_spacing")) {
        const auto d = n["swan_spacing"].numbers(0, "m");
        if (d.empty() || d.size() > 2 || !(d[0] > 0.0)) n["swan_spacing"].fail("expected [dx] or [dx, dy] with dx > 0 m");
        r.swan_dx = d[0];
        r.swan_dy = d.size() > 1 ? d[1] : 0.0;
    }
    if (n.has("swan_origin")) {
        const auto d = n["swan_origin"].numbers(2, "m");
        r.swan_x0 = d[0];
        r.swan_y0 = d[1];
    }
    if (n.has("spacing")) r.resample_spacing = n["spacing"].number("m");
    if (n.has("max_nodes")) r.max_nodes = n["max_nodes"].count();
}

void read_isobaths(const Node& n, IsobathOptions& o) {
    n.require_object({"levels", "spacing", "shoreline", "smoothing"});
    if (n.has("levels")) {
        o.levels = n["levels"].numbers(0, "m");
        if (o.levels.empty()) n["levels"].fail("expected at least one depth level");
    }
    if (n.has("spacing")) o.spacing = n["spacing"].number("m");
    if (n.has("levels") && n.has("spacing")) n.fail("give either levels or spacing, not both");
    if (n.has("shoreline")) o.include_shoreline = n["shoreline"].boolean();
    if (n.has("smoothing")) {
        const Node s = n["smoothing"];
        s.require_object({"samples", "beta1", "beta2"});
        if (s.has("samples")) o.smoothing_samples = static_cast<int>(s["samples"].count());
        if (s.has("beta1")) o.smoothing_beta1 = s["beta1"].number("bias");
        if (s.has("beta2")) o.smoothing_beta2 = s["beta2"].number("tension");
    }
}

// A direction [x, y] of travel (need not be unit; not zero).
std::pair<double, double> read_direction(const Node& n) {
    const auto d = n.numbers(2, "direction");
    if (d[0] == 0.0 && d[1] == 0.0) n.fail("expected a non-zero direction [x, y]");
    return {d[0], d[1]};
}

WaveTrain read_wave(const Node& n) {
    n.require_object({"period", "amplitude", "direction"});
    WaveTrain w;
    if (n.has("period")) w.period = n["period"].number("s");
    if (n.has("amplitude")) w.amplitude = n["amplitude"].number("m");
    if (n.has("direction")) std::tie(w.direction_x, w.direction_y) = read_direction(n["direction"]);
    return w;
}

void read_trace(const Node& n, Scene& s) {
    n.require_object({"ray_spacing", "orthogonals_per_grid_line", "max_rays", "max_crossings", "breaker_index"});
    if (n.has("ray_spacing")) s.trace.ray_spacing = n["ray_spacing"].number("m");
    if (n.has("orthogonals_per_grid_line")) s.orthogonals_per_grid_line = n["orthogonals_per_grid_line"].number("rays per grid line");
    if (n.has("ray_spacing") && n.has("orthogonals_per_grid_line")) n.fail("give either ray_spacing or orthogonals_per_grid_line, not both");
    if (n.has("max_rays")) s.trace.max_rays = n["max_rays"].count();
    if (n.has("max_crossings")) s.trace.max_crossings = n["max_crossings"].count();
    if (n.has("breaker_index")) s.trace.breaker_index = n["breaker_index"].number("H/h");
}

// The export forms by name: export_forms()'s rows.
std::map<std::string, Scene::Form> form_values() {
    std::map<std::string, Scene::Form> out;
    for (const ExportFormInfo& f : export_forms()) out.emplace(std::string(f.name), f.form);
    return out;
}

// The containers by name (container_name, container_from_name).
constexpr std::array<std::pair<std::string_view, Scene::Container>, 2> kContainers{
    {{"glb", Scene::Container::glb}, {"gltf", Scene::Container::gltf}}};

template <class T, std::size_t N>
std::map<std::string, T> named_values(const std::array<std::pair<std::string_view, T>, N>& table) {
    std::map<std::string, T> out;
    for (const auto& [name, value] : table) out.emplace(std::string(name), value);
    return out;
}

template <class T, std::size_t N>
std::string_view name_of(const std::array<std::pair<std::string_view, T>, N>& table, T value) {
    for (const auto& [name, v] : table)
        if (v == value) return name;
    throw InternalError("an export setting without a name");
}

template <class T, std::size_t N>
T value_named(const std::array<std::pair<std::string_view, T>, N>& table, std::string_view name, const char* what) {
    std::string list;
    for (const auto& [n, v] : table) {
        if (n == name) return v;
        list += (list.empty() ? "" : ", ") + std::string(n);
    }
    throw InputError(std::string(what) + ": expected one of " + list + ", got " + detail::brief_json(json(std::string(name))));
}

// /surface/kind: one of the registered models' names.
SurfaceKind read_kind(const Node& n) {
    std::map<std::string, SurfaceKind> kinds;
    for (const detail::SurfaceModel* m : detail::surface_models()) kinds.emplace(std::string(m->name), m->kind);
    return n.choice(kinds);
}

// A key that is false (off) or an object (on, its settings): whether it is there and on;
// true is refused, naming what false means.
bool switched_on(const Node& n, const char* key, const char* off) {
    if (!n.has(key)) return false;
    const Node k = n[key];
    if (!k.value().is_boolean()) return true;
    if (k.value().get<bool>()) k.fail(std::string("expected false (") + off + ") or an object");
    return false;
}

void read_surface(const Node& n, Scene& s) {
    n.require_object({"kind", "grid", "samples_per_span", "footprint", "footprint_radius", "tension_per_metre",
                      "max_tension", "repeat_time", "max_vertices", "camera_grid", "water_mesh", "far_field"});
    if (switched_on(n, "far_field", "no far field")) {
        const Node f = n["far_field"];
        f.require_object({"distance", "swell_wavelengths", "breaker_wavelengths"});
        Scene::FarField o;
        if (f.has("distance")) o.distance = f["distance"].number("m");
        if (f.has("swell_wavelengths")) o.swell_wavelengths = f["swell_wavelengths"].number("");
        if (f.has("breaker_wavelengths")) o.breaker_wavelengths = f["breaker_wavelengths"].number("");
        s.far_field = o;
    } else if (n.has("far_field")) {
        s.far_field.reset();
    }
    if (switched_on(n, "water_mesh", "the strips themselves")) {
        const Node w = n["water_mesh"];
        w.require_object({"vertices_per_wavelength", "surf_zone"});
        s.water_mesh_per_wavelength = w.has("vertices_per_wavelength") ? w["vertices_per_wavelength"].number("") : *Scene{}.water_mesh_per_wavelength;
        if (w.has("surf_zone")) s.surf_zone_mesh = w["surf_zone"].number("");
    } else if (n.has("water_mesh")) {
        s.water_mesh_per_wavelength.reset();
    }
    if (n.has("camera_grid")) {
        if (!n.has("water_mesh")) s.water_mesh_per_wavelength.reset();  // the grid replaces it
        if (n.has("far_field") && s.far_field)
            n["far_field"].fail("not with /surface/camera_grid: the camera grid reaches the horizon itself");
        s.far_field.reset();
        // Hinsinger's screen-space sampling (Jeschke §5); the camera stands at /camera/position.
        const Node c = n["camera_grid"];
        c.require_object({"look_at", "vertical_fov_degrees", "image", "pixel_step", "max_distance"});
        GridCamera g;
        if (c.has("look_at")) g.look_at = c["look_at"].point3();
        if (c.has("vertical_fov_degrees")) g.vertical_fov_degrees = c["vertical_fov_degrees"].number("degrees");
        if (c.has("image")) read_image(c["image"], g.image_width, g.image_height);
        if (c.has("pixel_step")) g.pixel_step = c["pixel_step"].count();
        if (c.has("max_distance")) g.max_distance = c["max_distance"].number("m");
        s.camera_grid = g;
    }
    HeightFieldOptions& o = s.surface;
    if (n.has("grid")) {
        const Node g = n["grid"];
        if (!g.value().is_array() || g.size() != 2) g.fail("expected [m, n] control vertices");
        o.nx = g[std::size_t{0}].count();
        o.ny = g[1].count();
    }
    if (n.has("samples_per_span")) o.samples_per_span = static_cast<int>(n["samples_per_span"].count());
    if (n.has("footprint"))
        o.footprint = n["footprint"].choice<Footprint>({{"bresenham", Footprint::bresenham}, {"smooth", Footprint::smooth}});
    if (n.has("footprint_radius")) o.footprint_radius = n["footprint_radius"].number("grid cells");
    if (n.has("tension_per_metre")) o.tension_per_metre = n["tension_per_metre"].number("1/m");
    if (n.has("max_tension")) o.max_tension = n["max_tension"].number("tension");
    if (n.has("repeat_time")) o.repeat_time = n["repeat_time"].number("s");
    if (n.has("max_vertices")) o.max_vertices = n["max_vertices"].count();
}

void read_field(const Node& n, Scene& s) {
    FieldOptions& o = s.field;
    n.require_object({"nodes_per_wavelength", "min_resolved_depth", "edges", "max_nodes", "amplitudes", "amplitude_dispersion",
                      "breaking_decay", "stable_index"});
    if (n.has("amplitudes")) s.amplitudes_from_field = n["amplitudes"].choice<bool>({{"field", true}, {"rays", false}});
    if (n.has("nodes_per_wavelength")) o.nodes_per_wavelength = n["nodes_per_wavelength"].number("nodes");
    if (n.has("min_resolved_depth")) o.min_resolved_depth = n["min_resolved_depth"].number("m");
    if (n.has("edges")) o.reflecting_edges = n["edges"].choice<bool>({{"open", false}, {"walls", true}});
    if (n.has("max_nodes")) o.max_nodes = n["max_nodes"].count();
    if (n.has("amplitude_dispersion")) o.amplitude_dispersion = n["amplitude_dispersion"].boolean();
    if (n.has("breaking_decay")) o.breaking_decay = n["breaking_decay"].number("1");
    if (n.has("stable_index")) o.stable_index = n["stable_index"].number("H/h");
}

void read_fronts(const Node& n, FrontOptions& o) {
    n.require_object({"refraction", "step", "split_distance", "flat_amplitude", "max_turn_degrees", "max_steps", "max_points"});
    if (n.has("max_turn_degrees")) o.max_turn_degrees = n["max_turn_degrees"].number("degrees");
    if (n.has("refraction"))
        o.refraction = n["refraction"].choice<FrontRefraction>({{"gradient", FrontRefraction::gradient},
                                                                {"isobath", FrontRefraction::isobath}});
    if (n.has("step")) o.step = n["step"].number("m");
    if (n.has("split_distance")) o.split_distance = n["split_distance"].number("m");
    if (n.has("flat_amplitude")) o.flat_amplitude = n["flat_amplitude"].number("m");
    if (n.has("max_steps")) o.max_steps = n["max_steps"].count();
    if (n.has("max_points")) o.max_points = n["max_points"].count();
}

void read_profile(const Node& n, GonzatoProfileOptions& o) {
    n.require_object({"profile", "stretch_max", "stretch_depth_factor", "displacement_depth_factor", "limit_to_disc",
                      "max_speed_ratio", "min_packing", "k0", "kx", "kz"});
    if (n.has("profile")) n["profile"].choice<int>({{"gonzato", 0}});
    if (n.has("stretch_max")) o.stretch_max = n["stretch_max"].number("wave heights");
    if (n.has("stretch_depth_factor")) o.stretch_depth_factor = n["stretch_depth_factor"].number("1/m");
    if (n.has("displacement_depth_factor"))
        o.displacement_depth_factor = n["displacement_depth_factor"].number("1/m");
    if (n.has("limit_to_disc")) o.limit_to_disc = n["limit_to_disc"].boolean();
    if (n.has("max_speed_ratio")) o.max_speed_ratio = n["max_speed_ratio"].number("phase speeds");
    if (n.has("min_packing")) o.min_packing = n["min_packing"].number("rest spacings");
    if (n.has("k0")) o.k0 = n["k0"].number("1/m");
    if (n.has("kx")) o.kx = n["kx"].number("1/m");
    if (n.has("kz")) o.kz = n["kz"].number("1/m");
}

// "breakers": "jeschke", or {"model": "jeschke", …options}.
JeschkeBreakerOptions read_breakers(const Node& n) {
    JeschkeBreakerOptions o;
    if (n.value().is_string()) {
        n.choice<int>({{"jeschke", 0}});
        return o;
    }
    n.require_object({"model", "breaking_share", "max_breaking_wavelengths", "min_surf_zone_wavelengths",
                      "rise_wavelengths", "min_reform_wavelengths", "foam_fade_time", "foam_onset", "curl_spilling", "curl_plunging",
                      "curl_collapsing", "curl_surging", "wave_variation", "varied_waves", "variation_seed", "lip",
                      "min_packing", "frozen_speed"});
    if (n.has("model")) n["model"].choice<int>({{"jeschke", 0}});
    const auto share = [&](const char* key, double& v, const char* unit) {
        if (n.has(key)) v = n[key].number(unit);
    };
    share("breaking_share", o.breaking_share, "share of the surf zone");
    share("max_breaking_wavelengths", o.max_breaking_wavelengths, "wavelengths");
    share("min_surf_zone_wavelengths", o.min_surf_zone_wavelengths, "wavelengths");
    share("rise_wavelengths", o.rise_wavelengths, "wavelengths");
    share("min_reform_wavelengths", o.min_reform_wavelengths, "wavelengths");
    share("foam_fade_time", o.foam_fade_time, "s");
    share("foam_onset", o.foam_onset, "share of the breaking phase");
    share("curl_spilling", o.curl_spilling, "share of the paper's rotation");
    share("curl_plunging", o.curl_plunging, "share of the paper's rotation");
    share("curl_collapsing", o.curl_collapsing, "share of the paper's rotation");
    share("curl_surging", o.curl_surging, "share of the paper's rotation");
    share("wave_variation", o.wave_variation, "local wavelengths / share of the collapse zone");
    if (n.has("varied_waves")) o.varied_waves = static_cast<std::uint32_t>(n["varied_waves"].count());
    if (n.has("variation_seed")) o.variation_seed = n["variation_seed"].count();
    if (n.has("lip")) o.lip = n["lip"].choice<BreakerLip>({{"outer", BreakerLip::outer}, {"tube", BreakerLip::tube}, {"curl", BreakerLip::curl}});
    share("min_packing", o.section_bounds.min_packing, "rest spacings");
    share("frozen_speed", o.section_bounds.frozen_speed, "phase speeds");
    return o;
}

// "preview": the sunset ray caster's view, sun and bump waves.
void read_preview(const Node& n, Scene& s) {
    n.require_object({"look_at", "vertical_fov_degrees", "image", "sun", "glitter_exponent", "fresnel", "bump_waves",
                      "bump_reference", "sea_to_horizon"});
    PreviewOptions& o = s.preview;
    if (n.has("look_at")) {
        o.look_at = n["look_at"].point3();
        s.preview_look_at_set = true;
    }
    if (n.has("vertical_fov_degrees")) o.vertical_fov_degrees = n["vertical_fov_degrees"].number("degrees");
    if (n.has("image")) read_image(n["image"], o.width, o.height);
    if (n.has("sun")) {
        const Node sun = n["sun"];
        sun.require_object({"azimuth_degrees", "elevation_degrees"});
        if (sun.has("azimuth_degrees")) o.sun_azimuth_degrees = sun["azimuth_degrees"].number("degrees");
        if (sun.has("elevation_degrees")) o.sun_elevation_degrees = sun["elevation_degrees"].number("degrees");
    }
    if (n.has("glitter_exponent")) o.glitter_exponent = n["glitter_exponent"].number("exponent");
    if (n.has("fresnel")) o.fresnel = n["fresnel"].boolean();
    if (n.has("sea_to_horizon")) o.sea_to_horizon = n["sea_to_horizon"].boolean();
    if (n.has("bump_reference")) {
        const auto v = n["bump_reference"].numbers(2, "m");
        o.bump_reference = {v[0], v[1]};
    }
    if (n.has("bump_waves")) {
        const Node b = n["bump_waves"];
        if (!b.value().is_array()) b.fail("expected an array of {amplitude, direction, wavelength, phase}");
        for (std::size_t i = 0; i < b.size(); ++i) {
            const Node w = b[i];
            w.require_object({"amplitude", "direction", "wavelength", "phase"});
            BumpWave bw;
            if (w.has("amplitude")) bw.amplitude = w["amplitude"].number("tan of the tilt");
            if (w.has("direction")) std::tie(bw.direction_x, bw.direction_y) = read_direction(w["direction"]);
            if (w.has("wavelength")) bw.wavelength = w["wavelength"].number("m");
            if (w.has("phase")) bw.phase = w["phase"].number("rad");
            o.bump.push_back(bw);
        }
    }
}

// "underwater/sunbeams": true, false, or the volume's voxels and darkest light.
std::optional<SunVolumeOptions> read_sunbeams(const Node& n) {
    if (n.value().is_boolean()) return n.boolean() ? std::optional<SunVolumeOptions>(SunVolumeOptions{}) : std::nullopt;
    if (!n.value().is_object()) n.fail("expected true, false or an object {\"voxels\": [x, y, z], \"darkest\": …}, got " + n.shown());
    n.require_object({"voxels", "darkest"});
    SunVolumeOptions o;
    if (n.has("voxels")) {
        const Node v = n["voxels"];
        if (!v.value().is_array() || v.size() != 3) v.fail("expected 3 voxel counts [x, y, z]");
        o.nx = v[std::size_t{0}].count(), o.ny = v[std::size_t{1}].count(), o.nz = v[std::size_t{2}].count();
    }
    if (n.has("darkest")) o.darkest = n["darkest"].number("share of I0");
    return o;
}

// "underwater": caustics on the seafloor under each frame's surface.
UnderwaterOptions read_underwater(const Node& n) {
    n.require_object({"caustics", "water_type", "attenuation", "map_size", "full_scale", "sunbeams"});
    UnderwaterOptions o;
    if (n.has("caustics")) o.caustics = n["caustics"].boolean();
    if (n.has("water_type") && n.has("attenuation"))
        n["attenuation"].fail("give /underwater/water_type or /underwater/attenuation, not both");
    if (n.has("water_type")) {
        std::map<std::string, WaterType> waters;
        for (WaterType t : {WaterType::clear_ocean, WaterType::ocean, WaterType::coastal, WaterType::turbid_coastal, WaterType::harbour})
            waters[water_type_name(t)] = t;
        o.attenuation = water_attenuation(n["water_type"].choice(waters));
    }
    if (n.has("attenuation")) o.attenuation = n["attenuation"].number("1/m");
    if (n.has("map_size")) o.map_size = n["map_size"].count();
    if (n.has("full_scale")) o.full_scale = n["full_scale"].number("E / I0");
    if (n.has("sunbeams")) o.sunbeams = read_sunbeams(n["sunbeams"]);
    return o;
}

// "whitewater": true, false, or the particles' options (WhitewaterOptions).
std::optional<WhitewaterOptions> read_whitewater(const Node& n) {
    if (n.value().is_boolean()) return n.boolean() ? std::optional<WhitewaterOptions>(WhitewaterOptions{}) : std::nullopt;
    if (!n.value().is_object()) n.fail("expected true, false or an object of whitewater options, got " + n.shown());
    n.require_object({"spray", "foam", "bubbles", "spray_density", "foam_density", "bubble_density", "spray_life", "foam_life",
                      "bubble_life", "spray_drag", "spray_lift", "foam_push", "foam_push_time", "foam_spread", "foam_patch", "foam_lace", "foam_lace_scale", "seed", "max_points"});
    WhitewaterOptions o;
    const auto number = [&](const char* key, double& v, const char* unit) {
        if (n.has(key)) v = n[key].number(unit);
    };
    if (n.has("spray")) o.spray = n["spray"].boolean();
    if (n.has("foam")) o.foam = n["foam"].boolean();
    if (n.has("bubbles")) o.bubbles = n["bubbles"].boolean();
    number("spray_density", o.spray_density, "per m of crest per m of height");
    number("foam_density", o.foam_density, "per m of crest per m of height");
    number("bubble_density", o.bubble_density, "per m of crest per m of height");
    number("spray_life", o.spray_life, "s");
    number("foam_life", o.foam_life, "s");
    number("bubble_life", o.bubble_life, "s");
    number("spray_drag", o.spray_drag, "1/s");
    number("spray_lift", o.spray_lift, "× sqrt(g H)");
    number("foam_push", o.foam_push, "× the crest speed");
    number("foam_push_time", o.foam_push_time, "s");
    number("foam_spread", o.foam_spread, "m/√s");
    number("foam_lace", o.foam_lace, "share left bare");
    number("foam_lace_scale", o.foam_lace_scale, "m");
    if (n.has("foam_patch")) o.foam_patch = static_cast<std::uint32_t>(n["foam_patch"].count());
    if (n.has("seed")) o.seed = n["seed"].count();
    if (n.has("max_points")) o.max_points = n["max_points"].count();
    if (!o.spray && !o.foam && !o.bubbles) n.fail("every kind is off (spray, foam, bubbles): give \"whitewater\": false instead");
    return o;
}

RefineOptions read_refine(const Node& n) {
    n.require_object({"scheme", "level", "adaptive", "max_angle_degrees", "near_distance", "crest_sharpness_per_metre",
                      "max_crest_sharpness"});
    RefineOptions o;
    if (n.has("crest_sharpness_per_metre")) o.crest_sharpness_per_metre = n["crest_sharpness_per_metre"].number("1/m");
    if (n.has("max_crest_sharpness")) o.max_crest_sharpness = n["max_crest_sharpness"].number("sharpness (10: infinitely sharp)");
    if (n.has("adaptive")) o.adaptive = n["adaptive"].boolean();
    if (n.has("max_angle_degrees")) o.max_angle_degrees = n["max_angle_degrees"].number("degrees");
    if (n.has("near_distance")) o.near_distance = n["near_distance"].number("m");
    if (n.has("scheme"))
        o.scheme = n["scheme"].choice<RefineScheme>({{"loop", RefineScheme::loop}, {"catmull-clark", RefineScheme::catmull_clark}});
    if (n.has("level")) o.level = static_cast<int>(n["level"].count());
    if (o.adaptive && o.scheme != RefineScheme::loop) n["scheme"].fail("adaptive refinement tessellates triangles: use \"loop\"");
    if (o.adaptive && o.crest_sharpness_per_metre > 0.0)
        n["crest_sharpness_per_metre"].fail("crest sharpness needs uniform refinement (not adaptive)");
    return o;
}

void read_ocean(const Node& n, OceanOptions& o, const std::string& origin) {
    n.require_object({"resolution", "size", "spectrum", "wind_speed", "wind_direction", "directional_exponent",
                      "against_wind", "phillips_constant", "small_wave_cutoff", "fetch", "peak_enhancement", "depth",
                      "capillary_length", "choppiness", "repeat_time", "seed"});
    OceanSpectrum& s = o.spectrum;
    if (n.has("resolution")) o.resolution = n["resolution"].count();
    if (n.has("size")) o.size = n["size"].number("m");
    if (n.has("spectrum"))
        s.model = n["spectrum"].choice<OceanSpectrumModel>({{"phillips", OceanSpectrumModel::phillips},
                                                            {"pierson-moskowitz", OceanSpectrumModel::pierson_moskowitz},
                                                            {"jonswap", OceanSpectrumModel::jonswap},
                                                            {"tma", OceanSpectrumModel::tma}});
    if (n.has("wind_speed")) s.wind_speed = n["wind_speed"].number("m/s");
    if (n.has("wind_direction")) {
        const auto d = n["wind_direction"].numbers(2, "direction");
        if (std::hypot(d[0], d[1]) == 0.0) n["wind_direction"].fail("expected a non-zero direction [x, y]");
        s.wind_direction = {d[0], d[1]};
    }
    if (n.has("directional_exponent")) s.directional_exponent = n["directional_exponent"].number("exponent");
    if (n.has("against_wind")) s.against_wind = n["against_wind"].number("factor in [0, 1]");
    if (n.has("phillips_constant")) s.phillips_constant = n["phillips_constant"].number("A");
    if (n.has("small_wave_cutoff")) s.small_wave_cutoff = n["small_wave_cutoff"].number("m");
    if (n.has("fetch")) s.fetch = n["fetch"].number("m");
    if (n.has("peak_enhancement")) s.peak_enhancement = n["peak_enhancement"].number("γ");
    if (n.has("depth")) s.depth = n["depth"].number("m");
    if (n.has("capillary_length")) s.capillary_length = n["capillary_length"].number("m");
    if (n.has("choppiness")) o.choppiness = n["choppiness"].number("λ");
    if (n.has("repeat_time")) o.repeat_time = n["repeat_time"].number("s");
    if (n.has("seed")) o.seed = n["seed"].count();
    validate_ocean_options(o, origin + ": /ocean");
}

GerstnerSpec read_gerstner(const Node& n) {
    n.require_object({"wavelength", "amplitude", "direction", "phase"});
    GerstnerSpec g;
    if (n.has("wavelength")) g.wavelength = n["wavelength"].number("m");
    if (n.has("amplitude")) g.amplitude = n["amplitude"].number("m");
    if (n.has("direction")) std::tie(g.direction_x, g.direction_y) = read_direction(n["direction"]);
    if (n.has("phase")) g.phase = n["phase"].number("rad");
    return g;
}

}  // namespace

std::string_view form_name(Scene::Form form) { return export_form(form).name; }
Scene::Form form_from_name(std::string_view name) { return export_form_named(name); }
std::string_view container_name(Scene::Container container) { return name_of(kContainers, container); }
Scene::Container container_from_name(std::string_view name) { return value_named(kContainers, name, "container"); }

namespace detail {

void refuse_height_field_options(const Node& root, std::string_view kind_hint) {
    if (!root.has("surface") || !root["surface"].value().is_object()) return;
    const Node n = root["surface"];
    for (const auto& [key, _] : n.value().items())
        if (key != "kind" && key != "camera_grid" && key != "water_mesh" && key != "far_field")
            n[key.c_str()].fail("a height-field option; this scene's surface kind is \"" + std::string(kind_hint));
}

// The most wave trains a scene may hold (the schema's /waves maxItems).
constexpr std::size_t kMaxWaveTrains = 16;

void refuse_ray_strip_keys(const Node& root) {
    for (const char* key : {"camera_grid", "water_mesh"})
        if (root.has("surface") && root["surface"].value().is_object() && root["surface"].has(key))
            root["surface"][key].fail(std::string("only for the ray-strips surface") + (key[0] == 'c' ? " with /breakers" : ""));
    if (root.has("breakers"))
        root["breakers"].fail("only for the ray-strips surface (Jeschke's breakers move the traced fronts)");
}

}  // namespace detail

Seafloor load_seafloor(const SeafloorSource& s) {
    const auto& names = procedural_seafloor_names();
    if (!detail::path_exists(s.source) && std::find(names.begin(), names.end(), s.source) != names.end())
        return make_named_seafloor(s.source);
    return read_seafloor(s.source, s.read);
}

Scene default_scene() {
    // A showcase that runs in seconds: a 6 s swell bending into Gonzato's bay and
    // breaking along its beach (Jeschke's breakers on the water mesh, Gonzato's fronts:
    // one ray per metre, step 0.4 m, a new ray where neighbours are 1.2 m apart), wind
    // waves over it, whitewater, seen from a few metres above the water looking along
    // the beach. One crest shape and a 6 s wind-sea loop: the loop is one swell period.
    static constexpr std::string_view kDefault = R"({"name": "default: a swell breaking in Gonzato's bay, wind waves over it",
 "seafloor": {"source": "gonzato-bay"},
 "waves": [{"period": 6, "amplitude": 0.6, "direction": [0.15, 1]}],
 "trace": {"ray_spacing": 1},
 "fronts": {"step": 0.4, "split_distance": 1.2},
 "breakers": {"model": "jeschke", "breaking_share": 0.4, "foam_fade_time": 5, "varied_waves": 1},
 "ocean": {"resolution": 128, "size": 64, "spectrum": "jonswap", "wind_speed": 6, "fetch": 20000,
           "wind_direction": [0.3, 1], "small_wave_cutoff": 0.05, "choppiness": 0.7, "seed": 3, "repeat_time": 6},
 "whitewater": true,
 "camera": {"position": [72, 68, 3.5]},
 "preview": {"look_at": [30, 86, 0], "vertical_fov_degrees": 40, "sun": {"elevation_degrees": 35, "azimuth_degrees": 200}},
 "outputs": {"quantize": true},
 "animation": {"fps": 12}})";
    return parse_scene(kDefault, "the default scene", ".");
}

Scene parse_scene(std::string_view text, const std::string& origin, const std::string& base_dir) {
    const json doc = detail::parse_json_input(text, origin);
    const Node root(doc, "", origin, &detail::scene_schema_doc());
    root.require_object({"name", "seafloor", "isobaths", "waves", "trace", "surface", "fronts", "motion", "camera",
                         "shade", "outputs", "animation", "ocean", "gerstner", "breakers", "refine", "preview", "field", "underwater", "whitewater"});
    Scene s;
    if (root.has("name")) s.name = root["name"].string();
    if (root.has("surface") && root["surface"].value().is_object() && root["surface"].has("kind"))
        s.surface_kind = read_kind(root["surface"]["kind"]);
    const detail::SurfaceModel& model = detail::surface_model(s.surface_kind);
    model.read_before(root, s);
    if (root.has("surface")) read_surface(root["surface"], s);
    if (root.has("ocean")) {
        if (!s.ocean) s.ocean = OceanOptions{};
        read_ocean(root["ocean"], *s.ocean, origin);
    }
    if (root.has("gerstner")) {
        const Node g = root["gerstner"];
        if (!g.value().is_array()) g.fail("expected an array of Gerstner waves {wavelength, amplitude, direction, phase}");
        for (std::size_t i = 0; i < g.size(); ++i) s.gerstner.push_back(read_gerstner(g[i]));
    }
    if (root.has("seafloor")) read_seafloor_spec(root["seafloor"], s.seafloor, base_dir);
    if (root.has("isobaths")) {
        read_isobaths(root["isobaths"], s.isobaths);
        if (!s.isobaths.levels.empty()) s.isobaths.spacing = 0.0;  // explicit levels replace the default spacing
    }
    if (model.traced != Traced::nothing) {
        if (!root.has("waves")) root.fail("missing \"waves\": at least one wave train {period, amplitude, direction}");
        const Node waves = root["waves"];
        if (!waves.value().is_array() || waves.size() == 0) waves.fail("expected a non-empty array of wave trains");
        // Each train is traced and its fronts held in the plan: 200 trains on a wave-field
        // scene took 3.5 GB and minutes before any limit (docs/hardening.md).
        if (waves.size() > detail::kMaxWaveTrains)
            waves.fail(std::to_string(waves.size()) + " wave trains; at most " + std::to_string(detail::kMaxWaveTrains) +
                       " (each is traced and held in the plan)");
        for (std::size_t i = 0; i < waves.size(); ++i) s.waves.push_back(read_wave(waves[i]));
    }
    if (root.has("trace")) read_trace(root["trace"], s);
    if (root.has("breakers")) {
        if (root.has("motion")) root["motion"].fail("not with /breakers: the breakers replace Gonzato's profile");
        s.breakers = read_breakers(root["breakers"]);
    }
    if (s.camera_grid && !s.breakers)
        root["surface"]["camera_grid"].fail("needs /breakers (the camera grid samples Jeschke's breakers)");
    if (s.camera_grid && root["surface"].has("water_mesh") && s.water_mesh_per_wavelength)
        root["surface"]["water_mesh"].fail("not with /surface/camera_grid: choose one surface to sample the breakers on");
    if (root.has("refine")) s.refine = read_refine(root["refine"]);
    if (root.has("preview")) read_preview(root["preview"], s);
    if (root.has("underwater")) {
        s.underwater = read_underwater(root["underwater"]);
        if (s.underwater->caustics && model.traced == Traced::nothing)
            root["underwater"].fail("caustics fall on a seafloor: the " + std::string(surface_kind_name(s.surface_kind)) +
                                    " surface has none");
        if (s.underwater->caustics && !(s.preview.sun_elevation_degrees > 0.1)) {
            const Node at = root.has("preview") && root["preview"].has("sun") ? root["preview"]["sun"] : root["underwater"];
            at.fail("caustics need the sun above the horizon (/preview/sun/elevation_degrees is " +
                    fmt(s.preview.sun_elevation_degrees) + ")");
        }
    }
    if (root.has("whitewater")) {
        s.whitewater = read_whitewater(root["whitewater"]);
        if (const detail::SurfaceModel& m = detail::surface_model(s.surface_kind); s.whitewater && !m.whitewater && !s.ocean && !m.wind_sea_patch)
            root["whitewater"].fail("needs breaking water: the ray strips' breakers (Gonzato's or /breakers) or a wind sea "
                                    "(/ocean, or the ocean surface)");
    }
    if (root.has("fronts")) read_fronts(root["fronts"], s.fronts);
    if (root.has("field")) read_field(root["field"], s);
    if (root.has("motion")) read_profile(root["motion"], s.profile);
    if (root.has("camera")) {
        const Node c = root["camera"];
        c.require_object({"position"});
        if (c.has("position")) s.camera = c["position"].point3();
    }
    if (root.has("shade")) {
        const Node sh = root["shade"];
        sh.require_object({"fresnel", "foam_fade_time", "foam_fade_periods", "foam_onset", "fold_threshold", "fold_softness", "fold_window",
                           "fold_lattice_step", "whitecap_coverage"});
        if (sh.has("fold_threshold") && sh.has("whitecap_coverage"))
            sh["whitecap_coverage"].fail("give /shade/fold_threshold or /shade/whitecap_coverage, not both (the coverage sets the threshold)");
        if (sh.has("fold_threshold")) {
            s.fold_foam.threshold = sh["fold_threshold"].number("J₋");
            s.fold_threshold_set = true;
        }
        if (sh.has("whitecap_coverage")) s.whitecap_coverage = sh["whitecap_coverage"].number("share of the sea");
        if (sh.has("fold_softness")) s.fold_foam.softness = sh["fold_softness"].number("J₋");
        if (sh.has("fold_window")) s.fold_foam.window = sh["fold_window"].number("s");
        if (sh.has("fold_lattice_step")) s.fold_foam.lattice_step = sh["fold_lattice_step"].number("s");
        if (sh.has("fresnel")) s.fresnel = sh["fresnel"].choice<FresnelModel>({{"exact", FresnelModel::exact}, {"tso", FresnelModel::tso}});
        if (sh.has("foam_fade_time") && sh.has("foam_fade_periods"))
            sh["foam_fade_periods"].fail("give /shade/foam_fade_time or /shade/foam_fade_periods, not both");
        if (sh.has("foam_fade_time")) s.foam.fade_time = sh["foam_fade_time"].number("s");
        if (sh.has("foam_fade_periods")) s.foam.fade_periods = sh["foam_fade_periods"].number("wave periods");
        if (sh.has("foam_onset")) s.foam.onset = sh["foam_onset"].number("share of the breaking height");
    }
    if (root.has("outputs")) {
        const Node o = root["outputs"];
        o.require_object({"attributes", "color", "form", "codec", "draco", "container", "quantize", "seafloor", "camera", "sun", "material"});
        if (o.has("codec")) {  // docs/export.md, "Which codec"
            const std::string codec = o["codec"].choice<std::string>(
                {{"auto", "auto"}, {"none", "none"}, {"meshopt", "meshopt"}, {"draco", "draco"}, {"quantize", "quantize"}});
            s.codec_auto = codec == "auto";
            s.meshopt = codec == "meshopt";
            if (codec == "draco") s.draco = DracoOptions{};
            if (codec == "quantize") s.quantize = true;
            const bool named = o.has("draco") || o.has("quantize");
            if (named && codec != "draco" && codec != "quantize")
                o["codec"].fail("\"" + codec + "\" with /outputs/draco or /outputs/quantize: name the codec once");
        }
        if (o.has("seafloor")) s.dress_seafloor = o["seafloor"].boolean();
        if (o.has("camera")) s.dress_camera = o["camera"].boolean();
        if (o.has("sun")) s.dress_sun = o["sun"].boolean();
        if (o.has("material")) s.dress_material = o["material"].boolean();
        if (o.has("quantize")) s.quantize = o["quantize"].boolean();
        if (o.has("container")) s.container = o["container"].choice(named_values(kContainers));
        if (o.has("form")) s.form = o["form"].choice(form_values());
        if (o.has("attributes"))
            s.attributes = o["attributes"].choice<Scene::Attributes>(
                {{"none", Scene::Attributes::none}, {"uv-maps", Scene::Attributes::uv_maps}, {"named", Scene::Attributes::named}});
        if (o.has("color")) s.color = o["color"].boolean();
        if (o.has("draco")) {
            const Node d = o["draco"];
            if (d.value().is_boolean()) {
                if (d.boolean()) s.draco = DracoOptions{};
            } else {
                d.require_object({"position_bits", "normal_bits", "texcoord_bits", "color_bits", "generic_bits", "encode_speed"});
                DracoOptions dr;
                const auto bits = [&](const char* key, int& field) {
                    if (!d.has(key)) return;
                    field = static_cast<int>(d[key].count());
                };
                bits("position_bits", dr.position_bits);
                bits("normal_bits", dr.normal_bits);
                bits("texcoord_bits", dr.texcoord_bits);
                bits("color_bits", dr.color_bits);
                bits("generic_bits", dr.generic_bits);
                if (d.has("encode_speed")) dr.encode_speed = static_cast<int>(d["encode_speed"].count());
                s.draco = dr;
            }
            if (s.draco && s.quantize) d.fail("choose Draco or /outputs/quantize, not both (Draco quantises itself)");
        }
        if (s.draco || s.quantize) s.codec_auto = false;
        if (s.color && s.attributes == Scene::Attributes::none) o["color"].fail("a baked colour needs the shading: set attributes to uv-maps or named");
    }
    s.foam.breaker_index = s.trace.breaker_index;
    s.field.breaker_index = s.trace.breaker_index;
    // The wind sea's fold foam has no single period: its own 1.5 s unless a time is given.
    if (s.foam.fade_time > 0.0) s.fold_foam.fade_time = s.foam.fade_time;
    validate_fold_foam(s.fold_foam, origin + ": /shade");
    if (root.has("animation")) {
        const Node a = root["animation"];
        a.require_object({"fps", "max_frames"});
        if (a.has("fps")) s.fps = a["fps"].number("frames per second");
        if (a.has("max_frames")) s.max_frames = a["max_frames"].count();
    }
    model.read_after(root, s);
    s.document = doc.dump();
    s.base_dir = base_dir;
    return s;
}

std::string_view scene_schema() { return detail::kSceneSchema; }

Scene read_scene(const std::string& path) {
    detail::require_input_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_scene(text.str(), path, std::filesystem::path(path).parent_path().string());
}

}  // namespace wave
