// Debugging aid: when GRADMESH_PLOT_DIR is set, tests draw a map's parameter-space triangulation
// (folded triangles filled red, slits blue) as a PPM image there.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "converters/tri_mesh.h"

namespace gm::test {

inline void plotUv(const TriMesh& mesh, const ParamMap& map, const std::string& name) {
    const char* dir = std::getenv("GRADMESH_PLOT_DIR");
    if (!dir) return;
    const int W = 900, H = std::max(1, static_cast<int>(std::lround(W * map.py / map.px)));
    const int pad = 10;
    std::vector<unsigned char> img(static_cast<size_t>(W + 2 * pad) * (H + 2 * pad) * 3, 255);
    auto put = [&](int x, int y, int r, int g, int b) {
        if (x < 0 || y < 0 || x >= W + 2 * pad || y >= H + 2 * pad) return;
        unsigned char* p = &img[(static_cast<size_t>(y) * (W + 2 * pad) + x) * 3];
        p[0] = r, p[1] = g, p[2] = b;
    };
    auto toPx = [&](Vec2 p) { return Vec2{pad + p.x / map.px * W, pad + p.y / map.py * H}; };
    auto line = [&](Vec2 a, Vec2 b, int r, int g, int bl) {
        a = toPx(a), b = toPx(b);
        const int n = static_cast<int>(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))) + 1;
        for (int k = 0; k <= n; ++k) {
            const double t = static_cast<double>(k) / n;
            put(static_cast<int>(a.x + t * (b.x - a.x)), static_cast<int>(a.y + t * (b.y - a.y)), r, g, bl);
        }
    };
    for (const auto& t : mesh.triangles) {
        const Vec2 a = map.uv[t[0]], b = map.uv[t[1]], c = map.uv[t[2]];
        const bool flipped = !((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0);
        const int r = flipped ? 255 : 60, g = flipped ? 0 : 60, bl = flipped ? 0 : 60;
        line(a, b, r, g, bl), line(b, c, r, g, bl), line(c, a, r, g, bl);
    }
    for (const auto& h : mesh.holeLoops)
        for (size_t k = 0; k < h.size(); ++k) line(map.uv[h[k]], map.uv[h[(k + 1) % h.size()]], 0, 0, 255);
    const std::string path = std::string(dir) + "/" + name + ".ppm";
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fprintf(f, "P6\n%d %d\n255\n", W + 2 * pad, H + 2 * pad);
        std::fwrite(img.data(), 1, img.size(), f);
        std::fclose(f);
    }
}

}  // namespace gm::test
