// Berkhoff, Booij & Radder's (1982) elliptic shoal against the measured wave heights
// (data/berkhoff/README.md): the RMS error of H/H0 per transect and over the 208 points
// of FUNWAVE's eight digitised transects, for the field as shipped (amplitude dispersion
// and breaking), the linear field, and the default resolution; Basilisk's digitisation
// (mirrored in y) as a cross-check; and the figure of every transect.
//
//   libwave_berkhoff_transects [figure.png]   (bench/RESULTS.md, docs/wave-field.md)
#include "libwave/field.h"
#include "libwave/scene.h"
#include "libwave/shade.h"

#include <stb/stb_easy_font.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Transect {
    std::string title;
    bool along_x = false;  // longitudinal (y fixed) or transverse (x fixed)
    double fixed = 0.0;    // the fixed coordinate (m)
    std::vector<double> s, ratio;        // FUNWAVE's points: the running coordinate, H/H0
    std::vector<double> s_cross, ratio_cross;  // Basilisk's, in libwave's y sign
};

std::vector<std::vector<double>> rows(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        std::fprintf(stderr, "error: cannot read %s\n", path.c_str());
        std::exit(1);
    }
    std::vector<std::vector<double>> out;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream s(line);
        std::vector<double> v;
        for (double d; s >> d;) v.push_back(d);
        if (!v.empty()) out.push_back(v);
    }
    return out;
}

std::vector<Transect> transects() {
    const std::string fw = std::string(LIBWAVE_DATA_DIR) + "/berkhoff/funwave_via_reef3d/";
    const std::string bs = std::string(LIBWAVE_DATA_DIR) + "/berkhoff/basilisk/";
    std::vector<Transect> t(8);
    for (int n = 0; n < 5; ++n) {
        Transect& tr = t[static_cast<std::size_t>(n)];
        tr.fixed = 1.0 + 2.0 * n;
        tr.title = "section " + std::to_string(n + 1) + ": x = " + std::to_string(static_cast<int>(tr.fixed)) + " m";
        for (const auto& r : rows(fw + "section" + std::to_string(n + 1) + ".dat")) {
            tr.s.push_back(r.at(0));
            tr.ratio.push_back(r.at(1) / 23.2);
        }
    }
    for (std::size_t k = 0; k < 3; ++k) {
        Transect& tr = t[5 + k];
        tr.along_x = true;
        tr.fixed = -2.0 + 2.0 * static_cast<double>(k);
        tr.title = "section " + std::to_string(6 + k) + ": y = " + std::to_string(static_cast<int>(tr.fixed)) + " m";
    }
    for (const auto& r : rows(fw + "section678.dat"))
        for (std::size_t k = 0; k < 3; ++k) {
            t[5 + k].s.push_back(-r.at(0));
            t[5 + k].ratio.push_back(r.at(1 + k) / 23.2);
        }
    // Basilisk: sections 2, 3, 5 (x = 3, 5, 9 m; y mirrored) and the centre line (7).
    for (int n : {2, 3, 5})
        for (const auto& r : rows(bs + "section-" + std::to_string(n))) {
            t[static_cast<std::size_t>(n - 1)].s_cross.push_back(-r.at(0));
            t[static_cast<std::size_t>(n - 1)].ratio_cross.push_back(r.at(1));
        }
    for (const auto& r : rows(bs + "section-7")) {
        t[6].s_cross.push_back(r.at(0));
        t[6].ratio_cross.push_back(r.at(1));
    }
    return t;
}

double ratio_at(const wave::WaveField& f, const Transect& t, double s) {
    const double x = t.along_x ? s : t.fixed, y = t.along_x ? t.fixed : s;
    const wave::FieldSample p = wave::sample_wave_field(f, x, y);
    return p.wet ? 2.0 * std::abs(p.eta) / f.incident_height : std::nan("");
}

// RMS over each transect and (last) over all points; `cross`: Basilisk's points.
std::vector<double> rms(const wave::WaveField& f, const std::vector<Transect>& ts, bool cross) {
    std::vector<double> out;
    double all = 0.0;
    std::size_t count = 0;
    for (const Transect& t : ts) {
        const std::vector<double>& s = cross ? t.s_cross : t.s;
        const std::vector<double>& r = cross ? t.ratio_cross : t.ratio;
        double sum = 0.0;
        for (std::size_t i = 0; i < s.size(); ++i) sum += std::pow(ratio_at(f, t, s[i]) - r[i], 2.0);
        out.push_back(s.empty() ? std::nan("") : std::sqrt(sum / static_cast<double>(s.size())));
        all += sum;
        count += s.size();
    }
    out.push_back(std::sqrt(all / static_cast<double>(count)));
    return out;
}

using Rgb = std::array<std::uint8_t, 3>;

struct Canvas {
    int w, h;
    std::vector<std::uint8_t> rgb;
    Canvas(int w_, int h_) : w(w_), h(h_), rgb(static_cast<std::size_t>(w_ * h_) * 3, 255) {}
    void dot(int x, int y, Rgb c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        std::copy(c.begin(), c.end(), &rgb[static_cast<std::size_t>(y * w + x) * 3]);
    }
    void line(double x0, double y0, double x1, double y1, Rgb c, int thick, bool dashed = false) {
        const int n = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
        for (int i = 0; i <= n; ++i) {
            if (dashed && (i / 5) % 2) continue;
            const double t = static_cast<double>(i) / n;
            const int x = static_cast<int>(std::lround(x0 + t * (x1 - x0))), y = static_cast<int>(std::lround(y0 + t * (y1 - y0)));
            for (int a = 0; a < thick; ++a)
                for (int b = 0; b < thick; ++b) dot(x + a, y + b, c);
        }
    }
    void text(int x, int y, const std::string& s, int scale = 1) {
        static std::vector<char> buffer(99999);
        const int quads = stb_easy_font_print(0, 0, const_cast<char*>(s.c_str()), nullptr, buffer.data(), static_cast<int>(buffer.size()));
        const float* v = reinterpret_cast<const float*>(buffer.data());
        for (int q = 0; q < quads; ++q) {
            const float* quad = v + q * 16;  // 4 vertices of x, y, z, colour
            for (int yy = static_cast<int>(quad[1]) * scale; yy < static_cast<int>(quad[9]) * scale; ++yy)
                for (int xx = static_cast<int>(quad[0]) * scale; xx < static_cast<int>(quad[4]) * scale; ++xx) dot(x + xx, y + yy, {0, 0, 0});
        }
    }
};

void figure(const std::string& path, const std::vector<Transect>& ts, const wave::WaveField& model, const wave::WaveField& linear,
            const std::vector<double>& rms_model, const std::vector<double>& rms_linear) {
    const int pw = 520, ph = 230, left = 50, top = 34, gap_x = 40, gap_y = 62, head = 52;
    Canvas c(2 * (left + pw) + gap_x + 40, head + 4 * (top + ph + gap_y - 20) + 10);
    c.text(10, 8, "Berkhoff, Booij & Radder (1982): H/H0 along the eight measured transects", 2);
    c.text(10, 30, "blue: libwave's field (amplitude dispersion, breaking; examples/berkhoff-shoal.json)   grey dashed: linear field   "
                   "red squares: measured (FUNWAVE's digitisation)   green crosses: Basilisk's digitisation");
    const Rgb blue{30, 80, 200}, grey{140, 140, 140}, red{210, 30, 30}, green{20, 150, 60}, light{225, 225, 225}, black{0, 0, 0};
    for (std::size_t n = 0; n < ts.size(); ++n) {
        const Transect& t = ts[n];
        const int ox = 10 + static_cast<int>(n % 2) * (left + pw + gap_x) + left;
        const int oy = head + static_cast<int>(n / 2) * (top + ph + gap_y - 20) + top;
        const double s0 = t.along_x ? 0.0 : -5.0, s1 = t.along_x ? 11.0 : 5.0, r1 = 2.5;
        const auto px = [&](double s) { return ox + (s - s0) / (s1 - s0) * pw; };
        const auto py = [&](double r) { return oy + ph - r / r1 * ph; };
        for (double r = 0.0; r <= r1 + 1e-9; r += 0.5) {
            c.line(ox, py(r), ox + pw, py(r), light, 1);
            char label[16];
            std::snprintf(label, sizeof label, "%.1f", r);
            c.text(ox - 28, static_cast<int>(py(r)) - 4, label);
        }
        for (double s = std::ceil(s0); s <= s1 + 1e-9; s += 1.0) {
            c.line(px(s), oy + ph, px(s), oy + ph + 4, black, 1);
            c.text(static_cast<int>(px(s)) - 4, oy + ph + 7, std::to_string(static_cast<int>(s)));
        }
        c.line(ox, oy, ox, oy + ph, black, 1);
        c.line(ox, oy + ph, ox + pw, oy + ph, black, 1);
        c.text(ox + pw - 40, oy + ph + 18, t.along_x ? "x (m)" : "y (m)");
        char title[160];
        std::snprintf(title, sizeof title, "%s   RMS %.3f (linear %.3f)", t.title.c_str(), rms_model[n], rms_linear[n]);
        c.text(ox, oy - 22, title, 2);
        for (const auto& [f, colour, dashed, thick] :
             {std::tuple{&linear, grey, true, 1}, std::tuple{&model, blue, false, 2}}) {
            double last_x = 0.0, last_y = 0.0;
            bool have = false;
            for (double s = s0; s <= s1 + 1e-9; s += 0.02) {
                const double r = ratio_at(*f, t, s);
                if (std::isnan(r)) {
                    have = false;
                    continue;
                }
                const double x = px(s), y = py(std::min(r, r1));
                if (have) c.line(last_x, last_y, x, y, colour, thick, dashed);
                last_x = x, last_y = y, have = true;
            }
        }
        for (std::size_t i = 0; i < t.s_cross.size(); ++i) {
            const double x = px(t.s_cross[i]), y = py(t.ratio_cross[i]);
            c.line(x - 4, y - 4, x + 4, y + 4, green, 1);
            c.line(x - 4, y + 4, x + 4, y - 4, green, 1);
        }
        for (std::size_t i = 0; i < t.s.size(); ++i) {
            const int x = static_cast<int>(std::lround(px(t.s[i]))), y = static_cast<int>(std::lround(py(t.ratio[i])));
            for (int a = -3; a <= 3; ++a)
                for (int b = -3; b <= 3; ++b) c.dot(x + a, y + b, red);
        }
    }
    const std::string bytes = wave::png_bytes(wave::Image{.width = static_cast<std::size_t>(c.w), .height = static_cast<std::size_t>(c.h), .rgb = std::move(c.rgb)});
    std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::printf("wrote %s\n", path.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    const wave::Scene scene = wave::read_scene(std::string(LIBWAVE_EXAMPLES_DIR) + "/berkhoff-shoal.json");
    const wave::Seafloor sea = wave::scene_seafloor(scene);
    const std::vector<Transect> ts = transects();
    std::size_t points = 0;
    for (const Transect& t : ts) points += t.s.size();
    wave::FieldOptions linear_options = scene.field, no_breaking = scene.field, defaults;
    linear_options.amplitude_dispersion = false;
    no_breaking.breaking_decay = 0.0;
    defaults.reflecting_edges = true;
    const wave::WaveField model = wave::solve_wave_field(sea, scene.waves[0], scene.field);
    const wave::WaveField linear = wave::solve_wave_field(sea, scene.waves[0], linear_options);
    const std::vector<double> m = rms(model, ts, false), l = rms(linear, ts, false);
    std::printf("Berkhoff's shoal, %zu measured points (FUNWAVE's digitisation), RMS error of H/H0\n\n", points);
    std::printf("| field | all | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 |\n|---|---|---|---|---|---|---|---|---|---|\n");
    const auto row = [](const char* name, const std::vector<double>& r) {
        std::printf("| %s | **%.3f** |", name, r.back());
        for (std::size_t i = 0; i + 1 < r.size(); ++i) std::printf(std::isnan(r[i]) ? " – |" : " %.3f |", r[i]);
        std::printf("\n");
    };
    row("example (amplitude dispersion, breaking)", m);
    row("linear (`amplitude_dispersion: false`)", l);
    row("no breaking dissipation (`breaking_decay: 0`)", rms(wave::solve_wave_field(sea, scene.waves[0], no_breaking), ts, false));
    row("default resolution, walls", rms(wave::solve_wave_field(sea, scene.waves[0], defaults), ts, false));
    std::printf("\nBasilisk's digitisation (sections 2, 3, 5, 7; y mirrored), the same fields:\n\n");
    row("example", rms(model, ts, true));
    row("linear", rms(linear, ts, true));
    if (argc > 1) figure(argv[1], ts, model, linear, m, l);
    return 0;
}
