// Internal to the export stage: buffer views through meshoptimizer's codecs
// (EXT_meshopt_compression, docs/export.md "Meshopt compression"). meshoptimizer's
// types stay in meshopt_codec.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace wave::detail {

/// EXT_meshopt_compression's modes and filters, as the extension spells them.
enum class MeshoptMode { attributes, triangles, indices };
enum class MeshoptFilter { none, octahedral, quaternion, exponential };
const char* meshopt_mode_name(MeshoptMode m) noexcept;
const char* meshopt_filter_name(MeshoptFilter f) noexcept;

/// The exponential filter with an exponent of its own per element and component:
/// value v becomes the 32-bit word (e << 24) | (m & 0xFFFFFF), decoded as m · 2^e
/// exactly. e is the smallest exponent ≥ `step_exponent[c]` (the coarsest step the
/// component allows: log2 of the step) at which m fits 24 signed bits, so the error
/// is at most 2^(step_exponent − 1) unless the value is too large for that step
/// (then 2^-24 of the value). `width` components per element, `values` a multiple of
/// it, `step_exponent.size() == width`. `decoded` (same size as `values`) gets the
/// floats a decoder returns. Preconditions: finite values; step exponents in [−100, 100].
void encode_exponential(std::span<const float> values, std::size_t width, std::span<const int> step_exponent,
                        std::span<std::uint32_t> words, std::span<float> decoded);

/// The vertex codec over `count` elements of `stride` bytes (stride a multiple of 4,
/// at most 256); the triangle-list index codec over `count` uint32 indices (a
/// multiple of 3). Deterministic: the same bytes for the same input.
std::string meshopt_encode_attributes(const void* data, std::size_t count, std::size_t stride);
std::string meshopt_encode_triangles(std::span<const std::uint32_t> indices);

/// Decodes one compressed view into `out` (count · stride bytes), then applies its
/// filter in place. Returns an empty string on success, otherwise what is wrong
/// (a stride the mode does not take, a stream that does not decode — truncated,
/// wrong counts —, a filter the stride does not allow).
std::string meshopt_decode(MeshoptMode mode, MeshoptFilter filter, std::size_t count, std::size_t stride,
                           std::span<const unsigned char> compressed, std::span<unsigned char> out);

}  // namespace wave::detail
