// Synthetic masks and images for the front pipeline tests: pixel (x, y) is inside a shape when
// its centre (x+.5, y+.5) is.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "converters/region.h"
#include "converters/tri_mesh.h"
#include "meshcore/image.h"

namespace gm::test {

inline std::vector<uint8_t> rasterize(int w, int h, const std::function<bool(double, double)>& in) {
    std::vector<uint8_t> bits(static_cast<size_t>(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) bits[static_cast<size_t>(y) * w + x] = in(x + .5, y + .5);
    return bits;
}

inline bool inDisk(double x, double y, double cx, double cy, double r) {
    return (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
}

// A rectangle of size rw × rh centred at (cx, cy), turned by `angle` radians (clockwise on
// screen, y down); corner k of the result is top-left, top-right, bottom-right, bottom-left of
// the unturned rectangle.
struct TurnedRect {
    double cx, cy, rw, rh, angle;
    Vec2 toImage(double u, double v) const {
        const double c = std::cos(angle), s = std::sin(angle);
        return {cx + u * c - v * s, cy + u * s + v * c};
    }
    Vec2 corner(int k) const {
        const double u[4] = {-rw / 2, rw / 2, rw / 2, -rw / 2};
        const double v[4] = {-rh / 2, -rh / 2, rh / 2, rh / 2};
        return toImage(u[k], v[k]);
    }
    bool contains(double x, double y) const {
        const double c = std::cos(angle), s = std::sin(angle);
        const double dx = x - cx, dy = y - cy;
        const double u = dx * c + dy * s, v = -dx * s + dy * c;
        return std::abs(u) < rw / 2 && std::abs(v) < rh / 2;
    }
};

// A smooth colour image with one sharp edge, so that saliency is not uniform.
inline RgbaImage gradientImage(int w, int h) {
    RgbaImage img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = img.at(x, y);
            p[0] = static_cast<float>(x) / w;
            p[1] = static_cast<float>(y) / h;
            p[2] = x > w / 2 ? 0.8f : 0.2f;
            p[3] = 1;
        }
    return img;
}

inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

inline bool segmentsCross(Vec2 p1, Vec2 p2, Vec2 p3, Vec2 p4) {
    if (std::max(p1.x, p2.x) < std::min(p3.x, p4.x) || std::max(p3.x, p4.x) < std::min(p1.x, p2.x) ||
        std::max(p1.y, p2.y) < std::min(p3.y, p4.y) || std::max(p3.y, p4.y) < std::min(p1.y, p2.y))
        return false;
    const double o1 = cross(p2 - p1, p3 - p1), o2 = cross(p2 - p1, p4 - p1);
    const double o3 = cross(p4 - p3, p1 - p3), o4 = cross(p4 - p3, p2 - p3);
    return o1 * o2 <= 0 && o3 * o4 <= 0;
}

// Pairs of non-adjacent edges that cross or touch, within and between the given loops.
inline int countLoopIntersections(const std::vector<const Polygon*>& loops) {
    struct E {
        size_t loop, k;
        Vec2 a, b;
    };
    std::vector<E> edges;
    for (size_t l = 0; l < loops.size(); ++l) {
        const auto& p = loops[l]->points;
        for (size_t k = 0; k < p.size(); ++k) edges.push_back({l, k, p[k], p[(k + 1) % p.size()]});
    }
    int count = 0;
    for (size_t i = 0; i < edges.size(); ++i)
        for (size_t j = i + 1; j < edges.size(); ++j) {
            const E& e = edges[i];
            const E& f = edges[j];
            if (e.loop == f.loop) {
                const size_t n = loops[e.loop]->points.size();
                if ((e.k + 1) % n == f.k || (f.k + 1) % n == e.k) continue;
            }
            if (segmentsCross(e.a, e.b, f.a, f.b)) ++count;
        }
    return count;
}

}  // namespace gm::test
