// Uniform subdivision of any libwave surface with OpenSubdiv (Ts'o–Barsky §5: refine
// the surface; OpenSubdiv Far's way: topology refined once, stencils applied per frame). The only
// translation unit that includes OpenSubdiv.
#include "libwave/errors.h"
#include "libwave/surface.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace wave {

namespace {

using namespace OpenSubdiv;

// Faces after `level` uniform steps: Loop 4 per step; Catmull–Clark 3 quads from each
// triangle, then 4 per step, each quad split into 2 triangles.
double refined_triangles(std::size_t coarse_triangles, RefineScheme scheme, int level) {
    double f = static_cast<double>(coarse_triangles);
    if (scheme == RefineScheme::loop) {
        for (int l = 0; l < level; ++l) f *= 4.0;
        return f;
    }
    f *= 3.0;
    for (int l = 1; l < level; ++l) f *= 4.0;
    return 2.0 * f;
}

template <class T>
void apply(const Refinement& r, std::span<const T> coarse, std::size_t c, std::span<T> fine) {
    if (c == 0 || coarse.size() != r.coarse_vertices * c || fine.size() != r.fine_vertices * c)
        throw InputError("apply_refinement: expected " + std::to_string(r.coarse_vertices * c) + " coarse and " +
                         std::to_string(r.fine_vertices * c) + " fine values, got " + std::to_string(coarse.size()) +
                         " and " + std::to_string(fine.size()));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, r.fine_vertices, 4096), [&](const tbb::blocked_range<std::size_t>& b) {
        for (std::size_t v = b.begin(); v != b.end(); ++v) {
            T sum[4] = {};
            for (std::uint32_t i = r.stencil_offsets[v]; i < r.stencil_offsets[v + 1]; ++i) {
                const T w = static_cast<T>(r.stencil_weights[i]);
                const T* src = &coarse[std::size_t{r.stencil_indices[i]} * c];
                for (std::size_t k = 0; k < c && k < 4; ++k) sum[k] += w * src[k];
            }
            for (std::size_t k = 0; k < c && k < 4; ++k) fine[v * c + k] = sum[k];
        }
    });
}

// Adaptive refinement: every coarse edge gets a rate (segments), every face is
// tessellated on the limit surface with its edges' rates (Bfr), and each new point's
// stencil over the face's control points is kept. Edge points are shared between the
// two faces of an edge (same rate, the same k-th point from the lower vertex), corners
// between all faces of a vertex: the mesh has no cracks.
Refinement adaptive_refinement(const Far::TopologyRefiner& refiner, std::size_t vertex_count,
                               std::span<const std::uint32_t> tri, const RefineOptions& o, std::size_t max_vertices,
                               const AdaptiveCriteria& c) {
    const std::size_t nt = tri.size() / 3;
    if (c.sample_normals.empty() || c.sample_normals.size() % (3 * vertex_count) != 0 || c.rest_x.size() != vertex_count ||
        c.rest_y.size() != vertex_count)
        throw InputError("refine: adaptive refinement needs sampled normals and rest positions of every vertex");
    const std::size_t samples = c.sample_normals.size() / (3 * vertex_count);
    const int max_rate = 1 << o.level;
    const double tolerance = o.max_angle_degrees * std::numbers::pi / 180.0;

    // The rate of each edge: Ts'o's flatness (the largest turn of the normal along it over
    // the sampled frames, in steps of the tolerance) or nearness to the camera.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> rate;
    for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = tri[3 * t + static_cast<std::size_t>(k)], b = tri[3 * t + static_cast<std::size_t>((k + 1) % 3)];
            const auto key = std::minmax(a, b);
            if (rate.count(key)) continue;
            double turn = 0.0;
            for (std::size_t sm = 0; sm < samples; ++sm) {
                const float* na = &c.sample_normals[3 * (sm * vertex_count + a)];
                const float* nb = &c.sample_normals[3 * (sm * vertex_count + b)];
                const double d = std::clamp(double{na[0]} * nb[0] + double{na[1]} * nb[1] + double{na[2]} * nb[2], -1.0, 1.0);
                turn = std::max(turn, std::acos(d));
            }
            double r = tolerance > 0.0 ? std::ceil(turn / tolerance) : max_rate;
            if (o.near_distance > 0.0) {
                const double mx = 0.5 * (c.rest_x[a] + c.rest_x[b]), my = 0.5 * (c.rest_y[a] + c.rest_y[b]);
                const double dist = std::max(std::hypot(mx - c.camera[0], my - c.camera[1], c.camera[2]), 1e-9);
                r = std::max(r, std::ceil(max_rate * o.near_distance / dist));
            }
            rate[key] = static_cast<int>(std::clamp(r, 1.0, static_cast<double>(max_rate)));
        }
    double estimate = static_cast<double>(vertex_count);
    for (std::size_t t = 0; t < nt; ++t) {
        int m = 1;
        for (int k = 0; k < 3; ++k)
            m = std::max(m, rate[std::minmax(tri[3 * t + static_cast<std::size_t>(k)], tri[3 * t + static_cast<std::size_t>((k + 1) % 3)])]);
        estimate += 0.5 * m * m;
    }
    if (estimate > static_cast<double>(max_vertices))
        throw LimitError("refine: adaptive level " + std::to_string(o.level) + " would make about " +
                         std::to_string(static_cast<long long>(estimate)) + " vertices (limit " + std::to_string(max_vertices) +
                         "); lower the level, raise max_angle_degrees or shorten near_distance");

    Refinement r;
    r.coarse_vertices = vertex_count;
    r.stencil_offsets.push_back(0);
    std::vector<std::uint32_t> corner(vertex_count, UINT32_MAX);
    std::map<std::tuple<std::uint32_t, std::uint32_t, int>, std::uint32_t> edge_point;
    Bfr::RefinerSurfaceFactory<> factory(refiner);
    Bfr::Surface<double> surface;
    std::vector<int> controls;
    std::vector<double> uv, weights;
    std::vector<int> facets;
    std::vector<std::uint32_t> global;
    constexpr double eps = 1e-9;
    for (std::size_t t = 0; t < nt; ++t) {
        if (!factory.InitVertexSurface(static_cast<int>(t), &surface) || !surface.IsValid())
            throw InputError("refine: OpenSubdiv cannot build the limit surface of triangle " + std::to_string(t));
        controls.resize(static_cast<std::size_t>(surface.GetNumControlPoints()));
        surface.GetControlPointIndices(controls.data());
        weights.resize(controls.size());
        const std::uint32_t v[3] = {tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]};
        int rates[3];
        for (int k = 0; k < 3; ++k) rates[k] = rate[std::minmax(v[k], v[(k + 1) % 3])];
        Bfr::Tessellation tess(surface.GetParameterization(), 3, rates, Bfr::Tessellation::Options().SetFacetSize(3));
        const int nc = tess.GetNumCoords(), nb = tess.GetNumBoundaryCoords();
        uv.resize(2 * static_cast<std::size_t>(nc));
        tess.GetCoords(uv.data());
        global.assign(static_cast<std::size_t>(nc), 0);
        const auto add_point = [&](const double* at) {  // a new refined vertex: its stencil
            surface.EvaluateStencil(at, weights.data());
            for (std::size_t i = 0; i < controls.size(); ++i)
                if (weights[i] != 0.0) {
                    r.stencil_indices.push_back(static_cast<std::uint32_t>(controls[i]));
                    r.stencil_weights.push_back(static_cast<float>(weights[i]));
                }
            r.stencil_offsets.push_back(static_cast<std::uint32_t>(r.stencil_indices.size()));
            return static_cast<std::uint32_t>(r.stencil_offsets.size() - 2);
        };
        for (int i = 0; i < nc; ++i) {
            const double* q = &uv[2 * static_cast<std::size_t>(i)];
            const double u = q[0], w = q[1];
            std::uint32_t& id = global[static_cast<std::size_t>(i)];
            if (i >= nb) {
                id = add_point(q);
                continue;
            }
            // A boundary point of the triangle's (u, v) domain: a corner or a point of an edge.
            int corner_k = -1;
            if (u < eps && w < eps) corner_k = 0;
            else if (u > 1.0 - eps && w < eps) corner_k = 1;
            else if (u < eps && w > 1.0 - eps) corner_k = 2;
            if (corner_k >= 0) {
                std::uint32_t& cid = corner[v[corner_k]];
                if (cid == UINT32_MAX) cid = add_point(q);
                id = cid;
                continue;
            }
            int e;
            double along;  // from the edge's first vertex (in this face's order)
            if (w < eps) e = 0, along = u;
            else if (u < eps) e = 2, along = 1.0 - w;
            else e = 1, along = w;
            const std::uint32_t a = v[e], b = v[(e + 1) % 3];
            int k = static_cast<int>(std::lround(along * rates[e]));
            if (a > b) k = rates[e] - k;  // count from the lower vertex: both faces agree
            const auto key = std::make_tuple(std::min(a, b), std::max(a, b), k);
            auto it = edge_point.find(key);
            if (it == edge_point.end()) it = edge_point.emplace(key, add_point(q)).first;
            id = it->second;
        }
        facets.resize(3 * static_cast<std::size_t>(tess.GetNumFacets()));
        tess.GetFacets(facets.data());
        for (int f : facets) r.triangles.push_back(global[static_cast<std::size_t>(f)]);
    }
    r.fine_vertices = r.stencil_offsets.size() - 1;
    return r;
}

}  // namespace

Creases crest_creases(std::span<const float> p, std::span<const std::uint32_t> tri, double per_metre, double max) {
    Creases c;
    if (!(per_metre > 0.0)) return c;
    std::map<std::pair<std::uint32_t, std::uint32_t>, bool> seen;
    for (std::size_t t = 0; 3 * t + 2 < tri.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = tri[3 * t + static_cast<std::size_t>(k)], b = tri[3 * t + static_cast<std::size_t>((k + 1) % 3)];
            const float za = p[3 * std::size_t{a} + 2], zb = p[3 * std::size_t{b} + 2];
            if (!(za > 0.0f && zb > 0.0f) || !seen.emplace(std::minmax(a, b), true).second) continue;
            const auto [lo, hi] = std::minmax(a, b);
            c.edges.insert(c.edges.end(), {lo, hi});
            c.sharpness.push_back(static_cast<float>(std::min(max, per_metre * 0.5 * (double{za} + zb))));
        }
    return c;
}

double refined_triangle_estimate(std::size_t coarse_triangles, const RefineOptions& options) noexcept {
    return refined_triangles(coarse_triangles, options.scheme, options.level);
}

Refinement plan_refinement(std::size_t vertex_count, std::span<const std::uint32_t> triangles, const RefineOptions& o,
                           std::size_t max_vertices, const AdaptiveCriteria* adaptive, const Creases* creases) {
    if (o.level < 1 || o.level > 6) throw InputError("refine: level must be 1 … 6, got " + std::to_string(o.level));
    const std::size_t nt = triangles.size() / 3;
    if (triangles.size() % 3 != 0 || nt == 0) throw InputError("refine: no triangles to refine");
    for (std::uint32_t v : triangles)
        if (v >= vertex_count) throw InputError("refine: triangle index " + std::to_string(v) + " >= " + std::to_string(vertex_count));
    if (o.adaptive && o.scheme != RefineScheme::loop)
        throw InputError("refine: adaptive refinement tessellates triangles: use the loop scheme");
    if (o.adaptive && !adaptive) throw InputError("refine: adaptive refinement needs its criteria (sampled normals, camera)");
    if (o.adaptive && !(o.max_angle_degrees >= 0.0 && o.near_distance >= 0.0))
        throw InputError("refine: max_angle_degrees and near_distance must be >= 0");
    // Refuse before OpenSubdiv allocates: a triangle mesh has about half as many
    // vertices as triangles.
    const double fine_estimate = o.adaptive ? 0.0 : 0.5 * refined_triangles(nt, o.scheme, o.level);
    if (fine_estimate > static_cast<double>(max_vertices)) {
        int fits = 0;
        while (fits < o.level && 0.5 * refined_triangles(nt, o.scheme, fits + 1) <= static_cast<double>(max_vertices)) ++fits;
        throw LimitError("refine: level " + std::to_string(o.level) + " would make about " +
                         std::to_string(static_cast<long long>(fine_estimate)) + " vertices (limit " +
                         std::to_string(max_vertices) + "); use level " + std::to_string(fits) +
                         (fits == 0 ? " (no refinement)" : "") + " or a coarser surface");
    }

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);  // the domain's edges stay put
    sdc.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_ALL);
    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(vertex_count);
    desc.numFaces = static_cast<int>(nt);
    const std::vector<int> per_face(nt, 3);
    const std::vector<int> indices(triangles.begin(), triangles.end());
    desc.numVertsPerFace = per_face.data();
    desc.vertIndicesPerFace = indices.data();
    std::vector<int> crease_pairs;
    if (creases && !creases->sharpness.empty()) {
        if (o.adaptive) throw InputError("refine: crest sharpness needs uniform refinement (not adaptive)");
        if (creases->edges.size() != 2 * creases->sharpness.size()) throw InputError("refine: creases need 2 vertices each");
        crease_pairs.assign(creases->edges.begin(), creases->edges.end());
        desc.numCreases = static_cast<int>(creases->sharpness.size());
        desc.creaseVertexIndexPairs = crease_pairs.data();
        desc.creaseWeights = creases->sharpness.data();
    }
    const Sdc::SchemeType scheme = o.scheme == RefineScheme::loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Create(
        desc, Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Options(scheme, sdc)));
    if (!refiner) throw InputError("refine: OpenSubdiv rejected the surface's topology (non-manifold?)");
    if (o.adaptive) return adaptive_refinement(*refiner, vertex_count, triangles, o, max_vertices, *adaptive);
    Far::TopologyRefiner::UniformOptions uniform(o.level);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);

    // The Real<float> factory itself: Far::StencilTableFactory::Create downcasts its
    // StencilTableReal<float> to StencilTable, which UBSan reports (OpenSubdiv 3.5).
    using Factory = Far::StencilTableFactoryReal<float>;
    Factory::Options so;
    so.generateOffsets = true;
    so.generateIntermediateLevels = false;  // the last level only, from the coarse vertices
    std::unique_ptr<const Far::StencilTableReal<float>> table(Factory::Create(*refiner, so));

    Refinement r;
    r.coarse_vertices = vertex_count;
    r.fine_vertices = static_cast<std::size_t>(table->GetNumStencils());
    const auto& sizes = table->GetSizes();
    const auto& idx = table->GetControlIndices();
    const auto& w = table->GetWeights();
    r.stencil_offsets.resize(r.fine_vertices + 1, 0);
    for (std::size_t v = 0; v < r.fine_vertices; ++v) r.stencil_offsets[v + 1] = r.stencil_offsets[v] + static_cast<std::uint32_t>(sizes[v]);
    r.stencil_indices.assign(idx.begin(), idx.end());
    r.stencil_weights.assign(w.begin(), w.end());

    const Far::TopologyLevel& last = refiner->GetLevel(o.level);
    r.triangles.reserve(static_cast<std::size_t>(refined_triangles(nt, o.scheme, o.level)) * 3);
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = last.GetFaceVertices(f);
        // Faces keep the coarse orientation; a quad (Catmull–Clark) splits along 0–2.
        for (int k = 1; k + 1 < fv.size(); ++k)
            r.triangles.insert(r.triangles.end(), {static_cast<std::uint32_t>(fv[0]), static_cast<std::uint32_t>(fv[k]),
                                                   static_cast<std::uint32_t>(fv[k + 1])});
    }
    return r;
}

void apply_refinement(const Refinement& r, std::span<const float> coarse, std::size_t c, std::span<float> fine) {
    apply<float>(r, coarse, c, fine);
}

void apply_refinement(const Refinement& r, std::span<const double> coarse, std::size_t c, std::span<double> fine) {
    apply<double>(r, coarse, c, fine);
}

}  // namespace wave
