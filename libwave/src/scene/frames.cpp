// The frame loop: a run's buffers, each frame's motion, untangling, shading, foam,
// whitewater and underwater files, frames side by side; AnimationStream and
// animate_scene.
#include "libwave/scene.h"

#include "core/memory.h"
#include "libwave/errors.h"
#include "libwave/shade.h"
#include "pipeline.h"
#include "surface_model.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace wave {

namespace {

// The range of a chunk's heights (min and max are exact in any order).
struct HeightRange {
    float low = std::numeric_limits<float>::infinity(), high = -std::numeric_limits<float>::infinity();
    HeightRange& add(float z) {
        low = std::min(low, z), high = std::max(high, z);
        return *this;
    }
    HeightRange& add(const HeightRange& o) {
        low = std::min(low, o.low), high = std::max(high, o.high);
        return *this;
    }
};

// The moved coarse positions of a range's frames, kept by the quantised morph form's
// delta-range pass (AnimationStream::position_delta_range) for the stream's own pass,
// which then skips the motion, the lips and the untangling — the same bits: the same
// code on the same input (spool_stands_in says when). In an unnamed temporary file
// (12 bytes a vertex and frame, gone when closed), not in memory: a loop's frames
// outgrow the run's memory budget. Frames are written and read whole, under a lock.
class PositionSpool {
public:
    PositionSpool(std::size_t first, std::size_t count, std::size_t floats)
        : file_(std::tmpfile()), first_(first), floats_(floats), kept_(count, 0) {}
    ~PositionSpool() {
        if (file_) std::fclose(file_);
    }
    PositionSpool(const PositionSpool&) = delete;
    PositionSpool& operator=(const PositionSpool&) = delete;
    // Keeps frame `frame` of the loop (nothing when the file could not be made or written).
    void keep(std::size_t frame, std::span<const float> p) {
        const std::lock_guard lock(mutex_);
        if (!file_ || !inside(frame) || p.size() != floats_) return;
        const bool written = seek(frame) && std::fwrite(p.data(), sizeof(float), floats_, file_) == floats_;
        kept_[frame - first_] = written ? 1 : 0;
    }
    // Frame `frame` into `p` if it was kept.
    bool take(std::size_t frame, std::span<float> p) {
        const std::lock_guard lock(mutex_);
        if (!file_ || !inside(frame) || !kept_[frame - first_] || p.size() != floats_) return false;
        return seek(frame) && std::fread(p.data(), sizeof(float), floats_, file_) == floats_;
    }

private:
    std::FILE* file_;
    std::size_t first_, floats_;
    std::vector<std::uint8_t> kept_;
    std::mutex mutex_;
    bool inside(std::size_t frame) const { return frame >= first_ && frame - first_ < kept_.size(); }
    bool seek(std::size_t frame) {
        const double at = static_cast<double>(frame - first_) * static_cast<double>(floats_) * sizeof(float);
        return at < static_cast<double>(std::numeric_limits<long>::max()) && std::fseek(file_, static_cast<long>(at), SEEK_SET) == 0;
    }
};

// What a run of frames reuses: the model's buffers, the wind sea's, the fold foam's past
// samples, and with /refine the coarse frame the stencils carry to the refined surface.
struct FrameRun {
    const Scene& scene;
    const ScenePlan& plan;
    const detail::SurfaceModel& model;
    const Refinement* refined;  // nullptr without /refine
    bool shaded, creased;
    bool positions_only = false;  // AnimationStream::position_delta_range's pass: no normals either
    PositionSpool* spool = nullptr;  // that pass's positions: kept by it, taken by the stream's own pass
    std::unique_ptr<detail::ModelState> state{};
    detail::WindSeaState wind_sea{};
    // J₋ at the vertices for past lattice times of the fold-foam fade (FoldFoamOptions),
    // kept while they are inside the window: each is computed once for a run of frames,
    // and equals what a frame computed alone would compute.
    std::map<long long, FoldSample> fold_past{};
    std::vector<float> fold_scratch{};  // a new past lattice time's J₋ at the vertices (reused: no fresh pages a frame)
    Refinement frame_refinement{};  // crest sharpness: creases follow each frame's heights
    std::vector<float> coarse_p{}, coarse_nr{}, coarse_foam{}, fine_depth{};
    std::vector<float> lip_weight{};  // the model's drawn walls and lips (SurfaceModel::lips)
    std::optional<UntanglePlan> untangle{};  // when the coarse vertices move sideways
    UntangleWorkspace untangle_scratch{};
    std::vector<float> far_field_scratch{};  // the skirt's anchors' residuals, then its breakers
    VertexFaces adjacency{};
    FresnelOptions fresnel{};
    std::optional<CausticPlan> caustics{};    // /underwater/caustics: a map per frame
    std::optional<SunVolumePlan> sunbeams{};  // /underwater/sunbeams: a volume per frame (its levels' caustic plans)
    CausticMesh caustic_mesh{};             // the surface's edges, walked once a frame
    CausticWorkspace caustic_scratch{};
    // A map's PNG and a volume's VDB are encoded on a task of their own while the frames
    // go on (the encoding is serial and takes as long as the map): two maps and volumes,
    // each pair with its encoding task.
    std::array<std::vector<float>, 2> caustic_maps{};
    std::array<std::vector<float>, 2> sun_volumes{};
    std::array<std::unique_ptr<tbb::task_group>, 2> underwater_encoders{};
    // /whitewater: the surface the particles ride, a frame's particles, and the wind
    // sea's whitecaps as events (from the fold foam's window of past samples).
    std::optional<WhitewaterRide> ride{};
    WhitewaterPoints points{}, fold_points{};
    WhitewaterWorkspace whitewater_work{};  // evaluate_whitewater's buffers, kept between frames
    WhitewaterEvents fold_events{};
    std::vector<std::pair<long long, const FoldSample*>> fold_window{};
    double fold_step = 0.0;
    double vertex_spacing = 0.0;  // the surface's mean edge (m): what a whitecap event stands for
};

// Waits for the underwater files still being encoded: rethrowing their errors, or,
// `quietly` (a frame's own error is unwinding), dropping them.
void finish_underwater_files(FrameRun& r, bool quietly = false) {
    for (auto& task : r.underwater_encoders) {
        if (!task) continue;
        try {
            task->wait();
        } catch (...) {
            if (!quietly) throw;
        }
    }
}

// The rectangle the untangling borders on: the far field's outer one round a skirt, else
// the seafloor's (the water mesh's domain). A whole side of the water's own rectangle
// that is a straight shore lies inside it, and is held as shore. None (NaN) when it
// does not hold the rest positions (a camera grid reaching the horizon).
std::array<double, 4> border_rectangle(const ScenePlan& p) {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    const ElevationGrid& g = p.seafloor.grid;
    std::array<double, 4> r{nan, nan, nan, nan};
    if (p.skirt.vertex_count() > 0)
        r = {p.skirt.x0 - p.skirt.reach, p.skirt.y0 - p.skirt.reach, p.skirt.x1 + p.skirt.reach, p.skirt.y1 + p.skirt.reach};
    else if (g.nx >= 2 && g.ny >= 2)
        r = {g.x0, g.y0, g.x_max(), g.y_max()};
    const auto [x0, x1] = std::minmax_element(p.rest_x.begin(), p.rest_x.end());
    const auto [y0, y1] = std::minmax_element(p.rest_y.begin(), p.rest_y.end());
    const bool holds = !p.rest_x.empty() && r[0] <= *x0 && r[1] <= *y0 && r[2] >= *x1 && r[3] >= *y1;
    return holds ? r : std::array<double, 4>{nan, nan, nan, nan};
}

void start_run(FrameRun& r, const std::vector<std::uint32_t>& triangles, std::size_t n) {
    const ScenePlan& plan = r.plan;
    const std::size_t nc = plan.rest_x.size();
    r.state = r.model.start(r.scene, plan, r.shaded);
    if (plan.ocean.n > 0) {
        r.wind_sea.workspace.emplace(plan.ocean.n);
        detail::size_for_overwrite(r.wind_sea.lattice_j, plan.ocean.n * plan.ocean.n);
        detail::size_for_overwrite(r.wind_sea.vertex_j, nc);
    }
    if (r.refined) {
        r.coarse_p.resize(3 * nc);
        r.coarse_nr.resize(3 * nc);
        r.coarse_foam.resize(nc);
        r.fine_depth.resize(n);
        apply_refinement(*r.refined, std::span<const float>(plan.rest_depth), 1, r.fine_depth);
    }
    // Sideways motion by the model, a superposed wind sea or Gerstner waves: untangled
    // every frame against the coarse surface at rest (breaking crests' lips excepted).
    // The surface's boundary off the domain's sides is the shore and holds still, but
    // for the traced strips themselves, whose boundary is where their rays end.
    // The open ocean's skirt (its wind sea, wind_sea_scale) does not untangle the patch:
    // the patch's folds are its whitecaps (fold foam), and its vertices stay the FFT's.
    const bool patch = r.model.wind_sea_patch;
    if (r.model.untangle || (!patch && !plan.wind_sea_scale.empty()) || !plan.gerstner.empty()) {
        const bool traced_strips = r.model.holds_boundary && !r.model.holds_boundary(r.scene);
        const bool lips = r.model.overturns && r.model.overturns(r.scene);
        UntangleOptions options{.lips_overturn = lips, .hold_shore = !traced_strips};
        // The traced strips hold slivers at rest, where the rays crowd: bounding their
        // angles only damped them unevenly (the bay's strips 5 → 48 ms a frame, vertices
        // 1.8 → 2.6 m/s).
        if (traced_strips) options.min_angle_degrees = 0.0;
        else options.border_rectangle = border_rectangle(plan);
        r.untangle = plan_untangle(plan.rest_x, plan.rest_y, detail::surface_triangles(r.scene, plan), options);
        if (!r.shaded || r.refined) r.coarse_foam.resize(nc);
    }
    if (r.shaded || r.untangle) r.fold_past.insert(plan.fold_past.begin(), plan.fold_past.end());  // frame 0's foam past
    if (r.scene.whitewater) {
        // The model's own triangles (its vertices come first): a far field's skirt spans
        // kilometres, and a bucket grid over it crowded thousands of the domain's small
        // triangles into each bucket (19 s a frame). Whitewater beyond the domain is dropped.
        const std::vector<std::uint32_t>& coarse = r.model.triangles(plan);
        r.ride = plan_whitewater_ride(plan.rest_x, plan.rest_y, coarse);
        double sum = 0.0;  // the mean edge of the first triangles
        const std::size_t edges = std::min<std::size_t>(coarse.size(), 30000);
        for (std::size_t e = 0; e < edges; ++e) {
            const std::uint32_t a = coarse[e], b = coarse[e % 3 == 2 ? e - 2 : e + 1];
            sum += std::hypot(plan.rest_x[a] - plan.rest_x[b], plan.rest_y[a] - plan.rest_y[b]);
        }
        r.vertex_spacing = edges > 0 ? sum / static_cast<double>(edges) : 1.0;
    }
    r.fresnel.camera = scene_camera(r.scene, plan.seafloor);
    r.fresnel.model = r.scene.fresnel;
    const std::optional<UnderwaterOptions>& u = r.scene.underwater;
    if (u && (u->caustics || u->sunbeams)) {
        CausticPlan caustics = plan_caustics(plan.seafloor.grid, scene_caustic_options(r.scene, plan));
        if (u->sunbeams) r.sunbeams = plan_sun_volume(caustics, *u->sunbeams);
        if (u->caustics) r.caustics = std::move(caustics);  // not a second copy of the seafloor grid
        const std::size_t map_pixels = r.caustics ? r.caustics->options.width * r.caustics->options.height : 0;
        r.caustic_mesh = plan_caustic_mesh(triangles, n);
        for (std::size_t b = 0; b < 2; ++b) {
            r.caustic_maps[b].resize(map_pixels);
            if (r.sunbeams) r.sun_volumes[b].resize(r.sunbeams->nx * r.sunbeams->ny * r.sunbeams->nz);
            r.underwater_encoders[b] = std::make_unique<tbb::task_group>();
        }
    }
}

// The vertices the surface model moves itself: all but a far field's skirt.
std::size_t model_vertex_count(const ScenePlan& plan) {
    return plan.model_vertices > 0 ? plan.model_vertices : plan.rest_x.size();
}

// What move_coarse says of the frame's coarse vertices.
struct CoarseFrame {
    bool normals_done = false;  // their normals are final
    bool weights_done = false;  // and so are their Fresnel weights
};

// Whether the model's own output is the frame's final surface, as far as the run's
// settings tell before the model moves it (move_coarse checks the rest).
bool model_output_final(const FrameRun& r) {
    return r.shaded && !r.refined && !r.untangle && r.plan.gerstner.empty() && r.plan.wind_sea_scale.empty() &&
           model_vertex_count(r.plan) == r.plan.rest_x.size();
}

// The surface's coarse vertices at time t (and their normals when they are exact; and
// their Fresnel weights into refl, refr when the model computes them as it goes and
// nothing moves the vertices after it).
CoarseFrame move_coarse(FrameRun& r, double t, std::span<float> pc, std::span<float> nrc, std::span<float> refl,
                        std::span<float> refr) {
    const ScenePlan& plan = r.plan;
    // With a far field the model moves its own vertices, the skirt follows them.
    const std::size_t own = model_vertex_count(plan);
    detail::ModelFrame frame{.positions = pc.first(3 * own), .normals = nrc.first(3 * own), .wind_sea = r.wind_sea};
    if (model_output_final(r)) frame.fresnel = &r.fresnel, frame.reflect = refl, frame.refract = refr;
    const bool exact_normals = r.model.move(r.scene, plan, t, r.state.get(), frame) && own == plan.rest_x.size();
    if (!plan.gerstner.empty()) {
        const std::span<const double> x(plan.rest_x.data(), own), y(plan.rest_y.data(), own);
        add_gerstner_waves(plan.gerstner, x, y, std::span<const float>(plan.rest_depth.data(), own), t, pc.first(3 * own));
    }
    if (plan.far_field.vertex_count() > 0) evaluate_far_field(plan.far_field, t, pc, r.far_field_scratch);
    else if (plan.skirt.vertex_count() > 0)  // the open ocean's skirt: at rest, then the patch's wind sea below
        for (std::size_t v = own; v < plan.rest_x.size(); ++v) {
            pc[3 * v] = static_cast<float>(plan.rest_x[v]);
            pc[3 * v + 1] = static_cast<float>(plan.rest_y[v]);
            pc[3 * v + 2] = 0.0f;
        }
    if (plan.skirt_breakers.vertex_count() > 0) evaluate_skirt_breakers(plan.skirt_breakers, t, pc, r.far_field_scratch);
    if (!plan.wind_sea_scale.empty()) {  // a wind sea superposed on the model's surface
        const OceanFields fields = evaluate_ocean(plan.ocean, t, *r.wind_sea.workspace);
        add_ocean_samples(plan.ocean, fields, plan.rest_x, plan.rest_y, plan.wind_sea_scale, pc);
        if (r.shaded) {
            ocean_jacobian_field(plan.ocean, fields, r.wind_sea.lattice_j);
            detail::fold_at_vertices(plan, r.model.wind_sea_patch, r.wind_sea.lattice_j, r.wind_sea.vertex_j);
        }
    }
    const bool normals_done = exact_normals && plan.gerstner.empty() && !r.refined;
    return {normals_done, normals_done && frame.weights_done};
}

// Foam at the coarse vertices: the model's, then the wind sea's folds fading out.
void coarse_foam(FrameRun& r, double t, std::span<float> fc) {
    const ScenePlan& plan = r.plan;
    if (r.model.foam) r.model.foam(r.scene, plan, t, r.state.get(), fc.first(model_vertex_count(plan)));
    // The skirt's foam: Jeschke's breakers carried on beyond the border where they run,
    // otherwise the border's own foam with its residual motion.
    if (plan.skirt_breakers.vertex_count() > 0) skirt_breaker_foam(plan.skirt_breakers, t, fc, r.far_field_scratch);
    else if (plan.far_field.vertex_count() > 0) far_field_foam(plan.far_field, fc);
    if (plan.ocean.n == 0) return;
    const FoldFoamOptions& fold = plan.fold_foam;
    accumulate_fold_foam(r.wind_sea.vertex_j, 0.0, fold, fc);
    r.fold_window.clear();
    double step = 0.0;
    const auto lattice = fold_lattice(t, fold, plan.loop_period, step);
    std::vector<AgedFoldSample> window;
    for (long long j : lattice) {
        auto it = r.fold_past.find(j);
        if (it == r.fold_past.end()) {
            evaluate_ocean_jacobian(plan.ocean, static_cast<double>(j) * step, *r.wind_sea.workspace, r.wind_sea.lattice_j);
            detail::size_for_overwrite(r.fold_scratch, plan.rest_x.size());
            detail::fold_at_vertices(plan, r.model.wind_sea_patch, r.wind_sea.lattice_j, r.fold_scratch);
            it = r.fold_past.emplace(j, fold_sample(r.fold_scratch, fold)).first;
        }
        window.push_back({&it->second, t - static_cast<double>(j) * step});
        if (r.ride) r.fold_window.emplace_back(j, &it->second);
    }
    r.fold_step = step;
    accumulate_fold_foam(window, fold, fc);
    if (!lattice.empty()) r.fold_past.erase(r.fold_past.begin(), r.fold_past.lower_bound(lattice.back()));
}

// The wind sea's whitecaps as whitewater events: every sample of the fold foam's window
// (its lattice times), the crests running downwind at half the wind's speed (short
// breaking waves, not the peak's), of a tenth of the significant height (4 σ) up to
// half a metre. A whitecap is sampled every lattice step while it lasts: each sample
// stands for that share of a second of breaking, on 0.3 m of crest per metre of the
// surface's spacing (whitecaps are short crests, not lines).
void fold_events(FrameRun& r) {
    const ScenePlan& plan = r.plan;
    r.fold_events = WhitewaterEvents{};
    if (r.fold_window.empty() || !r.scene.ocean) return;
    const OceanOptions& o = *r.scene.ocean;
    const double sigma = std::sqrt(std::max(0.0, plan.ocean.expected_variance));
    const double height = std::clamp(0.4 * sigma, 0.1, 0.5);
    const std::array<double, 2> wind = o.spectrum.wind_direction;
    for (const auto& [j, sample] : r.fold_window)
        fold_whitewater_events(*sample, static_cast<double>(j) * r.fold_step, plan.fold_foam, plan.rest_x, plan.rest_y, wind,
                               0.5 * o.spectrum.wind_speed, height, 0.3 * r.vertex_spacing * r.fold_step, j, r.fold_events);
}

// The frame's whitewater (Scene::whitewater): the breakers' particles and the wind
// sea's, put on the moved coarse surface `pc`; their foam splatted into the coarse
// foam `fc` when shaded (the smooth band takes their patches); the frame's POINTS file.
void whitewater_frame(FrameRun& r, double t, std::span<const float> pc, std::span<float> fc, SceneAnimation& a, std::size_t f) {
    const WhitewaterOptions& o = *r.scene.whitewater;
    evaluate_whitewater(r.plan.whitewater, o, t, r.points, r.whitewater_work);
    ride_whitewater(*r.ride, pc, r.points);
    fold_events(r);
    if (r.fold_events.size() > 0) {
        evaluate_whitewater(r.fold_events, o, t, r.fold_points, r.whitewater_work);
        ride_whitewater(*r.ride, pc, r.fold_points, true);
        const auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
        append(r.points.positions, r.fold_points.positions);
        append(r.points.velocities, r.fold_points.velocities);
        append(r.points.age, r.fold_points.age);
        append(r.points.size, r.fold_points.size);
        append(r.points.kind, r.fold_points.kind);
    }
    if (r.shaded) splat_whitewater_foam(*r.ride, r.points, 40.0, 0.85, fc);
    a.whitewater[f] = whitewater_glb(r.points, a.first_frame + f, r.scene.fps);
}

// Whether a frame's moved coarse positions, kept by the delta-range pass, stand in for
// move_coarse, the lips and the untangling: the untangling runs (so move_coarse's normals
// and Fresnel weights are not the frame's), no wind sea (whose fold samples move_coarse
// leaves for the foam), and the model's foam and lips need nothing move leaves.
bool may_spool(const FrameRun& r) { return r.untangle && r.plan.ocean.n == 0 && r.model.foam_of_time_alone; }
bool spool_stands_in(const FrameRun& r) { return r.spool && may_spool(r); }

// Frame f of the animation `a`: positions, normals and, shaded, the Fresnel weights,
// foam and colour.
void evaluate_frame(FrameRun& r, const std::vector<std::uint32_t>& coarse_triangles, std::size_t f, SceneAnimation& a,
                    HeightRange& heights) {
    const std::size_t n = a.vertex_count;
    const std::span<float> p(&a.positions[3 * n * f], 3 * n), nr(&a.normals[3 * n * f], 3 * n);
    const std::span<float> pc = r.refined ? std::span<float>(r.coarse_p) : p, nrc = r.refined ? std::span<float>(r.coarse_nr) : nr;
    const double t = static_cast<double>(a.first_frame + f) / r.scene.fps;
    const std::span<float> refl = r.shaded ? std::span<float>(&a.reflect[n * f], n) : std::span<float>();
    const std::span<float> refr = r.shaded ? std::span<float>(&a.refract[n * f], n) : std::span<float>();
    const std::size_t frame = a.first_frame + f;
    const bool kept = !r.positions_only && spool_stands_in(r) && r.spool->take(frame, pc);
    const CoarseFrame coarse = kept ? CoarseFrame{} : move_coarse(r, t, pc, nrc, refl, refr);
    bool normals_done = coarse.normals_done;
    // The model's drawn walls and lips, where it says where they are, for the untangling
    // (when this frame untangles: not when the delta-range pass's positions stand in).
    const bool untangles = r.untangle && !kept;
    bool lips_drawn = false;
    OverturnTest drawn;
    const std::span<float> foam = r.shaded ? std::span<float>(&a.foam[n * f], n) : std::span<float>();
    const std::span<float> fc = (r.refined || !r.shaded) ? std::span<float>(r.coarse_foam) : foam;
    if (untangles && r.model.lips) {
        r.lip_weight.resize(fc.size());  // zeros beyond the model's own vertices (the skirt): the hook writes all of its
        lips_drawn = r.model.lips(r.scene, r.plan, t, std::span<float>(r.lip_weight).first(model_vertex_count(r.plan)));
        if (lips_drawn && r.model.draws_overturned)
            drawn = [&r, t](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return r.model.draws_overturned(r.scene, r.plan, t, i, j, k); };
    }
    // Foam before untangling, which leaves the breaking crests' lips to overturn (the
    // foam marks them where the model draws none); foam does not depend on the
    // positions. Unshaded, a frame whose lips are drawn needs none (nor computes it
    // when nothing else carries from frame to frame: no wind sea's fold samples, a
    // model whose foam is of the time alone).
    const bool foam_alone = r.plan.ocean.n == 0 && r.model.foam_of_time_alone;
    if (r.shaded || (untangles && !lips_drawn) || (r.untangle && !foam_alone)) {
        std::fill(fc.begin(), fc.end(), 0.0f);
        coarse_foam(r, t, fc);
    }
    if (untangles) {
        untangle_motion(*r.untangle, lips_drawn ? std::span<const float>(r.lip_weight) : std::span<const float>(fc), pc,
                        &r.untangle_scratch, drawn);
        normals_done = false;
        if (r.positions_only && spool_stands_in(r)) r.spool->keep(frame, pc);
    }
    if (r.ride) whitewater_frame(r, t, pc, fc, a, f);
    const Refinement* fr = r.refined;
    if (r.creased) {
        const RefineOptions& o = *r.scene.refine;
        const Creases c = crest_creases(pc, coarse_triangles, o.crest_sharpness_per_metre, o.max_crest_sharpness);
        r.frame_refinement = plan_refinement(r.plan.rest_x.size(), coarse_triangles, o, r.scene.max_refined_vertices, nullptr, &c);
        fr = &r.frame_refinement;
    }
    if (r.refined) apply_refinement(*fr, pc, 3, p);
    if (!normals_done && !r.positions_only) {
        // Made when a frame first needs it: the FFT patch's normals are exact, and a
        // million vertices' adjacency took as long as three of its frames.
        if (r.adjacency.offsets.empty()) r.adjacency = vertex_faces(n, a.triangles);
        vertex_normals(p, a.triangles, r.adjacency, nr);
    }
    // The heights' range, in parallel (min and max are exact in any order).
    heights = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, 1 << 14), heights,
        [&](const tbb::blocked_range<std::size_t>& b, HeightRange m) {
            for (std::size_t v = b.begin(); v < b.end(); ++v) m.add(p[3 * v + 2]);
            return m;
        },
        [](HeightRange x, const HeightRange& y) { return x.add(y); });
    if (r.caustics || r.sunbeams) {
        const std::size_t b = f % 2;
        r.underwater_encoders[b]->wait();  // the map and volume two frames back are encoded: their buffers are free
        if (r.caustics) evaluate_caustics(*r.caustics, r.caustic_mesh, p, nr, r.caustic_maps[b], &r.caustic_scratch);
        if (r.sunbeams) evaluate_sun_volume(*r.sunbeams, r.caustic_mesh, p, nr, r.sun_volumes[b], &r.caustic_scratch);
        r.underwater_encoders[b]->run([&r, &a, b, f] {
            if (r.caustics)
                a.caustics[f] = caustic_png(r.caustic_maps[b], r.caustics->options.width, r.caustics->options.height,
                                            r.scene.underwater->full_scale);
            if (r.sunbeams) a.sunbeams[f] = sun_volume_vdb(*r.sunbeams, r.sun_volumes[b]);
        });
    }
    if (!r.shaded) return;
    if (!(coarse.weights_done && normals_done)) fresnel_weights(p, nr, r.fresnel, refl, refr);
    if (r.refined) apply_refinement(*fr, std::span<const float>(fc), 1, foam);
    const std::span<const float> depth = r.refined ? std::span<const float>(r.fine_depth) : std::span<const float>(r.plan.rest_depth);
    if (r.scene.color) water_colour(refl, depth, foam, WaterColours{}, std::span<float>(&a.colors[3 * n * f], 3 * n));
}

// A run of frames of the scene, not started.
FrameRun scene_run(const Scene& scene, const ScenePlan& plan, const Refinement* refined) {
    return FrameRun{.scene = scene, .plan = plan, .model = detail::surface_model(scene.surface_kind), .refined = refined,
                    .shaded = scene.attributes != Scene::Attributes::none,
                    .creased = refined && scene.refine->crest_sharpness_per_metre > 0.0};
}

}  // namespace

struct AnimationStream::State {
    const Scene& scene;
    const ScenePlan& plan;
    const Refinement* refined;
    const std::vector<std::uint32_t>& coarse_triangles;
    const std::vector<std::uint32_t>& triangles;  // the exported surface's
    std::size_t loop_frames = 0, first = 0, count = 0, done = 0;
    FrameRun run;
    std::unique_ptr<PositionSpool> spool{};  // position_delta_range's frames, when they stand in (run.spool)
    std::vector<std::unique_ptr<FrameRun>> lanes{};  // runs beside `run` when frames go side by side (frame_lanes)
    // The animation whose static parts this stream set last, and its triangles' storage:
    // a later chunk into it leaves them (24 MB of triangles a chunk at 1024²).
    const SceneAnimation* dressed = nullptr;
    const std::uint32_t* dressed_triangles = nullptr;
    const float* dressed_texcoords = nullptr;
    // Whether `a` still holds the static parts set in it (the same object, its triangles
    // and texture coordinates — two per vertex — neither replaced nor resized since).
    bool holds_static_parts(const SceneAnimation& a) const {
        return dressed == &a && a.triangles.data() == dressed_triangles && a.triangles.size() == triangles.size() &&
               a.texcoords.data() == dressed_texcoords && a.texcoords.size() == 2 * a.vertex_count;
    }

    // Frames 0 … k − 1 of the chunk `a` (sized for them), one after another on `run`, or
    // side by side on frame_lanes runs; returns their heights' range.
    HeightRange evaluate(SceneAnimation& a, std::size_t k, const std::function<void(std::size_t, std::size_t)>& progress) {
        const std::size_t lanes_now = detail::frame_lanes(scene, a.vertex_count, k);
        return lanes_now == 1 ? in_order(a, k, progress) : side_by_side(a, k, lanes_now, progress);
    }

    HeightRange in_order(SceneAnimation& a, std::size_t k, const std::function<void(std::size_t, std::size_t)>& progress) {
        HeightRange heights;
        try {
            for (std::size_t f = 0; f < k; ++f) {
                evaluate_frame(run, coarse_triangles, f, a, heights);
                if (progress) progress(done + f + 1, count);
            }
            finish_underwater_files(run);
        } catch (...) {
            finish_underwater_files(run, true);  // no encoding task may outlive the frames it reads and writes
            throw;
        }
        return heights;
    }

    // Each lane takes the next frame not yet taken; a frame's passes run isolated in it,
    // so a lane waiting for them never picks up another lane's frames meanwhile.
    HeightRange side_by_side(SceneAnimation& a, std::size_t k, std::size_t lane_count,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
        while (lanes.size() + 1 < lane_count) {
            lanes.push_back(std::make_unique<FrameRun>(scene_run(scene, plan, refined)));
            lanes.back()->positions_only = run.positions_only;
            lanes.back()->spool = run.spool;
            start_run(*lanes.back(), triangles, a.vertex_count);
        }
        std::vector<HeightRange> lane_heights(lane_count);
        std::atomic<std::size_t> next_frame{0};
        std::size_t finished = 0;
        std::mutex progress_lock;
        const auto lane_frames = [&](std::size_t lane) {
            FrameRun& on = lane == 0 ? run : *lanes[lane - 1];
            for (std::size_t f = next_frame++; f < k; f = next_frame++) {
                tbb::this_task_arena::isolate([&] { evaluate_frame(on, coarse_triangles, f, a, lane_heights[lane]); });
                if (!progress) continue;
                const std::lock_guard lock(progress_lock);
                progress(done + ++finished, count);
            }
        };
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, lane_count, 1),
            [&](const tbb::blocked_range<std::size_t>& r) {
                for (std::size_t lane = r.begin(); lane != r.end(); ++lane) lane_frames(lane);
            },
            tbb::simple_partitioner());
        HeightRange heights;
        for (const HeightRange& h : lane_heights) heights.add(h);
        return heights;
    }
};

AnimationStream::AnimationStream(const Scene& scene, const ScenePlan& plan, FrameRange range) {
    // The surface's own vertices (coarse), and with /refine the subdivided ones.
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    const std::vector<std::uint32_t>& coarse = detail::surface_triangles(scene, plan);
    const std::size_t loop_frames = scene_loop_frames(scene, plan), end = std::min(range.end, loop_frames);
    if (range.first >= end)
        throw InputError("scene: the frame range " + std::to_string(range.first) + ":" +
                         (range.end == static_cast<std::size_t>(-1) ? std::string() : std::to_string(range.end)) +
                         " holds no frame of the loop's 0:" + std::to_string(loop_frames));
    state_.reset(new State{.scene = scene, .plan = plan, .refined = refined, .coarse_triangles = coarse,
                           .triangles = refined ? refined->triangles : coarse, .loop_frames = loop_frames,
                           .first = range.first, .count = end - range.first, .run = scene_run(scene, plan, refined)});
    start_run(state_->run, state_->triangles, refined ? refined->fine_vertices : plan.rest_x.size());
}

AnimationStream::~AnimationStream() = default;

double AnimationStream::position_delta_range(std::size_t chunk) const {
    State& s = *state_;  // (its spool; the frames are not advanced)
    // No shading, colour, caustics, whitewater or normals: the positions are the same
    // (the particles ride the moved surface and the normals come from it; neither
    // moves it).
    Scene positions_only = s.scene;
    positions_only.attributes = Scene::Attributes::none;
    positions_only.color = false;
    positions_only.underwater.reset();
    positions_only.whitewater.reset();
    AnimationStream pass(positions_only, s.plan, FrameRange{s.first, s.first + s.count});
    pass.state_->run.positions_only = true;
    // Its moved positions kept for this stream's own pass (the lanes share the spool).
    if (may_spool(s.run)) {
        s.spool = std::make_unique<PositionSpool>(s.first, s.count, 3 * s.plan.rest_x.size());
        s.run.spool = pass.state_->run.spool = s.spool.get();
        for (const auto& lane : s.lanes) lane->spool = s.spool.get();
    }
    SceneAnimation a;
    std::vector<float> base;
    double range = 0.0;
    while (pass.next(a, std::max<std::size_t>(1, chunk)) > 0) {
        if (base.empty()) base.assign(a.positions.begin(), a.positions.begin() + static_cast<std::ptrdiff_t>(3 * a.vertex_count));
        range = wave::position_delta_range(base, a.positions, range);
    }
    return range;
}
std::size_t AnimationStream::first_frame() const noexcept { return state_->first; }
std::size_t AnimationStream::frame_count() const noexcept { return state_->count; }
std::size_t AnimationStream::frames_left() const noexcept { return state_->count - state_->done; }

std::size_t AnimationStream::next(SceneAnimation& a, std::size_t count, const std::function<void(std::size_t, std::size_t)>& progress) {
    State& s = *state_;
    const std::size_t k = std::min(count, frames_left());
    if (k == 0) return 0;
    const Scene& scene = s.scene;
    a.fps = scene.fps;
    a.scene = scene.name;
    a.vertex_count = s.refined ? s.refined->fine_vertices : s.plan.rest_x.size();
    a.loop_frames = s.loop_frames;
    a.first_frame = s.first + s.done;
    a.frame_count = k;
    const bool dressed = s.holds_static_parts(a);
    if (!dressed) a.triangles = s.triangles;
    const std::size_t n = a.vertex_count;
    // Every value is written below (foam is cleared per frame): the first chunk's arrays
    // are fresh memory, advised for huge pages, later chunks reuse them.
    detail::size_for_overwrite(a.positions, 3 * n * k);
    detail::size_for_overwrite(a.normals, 3 * n * k);
    a.layout = scene.attributes == Scene::Attributes::named ? ScalarLayout::custom : ScalarLayout::blender34;
    a.draco = scene.draco;
    a.quantize = scene.quantize;
    a.meshopt = scene.meshopt;
    const bool shaded = scene.attributes != Scene::Attributes::none;
    detail::size_for_overwrite(a.reflect, shaded ? n * k : 0);
    detail::size_for_overwrite(a.refract, shaded ? n * k : 0);
    detail::size_for_overwrite(a.foam, shaded ? n * k : 0);
    detail::size_for_overwrite(a.colors, scene.color ? 3 * n * k : 0);
    a.caustics.assign(scene.underwater && scene.underwater->caustics ? k : 0, std::string());
    a.sunbeams.assign(scene.underwater && scene.underwater->sunbeams ? k : 0, std::string());
    a.whitewater.assign(scene.whitewater ? k : 0, std::string());
    const HeightRange heights = s.evaluate(a, k, progress);
    a.z_min = heights.low, a.z_max = heights.high;
    s.done += k;
    if (!dressed) {
        detail::rest_texcoords(s.plan, s.refined, a);
        a.seafloor_positions.clear();
        a.seafloor_colors.clear();
        a.seafloor_triangles.clear();
        a.seafloor_texcoords.clear();
        detail::dress_animation(scene, s.plan, a);
        s.dressed = &a;
        s.dressed_triangles = a.triangles.data();
        s.dressed_texcoords = a.texcoords.data();
    }
    return k;
}

SceneAnimation animate_scene(const Scene& scene, const ScenePlan& plan, double max_bytes, FrameRange range,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
    AnimationStream stream(scene, plan, range);
    const Refinement* refined = plan.refinement.fine_vertices > 0 ? &plan.refinement : nullptr;
    check_run_limits(scene, RunEstimate{.vertices = refined ? refined->fine_vertices : plan.rest_x.size(), .frames = scene_loop_frames(scene, plan)},
                     stream.frame_count(), max_bytes);
    SceneAnimation a;
    stream.next(a, stream.frame_count(), progress);
    return a;
}

}  // namespace wave
