// Synthetic inputs for the grid / colours / refine tests: a structured triangulation of the
// parameter rectangle carried into the image by a known analytic map, the region it covers,
// and images painted by a colour function. Independent of the earlier pipeline stages.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "converters/region.h"
#include "converters/tri_mesh.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gmtest {

using MapFn = std::function<gm::Vec2(double u, double v)>;  // parameter → image

struct Synthetic {
    gm::TriMesh tri;
    gm::ParamMap map;
    gm::Region region;
};

// An n × m lattice over [0,px] × [0,py], two triangles per cell, image positions by `f`.
inline Synthetic makeSynthetic(double px, double py, int n, int m, const MapFn& f, int width,
                               int height) {
    Synthetic s;
    s.map.px = px;
    s.map.py = py;
    auto id = [&](int i, int j) { return j * (n + 1) + i; };
    for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= n; ++i) {
            const double u = px * i / n, v = py * j / m;
            s.map.uv.push_back({u, v});
            s.tri.vertices.push_back(f(u, v));
        }
    for (int j = 0; j < m; ++j)
        for (int i = 0; i < n; ++i) {
            // u right, v down: (i,j) → (i+1,j) → (i+1,j+1) has positive area with y down.
            s.tri.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            s.tri.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    for (int i = 0; i < n; ++i) s.tri.outerLoop.push_back(id(i, 0));
    for (int j = 0; j < m; ++j) s.tri.outerLoop.push_back(id(n, j));
    for (int i = n; i > 0; --i) s.tri.outerLoop.push_back(id(i, m));
    for (int j = m; j > 0; --j) s.tri.outerLoop.push_back(id(0, j));
    s.tri.corner = {0, n, n + m, 2 * n + m};

    gm::Region& r = s.region;
    r.width = width;
    r.height = height;
    for (int k : s.tri.outerLoop) r.outer.points.push_back(s.tri.vertices[k]);
    r.mask.assign(static_cast<size_t>(width) * height, 0);
    // Scanline fill of the outer loop at pixel centres (even-odd).
    const auto& P = r.outer.points;
    std::vector<double> xs;
    for (int y = 0; y < height; ++y) {
        const double cy = y + 0.5;
        xs.clear();
        for (size_t k = 0; k < P.size(); ++k) {
            const gm::Vec2 a = P[k], b = P[(k + 1) % P.size()];
            if ((a.y <= cy) != (b.y <= cy))
                xs.push_back(a.x + (cy - a.y) / (b.y - a.y) * (b.x - a.x));
        }
        std::sort(xs.begin(), xs.end());
        for (size_t k = 0; k + 1 < xs.size(); k += 2)
            for (int x = std::max(0, static_cast<int>(std::ceil(xs[k] - 0.5)));
                 x < width && x + 0.5 < xs[k + 1]; ++x)
                r.mask[static_cast<size_t>(y) * width + x] = 1;
    }
    r.pixelCount = static_cast<int>(std::count(r.mask.begin(), r.mask.end(), 1));
    return s;
}

// The elliptical square-to-disk map: the rectangle's sides go onto the circle of radius
// `radius` about (cx, cy), corners at 45°; smooth and one-to-one inside.
inline MapFn diskMap(double p, double cx, double cy, double radius) {
    return [=](double u, double v) {
        const double a = 2 * u / p - 1, b = 2 * v / p - 1;
        return gm::Vec2{cx + radius * a * std::sqrt(1 - b * b / 2),
                        cy + radius * b * std::sqrt(1 - a * a / 2)};
    };
}

inline gm::RgbaImage paint(int width, int height,
                           const std::function<gm::Vec3(double x, double y)>& colour) {
    gm::RgbaImage img(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const gm::Vec3 c = colour(x + 0.5, y + 0.5);
            float* p = img.at(x, y);
            p[0] = static_cast<float>(c.r);
            p[1] = static_cast<float>(c.g);
            p[2] = static_cast<float>(c.b);
            p[3] = 1.0f;
        }
    return img;
}

}  // namespace gmtest
