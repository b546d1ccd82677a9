// Uniform subdivision of any libwave surface with OpenSubdiv (Ts'o–Barsky §5: refine
// the surface; DESIGN.md: topology refined once, stencils applied per frame). The only
// translation unit that includes OpenSubdiv.
#include "libwave/errors.h"
#include "libwave/surface.h"

#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <string>
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

}  // namespace

Refinement plan_refinement(std::size_t vertex_count, std::span<const std::uint32_t> triangles, const RefineOptions& o,
                           std::size_t max_vertices) {
    if (o.level < 1 || o.level > 6) throw InputError("refine: level must be 1 … 6, got " + std::to_string(o.level));
    const std::size_t nt = triangles.size() / 3;
    if (triangles.size() % 3 != 0 || nt == 0) throw InputError("refine: no triangles to refine");
    for (std::uint32_t v : triangles)
        if (v >= vertex_count) throw InputError("refine: triangle index " + std::to_string(v) + " >= " + std::to_string(vertex_count));
    // Refuse before OpenSubdiv allocates: a triangle mesh has about half as many
    // vertices as triangles.
    const double fine_estimate = 0.5 * refined_triangles(nt, o.scheme, o.level);
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
    const Sdc::SchemeType scheme = o.scheme == RefineScheme::loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Create(
        desc, Far::TopologyRefinerFactory<Far::TopologyDescriptor>::Options(scheme, sdc)));
    if (!refiner) throw InputError("refine: OpenSubdiv rejected the surface's topology (non-manifold?)");
    Far::TopologyRefiner::UniformOptions uniform(o.level);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);

    Far::StencilTableFactory::Options so;
    so.generateOffsets = true;
    so.generateIntermediateLevels = false;  // the last level only, from the coarse vertices
    std::unique_ptr<const Far::StencilTable> table(Far::StencilTableFactory::Create(*refiner, so));

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
