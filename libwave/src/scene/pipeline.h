// What the pipeline's parts share (plan.cpp, budgets.cpp, frames.cpp, dressing.cpp):
// internal, not part of the public scene.h.
#pragma once

#include "libwave/scene.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace wave::detail {

/// The triangles of the surface's own vertices (before any refinement): the model's,
/// and the skirt's when the far field continues it (plan.cpp).
const std::vector<std::uint32_t>& surface_triangles(const Scene& scene, const ScenePlan& p);

/// The wind sea's J₋ (the fold foam's field) at the coarse vertices, from its FFT
/// lattice: the patch's (N+1)² vertices copy it (`patch`), the rest sample it (plan.cpp).
void fold_at_vertices(const ScenePlan& plan, bool patch, std::span<const float> lattice_j, std::span<float> out);

/// How many frames of a chunk of `frames` run side by side, each on a run of its own
/// (budgets.cpp, docs/motion.md "Frames side by side"); 1: one after another.
std::size_t frame_lanes(const Scene& scene, std::size_t vertices, std::size_t frames);

/// TEXCOORD_0 of the animation's vertices: the rest position over the seafloor's
/// rectangle (dressing.cpp).
void rest_texcoords(const ScenePlan& plan, const Refinement* refined, SceneAnimation& a);

/// The seafloor mesh, camera, sun and material settings the single-file forms carry
/// beside the water (dressing.cpp).
void dress_animation(const Scene& scene, const ScenePlan& plan, SceneAnimation& a);

}  // namespace wave::detail
