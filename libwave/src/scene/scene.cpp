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

namespace wave {
namespace {

using nlohmann::json;

std::string fmt(double v) { return detail::format_number(v); }

// The schema node for a value of this JSON type: a "oneOf" (e.g. /outputs/draco: true
// or an object) resolves to the branch of the value's type.
const json* schema_branch(const json* schema, const json& v) {
    if (!schema || !schema->contains("oneOf")) return schema;
    for (const json& b : (*schema)["oneOf"]) {
        const std::string type = b.value("type", std::string());
        if ((type == "object" && v.is_object()) || (type == "boolean" && v.is_boolean()) ||
            (type == "array" && v.is_array()) || (type == "string" && v.is_string()) ||
            ((type == "number" || type == "integer") && v.is_number()) || (type.empty() && v.is_string()))
            return &b;
    }
    return schema;
}

const json& scene_schema_doc() {
    static const json doc = json::parse(detail::kSceneSchema);
    return doc;
}

// A number's range from its schema node, e.g. "(0, 3600]"; checked by Node::number and
// Node::count, the one place a scene number's range is enforced.
struct Range {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    bool lo_open = false, hi_open = false;
    bool contains(double v) const {
        return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    }
    std::string text() const {
        const auto shown = [](double v) {  // whole bounds in full (2^53 − 1, not 9.00719925474099e+15)
            return std::abs(v) < 1e17 && v == std::floor(v) ? std::to_string(static_cast<long long>(v)) : fmt(v);
        };
        return std::string(lo_open ? "(" : "[") + shown(lo) + ", " + shown(hi) + (hi_open ? ")" : "]");
    }
};

// A JSON value with its pointer and its schema node, for reading with validation.
class Node {
public:
    Node(const json& v, std::string pointer, const std::string& origin, const json* schema)
        : v_(v), ptr_(std::move(pointer)), origin_(origin), schema_(schema_branch(schema, v)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(origin_ + ": " + (ptr_.empty() ? "/" : ptr_) + ": " + what);
    }
    const std::string& pointer() const { return ptr_; }
    const json& value() const { return v_; }
    std::string shown() const { return detail::brief_json(v_); }

    void require_object(std::initializer_list<const char*> allowed) const {
        if (!v_.is_object()) fail("expected an object, got " + shown());
        const std::set<std::string> ok(allowed.begin(), allowed.end());
        for (const auto& [key, _] : v_.items())
            if (!ok.count(key)) {
                std::string list;
                for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                const std::string shown_key = key.size() > 40 ? key.substr(0, 40) + "…" : key;
                throw InputError(origin_ + ": " + ptr_ + "/" + shown_key + ": unknown key; valid keys here: " + list);
            }
    }
    bool has(const char* key) const { return v_.contains(key); }
    Node operator[](const char* key) const {
        const json* child = nullptr;
        if (schema_ && schema_->contains("properties") && (*schema_)["properties"].contains(key))
            child = &(*schema_)["properties"][key];
        return {v_.at(key), ptr_ + "/" + key, origin_, child};
    }
    Node operator[](std::size_t i) const {
        const json* child = schema_ && schema_->contains("items") ? &(*schema_)["items"] : nullptr;
        return {v_.at(i), ptr_ + "/" + std::to_string(i), origin_, child};
    }
    std::size_t size() const { return v_.size(); }

    /// A finite number in the schema's range for this key.
    double number(const char* unit) const {
        const std::string u = *unit ? std::string(" (") + unit + ")" : std::string();
        if (!v_.is_number()) fail("expected a number" + u + ", got " + shown());
        const double d = v_.get<double>();
        const Range r = range();
        if (!std::isfinite(d) || !r.contains(d)) fail("expected a number in " + r.text() + u + ", got " + shown());
        return d;
    }
    /// A whole number in the schema's range for this key.
    std::size_t count() const {
        const Range r = range();
        const bool whole = v_.is_number_unsigned() || (v_.is_number_integer() && v_.get<long long>() >= 0);
        if (!whole || !r.contains(static_cast<double>(v_.get<std::uint64_t>())))
            fail("expected a whole number in " + r.text() + ", got " + shown());
        return v_.get<std::size_t>();
    }
    bool boolean() const {
        if (!v_.is_boolean()) fail("expected true or false, got " + shown());
        return v_.get<bool>();
    }
    std::string string() const {
        if (!v_.is_string()) fail("expected a string, got " + shown());
        return v_.get<std::string>();
    }
    template <class T>
    T choice(const std::map<std::string, T>& options) const {
        const std::string s = string();
        const auto it = options.find(s);
        if (it == options.end()) {
            std::string list;
            for (const auto& [k, _] : options) list += (list.empty() ? "" : ", ") + k;
            fail("expected one of " + list + ", got " + shown());
        }
        return it->second;
    }
    /// [a, b] of whole numbers (an image size, a grid's node counts).
    std::array<std::size_t, 2> count_pair(const char* what) const {
        if (!v_.is_array() || v_.size() != 2) fail(std::string("expected ") + what + ", got " + shown());
        return {(*this)[std::size_t{0}].count(), (*this)[1].count()};
    }
    /// [x, y, z] in metres.
    std::array<double, 3> point3() const {
        const auto v = numbers(3, "m");
        return {v[0], v[1], v[2]};
    }
    std::vector<double> numbers(std::size_t exact, const char* unit) const {
        if (!v_.is_array() || (exact && v_.size() != exact))
            fail((exact ? "expected an array of " + std::to_string(exact) + " numbers" : std::string("expected an array of numbers")) +
                 ", got " + shown());
        std::vector<double> out;
        for (std::size_t i = 0; i < v_.size(); ++i) out.push_back((*this)[i].number(unit));
        return out;
    }

private:
    Range range() const {
        // Every number the parser reads has its range in the schema; a key missing there
        // is a fault of libwave's (tests/test_cli.py checks the schema bounds every number).
        if (!schema_) throw std::logic_error("scene schema: no entry for " + ptr_);
        Range r;
        const json& s = *schema_;
        if (s.contains("minimum")) r.lo = s["minimum"].get<double>();
        if (s.contains("exclusiveMinimum")) r.lo = s["exclusiveMinimum"].get<double>(), r.lo_open = true;
        if (s.contains("maximum")) r.hi = s["maximum"].get<double>();
        if (s.contains("exclusiveMaximum")) r.hi = s["exclusiveMaximum"].get<double>(), r.hi_open = true;
        return r;
    }

    const json& v_;
    std::string ptr_;
    const std::string& origin_;
    const json* schema_;
};

// An image (the preview's, the camera grid's) is limited to 10⁸ pixels, the product
// taken without wrap-around.
void image_limit(const Node& n, std::size_t width, std::size_t height) {
    constexpr std::size_t kMaxPixels = 100'000'000;
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

WaveTrain read_wave(const Node& n) {
    n.require_object({"period", "amplitude", "direction"});
    WaveTrain w;
    if (n.has("period")) w.period = n["period"].number("s");
    if (n.has("amplitude")) w.amplitude = n["amplitude"].number("m");
    if (n.has("direction")) {
        const auto d = n["direction"].numbers(2, "direction");
        if (d[0] == 0.0 && d[1] == 0.0) n["direction"].fail("expected a non-zero direction [x, y]");
        w.direction_x = d[0];
        w.direction_y = d[1];
    }
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

void read_surface(const Node& n, Scene& s) {
    n.require_object({"kind", "grid", "samples_per_span", "footprint", "footprint_radius", "tension_per_metre",
                      "max_tension", "repeat_time", "max_vertices", "camera_grid"});
    if (n.has("kind"))
        s.surface_kind = n["kind"].choice<SurfaceKind>({{"ray-strips", SurfaceKind::ray_strips},
                                                        {"height-field", SurfaceKind::height_field},
                                                        {"ocean", SurfaceKind::ocean}});
    if (n.has("camera_grid")) {
        // Hinsinger's screen-space sampling (Jeschke §5); the camera stands at /camera/position.
        const Node c = n["camera_grid"];
        if (s.surface_kind != SurfaceKind::ray_strips) c.fail("only for the ray-strips surface with /breakers");
        c.require_object({"look_at", "vertical_fov_degrees", "image", "pixel_step", "max_distance"});
        GridCamera g;
        if (c.has("look_at")) g.look_at = c["look_at"].point3();
        if (c.has("vertical_fov_degrees")) g.vertical_fov_degrees = c["vertical_fov_degrees"].number("degrees");
        if (c.has("image")) {
            const auto im = c["image"].count_pair("[width, height] in pixels");
            g.image_width = im[0];
            g.image_height = im[1];
            image_limit(c["image"], g.image_width, g.image_height);
        }
        if (c.has("pixel_step")) g.pixel_step = c["pixel_step"].count();
        if (c.has("max_distance")) g.max_distance = c["max_distance"].number("m");
        s.camera_grid = g;
    }
    if (s.surface_kind != SurfaceKind::height_field)
        for (const auto& [key, _] : n.value().items())
            if (key != "kind" && key != "camera_grid")
                n[key.c_str()].fail(std::string("a height-field option; this scene's surface kind is \"") +
                                    (s.surface_kind == SurfaceKind::ocean ? "ocean\" (set /ocean instead)" : "ray-strips\""));
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

void read_fronts(const Node& n, FrontOptions& o) {
    n.require_object({"refraction", "step", "split_distance", "flat_amplitude", "max_turn_degrees", "max_steps", "max_points"});
    if (n.has("max_turn_degrees")) o.max_turn = n["max_turn_degrees"].number("degrees") * std::numbers::pi / 180.0;
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
                      "k0", "kx", "kz"});
    if (n.has("profile")) n["profile"].choice<int>({{"gonzato", 0}});
    if (n.has("stretch_max")) o.stretch_max = n["stretch_max"].number("wave heights");
    if (n.has("stretch_depth_factor")) o.stretch_depth_factor = n["stretch_depth_factor"].number("1/m");
    if (n.has("displacement_depth_factor"))
        o.displacement_depth_factor = n["displacement_depth_factor"].number("1/m");
    if (n.has("limit_to_disc")) o.limit_to_disc = n["limit_to_disc"].boolean();
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
    n.require_object({"model", "breaking_share", "max_breaking_wavelengths", "rise_wavelengths", "foam_fade_time",
                      "foam_onset", "curl_spilling", "curl_plunging", "curl_collapsing", "curl_surging", "wave_variation",
                      "varied_waves", "variation_seed"});
    if (n.has("model")) n["model"].choice<int>({{"jeschke", 0}});
    const auto share = [&](const char* key, double& v, const char* unit) {
        if (n.has(key)) v = n[key].number(unit);
    };
    share("breaking_share", o.breaking_share, "share of the surf zone");
    share("max_breaking_wavelengths", o.max_breaking_wavelengths, "wavelengths");
    share("rise_wavelengths", o.rise_wavelengths, "wavelengths");
    share("foam_fade_time", o.foam_fade_time, "s");
    share("foam_onset", o.foam_onset, "share of the breaking phase");
    share("curl_spilling", o.curl_spilling, "share of the paper's rotation");
    share("curl_plunging", o.curl_plunging, "share of the paper's rotation");
    share("curl_collapsing", o.curl_collapsing, "share of the paper's rotation");
    share("curl_surging", o.curl_surging, "share of the paper's rotation");
    share("wave_variation", o.wave_variation, "local wavelengths / share of the collapse zone");
    if (n.has("varied_waves")) o.varied_waves = static_cast<std::uint32_t>(n["varied_waves"].count());
    if (n.has("variation_seed")) o.variation_seed = n["variation_seed"].count();
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
    if (n.has("image")) {
        const auto im = n["image"].count_pair("[width, height] in pixels");
        o.width = im[0];
        o.height = im[1];
        image_limit(n["image"], o.width, o.height);
    }
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
            if (w.has("direction")) {
                const auto d = w["direction"].numbers(2, "");
                if (d[0] == 0.0 && d[1] == 0.0) w["direction"].fail("the direction must not be zero");
                bw.direction_x = d[0];
                bw.direction_y = d[1];
            }
            if (w.has("wavelength")) bw.wavelength = w["wavelength"].number("m");
            if (w.has("phase")) bw.phase = w["phase"].number("rad");
            o.bump.push_back(bw);
        }
    }
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
    if (n.has("direction")) {
        const auto d = n["direction"].numbers(2, "direction");
        if (std::hypot(d[0], d[1]) == 0.0) n["direction"].fail("expected a non-zero direction [x, y]");
        g.direction_x = d[0];
        g.direction_y = d[1];
    }
    if (n.has("phase")) g.phase = n["phase"].number("rad");
    return g;
}

}  // namespace

Seafloor load_seafloor(const SeafloorSource& s) {
    const auto& names = procedural_seafloor_names();
    if (!detail::path_exists(s.source) && std::find(names.begin(), names.end(), s.source) != names.end())
        return make_named_seafloor(s.source);
    return read_seafloor(s.source, s.read);
}

Scene default_scene() {
    Scene s;
    s.name = "default: Gonzato's bay with a swell";
    s.surface_kind = SurfaceKind::ray_strips;
    s.seafloor.source = "gonzato-bay";
    s.waves = {{.period = 5.0, .amplitude = 0.3, .direction_x = 0.0, .direction_y = 1.0}};
    s.trace.ray_spacing = 1.0;  // Gonzato: one ray per metre, step 0.4 m, split at 1.2 m
    s.fronts.step = 0.4;
    s.fronts.split_distance = 1.2;
    return s;
}

Scene parse_scene(std::string_view text, const std::string& origin, const std::string& base_dir) {
    const json doc = detail::parse_json_input(text, origin);
    const Node root(doc, "", origin, &scene_schema_doc());
    root.require_object({"name", "seafloor", "isobaths", "waves", "trace", "surface", "fronts", "motion", "camera",
                         "shade", "outputs", "animation", "ocean", "gerstner", "breakers", "refine", "preview"});
    Scene s;
    if (root.has("name")) s.name = root["name"].string();
    if (root.has("surface")) read_surface(root["surface"], s);
    if (s.surface_kind == SurfaceKind::ocean) {
        // The open-ocean patch: no seafloor to trace over, no swell to trace.
        for (const char* key : {"seafloor", "isobaths", "waves", "trace", "fronts", "motion"})
            if (root.has(key))
                root[key].fail("not for the open-ocean patch (/surface/kind \"ocean\"): it has no seafloor and no traced "
                               "swell; superpose /gerstner waves, or use a coastal surface with /ocean");
        s.ocean = OceanOptions{};
        s.ocean->repeat_time = 20.0;  // Tessendorf's figure 5
        if (root.has("ocean")) read_ocean(root["ocean"], *s.ocean, origin);
    } else if (root.has("ocean")) {
        s.ocean = OceanOptions{};
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
    if (s.surface_kind != SurfaceKind::ocean) {
        if (!root.has("waves")) root.fail("missing \"waves\": at least one wave train {period, amplitude, direction}");
        const Node waves = root["waves"];
        if (!waves.value().is_array() || waves.size() == 0) waves.fail("expected a non-empty array of wave trains");
        for (std::size_t i = 0; i < waves.size(); ++i) s.waves.push_back(read_wave(waves[i]));
    }
    if (root.has("trace")) read_trace(root["trace"], s);
    if (s.surface_kind == SurfaceKind::ray_strips) {
        const Node waves = root["waves"];
        if (s.waves.size() != 1)
            waves.fail("the ray-strips surface traces one wave train, got " + std::to_string(s.waves.size()) +
                       " (use \"surface\": {\"kind\": \"height-field\"} to superpose trains)");
        if (root.has("trace") && root["trace"].has("orthogonals_per_grid_line"))
            root["trace"]["orthogonals_per_grid_line"].fail("only for the height-field surface");
    } else if (s.surface_kind == SurfaceKind::height_field) {
        if (root.has("fronts")) root["fronts"].fail("only for the ray-strips surface");
        if (root.has("motion")) root["motion"].fail("only for the ray-strips surface (the height field moves as Ts'o's sinusoids)");
    }
    if (root.has("breakers")) {
        if (s.surface_kind != SurfaceKind::ray_strips)
            root["breakers"].fail("only for the ray-strips surface (Jeschke's breakers move the traced fronts)");
        if (root.has("motion")) root["motion"].fail("not with /breakers: the breakers replace Gonzato's profile");
        s.breakers = read_breakers(root["breakers"]);
    }
    if (s.camera_grid && !s.breakers)
        root["surface"]["camera_grid"].fail("needs /breakers (the camera grid samples Jeschke's breakers)");
    if (root.has("refine")) s.refine = read_refine(root["refine"]);
    if (root.has("preview")) read_preview(root["preview"], s);
    if (root.has("fronts")) read_fronts(root["fronts"], s.fronts);
    if (root.has("motion")) read_profile(root["motion"], s.profile);
    if (root.has("camera")) {
        const Node c = root["camera"];
        c.require_object({"position"});
        if (c.has("position")) s.camera = c["position"].point3();
    }
    if (root.has("shade")) {
        const Node sh = root["shade"];
        sh.require_object({"fresnel", "foam_fade_time", "foam_onset", "fold_threshold", "fold_softness", "fold_window",
                           "fold_lattice_step"});
        if (sh.has("fold_threshold")) s.fold_foam.threshold = sh["fold_threshold"].number("J₋");
        if (sh.has("fold_softness")) s.fold_foam.softness = sh["fold_softness"].number("J₋");
        if (sh.has("fold_window")) s.fold_foam.window = sh["fold_window"].number("s");
        if (sh.has("fold_lattice_step")) s.fold_foam.lattice_step = sh["fold_lattice_step"].number("s");
        if (sh.has("fresnel")) s.fresnel = sh["fresnel"].choice<FresnelModel>({{"exact", FresnelModel::exact}, {"tso", FresnelModel::tso}});
        if (sh.has("foam_fade_time")) s.foam.fade_time = sh["foam_fade_time"].number("s");
        if (sh.has("foam_onset")) s.foam.onset = sh["foam_onset"].number("share of the breaking height");
    }
    if (root.has("outputs")) {
        const Node o = root["outputs"];
        o.require_object({"attributes", "color", "form", "draco", "container", "quantize"});
        if (o.has("quantize")) s.quantize = o["quantize"].boolean();
        if (o.has("container"))
            s.container = o["container"].choice<Scene::Container>({{"glb", Scene::Container::glb}, {"gltf", Scene::Container::gltf}});
        if (o.has("form"))
            s.form = o["form"].choice<Scene::Form>({{"morph", Scene::Form::morph}, {"nodes", Scene::Form::nodes}, {"files", Scene::Form::files}});
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
        if (s.color && s.attributes == Scene::Attributes::none) o["color"].fail("a baked colour needs the shading: set attributes to uv-maps or named");
    }
    s.foam.breaker_index = s.trace.breaker_index;
    s.fold_foam.fade_time = s.foam.fade_time;
    validate_fold_foam(s.fold_foam, origin + ": /shade");
    if (root.has("animation")) {
        const Node a = root["animation"];
        a.require_object({"fps", "max_frames"});
        if (a.has("fps")) s.fps = a["fps"].number("frames per second");
        if (a.has("max_frames")) s.max_frames = a["max_frames"].count();
    }
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

PreviewOptions scene_preview(const Scene& scene, const Seafloor& seafloor) {
    PreviewOptions o = scene.preview;
    o.camera = scene_camera(scene, seafloor);
    if (!scene.preview_look_at_set) {
        const ElevationGrid& g = seafloor.grid;
        o.look_at = {0.5 * (g.x0 + g.x_max()), 0.5 * (g.y0 + g.y_max()), 0.0};
    }
    return o;
}

std::array<double, 3> scene_camera(const Scene& scene, const Seafloor& seafloor) {
    const ElevationGrid& g = seafloor.grid;
    if (scene.camera) {
        const auto& c = *scene.camera;
        if (c[0] >= g.x0 && c[0] <= g.x_max() && c[1] >= g.y0 && c[1] <= g.y_max() &&
            c[2] <= -depth_at(g, c[0], c[1]))
            throw InputError("scene: /camera/position [" + fmt(c[0]) + ", " + fmt(c[1]) + ", " + fmt(c[2]) +
                             "] is inside the seafloor (its elevation there is " + fmt(-depth_at(g, c[0], c[1])) + " m)");
        return c;
    }
    const double w = g.x_max() - g.x0, h = g.y_max() - g.y0, size = std::max(w, h);
    double dx = 0.0, dy = 1.0;
    if (!scene.waves.empty()) {
        const double len = std::hypot(scene.waves[0].direction_x, scene.waves[0].direction_y);
        dx = scene.waves[0].direction_x / len;
        dy = scene.waves[0].direction_y / len;
    }
    // From the open sea towards the shore, as a viewer on a boat would see the waves arrive.
    const double cx = g.x0 + 0.5 * w, cy = g.y0 + 0.5 * h;
    return {cx - dx * 1.1 * size, cy - dy * 1.1 * size, 0.4 * size};
}

TraceOptions scene_trace_options(const Scene& scene, const Seafloor& seafloor) {
    TraceOptions trace = scene.trace;
    if (scene.orthogonals_per_grid_line > 0.0 && scene.surface.nx >= 2 && scene.surface.ny >= 2) {
        const ElevationGrid& g = seafloor.grid;
        const double cell = std::min((g.x_max() - g.x0) / static_cast<double>(scene.surface.nx - 1),
                                     (g.y_max() - g.y0) / static_cast<double>(scene.surface.ny - 1));
        trace.ray_spacing = cell / scene.orthogonals_per_grid_line;  // Ts'o §3.2.3
    }
    return trace;
}

Seafloor scene_seafloor(const Scene& scene) {
    if (scene.surface_kind != SurfaceKind::ocean) return load_seafloor(scene.seafloor);
    const OceanOptions o = scene.ocean.value_or(OceanOptions{});
    const double depth = std::isinf(o.spectrum.depth) ? 1e4 : o.spectrum.depth;
    Seafloor sea;
    sea.grid.nx = sea.grid.ny = 2;
    sea.grid.dx = sea.grid.dy = o.size;
    sea.grid.z.assign(4, -depth);
    sea.source = "open ocean: flat bottom " + fmt(depth) + " m under a " + fmt(o.size) + " m patch";
    sea.frame = "local metres";
    return sea;
}

namespace {

// The components every surface kind can carry: the FFT ocean (its loop fitted to the
// swell's), Gerstner waves, and the per-vertex rest data they are evaluated at.
// The triangles of the surface's own vertices (before any refinement).
const std::vector<std::uint32_t>& surface_triangles(const Scene& scene, const ScenePlan& p) {
    if (scene.surface_kind == SurfaceKind::ocean) return p.patch_triangles;
    if (p.camera_grid.vertex_count() > 0) return p.camera_grid.triangles;
    if (scene.surface_kind == SurfaceKind::ray_strips) return p.strips.triangles;
    return p.surface.triangles;
}

void plan_components(const Scene& scene, ScenePlan& p) {
    const bool ocean_kind = scene.surface_kind == SurfaceKind::ocean;
    if (scene.ocean || ocean_kind) {
        OceanOptions o = scene.ocean.value_or(OceanOptions{});
        if (ocean_kind) {
            if (o.repeat_time == 0.0) o.repeat_time = 20.0;
        } else {
            const double base = p.loop_period;
            if (o.repeat_time == 0.0) {
                o.repeat_time = base * std::max(1.0, std::round(20.0 / base));  // the multiple nearest 20 s
            } else {
                const double r = o.repeat_time / base;
                if (std::round(r) < 1.0 || std::abs(r - std::round(r)) > 1e-6 * r)
                    throw InputError("scene: /ocean/repeat_time " + fmt(o.repeat_time) +
                                     " s is not a whole multiple of the swell's loop (" + fmt(base) +
                                     " s), so the animation could not loop; use e.g. " +
                                     fmt(base * std::max(1.0, std::round(r))) + " s");
            }
        }
        p.ocean = plan_ocean(o);
        p.loop_period = o.repeat_time;
        if (o.spectrum.wind_speed * o.spectrum.wind_speed / kGravity < 2.0 * p.ocean.spacing())
            p.warnings.push_back("the ocean's largest waves (V²/g = " +
                                 fmt(o.spectrum.wind_speed * o.spectrum.wind_speed / kGravity) +
                                 " m) are shorter than two cells (" + fmt(p.ocean.spacing()) +
                                 " m): raise /ocean/resolution or lower /ocean/size (Tessendorf §3.4)");
    }
    if (!(p.loop_period * scene.fps >= 1.0))
        throw InputError("scene: the loop (" + fmt(p.loop_period) + " s) is shorter than one frame at " + fmt(scene.fps) +
                         " fps; " +
                         (scene.ocean ? std::string("lengthen /ocean/repeat_time")
                          : scene.surface_kind == SurfaceKind::height_field ? std::string("lengthen /surface/repeat_time or the periods in /waves")
                                                                            : std::string("lengthen /waves/0/period")) +
                         " or raise /animation/fps");

    // Rest positions and depths of the surface's vertices.
    const ElevationGrid& g = p.seafloor.grid;
    if (ocean_kind) {
        const std::size_t side = p.ocean.n + 1;
        p.patch_triangles = grid_triangles(side, side);
        for (std::size_t row = 0; row < side; ++row)
            for (std::size_t col = 0; col < side; ++col) {
                p.rest_x.push_back(p.ocean.spacing() * static_cast<double>(col));
                p.rest_y.push_back(p.ocean.spacing() * static_cast<double>(row));
            }
    } else if (scene.surface_kind == SurfaceKind::ray_strips && p.camera_grid.vertex_count() > 0) {
        p.rest_x = p.camera_grid.x;
        p.rest_y = p.camera_grid.y;
    } else if (scene.surface_kind == SurfaceKind::ray_strips) {
        p.rest_x = p.motion.x;
        p.rest_y = p.motion.y;
    } else {
        const HeightFieldPlan& sp = p.surface;
        for (std::size_t v = 0; v < sp.vertex_count(); ++v) {
            const std::size_t row = v / sp.vertex_nx, col = v % sp.vertex_nx;
            p.rest_x.push_back(g.x0 + (g.x_max() - g.x0) * static_cast<double>(col) / static_cast<double>(sp.vertex_nx - 1));
            p.rest_y.push_back(g.y0 + (g.y_max() - g.y0) * static_cast<double>(row) / static_cast<double>(sp.vertex_ny - 1));
        }
    }
    p.rest_depth.resize(p.rest_x.size());
    for (std::size_t v = 0; v < p.rest_x.size(); ++v)
        p.rest_depth[v] = static_cast<float>(std::max(0.0, depth_at(g, p.rest_x[v], p.rest_y[v])));
    if (scene.ocean && !ocean_kind) {
        // Wind waves calm down over the shelf (Kitaigorodskii's depth function at the peak).
        p.wind_sea_scale.resize(p.rest_x.size());
        for (std::size_t v = 0; v < p.rest_x.size(); ++v)
            p.wind_sea_scale[v] = static_cast<float>(wind_sea_depth_factor(p.ocean.peak_omega, p.rest_depth[v]));
    }

    for (std::size_t i = 0; i < scene.gerstner.size(); ++i) {
        const GerstnerSpec& s = scene.gerstner[i];
        const double k = 2.0 * std::numbers::pi / s.wavelength, len = std::hypot(s.direction_x, s.direction_y);
        const double depth = ocean_kind ? scene.ocean.value_or(OceanOptions{}).spectrum.depth
                                        : std::numeric_limits<double>::infinity();
        GerstnerWave w{.kx = k * s.direction_x / len, .ky = k * s.direction_y / len, .amplitude = s.amplitude,
                       .omega = quantize_frequency(dispersion_omega(k, depth), p.loop_period), .phase = s.phase};
        p.gerstner.push_back(w);
    }
    if (gerstner_steepness(p.gerstner) >= 1.0)
        p.warnings.push_back("the Gerstner waves' Σ k A = " + fmt(gerstner_steepness(p.gerstner)) +
                             " >= 1: crests may loop over themselves (Tessendorf §3.1); lower the amplitudes");
}

// The ray strips came out empty: say why, naming the seafloor and the scene key, rather
// than let the exporter find "nothing to export".
[[noreturn]] void refuse_empty_strips(const Scene& scene, const ScenePlan& p) {
    const SeafloorStats st = seafloor_stats(p.seafloor);
    const std::string where = "scene: no water surface to animate over " + p.seafloor.source + ": ";
    if (!(st.depth_max > 0.0))
        throw InputError(where + "the seafloor has no water (every node is land" +
                         (st.nodata_count > 0 ? std::string(" or NODATA read as land: /seafloor/nodata_policy") : std::string()) +
                         "); check /seafloor/sign and /seafloor/vertical_offset");
    const WaveTrain& w = scene.waves[0];
    // The seafloor's width across the swell, where its rays enter.
    const double len = std::hypot(w.direction_x, w.direction_y);
    const double across = (std::abs(w.direction_y) * (st.x_max - st.x_min) + std::abs(w.direction_x) * (st.y_max - st.y_min)) / len;
    if (across / scene.trace.ray_spacing < 2.0)
        throw InputError(where + "/trace/ray_spacing " + fmt(scene.trace.ray_spacing) + " m leaves fewer than two rays across the " +
                         fmt(across) + " m the swell enters over; a front needs two: lower /trace/ray_spacing");
    throw InputError(where + "no front formed: the swell travels towards [" + fmt(w.direction_x) + ", " +
                     fmt(w.direction_y) + "] (/waves/0/direction), so its rays start on the seafloor's upwave side, and " +
                     (p.fronts.initial_rays == 0 ? "none started in water there"
                                                 : std::to_string(p.fronts.initial_rays) + " ray(s) that started there made no strip") +
                     "; a direction points where the waves go, from the open sea towards the shore");
}

}  // namespace

ScenePlan plan_scene(const Scene& scene, PlanStages stages) {
    ScenePlan p;
    p.seafloor = scene_seafloor(scene);
    scene_camera(scene, p.seafloor);  // a camera inside the seafloor is an input error, found before the work
    if (scene.surface_kind == SurfaceKind::ocean) {
        if (stages != PlanStages::trace) plan_components(scene, p);
        if (stages == PlanStages::all) refine_scene_plan(scene, p);
        return p;
    }
    if (scene.surface_kind == SurfaceKind::ray_strips) {
        if (scene.waves.size() != 1)
            throw InputError("scene: the ray-strips surface traces one wave train, got " + std::to_string(scene.waves.size()));
        FrontOptions fronts = scene.fronts;
        fronts.ray_spacing = scene.trace.ray_spacing;
        fronts.breaker_index = scene.trace.breaker_index;
        fronts.max_rays = scene.trace.max_rays;
        p.isobaths = extract_isobaths(p.seafloor, scene.isobaths);
        p.fronts = trace_fronts(p.seafloor, scene.waves[0], fronts, &p.isobaths);
        p.strips = build_ray_strips(p.fronts);
        if (p.strips.triangle_count() == 0) refuse_empty_strips(scene, p);
        p.loop_period = scene.waves[0].period;
        if (stages != PlanStages::trace) {
            p.motion = plan_gonzato_motion(p.strips, scene.profile);
            if (scene.breakers) {
                JeschkeBreakerOptions o = *scene.breakers;
                o.breaker_index = scene.trace.breaker_index;
                const WaveTrain& w = scene.waves[0];
                p.breakers = plan_jeschke_breakers(p.strips, 2.0 * w.amplitude, deep_water_wavelength(w.period), o);
                if (scene.camera_grid) {
                    GridCamera c = *scene.camera_grid;
                    c.position = scene_camera(scene, p.seafloor);
                    p.camera_grid = camera_grid(c);
                    p.breakers = resample_jeschke_breakers(p.breakers, p.strips.triangles, p.camera_grid.x, p.camera_grid.y);
                }
                // Varied crests repeat after m of them: the loop holds m periods.
                p.loop_period *= static_cast<double>(p.breakers.loop_periods());
            }
            plan_components(scene, p);
            if (stages == PlanStages::all) refine_scene_plan(scene, p);
        }
        return p;
    }
    const TraceOptions trace = scene_trace_options(scene, p.seafloor);
    const ElevationGrid& g = p.seafloor.grid;
    if (scene.surface.nx >= 2 && scene.surface.ny >= 2) {
        const double cell = std::min((g.x_max() - g.x0) / static_cast<double>(scene.surface.nx - 1),
                                     (g.y_max() - g.y0) / static_cast<double>(scene.surface.ny - 1));
        if (scene.surface.footprint == Footprint::bresenham && trace.ray_spacing > cell)
            throw InputError("scene: the Bresenham footprint needs at least one orthogonal per grid line (Ts'o): "
                             "ray spacing " + fmt(trace.ray_spacing) + " m exceeds the grid cell " +
                             fmt(cell) + " m; lower /trace/ray_spacing, raise "
                             "/trace/orthogonals_per_grid_line, or use the smooth footprint");
        for (std::size_t n = 0; n < scene.waves.size(); ++n) {
            const double shortest = linear_wave(2.0 * std::numbers::pi / scene.waves[n].period,
                                                std::max(0.05, seafloor_stats(p.seafloor).depth_max)).wavelength;
            if (2.0 * cell > shortest)
                p.warnings.push_back("wave train " + std::to_string(n) + " (T = " + fmt(scene.waves[n].period) +
                                     " s, L <= " + fmt(shortest) + " m) is shorter than two surface cells (" +
                                     fmt(cell) + " m): it aliases on this grid");
        }
    }
    p.isobaths = extract_isobaths(p.seafloor, scene.isobaths);
    p.rays = trace_rays(p.seafloor, p.isobaths, scene.waves, trace);
    if (stages == PlanStages::trace) return p;
    p.surface = plan_height_field(p.seafloor, p.rays, scene.waves, scene.surface);
    p.loop_period = p.surface.loop_period;
    plan_components(scene, p);
    if (stages == PlanStages::all) refine_scene_plan(scene, p);
    return p;
}

std::size_t scene_loop_frames(const Scene& scene, const ScenePlan& plan) {
    const double frames = std::round(plan.loop_period * scene.fps);
    if (!(frames < 1e18)) return std::numeric_limits<std::size_t>::max();  // refused by max_frames, never cast
    return std::max<std::size_t>(1, static_cast<std::size_t>(frames));
}

void refine_scene_plan(const Scene& scene, ScenePlan& p) {
    // Subdivision: the surface's topology refined once; frames apply the stencils.
    if (scene.refine) {
        const std::vector<std::uint32_t>& coarse = surface_triangles(scene, p);
        if (!scene.refine->adaptive) {
            p.refinement = plan_refinement(p.rest_x.size(), coarse, *scene.refine, scene.max_refined_vertices);
        } else {
            // Where the surface bends: its normals at 8 times spread over the loop (the
            // crests move, so one frame would not do), and the camera for nearness.
            Scene probe = scene;
            probe.refine.reset();
            probe.attributes = Scene::Attributes::none;
            probe.color = false;
            const std::size_t loop_frames = scene_loop_frames(scene, p);
            std::vector<float> normals;
            for (std::size_t k = 0; k < 8; ++k) {
                const std::size_t f = k * loop_frames / 8;
                const SceneAnimation a = animate_scene(probe, p, 2e9, FrameRange{f, f + 1});
                normals.insert(normals.end(), a.normals.begin(), a.normals.end());
            }
            const AdaptiveCriteria criteria{normals, p.rest_x, p.rest_y, scene_camera(scene, p.seafloor)};
            p.refinement = plan_refinement(p.rest_x.size(), coarse, *scene.refine, scene.max_refined_vertices, &criteria);
        }
    }
}

EncodedFiles encode_animation(const MorphAnimationView& view, Scene::Form form, Scene::Container container, bool whole) {
    EncodedFiles files;
    char slice_name[64];
    std::snprintf(slice_name, sizeof slice_name, "animation-frames-%zu-%zu.glb", view.first_frame, view.first_frame + view.frame_count);
    const std::string animation_name = whole ? "animation.glb" : slice_name;
    if (form == Scene::Form::morph) files.emplace_back(animation_name, gltf_morph_glb(view));
    if (form == Scene::Form::nodes) files.emplace_back(animation_name, gltf_nodes_glb(view));
    if (form == Scene::Form::files)
        for (std::size_t k = 0; k < view.frame_count; ++k) {
            char name[48];
            std::snprintf(name, sizeof name, "frames/frame-%04zu.glb", view.first_frame + k);
            files.emplace_back(name, gltf_frame_glb(view, k));
        }
    if (container == Scene::Container::gltf) {
        // Each .glb becomes name.gltf + name.bin (the .bin named relative to the .gltf).
        EncodedFiles split;
        for (auto& [name, bytes] : files) {
            const std::string base = name.substr(0, name.size() - 4);  // without ".glb"
            const std::string bin = base + ".bin";
            GltfFiles g = glb_to_gltf(bytes, std::filesystem::path(bin).filename().string());
            split.emplace_back(base + ".gltf", std::move(g.json));
            split.emplace_back(bin, std::move(g.bin));
        }
        files.swap(split);
    }
    return files;
}

MorphAnimationView SceneAnimation::view() const {
    MorphAnimationView v = animation_view(*this);
    v.draco = draco;
    v.quantize = quantize;
    return v;
}

RunEstimate estimate_run(const Scene& scene, const ScenePlan& plan) {
    RunEstimate e;
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    const std::size_t coarse_triangles = surface_triangles(scene, plan).size() / 3;
    if (refined) {
        e.vertices = refined->fine_vertices;
        e.triangles = refined->triangles.size() / 3;
    } else if (scene.refine) {  // not planned yet (PlanStages::surface): predicted
        const double t = refined_triangle_estimate(coarse_triangles, *scene.refine);
        e.triangles = t < 1e18 ? static_cast<std::size_t>(t) : std::numeric_limits<std::size_t>::max();
        e.vertices = e.triangles / 2;
    } else {
        e.vertices = plan.rest_x.size();
        e.triangles = coarse_triangles;
    }
    const bool fine = scene.refine.has_value();
    e.frames = scene_loop_frames(scene, plan);
    const double n = static_cast<double>(e.vertices), frames = static_cast<double>(e.frames);
    const bool shaded = scene.attributes != Scene::Attributes::none;
    // animate_scene: positions + normals, reflect/refract/foam, colour (floats).
    const double arrays_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    e.frame_array_bytes = frames * n * arrays_per_vertex;
    // The writer: POSITION + NORMAL, TEXCOORD_0, shading (UV maps 2 × vec2, or 3 floats), COLOR_0.
    const double shading = scene.attributes == Scene::Attributes::uv_maps ? 16.0 : scene.attributes == Scene::Attributes::named ? 12.0 : 0.0;
    const double per_frame_vertex = 24.0 + shading + (scene.color ? 12.0 : 0.0);
    const double indices = 12.0 * static_cast<double>(e.triangles), uv0 = 8.0 * n;
    const double draco_frame = 4.8 * n;  // measured: default scene, 14-bit positions (see RunEstimate)
    switch (scene.form) {
        case Scene::Form::morph:
            e.output_bytes = (scene.draco ? draco_frame : n * per_frame_vertex + uv0 + indices) +
                             frames * n * per_frame_vertex * (scene.quantize ? 0.7 : 1.0);
            break;
        case Scene::Form::nodes:  // meshes share the indices and TEXCOORD_0
            e.output_bytes = scene.draco ? frames * draco_frame
                                         : indices + uv0 + frames * n * per_frame_vertex * (scene.quantize ? 0.7 : 1.0);
            break;
        case Scene::Form::files:
            e.output_bytes = frames * (scene.draco ? draco_frame : indices + uv0 + n * per_frame_vertex * (scene.quantize ? 0.7 : 1.0));
            break;
    }
    // Measured on the default scene (peak RSS of wave run, each form): ~30 MB of
    // process and libraries, ~1.5 kB per surface vertex of plan (isobaths, fronts, the
    // OpenMesh strips, motion fields), refinement stencils ~12 weights per fine vertex;
    // a single-file form holds its bytes three times at the end (tinygltf's buffer, the
    // serialised stream, the file's string), the files form one chunk of frames.
    const double plan_bytes = 30e6 + 1500.0 * static_cast<double>(plan.rest_x.size()) + (fine ? 96.0 * n : 0.0);
    if (scene.form == Scene::Form::files) {  // one chunk of frames at a time, each encoded once
        const double chunk = static_cast<double>(files_form_chunk(e));
        e.peak_memory_bytes = plan_bytes + (e.frame_array_bytes + e.output_bytes) * chunk / frames;
    } else {
        e.peak_memory_bytes = plan_bytes + e.frame_array_bytes + 3.0 * e.output_bytes;
    }
    return e;
}

void check_run_limits(const Scene& scene, const RunEstimate& e, std::size_t frames, double max_bytes) {
    if (e.frames > scene.max_frames)
        throw LimitError("scene: the loop holds " + detail::format_count(e.frames) + " frames (at " + fmt(scene.fps) +
                         " fps), more than the limit of " + detail::format_count(scene.max_frames) +
                         "; lower /animation/fps, or raise /animation/max_frames");
    const bool shaded = scene.attributes != Scene::Attributes::none;
    const double bytes_per_vertex = 24.0 + (shaded ? 12.0 : 0.0) + (scene.color ? 12.0 : 0.0);
    if (!(static_cast<double>(frames) * static_cast<double>(e.vertices) * bytes_per_vertex > max_bytes)) return;
    const bool ocean_kind = scene.surface_kind == SurfaceKind::ocean, strips = scene.surface_kind == SurfaceKind::ray_strips;
    throw LimitError("scene: the animation would hold " + detail::format_count(frames) + " frames of " +
                     detail::format_count(e.vertices) + " vertices (over " + fmt(max_bytes / 1e9) +
                     " GB of per-frame arrays); " +
                     (scene.refine ? std::string("lower /refine/level, or ") : std::string()) +
                     (ocean_kind ? "lower /ocean/resolution, /ocean/repeat_time or /animation/fps"
                      : strips   ? "raise /trace/ray_spacing or /fronts/step, or lower /animation/fps"
                                 : "lower /surface/samples_per_span, /surface/grid or /animation/fps") +
                     ", or raise the limit (wave run --max-memory-gb)");
}

std::size_t files_form_chunk(const RunEstimate& e, double max_bytes) {
    if (e.frames == 0) return 1;
    const double per_frame = e.frame_array_bytes / static_cast<double>(e.frames);
    const double by_memory = per_frame > 0.0 ? std::floor(std::min(max_bytes, 256e6) / per_frame) : static_cast<double>(e.frames);
    const std::size_t spread = std::max<std::size_t>(8, (e.frames + 63) / 64);
    const std::size_t chunk = by_memory < static_cast<double>(spread) ? static_cast<std::size_t>(std::max(1.0, by_memory)) : spread;
    return std::min(chunk, e.frames);
}

SceneAnimation animate_scene(const Scene& scene, const ScenePlan& plan, double max_bytes, FrameRange range,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
    const bool strips = scene.surface_kind == SurfaceKind::ray_strips;
    const bool ocean_kind = scene.surface_kind == SurfaceKind::ocean;
    const bool wind_sea = plan.ocean.n > 0;
    const HeightFieldPlan& sp = plan.surface;
    SceneAnimation a;
    a.fps = scene.fps;
    a.scene = scene.name;
    // The surface's own vertices (coarse), and with /refine the subdivided ones.
    const std::size_t nc = plan.rest_x.size();
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    a.vertex_count = refined ? refined->fine_vertices : nc;
    a.loop_frames = scene_loop_frames(scene, plan);
    const std::size_t end = std::min(range.end, a.loop_frames);
    if (range.first >= end)
        throw InputError("scene: the frame range " + std::to_string(range.first) + ":" +
                         (range.end == static_cast<std::size_t>(-1) ? std::string() : std::to_string(range.end)) +
                         " holds no frame of the loop's 0:" + std::to_string(a.loop_frames));
    a.first_frame = range.first;
    a.frame_count = end - range.first;
    const std::vector<std::uint32_t>& coarse_triangles = surface_triangles(scene, plan);
    a.triangles = refined ? refined->triangles : coarse_triangles;
    // Crest sharpness: creases follow the frame's heights, so each frame is refined again.
    const bool creased = refined && scene.refine->crest_sharpness_per_metre > 0.0;
    Refinement frame_refinement;
    const std::size_t n = a.vertex_count;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    check_run_limits(scene, RunEstimate{.vertices = n, .frames = a.loop_frames}, a.frame_count, max_bytes);
    a.positions.resize(3 * n * a.frame_count);
    a.normals.resize(3 * n * a.frame_count);
    a.layout = scene.attributes == Scene::Attributes::named ? ScalarLayout::custom : ScalarLayout::blender34;
    a.draco = scene.draco;
    a.quantize = scene.quantize;
    FresnelOptions fresnel;
    fresnel.camera = scene_camera(scene, plan.seafloor);
    fresnel.model = scene.fresnel;
    const ElevationGrid& g = plan.seafloor.grid;
    const double width = g.x_max() - g.x0, height = g.y_max() - g.y0;
    std::vector<float> node_depth, node_foam;  // height field: foam from its control nodes
    if (shaded && !strips && !ocean_kind) {
        node_depth.resize(sp.control_count());
        node_foam.resize(sp.control_count());
        for (std::size_t j = 0; j < sp.ny; ++j)
            for (std::size_t i = 0; i < sp.nx; ++i)
                node_depth[j * sp.nx + i] = static_cast<float>(std::max(
                    0.0, depth_at(g, sp.x0 + static_cast<double>(i) * sp.dx, sp.y0 + static_cast<double>(j) * sp.dy)));
    }
    if (shaded) {
        a.reflect.resize(n * a.frame_count);
        a.refract.resize(n * a.frame_count);
        a.foam.assign(n * a.frame_count, 0.0f);
    }
    if (scene.color) a.colors.resize(3 * n * a.frame_count);
    std::vector<float> heights(strips || ocean_kind ? 0 : sp.control_count());
    std::optional<OceanWorkspace> ocean_ws;
    std::vector<float> lattice_j, vertex_j;  // J₋ on the FFT lattice and at the vertices
    // J₋ at the vertices for past lattice times of the fold-foam fade (FoldFoamOptions),
    // kept while they are inside the window: each is computed once for a run of frames,
    // and equals what a frame computed alone would compute.
    std::map<long long, FoldSample> fold_past;
    if (wind_sea) {
        ocean_ws.emplace(plan.ocean.n);
        lattice_j.resize(plan.ocean.n * plan.ocean.n);
        vertex_j.resize(nc);
    }
    // With /refine every component is evaluated on the coarse surface, then the stencils
    // carry positions, foam and depths to the refined one; normals and Fresnel are the
    // refined mesh's own.
    std::vector<float> coarse_p(refined ? 3 * nc : 0), coarse_nr(refined ? 3 * nc : 0), coarse_foam(refined ? nc : 0);
    std::vector<float> fine_depth;
    if (refined) {
        fine_depth.resize(n);
        apply_refinement(*refined, std::span<const float>(plan.rest_depth), 1, fine_depth);
    }
    const std::span<const float> depth_at_vertices = refined ? std::span<const float>(fine_depth) : std::span<const float>(plan.rest_depth);
    const auto to_vertices = [&](std::span<float> out) {  // lattice_j → J₋ per vertex
        if (ocean_kind) {  // the patch's (N+1)² vertices repeat the first row and column
            const std::size_t N = plan.ocean.n, side = N + 1;
            for (std::size_t row = 0; row < side; ++row) {
                const float* src = &lattice_j[(row == N ? 0 : row) * N];
                std::copy(src, src + N, &out[row * side]);
                out[row * side + N] = src[0];
            }
        } else {
            sample_ocean_field(plan.ocean, lattice_j, plan.rest_x, plan.rest_y, plan.wind_sea_scale, out);
        }
    };
    const VertexFaces adjacency = vertex_faces(n, a.triangles);  // normals gathered in parallel
    a.z_min = std::numeric_limits<float>::infinity();
    a.z_max = -std::numeric_limits<float>::infinity();
    for (std::size_t f = 0; f < a.frame_count; ++f) {
        const std::span<float> p(&a.positions[3 * n * f], 3 * n), nr(&a.normals[3 * n * f], 3 * n);
        const std::span<float> pc = refined ? std::span<float>(coarse_p) : p, nrc = refined ? std::span<float>(coarse_nr) : nr;
        const double t = static_cast<double>(a.first_frame + f) / scene.fps;
        bool normals_done = false;
        if (ocean_kind) {
            const OceanFields fields = evaluate_ocean(plan.ocean, t, *ocean_ws);
            ocean_patch_frame(plan.ocean, fields, pc, nrc, vertex_j);  // exact normals from the FFT
            normals_done = plan.gerstner.empty() && !refined;
        } else {
            if (strips && scene.breakers) evaluate_jeschke_breakers(plan.breakers, t, pc);
            else if (strips) evaluate_gonzato_motion(plan.motion, t, pc);
            else evaluate_height_field(sp, t, heights, pc);
            if (wind_sea) {
                const OceanFields fields = evaluate_ocean(plan.ocean, t, *ocean_ws);
                add_ocean_samples(plan.ocean, fields, plan.rest_x, plan.rest_y, plan.wind_sea_scale, pc);
                if (shaded) {
                    ocean_jacobian_field(plan.ocean, fields, lattice_j);
                    to_vertices(vertex_j);
                }
            }
        }
        if (!plan.gerstner.empty()) add_gerstner_waves(plan.gerstner, plan.rest_x, plan.rest_y, plan.rest_depth, t, pc);
        const Refinement* fr = refined;
        if (creased) {
            const Creases c = crest_creases(pc, coarse_triangles, scene.refine->crest_sharpness_per_metre,
                                            scene.refine->max_crest_sharpness);
            frame_refinement = plan_refinement(nc, coarse_triangles, *scene.refine, scene.max_refined_vertices, nullptr, &c);
            fr = &frame_refinement;
        }
        if (refined) apply_refinement(*fr, pc, 3, p);
        if (!normals_done) vertex_normals(p, a.triangles, adjacency, nr);
        for (std::size_t v = 0; v < n; ++v) {
            a.z_min = std::min(a.z_min, p[3 * v + 2]);
            a.z_max = std::max(a.z_max, p[3 * v + 2]);
        }
        if (shaded) {
            const std::span<float> r(&a.reflect[n * f], n), tr(&a.refract[n * f], n), foam(&a.foam[n * f], n);
            const std::span<float> fc = refined ? std::span<float>(coarse_foam) : foam;
            if (refined) std::fill(fc.begin(), fc.end(), 0.0f);
            fresnel_weights(p, nr, fresnel, r, tr);
            if (strips && scene.breakers) jeschke_foam(plan.breakers, t, fc);
            else if (strips) breaking_foam(plan.strips, plan.motion, t, scene.foam, fc);
            else if (!ocean_kind) height_field_foam(sp, node_depth, t, scene.foam, node_foam, fc);
            if (wind_sea) {
                accumulate_fold_foam(vertex_j, 0.0, scene.fold_foam, fc);
                double step = 0.0;
                const auto lattice = fold_lattice(t, scene.fold_foam, plan.loop_period, step);
                for (long long j : lattice) {
                    auto it = fold_past.find(j);
                    if (it == fold_past.end()) {
                        evaluate_ocean_jacobian(plan.ocean, static_cast<double>(j) * step, *ocean_ws, lattice_j);
                        std::vector<float> past(nc);
                        to_vertices(past);
                        it = fold_past.emplace(j, fold_sample(past, scene.fold_foam)).first;
                    }
                    accumulate_fold_foam(it->second, t - static_cast<double>(j) * step, scene.fold_foam, fc);
                }
                if (!lattice.empty()) fold_past.erase(fold_past.begin(), fold_past.lower_bound(lattice.back()));
            }
            if (refined) apply_refinement(*fr, std::span<const float>(fc), 1, foam);
            if (scene.color) water_colour(r, depth_at_vertices, foam, WaterColours{}, std::span<float>(&a.colors[3 * n * f], 3 * n));
        }
        if (progress) progress(f + 1, a.frame_count);
    }
    // TEXCOORD_0: the rest position over the seafloor's rectangle (the patch for the
    // ocean: it tiles), u along +x, v down (glTF's image origin is top-left).
    std::vector<double> fine_x, fine_y;
    if (refined) {
        fine_x.resize(n);
        fine_y.resize(n);
        apply_refinement(*refined, std::span<const double>(plan.rest_x), 1, fine_x);
        apply_refinement(*refined, std::span<const double>(plan.rest_y), 1, fine_y);
    }
    const std::vector<double>& rx = refined ? fine_x : plan.rest_x;
    const std::vector<double>& ry = refined ? fine_y : plan.rest_y;
    a.texcoords.resize(2 * n);
    for (std::size_t v = 0; v < n; ++v) {
        a.texcoords[2 * v] = static_cast<float>((rx[v] - g.x0) / width);
        a.texcoords[2 * v + 1] = static_cast<float>(1.0 - (ry[v] - g.y0) / height);
    }
    return a;
}

}  // namespace wave
