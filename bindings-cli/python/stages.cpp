// `import libwave`, stage by stage: the seafloor, isobaths, fronts, the wave field, ray
// strips, the water mesh, Gonzato's motion, foam, untangling, normals, Fresnel and one
// frame's .glb — each a call into libwave's public API with NumPy in and out, so that a
// script can replace or inspect any stage and still get `wave run`'s frame bit for bit
// (examples/pipeline.py). Arrays of libwave's results are read-only views of its
// buffers; arrays passed in are converted (float64 positions in plan, float32 frames).
#include "arrays.h"

#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/field.h"
#include "libwave/isobath.h"
#include "libwave/motion.h"
#include "libwave/scene.h"
#include "libwave/shade.h"
#include "libwave/surface.h"
#include "libwave/trace.h"
#include "libwave/whitewater.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace libwave_python {
namespace {

using Shared = py::object;  // a bound libwave object, the owner of the views it returns

// One of two named values of a keyword argument: `what` is "function: key" for the
// message, which names both names and the value given.
template <class Value>
Value either(const char* what, const std::string& given, const char* first, Value first_value, const char* second,
             Value second_value) {
    if (given == first) return first_value;
    if (given == second) return second_value;
    throw wave::InputError(std::string(what) + " must be \"" + first + "\" or \"" + second + "\", got \"" + given + "\"");
}

// Reader options with the values' sign named by a keyword argument of `function`
// ("elevation" or "depth"; none: the source's own convention).
wave::ReadOptions options_with_sign(const std::string& function, const std::optional<std::string>& sign) {
    wave::ReadOptions o;
    if (sign)
        o.sign = either((function + ": sign").c_str(), *sign, "elevation", wave::ValueSign::elevation, "depth", wave::ValueSign::depth);
    return o;
}

wave::WaveTrain train(double period, double amplitude, const std::array<double, 2>& direction) {
    return {.period = period, .amplitude = amplitude, .direction_x = direction[0], .direction_y = direction[1]};
}

// A writable float32 C-order array of exactly `count` values (an in-place argument).
py::array_t<float> writable_floats(const py::object& given, std::size_t count, const char* what) {
    if (!py::isinstance<py::array>(given))
        throw libwave_python::ArgumentTypeError(std::string(what) + ": expected a writable C-contiguous float32 array, got " +
                                                std::string(py::str(py::type::of(given).attr("__name__"))));
    const py::array a = py::reinterpret_borrow<py::array>(given);
    if (!py::isinstance<py::array_t<float>>(a) || !(a.flags() & py::array::c_style) || !a.writeable())
        throw libwave_python::ArgumentTypeError(std::string(what) + ": expected a writable C-contiguous float32 array, got " +
                                                (a.writeable() ? "" : "a read-only ") + std::string(py::str(a.dtype())) +
                                                (a.flags() & py::array::c_style ? "" : " not C-contiguous"));
    if (static_cast<std::size_t>(a.size()) != count)
        throw wave::InputError(std::string(what) + ": expected " + std::to_string(count) + " values, got " + std::to_string(a.size()) +
                               " (shape " + libwave_python::shape_text(a) + ")");
    return py::array_t<float>(a);
}

std::span<float> span_of(py::array_t<float>& a) { return {a.mutable_data(), static_cast<std::size_t>(a.size())}; }

// A motion plan's positions at time t (vertices × 3 float32, z up), into `out` when given.
template <class Plan>
py::array_t<float> positions_at(const Plan& p, double t, const std::optional<Float32Out>& out,
                                void (*evaluate)(const Plan&, double, std::span<float>)) {
    py::array_t<float> a = out ? writable_floats(*out, 3 * p.vertex_count(), "evaluate out")
                               : py::array_t<float>({ssize(p.vertex_count()), py::ssize_t{3}});
    std::span<float> s = span_of(a);
    py::gil_scoped_release release;
    evaluate(p, t, s);
    return a;
}

// A member array of a bound libwave object as a read-only 1-D NumPy view.
template <class T, class V>
void def_array(py::class_<T, std::shared_ptr<T>>& cls, const char* name, std::vector<V> T::*member, const char* doc = "") {
    cls.def_property_readonly(name, [member](Shared self) {
        const auto& o = self.cast<const T&>();
        return view(o.*member, {ssize((o.*member).size())}, self);
    }, doc);
}

// Seafloor.from_grid: a seafloor from a 2-D array of elevations (docs/formats.md), every
// argument checked here and named in the message as `function: argument`.
std::shared_ptr<wave::Seafloor> seafloor_of_grid(const std::string& fn, const ArrayLike& values, const py::object& origin,
                                                 const py::object& spacing, const std::optional<std::string>& sign,
                                                 std::optional<double> nodata, const ArrayLike& mask, double vertical_offset,
                                                 const std::string& name) {
    // Shapes and types are the caller's input: InputError (a libwave.Error), not ValueError.
    const std::vector<double> z = to_vector<double>(values, 1, fn + ": values");
    const auto a = py::array::ensure(values);
    if (a.ndim() != 2)
        throw wave::InputError(fn + ": values must be a 2-D array (rows of y, columns of x), got shape " + shape_text(a));
    wave::ElevationGrid g;
    g.ny = static_cast<std::size_t>(a.shape(0)), g.nx = static_cast<std::size_t>(a.shape(1));
    const std::vector<double> at = to_vector<double>(origin, 1, fn + ": origin");
    if (at.size() != 2) throw wave::InputError(fn + ": origin must be (x0, y0), got " + std::to_string(at.size()) + " values");
    g.x0 = at[0], g.y0 = at[1];
    const std::vector<double> step = to_vector<double>(spacing, 1, fn + ": spacing");
    if (step.size() != 1 && step.size() != 2)
        throw wave::InputError(fn + ": spacing must be a number or (dx, dy), got " + std::to_string(step.size()) + " values");
    g.dx = step[0], g.dy = step.back();
    g.z = z;
    std::vector<char> missing;
    if (!mask.is_none()) {
        const auto b = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
        if (!b || b.ndim() != 2 || b.shape(0) != a.shape(0) || b.shape(1) != a.shape(1))
            throw wave::InputError(fn + ": mask must be a boolean array of the values' shape " + shape_text(a));
        missing.assign(b.data(), b.data() + b.size());
    }
    wave::ReadOptions o = options_with_sign(fn, sign);
    o.nodata_value = nodata;
    o.vertical_offset = vertical_offset;
    py::gil_scoped_release release;
    return std::make_shared<wave::Seafloor>(wave::seafloor_from_grid(g, missing, o, name.empty() ? fn : name));
}

// Seafloor.from_triangles: a seafloor from a triangle mesh's vertex and index arrays.
std::shared_ptr<wave::Seafloor> seafloor_of_triangles(const std::string& fn, const char* index_name, const ArrayLike& vertices,
                                                      const ArrayLike& indices, double spacing,
                                                      const std::optional<std::string>& sign, double vertical_offset,
                                                      const std::string& name) {
    const std::vector<double> xyz = to_vector<double>(vertices, 3, fn + ": vertices");
    const auto v = py::array::ensure(vertices);
    if (v.ndim() != 2) throw wave::InputError(fn + ": vertices must be an (n, 3) array, got shape " + shape_text(v));
    const auto t = py::array::ensure(indices);
    if (t && t.size() > 0 && t.dtype().kind() != 'i' && t.dtype().kind() != 'u')
        throw ArgumentTypeError(fn + ": " + index_name + " must be integers (vertex indices), got an array of " +
                                std::string(py::str(t.dtype())));
    const std::vector<std::int64_t> raw = to_vector<std::int64_t>(indices, 3, fn + ": " + index_name);
    if (!t || t.ndim() != 2)
        throw wave::InputError(fn + ": " + index_name + " must be a (t, 3) array of vertex indices, got shape " +
                               (t ? shape_text(t) : std::string("()")));
    const std::size_t n = xyz.size() / 3;
    std::vector<std::uint32_t> tri(raw.size());
    for (std::size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] < 0 || static_cast<std::size_t>(raw[i]) >= n)
            throw wave::InputError(fn + ": " + index_name + " row " + std::to_string(i / 3) + " names vertex " + std::to_string(raw[i]) +
                                   " of " + std::to_string(n) + " (0-based)");
        tri[i] = static_cast<std::uint32_t>(raw[i]);
    }
    if (spacing < 0.0 || !std::isfinite(spacing))
        throw wave::InputError(fn + ": spacing must be >= 0 (0: about a node per vertex), got " + std::to_string(spacing));
    wave::ReadOptions o = options_with_sign(fn, sign);
    o.resample_spacing = spacing;
    o.vertical_offset = vertical_offset;
    py::gil_scoped_release release;
    return std::make_shared<wave::Seafloor>(wave::seafloor_from_mesh(xyz, tri, o, name.empty() ? fn : name));
}

void bind_seafloor(py::module_& m) {
    py::class_<wave::Seafloor, std::shared_ptr<wave::Seafloor>>(
        m, "Seafloor", "A seafloor: an elevation grid (z up, m) and where it came from (read_seafloor, procedural_seafloor, "
                       "Seafloor.from_grid, Seafloor.from_triangles)")
        .def_static(
            "from_grid",
            [](const ArrayLike& values, const py::object& origin, const py::object& spacing, std::optional<std::string> sign,
               std::optional<double> nodata, const ArrayLike& mask, double vertical_offset, const std::string& name) {
                return seafloor_of_grid("Seafloor.from_grid", values, origin, spacing, sign, nodata, mask, vertical_offset, name);
            },
            py::arg("values"), py::arg("origin") = std::array<double, 2>{0.0, 0.0}, py::arg("spacing") = 1.0,
            py::arg("sign") = py::none(), py::arg("nodata") = py::none(), py::arg("mask") = py::none(),
            py::arg("vertical_offset") = 0.0, py::arg("name") = "",
            "A seafloor from a 2-D array of heights: row j is y = y0 + j·dy (south to north), column i is x = x0 + i·dx; "
            "node (0, 0) sits at `origin` (a node, as the grid readers place a raster's first cell centre: a raster "
            "whose values stand for cells starts half a cell in from its corner). `spacing` a number or (dx, dy) (m); "
            "`sign` 'elevation' (default, z up) or 'depth'; `nodata` a value and `mask` a boolean array marking nodes "
            "without data (filled as land); `vertical_offset` (m) added to every elevation (−level puts still water at "
            "z = level); `name` names it in messages. Raises InputError (ArgumentTypeError for what is not numbers) "
            "naming the argument")
        .def_static(
            "from_triangles",
            [](const ArrayLike& vertices, const ArrayLike& indices, double spacing, std::optional<std::string> sign,
               double vertical_offset, const std::string& name) {
                return seafloor_of_triangles("Seafloor.from_triangles", "indices", vertices, indices, spacing, sign,
                                             vertical_offset, name);
            },
            py::arg("vertices"), py::arg("indices"), py::arg("spacing") = 0.0, py::arg("sign") = py::none(),
            py::arg("vertical_offset") = 0.0, py::arg("name") = "",
            "A seafloor from a triangle mesh in world space: `vertices` (n, 3) x, y, z in metres (z up, elevation "
            "unless sign='depth'), `indices` (t, 3) 0-based vertex indices; resampled to a grid of `spacing` m (0: about "
            "a node per vertex) as a mesh file is, the triangles kept for the isobaths; nodes no triangle covers are "
            "land. `vertical_offset` (m) is added to every z (−level: still water at z = level). Raises InputError "
            "(ArgumentTypeError for what is not numbers, or indices that are not integers) naming the argument")
        .def_property_readonly("elevation", [](Shared self) {
            const auto& s = self.cast<const wave::Seafloor&>();
            return view(s.grid.z, {ssize(s.grid.ny), ssize(s.grid.nx)}, self);
        }, "(ny, nx) float64 elevation (m, z up; negative under water), row j at y0 + j·dy")
        .def_property_readonly("origin", [](const wave::Seafloor& s) { return std::make_pair(s.grid.x0, s.grid.y0); },
                               "(x0, y0) of node (0, 0) (m)")
        .def_property_readonly("spacing", [](const wave::Seafloor& s) { return std::make_pair(s.grid.dx, s.grid.dy); },
                               "(dx, dy) node spacing (m)")
        .def_readonly("source", &wave::Seafloor::source)
        .def_readonly("frame", &wave::Seafloor::frame, "the coordinate frame (e.g. a projection GDAL reprojected to)")
        .def(
            "depth_at",
            [](const wave::Seafloor& s, const ArrayLike& x, const ArrayLike& y) {
                const auto xs = to_vector<double>(x, 1, "depth_at x"), ys = to_vector<double>(y, 1, "depth_at y");
                if (xs.size() != ys.size()) throw wave::InputError("depth_at: x and y differ in length");
                py::array_t<double> out(ssize(xs.size()));
                for (std::size_t i = 0; i < xs.size(); ++i) out.mutable_data()[i] = wave::depth_at(s.grid, xs[i], ys[i]);
                return out;
            },
            py::arg("x"), py::arg("y"), "Bicubic depth h (m, positive down) at points (arrays of equal length)")
        .def("stats", [](const wave::Seafloor& s) {
            const wave::SeafloorStats st = wave::seafloor_stats(s);
            py::dict d;
            d["nx"] = st.nx, d["ny"] = st.ny, d["x_min"] = st.x_min, d["x_max"] = st.x_max, d["y_min"] = st.y_min;
            d["y_max"] = st.y_max, d["depth_min"] = st.depth_min, d["depth_max"] = st.depth_max;
            d["land_fraction"] = st.land_fraction, d["nodata_count"] = st.nodata_count;
            return d;
        }, "Extent, depth range and land fraction");

    m.def(
        "read_seafloor",
        [](const std::string& path, std::optional<std::string> sign, double vertical_scale, double vertical_offset,
           double horizontal_scale, std::optional<double> nodata) {
            wave::ReadOptions o = options_with_sign("read_seafloor", sign);
            o.vertical_scale = vertical_scale, o.vertical_offset = vertical_offset, o.horizontal_scale = horizontal_scale;
            o.nodata_value = nodata;
            py::gil_scoped_release release;
            return std::make_shared<wave::Seafloor>(wave::read_seafloor(path, o));
        },
        py::arg("path"), py::arg("sign") = py::none(), py::arg("vertical_scale") = 1.0, py::arg("vertical_offset") = 0.0,
        py::arg("horizontal_scale") = 1.0, py::arg("nodata") = py::none(),
        "Reads a seafloor file (GDAL rasters, SWAN .bot needs the scene route, meshes, contour JSON; "
        "docs/formats.md); raises InputError naming the file and what is wrong");
    m.def(
        "seafloor_from_grid",
        [](const ArrayLike& values, std::array<double, 2> origin, py::object spacing, std::optional<std::string> sign,
           std::optional<double> nodata, const ArrayLike& mask, const std::string& name) {
            // Shapes and types are the caller's input: InputError (a libwave.Error), not ValueError.
            const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
            if (!a || a.ndim() != 2)
                throw wave::InputError("seafloor_from_grid: values must be a 2-D array of numbers (rows of y, columns of x)");
            wave::ElevationGrid g;
            g.ny = static_cast<std::size_t>(a.shape(0)), g.nx = static_cast<std::size_t>(a.shape(1));
            g.x0 = origin[0], g.y0 = origin[1];
            std::array<double, 2> step{};
            try {
                step = py::isinstance<py::sequence>(spacing) ? spacing.cast<std::array<double, 2>>()
                                                             : std::array<double, 2>{spacing.cast<double>(), spacing.cast<double>()};
            } catch (const py::cast_error&) {
                throw wave::InputError("seafloor_from_grid: spacing must be a number or (dx, dy)");
            }
            g.dx = step[0], g.dy = step[1];
            g.z.assign(a.data(), a.data() + a.size());
            std::vector<char> missing;
            if (!mask.is_none()) {
                const auto b = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
                if (!b || b.ndim() != 2 || b.shape(0) != a.shape(0) || b.shape(1) != a.shape(1))
                    throw wave::InputError("seafloor_from_grid: mask must be a boolean array of the values' shape");
                missing.assign(b.data(), b.data() + b.size());
            }
            wave::ReadOptions o = options_with_sign("seafloor_from_grid", sign);
            o.nodata_value = nodata;
            py::gil_scoped_release release;
            return std::make_shared<wave::Seafloor>(wave::seafloor_from_grid(g, missing, o, name));
        },
        py::arg("values"), py::arg("origin") = std::array<double, 2>{0.0, 0.0}, py::arg("spacing") = 1.0,
        py::arg("sign") = py::none(), py::arg("nodata") = py::none(), py::arg("mask") = py::none(),
        py::arg("name") = "<numpy grid>",
        "A seafloor from a 2-D array (rows of y from `origin`'s y northwards, columns of x eastwards; node (0, 0) at "
        "`origin`, a node and not a cell corner), `spacing` a number or (dx, dy) in metres; `sign` 'elevation' "
        "(default) or 'depth'; `nodata` a value and `mask` a boolean array marking nodes without data (filled as "
        "land); validated as the file readers validate: raises InputError naming what is wrong");
    m.def(
        "seafloor_from_mesh",
        [](const ArrayLike& vertices, const ArrayLike& triangles, double spacing, std::optional<std::string> sign,
           const std::string& name) {
            const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
            const auto t = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(triangles);
            if (!v || v.ndim() != 2 || v.shape(1) != 3) throw wave::InputError("seafloor_from_mesh: vertices must be an (n, 3) array");
            if (!t || t.ndim() != 2 || t.shape(1) != 3) throw wave::InputError("seafloor_from_mesh: triangles must be a (t, 3) array of indices");
            std::vector<std::uint32_t> indices(static_cast<std::size_t>(t.size()));
            for (py::ssize_t i = 0; i < t.size(); ++i) {
                const std::int64_t k = t.data()[i];
                if (k < 0 || k >= v.shape(0))
                    throw wave::InputError("seafloor_from_mesh: triangle " + std::to_string(i / 3 + 1) + " names vertex " +
                                           std::to_string(k) + " of " + std::to_string(v.shape(0)));
                indices[static_cast<std::size_t>(i)] = static_cast<std::uint32_t>(k);
            }
            std::vector<double> xyz(v.data(), v.data() + v.size());
            wave::ReadOptions o = options_with_sign("seafloor_from_mesh", sign);
            o.resample_spacing = spacing;
            py::gil_scoped_release release;
            return std::make_shared<wave::Seafloor>(wave::seafloor_from_mesh(xyz, indices, o, name));
        },
        py::arg("vertices"), py::arg("triangles"), py::arg("spacing") = 0.0, py::arg("sign") = py::none(),
        py::arg("name") = "<numpy mesh>",
        "A seafloor from a triangle mesh's (n, 3) vertices (x, y, z in metres, z elevation unless sign='depth') and "
        "(t, 3) triangles, resampled to a grid of `spacing` (0: about a node per vertex) as mesh files are, the mesh "
        "kept for the isobaths; raises InputError naming what is wrong");
    m.def(
        "procedural_seafloor", [](const std::string& name) { return std::make_shared<wave::Seafloor>(wave::make_named_seafloor(name)); },
        py::arg("name"), "A built-in seafloor by name: gonzato-bay, gonzato-island, planar-beach, ...");
    m.def(
        "scene_seafloor",
        [](const wave::Scene& scene) {
            py::gil_scoped_release release;
            return std::make_shared<wave::Seafloor>(wave::scene_seafloor(scene));
        },
        py::arg("scene"), "The scene's seafloor, read and transformed as its /seafloor says");
}

void bind_isobaths(py::module_& m) {
    py::class_<wave::DepthContours, std::shared_ptr<wave::DepthContours>>(m, "Isobaths", "Depth-tagged polylines")
        .def("__len__", &wave::DepthContours::size)
        .def_property_readonly("depths", [](Shared self) {
            const auto& c = self.cast<const wave::DepthContours&>();
            return view(c.depth, {ssize(c.size())}, self);
        }, "depth h (m, positive down) of each polyline")
        .def_property_readonly("closed", [](Shared self) {
            const auto& c = self.cast<const wave::DepthContours&>();
            return view(c.closed, {ssize(c.size())}, self);
        })
        .def(
            "polyline",
            [](Shared self, std::size_t i) {
                const auto& c = self.cast<const wave::DepthContours&>();
                if (i >= c.size()) throw py::index_error("isobath " + std::to_string(i) + " of " + std::to_string(c.size()));
                const std::size_t a = c.offsets[i], b = c.offsets[i + 1];
                return copy(std::vector<double>(c.xy.begin() + 2 * a, c.xy.begin() + 2 * b), {ssize(b - a), 2});
            },
            py::arg("index"), "(points, 2) float64 x, y (m) of polyline `index`");
    m.def(
        "extract_isobaths",
        [](const wave::Seafloor& seafloor, double spacing, std::vector<double> levels, bool shoreline, int smoothing_samples,
           double beta1, double beta2) {
            wave::IsobathOptions o;
            o.spacing = spacing, o.levels = std::move(levels), o.include_shoreline = shoreline;
            o.smoothing_samples = smoothing_samples, o.smoothing_beta1 = beta1, o.smoothing_beta2 = beta2;
            py::gil_scoped_release release;
            return std::make_shared<wave::DepthContours>(wave::extract_isobaths(seafloor, o));
        },
        py::arg("seafloor"), py::arg("spacing") = 0.25, py::arg("levels") = std::vector<double>{},
        py::arg("shoreline") = true, py::arg("smoothing_samples") = 0, py::arg("beta1") = 1.0, py::arg("beta2") = 0.0,
        "Slices the seafloor at every multiple of `spacing` (or the given levels) with CGAL, the shoreline h = 0 "
        "included; smoothing by Ts'o's Beta2-spline when smoothing_samples > 0 (as the scene's /isobaths)");
}

void bind_fronts(py::module_& m) {
    py::class_<wave::FrontSet, std::shared_ptr<wave::FrontSet>> front_class(
        m, "Fronts", "Gonzato's adaptive wave fronts: point arrays, front f at front_offsets[f] .. front_offsets[f+1]");
    def_array(front_class, "x", &wave::FrontSet::x, "x (m) of every point");
    def_array(front_class, "y", &wave::FrontSet::y, "y (m)");
    def_array(front_class, "phase", &wave::FrontSet::phase, "the phase on entry + Σ k Δs (rad)");
    def_array(front_class, "entry_break_phase", &wave::FrontSet::entry_break_phase,
              "per ray id: the phase where its wave broke before it entered (over the apron beyond its side), NaN if it entered unbroken");
    def_array(front_class, "k", &wave::FrontSet::k, "wavenumber (rad/m)");
    def_array(front_class, "depth", &wave::FrontSet::depth, "h (m)");
    def_array(front_class, "amplitude", &wave::FrontSet::amplitude, "A (m): A∞ K_s K_r, or the field's after take_field_amplitudes");
    def_array(front_class, "ray", &wave::FrontSet::ray, "ray id of every point");
    def_array(front_class, "front_offsets", &wave::FrontSet::front_offsets);
    front_class.def_property_readonly("front_count", &wave::FrontSet::front_count)
        .def_readonly("initial_rays", &wave::FrontSet::initial_rays)
        .def_readonly("inserted_rays", &wave::FrontSet::inserted_rays)
        .def_readonly("rays_aground", &wave::FrontSet::rays_aground)
        .def_readonly("rays_trapped", &wave::FrontSet::rays_trapped);
    m.def(
        "trace_fronts",
        [](const wave::Seafloor& seafloor, double period, double amplitude, std::array<double, 2> direction,
           const wave::DepthContours* isobaths, const std::string& refraction, double ray_spacing, double step,
           double split_distance, double max_turn_degrees, double breaker_index, std::size_t max_rays) {
            wave::FrontOptions o;
            o.refraction = either("trace_fronts: refraction", refraction, "gradient", wave::FrontRefraction::gradient, "isobath",
                                  wave::FrontRefraction::isobath);
            o.ray_spacing = ray_spacing, o.step = step, o.split_distance = split_distance;
            o.max_turn_degrees = max_turn_degrees, o.breaker_index = breaker_index, o.max_rays = max_rays;
            py::gil_scoped_release release;
            return std::make_shared<wave::FrontSet>(wave::trace_fronts(seafloor, train(period, amplitude, direction), o, isobaths));
        },
        py::arg("seafloor"), py::arg("period"), py::arg("amplitude"), py::arg("direction"), py::arg("isobaths") = nullptr,
        py::arg("refraction") = "gradient", py::arg("ray_spacing") = 1.0, py::arg("step") = 0.4,
        py::arg("split_distance") = 1.2, py::arg("max_turn_degrees") = 360.0, py::arg("breaker_index") = wave::kBreakerIndex,
        py::arg("max_rays") = 1'000'000,
        "Traces one wave train (period s, deep-water amplitude m, direction of travel [x, y]) as Gonzato's adaptive "
        "fronts; the defaults are the scene keys' (/trace, /fronts)");

    py::class_<wave::RaySet, std::shared_ptr<wave::RaySet>> ray_class(
        m, "Rays", "Ts'o–Barsky's rays: points of ray r at offsets[r] .. offsets[r+1]");
    def_array(ray_class, "x", &wave::RaySet::x, "x (m) of every point");
    def_array(ray_class, "y", &wave::RaySet::y, "y (m)");
    def_array(ray_class, "phase", &wave::RaySet::phase, "Σ k Δs plus the phase on entry (rad)");
    def_array(ray_class, "depth", &wave::RaySet::depth, "depth the leg is computed with (m)");
    def_array(ray_class, "amplitude", &wave::RaySet::amplitude, "A = A∞ K_s K_r, capped at caustics (m)");
    def_array(ray_class, "offsets", &wave::RaySet::offsets);
    ray_class.def_property_readonly("ray_count", &wave::RaySet::ray_count);
    m.def(
        "trace_rays",
        [](const wave::Seafloor& seafloor, const wave::DepthContours& isobaths, double period, double amplitude,
           std::array<double, 2> direction, double ray_spacing, double breaker_index, std::size_t max_rays) {
            wave::TraceOptions o;
            o.ray_spacing = ray_spacing, o.breaker_index = breaker_index, o.max_rays = max_rays;
            const std::vector<wave::WaveTrain> trains{train(period, amplitude, direction)};
            py::gil_scoped_release release;
            return std::make_shared<wave::RaySet>(wave::trace_rays(seafloor, isobaths, trains, o));
        },
        py::arg("seafloor"), py::arg("isobaths"), py::arg("period"), py::arg("amplitude"), py::arg("direction"),
        py::arg("ray_spacing") = 1.0, py::arg("breaker_index") = wave::kBreakerIndex, py::arg("max_rays") = 1'000'000,
        "Ts'o–Barsky's rays of one train over the isobaths (exact crossings, Snell at each; the height field's tracing)");

    py::class_<wave::WaveField, std::shared_ptr<wave::WaveField>>(
        m, "WaveField", "The refraction–diffraction field of one train (docs/wave-field.md)");
    m.def(
        "solve_wave_field",
        [](const wave::Seafloor& seafloor, double period, double amplitude, std::array<double, 2> direction,
           double nodes_per_wavelength, double breaker_index, bool reflecting_edges, bool amplitude_dispersion,
           double breaking_decay, double stable_index) {
            wave::FieldOptions o;
            o.nodes_per_wavelength = nodes_per_wavelength, o.breaker_index = breaker_index, o.reflecting_edges = reflecting_edges;
            o.amplitude_dispersion = amplitude_dispersion, o.breaking_decay = breaking_decay, o.stable_index = stable_index;
            py::gil_scoped_release release;
            return std::make_shared<wave::WaveField>(wave::solve_wave_field(seafloor, train(period, amplitude, direction), o));
        },
        py::arg("seafloor"), py::arg("period"), py::arg("amplitude"), py::arg("direction"),
        py::arg("nodes_per_wavelength") = 12.0, py::arg("breaker_index") = wave::kBreakerIndex,
        py::arg("reflecting_edges") = false, py::arg("amplitude_dispersion") = wave::FieldOptions{}.amplitude_dispersion,
        py::arg("breaking_decay") = wave::FieldOptions{}.breaking_decay, py::arg("stable_index") = wave::FieldOptions{}.stable_index,
        "Solves the parabolic mild-slope field of one train (as the scene's /field): amplitude dispersion and breaking "
        "dissipation (Dally, Dean & Dalrymple) on by default");
    m.def(
        "take_field_amplitudes",
        [](const wave::WaveField& field, wave::FrontSet& fronts) { return wave::take_field_amplitudes(field, fronts); },
        py::arg("field"), py::arg("fronts"),
        "Gives the fronts' points the field's amplitudes (in place; rays keep direction and phase): what scenes do by "
        "default (/field/amplitudes \"field\"). Returns the points changed");
}

void bind_surfaces(py::module_& m) {
    py::class_<wave::RayStrips, std::shared_ptr<wave::RayStrips>> strip_class(
        m, "RayStrips", "Triangles between consecutive fronts, one vertex per ray per front, with the rays' fields");
    def_array(strip_class, "x", &wave::RayStrips::x);
    def_array(strip_class, "y", &wave::RayStrips::y);
    def_array(strip_class, "phase", &wave::RayStrips::phase);
    def_array(strip_class, "k", &wave::RayStrips::k);
    def_array(strip_class, "amplitude", &wave::RayStrips::amplitude);
    def_array(strip_class, "depth", &wave::RayStrips::depth);
    def_array(strip_class, "dir_x", &wave::RayStrips::dir_x, "unit direction of travel, x");
    def_array(strip_class, "dir_y", &wave::RayStrips::dir_y, "unit direction of travel, y");
    def_array(strip_class, "caustic", &wave::RayStrips::caustic, "1 where rays crossed");
    strip_class.def_property_readonly("triangles", [](Shared self) {
              const auto& s = self.cast<const wave::RayStrips&>();
              return view(s.triangles, {ssize(s.triangle_count()), 3}, self);
          }, "(triangles, 3) uint32, counter-clockwise seen from above")
        .def_property_readonly("vertex_count", &wave::RayStrips::vertex_count)
        .def("write_ply", [](const wave::RayStrips& s, const std::string& path) { wave::write_ray_strips_ply(s, path); },
             py::arg("path"), "The strips as `wave run`'s strips.ply (OpenMesh, binary PLY with the rays' fields)");
    m.def("build_ray_strips", [](const wave::FrontSet& f) {
        py::gil_scoped_release release;
        return std::make_shared<wave::RayStrips>(wave::build_ray_strips(f));
    }, py::arg("fronts"), "Tessellates the fronts into ray strips (Gonzato fig. 11)");

    py::class_<wave::WaterMesh, std::shared_ptr<wave::WaterMesh>> mesh_class(
        m, "WaterMesh", "The graded triangulation of the water, bounded by the domain's sides and the shoreline");
    def_array(mesh_class, "x", &wave::WaterMesh::x, "vertices (m)");
    def_array(mesh_class, "y", &wave::WaterMesh::y);
    def_array(mesh_class, "boundary", &wave::WaterMesh::boundary, "1 on the domain's sides or the shoreline");
    mesh_class
        .def_property_readonly("triangles", [](Shared self) {
            const auto& w = self.cast<const wave::WaterMesh&>();
            return view(w.triangles, {ssize(w.triangles.size() / 3), 3}, self);
        })
        .def_property_readonly("vertex_count", &wave::WaterMesh::vertex_count);
    m.def(
        "mesh_water",
        [](const wave::Seafloor& seafloor, double period, double amplitude, double per_wavelength, double breaker_index,
           double min_angle_deg, std::size_t max_vertices, bool inland_water) {
            wave::WaterMeshOptions o;
            o.min_angle_deg = min_angle_deg, o.max_vertices = max_vertices, o.inland_water = inland_water;
            const wave::EdgeSize size = wave::wavelength_edge_size(seafloor, train(period, amplitude, {0.0, 1.0}),
                                                                   per_wavelength, breaker_index);
            py::gil_scoped_release release;
            return std::make_shared<wave::WaterMesh>(wave::mesh_water(seafloor, size, o));
        },
        py::arg("seafloor"), py::arg("period"), py::arg("amplitude"), py::arg("per_wavelength") = 16.0,
        py::arg("breaker_index") = wave::kBreakerIndex, py::arg("min_angle_deg") = 20.0,
        py::arg("max_vertices") = 20'000'000, py::arg("inland_water") = false,
        "The water mesh sized by the train's local wavelength (per_wavelength vertices per wavelength, the depth no "
        "shallower than where it breaks): the scenes' /surface/water_mesh; inland_water keeps the hollows below still "
        "water that no water joins to the domain's sides (left out by default)");
    m.def(
        "resample_ray_strips",
        [](const wave::RayStrips& strips, const wave::Seafloor& seafloor, const wave::WaterMesh& mesh) {
            py::gil_scoped_release release;
            return std::make_shared<wave::RayStrips>(
                wave::resample_ray_strips(strips, seafloor, mesh.x, mesh.y, mesh.triangles));
        },
        py::arg("strips"), py::arg("seafloor"), py::arg("mesh"),
        "The strips' fields at the water mesh's vertices (its triangles): the surface Gonzato's motion moves");
    m.def(
        "fill_strip_gaps",
        [](const wave::WaveField& field, const wave::Seafloor& seafloor, wave::RayStrips& strips) {
            py::gil_scoped_release release;
            return wave::fill_strip_gaps(field, seafloor, strips);
        },
        py::arg("field"), py::arg("seafloor"), py::arg("strips"),
        "Gives resampled strips' vertices no strip covers the field's wave (in place; phase matched to the rays'): what "
        "scenes do on the water mesh when the field gives the heights. Returns the vertices filled");
}

void bind_far_field(py::module_& m) {
    py::class_<wave::SeaSkirt, std::shared_ptr<wave::SeaSkirt>> skirt_class(
        m, "SeaSkirt", "The sea beyond the domain: triangles from the surface's border out to a far rectangle (plan_sea_skirt)");
    def_array(skirt_class, "x", &wave::SeaSkirt::x, "new vertices (m), after the surface's own");
    def_array(skirt_class, "y", &wave::SeaSkirt::y);
    def_array(skirt_class, "distance", &wave::SeaSkirt::distance, "per new vertex: to the domain's rectangle (m)");
    skirt_class
        .def_property_readonly("triangles", [](Shared self) {
            const auto& k = self.cast<const wave::SeaSkirt&>();
            return view(k.triangles, {ssize(k.triangles.size() / 3), 3}, self);
        }, "(triangles, 3) uint32 into the surface's vertices then the skirt's")
        .def_property_readonly("vertex_count", &wave::SeaSkirt::vertex_count)
        .def_readonly("surface_vertices", &wave::SeaSkirt::surface_vertices)
        .def_readonly("reach", &wave::SeaSkirt::reach);
    m.def(
        "plan_sea_skirt",
        [](const wave::Seafloor& seafloor, const ArrayLike& x, const ArrayLike& y, const ArrayLike& triangles, double period,
           double distance, double swell_wavelengths, std::size_t max_vertices, double min_depth) {
            const auto xs = to_vector<double>(x, 1, "plan_sea_skirt x"), ys = to_vector<double>(y, 1, "plan_sea_skirt y");
            const auto t = to_vector<std::uint32_t>(triangles, 3, "plan_sea_skirt triangles");
            wave::SeaSkirtOptions o;
            o.distance = distance, o.max_vertices = max_vertices;
            o.size = wave::swell_skirt_size(seafloor, period, swell_wavelengths, min_depth);
            o.seafloor = &seafloor.grid;
            py::gil_scoped_release release;
            return std::make_shared<wave::SeaSkirt>(wave::plan_sea_skirt(xs, ys, t, o));
        },
        py::arg("seafloor"), py::arg("x"), py::arg("y"), py::arg("triangles"), py::arg("period"), py::arg("distance"),
        py::arg("swell_wavelengths") = 2.0, py::arg("max_vertices") = 20'000'000, py::arg("min_depth") = 1e-3,
        "The skirt of a surface (rest x, y, triangles) sized for the shortest train's period out to `distance` m, the "
        "depth taken no shallower than `min_depth` m (the scenes: the breaking depth), and no sea carried on beyond a "
        "straight shore that is a whole side of the surface's rectangle: the scenes' /surface/far_field");
    m.def("far_field_sample_times", &wave::far_field_sample_times, py::arg("loop_period"), py::arg("components"),
          "The times (s) at which the scenes sample a surface for plan_far_field");

    py::class_<wave::FarFieldPlan, std::shared_ptr<wave::FarFieldPlan>>(
        m, "FarField", "The skirt's motion: the border's periodic components carried out (plan_far_field)")
        .def_property_readonly("vertex_count", &wave::FarFieldPlan::vertex_count)
        .def_readonly("surface_vertices", &wave::FarFieldPlan::surface_vertices)
        .def(
            "evaluate",
            [](const wave::FarFieldPlan& p, double t, Float32Out positions) {
                py::array_t<float> a = writable_floats(positions, 3 * (p.surface_vertices + p.vertex_count()), "far field positions");
                std::span<float> s = span_of(a);
                std::vector<float> scratch;
                py::gil_scoped_release release;
                wave::evaluate_far_field(p, t, s, scratch);
            },
            py::arg("t"), py::arg("positions"),
            "Moves the skirt at time t (s) in place: positions is a writable (surface + skirt vertices, 3) float32 "
            "array whose first rows hold the surface already moved")
        .def(
            "foam",
            [](const wave::FarFieldPlan& p, Float32Out foam) {
                py::array_t<float> a = writable_floats(foam, p.surface_vertices + p.vertex_count(), "far field foam");
                std::span<float> s = span_of(a);
                py::gil_scoped_release release;
                wave::far_field_foam(p, s);
            },
            py::arg("foam"),
            "The skirt's foam in place: foam is a writable (surface + skirt vertices) float32 array whose first values "
            "hold the surface's foam; each skirt vertex takes its anchors' foam with their residual motion");
    m.def(
        "plan_far_field",
        [](const wave::SeaSkirt& skirt, const wave::Seafloor& seafloor, const std::vector<py::tuple>& waves,
           const ArrayLike& rest_x, const ArrayLike& rest_y, const ArrayLike& times, const ArrayLike& samples) {
            std::vector<wave::FarFieldWave> w;
            for (std::size_t i = 0; i < waves.size(); ++i) {
                const py::tuple& c = waves[i];
                const std::string what = "plan_far_field waves[" + std::to_string(i) + "]";
                if (c.size() != 4) throw wave::InputError(what + ": expected an (omega, harmonic, (dx, dy), k) tuple, got " + std::to_string(c.size()) + " items");
                try {
                    const auto d = c[2].cast<std::array<double, 2>>();
                    w.push_back({.omega = c[0].cast<double>(), .harmonic = c[1].cast<int>(), .direction_x = d[0],
                                 .direction_y = d[1], .k = c[3].cast<double>()});
                } catch (const py::cast_error&) {
                    throw libwave_python::ArgumentTypeError(what + ": expected numbers (omega, harmonic, (dx, dy), k)");
                }
            }
            const auto xs = to_vector<double>(rest_x, 1, "plan_far_field rest_x"), ys = to_vector<double>(rest_y, 1, "plan_far_field rest_y");
            const auto ts = to_vector<double>(times, 1, "plan_far_field times");
            const auto ps = to_vector<float>(samples, 1, "plan_far_field samples");
            py::gil_scoped_release release;
            return std::make_shared<wave::FarFieldPlan>(wave::plan_far_field(skirt, seafloor.grid, w, xs, ys, ts, ps));
        },
        py::arg("skirt"), py::arg("seafloor"), py::arg("waves"), py::arg("rest_x"), py::arg("rest_y"), py::arg("times"),
        py::arg("samples"),
        "Fits the surface's border motion (samples: the surface at `times`, (times, vertices, 3) float32) by the "
        "components `waves` — (omega, harmonic, (dx, dy), k or 0 for the dispersion relation) — and carries them out "
        "over the skirt");
}

void bind_motion(py::module_& m) {
    py::class_<wave::GonzatoMotionPlan, std::shared_ptr<wave::GonzatoMotionPlan>>(
        m, "GonzatoMotion", "Gonzato's plunging profile planned for every vertex (plan_gonzato_motion)")
        .def_property_readonly("vertex_count", &wave::GonzatoMotionPlan::vertex_count)
        .def(
            "evaluate",
            [](const wave::GonzatoMotionPlan& p, double t, std::optional<Float32Out> out) {
                return positions_at(p, t, out, &wave::evaluate_gonzato_motion);
            },
            py::arg("t"), py::arg("out") = py::none(),
            "Positions at time t (s): (vertices, 3) float32, z up; into `out` when given (no allocation)");
    m.def(
        "plan_gonzato_motion", [](const wave::RayStrips& s) { return std::make_shared<wave::GonzatoMotionPlan>(wave::plan_gonzato_motion(s)); },
        py::arg("strips"), "Gonzato's profile for every vertex of the strips (or of the water mesh's resampled strips)");
    m.def(
        "breaking_foam",
        [](const wave::RayStrips& strips, const wave::GonzatoMotionPlan& motion, double t, double breaker_index,
           double onset, double fade_periods, double fade_time) {
            wave::FoamOptions o;
            o.breaker_index = breaker_index, o.onset = onset, o.fade_periods = fade_periods, o.fade_time = fade_time;
            py::array_t<float> out(ssize(strips.vertex_count()));
            std::span<float> s = span_of(out);
            py::gil_scoped_release release;
            wave::breaking_foam(strips, motion, t, o, s);
            return out;
        },
        py::arg("strips"), py::arg("motion"), py::arg("t"), py::arg("breaker_index") = wave::kBreakerIndex,
        py::arg("onset") = 0.9, py::arg("fade_periods") = 0.3, py::arg("fade_time") = 0.0,
        "Depth-limited breaking foam in [0, 1] per vertex at time t (docs/shade.md): it fades over fade_periods "
        "of the wave's period, or fade_time s when > 0");

    py::class_<wave::WaterlinePlan, std::shared_ptr<wave::WaterlinePlan>>(
        m, "Waterline", "Where the moved water meets the beach on a water mesh (plan_waterline)")
        .def_property_readonly("vertex_count", [](const wave::WaterlinePlan& p) { return p.depth.size(); })
        .def(
            "apply",
            [](const wave::WaterlinePlan& p, Float32Out positions) {
                py::array_t<float> a = writable_floats(positions, 3 * p.depth.size(), "waterline positions");
                wave::keep_waterline(p, span_of(a));
            },
            py::arg("positions"),
            "In place on one frame's moved positions (writable (vertices, 3) float32, the mesh's vertices first): "
            "troughs leave a film of water over the sand, the shoreline stands under it (docs/inspect.md)");
    m.def(
        "plan_waterline",
        [](const wave::WaterMesh& mesh, const wave::Seafloor& seafloor, double amplitude) {
            return std::make_shared<wave::WaterlinePlan>(wave::plan_waterline(mesh, seafloor, amplitude));
        },
        py::arg("mesh"), py::arg("seafloor"), py::arg("amplitude"),
        "Plans the waterline of a water mesh for a train of this amplitude (m), as the scenes' ray strips do");

    py::class_<wave::UntanglePlan, std::shared_ptr<wave::UntanglePlan>>(
        m, "Untangle", "The rest triangles a frame is untangled against (plan_untangle)")
        .def_property_readonly("vertex_count", &wave::UntanglePlan::vertex_count)
        .def(
            "apply",
            [](const wave::UntanglePlan& p, Float32Out positions, std::optional<ArrayLike> foam) {
                py::array_t<float> a = writable_floats(positions, 3 * p.vertex_count(), "untangle positions");
                const std::vector<float> f = foam ? to_vector<float>(*foam, 1, "untangle foam") : std::vector<float>{};
                std::span<float> s = span_of(a);
                py::gil_scoped_release release;
                return wave::untangle_motion(p, f, s).damped_vertices;
            },
            py::arg("positions"), py::arg("foam") = py::none(),
            "Untangles one frame in place (positions: writable (vertices, 3) float32); planned with lips_overturn, "
            "triangles with a vertex whose foam is >= 0.1 are breaking lips left to overturn, and foam from 0.1 to 1 "
            "frees a vertex of the ramp's damping (docs/inspect.md, untangling). Returns how many vertices were damped");
    m.def(
        "plan_untangle",
        [](const ArrayLike& x, const ArrayLike& y, const ArrayLike& triangles, bool pin_border, bool hold_shore,
           bool lips_overturn, double min_angle_degrees, std::optional<std::array<double, 4>> border_rectangle) {
            const auto xs = to_vector<double>(x, 1, "plan_untangle x"), ys = to_vector<double>(y, 1, "plan_untangle y");
            const auto t = to_vector<std::uint32_t>(triangles, 3, "plan_untangle triangles");
            wave::UntangleOptions o{.lips_overturn = lips_overturn, .pin_border = pin_border, .hold_shore = hold_shore,
                                    .min_angle_degrees = min_angle_degrees};
            if (border_rectangle) o.border_rectangle = *border_rectangle;
            return std::make_shared<wave::UntanglePlan>(wave::plan_untangle(xs, ys, t, o));
        },
        py::arg("x"), py::arg("y"), py::arg("triangles"), py::arg("pin_border") = true, py::arg("hold_shore") = true,
        py::arg("lips_overturn") = true, py::arg("min_angle_degrees") = wave::UntangleOptions{}.min_angle_degrees,
        py::arg("border_rectangle") = py::none(),
        "Plans untangling against the rest positions (m) and triangles: with pin_border the sides of their bounding "
        "rectangle stay straight, with hold_shore the other boundary (the shore) keeps its rest position in plan and "
        "no triangle on it overturns; lips_overturn when the motion draws crests that turn over (Gonzato's eq. 7 as "
        "drawn, Jeschke's tube): foamy triangles are lips, left to overturn; False for the bounded sections (the "
        "defaults), which never turn over: every triangle is untangled; min_angle_degrees: the smallest angle the "
        "motion may leave a triangle (0: no bound; the traced strips take 0); border_rectangle: the domain "
        "(x0, y0, x1, y1) holding every rest position, or None for their bounding rectangle: a side of that rectangle "
        "inside the domain (a straight shore that is a whole side) is shore, not border (docs/inspect.md, untangling)");
}

void bind_breakers_and_ocean(py::module_& m) {
    py::class_<wave::JeschkeMotionPlan, std::shared_ptr<wave::JeschkeMotionPlan>>(
        m, "JeschkeBreakers", "Jeschke's procedural breakers planned on ray strips (plan_jeschke_breakers)")
        .def_property_readonly("vertex_count", &wave::JeschkeMotionPlan::vertex_count)
        .def_property_readonly("loop_periods", &wave::JeschkeMotionPlan::loop_periods, "swell periods after which they repeat")
        .def(
            "evaluate",
            [](const wave::JeschkeMotionPlan& p, double t, std::optional<Float32Out> out) {
                return positions_at(p, t, out, &wave::evaluate_jeschke_breakers);
            },
            py::arg("t"), py::arg("out") = py::none(), "Positions at time t (s): (vertices, 3) float32, z up")
        .def(
            "foam",
            [](const wave::JeschkeMotionPlan& p, double t) {
                py::array_t<float> out(ssize(p.vertex_count()));
                std::span<float> s = span_of(out);
                py::gil_scoped_release release;
                wave::jeschke_foam(p, t, s);
                return out;
            },
            py::arg("t"), "Foam in [0, 1] per vertex at time t: broken crests' foam fading behind them")
        .def(
            "whitewater",
            [](const wave::JeschkeMotionPlan& p, const ArrayLike& triangles, double t, std::uint64_t seed) {
                const auto tri = to_vector<std::uint32_t>(triangles, 3, "whitewater triangles");
                wave::WhitewaterPoints w;
                {
                    py::gil_scoped_release release;
                    wave::WhitewaterOptions o;
                    o.seed = seed;
                    wave::evaluate_whitewater(wave::jeschke_whitewater_events(p, tri), o, t, w);
                }
                const auto n = ssize(w.count());
                py::dict out;
                out["positions"] = py::array_t<float>({n, py::ssize_t{3}}, w.positions.data());
                out["velocities"] = py::array_t<float>({n, py::ssize_t{3}}, w.velocities.data());
                out["age"] = py::array_t<float>(n, w.age.data());
                out["size"] = py::array_t<float>(n, w.size.data());
                out["kind"] = py::array_t<std::uint8_t>(n, w.kind.data());
                return out;
            },
            py::arg("triangles"), py::arg("t"), py::arg("seed") = 1,
            "The whitewater these breakers throw, alive at time t (docs/whitewater.md), over the surface whose "
            "(triangles, 3) indices are given: a dict of positions (n, 3), velocities (n, 3) float32 (z up; foam and "
            "bubbles at their drift position, their height relative to the water), age, size float32 and kind uint8 "
            "(0 spray, 1 foam, 2 bubble); the same particles for the same t, on any thread count");
    m.def(
        "plan_jeschke_breakers",
        [](const wave::RayStrips& strips, double period, double amplitude, double breaker_index, double wave_variation,
           const std::string& lip) {
            wave::JeschkeBreakerOptions o;
            o.breaker_index = breaker_index, o.wave_variation = wave_variation;
            o.lip = either("plan_jeschke_breakers: lip", lip, "outer", wave::BreakerLip::outer, "tube", wave::BreakerLip::tube);
            py::gil_scoped_release release;
            return std::make_shared<wave::JeschkeMotionPlan>(
                wave::plan_jeschke_breakers(strips, 2.0 * amplitude, wave::deep_water_wavelength(period), o));
        },
        py::arg("strips"), py::arg("period"), py::arg("amplitude"), py::arg("breaker_index") = wave::kBreakerIndex,
        py::arg("wave_variation") = 0.25, py::arg("lip") = "outer",
        "Jeschke's breakers for the strips of a train (period s, deep-water amplitude m), parametrised from its rays "
        "(as the scenes' /breakers); lip \"outer\" (the tube's outer section at the mesh's scale) or \"tube\" (the "
        "paper's curve as drawn)");

    py::class_<wave::OceanPlan, std::shared_ptr<wave::OceanPlan>>(
        m, "OceanPatch", "Tessendorf's FFT ocean patch planned once (plan_ocean_patch)")
        .def_readonly("resolution", &wave::OceanPlan::n)
        .def_readonly("size", &wave::OceanPlan::size)
        .def(
            "evaluate",
            [](const wave::OceanPlan& p, double t) {
                const std::size_t side = p.n + 1;
                py::array_t<float> pos({ssize(side * side), py::ssize_t{3}}), nrm({ssize(side * side), py::ssize_t{3}});
                py::array_t<float> jm(ssize(side * side));
                std::span<float> ps = span_of(pos), ns = span_of(nrm), js = span_of(jm);
                {
                    py::gil_scoped_release release;
                    wave::OceanWorkspace workspace(p.n);
                    wave::ocean_patch_frame(p, wave::evaluate_ocean(p, t, workspace), ps, ns, js);
                }
                return std::tuple{pos, nrm, jm};  // typed: the stubs show each array's dtype
            },
            py::arg("t"),
            "The patch at time t: (positions, normals, j_minus) for its (N+1)² vertices (row-major, the last row and "
            "column repeat the first: patches tile); J₋ < 0 where the surface folds");
    m.def(
        "plan_ocean_patch",
        [](std::size_t resolution, double size, double wind_speed, std::array<double, 2> wind_direction, double choppiness,
           double repeat_time, std::uint64_t seed) {
            wave::OceanOptions o;
            o.resolution = resolution, o.size = size, o.choppiness = choppiness, o.repeat_time = repeat_time, o.seed = seed;
            o.spectrum.wind_speed = wind_speed, o.spectrum.wind_direction = wind_direction;
            py::gil_scoped_release release;
            return std::make_shared<wave::OceanPlan>(wave::plan_ocean(o));
        },
        py::arg("resolution") = 256, py::arg("size") = 1000.0, py::arg("wind_speed") = 31.0,
        py::arg("wind_direction") = std::array<double, 2>{1.0, 0.0}, py::arg("choppiness") = 1.0,
        py::arg("repeat_time") = 0.0, py::arg("seed") = 1,
        "Tessendorf's FFT ocean (Phillips spectrum, the scenes' /ocean defaults): N×N waves on an L×L m patch");
    m.def("grid_triangles", [](std::size_t nx, std::size_t ny) {
        const std::vector<std::uint32_t> t = wave::grid_triangles(nx, ny);
        return copy(t, {ssize(t.size() / 3), 3});
    }, py::arg("nx"), py::arg("ny"), "Triangles of a row-major nx × ny vertex grid (the ocean patch's: nx = ny = N + 1)");
}

void bind_shading(py::module_& m) {
    m.def(
        "vertex_normals",
        [](const ArrayLike& positions, const ArrayLike& triangles) {
            const auto p = to_vector<float>(positions, 3, "vertex_normals positions");
            const auto t = to_vector<std::uint32_t>(triangles, 3, "vertex_normals triangles");
            py::array_t<float> out({ssize(p.size() / 3), py::ssize_t{3}});
            std::span<float> s = span_of(out);
            py::gil_scoped_release release;
            wave::vertex_normals(p, t, wave::vertex_faces(p.size() / 3, t), s);
            return out;
        },
        py::arg("positions"), py::arg("triangles"), "Unit area-weighted vertex normals: (vertices, 3) float32");
    m.def(
        "fresnel_weights",
        [](const ArrayLike& positions, const ArrayLike& normals, std::array<double, 3> camera, const std::string& model) {
            wave::FresnelOptions o;
            o.camera = camera;
            o.model = either("fresnel_weights: model", model, "exact", wave::FresnelModel::exact, "tso", wave::FresnelModel::tso);
            const auto p = to_vector<float>(positions, 3, "fresnel_weights positions");
            const auto n = to_vector<float>(normals, 3, "fresnel_weights normals");
            py::array_t<float> reflect(ssize(p.size() / 3)), refract(ssize(p.size() / 3));
            std::span<float> r = span_of(reflect), t = span_of(refract);
            {
                py::gil_scoped_release release;
                wave::fresnel_weights(p, n, o, r, t);
            }
            return std::tuple{reflect, refract};
        },
        py::arg("positions"), py::arg("normals"), py::arg("camera"), py::arg("model") = "exact",
        "Fresnel reflect and refract weights per vertex for a viewer at `camera` (m, z up): (reflect, refract)");
    m.def(
        "scene_camera",
        [](const wave::Scene& scene, const wave::Seafloor& seafloor) { return wave::scene_camera(scene, seafloor); },
        py::arg("scene"), py::arg("seafloor"), "The scene's camera position (m, z up): /camera/position or its default");
}

// Stage arrays of a mesh's frames for the glTF writers (frame_glb, animation_glb): each
// per-vertex argument checked against positions by name, TEXCOORD_0 made when none is
// given. `many`: positions (frames, vertices, 3), shading (frames, vertices); else one
// frame's (vertices, 3) and (vertices,).
struct StageFrames {
    std::vector<float> p, n, uv, f, r, tr;
    std::vector<std::uint32_t> t;
    std::size_t frames = 1, vertices = 0;

    StageFrames(const std::string& fn, const ArrayLike& positions, const ArrayLike& normals, const ArrayLike& triangles,
                const std::optional<ArrayLike>& texcoords, const std::optional<ArrayLike>& foam,
                const std::optional<ArrayLike>& reflect, const std::optional<ArrayLike>& refract, bool many) {
        const auto shape_of = [&](const ArrayLike& a, const char* what) {
            const py::array given = py::array::ensure(a);
            if (!many || !given || given.ndim() != 3) return std::pair{std::size_t{1}, to_vector<float>(a, 3, fn + " " + what)};
            if (given.shape(2) != 3)
                throw wave::InputError(fn + " " + what + ": expected shape (frames, vertices, 3), got " + shape_text(given));
            const py::array flat = given.attr("reshape")(-1, 3);
            return std::pair{static_cast<std::size_t>(given.shape(0)), to_vector<float>(flat, 3, fn + " " + what)};
        };
        std::size_t normal_frames = 1;
        std::tie(frames, p) = shape_of(positions, "positions");
        std::tie(normal_frames, n) = shape_of(normals, "normals");
        vertices = frames ? p.size() / 3 / frames : 0;
        if (frames == 0 || vertices == 0) throw wave::InputError(fn + " positions: no vertices");
        if (normal_frames != frames || n.size() != p.size())
            throw wave::InputError(fn + " normals: " +
                                   (many ? std::to_string(normal_frames) + " frames of " +
                                               std::to_string(n.size() / 3 / std::max<std::size_t>(normal_frames, 1)) + " vertices, positions has " +
                                               std::to_string(frames) + " of " + std::to_string(vertices)
                                         : std::to_string(n.size() / 3) + " vertices, positions has " + std::to_string(vertices)));
        t = to_vector<std::uint32_t>(triangles, 3, fn + " triangles");
        const auto same_count = [&](std::size_t count, std::size_t expected, const char* what, const char* unit) {
            if (count != expected)
                throw wave::InputError(fn + " " + what + ": " + std::to_string(count) + " " + unit + ", positions has " + std::to_string(expected));
        };
        if (texcoords) {
            uv = to_vector<float>(*texcoords, 2, fn + " texcoords");
            same_count(uv.size() / 2, vertices, "texcoords", "vertices");
        }
        const auto shading = {std::tuple{&foam, &f, "foam"}, std::tuple{&reflect, &r, "reflect"}, std::tuple{&refract, &tr, "refract"}};
        for (const auto& [given, values, what] : shading)  // each one's type first (ArgumentTypeError), then the set
            if (*given) *values = to_vector<float>(**given, 1, fn + " " + what);
        const int count = int{foam.has_value()} + int{reflect.has_value()} + int{refract.has_value()};
        if (count != 0 && count != 3)
            throw wave::InputError(fn + ": give foam, reflect and refract together (or none); got " + (foam ? "foam " : "") +
                                   (reflect ? "reflect " : "") + (refract ? "refract " : "") + "only");
        for (const auto& [given, values, what] : shading)
            if (*given) same_count(values->size(), frames * vertices, what, many ? "values" : "vertices");
        if (!texcoords) {
            // TEXCOORD_0 over the first frame's rectangle in plan, as domain_texcoords lays
            // it over the seafloor's (u along +x, v down): glTF clients expect a UV map.
            float x0 = p[0], x1 = p[0], y0 = p[1], y1 = p[1];
            for (std::size_t i = 1; i < vertices; ++i) {
                x0 = std::min(x0, p[3 * i]), x1 = std::max(x1, p[3 * i]);
                y0 = std::min(y0, p[3 * i + 1]), y1 = std::max(y1, p[3 * i + 1]);
            }
            const double width = x1 > x0 ? static_cast<double>(x1) - x0 : 1.0, height = y1 > y0 ? static_cast<double>(y1) - y0 : 1.0;
            uv.resize(2 * vertices);
            for (std::size_t i = 0; i < vertices; ++i) {
                uv[2 * i] = static_cast<float>((static_cast<double>(p[3 * i]) - x0) / width);
                uv[2 * i + 1] = static_cast<float>(1.0 - (static_cast<double>(p[3 * i + 1]) - y0) / height);
            }
        }
    }

    wave::MorphAnimationView view(double fps, std::size_t first_frame, std::size_t loop_frames) const {
        wave::MorphAnimationView v;
        v.triangles = t, v.vertex_count = vertices, v.frame_count = frames, v.first_frame = first_frame, v.fps = fps;
        v.loop_frames = loop_frames;
        v.positions = p, v.normals = n, v.texcoords = uv, v.foam = f, v.reflect = r, v.refract = tr;
        return v;
    }
};

void bind_export(py::module_& m) {
    m.def(
        "domain_texcoords",
        [](const wave::Seafloor& seafloor, const ArrayLike& x, const ArrayLike& y) {
            const auto xs = to_vector<double>(x, 1, "domain_texcoords x"), ys = to_vector<double>(y, 1, "domain_texcoords y");
            std::vector<float> uv(2 * xs.size());
            wave::domain_texcoords(seafloor.grid, xs, ys, uv);
            return copy(uv, {ssize(xs.size()), 2});
        },
        py::arg("seafloor"), py::arg("x"), py::arg("y"),
        "TEXCOORD_0 of points in plan over the seafloor's rectangle, as wave run writes it: (points, 2) float32, "
        "u along +x, v down");
    m.def(
        "frame_glb",
        [](const ArrayLike& positions, const ArrayLike& normals, const ArrayLike& triangles, std::optional<ArrayLike> texcoords,
           std::optional<ArrayLike> foam, std::optional<ArrayLike> reflect, std::optional<ArrayLike> refract, double fps,
           std::size_t frame, std::size_t loop_frames) {
            StageFrames a("frame_glb", positions, normals, triangles, texcoords, foam, reflect, refract, false);
            wave::MorphAnimationView v = a.view(fps, frame, loop_frames);
            std::string bytes;
            {
                py::gil_scoped_release release;
                bytes = wave::gltf_frame_glb(v, 0);
            }
            return py::bytes(bytes);
        },
        py::arg("positions"), py::arg("normals"), py::arg("triangles"), py::arg("texcoords") = py::none(),
        py::arg("foam") = py::none(), py::arg("reflect") = py::none(), py::arg("refract") = py::none(),
        py::arg("fps") = 24.0, py::arg("frame") = 0, py::arg("loop_frames") = 0,
        "One frame as a static .glb (the files form's frame file): positions and normals (vertices, 3), triangles "
        "(triangles, 3), optional TEXCOORD_0 (vertices, 2; None: u, v over the positions' own rectangle in plan, as "
        "domain_texcoords over the seafloor's) and foam/reflect/refract (vertices,; all three or none); `frame` its "
        "number in the loop and `loop_frames` the loop's length (0: not known), recorded for wave merge and the readers");
    m.def(
        "animation_glb",
        [](const ArrayLike& positions, const ArrayLike& normals, const ArrayLike& triangles, std::optional<ArrayLike> texcoords,
           std::optional<ArrayLike> foam, std::optional<ArrayLike> reflect, std::optional<ArrayLike> refract, double fps,
           const std::string& form, std::size_t first_frame, std::size_t loop_frames) {
            StageFrames a("animation_glb", positions, normals, triangles, texcoords, foam, reflect, refract, true);
            wave::MorphAnimationView v = a.view(fps, first_frame, loop_frames);
            if (loop_frames != 0 && first_frame + a.frames > loop_frames)
                throw wave::InputError("animation_glb: frames " + std::to_string(first_frame) + " … " +
                                       std::to_string(first_frame + a.frames - 1) + " run past loop_frames " + std::to_string(loop_frames));
            if (form != "morph" && form != "nodes")
                throw wave::InputError("animation_glb: form must be \"morph\" or \"nodes\", got \"" + form + "\"");
            std::string bytes;
            {
                py::gil_scoped_release release;
                bytes = form == "morph" ? wave::gltf_morph_glb(v) : wave::gltf_nodes_glb(v);
            }
            return py::bytes(bytes);
        },
        py::arg("positions"), py::arg("normals"), py::arg("triangles"), py::arg("texcoords") = py::none(),
        py::arg("foam") = py::none(), py::arg("reflect") = py::none(), py::arg("refract") = py::none(),
        py::arg("fps") = 24.0, py::arg("form") = "morph", py::arg("first_frame") = 0, py::arg("loop_frames") = 0,
        "Frames of one mesh as one .glb, as wave run writes its morph or nodes form: positions and normals (frames, "
        "vertices, 3), triangles (triangles, 3), optional TEXCOORD_0 (vertices, 2; None: over the first frame's "
        "rectangle in plan) and foam/reflect/refract (frames, vertices; all three or none); frame k at key time "
        "(first_frame + k) / fps; `loop_frames` the loop's length (0: not known)");
}

}  // namespace

void bind_stages(py::module_& m) {
    bind_seafloor(m);
    bind_isobaths(m);
    bind_fronts(m);
    bind_surfaces(m);
    bind_motion(m);
    bind_far_field(m);
    bind_breakers_and_ocean(m);
    bind_shading(m);
    bind_export(m);
}

}  // namespace libwave_python
