// Small 2D helpers shared by the pipeline stages (Vec2, dot and norm are in gradient_mesh.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

// The z component of the 3D cross product: twice the signed area of the triangle (0, a, b),
// positive when b is counter-clockwise from a (in y-up axes).
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// The parameter t in [0, 1] of the point a + t·(b − a) of segment [a, b] closest to p (0 when
// the segment is a point).
inline double closestSegmentParameter(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 ab = b - a;
    const double len2 = dot(ab, ab);
    return len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
}

// Distance from p to the segment [a, b].
inline double pointSegmentDistance(Vec2 p, Vec2 a, Vec2 b) {
    return norm(p - (a + closestSegmentParameter(p, a, b) * (b - a)));
}

// The largest distance from a point of `from` to the polyline `to` (the directed Hausdorff
// distance of the points), and the index of that point.
inline std::pair<double, size_t> directedPolylineDistance(const std::vector<Vec2>& from,
                                                          const std::vector<Vec2>& to) {
    double worst = 0;
    size_t at = 0;
    for (size_t q = 0; q < from.size(); ++q) {
        double best = INFINITY;
        for (size_t k = 0; k + 1 < to.size() && best > worst; ++k)
            best = std::min(best, pointSegmentDistance(from[q], to[k], to[k + 1]));
        if (best > worst) {
            worst = best;
            at = q;
        }
    }
    return {worst, at};
}

}  // namespace gm
