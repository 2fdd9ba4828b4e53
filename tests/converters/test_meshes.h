// Triangulations built in the tests themselves (no dependency on the triangulate stage): rings
// zipped together (disks, star-shaped blobs, annuli), a jittered square grid, and a small
// Bowyer–Watson Delaunay triangulation for a disk with round holes.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <vector>

#include "converters/tri_mesh.h"

namespace gm::test {

constexpr double kPi = 3.14159265358979323846;

inline double twiceArea(Vec2 a, Vec2 b, Vec2 c) {
    return (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
}

inline void addOriented(TriMesh& m, int a, int b, int c) {
    if (twiceArea(m.vertices[a], m.vertices[b], m.vertices[c]) < 0) std::swap(b, c);
    m.triangles.push_back({a, b, c});
}

// Outer-loop corners nearest the screen's top-left, top-right, bottom-right, bottom-left
// directions (angles 225°, 315°, 45°, 135° with y down), the loop rotated to start at top-left.
inline void setOuterLoop(TriMesh& m, std::vector<int> loop, Vec2 centre) {
    auto angleOf = [&](int i) {
        const Vec2 d = m.vertices[i] - centre;
        double a = std::atan2(d.y, d.x) * 180 / kPi;
        return a < 0 ? a + 360 : a;
    };
    auto nearest = [&](double target) {
        int best = 0;
        double bestD = 1e9;
        for (size_t k = 0; k < loop.size(); ++k) {
            double d = std::abs(angleOf(loop[k]) - target);
            d = std::min(d, 360 - d);
            if (d < bestD) bestD = d, best = static_cast<int>(k);
        }
        return best;
    };
    const int tl = nearest(225);
    std::rotate(loop.begin(), loop.begin() + tl, loop.end());
    m.outerLoop = loop;
    m.corner = {0, nearest(315), nearest(45), nearest(135)};
}

// Rings of points around `centre` at the given radii, each with `count` points; radiusScale(θ)
// bends circles into star-shaped curves. Ring k is rotated by half a step when k is odd, and
// neighbouring rings are zipped by angle. innerHole: ring 0 is a hole loop; otherwise a centre
// vertex fans ring 0. The last ring is the outer loop.
inline TriMesh ringMesh(Vec2 centre, const std::vector<double>& radii, int count, bool innerHole,
                        const std::function<double(double)>& radiusScale = nullptr) {
    TriMesh m;
    const double step = 2 * kPi / count;
    const int rings = static_cast<int>(radii.size());
    const double start = 225 * kPi / 180;
    auto angle = [&](int ring, int k) {
        return start + (k + 0.5 * ((rings - 1 - ring) % 2)) * step;
    };
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < count; ++k) {
            const double a = angle(r, k), s = radiusScale ? radiusScale(a) : 1.0;
            m.vertices.push_back({centre.x + radii[r] * s * std::cos(a),
                                  centre.y + radii[r] * s * std::sin(a)});
        }
    auto id = [&](int r, int k) { return r * count + ((k % count) + count) % count; };
    if (!innerHole) {
        m.vertices.push_back(centre);
        const int c = static_cast<int>(m.vertices.size()) - 1;
        for (int k = 0; k < count; ++k) addOriented(m, c, id(0, k), id(0, k + 1));
    }
    for (int r = 0; r + 1 < rings; ++r) {
        // Walk once around the strip from the edge (inner 0, first outer point after it),
        // adding a triangle per step on whichever ring's next point comes first by angle.
        const double a0 = angle(r, 0);
        const int oStart = angle(r + 1, 0) < a0 ? 1 : 0;
        const double b0 = angle(r + 1, oStart);
        int i = 0, j = 0;
        while (i < count || j < count) {
            const bool advanceInner = j >= count || (i < count && a0 + (i + 1) * step < b0 + (j + 1) * step);
            if (advanceInner) {
                addOriented(m, id(r, i), id(r, i + 1), id(r + 1, oStart + j));
                ++i;
            } else {
                addOriented(m, id(r, i), id(r + 1, oStart + j), id(r + 1, oStart + j + 1));
                ++j;
            }
        }
    }
    std::vector<int> outer(count);
    for (int k = 0; k < count; ++k) outer[k] = id(rings - 1, k);
    setOuterLoop(m, outer, centre);
    if (innerHole) {
        std::vector<int> hole(count);
        for (int k = 0; k < count; ++k) hole[k] = id(0, k);
        m.holeLoops.push_back(hole);
    }
    return m;
}

// An n×n grid over [0, size]², interior points jittered by up to `jitter` of the spacing, cells
// split along alternating diagonals. The outer loop runs along the square's sides.
inline TriMesh squareGrid(int n, double size, double jitter, unsigned seed = 1) {
    TriMesh m;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-jitter, jitter);
    const double h = size / (n - 1);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const bool inner = x > 0 && y > 0 && x < n - 1 && y < n - 1;
            m.vertices.push_back({x * h + (inner ? U(rng) * h : 0), y * h + (inner ? U(rng) * h : 0)});
        }
    auto id = [&](int x, int y) { return y * n + x; };
    for (int y = 0; y + 1 < n; ++y)
        for (int x = 0; x + 1 < n; ++x) {
            if ((x + y) % 2) {
                addOriented(m, id(x, y), id(x + 1, y), id(x + 1, y + 1));
                addOriented(m, id(x, y), id(x + 1, y + 1), id(x, y + 1));
            } else {
                addOriented(m, id(x, y), id(x + 1, y), id(x, y + 1));
                addOriented(m, id(x + 1, y), id(x + 1, y + 1), id(x, y + 1));
            }
        }
    for (int x = 0; x < n - 1; ++x) m.outerLoop.push_back(id(x, 0));
    for (int y = 0; y < n - 1; ++y) m.outerLoop.push_back(id(n - 1, y));
    for (int x = n - 1; x > 0; --x) m.outerLoop.push_back(id(x, n - 1));
    for (int y = n - 1; y > 0; --y) m.outerLoop.push_back(id(0, y));
    m.corner = {0, n - 1, 2 * (n - 1), 3 * (n - 1)};
    return m;
}

struct Circle {
    Vec2 c;
    double r;
};

// A Delaunay triangulation (Bowyer–Watson, quadratic: keep it to a few thousand points) of the
// disk `outer` minus the disks `holes`: loops sampled every 0.75·spacing, a jittered hexagonal
// lattice of the given spacing inside, kept 0.7·spacing away from every loop, so that the loop
// edges are Delaunay edges.
inline TriMesh holedDisk(const Circle& outer, const std::vector<Circle>& holes, double spacing,
                         unsigned seed = 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    std::vector<Vec2> pts;
    auto loop = [&](const Circle& c) {
        const int n = std::max(8, static_cast<int>(std::ceil(2 * kPi * c.r / (0.75 * spacing))));
        std::vector<int> ids;
        for (int k = 0; k < n; ++k) {
            const double a = 2 * kPi * k / n, r = c.r * (1 + 1e-6 * U(rng));
            ids.push_back(static_cast<int>(pts.size()));
            pts.push_back({c.c.x + r * std::cos(a), c.c.y + r * std::sin(a)});
        }
        return ids;
    };
    const std::vector<int> outerIds = loop(outer);
    std::vector<std::vector<int>> holeIds;
    for (const Circle& h : holes) holeIds.push_back(loop(h));
    const double dy = spacing * std::sqrt(3.0) / 2;
    for (double y = outer.c.y - outer.r; y <= outer.c.y + outer.r; y += dy) {
        const int row = static_cast<int>(std::lround((y - outer.c.y) / dy));
        for (double x = outer.c.x - outer.r + (row % 2 ? spacing / 2 : 0); x <= outer.c.x + outer.r;
             x += spacing) {
            const Vec2 p{x + 0.15 * spacing * U(rng), y + 0.15 * spacing * U(rng)};
            bool ok = norm(p - outer.c) < outer.r - 0.7 * spacing;
            for (const Circle& h : holes) ok = ok && norm(p - h.c) > h.r + 0.7 * spacing;
            if (ok) pts.push_back(p);
        }
    }
    const int realCount = static_cast<int>(pts.size());
    for (const Circle& h : holes) pts.push_back(h.c);  // fans the hole's inside, dropped below
    const double big = 100 * outer.r;
    pts.push_back({outer.c.x - big, outer.c.y - big});
    pts.push_back({outer.c.x + big, outer.c.y - big});
    pts.push_back({outer.c.x, outer.c.y + big});
    const int n = static_cast<int>(pts.size());

    struct Tri {
        int v[3];
        Vec2 cc;
        double r2;
    };
    auto make = [&](int a, int b, int c) {
        if (twiceArea(pts[a], pts[b], pts[c]) < 0) std::swap(b, c);
        const Vec2 A = pts[a], B = pts[b], C = pts[c];
        const double d = 2 * (A.x * (B.y - C.y) + B.x * (C.y - A.y) + C.x * (A.y - B.y));
        const double a2 = dot(A, A), b2 = dot(B, B), c2 = dot(C, C);
        const Vec2 cc{(a2 * (B.y - C.y) + b2 * (C.y - A.y) + c2 * (A.y - B.y)) / d,
                      (a2 * (C.x - B.x) + b2 * (A.x - C.x) + c2 * (B.x - A.x)) / d};
        return Tri{{a, b, c}, cc, dot(A - cc, A - cc)};
    };
    std::vector<Tri> tris{make(n - 3, n - 2, n - 1)};
    for (int p = 0; p < n - 3; ++p) {
        std::vector<std::array<int, 2>> edges;
        std::vector<Tri> kept;
        for (const Tri& t : tris) {
            if (dot(pts[p] - t.cc, pts[p] - t.cc) < t.r2) {
                for (int k = 0; k < 3; ++k) edges.push_back({t.v[k], t.v[(k + 1) % 3]});
            } else {
                kept.push_back(t);
            }
        }
        for (const auto& e : edges) {
            bool shared = false;
            for (const auto& f : edges) shared = shared || (f[0] == e[1] && f[1] == e[0]);
            if (!shared) kept.push_back(make(e[0], e[1], p));
        }
        tris.swap(kept);
    }
    TriMesh m;
    m.vertices.assign(pts.begin(), pts.begin() + realCount);
    for (const Tri& t : tris) {
        if (t.v[0] >= realCount || t.v[1] >= realCount || t.v[2] >= realCount) continue;
        const Vec2 g = (1.0 / 3) * (pts[t.v[0]] + pts[t.v[1]] + pts[t.v[2]]);
        bool inside = norm(g - outer.c) < outer.r;
        for (const Circle& h : holes) inside = inside && norm(g - h.c) > h.r;
        if (inside) m.triangles.push_back({t.v[0], t.v[1], t.v[2]});
    }
    setOuterLoop(m, outerIds, outer.c);
    m.holeLoops = holeIds;
    return m;
}

}  // namespace gm::test
