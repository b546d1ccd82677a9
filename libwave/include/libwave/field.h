/// \file
/// libwave — the refraction–diffraction wave field: the complex amplitude η̂(x, y) of a
/// time-harmonic wave train over the seafloor (η = Re(η̂ e^{−iωt})), from the mild-slope
/// equation in its wide-angle parabolic form, marched along the swell (docs/wave-field.md).
///
/// Rays give a swell's direction and phase well, but their amplitude comes from the
/// spacing of neighbours and goes to infinity where rays cross (caustics behind shoals,
/// islands and headlands). The field diffracts energy across rays and stays finite.
#pragma once

#include "libwave/bathymetry.h"
#include "libwave/trace.h"

#include <complex>
#include <cstddef>
#include <cstdint>
#include <string>
#include <span>
#include <vector>

namespace wave {

/// Options of solve_wave_field, with their defaults.
struct FieldOptions {
    /// Grid nodes per wavelength at the resolved depth (the shallowest depth the incident
    /// wave reaches before it breaks: H∞/γ, or min_resolved_depth when larger).
    double nodes_per_wavelength = 12.0;
    /// γ: breaking starts where H > γh (and H never exceeds γh).
    double breaker_index = 0.78;
    /// Γ: breaking stops where H falls below Γh (Dally, Dean & Dalrymple's stable height
    /// H_s = Γh, towards which the broken wave decays). In (0, 2]; taken as breaker_index
    /// where larger (the stop never above the onset).
    double stable_index = 0.4;
    /// K: Dally, Dean & Dalrymple's decay coefficient, d(E C_g)/dx = −(K/h)(E C_g − E_s C_g)
    /// in the surf zone. 0: no dissipation (saturated breaking alone, H = γh). In [0, 1].
    double breaking_decay = 0.15;
    /// Kirby & Dalrymple (1986)'s composite nonlinear dispersion (the wave's own height
    /// speeds it up over shallow water), iterated per step; false: linear dispersion.
    bool amplitude_dispersion = true;
    double min_resolved_depth = 0.0;  ///< m; shallower water is computed on the same grid
    /// The lateral edges of the marching grid: absorbing (a sponge two wavelengths wide,
    /// open sea beside the domain) or reflecting (walls, as in a wave basin).
    bool reflecting_edges = false;
    std::size_t max_nodes = 20'000'000;  ///< guard rail: LimitError above this
    /// The memory the grid may take (bytes; `wave field --max-memory-gb`, the run's limit
    /// for a wave-field scene): kFieldNodeBytes a node, checked before the grid is allocated.
    double max_bytes = 2e9;
};

/// What a node of the marching grid takes, solved and rasterised (its envelope, flags and
/// the raster's bands: measured 48 bytes at 75 M nodes).
inline constexpr double kFieldNodeBytes = 48.0;

/// Node flags.
enum : std::uint8_t {
    kFieldWet = 1,     ///< water (depth > 0)
    kFieldBroken = 2,  ///< in the surf zone: breaking (between onset H > γh and stop H < Γh)
};

/// One train's field on a grid aligned with the swell: node (i, j) lies at
/// (x0, y0) + i·dx·(ux, uy) + j·dy·(−uy, ux), i along the swell (the marching direction)
/// and j across it. η̂ = envelope · e^{i·phase_ref[i]}: the envelope varies slowly (it is
/// interpolated), the reference phase is Σ k̄ dx along the march.
struct WaveField {
    double x0 = 0.0;  ///< node (0, 0) in seafloor coordinates (m)
    double y0 = 0.0;  ///< node (0, 0) in seafloor coordinates (m)
    double ux = 1.0;  ///< the swell's direction (unit)
    double uy = 0.0;  ///< the swell's direction (unit)
    double dx = 0.0;  ///< node spacing along and across the swell (m)
    double dy = 0.0;  ///< node spacing along and across the swell (m)
    std::size_t nx = 0;  ///< nodes along and across
    std::size_t ny = 0;  ///< nodes along and across
    std::vector<std::complex<float>> envelope;  ///< ny · nx, row j then column i (m)
    std::vector<double> phase_ref;               ///< nx: reference phase at column i (rad)
    std::vector<std::uint8_t> flags;             ///< ny · nx
    double omega = 0.0;              ///< rad/s
    double incident_amplitude = 0.0; ///< A∞ (m)
    /// H0: the incident height where the wave enters the grid (the deepest node of the
    /// first column: 2 A∞ K_s there), the reference of H/H0.
    double incident_height = 0.0;
    std::size_t broken_nodes = 0;  ///< nodes in the surf zone (flagged kFieldBroken)
};

/// Solves the field of `train` over `seafloor` (Kirby's wide-angle parabolic mild-slope
/// model in Padé (1,1) form, marched with Crank–Nicolson; each row a tridiagonal solve
/// by LAPACK). The grid covers the seafloor's rectangle; outside it the edge depths
/// extend, so the incident wave enters from every upwave side. Land damps the wave
/// (no reflection). With amplitude_dispersion, k at each node follows Kirby &
/// Dalrymple's composite relation for the node's own |η̂| (a predictor–corrector per
/// column). Breaking: a row starts to break where H > γh, loses energy by Dally, Dean &
/// Dalrymple's law while it breaks, and stops where H < Γh (it re-forms behind a bar);
/// H never exceeds γh. Surf-zone nodes are flagged. The train is solved alone: with
/// several trains, each one's nonlinearity and breaking see its own height only
/// (docs/wave-field.md). Throws InputError for bad options or a dry seafloor, LimitError
/// above max_nodes.
WaveField solve_wave_field(const Seafloor& seafloor, const WaveTrain& train, const FieldOptions& options = {});

/// The field at a point of the seafloor's plane.
struct FieldSample {
    std::complex<double> eta;   ///< η̂ (m): |η̂| the amplitude, arg η̂ the phase
    double dir_x = 0.0;  ///< the local direction of travel (unit; ∇ arg η̂)
    double dir_y = 0.0;  ///< the local direction of travel (unit; ∇ arg η̂)
    bool wet = false;           ///< inside the grid and in water
    bool broken = false;        ///< limited by breaking at the nearest node
};

/// Samples the field: the envelope bilinearly, the reference phase linearly (exact for
/// a plane wave along the swell). Outside the grid: wet = false, η̂ = 0; a point within
/// 1e-9 of a cell outside it (a domain corner the rotated grid just covers, computed
/// another way) samples the grid's edge.
FieldSample sample_wave_field(const WaveField& field, double x, double y) noexcept;

/// Gives the fronts' points their amplitude from the field (|η̂| where the field has
/// water): the rays keep their direction and phase. Where the field broke, the larger
/// of the field's and the ray's own amplitude (the ray's says how far past breaking
/// the wave is, which breaker models read). Points on land and aground rays (on the
/// shoreline) keep theirs. Returns how many points took the field's.
std::size_t take_field_amplitudes(const WaveField& field, FrontSet& fronts) noexcept;

/// The same for Ts'o's rays: `fields[t]` is train t's field (RaySet::train).
std::size_t take_field_amplitudes(std::span<const WaveField> fields, RaySet& rays) noexcept;

/// The field resampled on a regular grid over the seafloor's rectangle (row 0 at y0,
/// the field's spacing): what `wave field` writes. NaN where there is no water.
struct FieldRaster {
    double x0 = 0.0;       ///< pixel (0, 0) (m)
    double y0 = 0.0;       ///< pixel (0, 0) (m)
    double spacing = 0.0;  ///< m between pixels
    std::size_t nx = 0;    ///< columns
    std::size_t ny = 0;    ///< rows
    std::vector<float> height_ratio;   ///< H/H0 (H = 2|η̂|, H0 = WaveField::incident_height)
    std::vector<float> phase;          ///< arg η̂ (rad, in (−π, π])
    std::vector<float> direction_deg;  ///< direction of travel, degrees from +x towards +y
    double incident_height = 0.0;      ///< H0 (m)
    float ratio_max = 0.0f;            ///< the largest H/H0
};
/// The field on the seafloor's grid, as FieldRaster describes.
FieldRaster rasterize_wave_field(const WaveField& field, const Seafloor& seafloor);

/// A GeoTIFF (GDAL) of the raster: bands H/H0, phase (rad), direction (degrees),
/// float32, NaN as no-data, the seafloor's frame in the metadata. Returns the bytes.
std::string field_geotiff(const FieldRaster& raster, const Seafloor& seafloor);

/// A PNG plot of H/H0 over the seafloor's rectangle, the depth contours drawn over it,
/// a labelled colour scale beside it (`title` above). Returns the bytes.
std::string field_plot_png(const FieldRaster& raster, const DepthContours& isobaths, const std::string& title);

}  // namespace wave
