// Buffer views through meshoptimizer's vertex and index codecs and its filters
// (EXT_meshopt_compression): what the writer compresses and the reader decodes.
#include "meshopt_codec.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace wave::detail {

const char* meshopt_mode_name(MeshoptMode m) noexcept {
    switch (m) {
        case MeshoptMode::attributes: return "ATTRIBUTES";
        case MeshoptMode::triangles: return "TRIANGLES";
        case MeshoptMode::indices: return "INDICES";
    }
    return "ATTRIBUTES";
}

const char* meshopt_filter_name(MeshoptFilter f) noexcept {
    switch (f) {
        case MeshoptFilter::none: return "NONE";
        case MeshoptFilter::octahedral: return "OCTAHEDRAL";
        case MeshoptFilter::quaternion: return "QUATERNION";
        case MeshoptFilter::exponential: return "EXPONENTIAL";
    }
    return "NONE";
}

void encode_exponential(std::span<const float> values, std::size_t width, std::span<const int> step_exponent,
                        std::span<std::uint32_t> words, std::span<float> decoded) {
    constexpr double kMantissa = 8388607.0;  // 2^23 − 1: the largest |m| of 24 signed bits
    // The decoder's exponent is a signed byte whose float scale must be normal.
    const auto clamp_exponent = [](int e) { return e < -126 ? -126 : e > 127 ? 127 : e; };
    const auto word = [&](std::size_t i, double m, int e) {
        const auto q = static_cast<std::int32_t>(m < -kMantissa ? -kMantissa : m > kMantissa ? kMantissa : m);
        words[i] = (static_cast<std::uint32_t>(q) & 0xFFFFFFu) | (static_cast<std::uint32_t>(e) << 24);
        decoded[i] = static_cast<float>(std::ldexp(static_cast<double>(q), e));
    };
    // Per component: the step's exponent, its scale and the largest value it holds.
    std::vector<int> exponent(width);
    std::vector<double> step(width), inverse(width), largest(width);
    for (std::size_t c = 0; c < width; ++c) {
        exponent[c] = clamp_exponent(step_exponent[c]);
        step[c] = std::ldexp(1.0, exponent[c]);
        inverse[c] = std::ldexp(1.0, -exponent[c]);
        largest[c] = (kMantissa - 0.5) * step[c];
    }
    for (std::size_t i = 0; i < values.size(); ++i) {
        const std::size_t c = i % width;
        const double v = values[i];
        if (std::abs(v) <= largest[c]) {  // the component's own step (powers of two: exact scaling)
            const double m = std::nearbyint(v * inverse[c]);
            const auto q = static_cast<std::int32_t>(m);
            words[i] = (static_cast<std::uint32_t>(q) & 0xFFFFFFu) | (static_cast<std::uint32_t>(exponent[c]) << 24);
            decoded[i] = static_cast<float>(m * step[c]);
            continue;
        }
        // Too large for that step: the smallest exponent at which the mantissa fits.
        int f = 0;
        std::frexp(v, &f);  // |v| < 2^f
        int e = clamp_exponent(f - 23);
        if (std::abs(std::nearbyint(std::ldexp(v, -e))) > kMantissa) e = clamp_exponent(e + 1);  // a rounding up to 2^23
        word(i, std::nearbyint(std::ldexp(v, -e)), e);
    }
}

std::string meshopt_encode_attributes(const void* data, std::size_t count, std::size_t stride) {
    std::string out(meshopt_encodeVertexBufferBound(count, stride), '\0');
    out.resize(meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(out.data()), out.size(), data, count, stride));
    return out;
}

std::string meshopt_encode_triangles(std::span<const std::uint32_t> indices) {
    std::size_t vertices = 0;
    for (const std::uint32_t i : indices) vertices = std::max<std::size_t>(vertices, std::size_t{i} + 1);
    std::string out(meshopt_encodeIndexBufferBound(indices.size(), vertices), '\0');
    out.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(out.data()), out.size(), indices.data(), indices.size()));
    return out;
}

std::string meshopt_decode(MeshoptMode mode, MeshoptFilter filter, std::size_t count, std::size_t stride,
                           std::span<const unsigned char> compressed, std::span<unsigned char> out) {
    if (out.size() != count * stride) return "its byteLength is not count × byteStride";
    int status = 0;
    switch (mode) {
        case MeshoptMode::attributes:
            if (stride == 0 || stride % 4 != 0 || stride > 256) return "ATTRIBUTES needs a byteStride of 4 … 256, a multiple of 4";
            status = meshopt_decodeVertexBuffer(out.data(), count, stride, compressed.data(), compressed.size());
            break;
        case MeshoptMode::triangles:
            if (stride != 2 && stride != 4) return "TRIANGLES needs a byteStride of 2 or 4";
            if (count % 3 != 0) return "TRIANGLES needs a count that is a multiple of 3";
            status = meshopt_decodeIndexBuffer(out.data(), count, stride, compressed.data(), compressed.size());
            break;
        case MeshoptMode::indices:
            if (stride != 2 && stride != 4) return "INDICES needs a byteStride of 2 or 4";
            status = meshopt_decodeIndexSequence(out.data(), count, stride, compressed.data(), compressed.size());
            break;
    }
    if (status != 0) return "the compressed stream does not decode (truncated, or other counts than the view's)";
    if (filter != MeshoptFilter::none && mode != MeshoptMode::attributes) return "a filter on indices";
    switch (filter) {
        case MeshoptFilter::none: break;
        case MeshoptFilter::octahedral:
            if (stride != 4 && stride != 8) return "the OCTAHEDRAL filter needs a byteStride of 4 or 8";
            meshopt_decodeFilterOct(out.data(), count, stride);
            break;
        case MeshoptFilter::quaternion:
            if (stride != 8) return "the QUATERNION filter needs a byteStride of 8";
            meshopt_decodeFilterQuat(out.data(), count, stride);
            break;
        case MeshoptFilter::exponential:
            if (stride % 4 != 0) return "the EXPONENTIAL filter needs a byteStride that is a multiple of 4";
            meshopt_decodeFilterExp(out.data(), count, stride);
            break;
    }
    return {};
}

}  // namespace wave::detail
