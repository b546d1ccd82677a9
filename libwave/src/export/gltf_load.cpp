// Loading libwave's glTF outputs: the container and its chunks, the layout of buffers,
// views and accessors checked against the file before tinygltf parses it, the asset's
// extras, EXT_meshopt_compression's views unpacked, and the frames' views left in the file
// (LazyViews) while tinygltf loads the static ones.
#include "gltf_load.h"

#include "core/files.h"
#include "core/format.h"
#include "core/json_input.h"
#include "libwave/errors.h"
#include "libwave/io.h"

#include <draco/compression/decode.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <limits>
#include <optional>
#include <span>

namespace wave::detail {

namespace {

// `length` bytes of a file from `at` into `into` (the stream's state cleared first).
void read_at(std::ifstream& in, const std::string& path, std::size_t at, char* into, std::size_t length) {
    in.clear();
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(into, static_cast<std::streamsize>(length))) throw InputError(path + ": cannot read the file");
}

// The decoded bytes of a compressed view, or InputError naming the file and the view.
std::vector<unsigned char> decode_meshopt(const std::string& path, int view, const MeshoptView& m, std::span<const unsigned char> compressed) {
    std::vector<unsigned char> out(m.count * m.stride);
    const std::string error = detail::meshopt_decode(m.mode, m.filter, m.count, m.stride, compressed, out);
    if (!error.empty()) throw InputError(path + ": bufferView " + std::to_string(view) + " (EXT_meshopt_compression): " + error);
    return out;
}

// A glTF file's JSON and, for a .glb, where its BIN chunk's data lies: read without
// that data, the header and chunk lengths checked against the file.
struct Container {
    std::string json;
    std::size_t bin_at = 0, bin_length = 0;  // a .glb's BIN chunk data: file offset, length
};

Container read_container(const std::string& path, std::ifstream& in, std::uintmax_t size, bool binary) {
    const auto fail = [&](const std::string& what) { throw InputError(path + ": not a readable glTF 2.0 file: " + what); };
    Container c;
    if (!binary) {
        c.json.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        if (in.bad()) throw InputError(path + ": cannot read the file");
        return c;
    }
    const auto u32 = [](const char* at) {
        std::uint32_t v = 0;
        std::memcpy(&v, at, 4);
        return std::size_t{v};
    };
    char head[20];
    if (size < 20 || !in.read(head, 20) || std::memcmp(head, "glTF", 4) != 0 || u32(head + 8) != size)
        fail("the GLB header does not match the file");
    const std::size_t json_length = u32(head + 12);
    if (json_length > size - 20 || std::memcmp(head + 16, "JSON", 4) != 0) fail("the JSON chunk runs past the file");
    c.json.resize(json_length);
    if (!in.read(c.json.data(), static_cast<std::streamsize>(json_length))) throw InputError(path + ": cannot read the file");
    const std::size_t bin_at = 20 + json_length;
    char chunk[8];
    if (bin_at + 8 <= size) {
        if (!in.read(chunk, 8)) throw InputError(path + ": cannot read the file");
        c.bin_length = u32(chunk);
        if (c.bin_length > size - bin_at - 8) fail("the BIN chunk runs past the file");
        c.bin_at = bin_at + 8;
    }
    return c;
}

// `length` bytes of a file from `at` (a Draco view, a static view of a lazy read).
std::string file_bytes(std::ifstream& in, const std::string& path, std::size_t at, std::size_t length) {
    std::string out(length, '\0');
    read_at(in, path, at, out.data(), length);
    return out;
}

// The bytes an embedded buffer's data: URI holds, as tinygltf decodes it (base64 of
// application/octet-stream or application/gltf-buffer); nothing for any other data: URI.
std::optional<std::size_t> data_uri_bytes(const std::string& uri) {
    std::string_view payload;
    for (const std::string_view header : {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,"})
        if (uri.rfind(header, 0) == 0) payload = std::string_view(uri).substr(header.size());
    if (payload.empty() || payload.size() % 4 != 0) return std::nullopt;
    std::size_t pad = 0;
    while (pad < 2 && payload[payload.size() - 1 - pad] == '=') ++pad;
    for (std::size_t i = 0; i < payload.size() - pad; ++i) {
        const char c = payload[i];
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '+' && c != '/') return std::nullopt;
    }
    return payload.size() / 4 * 3 - pad;
}

// A .gltf's external buffer, as tinygltf finds it (its URI percent-decoded beside the
// .gltf): inside the .gltf's folder and a regular file, or InputError.
std::string buffer_file(const std::string& path, const std::string& uri, const std::string& what) {
    std::string decoded;
    const auto hex = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : (std::tolower(static_cast<unsigned char>(c)) - 'a' + 10) & 15; };
    for (std::size_t i = 0; i < uri.size(); ++i) {  // tinygltf's dlib::urldecode
        if (uri[i] == '+') decoded += ' ';
        else if (uri[i] == '%' && uri.size() > i + 2) decoded += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2])), i += 2;
        else decoded += uri[i];
    }
    const std::string file = path_inside(std::filesystem::path(path).parent_path().string(), decoded, path + ": " + what + "'s uri");
    require_input_file(file);
    return file;
}

// tinygltf (Debian's) trusts the file's byte ranges when it decodes Draco
// primitives: a bufferView beyond its buffer overflows the heap (found by
// tests/fuzz/fuzz_gltf). The container and every range are checked here first, on the
// JSON then handed to tinygltf; a .glb's Draco bitstreams are read from `in`.
void check_layout(const std::string& path, const nlohmann::json& doc, const Container& c, bool binary, std::ifstream& in) {
    const auto fail = [&](const std::string& what) { throw InputError(path + ": not a readable glTF 2.0 file: " + what); };
    const std::size_t bin_length = c.bin_length;
    const auto count = [](const nlohmann::json& o, const char* key) -> double {
        const auto it = o.find(key);
        return it == o.end() ? 0.0 : it->is_number() ? it->get<double>() : -1.0;
    };
    std::vector<double> buffer_bytes;
    if (doc.contains("buffers") && doc["buffers"].is_array())
        for (const auto& b : doc["buffers"]) {
            if (!b.is_object()) fail("a buffer is not an object");
            const std::string what = "buffer " + std::to_string(buffer_bytes.size());
            const double length = count(b, "byteLength");
            double available = static_cast<double>(bin_length);  // the GLB's own buffer
            if (b.contains("uri")) {
                if (!b["uri"].is_string()) fail(what + ": its uri is not a string");
                const std::string uri = b["uri"].get<std::string>();
                if (uri.rfind("data:", 0) == 0) {
                    const auto bytes = data_uri_bytes(uri);
                    if (!bytes)
                        throw InputError(path + ": " + what + ": an embedded data: URI other than base64 of application/octet-stream or "
                                         "application/gltf-buffer is not supported");
                    if (static_cast<double>(*bytes) != length)
                        throw InputError(path + ": " + what + ": its data: URI holds " + std::to_string(*bytes) + " bytes, its byteLength says " +
                                         detail::format_number(length));
                    available = static_cast<double>(*bytes);
                } else {
                    const std::string file = buffer_file(path, uri, what);
                    available = static_cast<double>(detail::input_file_bytes(file));
                }
            }
            if (!(length >= 0.0 && length <= available)) fail(what + ": its byteLength is not in its data");
            buffer_bytes.push_back(length);
        }
    if (doc.contains("bufferViews") && doc["bufferViews"].is_array())
        for (const auto& v : doc["bufferViews"]) {
            if (!v.is_object()) fail("a bufferView is not an object");
            const double buffer = count(v, "buffer"), offset = count(v, "byteOffset"), length = count(v, "byteLength");
            if (!(buffer >= 0.0 && buffer < static_cast<double>(buffer_bytes.size()) && offset >= 0.0 && length >= 0.0 &&
                  offset + length <= buffer_bytes[static_cast<std::size_t>(buffer)]))
                fail("a bufferView lies outside its buffer");
            // tinygltf takes a negative stride for none (packed elements): refused, as the
            // glTF specification does (4 … 252, a multiple of 4).
            if (v.contains("byteStride")) {
                const nlohmann::json& stride = v["byteStride"];
                if (!stride.is_number_integer() || stride.get<double>() < 4.0 || stride.get<double>() > 252.0 || stride.get<std::int64_t>() % 4 != 0)
                    fail("bufferView " + std::to_string(&v - &doc["bufferViews"][0]) + ": byteStride " + stride.dump().substr(0, 24) +
                         " is not a multiple of 4 in [4, 252]");
            }
        }
    // Indices into the arrays tinygltf indexes without checking (its Draco decoding).
    const auto size_of = [&](const char* key) {
        return doc.contains(key) && doc[key].is_array() ? static_cast<double>(doc[key].size()) : 0.0;
    };
    const double accessors = size_of("accessors"), views = size_of("bufferViews");
    const auto index_in = [&](const nlohmann::json& v, double n, const char* what) {
        if (!v.is_number_integer() || v.get<double>() < 0.0 || v.get<double>() >= n) fail(std::string("a ") + what + " index is out of range");
    };
    if (doc.contains("accessors") && doc["accessors"].is_array())
        for (const auto& a : doc["accessors"])
            if (a.is_object() && a.contains("bufferView")) index_in(a["bufferView"], views, "bufferView");
    if (doc.contains("meshes") && doc["meshes"].is_array())
        for (const auto& mesh : doc["meshes"]) {
            if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
            for (const auto& prim : mesh["primitives"]) {
                if (!prim.is_object()) fail("a primitive is not an object");
                if (prim.contains("indices")) index_in(prim["indices"], accessors, "indices accessor");
                if (prim.contains("attributes") && prim["attributes"].is_object())
                    for (const auto& [_, a] : prim["attributes"].items()) index_in(a, accessors, "attribute accessor");
                if (prim.contains("targets") && prim["targets"].is_array())
                    for (const auto& t : prim["targets"])
                        if (t.is_object())
                            for (const auto& [_, a] : t.items()) index_in(a, accessors, "morph target accessor");
                const auto ext = prim.find("extensions");
                if (ext != prim.end() && ext->is_object() && ext->contains("KHR_draco_mesh_compression")) {
                    const auto& d = (*ext)["KHR_draco_mesh_compression"];
                    if (!d.is_object() || !d.contains("bufferView")) fail("a Draco primitive without a bufferView");
                    index_in(d["bufferView"], views, "Draco bufferView");
                    if (!prim.contains("indices")) fail("a Draco primitive without indices");
                    if (!d.contains("attributes") || !d["attributes"].is_object()) fail("a Draco primitive without attributes");
                    // tinygltf sizes its decoded buffers by the accessors' component types.
                    const auto component = [&](const nlohmann::json& accessor, std::initializer_list<int> valid) {
                        const auto& a = doc["accessors"][accessor.get<std::size_t>()];
                        const int type = a.is_object() && a.contains("componentType") && a["componentType"].is_number_integer()
                                             ? a["componentType"].get<int>() : 0;
                        if (std::find(valid.begin(), valid.end(), type) == valid.end()) fail("a Draco accessor has an invalid componentType");
                    };
                    component(prim["indices"], {5121, 5123, 5125});
                    if (prim.contains("attributes") && prim["attributes"].is_object())
                        for (const auto& [_, a] : prim["attributes"].items()) component(a, {5120, 5121, 5122, 5123, 5125, 5126});
                    // tinygltf dereferences the Draco attribute of every id without a check:
                    // decode the bitstream here and require each id (and a GLB's own buffer).
                    const auto& view = doc["bufferViews"][d["bufferView"].get<std::size_t>()];
                    if (!binary || count(view, "buffer") != 0.0 || doc["buffers"][0].contains("uri")) continue;
                    const std::string bitstream = file_bytes(in, path, c.bin_at + static_cast<std::size_t>(count(view, "byteOffset")),
                                                             static_cast<std::size_t>(count(view, "byteLength")));
                    draco::DecoderBuffer buffer;
                    buffer.Init(bitstream.data(), bitstream.size());
                    draco::Decoder decoder;
                    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
                    if (!decoded.ok()) fail(std::string("a Draco primitive does not decode: ") + decoded.status().error_msg());
                    for (const auto& [name, id] : d["attributes"].items())
                        if (!id.is_number_integer() || !decoded.value()->GetAttributeByUniqueId(id.get<std::uint32_t>()))
                            fail("the Draco attribute of " + name + " is not in the bitstream");
                }
            }
        }
}

// The buffer views only a file's frames use: those of morph target accessors and of the
// nodes form's later meshes (every mesh after the first but the seafloor), unless an
// accessor of the static parts (the first mesh, the seafloor, the animation), an image
// or a Draco bitstream uses them too.
std::set<int> frame_views(const nlohmann::json& doc, bool every_view) {
    std::set<int> frame_accessors, static_accessors, pinned;
    const auto accessor_of = [](const nlohmann::json& v, std::set<int>& into) {
        if (v.is_number_integer()) into.insert(v.get<int>());
    };
    const auto array = [&](const char* key) { return doc.contains(key) && doc[key].is_array() ? doc[key] : nlohmann::json::array(); };
    const nlohmann::json meshes = array("meshes");
    // The nodes form (several water meshes): the first frame's own attributes are a
    // frame's too, so a reader of another frame (read_animation_frames) leaves them in
    // the file; its indices and TEXCOORD_0, which every frame shares, stay resident.
    const auto water_mesh = [](const nlohmann::json& m) { return m.is_object() && !(m.contains("name") && m["name"] == "seafloor"); };
    const bool frames_of_their_own = std::count_if(meshes.begin(), meshes.end(), water_mesh) > 1;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const nlohmann::json& mesh = meshes[i];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        const bool frame_mesh = i > 0 && water_mesh(mesh);
        for (const auto& prim : mesh["primitives"]) {
            if (!prim.is_object()) continue;
            std::set<int>& own = frame_mesh ? frame_accessors : static_accessors;
            if (prim.contains("indices")) accessor_of(prim["indices"], own);
            if (prim.contains("attributes") && prim["attributes"].is_object())
                for (const auto& [name, a] : prim["attributes"].items())
                    accessor_of(a, i == 0 && frames_of_their_own && name != "TEXCOORD_0" ? frame_accessors : own);
            if (prim.contains("targets") && prim["targets"].is_array())
                for (const auto& t : prim["targets"])
                    if (t.is_object())
                        for (const auto& [_, a] : t.items()) accessor_of(a, frame_accessors);
            const auto ext = prim.find("extensions");
            if (ext != prim.end() && ext->is_object() && ext->contains("KHR_draco_mesh_compression") &&
                (*ext)["KHR_draco_mesh_compression"].is_object())
                accessor_of((*ext)["KHR_draco_mesh_compression"].value("bufferView", nlohmann::json()), pinned);
        }
    }
    for (const auto& anim : array("animations"))
        if (anim.is_object() && anim.contains("samplers") && anim["samplers"].is_array())
            for (const auto& sampler : anim["samplers"])
                if (sampler.is_object()) {
                    accessor_of(sampler.value("input", nlohmann::json()), static_accessors);
                    accessor_of(sampler.value("output", nlohmann::json()), static_accessors);
                }
    for (const auto& image : array("images"))
        if (image.is_object()) accessor_of(image.value("bufferView", nlohmann::json()), pinned);
    const nlohmann::json accessors = array("accessors");
    const auto views_of = [&](int a, std::set<int>& into) {
        if (a < 0 || static_cast<std::size_t>(a) >= accessors.size() || !accessors[static_cast<std::size_t>(a)].is_object()) return;
        const nlohmann::json& acc = accessors[static_cast<std::size_t>(a)];
        accessor_of(acc.value("bufferView", nlohmann::json()), into);
        if (acc.contains("sparse") && acc["sparse"].is_object())
            for (const char* part : {"indices", "values"})
                if (acc["sparse"].contains(part) && acc["sparse"][part].is_object())
                    accessor_of(acc["sparse"][part].value("bufferView", nlohmann::json()), into);
    };
    std::set<int> lazy;
    for (const int a : frame_accessors) views_of(a, lazy);
    for (const int a : static_accessors) views_of(a, every_view ? lazy : pinned);
    for (const int v : pinned) lazy.erase(v);
    return lazy;
}

// The views of every primitive's indices and TEXCOORD_0 (the rest positions): what the
// frame files of one run share.
std::set<int> shared_views(const nlohmann::json& doc) {
    std::set<int> out;
    if (!doc.contains("meshes") || !doc["meshes"].is_array() || !doc.contains("accessors") || !doc["accessors"].is_array()) return out;
    const nlohmann::json& accessors = doc["accessors"];
    const auto view_of = [&](const nlohmann::json& a) {
        if (!a.is_number_integer() || a.get<double>() < 0.0 || a.get<double>() >= static_cast<double>(accessors.size())) return;
        const nlohmann::json& acc = accessors[a.get<std::size_t>()];
        if (acc.is_object() && acc.contains("bufferView") && acc["bufferView"].is_number_integer()) out.insert(acc["bufferView"].get<int>());
    };
    for (const auto& mesh : doc["meshes"])
        if (mesh.is_object() && mesh.contains("primitives") && mesh["primitives"].is_array())
            for (const auto& prim : mesh["primitives"]) {
                if (!prim.is_object()) continue;
                if (prim.contains("indices")) view_of(prim["indices"]);
                if (prim.contains("attributes") && prim["attributes"].is_object() && prim["attributes"].contains("TEXCOORD_0"))
                    view_of(prim["attributes"]["TEXCOORD_0"]);
            }
    return out;
}

// EXT_meshopt_compression: each compressed view is pointed at its compressed bytes
// (the extension's buffer, offset and length) and its decoding recorded, the fallback
// buffers (no data) are dropped, so that the layout checks and the lazy reading see
// plain views of one buffer; the bytes are decoded as they are read. Every field is
// checked first: a view's decoded size must be count × byteStride and within what the
// codecs can expand its compressed bytes to (no allocation a stream cannot fill).
std::map<int, MeshoptView> unpack_meshopt(const std::string& path, nlohmann::json& doc) {
    std::map<int, MeshoptView> out;
    const auto listed = [&](const char* key) {
        if (!doc.contains(key) || !doc[key].is_array()) return false;
        for (const auto& e : doc[key])
            if (e == "EXT_meshopt_compression") return true;
        return false;
    };
    if (!listed("extensionsUsed")) return out;
    const auto fail = [&](const std::string& what) { throw InputError(path + ": EXT_meshopt_compression: " + what); };
    if (!doc.contains("buffers") || !doc["buffers"].is_array()) fail("no buffers");
    nlohmann::json& buffers = doc["buffers"];
    std::vector<char> fallback(buffers.size(), 0);
    for (std::size_t b = 0; b < buffers.size(); ++b) {
        const nlohmann::json& buffer = buffers[b];
        if (buffer.is_object() && buffer.contains("extensions") && buffer["extensions"].is_object() &&
            buffer["extensions"].contains("EXT_meshopt_compression")) {
            const nlohmann::json& e = buffer["extensions"]["EXT_meshopt_compression"];
            fallback[b] = e.is_object() && e.value("fallback", false) == true;
        }
    }
    std::size_t data_buffers = 0;  // the fallback buffers must come after every buffer with data
    while (data_buffers < fallback.size() && !fallback[data_buffers]) ++data_buffers;
    for (std::size_t b = data_buffers; b < fallback.size(); ++b)
        if (!fallback[b]) fail("buffer " + std::to_string(b) + " has data but follows a fallback buffer");
    if (!doc.contains("bufferViews") || !doc["bufferViews"].is_array()) return out;
    nlohmann::json& views = doc["bufferViews"];
    const auto whole = [&](const nlohmann::json& o, const char* key, std::size_t dflt, double most, const std::string& what) {
        if (!o.contains(key)) return dflt;
        const nlohmann::json& x = o[key];
        if (!x.is_number_integer() || x.get<double>() < 0.0 || x.get<double>() > most)
            fail(what + ": " + key + " is not a whole number in [0, " + detail::format_number(most) + "]");
        return x.get<std::size_t>();
    };
    for (std::size_t v = 0; v < views.size(); ++v) {
        nlohmann::json& view = views[v];
        const std::string what = "bufferView " + std::to_string(v);
        if (!view.is_object()) fail(what + " is not an object");
        const bool compressed = view.contains("extensions") && view["extensions"].is_object() &&
                                view["extensions"].contains("EXT_meshopt_compression");
        if (!compressed) {
            if (whole(view, "buffer", 0, 1e9, what) >= data_buffers) fail(what + " lies in a fallback buffer, which has no data");
            continue;
        }
        const nlohmann::json e = view["extensions"]["EXT_meshopt_compression"];
        if (!e.is_object()) fail(what + ": the extension is not an object");
        MeshoptView m;
        const std::size_t buffer = whole(e, "buffer", std::size_t(-1), 1e9, what);
        if (buffer >= data_buffers) fail(what + ": its compressed bytes are not in a buffer with data");
        const std::size_t offset = whole(e, "byteOffset", 0, 4294967295.0, what);
        const std::size_t length = whole(e, "byteLength", std::size_t(-1), 4294967295.0, what);
        m.stride = whole(e, "byteStride", std::size_t(-1), 256, what);
        m.count = whole(e, "count", std::size_t(-1), 4294967295.0, what);
        if (!e.contains("mode") || !e["mode"].is_string()) fail(what + ": no mode");
        const std::string mode = e["mode"].get<std::string>(), filter = e.value("filter", std::string("NONE"));
        if (mode == "ATTRIBUTES") m.mode = detail::MeshoptMode::attributes;
        else if (mode == "TRIANGLES") m.mode = detail::MeshoptMode::triangles;
        else if (mode == "INDICES") m.mode = detail::MeshoptMode::indices;
        else fail(what + ": unknown mode \"" + mode + "\"");
        if (filter == "NONE") m.filter = detail::MeshoptFilter::none;
        else if (filter == "OCTAHEDRAL") m.filter = detail::MeshoptFilter::octahedral;
        else if (filter == "QUATERNION") m.filter = detail::MeshoptFilter::quaternion;
        else if (filter == "EXPONENTIAL") m.filter = detail::MeshoptFilter::exponential;
        else fail(what + ": unknown filter \"" + filter + "\"");
        const std::size_t decoded = m.count * m.stride;
        if (whole(view, "byteLength", std::size_t(-1), 4294967295.0, what) != decoded)
            fail(what + ": byteLength " + std::to_string(view.value("byteLength", std::size_t{0})) + " is not count " + std::to_string(m.count) +
                 " × byteStride " + std::to_string(m.stride));
        // The vertex codec packs at most 64 bytes per byte (a stream of zeros), the index
        // codecs less: a larger declared size is not what the stream holds.
        if (decoded > 64 * length + 4096)
            fail(what + ": declares " + std::to_string(decoded) + " bytes for a stream of " + std::to_string(length));
        view["buffer"] = buffer;
        view["byteOffset"] = offset;
        view["byteLength"] = length;
        view["extensions"].erase("EXT_meshopt_compression");
        if (view["extensions"].empty()) view.erase("extensions");
        out[static_cast<int>(v)] = m;
    }
    buffers.erase(buffers.begin() + static_cast<std::ptrdiff_t>(data_buffers), buffers.end());
    for (const char* key : {"extensionsUsed", "extensionsRequired"})
        if (doc.contains(key) && doc[key].is_array()) {
            nlohmann::json kept = nlohmann::json::array();
            for (const auto& e : doc[key])
                if (e != "EXT_meshopt_compression") kept.push_back(e);
            doc[key] = kept;
        }
    return out;
}

}  // namespace

const std::vector<unsigned char>* LazyViews::bytes(int view, const std::string& path) const {
    const auto it = where.find(view);
    if (it == where.end()) return nullptr;
    const auto m = meshopt.find(view);
    if (memo && m != meshopt.end() && kept.count(view)) {
        std::vector<unsigned char> compressed(it->second.second);
        read_at(in, path, base + it->second.first, reinterpret_cast<char*>(compressed.data()), compressed.size());
        KeptView& k = (*memo)[view];
        const MeshoptView& c = m->second;
        if (k.compressed != compressed || k.codec.mode != c.mode || k.codec.filter != c.filter || k.codec.count != c.count ||
            k.codec.stride != c.stride) {
            k.decoded = decode_meshopt(path, view, c, compressed);
            k.codec = c;
            k.compressed = std::move(compressed);
        }
        return &k.decoded;
    }
    auto [slot, fresh] = loaded.try_emplace(view);
    if (fresh) {
        slot->second.resize(it->second.second);
        read_at(in, path, base + it->second.first, reinterpret_cast<char*>(slot->second.data()), it->second.second);
        if (m != meshopt.end()) slot->second = decode_meshopt(path, view, m->second, slot->second);
    }
    return &slot->second;
}

// asset.extras.libwave's numbers, checked in the file's JSON before tinygltf converts
// them: it casts an integer to int, so a loop of 2^40 frames became 0 in the output's
// extras, and a negative one wrapped round (docs/hardening.md).
void check_extras(const std::string& path, const nlohmann::json& doc) {
    const nlohmann::json* info = &doc;
    for (const char* key : {"asset", "extras", "libwave"}) {
        if (!info->is_object() || !info->contains(key)) return;  // read_glb_pieces says what is missing
        info = &(*info)[key];
    }
    const auto fail = [&](const std::string& what) { throw InputError(path + ": asset.extras.libwave." + what); };
    if (!info->is_object()) fail(" is not an object");
    const auto number = [&](const char* key, double most, bool whole) {
        const nlohmann::json v = info->value(key, nlohmann::json());
        if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= most) || (whole && !v.is_number_unsigned()))
            fail(std::string(key) + " is not " + (whole ? "a whole number" : "a number") + " in [0, " + detail::format_number(most) + "]");
        return v.get<double>();
    };
    if (!(number("fps", 1000.0, false) > 0.0)) fail("fps is 0");
    number("loop_frames", kMaxStoredFrames, true);
    number("first_frame", kMaxStoredFrames, true);
    if (!info->value("name", nlohmann::json()).is_string()) fail("name is not a string");
    if (info->contains("scene") && !(*info)["scene"].is_string()) fail("scene is not a string");
}

// Loads one of libwave's glTF files into `m`. When buffer 0 is a .glb's BIN chunk or a
// .gltf's external .bin (every layout libwave writes), tinygltf parses the JSON with a
// buffer of the static views alone, moved together, and the frames' views stay in the
// file for `lazy`; otherwise it loads the whole file, as it would.
// With `memo` (a FrameReader's files form), every view stays in the file until it is
// asked for, and the shared ones (shared_views) decode through the memo.
void load_model(const std::string& path, tinygltf::Model& m, LazyViews& lazy, ViewMemo* memo) {
    const bool binary = std::filesystem::path(path).extension() == ".glb";
    detail::require_input_file(path);
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in) throw InputError(path + ": cannot read the file");
    const Container c = read_container(path, in, size, binary);
    nlohmann::json doc = detail::parse_json_input(c.json, path);  // nesting bounded before tinygltf parses it
    check_extras(path, doc);
    const std::map<int, MeshoptView> meshopt = unpack_meshopt(path, doc);
    check_layout(path, doc, c, binary, in);
    const std::string base_dir = std::filesystem::path(path).parent_path().string();  // a .gltf's .bin lies beside it
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool one_buffer = doc.contains("buffers") && doc["buffers"].is_array() && doc["buffers"].size() == 1 && doc["buffers"][0].is_object();
    const nlohmann::json uri = one_buffer ? doc["buffers"][0].value("uri", nlohmann::json()) : nlohmann::json();
    const bool in_bin_chunk = binary && one_buffer && uri.is_null() && c.bin_length > 0;
    const bool in_bin_file = !binary && one_buffer && uri.is_string() && uri.get<std::string>().rfind("data:", 0) != 0;
    const bool views_listed = !doc.contains("bufferViews") || doc["bufferViews"].is_array();
    if ((!in_bin_chunk && !in_bin_file) || !views_listed) {
        if (!meshopt.empty()) throw InputError(path + ": EXT_meshopt_compression with its data elsewhere than the GLB's chunk or one .bin");
        in.clear();
        in.seekg(0);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (in.bad()) throw InputError(path + ": cannot read the file");
        if (bytes.size() > std::numeric_limits<unsigned int>::max()) throw InputError(path + ": larger than glTF's 4 GB");
        const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
        const auto length = static_cast<unsigned int>(bytes.size());
        const bool ok = binary ? loader.LoadBinaryFromMemory(&m, &err, &warn, data, length, base_dir)
                               : loader.LoadASCIIFromString(&m, &err, &warn, bytes.data(), length, base_dir);
        if (!ok) throw InputError(path + ": not a readable glTF 2.0 file: " + err);
        return;
    }
    lazy.file = in_bin_chunk ? path : buffer_file(path, uri.get<std::string>(), "buffer 0");
    lazy.base = in_bin_chunk ? c.bin_at : 0;
    lazy.in.open(lazy.file, std::ios::binary);
    if (!lazy.in) throw InputError(path + ": cannot read its buffer " + lazy.file);
    const std::set<int> deferred = frame_views(doc, memo != nullptr);
    if (memo) {
        lazy.memo = memo;
        lazy.kept = shared_views(doc);
    }
    std::string bin;  // the static views, each 4-byte aligned (accessors keep their alignment)
    nlohmann::json& views = doc["bufferViews"];
    for (std::size_t v = 0; v < views.size(); ++v) {
        nlohmann::json& view = views[v];
        const std::size_t offset = view.value("byteOffset", std::size_t{0}), length = view.value("byteLength", std::size_t{0});
        const auto compressed = meshopt.find(static_cast<int>(v));
        if (compressed != meshopt.end()) view["byteLength"] = compressed->second.count * compressed->second.stride;
        if (deferred.count(static_cast<int>(v))) {
            lazy.where[static_cast<int>(v)] = {offset, length};
            if (compressed != meshopt.end()) lazy.meshopt[static_cast<int>(v)] = compressed->second;
            view["byteOffset"] = 0;  // tinygltf does not read it; the reader asks `lazy`
            continue;
        }
        bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
        view["byteOffset"] = bin.size();
        if (compressed == meshopt.end()) {
            bin += file_bytes(lazy.in, path, lazy.base + offset, length);
        } else {
            const std::string packed = file_bytes(lazy.in, path, lazy.base + offset, length);
            const std::vector<unsigned char> plain = decode_meshopt(
                path, static_cast<int>(v), compressed->second,
                std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(packed.data()), packed.size()));
            bin.append(reinterpret_cast<const char*>(plain.data()), plain.size());
        }
    }
    if (bin.empty()) bin.assign(4, '\0');  // every view left in the file (a FrameReader's): tinygltf wants a BIN chunk
    doc["buffers"][0] = nlohmann::json{{"byteLength", bin.size()}};
    std::string json = doc.dump();
    json.resize((json.size() + 3) & ~std::size_t{3}, ' ');
    bin.resize((bin.size() + 3) & ~std::size_t{3}, '\0');
    const auto u32 = [](std::size_t v) {
        const auto x = static_cast<std::uint32_t>(v);
        return std::string(reinterpret_cast<const char*>(&x), 4);
    };
    const std::string glb = "glTF" + u32(2) + u32(28 + json.size() + bin.size()) + u32(json.size()) + "JSON" + json +
                            u32(bin.size()) + std::string("BIN\0", 4) + bin;
    if (!loader.LoadBinaryFromMemory(&m, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                     static_cast<unsigned int>(glb.size()), base_dir))
        throw InputError(path + ": not a readable glTF 2.0 file: " + err);
}

}  // namespace wave::detail
