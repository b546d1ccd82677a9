// Triangle-mesh seafloors (OFF, OBJ, PLY, STL) through CGAL's polygon-soup I/O. The
// mesh is kept for the isobath stage and resampled to a grid for depth queries.
#include "grid_fill.h"
#include "libwave/bathymetry.h"
#include "libwave/errors.h"
#include "core/files.h"

#include <CGAL/IO/io.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/exceptions.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>
#include <limits>

namespace wave {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;

// Writes z of every triangle into the grid nodes its xy projection covers; where
// triangles overlap (overhangs, folded meshes) the highest surface wins.
// CGAL 5.5's ASCII OFF scanner reads counts and facet indices as doubles and casts them
// to size_t: a negative, fractional-overflow or huge value is undefined behaviour there
// (found by tests/fuzz/fuzz_mesh_off), and it accepts header spellings and token layouts
// whose reading is anything but obvious. So an ASCII OFF file must be plainly OFF
// before CGAL sees it: a header keyword of the OFF family ([ST][C][N][4][n]OFF, the
// dimension after nOFF), a line of three whole counts, a line per vertex with at least
// its coordinates, a line per facet with its vertex count and that many indices, each a
// whole number in [0, vertex count). Anything else is refused, named by line.
// A token read from a file, fit for an error message: bytes other than printable ASCII
// as \xNN (a NUL would end the message).
std::string printable(const std::string& token) {
    std::string out;
    for (const char c : token) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7F) {
            out += c;
        } else {
            char hex[5];
            std::snprintf(hex, sizeof hex, "\\x%02X", u);
            out += hex;
        }
    }
    return out;
}

void check_off_facets(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line, raw;  // a line without, and with, its comment
    std::size_t number = 0;
    const auto next = [&](std::istringstream& tokens) {  // the next line with content
        while (std::getline(in, line)) {
            ++number;
            raw = line;
            if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
            if (line.find_first_not_of(" \t\r") != std::string::npos) {
                tokens = std::istringstream(line);
                return true;
            }
        }
        return false;
    };
    const auto fail = [&](const std::string& what) {
        throw InputError(path + ": line " + std::to_string(number) + ": " + what);
    };
    const auto whole = [](const std::string& t, long long lo, long long hi) {
        long long value = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
        return ec == std::errc() && end == t.data() + t.size() && value >= lo && value < hi;
    };
    std::istringstream tokens;
    if (!next(tokens)) fail("an empty file is not an OFF mesh");
    std::string header;
    tokens >> header;
    // CGAL reads the keyword up to the first character that is not a letter or digit and
    // swallows that character: a comment glued to it ("OFF#…") would turn the rest of
    // the comment into counts.
    if (const auto start = raw.find(header); start + header.size() < raw.size() &&
                                             !std::isspace(static_cast<unsigned char>(raw[start + header.size()])))
        fail("'" + printable(header) + "' must be followed by a space or the end of the line");
    // [ST][C][N][4][n]OFF: texture coordinates, colours, normals, homogeneous, n-dimensional.
    std::size_t at = 0;
    for (const char* prefix : {"ST", "C", "N", "4", "n"})
        if (header.compare(at, std::strlen(prefix), prefix) == 0) at += std::strlen(prefix);
    if (header.compare(at, std::string::npos, "OFF") != 0)
        fail("'" + printable(header) + "' is not an OFF header keyword (OFF, COFF, NOFF, STOFF, 4OFF, nOFF, …)");
    // The header is now [ST][C][N][4][n]OFF: its letters are its flags.
    const bool dimensioned = header.find('n') != std::string::npos;
    const bool colours = header.find('C') != std::string::npos;
    // CGAL 5.5 finds texture coordinates behind the colour, through an offset it sets
    // only when the file has colours: ST…OFF without C reads from an uninitialised index.
    if (header.starts_with("ST") && !colours)
        fail("'" + header + "': CGAL 5.5 cannot read texture coordinates without colours; drop the ST (a seafloor "
             "needs no texture coordinates) or convert the file to plain OFF");

    std::string word;
    // Binary OFF ends every facet with its colour count (and colours); CGAL 5.5 reads no
    // such count, so it takes the next facet's vertex count from it and silently drops or
    // mangles facets (a two-triangle file read as one), and a header whose counts are
    // negative or near 2^31 overflows its edge estimate (tests/fuzz/regressions/fuzz_mesh_off).
    if (tokens >> word && word == "BINARY")
        fail("binary OFF is not read (CGAL 5.5 misreads its facets); write the mesh as ASCII OFF, binary or ASCII "
             "PLY, or STL");
    std::vector<std::string> counts;
    if (!word.empty()) counts.push_back(word);
    for (std::string t; tokens >> t;) counts.push_back(t);
    if (dimensioned) {
        if (counts.empty() && next(tokens))
            for (std::string t; tokens >> t;) counts.push_back(t);
        if (counts.empty() || counts.front() != "3") fail("nOFF: a seafloor has dimension 3");
        counts.erase(counts.begin());
    }
    if (counts.empty() && next(tokens))
        for (std::string t; tokens >> t;) counts.push_back(t);
    // Each vertex and facet takes a line: more than the file's bytes is a lie that
    // would keep CGAL reading (or reserving) for ever.
    const auto bytes = static_cast<long long>(detail::input_file_bytes(path)) + 1;
    // CGAL reads the edge count into an int and doubles it (signed overflow past 2^30;
    // tests/fuzz/regressions/fuzz_mesh_off): it must fit the file too.
    const long long edges_limit = std::min<long long>(bytes, INT_MAX / 2);
    if (counts.size() != 3 || !whole(counts[0], 0, bytes) || !whole(counts[1], 0, bytes) || !whole(counts[2], 0, edges_limit))
        fail("expected the vertex, facet and edge counts (three whole numbers that fit the file)");
    const long long nv = std::stoll(counts[0]), nf = std::stoll(counts[1]);
    // CGAL estimates the half-edges as int(2.1 (vertices + facets + 10)): it must fit an int.
    if (static_cast<double>(nv + nf + 10) * 2.1 >= static_cast<double>(INT_MAX))
        fail("more than 10^9 vertices and facets: split the mesh or resample it to a grid");
    // CGAL indexes a vertex line's leading numbers without a bounds check: coordinates
    // (3, or 4 homogeneous), then normals, a colour (1, 3 or 4 numbers) and texture
    // coordinates as the keyword announces — they must all be there.
    const std::size_t h = header.find('4') != std::string::npos ? 1 : 0;
    const std::size_t needed = (3 + h) + (header.find('N') != std::string::npos ? 3 + h : 0) +
                               (header.starts_with("ST") ? 2 + h : 0);
    // Once one vertex (or facet) has a colour CGAL reads one for every later one: in a
    // C…OFF file all have a colour or none has.
    std::optional<bool> vertex_colours, facet_colours;
    const auto colour_fits = [](std::size_t n) { return n == 1 || n == 3 || n == 4; };
    // CGAL casts colours to int and unsigned char: an index into its 149-colour map, or
    // r g b [a] as whole numbers 0 … 255, or as fractions 0 … 1 when one is not whole.
    const auto colour_in_range = [](const std::vector<double>& c) {
        if (c.size() == 1) return c[0] >= 0.0 && c[0] < 149.0;
        bool whole_numbers = true;
        for (std::size_t i = 0; i < 3; ++i) whole_numbers = whole_numbers && std::floor(c[i]) == c[i];
        for (std::size_t i = 0; i < 3; ++i)
            if (!(c[i] >= 0.0 && c[i] <= (whole_numbers ? 255.0 : 1.0))) return false;
        return true;
    };
    // A line's leading numbers exactly as CGAL scans them: with CGAL's own reader
    // (IO::iformat), which splits "5-4" into 5 and −4 — a hand-written scanner got that
    // wrong (tests/fuzz/regressions/fuzz_mesh_off).
    std::vector<double> numbers;
    const auto read_numbers = [&](std::istringstream& line_tokens) {
        numbers.clear();
        const std::streamoff from = line_tokens.tellg();  // −1 once the tokens reached the end
        std::istringstream rest(from < 0 ? std::string() : line_tokens.str().substr(static_cast<std::size_t>(from)));
        for (double d = 0.0; numbers.size() <= line.size() && rest >> CGAL::IO::iformat(d);) numbers.push_back(d);
    };
    for (long long v = 0; v < nv; ++v) {
        if (!next(tokens)) fail("the file ends before vertex " + std::to_string(v + 1) + " of " + std::to_string(nv));
        read_numbers(tokens);
        const std::size_t colour = numbers.size() >= needed ? numbers.size() - needed : 0;
        if (numbers.size() < needed || (colours && colour != 0 && !colour_fits(colour)))
            fail("vertex " + std::to_string(v + 1) + " has " + std::to_string(numbers.size()) + " numbers where " + header +
                 " needs " + std::to_string(needed) + (colours ? " (+ a colour of 1, 3 or 4)" : ""));
        if (colours && colour > 0 && !colour_in_range({numbers.begin() + static_cast<std::ptrdiff_t>(needed), numbers.end()}))
            fail("vertex " + std::to_string(v + 1) + ": the colour is neither a colour-map index 0 … 148 nor r g b in 0 … 255 or 0 … 1");
        if (colours && vertex_colours.value_or(colour > 0) != (colour > 0))
            fail("vertex " + std::to_string(v + 1) + (colour > 0 ? " has" : " has no") + " colour, unlike vertex 1");
        vertex_colours = colour > 0;
    }
    for (long long f = 0; f < nf; ++f) {
        if (!next(tokens)) fail("the file ends before facet " + std::to_string(f + 1) + " of " + std::to_string(nf));
        std::string t;
        tokens >> t;
        if (!whole(t, 1, 1 << 20)) fail("the facet's vertex count '" + printable(t) + "' is not a whole number");
        const long long k = std::stoll(t);
        for (long long i = 0; i < k; ++i)
            if (!(tokens >> t) || !whole(t, 0, nv))
                fail("facet vertex index '" + printable(t) + "' is not a whole number in [0, " + std::to_string(nv) + ")");
        if (!colours) continue;
        read_numbers(tokens);
        const std::size_t colour = numbers.size();
        if ((colour != 0 && !colour_fits(colour)) || facet_colours.value_or(colour > 0) != (colour > 0))
            fail("facet " + std::to_string(f + 1) + ": a colour of " + std::to_string(colour) +
                 " numbers (1, 3 or 4, and on every facet or none)");
        if (colour > 0 && !colour_in_range(numbers))
            fail("facet " + std::to_string(f + 1) + ": the colour is neither a colour-map index 0 … 148 nor r g b in 0 … 255 or 0 … 1");
        facet_colours = colour > 0;
    }
}

// CGAL 5.5's PLY reader trusts the file: it appends a `property` to the last `element`
// without checking that one was declared, loops over element counts as given, and sizes
// each list from a count it reads without checking the read — past the end of the data
// that count is an uninitialised value, and one asked for 4.7 GB
// (tests/fuzz/regressions/fuzz_mesh). So the file is first walked as CGAL will read it:
// the header line by line (line 1 the signature, line 2 the format, whatever they say),
// then the data element by element and property by property — in ASCII token by token,
// in binary byte by byte. Every value CGAL will read must be there and fit its type, and
// a list count must be a whole number whose values follow. Properties of a type CGAL
// does not know it skips in the header and reads no data for; so does this walk.
struct PlyType {
    const char *name, *sized_name;
    std::size_t bytes;
    bool integer;
    long long lo, hi;  // an integer type's range
};
constexpr PlyType kPlyTypes[] = {
    {"char", "int8", 1, true, INT8_MIN, INT8_MAX},     {"uchar", "uint8", 1, true, 0, UINT8_MAX},
    {"short", "int16", 2, true, INT16_MIN, INT16_MAX}, {"ushort", "uint16", 2, true, 0, UINT16_MAX},
    {"int", "int32", 4, true, INT32_MIN, INT32_MAX},   {"uint", "uint32", 4, true, 0, UINT32_MAX},
    {"float", "float32", 4, false, 0, 0},              {"double", "float64", 8, false, 0, 0},
};
const PlyType* ply_type(const std::string& word) {
    for (const PlyType& t : kPlyTypes)
        if (word == t.name || word == t.sized_name) return &t;
    return nullptr;
}
struct PlyProperty {
    std::string name;
    const PlyType* count;  // a list's count type; nullptr for a single value
    const PlyType* value;
};
struct PlyElement {
    std::string name;
    unsigned long long items;
    std::vector<PlyProperty> properties;
};

void check_ply(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const auto file_bytes = detail::input_file_bytes(path);
    const auto at_line = [&](std::size_t number, const std::string& what) {
        return InputError(path + ": line " + std::to_string(number) + ": " + what);
    };
    enum class Format { ascii, little_endian, big_endian } format = Format::ascii;
    std::vector<PlyElement> elements;
    std::string line, keyword;
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        std::istringstream tokens(line);
        if (number == 1) {
            if (!(tokens >> keyword) || keyword != "ply") return;  // CGAL refuses it unread
            continue;
        }
        if (number == 2) {
            std::string tag, name, version;
            if (!(tokens >> tag >> name >> version))
                throw at_line(number, "expected 'format <ascii|binary_little_endian|binary_big_endian> <version>'");
            if (name == "ascii") format = Format::ascii;
            else if (name == "binary_little_endian") format = Format::little_endian;
            else if (name == "binary_big_endian") format = Format::big_endian;
            else throw at_line(number, "the PLY format '" + printable(name) + "' is none of ascii, binary_little_endian, binary_big_endian");
            continue;
        }
        if (!(tokens >> keyword)) throw at_line(number, "an empty line in the PLY header");
        if (keyword == "end_header") break;
        if (keyword == "element") {
            std::string name, count;
            unsigned long long n = 0;
            tokens >> name >> count;
            const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
            if (ec != std::errc() || end != count.data() + count.size() || n > file_bytes)
                throw at_line(number, "the PLY element count '" + printable(count) + "' is not a whole number that fits the file");
            elements.push_back({name, n, {}});
        } else if (keyword == "property") {
            if (elements.empty()) throw at_line(number, "a PLY property before any element");
            std::string type, name;
            if (!(tokens >> type >> name)) throw at_line(number, "expected 'property <type> <name>'");
            if (type != "list") {
                if (const PlyType* t = ply_type(type)) elements.back().properties.push_back({name, nullptr, t});
                continue;
            }
            const std::string count_type = name;
            std::string value_type;
            if (!(tokens >> value_type >> name))
                throw at_line(number, "expected 'property list <count type> <value type> <name>'");
            const PlyType* count = ply_type(count_type);
            const PlyType* value = ply_type(value_type);
            if (count && count->integer && value) elements.back().properties.push_back({name, count, value});
        }
    }

    // CGAL then takes values by name and dereferences a null pointer (an assertion in
    // debug builds, a segfault in release ones) when the property it names has another
    // type than it expects (found by fuzz_mesh): a vertex's x, y, z must be float or
    // double; the colour it picks, when every channel is a uchar under one of its names,
    // uchar under the names it then reads; a halfedge's source and target uint.
    for (const PlyElement& e : elements) {
        const auto find = [&](const char* name) -> const PlyProperty* {
            for (const PlyProperty& p : e.properties)
                if (p.name == name) return &p;  // CGAL takes the first of a name
            return nullptr;
        };
        const auto scalar_of = [&](const char* name, std::initializer_list<std::string_view> types) {
            const PlyProperty* p = find(name);
            return p && !p->count && std::find(types.begin(), types.end(), p->value->name) != types.end();
        };
        const auto need = [&](std::initializer_list<const char*> names, std::initializer_list<std::string_view> types,
                              const std::string& what) {
            for (const char* name : names)
                if (find(name) && !scalar_of(name, types))
                    throw InputError(path + ": PLY element '" + printable(e.name) + "': property '" + name + "' must be " + what);
        };
        const bool vertex = e.name == "vertex" || e.name == "vertices";
        if (vertex) need({"x", "y", "z"}, {"float", "double"}, "a float or double (a coordinate)");
        if (vertex || e.name == "face" || e.name == "faces") {
            const auto uchar = [&](const char* name) { return scalar_of(name, {"uchar"}); };
            if ((uchar("red") || uchar("r")) && (uchar("green") || uchar("g")) && (uchar("blue") || uchar("b"))) {
                if (uchar("red")) need({"green", "blue"}, {"uchar"}, "a uchar, as red is (a colour channel)");
                else need({"g", "b"}, {"uchar"}, "a uchar, as r is (a colour channel)");
            }
        }
        if (e.name == "halfedge") need({"source", "target"}, {"uint"}, "a uint (a vertex number)");
    }

    // The data, read as CGAL reads it: straight after the header's last line.
    const PlyElement* element = nullptr;
    const PlyProperty* property = nullptr;
    unsigned long long item = 0;
    const auto fail = [&](const std::string& what) {
        throw InputError(path + ": PLY element '" + printable(element->name) + "' " + std::to_string(item + 1) + " of " +
                         std::to_string(element->items) + ", property '" + printable(property->name) + "': " + what);
    };
    const auto ends = [&] { fail("the file ends before its data"); };
    std::string token;
    // The next value as CGAL reads it; an integer's value is returned (a list's count).
    const auto next = [&](const PlyType& t) -> long long {
        if (format == Format::ascii) {
            if (!(in >> token)) ends();
            const char* first = token.data();
            const char* last = first + token.size();
            if (token.size() > 1 && token[0] == '+' && token[1] != '-') ++first;  // a sign CGAL's >> reads, from_chars does not
            if (!t.integer) {
                double d = 0.0;
                const auto [end, ec] = std::from_chars(first, last, d);
                if (ec != std::errc() || end != last) fail("'" + printable(token) + "' is not a number");
                return 0;
            }
            long long v = 0;
            const auto [end, ec] = std::from_chars(first, last, v);
            if (ec != std::errc() || end != last || v < t.lo || v > t.hi)
                fail("'" + printable(token) + "' is not a whole number of type " + t.name + " (" + std::to_string(t.lo) +
                     " … " + std::to_string(t.hi) + ")");
            return v;
        }
        unsigned char bytes[8] = {};
        if (!in.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(t.bytes))) ends();
        if (!t.integer) return 0;
        unsigned long long u = 0;
        for (std::size_t k = 0; k < t.bytes; ++k)
            u |= static_cast<unsigned long long>(bytes[format == Format::little_endian ? k : t.bytes - 1 - k]) << (8 * k);
        const unsigned long long sign = 1ull << (8 * t.bytes - 1);
        if (t.lo < 0 && (u & sign)) return static_cast<long long>(u) - static_cast<long long>(sign << 1);
        return static_cast<long long>(u);
    };
    for (const PlyElement& e : elements) {
        element = &e;
        for (item = 0; item < e.items; ++item) {
            for (const PlyProperty& p : e.properties) {
                property = &p;
                if (!p.count) {
                    next(*p.value);
                    continue;
                }
                const long long count = next(*p.count);
                if (count < 0) fail("the list count " + std::to_string(count) + " is negative");
                if (format != Format::ascii) {  // the values must be in the file: no need to look at them
                    const auto want = static_cast<std::streamsize>(static_cast<unsigned long long>(count) * p.value->bytes);
                    if (in.ignore(want).gcount() != want) ends();
                    continue;
                }
                for (long long k = 0; k < count; ++k) next(*p.value);
            }
        }
    }
}

void rasterise(const SeafloorMesh& m, ElevationGrid& g, std::vector<char>& covered) {
    const double inf = std::numeric_limits<double>::infinity();
    std::fill(g.z.begin(), g.z.end(), -inf);
    for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3) {
        const double* a = &m.xyz[3 * m.triangles[t]];
        const double* b = &m.xyz[3 * m.triangles[t + 1]];
        const double* c = &m.xyz[3 * m.triangles[t + 2]];
        const double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        if (std::abs(det) < 1e-300) continue;  // vertical or degenerate: covers no area
        // A node within a thousandth of the grid's spacing outside the triangle counts as
        // in it (its plane extended that far): a mesh's coordinates carry rounding — a
        // terrain turned as a DCC object and stored as float32 has its border vertices a few
        // µm inside the bounding box the grid spans, and its border nodes fell outside every
        // triangle and became land (a ring of NODATA round the sea). Node ranges likewise.
        const double reach = 1e-3 * std::min(g.dx, g.dy);
        const double kSlack = 1e-3;
        const auto lo_i = static_cast<std::ptrdiff_t>(std::ceil((std::min({a[0], b[0], c[0]}) - g.x0) / g.dx - kSlack));
        const auto hi_i = static_cast<std::ptrdiff_t>(std::floor((std::max({a[0], b[0], c[0]}) - g.x0) / g.dx + kSlack));
        const auto lo_j = static_cast<std::ptrdiff_t>(std::ceil((std::min({a[1], b[1], c[1]}) - g.y0) / g.dy - kSlack));
        const auto hi_j = static_cast<std::ptrdiff_t>(std::floor((std::max({a[1], b[1], c[1]}) - g.y0) / g.dy + kSlack));
        // l_k × |det| / |edge k| is the node's distance inside edge k (the one opposite vertex
        // k); nodes on shared edges belong to both triangles.
        const double e1 = -std::max(1e-9, reach * std::hypot(b[0] - c[0], b[1] - c[1]) / std::abs(det));
        const double e2 = -std::max(1e-9, reach * std::hypot(c[0] - a[0], c[1] - a[1]) / std::abs(det));
        const double e3 = -std::max(1e-9, reach * std::hypot(a[0] - b[0], a[1] - b[1]) / std::abs(det));
        for (auto j = std::max<std::ptrdiff_t>(lo_j, 0); j <= std::min<std::ptrdiff_t>(hi_j, static_cast<std::ptrdiff_t>(g.ny) - 1); ++j) {
            for (auto i = std::max<std::ptrdiff_t>(lo_i, 0); i <= std::min<std::ptrdiff_t>(hi_i, static_cast<std::ptrdiff_t>(g.nx) - 1); ++i) {
                const double x = g.x0 + static_cast<double>(i) * g.dx;
                const double y = g.y0 + static_cast<double>(j) * g.dy;
                const double l1 = ((b[1] - c[1]) * (x - c[0]) + (c[0] - b[0]) * (y - c[1])) / det;
                const double l2 = ((c[1] - a[1]) * (x - c[0]) + (a[0] - c[0]) * (y - c[1])) / det;
                const double l3 = 1.0 - l1 - l2;
                if (l1 < e1 || l2 < e2 || l3 < e3) continue;
                const double z = l1 * a[2] + l2 * b[2] + l3 * c[2];
                const std::size_t n = static_cast<std::size_t>(j) * g.nx + static_cast<std::size_t>(i);
                g.z[n] = std::max(g.z[n], z);
                covered[n] = 1;
            }
        }
    }
}

}  // namespace

Seafloor read_mesh_file(const std::string& path, const ReadOptions& o) {
    detail::require_input_file(path);
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (extension == ".off") check_off_facets(path);
    if (extension == ".ply") check_ply(path);
    std::vector<Kernel::Point_3> points;
    std::vector<std::vector<std::size_t>> polygons;
    bool read = false;
    try {
        read = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
    } catch (const std::length_error& e) {  // CGAL sizes vectors from the file's counts
        throw InputError(path + ": not a readable OFF/OBJ/PLY/STL triangle mesh (a count in the file is impossible: " +
                         e.what() + ")");
    } catch (const CGAL::Failure_exception& e) {  // CGAL's readers assert on some malformed headers (tests/fuzz)
        throw InputError(path + ": not a readable OFF/OBJ/PLY/STL triangle mesh (" + e.expression() + ")");
    }
    if (!read) throw InputError(path + ": not a readable OFF/OBJ/PLY/STL triangle mesh");

    std::vector<double> xyz;
    xyz.reserve(3 * points.size());
    for (const auto& p : points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
    std::vector<std::uint32_t> triangles;
    for (std::size_t f = 0; f < polygons.size(); ++f) {
        const auto& poly = polygons[f];
        for (std::size_t v : poly)
            if (v >= points.size())
                throw InputError(path + ": face " + std::to_string(f + 1) + " names vertex " +
                                 std::to_string(v + 1) + " of " + std::to_string(points.size()));
        for (std::size_t k = 1; k + 1 < poly.size(); ++k)  // fan-triangulate polygons
            triangles.insert(triangles.end(), {static_cast<std::uint32_t>(poly[0]),
                                               static_cast<std::uint32_t>(poly[k]),
                                               static_cast<std::uint32_t>(poly[k + 1])});
    }
    Seafloor out = seafloor_from_mesh(xyz, triangles, o, path);
    out.frame = "local metres (the mesh's own x/y)";
    return out;
}

Seafloor seafloor_from_mesh(std::span<const double> xyz, std::span<const std::uint32_t> triangles, const ReadOptions& o,
                            const std::string& name) {
    const std::string& path = name;
    if (xyz.size() % 3 != 0) throw InputError(path + ": vertex coordinates come in threes, got " + std::to_string(xyz.size()));
    if (triangles.size() % 3 != 0) throw InputError(path + ": triangle indices come in threes, got " + std::to_string(triangles.size()));
    const std::size_t vertices = xyz.size() / 3;
    const ValueSign sign = o.sign.value_or(ValueSign::elevation);
    const double s = sign == ValueSign::elevation ? 1.0 : -1.0;
    Seafloor out;
    out.source = path;
    out.frame = "local metres";
    SeafloorMesh& m = out.mesh;
    m.xyz.reserve(xyz.size());
    for (std::size_t v = 0; v < vertices; ++v) {
        const double x = xyz[3 * v], y = xyz[3 * v + 1], z = xyz[3 * v + 2];
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            throw InputError(path + ": vertex " + std::to_string(v + 1) + " has a NaN or infinite coordinate");
        m.xyz.insert(m.xyz.end(), {x * o.horizontal_scale, y * o.horizontal_scale, s * (z * o.vertical_scale + o.vertical_offset)});
    }
    for (std::size_t t = 0; t < triangles.size(); ++t)
        if (triangles[t] >= vertices)
            throw InputError(path + ": triangle " + std::to_string(t / 3 + 1) + " names vertex " + std::to_string(triangles[t] + 1) +
                             " of " + std::to_string(vertices));
    m.triangles.assign(triangles.begin(), triangles.end());
    if (m.triangles.empty()) throw InputError(path + ": the mesh has no triangles");
    const std::size_t point_count = vertices;

    double x_lo = HUGE_VAL, x_hi = -HUGE_VAL, y_lo = HUGE_VAL, y_hi = -HUGE_VAL;
    for (std::size_t v = 0; v < m.xyz.size(); v += 3) {
        x_lo = std::min(x_lo, m.xyz[v]);
        x_hi = std::max(x_hi, m.xyz[v]);
        y_lo = std::min(y_lo, m.xyz[v + 1]);
        y_hi = std::max(y_hi, m.xyz[v + 1]);
    }
    if (!(x_hi > x_lo && y_hi > y_lo))
        throw InputError(path + ": the mesh has no horizontal extent (all vertices on a vertical line or plane)");
    // Default spacing: about one node per mesh vertex over the bounding box. The grid
    // spans the box exactly (the spacing shrunk to fit it): a floor'd node count had
    // cropped the far edges, and with them a mesh's highest ground.
    const double spacing = o.resample_spacing > 0.0
        ? o.resample_spacing
        : std::sqrt((x_hi - x_lo) * (y_hi - y_lo) / static_cast<double>(point_count));
    const std::size_t nx = detail::nodes_spanning(path, x_hi - x_lo, spacing, o);
    const std::size_t ny = detail::nodes_spanning(path, y_hi - y_lo, spacing, o);
    detail::check_grid_size(path, nx, ny, o);
    ElevationGrid& g = out.grid;
    g.nx = nx;
    g.ny = ny;
    g.x0 = x_lo;
    g.y0 = y_lo;
    g.dx = (x_hi - x_lo) / static_cast<double>(nx - 1);
    g.dy = (y_hi - y_lo) / static_cast<double>(ny - 1);
    g.z.assign(nx * ny, 0.0);
    std::vector<char> covered(nx * ny, 0);
    rasterise(m, g, covered);
    std::vector<char> missing(nx * ny);
    std::transform(covered.begin(), covered.end(), missing.begin(), [](char c) { return c ? 0 : 1; });
    // Values are already elevations: convert only fills the uncovered nodes.
    ReadOptions fill = o;
    fill.sign = ValueSign::elevation;
    fill.vertical_scale = 1.0;
    fill.vertical_offset = 0.0;
    const auto where = [&](std::size_t i, std::size_t j) {
        return "grid node (" + detail::format_number(g.x0 + static_cast<double>(i) * g.dx) + ", " +
               detail::format_number(g.y0 + static_cast<double>(j) * g.dy) + ") is covered by no triangle and";
    };
    out.nodata_count = detail::convert_to_elevation(g.z, std::nullopt, missing, ValueSign::elevation,
                                                    fill, path, where, nx);
    return out;
}

}  // namespace wave
