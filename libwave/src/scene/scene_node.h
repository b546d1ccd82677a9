// Reading a scene file: a JSON value with its pointer and its schema node. Private to
// libwave (scene reading and the surface models' key rules).
#pragma once

#include "core/format.h"
#include "core/json_input.h"
#include "libwave/errors.h"
#include "scene_schema.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace wave::detail {

using nlohmann::json;

inline std::string fmt(double v) { return format_number(v); }

// The schema node for a value of this JSON type: a "oneOf" (e.g. /outputs/draco: true
// or an object) resolves to the branch of the value's type.
inline const json* schema_branch(const json* schema, const json& v) {
    if (!schema || !schema->contains("oneOf")) return schema;
    for (const json& b : (*schema)["oneOf"]) {
        const std::string type = b.value("type", std::string());
        if ((type == "object" && v.is_object()) || (type == "boolean" && v.is_boolean()) ||
            (type == "array" && v.is_array()) || (type == "string" && v.is_string()) ||
            ((type == "number" || type == "integer") && v.is_number()) || (type.empty() && v.is_string()))
            return &b;
    }
    return schema;
}

inline const json& scene_schema_doc() {
    static const json doc = json::parse(kSceneSchema);
    return doc;
}

// A number's range from its schema node, e.g. "(0, 3600]"; checked by Node::number and
// Node::count, the one place a scene number's range is enforced.
struct Range {
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    bool lo_open = false, hi_open = false;
    bool contains(double v) const {
        return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
    }
    std::string text() const {
        const auto shown = [](double v) {  // whole bounds in full (2^53 − 1, not 9.00719925474099e+15)
            return std::abs(v) < 1e17 && v == std::floor(v) ? std::to_string(static_cast<long long>(v)) : fmt(v);
        };
        return std::string(lo_open ? "(" : "[") + shown(lo) + ", " + shown(hi) + (hi_open ? ")" : "]");
    }
};

// A JSON value with its pointer and its schema node, for reading with validation.
class Node {
public:
    Node(const json& v, std::string pointer, const std::string& origin, const json* schema)
        : v_(v), ptr_(std::move(pointer)), origin_(origin), schema_(schema_branch(schema, v)) {}

    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(origin_ + ": " + (ptr_.empty() ? "/" : ptr_) + ": " + what);
    }
    const std::string& pointer() const { return ptr_; }
    const json& value() const { return v_; }
    std::string shown() const { return brief_json(v_); }

    void require_object(std::initializer_list<const char*> allowed) const {
        if (!v_.is_object()) fail("expected an object, got " + shown());
        const std::set<std::string> ok(allowed.begin(), allowed.end());
        for (const auto& [key, _] : v_.items())
            if (!ok.count(key)) {
                std::string list;
                for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                const std::string shown_key = key.size() > 40 ? key.substr(0, 40) + "…" : key;
                throw InputError(origin_ + ": " + ptr_ + "/" + shown_key + ": unknown key; valid keys here: " + list);
            }
    }
    bool has(const char* key) const { return v_.contains(key); }
    Node operator[](const char* key) const {
        const json* child = nullptr;
        if (schema_ && schema_->contains("properties") && (*schema_)["properties"].contains(key))
            child = &(*schema_)["properties"][key];
        return {v_.at(key), ptr_ + "/" + key, origin_, child};
    }
    Node operator[](std::size_t i) const {
        const json* child = schema_ && schema_->contains("items") ? &(*schema_)["items"] : nullptr;
        return {v_.at(i), ptr_ + "/" + std::to_string(i), origin_, child};
    }
    std::size_t size() const { return v_.size(); }

    /// A finite number in the schema's range for this key.
    double number(const char* unit) const {
        const std::string u = *unit ? std::string(" (") + unit + ")" : std::string();
        if (!v_.is_number()) fail("expected a number" + u + ", got " + shown());
        const double d = v_.get<double>();
        const Range r = range();
        if (!std::isfinite(d) || !r.contains(d)) fail("expected a number in " + r.text() + u + ", got " + shown());
        return d;
    }
    /// A whole number in the schema's range for this key.
    std::size_t count() const {
        const Range r = range();
        const bool whole = v_.is_number_unsigned() || (v_.is_number_integer() && v_.get<long long>() >= 0);
        if (!whole || !r.contains(static_cast<double>(v_.get<std::uint64_t>())))
            fail("expected a whole number in " + r.text() + ", got " + shown());
        return v_.get<std::size_t>();
    }
    bool boolean() const {
        if (!v_.is_boolean()) fail("expected true or false, got " + shown());
        return v_.get<bool>();
    }
    std::string string() const {
        if (!v_.is_string()) fail("expected a string, got " + shown());
        return v_.get<std::string>();
    }
    template <class T>
    T choice(const std::map<std::string, T>& options) const {
        const std::string s = string();
        const auto it = options.find(s);
        if (it == options.end()) {
            std::string list;
            for (const auto& [k, _] : options) list += (list.empty() ? "" : ", ") + k;
            fail("expected one of " + list + ", got " + shown());
        }
        return it->second;
    }
    /// [a, b] of whole numbers (an image size, a grid's node counts).
    std::array<std::size_t, 2> count_pair(const char* what) const {
        if (!v_.is_array() || v_.size() != 2) fail(std::string("expected ") + what + ", got " + shown());
        return {(*this)[std::size_t{0}].count(), (*this)[1].count()};
    }
    /// [x, y, z] in metres.
    std::array<double, 3> point3() const {
        const auto v = numbers(3, "m");
        return {v[0], v[1], v[2]};
    }
    std::vector<double> numbers(std::size_t exact, const char* unit) const {
        if (!v_.is_array() || (exact && v_.size() != exact))
            fail((exact ? "expected an array of " + std::to_string(exact) + " numbers" : std::string("expected an array of numbers")) +
                 ", got " + shown());
        std::vector<double> out;
        for (std::size_t i = 0; i < v_.size(); ++i) out.push_back((*this)[i].number(unit));
        return out;
    }

private:
    Range range() const {
        // Every number the parser reads has its range in the schema; a key missing there
        // is a fault of libwave's (tests/test_cli.py checks the schema bounds every number).
        if (!schema_) throw std::logic_error("scene schema: no entry for " + ptr_);
        Range r;
        const json& s = *schema_;
        if (s.contains("minimum")) r.lo = s["minimum"].get<double>();
        if (s.contains("exclusiveMinimum")) r.lo = s["exclusiveMinimum"].get<double>(), r.lo_open = true;
        if (s.contains("maximum")) r.hi = s["maximum"].get<double>();
        if (s.contains("exclusiveMaximum")) r.hi = s["exclusiveMaximum"].get<double>(), r.hi_open = true;
        return r;
    }

    const json& v_;
    std::string ptr_;
    const std::string& origin_;
    const json* schema_;
};

}  // namespace wave::detail
