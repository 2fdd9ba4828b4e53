// Benchmark of the raster re-renderer: a 512×512 canvas with a 32×32 wavy, curved mesh of
// varied colours and, over it, a mesh with three elliptical holes (~1,100 patches in all),
// rendered at scale 1 and 4 on one thread and on all hardware threads. Prints a Markdown table.
//
//   bench_render [--repeat N] [--scale S] [--ppm PREFIX]
//   --scale S: only that scale; --ppm: also write PREFIX_s<scale>.ppm over a grey checkerboard.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "meshcore/render.h"

using namespace gm;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A C×R warp of [x0,x0+w]×[y0,y0+h] by sine waves, exact derivatives, smooth varied colours.
GradientMesh wavyMesh(int C, int R, double x0, double y0, double w, double h, double amp,
                      double phase) {
    GradientMesh m(C, R);
    const double ax = 0.05 * w * amp, ay = 0.05 * h * amp;
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            const double U = double(i) / C, V = double(j) / R;
            const double px = 3 * kPi * V + 2.0 * U + phase, py = 3 * kPi * U + 1.5 * V;
            Node& n = m.node(i, j);
            n.pos = {x0 + w * U + ax * std::sin(px), y0 + h * V + ay * std::sin(py)};
            n.posU = Vec2{w + ax * std::cos(px) * 2.0, ay * std::cos(py) * 3 * kPi} * (1.0 / C);
            n.posV = Vec2{ax * std::cos(px) * 3 * kPi, h + ay * std::cos(py) * 1.5} * (1.0 / R);
            const double a = 5 * kPi * U + phase, b = 4 * kPi * V + 1, d = 3 * kPi * (U - V);
            n.col = {0.5 + 0.45 * std::sin(a), 0.5 + 0.45 * std::cos(b), 0.5 + 0.4 * std::sin(d)};
            n.colU = Vec3{0.45 * std::cos(a) * 5 * kPi, 0, 0.4 * std::cos(d) * 3 * kPi} * (1.0 / C);
            n.colV =
                Vec3{0, -0.45 * std::sin(b) * 4 * kPi, -0.4 * std::cos(d) * 3 * kPi} * (1.0 / R);
        }
    return m;
}

// A gently curved mesh with `holes` slits on rows 2, 4, …, each opened into an ellipse.
GradientMesh holedMesh(int holes, double x0, double y0, double w, double h) {
    const int C = 10, R = 2 * holes + 2;
    GradientMesh m = wavyMesh(C, R, x0, y0, w, h, 0.2, 0.5);
    const double cellW = w / C, cellH = h / R;
    for (int k = 0; k < holes; ++k) {
        Slit s;
        s.row = 2 * k + 2;
        s.i0 = 2 + k;
        s.i1 = s.i0 + 4;
        const int span = s.i1 - s.i0;
        const double a = 0.5 * span * cellW, b = 0.4 * cellH, dtheta = kPi / span;
        const Vec2 left = m.node(s.i0, s.row).pos, right = m.node(s.i1, s.row).pos;
        const Vec2 c = 0.5 * (left + right);
        for (int i = s.i0 + 1; i < s.i1; ++i) {
            const double th = dtheta * (i - s.i0);
            Node& up = m.node(i, s.row);
            Node low = up;
            up.pos = {c.x - a * std::cos(th), c.y - b * std::sin(th)};
            up.posU = Vec2{a * std::sin(th), -b * std::cos(th)} * dtheta;
            low.pos = {c.x - a * std::cos(th), c.y + b * std::sin(th)};
            low.posU = Vec2{a * std::sin(th), b * std::cos(th)} * dtheta;
            low.col = Vec3{1, 1, 1} - up.col;
            s.below.push_back(low);
        }
        s.left.posU = {0, -b * dtheta};
        s.right.posU = {0, b * dtheta};
        m.slits.push_back(s);
    }
    return m;
}

Document benchDocument() {
    Document doc;
    doc.width = 512;
    doc.height = 512;
    doc.meshes.push_back(wavyMesh(32, 32, 16, 16, 480, 480, 1.0, 0.0));
    doc.meshes.push_back(holedMesh(3, 150, 120, 240, 260));
    return doc;
}

void writePpm(const RgbaImage& im, const std::string& path) {
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        std::fprintf(stderr, "cannot write %s\n", path.c_str());
        return;
    }
    std::fprintf(f, "P6\n%d %d\n255\n", im.width, im.height);
    std::vector<unsigned char> row(static_cast<size_t>(im.width) * 3);
    for (int y = 0; y < im.height; ++y) {
        for (int x = 0; x < im.width; ++x) {
            const float* p = im.at(x, y);
            const float bg = ((x / 8 + y / 8) % 2) ? 0.55f : 0.45f;
            for (int c = 0; c < 3; ++c) {
                const float v = std::min(1.0f, std::max(0.0f, p[c])) * p[3] + bg * (1 - p[3]);
                row[3 * static_cast<size_t>(x) + c] =
                    static_cast<unsigned char>(std::lround(v * 255));
            }
        }
        std::fwrite(row.data(), 1, row.size(), f);
    }
    std::fclose(f);
}

double cpuMs() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Timing {
    double wallMs = 0, cpuMs = 0;  // medians
    size_t triangles = 0;
};

// Wall time and CPU time (all threads) per render. On a loaded machine the wall time of a
// single-threaded run overstates the cost; its CPU time does not.
Timing measure(const Document& doc, const RenderOptions& o, int repeat) {
    std::vector<double> wall, cpu;
    Timing t;
    for (int k = 0; k < repeat; ++k) {
        const double c0 = cpuMs();
        const auto t0 = std::chrono::steady_clock::now();
        const RenderResult r = renderDocument(doc, o);
        const auto t1 = std::chrono::steady_clock::now();
        cpu.push_back(cpuMs() - c0);
        wall.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        t.triangles = r.triangles;
    }
    std::sort(wall.begin(), wall.end());
    std::sort(cpu.begin(), cpu.end());
    t.wallMs = wall[wall.size() / 2];
    t.cpuMs = cpu[cpu.size() / 2];
    return t;
}

}  // namespace

int main(int argc, char** argv) {
    int repeat = 9;
    std::vector<double> scales = {1.0, 4.0};
    std::string ppm;
    for (int k = 1; k < argc; ++k) {
        if (!std::strcmp(argv[k], "--repeat") && k + 1 < argc) {
            repeat = std::max(1, std::atoi(argv[++k]));
        } else if (!std::strcmp(argv[k], "--scale") && k + 1 < argc) {
            scales = {std::atof(argv[++k])};
        } else if (!std::strcmp(argv[k], "--ppm") && k + 1 < argc) {
            ppm = argv[++k];
        } else {
            std::fprintf(stderr, "usage: %s [--repeat N] [--scale S] [--ppm PREFIX]\n", argv[0]);
            return 2;
        }
    }
    const Document doc = benchDocument();
    size_t patches = 0;
    for (const GradientMesh& m : doc.meshes) patches += static_cast<size_t>(m.patchCount());
    const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::printf(
        "render benchmark: %dx%d canvas, %zu meshes, %zu patches, %d holes; median of %d\n\n",
        doc.width, doc.height, doc.meshes.size(), patches, doc.meshes[1].holeCount(), repeat);
    std::printf(
        "| scale | output    | threads | wall ms | CPU ms | Mpixel/s (wall) | triangles |\n");
    std::printf(
        "|------:|-----------|--------:|--------:|-------:|----------------:|----------:|\n");
    for (double scale : scales) {
        for (int threads : {1, hw}) {
            RenderOptions o;
            o.scale = scale;
            o.threads = threads;
            const Timing t = measure(doc, o, repeat);
            const int w = static_cast<int>(std::round(doc.width * scale));
            const int h = static_cast<int>(std::round(doc.height * scale));
            char size[32];
            std::snprintf(size, sizeof size, "%dx%d", w, h);
            std::printf("| %5g | %-9s | %7d | %7.1f | %6.1f | %15.1f | %9zu |\n", scale, size,
                        threads, t.wallMs, t.cpuMs, double(w) * h / t.wallMs / 1000.0, t.triangles);
            if (hw == 1) break;
        }
        if (!ppm.empty()) {
            RenderOptions o;
            o.scale = scale;
            char name[32];
            std::snprintf(name, sizeof name, "_s%g.ppm", scale);
            writePpm(renderDocument(doc, o).image, ppm + name);
        }
    }
    return 0;
}
