// libwave stage by stage: real bathymetry in, one animated frame out.
//
//   pipeline OKUSHIRI_ASC OUT.glb [FRAME]
//
// Reads the Okushiri (Monai valley, 1:400 laboratory model) elevation grid, slices its
// isobaths, traces Gonzato's adaptive wave fronts of a 0.6 s swell over it, takes their
// heights from the refraction–diffraction field, tessellates them into ray strips, meshes
// the water, carries the strips' fields onto the mesh (the field's where no strip passed),
// continues it to the horizon on a skirt, moves it with Gonzato's plunging profile at
// frame FRAME (default 3, 25 frames/s) and the skirt with the border's fitted swell,
// adds the breaking foam (the skirt takes the border's), untangles it, computes normals
// and Fresnel weights, and writes that one frame as a .glb.
//
// Then it asks the scene pipeline (plan_scene, animate_scene) for the same frame of the
// same scene and checks that every array is equal bit for bit: the stages below are
// exactly what `wave run` does. Exit 0 when they agree, 1 when not, 2 on bad input.
//
// Components: io (read_seafloor), core (every stage), export (gltf_frame_glb), and
// scene for the comparison; a program without the comparison links
// libwave::io and libwave::export only.
#include <libwave/bathymetry.h>
#include <libwave/errors.h>
#include <libwave/export.h>
#include <libwave/field.h>
#include <libwave/io.h>
#include <libwave/isobath.h>
#include <libwave/motion.h>
#include <libwave/physics.h>
#include <libwave/scene.h>
#include <libwave/shade.h>
#include <libwave/surface.h>
#include <libwave/trace.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace {

// The scene the stages below spell out, for the comparison with the scene pipeline.
std::string scene_json(const std::string& grid_path) {
    return R"({
  "name": "pipeline example",
  "seafloor": {"source": ")" + grid_path + R"("},
  "isobaths": {"spacing": 0.01},
  "waves": [{"period": 0.6, "amplitude": 0.004, "direction": [1.0, 0.15]}],
  "trace": {"ray_spacing": 0.02},
  "fronts": {"step": 0.01, "split_distance": 0.03},
  "camera": {"position": [2.5, -2.0, 1.2]},
  "animation": {"fps": 25}
})";
}

struct Frame {
    std::vector<float> positions, normals, texcoords, foam, reflect, refract;
    std::vector<std::uint32_t> triangles;
};

Frame frame_by_stages(const std::string& grid_path, std::size_t frame_number) {
    // io: the elevation grid through GDAL (an ESRI ASCII grid; elevation, metres).
    const wave::Seafloor seafloor = wave::read_seafloor(grid_path);

    // core: isobaths every centimetre, the shoreline included.
    wave::IsobathOptions iso;
    iso.spacing = 0.01;
    const wave::DepthContours isobaths = wave::extract_isobaths(seafloor, iso);

    // Gonzato's adaptive fronts of one swell, tessellated into ray strips.
    const wave::WaveTrain swell{.period = 0.6, .amplitude = 0.004, .direction_x = 1.0, .direction_y = 0.15};
    wave::FrontOptions fronts;
    fronts.ray_spacing = 0.02;
    fronts.step = 0.01;
    fronts.split_distance = 0.03;
    wave::FrontSet traced = wave::trace_fronts(seafloor, swell, fronts, &isobaths);
    // The rays keep their direction and phase; the refraction–diffraction field gives the
    // heights (finite where rays cross behind the island).
    const wave::WaveField field = wave::solve_wave_field(seafloor, swell);
    wave::take_field_amplitudes(field, traced);
    const wave::RayStrips strips = wave::build_ray_strips(traced);

    // The water mesh: 16 vertices per local wavelength, the depth no shallower than
    // where the swell breaks (H∞/γ), and the strips' fields at its vertices.
    const wave::WaterMesh mesh = wave::mesh_water(seafloor, wave::wavelength_edge_size(seafloor, swell, 16.0));
    wave::RayStrips on_mesh = wave::resample_ray_strips(strips, seafloor, mesh.x, mesh.y, mesh.triangles);
    wave::fill_strip_gaps(field, seafloor, on_mesh);  // where no strip passed, the field's wave
    const wave::GonzatoMotionPlan motion = wave::plan_gonzato_motion(on_mesh);
    const std::size_t n = mesh.vertex_count();

    // The far field: a skirt to the horizon (2000 camera heights, at least ten domains and 5 km),
    // moved by the swell's fundamental and first overtone fitted at the border.
    const wave::ElevationGrid& g = seafloor.grid;
    wave::SeaSkirtOptions skirt_options;
    skirt_options.distance = std::max({2000.0 * 1.2, 10.0 * std::max(g.x_max() - g.x0, g.y_max() - g.y0), 5000.0});
    skirt_options.size = wave::swell_skirt_size(seafloor, swell.period, 2.0, 2.0 * swell.amplitude / wave::kBreakerIndex);
    skirt_options.seafloor = &g;  // no sea carried on over the land beyond a shore that is a whole side
    const wave::SeaSkirt skirt = wave::plan_sea_skirt(mesh.x, mesh.y, mesh.triangles, skirt_options);
    const double omega = 2.0 * std::numbers::pi / swell.period;
    const std::vector<wave::FarFieldWave> waves{{.omega = omega, .harmonic = 1, .direction_x = 1.0, .direction_y = 0.15},
                                                {.omega = omega, .harmonic = 2, .direction_x = 1.0, .direction_y = 0.15}};
    const std::vector<double> times = wave::far_field_sample_times(swell.period, waves.size());
    // The waterline: the shoreline under the sand, a film of water left by the troughs.
    const wave::WaterlinePlan waterline = wave::plan_waterline(mesh, seafloor, swell.amplitude);
    std::vector<float> samples(3 * n * times.size());
    for (std::size_t s = 0; s < times.size(); ++s) {
        wave::evaluate_gonzato_motion(motion, times[s], std::span<float>(&samples[3 * n * s], 3 * n));
        wave::keep_waterline(waterline, std::span<float>(&samples[3 * n * s], 3 * n));
    }
    const wave::FarFieldPlan far = wave::plan_far_field(skirt, g, waves, mesh.x, mesh.y, times, samples);
    std::vector<double> x = mesh.x, y = mesh.y;
    x.insert(x.end(), skirt.x.begin(), skirt.x.end());
    y.insert(y.end(), skirt.y.begin(), skirt.y.end());
    Frame f;
    f.triangles = mesh.triangles;
    f.triangles.insert(f.triangles.end(), skirt.triangles.begin(), skirt.triangles.end());

    // Motion and shading of one frame, into caller-owned buffers.
    // Gonzato's sections bounded by their packing (the default) never turn over: no lips.
    const wave::UntanglePlan untangle = wave::plan_untangle(x, y, f.triangles, {.lips_overturn = false});
    const std::size_t all = x.size();
    const wave::VertexFaces adjacency = wave::vertex_faces(all, f.triangles);
    f.positions.resize(3 * all);
    f.normals.resize(3 * all);
    f.foam.assign(all, 0.0f);
    f.reflect.resize(all);
    f.refract.resize(all);
    const double t = static_cast<double>(frame_number) / 25.0;
    std::vector<float> scratch;
    wave::evaluate_gonzato_motion(motion, t, std::span<float>(f.positions).first(3 * n));
    wave::keep_waterline(waterline, std::span<float>(f.positions).first(3 * n));
    wave::evaluate_far_field(far, t, f.positions, scratch);
    wave::breaking_foam(on_mesh, motion, t, wave::FoamOptions{}, std::span<float>(f.foam).first(n));
    wave::far_field_foam(far, f.foam);  // the border's foam carried onto the skirt with its residual motion
    wave::untangle_motion(untangle, f.foam, f.positions);
    wave::vertex_normals(f.positions, f.triangles, adjacency, f.normals);
    wave::FresnelOptions fresnel;
    fresnel.camera = {2.5, -2.0, 1.2};
    wave::fresnel_weights(f.positions, f.normals, fresnel, f.reflect, f.refract);
    // TEXCOORD_0: the rest position over the seafloor's rectangle.
    f.texcoords.resize(2 * all);
    wave::domain_texcoords(g, x, y, f.texcoords);
    std::printf("stages: %zu isobaths, %zu rays, %zu strip triangles, water mesh %zu vertices, %zu triangles, skirt %zu vertices\n",
                isobaths.size(), traced.initial_rays + traced.inserted_rays, strips.triangle_count(), n,
                mesh.triangles.size() / 3, skirt.vertex_count());
    return f;
}

// export: one frame as a .glb (the files form's frame file).
void write_frame(const Frame& f, std::size_t frame_number, const std::string& path) {
    wave::MorphAnimationView view;
    view.triangles = f.triangles;
    view.vertex_count = f.foam.size();
    view.frame_count = 1;
    view.first_frame = frame_number;
    view.positions = f.positions;
    view.normals = f.normals;
    view.texcoords = f.texcoords;
    view.foam = f.foam;
    view.reflect = f.reflect;
    view.refract = f.refract;
    view.fps = 25.0;
    wave::write_file_atomic(path, wave::gltf_frame_glb(view, 0));
}

bool same(const char* what, const std::vector<float>& a, const std::vector<float>& b) {
    const bool ok = a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
    if (!ok) std::printf("differs from the scene pipeline: %s (%zu vs %zu values)\n", what, a.size(), b.size());
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s OKUSHIRI_ASC OUT.glb [FRAME]\n", argv[0]);
        return 2;
    }
    const std::string grid_path = argv[1], out = argv[2];
    const std::size_t frame_number = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 3;
    try {
        const Frame f = frame_by_stages(grid_path, frame_number);
        write_frame(f, frame_number, out);
        std::printf("wrote frame %zu to %s\n", frame_number, out.c_str());

        // The same frame through the scene pipeline.
        const wave::Scene scene = wave::parse_scene(scene_json(grid_path), "pipeline example", ".");
        const wave::ScenePlan plan = wave::plan_scene(scene);
        wave::AnimationStream stream(scene, plan, {.first = frame_number, .end = frame_number + 1});
        wave::SceneAnimation a;
        stream.next(a, 1);
        bool ok = a.triangles == f.triangles;
        if (!ok) std::printf("differs from the scene pipeline: triangles\n");
        ok = same("positions", f.positions, a.positions) & ok;
        ok = same("normals", f.normals, a.normals) & ok;
        ok = same("texcoords", f.texcoords, a.texcoords) & ok;
        ok = same("foam", f.foam, a.foam) & ok;
        ok = same("reflect", f.reflect, a.reflect) & ok;
        ok = same("refract", f.refract, a.refract) & ok;
        std::printf(ok ? "equal to the scene pipeline's frame, bit for bit\n" : "NOT equal to the scene pipeline's frame\n");
        return ok ? 0 : 1;
    } catch (const wave::InputError& e) {
        std::fprintf(stderr, "pipeline: %s\n", e.what());
        return 2;
    } catch (const wave::Error& e) {
        std::fprintf(stderr, "pipeline: %s\n", e.what());
        return 1;
    }
}
