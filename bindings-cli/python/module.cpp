// `import libwave`: the scene → plan → frames → export pipeline for Python, with the
// per-frame arrays as NumPy views of libwave's own buffers (no copies). Argument
// handling and calls into libwave only; the GIL is released during long work.
#include "libwave/errors.h"
#include "libwave/export.h"
#include "libwave/inspect.h"
#include "libwave/io.h"
#include "libwave/physics.h"
#include "libwave/scene.h"
#include "libwave/shade.h"
#include "libwave/underwater.h"
#include "libwave/version.h"

#include "arrays.h"
#include "signatures.h"

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <filesystem>
#include <string>

namespace py = pybind11;

namespace libwave_python {
void bind_stages(py::module_& m);  // stages.cpp
}

namespace {

using libwave_python::view;
using wave::SceneAnimation;
using wave::ScenePlan;

// JSON text of a Python value (dict, list, str, number) by Python's json module.
std::string json_text(const py::object& value) {
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    return py::module_::import("json").attr("dumps")(value).cast<std::string>();
}

// The scene with the value at a JSON pointer of its document replaced (or added), parsed
// again: every rule of parse_scene applies, and an error names the key.
wave::Scene scene_with(const wave::Scene& s, const std::string& pointer, const std::string& value_json) {
    nlohmann::json doc = nlohmann::json::parse(s.document);
    try {
        doc[nlohmann::json::json_pointer(pointer)] = nlohmann::json::parse(value_json);
    } catch (const nlohmann::json::exception& e) {
        throw wave::InputError("Scene.set: " + pointer + ": " + e.what());
    }
    return wave::parse_scene(doc.dump(), "Scene.set(\"" + pointer + "\")", s.base_dir);
}

std::string mesh_form_bytes(const SceneAnimation& a, const std::string& form) {
    // The forms whose animation is one file (export_forms()'s single_file rows).
    std::string names;
    for (const wave::ExportFormInfo& f : wave::export_forms()) {
        if (!f.single_file) continue;
        if (f.name == form) return std::move(wave::encode_animation(a.view(), f.form, wave::ExportContainer::glb, true).front().second);
        names += (names.empty() ? "\"" : " or \"") + std::string(f.name) + "\"";
    }
    throw wave::InputError("export: form must be " + names + " (one file per frame: frame_glb), got \"" + form + "\"");
}


}  // namespace

PYBIND11_MODULE(_libwave, m) {
    m.doc() = "libwave: coastal wave tracing and animated water meshes (scene → plan → frames → glTF)";
    m.attr("__version__") = wave::version();

    // Errors keep libwave's messages (file, JSON pointer, value). The hierarchy is C++'s:
    // InputError and LimitError are libwave.Error (`except libwave.Error` catches every
    // libwave failure); InputError is also a ValueError, Error a RuntimeError.
    static PyObject* const error = PyErr_NewException("libwave.Error", PyExc_RuntimeError, nullptr);
    static PyObject* const input_error =
        PyErr_NewException("libwave.InputError", py::make_tuple(py::handle(error), py::handle(PyExc_ValueError)).ptr(), nullptr);
    static PyObject* const limit_error = PyErr_NewException("libwave.LimitError", input_error, nullptr);
    // An argument of the wrong type or layout (an array of strings, a float64 buffer
    // where a float32 frame is written): an InputError that is also a TypeError.
    static PyObject* const argument_type_error =
        PyErr_NewException("libwave.ArgumentTypeError", py::make_tuple(py::handle(input_error), py::handle(PyExc_TypeError)).ptr(), nullptr);
    if (!error || !input_error || !limit_error || !argument_type_error) throw py::error_already_set();
    m.attr("Error") = py::handle(error);
    m.attr("InputError") = py::handle(input_error);
    m.attr("LimitError") = py::handle(limit_error);
    m.attr("ArgumentTypeError") = py::handle(argument_type_error);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const libwave_python::ArgumentTypeError& e) {
            PyErr_SetString(argument_type_error, wave::printable(e.what()).c_str());
        } catch (const wave::LimitError& e) {
            PyErr_SetString(limit_error, wave::printable(e.what()).c_str());
        } catch (const wave::InputError& e) {
            PyErr_SetString(input_error, wave::printable(e.what()).c_str());
        } catch (const wave::Error& e) {
            PyErr_SetString(error, wave::printable(e.what()).c_str());
        }
    });

    py::class_<wave::Scene>(m, "Scene",
                            "A validated scene (docs/scene.md). Scene(dict or JSON text, base_dir) parses one; to_dict() "
                            "gives its document back and set(pointer, value) changes a key, checked as in a file")
        .def(py::init([](const py::object& document, const std::string& base_dir) {
                 const std::string text = json_text(document);
                 py::gil_scoped_release release;
                 return wave::parse_scene(text, "<python>", base_dir);
             }),
             py::arg("document"), py::arg("base_dir") = ".")
        .def_readonly("name", &wave::Scene::name)
        .def_readonly("fps", &wave::Scene::fps)
        .def_readonly("base_dir", &wave::Scene::base_dir, "the folder relative seafloor paths are resolved against")
        .def_property_readonly("surface_kind", [](const wave::Scene& s) {
            return std::string(wave::surface_kind_name(s.surface_kind));
        })
        .def("to_dict", [](const wave::Scene& s) { return py::module_::import("json").attr("loads")(s.document); },
             "The scene's document as written (defaults not filled in): Scene(scene.to_dict(), scene.base_dir) is "
             "the same scene")
        .def(
            "get",
            [](const wave::Scene& s, const std::string& pointer) {
                const nlohmann::json doc = nlohmann::json::parse(s.document);
                std::string value;
                try {
                    const nlohmann::json::json_pointer ptr(pointer);
                    if (!doc.contains(ptr)) throw wave::InputError("Scene.get: " + pointer + " is not set in the scene");
                    value = doc[ptr].dump();
                } catch (const nlohmann::json::exception& e) {
                    throw wave::InputError("Scene.get: " + pointer + ": " + e.what());
                }
                return py::module_::import("json").attr("loads")(value);
            },
            py::arg("pointer"), "The value at a JSON pointer of the document (e.g. \"/waves/0/period\")")
        .def(
            "set",
            [](wave::Scene& s, const std::string& pointer, const py::object& value) {
                // The value as Python holds it: a str is a JSON string ("files"), not JSON text.
                s = scene_with(s, pointer, py::module_::import("json").attr("dumps")(value).cast<std::string>());
            },
            py::arg("pointer"), py::arg("value"),
            "Sets the value at a JSON pointer to a Python value (e.g. set(\"/waves/0/period\", 8.0), "
            "set(\"/outputs/form\", \"files\"), set(\"/outputs\", {\"codec\": \"meshopt\"})) and validates the "
            "scene again; on an error (InputError naming the key) the scene is unchanged")
        .def("__repr__", [](const wave::Scene& s) { return "libwave.Scene(" + s.document + ")"; });
    m.def("default_scene", &wave::default_scene, "The built-in default scene (Gonzato's bay with a swell)");
    m.def("read_scene", &wave::read_scene, py::arg("path"), py::call_guard<py::gil_scoped_release>(),
          "Reads and validates a scene file; raises InputError naming the file and JSON pointer");
    m.def(
        "parse_scene",
        [](py::object doc, const std::string& origin, const std::string& base_dir) {
            // A dict is serialised by Python's json module; a str is JSON text.
            const std::string text = json_text(doc);
            py::gil_scoped_release release;
            return wave::parse_scene(text, origin, base_dir);
        },
        py::arg("scene"), py::arg("origin") = "<python>", py::arg("base_dir") = ".",
        "A scene from a dict or JSON text; relative seafloor paths are resolved against base_dir");

    py::class_<ScenePlan, std::shared_ptr<ScenePlan>>(m, "Plan", "The static products of a scene (computed once)")
        .def_property_readonly("vertex_count", [](const ScenePlan& p) { return p.rest_x.size(); })
        .def_readonly("loop_period", &ScenePlan::loop_period)
        .def_readonly("warnings", &ScenePlan::warnings)
        .def_property_readonly("rest_positions", [](py::object self) {
            const auto& p = self.cast<const ScenePlan&>();
            py::array_t<double> xy({static_cast<py::ssize_t>(p.rest_x.size()), py::ssize_t{2}});
            auto r = xy.mutable_unchecked<2>();
            for (py::ssize_t v = 0; v < r.shape(0); ++v) r(v, 0) = p.rest_x[v], r(v, 1) = p.rest_y[v];
            return xy;
        });
    m.def(
        "plan",
        [](const wave::Scene& scene, const py::object& given) {
            // An object, not a typed argument: Seafloor is bound later (stages.cpp), and its
            // name in the signature (the stubs) would be the C++ one.
            std::shared_ptr<wave::Seafloor> seafloor;
            if (!given.is_none()) {
                if (!py::isinstance<wave::Seafloor>(given))
                    throw libwave_python::ArgumentTypeError(
                        "plan: seafloor must be a libwave.Seafloor (Seafloor.from_triangles, Seafloor.from_grid, "
                        "read_seafloor), got " + std::string(py::str(py::type::of(given).attr("__name__"))));
                seafloor = given.cast<std::shared_ptr<wave::Seafloor>>();
            }
            py::gil_scoped_release release;
            return std::make_shared<ScenePlan>(seafloor ? wave::plan_scene(scene, *seafloor) : wave::plan_scene(scene));
        },
        py::arg("scene"), py::arg("seafloor") = py::none(),
        "Runs the static stages: seafloor, isobaths, tracing, surface, motion plan. With `seafloor` (a libwave.Seafloor: "
        "Seafloor.from_triangles of a terrain in memory, from_grid of an array) the scene stands on it and its /seafloor "
        "is not read: the same plan as a scene whose /seafloor reads those values from a file");

    py::class_<SceneAnimation, std::shared_ptr<SceneAnimation>>(m, "Animation",
                                                                "Frames of one loop; arrays are read-only NumPy views")
        .def_readonly("vertex_count", &SceneAnimation::vertex_count)
        .def_readonly("frame_count", &SceneAnimation::frame_count)
        .def_readonly("first_frame", &SceneAnimation::first_frame)
        .def_readonly("loop_frames", &SceneAnimation::loop_frames)
        .def_readonly("fps", &SceneAnimation::fps)
        .def_property_readonly("positions", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.positions, {static_cast<py::ssize_t>(a.frame_count), static_cast<py::ssize_t>(a.vertex_count), 3}, self);
        }, "(frames, vertices, 3) float32, z up (m)")
        .def_property_readonly("normals", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.normals, {static_cast<py::ssize_t>(a.frame_count), static_cast<py::ssize_t>(a.vertex_count), 3}, self);
        })
        .def_property_readonly("triangles", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.triangles, {static_cast<py::ssize_t>(a.triangles.size() / 3), 3}, self);
        }, "(triangles, 3) uint32, counter-clockwise seen from above")
        .def_property_readonly("texcoords", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.texcoords, {static_cast<py::ssize_t>(a.vertex_count), 2}, self);
        })
        .def_property_readonly("foam", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.foam, {static_cast<py::ssize_t>(a.foam.empty() ? 0 : a.frame_count), static_cast<py::ssize_t>(a.vertex_count)}, self);
        }, "(frames, vertices) in [0, 1]; empty when the scene's attributes are none")
        .def_property_readonly("reflect", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.reflect, {static_cast<py::ssize_t>(a.reflect.empty() ? 0 : a.frame_count), static_cast<py::ssize_t>(a.vertex_count)}, self);
        }, "Fresnel reflect weight R per frame and vertex")
        .def_property_readonly("refract", [](py::object self) {
            const auto& a = self.cast<const SceneAnimation&>();
            return view(a.refract, {static_cast<py::ssize_t>(a.refract.empty() ? 0 : a.frame_count), static_cast<py::ssize_t>(a.vertex_count)}, self);
        }, "T = 1 − R")
        .def(
            "glb",
            [](const SceneAnimation& a, const std::string& form) {
                std::string bytes;
                {
                    py::gil_scoped_release release;
                    bytes = mesh_form_bytes(a, form);
                }
                return py::bytes(bytes);
            },
            py::arg("form") = "morph", "The animation as one .glb (morph targets or scale-switched nodes)")
        .def(
            "frame_glb", [](const SceneAnimation& a, std::size_t k) {
                if (k >= a.frame_count) throw wave::InputError("frame_glb: frame " + std::to_string(k) + " of " + std::to_string(a.frame_count));
                std::string bytes;
                {
                    py::gil_scoped_release release;
                    bytes = wave::gltf_frame_glb(a.view(), k);
                }
                return py::bytes(bytes);
            },
            py::arg("frame"), "One frame (index within this animation) as a static .glb")
        .def(
            "whitewater_glb", [](const SceneAnimation& a, std::size_t k) -> std::optional<py::bytes> {
                if (k >= a.frame_count) throw wave::InputError("whitewater_glb: frame " + std::to_string(k) + " of " + std::to_string(a.frame_count));
                if (a.whitewater.empty()) return std::nullopt;
                return py::bytes(a.whitewater[k]);
            },
            py::arg("frame"), "The frame's whitewater particles (/whitewater) as a POINTS .glb, or None without them")
        .def(
            "write_glb",
            [](const SceneAnimation& a, const std::string& path, const std::string& form) {
                py::gil_scoped_release release;
                wave::write_file_atomic(path, mesh_form_bytes(a, form));  // never a half-written file under `path`
            },
            py::arg("path"), py::arg("form") = "morph");
    m.def(
        "animate",
        [](const wave::Scene& read, const ScenePlan& plan, std::size_t first, py::object end) {
            wave::FrameRange range{first, end.is_none() ? static_cast<std::size_t>(-1) : end.cast<std::size_t>()};
            py::gil_scoped_release release;
            const wave::Scene scene = wave::resolve_codec(read, wave::estimate_run(read, plan));  // as wave run chooses
            return std::make_shared<SceneAnimation>(wave::animate_scene(scene, plan, 2e9, range));
        },
        py::arg("scene"), py::arg("plan"), py::arg("first") = 0, py::arg("end") = py::none(),
        "Evaluates frames [first, end) of the loop: positions, normals, shading; the export codec as wave run chooses it (/outputs/codec auto: meshopt above 32 MB of plain output)");

    m.def(
        "write_animation",
        [](const wave::Scene& read, const ScenePlan& plan, const std::string& folder, std::size_t first, py::object end,
           std::size_t chunk) {
            wave::FrameRange range{first, end.is_none() ? static_cast<std::size_t>(-1) : end.cast<std::size_t>()};
            std::vector<std::pair<std::string, std::size_t>> files;
            {
                py::gil_scoped_release release;
                const wave::Scene scene = wave::resolve_codec(read, wave::estimate_run(read, plan));  // as wave run chooses
                wave::AnimationStream stream(scene, plan, range);
                const bool whole = stream.first_frame() == 0 && stream.frame_count() == wave::scene_loop_frames(scene, plan);
                if (chunk == 0) chunk = wave::files_form_chunk(wave::estimate_run(scene, plan));
                std::filesystem::create_directories(folder);
                files = wave::stream_animation(stream, scene, folder, whole, chunk).files;
            }
            py::list out;
            for (const auto& [name, bytes] : files) out.append(py::make_tuple(name, bytes));
            return out;
        },
        py::arg("scene"), py::arg("plan"), py::arg("folder"), py::arg("first") = 0, py::arg("end") = py::none(),
        py::arg("chunk") = 0,
        "Evaluates frames [first, end) of the loop a chunk at a time and writes the scene's form (morph, nodes or pc2, "
        "not quantised; caustic maps too) into `folder` as they come, so that memory holds one chunk "
        "(docs/export.md, \"Streamed output\"): the same bytes as `wave run`. chunk 0 = wave run's. Returns "
        "[(file name, bytes)]");

    m.def(
        "write_files_form",
        [](const wave::Scene& read, const ScenePlan& plan, const std::string& folder, std::size_t first, py::object end,
           bool resume) {
            wave::FrameRange range{first, end.is_none() ? static_cast<std::size_t>(-1) : end.cast<std::size_t>()};
            std::string index;
            wave::FilesFormRun run;
            {
                py::gil_scoped_release release;
                wave::Scene scene = read;
                scene.form = wave::ExportForm::files;  // whatever /outputs/form says; the codec as wave run --form files chooses it
                scene = wave::resolve_codec(scene, wave::estimate_run(scene, plan));
                const wave::FrameIndexInfo info{scene.name, scene.fps, plan.loop_period, wave::scene_loop_frames(scene, plan),
                                                wave::scene_run_key(scene, plan, read.document)};
                run = wave::write_files_form(scene, plan, folder, info, range, resume);
                index = wave::publish_files_form(run, folder, info, resume);
            }
            py::dict out;
            out["index"] = py::module_::import("json").attr("loads")(index);
            py::list files;
            for (const auto& [name, bytes] : run.files) files.append(py::make_tuple(name, bytes));
            out["files"] = files;
            out["kept_frames"] = run.verified;
            out["computed_frames"] = run.computed;
            out["height_range_m"] = py::make_tuple(run.z_min, run.z_max);
            return out;
        },
        py::arg("scene"), py::arg("plan"), py::arg("folder"), py::arg("first") = 0, py::arg("end") = py::none(),
        py::arg("resume") = false,
        "Writes the files form of frames [first, end) of the loop into `folder`, as `wave run --form files` does "
        "(docs/export.md, the files form; whatever the scene's /outputs/form, its codec as that run chooses it): frames/frame-NNNN.glb (each frame's underwater files after it) and "
        "index.json listing each frame's files with their bytes and SHA-256, merged with the index a slice of the same "
        "animation left there. The frames are computed a chunk at a time into a hidden partial folder, so that "
        "resume=True after a killed call keeps the frames whose files still match their entries (docs/hardening.md, "
        "\"Crash safety\"). Returns {\"index\": "
        "the index, \"files\": [(file name, bytes)] of the range, \"kept_frames\", \"computed_frames\", "
        "\"height_range_m\": (least, greatest)}");

    m.def(
        "preview",
        [](const wave::Scene& scene, const ScenePlan& plan, const SceneAnimation& a, std::size_t frame, std::size_t width,
           std::size_t height) {
            if (frame >= a.frame_count)
                throw wave::InputError("preview: frame " + std::to_string(frame) + " of " + std::to_string(a.frame_count));
            wave::PreviewOptions o = wave::scene_preview(scene, plan.seafloor);
            if (width > 0) o.width = width;
            if (height > 0) o.height = height;
            wave::Image image;
            {
                py::gil_scoped_release release;
                const std::size_t n = a.vertex_count;
                image = wave::render_preview(std::span<const float>(&a.positions[3 * n * frame], 3 * n),
                                             std::span<const float>(&a.normals[3 * n * frame], 3 * n), a.triangles, o);
            }
            py::array_t<std::uint8_t> rgb({static_cast<py::ssize_t>(image.height), static_cast<py::ssize_t>(image.width), py::ssize_t{3}});
            std::copy(image.rgb.begin(), image.rgb.end(), rgb.mutable_data());
            return rgb;
        },
        py::arg("scene"), py::arg("plan"), py::arg("animation"), py::arg("frame") = 0, py::arg("width") = 0,
        py::arg("height") = 0,
        "A frame (index within the animation) rendered by the sunset ray caster: (height, width, 3) uint8 RGB");

    m.def(
        "caustics",
        [](const wave::Scene& scene, const ScenePlan& plan, const SceneAnimation& a, const py::object& frame, std::size_t map_size) {
            // One frame (an int: a (height, width) map) or several (a sequence: (frames, height, width)),
            // the floor and the mesh's edges planned once for all of them.
            const bool one = py::isinstance<py::int_>(frame);
            const std::vector<std::size_t> frames = one ? std::vector<std::size_t>{frame.cast<std::size_t>()}
                                                        : frame.cast<std::vector<std::size_t>>();
            for (std::size_t f : frames)
                if (f >= a.frame_count) throw wave::InputError("caustics: frame " + std::to_string(f) + " of " + std::to_string(a.frame_count));
            wave::Scene s = scene;
            if (!s.underwater) s.underwater = wave::UnderwaterOptions{};
            if (map_size > 0) s.underwater->map_size = map_size;
            std::vector<float> maps;
            wave::CausticOptions o;
            {
                py::gil_scoped_release release;
                o = wave::scene_caustic_options(s, plan);
                const wave::CausticPlan cp = wave::plan_caustics(plan.seafloor.grid, o);
                const std::size_t n = a.vertex_count, pixels = o.width * o.height;
                const wave::CausticMesh mesh = wave::plan_caustic_mesh(a.triangles, n);
                wave::CausticWorkspace workspace;
                maps.resize(frames.size() * pixels);
                for (std::size_t i = 0; i < frames.size(); ++i)
                    wave::evaluate_caustics(cp, mesh, std::span<const float>(&a.positions[3 * n * frames[i]], 3 * n),
                                            std::span<const float>(&a.normals[3 * n * frames[i]], 3 * n),
                                            std::span<float>(maps).subspan(i * pixels, pixels), &workspace);
            }
            const auto h = static_cast<py::ssize_t>(o.height), w = static_cast<py::ssize_t>(o.width);
            py::array_t<float> out = one ? py::array_t<float>({h, w}) : py::array_t<float>({static_cast<py::ssize_t>(frames.size()), h, w});
            std::copy(maps.begin(), maps.end(), out.mutable_data());
            return out;
        },
        py::arg("scene"), py::arg("plan"), py::arg("animation"), py::arg("frame") = 0, py::arg("map_size") = 0,
        "The caustics a frame (index within the animation) focuses onto the seafloor under the scene's sun "
        "(docs/underwater.md): (height, width) float32 irradiance relative to the sun's on flat water, row 0 at the "
        "seafloor's largest y; the scene's /underwater water, or coastal water; map_size 0 = the scene's (512). "
        "`frame` a sequence of frames: (frames, height, width), the seafloor and the mesh's edges planned once "
        "for all of them (planning the edges of a 512² surface takes about as long as four maps)");

    m.def(
        "sunbeams",
        [](const wave::Scene& scene, const ScenePlan& plan, const SceneAnimation& a, const py::object& frame,
           const std::optional<std::array<std::size_t, 3>>& voxels) {
            const bool one = py::isinstance<py::int_>(frame);
            const std::vector<std::size_t> frames = one ? std::vector<std::size_t>{frame.cast<std::size_t>()}
                                                        : frame.cast<std::vector<std::size_t>>();
            for (std::size_t f : frames)
                if (f >= a.frame_count) throw wave::InputError("sunbeams: frame " + std::to_string(f) + " of " + std::to_string(a.frame_count));
            wave::Scene s = scene;
            if (!s.underwater) s.underwater = wave::UnderwaterOptions{};
            wave::SunVolumeOptions options = s.underwater->sunbeams.value_or(wave::SunVolumeOptions{});
            if (voxels) std::tie(options.nx, options.ny, options.nz) = std::tuple((*voxels)[0], (*voxels)[1], (*voxels)[2]);
            std::vector<float> light;
            std::optional<wave::SunVolumePlan> vp;
            {
                py::gil_scoped_release release;
                vp = wave::plan_sun_volume(wave::plan_caustics(plan.seafloor.grid, wave::scene_caustic_options(s, plan)), options);
                const std::size_t n = a.vertex_count, voxel_count = vp->nx * vp->ny * vp->nz;
                const wave::CausticMesh mesh = wave::plan_caustic_mesh(a.triangles, n);
                wave::CausticWorkspace workspace;
                light.resize(frames.size() * voxel_count);
                for (std::size_t i = 0; i < frames.size(); ++i)
                    wave::evaluate_sun_volume(*vp, mesh, std::span<const float>(&a.positions[3 * n * frames[i]], 3 * n),
                                              std::span<const float>(&a.normals[3 * n * frames[i]], 3 * n),
                                              std::span<float>(light).subspan(i * voxel_count, voxel_count), &workspace);
            }
            std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(vp->nz), static_cast<py::ssize_t>(vp->ny), static_cast<py::ssize_t>(vp->nx)};
            if (!one) shape.insert(shape.begin(), static_cast<py::ssize_t>(frames.size()));
            py::array_t<float> out(shape);
            std::copy(light.begin(), light.end(), out.mutable_data());
            py::dict result;
            result["light"] = out;
            result["origin"] = py::make_tuple(vp->x0, vp->y0, vp->z0);
            result["voxel_size"] = py::make_tuple(vp->dx, vp->dy, vp->dz);
            return result;
        },
        py::arg("scene"), py::arg("plan"), py::arg("animation"), py::arg("frame") = 0, py::arg("voxels") = py::none(),
        "The sunlight in the water under a frame (index within the animation; docs/underwater.md, \"Sunbeams\"): "
        "{\"light\": (nz, ny, nx) float32 E / I0 (z up from the bottom, y up from the seafloor's least y), "
        "\"origin\": the outer corner of voxel (0, 0, 0) (m), \"voxel_size\": (dx, dy, dz) (m)}; the scene's "
        "/underwater water and sunbeams, or coastal water and 128 x 128 x 32 voxels; voxels = (nx, ny, nz) overrides. "
        "`frame` a sequence of frames: light (frames, nz, ny, nx), planned once for all of them");

    libwave_python::bind_stages(m);

    m.def(
        "linear_wave",
        [](double period, double depth) {
            const wave::LinearWave w = wave::linear_wave(2.0 * 3.141592653589793 / period, depth);
            py::dict d;
            d["k"] = w.k, d["wavelength"] = w.wavelength, d["celerity"] = w.celerity;
            d["group_velocity"] = w.group_velocity, d["shoaling"] = w.shoaling, d["dry"] = w.dry;
            return d;
        },
        py::arg("period"), py::arg("depth"), "Linear wave quantities (SI) for a period (s) in depth h (m)");

    m.def(
        "wave_field",
        [](const wave::Scene& scene, std::size_t train) {
            if (train >= scene.waves.size())
                throw wave::InputError("wave_field: train " + std::to_string(train) + " of " + std::to_string(scene.waves.size()));
            wave::FieldRaster r;
            {
                py::gil_scoped_release release;
                const wave::Seafloor sea = wave::scene_seafloor(scene);
                r = wave::rasterize_wave_field(wave::solve_wave_field(sea, scene.waves[train], scene.field), sea);
            }
            const auto grid = [&](const std::vector<float>& v) {
                py::array_t<float> a({static_cast<py::ssize_t>(r.ny), static_cast<py::ssize_t>(r.nx)});
                std::copy(v.begin(), v.end(), a.mutable_data());
                return a;
            };
            py::dict d;
            d["height_ratio"] = grid(r.height_ratio), d["phase"] = grid(r.phase), d["direction_deg"] = grid(r.direction_deg);
            d["x0"] = r.x0, d["y0"] = r.y0, d["spacing"] = r.spacing, d["incident_height"] = r.incident_height;
            return d;
        },
        py::arg("scene"), py::arg("train") = 0,
        "The refraction-diffraction field of one wave train (docs/wave-field.md) on a regular grid over the seafloor: "
        "(ny, nx) float32 arrays height_ratio (H/H0), phase (rad) and direction_deg, row 0 at y0, NaN on land; "
        "x0, y0, spacing (m) and incident_height H0 (m)");

    m.def(
        "read_animation",
        [](const std::string& path, std::size_t first, py::object count) {
            wave::StoredAnimation a;
            const bool window = first > 0 || !count.is_none();
            const std::size_t wanted = count.is_none() ? static_cast<std::size_t>(-1) : count.cast<std::size_t>();
            {
                py::gil_scoped_release release;
                a = window ? wave::read_animation_frames(path, first, wanted) : wave::read_animation(path);
            }
            const auto frames = static_cast<py::ssize_t>(a.frame_count), n = static_cast<py::ssize_t>(a.vertex_count);
            const auto copy = [](const auto& v, std::vector<py::ssize_t> shape) {
                using T = typename std::decay_t<decltype(v)>::value_type;
                if (v.empty()) shape[0] = 0;
                py::array_t<T> out(shape);
                std::copy(v.begin(), v.end(), out.mutable_data());
                return out;
            };
            py::dict d;
            d["positions"] = copy(a.positions, {frames, n, 3});
            d["normals"] = copy(a.normals, {frames, n, 3});
            d["foam"] = copy(a.foam, {frames, n});
            d["reflect"] = copy(a.reflect, {frames, n});
            d["refract"] = copy(a.refract, {frames, n});
            d["colors"] = copy(a.colors, {frames, n, 3});
            d["triangles"] = copy(a.triangles, {static_cast<py::ssize_t>(a.triangles.size() / 3), 3});
            d["vertex_count"] = a.vertex_count, d["frame_count"] = a.frame_count, d["first_frame"] = a.first_frame;
            d["loop_frames"] = a.loop_frames, d["fps"] = a.fps, d["scene"] = a.scene;
            return d;
        },
        py::arg("path"), py::arg("first") = 0, py::arg("count") = py::none(),
        "Reads an output of wave run (.glb/.gltf of the morph or nodes form, a frame file, or the files form's "
        "index.json; plain, quantised, meshopt or Draco, a Draco frame's skirt primitive joined to it): positions and "
        "normals (frames, n, 3) z up, "
        "foam/reflect/refract (frames, n), colors, triangles, fps, frame_count, first_frame, loop_frames, scene. "
        "With `first` or `count` (a .glb/.gltf only): frames [first, first + count) of the file alone, the others "
        "neither read nor decoded (a player's one frame of a compressed file)");

    py::class_<wave::FrameReader>(
        m, "FrameReader",
        "A player's reader of an output of wave run (.glb/.gltf of the morph or nodes form, a frame file, or the files "
        "form's index.json; plain, quantised, meshopt or Draco), opened once: it keeps the parsed file, its static views "
        "and the triangles (for the files form the frame files' decoded indices and rest positions), so that frame(k) "
        "reads and decodes only frame k's own views. Frames equal read_animation's bit for bit.")
        .def(py::init([](const std::string& path) {
                 py::gil_scoped_release release;
                 return std::make_unique<wave::FrameReader>(path);
             }),
             py::arg("path"))
        .def_property_readonly("frame_count", &wave::FrameReader::frame_count)
        .def_property_readonly("vertex_count", &wave::FrameReader::vertex_count)
        .def_property_readonly("first_frame", &wave::FrameReader::first_frame)
        .def_property_readonly("loop_frames", &wave::FrameReader::loop_frames)
        .def_property_readonly("fps", &wave::FrameReader::fps)
        .def_property_readonly("scene", &wave::FrameReader::scene)
        .def_property_readonly(
            "triangles",
            [](py::object self) {
                const auto& t = self.cast<const wave::FrameReader&>().triangles();
                return view(t, {static_cast<py::ssize_t>(t.size() / 3), 3}, self);
            },
            "(t, 3) uint32, shared by every frame (read-only)")
        .def(
            "frame",
            [](wave::FrameReader& r, std::size_t k, bool normals) {
                wave::StoredAnimation a;
                {
                    py::gil_scoped_release release;
                    a = r.frame(k, normals);
                }
                const auto n = static_cast<py::ssize_t>(a.vertex_count);
                const auto put = [](std::vector<float>& v, std::vector<py::ssize_t> shape) -> py::object {
                    if (v.empty()) return py::none();
                    // The array owns the frame's vector: no copy.
                    auto* owned = new std::vector<float>(std::move(v));
                    py::capsule free(owned, [](void* p) { delete static_cast<std::vector<float>*>(p); });
                    return py::array_t<float>(shape, owned->data(), free);
                };
                py::dict d;
                d["positions"] = put(a.positions, {n, 3});
                d["normals"] = put(a.normals, {n, 3});
                d["foam"] = put(a.foam, {n});
                d["reflect"] = put(a.reflect, {n});
                d["refract"] = put(a.refract, {n});
                d["colors"] = put(a.colors, {n, 3});
                return d;
            },
            py::arg("k"), py::arg("normals") = true,
            "Frame k (0 ≤ k < frame_count) of the output: a dict of positions and normals (n, 3) z up, foam, reflect, "
            "refract (n,), colors (n, 3), each None when the file has none (normals None when normals=False: they are "
            "then neither read nor decoded). The GIL is released while the frame is read");

    m.def(
        "inspect",
        [](py::object source, double sliver_angle, double lip_foam, double long_edge_ratio, bool per_frame) {
            wave::InspectOptions o;
            o.sliver_angle_deg = sliver_angle, o.lip_foam = lip_foam, o.long_edge_ratio = long_edge_ratio;
            std::string text;
            if (py::isinstance<SceneAnimation>(source)) {
                const auto& a = source.cast<const SceneAnimation&>();
                py::gil_scoped_release release;
                text = wave::inspection_json(wave::inspect_animation(a.view(), o), o, per_frame);
            } else {
                const std::string path = py::str(source);
                py::gil_scoped_release release;
                text = wave::inspection_json(wave::inspect_animation(wave::read_animation(path).view(), o), o, per_frame);
            }
            return py::module_::import("json").attr("loads")(text);
        },
        py::arg("source"), py::arg("sliver_angle") = 15.0, py::arg("lip_foam") = 0.1, py::arg("long_edge_ratio") = 3.0,
        py::arg("per_frame") = true,
        "Checks an animation as a renderer meets it (docs/inspect.md): an Animation, or the path of an output of wave run "
        "(.glb/.gltf or index.json). Returns a dict: topology (unreferenced_vertices, non_manifold_edges, boundary loops, "
        "shore_vertices, shore_drift_m), worst (folds, lips, slivers, lip_slivers, shore_slivers, smallest_angle_deg, smallest_angle_off_lips_deg, longest_edge_m, "
        "worst_edge_ratio, max_speed_m_s, ...) and "
        "per_frame, the same for every frame");

    // Last: inspect.signature for every function and method defined above, and their
    // argument refusals as libwave.ArgumentTypeError.
    libwave_python::add_text_signatures(m, argument_type_error);
}
