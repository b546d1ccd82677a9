// Internal to the bathymetry stage: turning raw file values into a validated grid.
#pragma once

#include "core/format.h"
#include "libwave/bathymetry.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace wave::detail {

/// Describes where grid node (i, j) sits in the file, for error messages.
using NodeLocator = std::function<std::string(std::size_t i, std::size_t j)>;

/// Throws LimitError when nx·ny exceeds options.max_nodes, InputError when the grid
/// has fewer than 2 nodes along an axis. Call before allocating.
void check_grid_size(const std::string& path, std::size_t nx, std::size_t ny,
                     const ReadOptions& options);

/// Nodes along a side of `extent` metres at `spacing` (floor(extent / spacing) + 1 +
/// `extra`), computed in double and refused (LimitError) before any integer cast when
/// it exceeds max_nodes or is not finite (a 1e300 m extent, a 1e-300 m spacing).
std::size_t nodes_along(const std::string& path, double extent, double spacing, std::size_t extra,
                        const ReadOptions& options);

/// Nodes that span `extent` at `spacing` or a little less: ceil(extent / spacing) + 1,
/// the first node on one end of the extent and the last on the other once the spacing is
/// shrunk to extent / (nodes − 1). Refused as nodes_along.
std::size_t nodes_spanning(const std::string& path, double extent, double spacing, const ReadOptions& options);

/// Converts raw values (grid order, j = 0 south) in place into elevations:
/// NODATA nodes (== nodata, or flagged in `missing`) are filled per the policy and
/// counted; NaN/Inf throws InputError naming the file and node; the rest become
/// sign · (value · scale + offset). Returns the NODATA count.
std::size_t convert_to_elevation(std::vector<double>& values, std::optional<double> nodata,
                                 const std::vector<char>& missing, ValueSign file_sign,
                                 const ReadOptions& options, const std::string& path,
                                 const NodeLocator& where, std::size_t nx);

}  // namespace wave::detail
