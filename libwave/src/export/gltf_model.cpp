// ModelWriter: a glTF model with one buffer, the shared index and TEXCOORD_0 accessors,
// a frame's primitives (plain, quantised, meshopt or Draco; a far-field skirt's part on
// grids of its own), nodes, the scene's dressing, and the model's JSON.
#include "gltf_model.h"

#include "normalised.h"

#include <cmath>
#include <map>
#include <numbers>

namespace wave::detail {

FrameArrays frame_arrays(const MorphAnimationView& a, std::size_t f) {
    const std::size_t n = a.vertex_count;
    FrameArrays out;
    std::vector<float> p(3 * n), q(3 * n);
    for (std::size_t v = 0; v < n; ++v) {
        to_y_up(&a.positions[3 * (f * n + v)], &p[3 * v]);
        to_y_up(&a.normals[3 * (f * n + v)], &q[3 * v]);
    }
    out.attributes.emplace_back("POSITION", TINYGLTF_TYPE_VEC3, std::move(p));
    out.attributes.emplace_back("NORMAL", TINYGLTF_TYPE_VEC3, std::move(q));
    const auto slice = [&](std::span<const float> c, std::size_t width) {
        return std::vector<float>(c.begin() + static_cast<std::ptrdiff_t>(width * f * n),
                                  c.begin() + static_cast<std::ptrdiff_t>(width * (f + 1) * n));
    };
    if (!a.colors.empty()) out.attributes.emplace_back("COLOR_0", TINYGLTF_TYPE_VEC3, slice(a.colors, 3));
    if (a.reflect.empty()) return out;
    if (a.layout == ScalarLayout::custom) {
        out.attributes.emplace_back("_REFLECT", TINYGLTF_TYPE_SCALAR, slice(a.reflect, 1));
        out.attributes.emplace_back("_REFRACT", TINYGLTF_TYPE_SCALAR, slice(a.refract, 1));
        out.attributes.emplace_back("_FOAM", TINYGLTF_TYPE_SCALAR, slice(a.foam, 1));
    } else {
        std::vector<float> uv1(2 * n), uv2(2 * n, 0.0f);
        for (std::size_t v = 0; v < n; ++v) {
            uv1[2 * v] = a.reflect[f * n + v];
            uv1[2 * v + 1] = a.refract[f * n + v];
            uv2[2 * v] = a.foam[f * n + v];
        }
        out.attributes.emplace_back("TEXCOORD_1", TINYGLTF_TYPE_VEC2, std::move(uv1));
        out.attributes.emplace_back("TEXCOORD_2", TINYGLTF_TYPE_VEC2, std::move(uv2));
    }
    return out;
}

ModelWriter::ModelWriter(const MorphAnimationView& a, std::size_t frames, std::FILE* file, std::string path, bool morph_targets)
    : dressing(a.dressing) {
    model.buffers.emplace_back();
    if (file) {
        sink.file = file;
        sink.path = std::move(path);
    } else {
        sink.memory = &memory;
        const std::size_t per_vertex = 4 * (3 + 3 + 2 + 4 + (a.colors.empty() ? 0 : 3));
        memory.reserve(frames * a.vertex_count * per_vertex + a.triangles.size_bytes() + 8 * a.vertex_count +
                       4 * frames * frames + (1 << 16));
    }
    model.asset.version = "2.0";
    model.asset.generator = "libwave";
    // What a reader (read_animation, `wave convert`) needs that glTF has no field for.
    tinygltf::Value::Object info;
    info["fps"] = tinygltf::Value(a.fps);
    info["first_frame"] = tinygltf::Value(static_cast<int>(a.first_frame));
    info["loop_frames"] = tinygltf::Value(static_cast<int>(a.loop_frames));
    info["name"] = tinygltf::Value(a.name);
    info["scene"] = tinygltf::Value(a.scene);
    if (!a.run_key.empty()) info["run_key"] = tinygltf::Value(a.run_key);
    tinygltf::Value::Object extras;
    extras["libwave"] = tinygltf::Value(info);
    model.asset.extras = tinygltf::Value(extras);
    if (a.draco) return;  // every primitive carries its own compressed indices and UVs
    if (a.meshopt) {
        b.meshopt = true;
        position_steps = meshopt_position_steps(a);
        model.extensionsUsed.push_back("EXT_meshopt_compression");
        model.extensionsRequired.push_back("EXT_meshopt_compression");
        indices = b.accessor(b.compressed_view(encoded_triangles(a.triangles), a.triangles.size(), 4,
                                               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, detail::MeshoptMode::triangles,
                                               detail::MeshoptFilter::none),
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, a.triangles.size(), TINYGLTF_TYPE_SCALAR);
        texcoord0 = floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, std::vector<float>(a.texcoords.begin(), a.texcoords.end()));
        return;
    }
    if (a.quantize) {
        if (!morph_targets) split = split_skirt(a.texcoords, a.triangles, a.vertex_count);
        std::span<const std::uint32_t> domain;  // the vertices the grid spans (empty: all)
        if (split) domain = (*split)[0].vertices;
        quant = quantization_for(a, morph_targets, domain);
        model.extensionsUsed.push_back("KHR_mesh_quantization");
        model.extensionsRequired.push_back("KHR_mesh_quantization");
    }
    if (split) {
        for (std::size_t k = 0; k < 2; ++k) {
            const std::vector<std::uint32_t>& t = (*split)[k].triangles;
            part_indices[k] = b.accessor(b.view(t.data(), t.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, t.size(), TINYGLTF_TYPE_SCALAR);
            const std::vector<float> uv = gather(a.texcoords, 2, (*split)[k].vertices);
            // The skirt's rest positions lie beyond [0, 1]², which normalised uint16 cannot hold.
            part_texcoord0[k] = k == 0 ? floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, uv) : plain(TINYGLTF_TYPE_VEC2, uv);
        }
        return;
    }
    indices = b.accessor(b.view(a.triangles.data(), a.triangles.size_bytes(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                         TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, a.triangles.size(), TINYGLTF_TYPE_SCALAR);
    // A far-field skirt's rest positions lie beyond [0, 1]², which normalised uint16
    // would clamp onto the domain's edge (the quantised morph form's skirt then read
    // as domain: the viewer framed 160 km of it): they stay float.
    std::vector<float> uv(a.texcoords.begin(), a.texcoords.end());
    const bool beyond = std::any_of(uv.begin(), uv.end(), [](float t) { return t < 0.0f || t > 1.0f; });
    texcoord0 = quant && beyond ? plain(TINYGLTF_TYPE_VEC2, uv) : floats("TEXCOORD_0", TINYGLTF_TYPE_VEC2, uv);
}

std::vector<float> ModelWriter::gather(std::span<const float> source, std::size_t width, const std::vector<std::uint32_t>& vertices) {
    std::vector<float> out(width * vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
        std::copy_n(source.begin() + static_cast<std::ptrdiff_t>(width * vertices[i]), width, out.begin() + static_cast<std::ptrdiff_t>(width * i));
    return out;
}

template <class Int>
int ModelWriter::normalised(const std::vector<float>& values, std::size_t width, std::size_t stride, int component, int type, const std::function<double(std::size_t, std::size_t)>& encode, bool bounds, bool target) {
    const std::size_t count = values.size() / width;
    std::vector<Int> q(count * stride, 0);
    std::vector<double> lo(width, std::numeric_limits<double>::infinity()), hi(width, -std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < count; ++v)
        for (std::size_t c = 0; c < width; ++c) {
            const Int x = detail::nearest<Int>(encode(v, c));
            q[v * stride + c] = x;
            lo[c] = std::min(lo[c], static_cast<double>(x)), hi[c] = std::max(hi[c], static_cast<double>(x));
        }
    return b.stored(q.data(), width * sizeof(Int), stride * sizeof(Int), count, component, type, true,
                    bounds ? lo : std::vector<double>{}, bounds ? hi : std::vector<double>{}, target);
}

int ModelWriter::meshopt_floats(const std::string& name, int type, const std::vector<float>& values) {
    const std::size_t width = components_of(type), count = values.size() / width;
    std::array<int, 3> steps = position_steps;
    if (name != "POSITION") steps.fill(name == "NORMAL" ? -15 : name == "TEXCOORD_0" ? -21 : -17);
    std::vector<std::uint32_t> words(values.size());
    std::vector<float> decoded(values.size());
    detail::encode_exponential(values, width, std::span<const int>(steps.data(), width), words, decoded);
    std::vector<double> lo, hi;
    if (name == "POSITION") {
        lo.assign(3, std::numeric_limits<double>::infinity());
        hi.assign(3, -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < decoded.size(); ++i)
            lo[i % 3] = std::min(lo[i % 3], double{decoded[i]}), hi[i % 3] = std::max(hi[i % 3], double{decoded[i]});
    }
    const int view = b.compressed_view(detail::meshopt_encode_attributes(words.data(), count, 4 * width), count, 4 * width,
                                       TINYGLTF_TARGET_ARRAY_BUFFER, detail::MeshoptMode::attributes,
                                       detail::MeshoptFilter::exponential);
    return b.accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, count, type, std::move(lo), std::move(hi));
}

int ModelWriter::floats(const std::string& name, int type, const std::vector<float>& values, bool target) {
    if (b.meshopt) return meshopt_floats(name, type, values);
    if (quant && name == "POSITION" && quant->float_base && !target) {
        std::vector<float> scaled(values.size());
        for (std::size_t i = 0; i < values.size(); ++i)
            scaled[i] = static_cast<float>((values[i] - quant->origin[i % 3]) / quant->scale);
        return b.vec3(scaled, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    }
    if (quant && name == "POSITION") {
        const Quantization& qz = *quant;
        return normalised<std::int16_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                        [&](std::size_t v, std::size_t c) {
                                            return target ? values[3 * v + c] / qz.scale * 32767.0 : qz.steps(values[3 * v + c], c);
                                        }, true, target);
    }
    if (quant && name == "NORMAL" && !target)
        return normalised<std::int8_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC3,
                                       [&](std::size_t v, std::size_t c) { return values[3 * v + c] * 127.0; }, false, false);
    if (quant && name == "NORMAL")  // the part within ±1 (normal_overflow holds the rest)
        return normalised<std::int16_t>(values, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                        [&](std::size_t v, std::size_t c) {
                                            return std::clamp(double{values[3 * v + c]}, -1.0, 1.0) * 32767.0;
                                        }, false, true);
    if (quant && name.rfind("TEXCOORD_", 0) == 0) {
        if (target)
            return normalised<std::int16_t>(values, 2, 2, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC2,
                                            [&](std::size_t v, std::size_t c) { return values[2 * v + c] * 32767.0; }, false, true);
        return normalised<std::uint16_t>(values, 2, 2, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2,
                                         [&](std::size_t v, std::size_t c) { return values[2 * v + c] * 65535.0; }, false, false);
    }
    if (name == "POSITION" && !target) return b.vec3(values, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    if (name != "POSITION") return plain(type, values, target);
    // A position target's bounds (the validator checks them).
    std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < values.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], double{values[i]});
        hi[i % 3] = std::max(hi[i % 3], double{values[i]});
    }
    return b.stored(values.data(), 3 * sizeof(float), 3 * sizeof(float), values.size() / 3, TINYGLTF_COMPONENT_TYPE_FLOAT,
                    type, false, std::move(lo), std::move(hi), target);
}

int ModelWriter::plain(int type, const std::vector<float>& values, bool target) {
    const std::size_t width = components_of(type);
    return b.stored(values.data(), width * sizeof(float), width * sizeof(float), values.size() / width,
                    TINYGLTF_COMPONENT_TYPE_FLOAT, type, false, {}, {}, target);
}

int ModelWriter::skirt_positions(std::vector<float> values, const std::vector<char>& seam) {
    const Quantization& qz = *quant;
    for (std::size_t i = 0; i < values.size(); ++i) {
        const std::size_t c = i % 3;
        if (!seam[i / 3]) {
            values[i] = static_cast<float>(qz.in_node(values[i], c));
            continue;
        }
        values[i] = static_cast<float>(detail::snorm16(detail::nearest<std::int16_t>(qz.steps(values[i], c))));
    }
    return b.vec3(values, TINYGLTF_TARGET_ARRAY_BUFFER, true);
}

int ModelWriter::normal_overflow(const std::vector<float>& delta) {
    std::vector<float> excess(delta.size());
    bool any = false;
    for (std::size_t i = 0; i < delta.size(); ++i) {
        excess[i] = delta[i] - std::clamp(delta[i], -1.0f, 1.0f);
        any = any || excess[i] != 0.0f;
    }
    if (!any) return -1;
    return normalised<std::int16_t>(excess, 3, 4, TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_TYPE_VEC3,
                                    [&](std::size_t v, std::size_t c) { return excess[3 * v + c] * 32767.0; }, false, true);
}

tinygltf::Primitive ModelWriter::primitive(const FrameArrays& frame) {
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = indices;
    prim.attributes["TEXCOORD_0"] = texcoord0;
    for (const auto& [name, type, values] : frame.attributes) prim.attributes[name] = floats(name, type, values);
    return prim;
}

tinygltf::Primitive ModelWriter::draco_primitive(const MorphAnimationView& a, const FrameArrays& frame, bool keep_order) {
    std::vector<detail::DracoInput> inputs{{"TEXCOORD_0", 2, a.texcoords}};
    for (const auto& [name, type, values] : frame.attributes)
        inputs.push_back({name, static_cast<int>(components_of(type)), values});
    return draco_primitive(a.triangles, a.vertex_count, inputs, draco_bits_for_reach(*a.draco, a.texcoords, inputs), keep_order);
}

tinygltf::Primitive ModelWriter::draco_primitive(std::span<const std::uint32_t> triangles, std::size_t vertex_count, const std::vector<detail::DracoInput>& inputs, const DracoOptions& options, bool keep_order, const detail::DracoGrid* grid) {
    const detail::DracoOutput encoded = detail::draco_encode(triangles, vertex_count, inputs, options, keep_order, grid);
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.indices = b.accessor(-1, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, triangles.size(), TINYGLTF_TYPE_SCALAR);
    tinygltf::Value::Object ids;
    for (const detail::DracoInput& in : inputs) {
        std::vector<double> lo, hi;
        if (in.name == "POSITION") {
            lo.assign(3, std::numeric_limits<double>::infinity());
            hi.assign(3, -std::numeric_limits<double>::infinity());
            for (std::size_t i = 0; i < in.values.size(); ++i) {
                lo[i % 3] = std::min(lo[i % 3], double{in.values[i]});
                hi[i % 3] = std::max(hi[i % 3], double{in.values[i]});
            }
        }
        const int type = in.components == 3 ? TINYGLTF_TYPE_VEC3 : in.components == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_SCALAR;
        prim.attributes[in.name] = b.accessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, vertex_count, type, lo, hi);
        ids[in.name] = tinygltf::Value(encoded.ids.at(in.name));
    }
    tinygltf::Value::Object ext;
    ext["bufferView"] = tinygltf::Value(b.view(encoded.bytes.data(), encoded.bytes.size(), 0));
    ext["attributes"] = tinygltf::Value(ids);
    prim.extensions["KHR_draco_mesh_compression"] = tinygltf::Value(ext);
    if (model.extensionsUsed.empty()) {
        model.extensionsUsed.push_back("KHR_draco_mesh_compression");
        model.extensionsRequired.push_back("KHR_draco_mesh_compression");
    }
    return prim;
}

std::vector<tinygltf::Primitive> ModelWriter::draco_split_primitives(const MorphAnimationView& a, const FrameArrays& frame, const std::array<SkirtPart, 2>& parts) {
    std::span<const float> all;  // POSITION, glTF axes
    for (const auto& [name, type, values] : frame.attributes)
        if (name == "POSITION") all = values;
    const DracoLattice lattice = split_steps(all, parts, a.draco->position_bits);
    frame_unit = lattice.unit;
    std::vector<tinygltf::Primitive> out;
    for (std::size_t k = 0; k < 2; ++k) {
        const SkirtPart& part = parts[k];
        const std::size_t n = part.vertices.size();
        std::vector<std::vector<float>> values;  // per input, the part's vertices
        std::vector<detail::DracoInput> inputs;
        values.reserve(frame.attributes.size() + 1);
        const auto add = [&](std::string name, std::size_t components, std::span<const float> source) {
            values.push_back(gather(source, components, part.vertices));  // reserved: earlier spans stay valid
            inputs.push_back({std::move(name), static_cast<int>(components), values.back()});
        };
        add("TEXCOORD_0", 2, a.texcoords);
        for (const auto& [name, type, source] : frame.attributes) add(name, components_of(type), source);
        std::vector<float>& positions = values[static_cast<std::size_t>(std::distance(
            inputs.begin(), std::find_if(inputs.begin(), inputs.end(), [](const auto& in) { return in.name == "POSITION"; })))];
        for (float& x : positions) x = static_cast<float>(x / lattice.unit);  // exact: a power of two
        const detail::DracoGrid grid =
            snap_to_lattice(positions, part.seam, k == 0 ? lattice.domain : lattice.skirt, lattice.skirt);
        DracoOptions options = *a.draco;
        options.texcoord_bits = draco_bits_for_reach(options, inputs[0].values, inputs).texcoord_bits;
        out.push_back(draco_primitive(part.triangles, n, inputs, options, false, &grid));
    }
    return out;
}

std::vector<tinygltf::Primitive> ModelWriter::split_primitives(const FrameArrays& frame) {
    std::vector<tinygltf::Primitive> out(2);
    for (std::size_t k = 0; k < 2; ++k) {
        const SkirtPart& part = (*split)[k];
        tinygltf::Primitive& prim = out[k];
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.indices = part_indices[k];
        prim.attributes["TEXCOORD_0"] = part_texcoord0[k];
        for (const auto& [name, type, values] : frame.attributes) {
            std::vector<float> v = gather(values, components_of(type), part.vertices);
            prim.attributes[name] = k == 1 && name == "POSITION" ? skirt_positions(std::move(v), part.seam) : floats(name, type, v);
        }
    }
    return out;
}

std::vector<tinygltf::Primitive> ModelWriter::frame_primitives(const MorphAnimationView& a, std::size_t f) {
    const FrameArrays frame = frame_arrays(a, f);
    frame_unit = 1.0;
    if (split) return split_primitives(frame);
    if (!a.draco) return {primitive(frame)};
    if (const std::optional<std::array<SkirtPart, 2>> parts = split_skirt(a.texcoords, a.triangles, a.vertex_count))
        return draco_split_primitives(a, frame, *parts);
    return {draco_primitive(a, frame)};
}

int ModelWriter::node(const std::string& name, int mesh) {
    tinygltf::Node n;
    n.name = name;
    n.mesh = mesh;
    if (quant) {  // undoes the position quantisation
        if (!quant->float_base) n.translation = {quant->origin[0], quant->origin[1], quant->origin[2]};
        n.scale = {quant->scale, quant->scale, quant->scale};
    } else if (frame_unit != 1.0) {  // a Draco frame in units below the metre (DracoLattice)
        n.scale = {frame_unit, frame_unit, frame_unit};
    }
    model.nodes.push_back(n);
    return static_cast<int>(model.nodes.size() - 1);
}

void ModelWriter::dress(const SceneDressing& d, std::vector<int>& roots) {
    const auto add_root = [&](tinygltf::Node n) {
        model.nodes.push_back(std::move(n));
        roots.push_back(static_cast<int>(model.nodes.size() - 1));
    };
    if (d.water_material) {
        tinygltf::Material water;
        water.name = "water";
        water.doubleSided = true;
        water.pbrMetallicRoughness.baseColorFactor = {0.02, 0.12, 0.16, 1.0};
        water.pbrMetallicRoughness.metallicFactor = 0.0;
        water.pbrMetallicRoughness.roughnessFactor = 0.05;
        tinygltf::Value::Object transmission, ior;
        transmission["transmissionFactor"] = tinygltf::Value(1.0);
        ior["ior"] = tinygltf::Value(1.333);
        water.extensions["KHR_materials_transmission"] = tinygltf::Value(transmission);
        water.extensions["KHR_materials_ior"] = tinygltf::Value(ior);
        model.materials.push_back(water);
        for (tinygltf::Mesh& m : model.meshes)
            for (tinygltf::Primitive& prim : m.primitives) prim.material = static_cast<int>(model.materials.size() - 1);
        model.extensionsUsed.push_back("KHR_materials_transmission");
        model.extensionsUsed.push_back("KHR_materials_ior");
    }
    if (!d.seafloor_triangles.empty()) {
        const std::size_t n = d.seafloor_positions.size() / 3;
        std::vector<float> p(3 * n);
        for (std::size_t v = 0; v < n; ++v) to_y_up(&d.seafloor_positions[3 * v], &p[3 * v]);
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        prim.attributes["POSITION"] = b.vec3(p, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        std::vector<float> c(d.seafloor_colors.begin(), d.seafloor_colors.end());
        prim.attributes["COLOR_0"] = b.vec3(c, TINYGLTF_TARGET_ARRAY_BUFFER, false);
        if (d.seafloor_texcoords.size() == 2 * n) {
            std::vector<float> uv(d.seafloor_texcoords.begin(), d.seafloor_texcoords.end());
            prim.attributes["TEXCOORD_0"] = b.accessor(b.view(uv.data(), uv.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER),
                                                       TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC2);
        }
        prim.indices = b.accessor(b.view(d.seafloor_triangles.data(), d.seafloor_triangles.size_bytes(),
                                         TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, d.seafloor_triangles.size(), TINYGLTF_TYPE_SCALAR);
        tinygltf::Material sand;
        sand.name = "seafloor";
        sand.pbrMetallicRoughness.metallicFactor = 0.0;
        sand.pbrMetallicRoughness.roughnessFactor = 0.9;  // base colour white: COLOR_0 is the colour
        tinygltf::Value::Object extras;
        if (!d.caustic_images.empty()) {
            tinygltf::Value::Object caustics;
            caustics["images"] = tinygltf::Value(d.caustic_images);
            caustics["frames"] = tinygltf::Value(static_cast<int>(d.caustic_frames));
            caustics["fps"] = tinygltf::Value(d.caustic_fps);
            caustics["texCoord"] = tinygltf::Value(0);
            caustics["full_scale"] = tinygltf::Value(d.caustic_full_scale);
            extras["libwave_caustics"] = tinygltf::Value(caustics);
        }
        if (!d.sunbeam_volumes.empty()) {
            tinygltf::Value::Object sunbeams;
            sunbeams["volumes"] = tinygltf::Value(d.sunbeam_volumes);
            sunbeams["frames"] = tinygltf::Value(static_cast<int>(d.sunbeam_frames));
            sunbeams["fps"] = tinygltf::Value(d.sunbeam_fps);
            sunbeams["grid"] = tinygltf::Value(std::string("sunlight"));
            sunbeams["attenuation"] = tinygltf::Value(d.sunbeam_attenuation);
            const std::array<double, 3>& t = d.sunbeam_direction;
            sunbeams["direction"] = tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(t[0]), tinygltf::Value(t[2]), tinygltf::Value(-t[1])});
            extras["libwave_sunbeams"] = tinygltf::Value(sunbeams);
        }
        if (!extras.empty()) sand.extras = tinygltf::Value(extras);
        model.materials.push_back(sand);
        prim.material = static_cast<int>(model.materials.size() - 1);
        tinygltf::Mesh mesh;
        mesh.name = "seafloor";
        mesh.primitives.push_back(prim);
        model.meshes.push_back(mesh);
        tinygltf::Node node;
        node.name = "seafloor";
        node.mesh = static_cast<int>(model.meshes.size() - 1);
        add_root(std::move(node));
    }
    if (d.camera) {
        tinygltf::Camera cam;
        cam.name = "camera";
        cam.type = "perspective";
        cam.perspective.yfov = d.camera_yfov;
        cam.perspective.aspectRatio = d.camera_aspect;
        cam.perspective.znear = 0.05;
        cam.perspective.zfar = 1e5;  // tinygltf writes zfar even when 0 (infinite), which the validator refuses
        model.cameras.push_back(cam);
        const std::array<double, 3> eye = d.camera_position;
        tinygltf::Node node;
        node.name = "camera";
        node.camera = static_cast<int>(model.cameras.size() - 1);
        node.rotation.assign(d.camera_rotation.begin(), d.camera_rotation.end());
        node.translation = {eye[0], eye[2], -eye[1]};
        add_root(std::move(node));
    }
    if (d.sun) {
        tinygltf::Light sun;
        sun.name = "sun";
        sun.type = "directional";
        sun.intensity = 3.0;
        sun.color = {1.0, 0.96, 0.9};
        model.lights.push_back(sun);
        tinygltf::Node node;
        node.name = "sun";
        node.rotation.assign(d.sun_rotation.begin(), d.sun_rotation.end());  // a directional light shines along its −Z
        tinygltf::Value::Object light;
        light["light"] = tinygltf::Value(static_cast<int>(model.lights.size() - 1));
        node.extensions["KHR_lights_punctual"] = tinygltf::Value(light);
        add_root(std::move(node));
    }
}

std::string ModelWriter::finish(std::vector<int> roots) {
    if (dressing) dress(*dressing, roots);
    tinygltf::Scene scene;
    scene.nodes = roots;
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true))
        throw RuntimeError("glTF export: tinygltf could not serialise the model");
    const std::string glb = out.str();  // a GLB of the JSON chunk alone (the buffer's data is not in the model)
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    nlohmann::json doc = nlohmann::json::parse(glb.substr(20, length));
    doc["buffers"][0]["byteLength"] = sink.size;
    if (b.meshopt) {
        for (auto& [view, ext] : b.view_extensions) doc["bufferViews"][static_cast<std::size_t>(view)]["extensions"]["EXT_meshopt_compression"] = ext;
        doc["buffers"].push_back({{"byteLength", b.fallback}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    }
    return doc.dump();
}

}  // namespace wave::detail
