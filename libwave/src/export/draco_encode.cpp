// Draco compression of one primitive (KHR_draco_mesh_compression): positions,
// normals, UV maps, colours and custom scalars, quantised with the caller's bits.
#include "draco_encode.h"

#include "libwave/errors.h"

#include <draco/compression/config/compression_shared.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/metadata/geometry_metadata.h>

namespace wave::detail {

DracoOutput draco_encode(std::span<const std::uint32_t> triangles, std::size_t n,
                         const std::vector<DracoInput>& attributes, const DracoOptions& o, bool keep_order, const DracoGrid* position_grid) {
    draco::Mesh mesh;
    mesh.set_num_points(static_cast<draco::PointIndex::ValueType>(n));
    mesh.SetNumFaces(triangles.size() / 3);
    for (std::size_t t = 0; t < triangles.size() / 3; ++t)
        mesh.SetFace(draco::FaceIndex(static_cast<std::uint32_t>(t)),
                     {draco::PointIndex(triangles[3 * t]), draco::PointIndex(triangles[3 * t + 1]),
                      draco::PointIndex(triangles[3 * t + 2])});
    DracoOutput out;
    std::vector<std::pair<std::string, int>> local_ids;
    for (const DracoInput& in : attributes) {
        using T = draco::GeometryAttribute;
        T::Type type = T::GENERIC;
        if (in.name == "POSITION") type = T::POSITION;
        else if (in.name == "NORMAL") type = T::NORMAL;
        else if (in.name.rfind("TEXCOORD_", 0) == 0) type = T::TEX_COORD;
        else if (in.name.rfind("COLOR_", 0) == 0) type = T::COLOR;
        T att;
        att.Init(type, nullptr, static_cast<std::uint8_t>(in.components), draco::DT_FLOAT32, false,
                 static_cast<std::int64_t>(sizeof(float)) * in.components, 0);
        const int id = mesh.AddAttribute(att, true, static_cast<std::uint32_t>(n));
        draco::PointAttribute* pa = mesh.attribute(id);
        for (std::size_t v = 0; v < n; ++v)
            pa->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(v)),
                                  &in.values[static_cast<std::size_t>(in.components) * v]);
        if (type == T::GENERIC) {
            // Custom attributes are named through metadata (docs/build-notes.md).
            auto metadata = std::make_unique<draco::AttributeMetadata>();
            metadata->AddEntryString("name", in.name);
            mesh.AddAttributeMetadata(id, std::move(metadata));
        }
        out.ids[in.name] = static_cast<int>(pa->unique_id());
    }
    draco::Encoder encoder;
    if (position_grid)
        encoder.SetAttributeExplicitQuantization(draco::GeometryAttribute::POSITION, position_grid->bits, 3,
                                                 position_grid->origin.data(), position_grid->range);
    else
        encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, o.position_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, o.normal_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, o.texcoord_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::COLOR, o.color_bits);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, o.generic_bits);
    encoder.SetSpeedOptions(o.encode_speed, o.encode_speed);
    if (keep_order) encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodeMeshToBuffer(mesh, &buffer);
    if (!status.ok()) throw RuntimeError(std::string("Draco encoder: ") + status.error_msg());
    out.bytes.assign(buffer.data(), buffer.size());
    return out;
}

}  // namespace wave::detail
