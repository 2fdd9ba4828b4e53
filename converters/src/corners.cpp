#include "converters/corners.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "meshcore/error.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {

constexpr double kPi = 3.14159265358979323846;


// Signed area of disk(0, r) ∩ triangle(0, a, b), with the sign of cross(a, b).
double diskTriangleArea(Vec2 a, Vec2 b, double r) {
    auto sector = [r](Vec2 p, Vec2 q) { return 0.5 * r * r * std::atan2(cross(p, q), dot(p, q)); };
    const Vec2 d = b - a;
    const double A = dot(d, d), B = dot(a, d), C = dot(a, a) - r * r;
    if (A <= 0) return 0;
    const double disc = B * B - A * C;
    if (disc <= 0) return sector(a, b);
    const double s = std::sqrt(disc);
    const double t1 = (-B - s) / A, t2 = (-B + s) / A;
    if (t2 <= 0 || t1 >= 1) return sector(a, b);
    const Vec2 p1 = a + std::max(t1, 0.0) * d, p2 = a + std::min(t2, 1.0) * d;
    return sector(a, p1) + 0.5 * cross(p1, p2) + sector(p2, b);
}

// Area of the region bounded by `loop` inside the disk of radius r around c: the integral
// invariant of Manay et al., exact instead of counted pixels.
double diskArea(const std::vector<Vec2>& loop, Vec2 c, double r) {
    double area = 0;
    const size_t n = loop.size();
    for (size_t k = 0; k < n; ++k) area += diskTriangleArea(loop[k] - c, loop[(k + 1) % n] - c, r);
    return std::abs(area);
}

// Arc length along the loop from index i forward to index j.
double arcLength(const std::vector<Vec2>& p, int i, int j) {
    const int n = static_cast<int>(p.size());
    double len = 0;
    for (int k = i; k != j; k = (k + 1) % n) len += norm(p[(k + 1) % n] - p[k]);
    return len;
}

RegionCorners labelCorners(const std::vector<Vec2>& p, const std::array<int, 4>& sorted);

// The outer loop, with at least the 4 points that four corners need (gm::Error otherwise).
const std::vector<Vec2>& outerLoopOf(const Region& region) {
    const std::vector<Vec2>& p = region.outer.points;
    if (p.size() < 4)
        throw Error("the region's outer loop has " + std::to_string(p.size()) +
                    " points; four corners need at least 4");
    return p;
}
}  // namespace

namespace {
// The loop in the polygon's principal frame (area moments by Green's theorem: centroid and
// covariance), and the corners of its bounding box there. Y runs along the major axis, X along
// the minor one (paper: "the shortest being x"); the bounding box is the same either way.
struct PrincipalFrame {
    std::vector<Vec2> points;  // the loop's points in the frame
    Vec2 boxCorner[4];
};

PrincipalFrame principalFrame(const std::vector<Vec2>& p) {
    const int n = static_cast<int>(p.size());
    double area = 0, cx = 0, cy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int k = 0; k < n; ++k) {
        const Vec2 a = p[k], b = p[(k + 1) % n];
        const double w = cross(a, b);
        area += w / 2;
        cx += (a.x + b.x) * w / 6;
        cy += (a.y + b.y) * w / 6;
        sxx += (a.x * a.x + a.x * b.x + b.x * b.x) * w / 12;
        syy += (a.y * a.y + a.y * b.y + b.y * b.y) * w / 12;
        sxy += (a.x * b.y + 2 * a.x * a.y + 2 * b.x * b.y + b.x * a.y) * w / 24;
    }
    if (!(area > 0)) throw Error("the region's outer loop encloses no area");
    cx /= area, cy /= area;
    const double cxx = sxx / area - cx * cx, cyy = syy / area - cy * cy, cxy = sxy / area - cx * cy;
    const double theta = 0.5 * std::atan2(2 * cxy, cxx - cyy);
    const Vec2 major{std::cos(theta), std::sin(theta)}, minor{-major.y, major.x};
    const Vec2 centre{cx, cy};
    auto toFrame = [&](Vec2 q) { return Vec2{dot(q - centre, minor), dot(q - centre, major)}; };
    double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;
    PrincipalFrame frame;
    frame.points.resize(static_cast<size_t>(n));
    std::vector<Vec2>& f = frame.points;
    for (int k = 0; k < n; ++k) {
        f[k] = toFrame(p[k]);
        x0 = std::min(x0, f[k].x), x1 = std::max(x1, f[k].x);
        y0 = std::min(y0, f[k].y), y1 = std::max(y1, f[k].y);
    }
    frame.boxCorner[0] = {x0, y0};
    frame.boxCorner[1] = {x1, y0};
    frame.boxCorner[2] = {x1, y1};
    frame.boxCorner[3] = {x0, y1};
    return frame;
}

// The loop point for one box corner: of the stretch of loop around the point nearest to the
// corner that stays within `reach` of it, the one whose disk area is nearest a quarter disk
// (a right-angled corner), penalised by lambda times its distance from the nearest point.
int cornerNear(const std::vector<Vec2>& p, const std::vector<Vec2>& framed, Vec2 boxCorner,
               double reach, const CornerOptions& options) {
    const int n = static_cast<int>(p.size());
    const double target = kPi * options.radius * options.radius / 4;
    int nearest = 0;
    for (int k = 1; k < n; ++k)
        if (norm(framed[k] - boxCorner) < norm(framed[nearest] - boxCorner)) nearest = k;
    auto cost = [&](int k) {
        return std::abs(diskArea(p, p[k], options.radius) - target) +
               options.lambda * norm(p[k] - p[nearest]);
    };
    int best = nearest;
    double bestCost = cost(nearest);
    for (int dir : {1, -1}) {
        for (int step = 1; step < n; ++step) {
            const int k = ((nearest + dir * step) % n + n) % n;
            if (norm(p[k] - p[nearest]) > reach) break;
            const double c2 = cost(k);
            if (c2 < bestCost) bestCost = c2, best = k;
        }
    }
    return best;
}

// Two box corners snapped to one point (a very thin or odd shape): keep the first and spread
// the others by arc length (or evenly by index when that fails too). Returns them sorted.
std::array<int, 4> spreadCorners(const std::vector<Vec2>& p, int start, double perimeter) {
    const int n = static_cast<int>(p.size());
    std::array<int, 4> sorted{};
    double acc = 0;
    int q = 1;
    sorted[0] = start;
    for (int s = 0; s < n && q < 4; ++s) {
        const int k = (start + s) % n;
        acc += norm(p[(k + 1) % n] - p[k]);
        if (acc >= q * perimeter / 4) sorted[q++] = (k + 1) % n;
    }
    if (q < 4 || sorted[1] == sorted[0] || sorted[2] == sorted[1] || sorted[3] == sorted[2] ||
        sorted[3] == sorted[0])
        for (int c = 0; c < 4; ++c) sorted[c] = (start + c * n / 4) % n;
    std::sort(sorted.begin(), sorted.end());
    return sorted;
}
}  // namespace

RegionCorners findCorners(const Region& region, const CornerOptions& options) {
    const std::vector<Vec2>& p = outerLoopOf(region);
    const int n = static_cast<int>(p.size());
    const PrincipalFrame frame = principalFrame(p);
    double perimeter = 0;
    for (int k = 0; k < n; ++k) perimeter += norm(p[(k + 1) % n] - p[k]);
    const double reach = options.searchFraction * perimeter;
    std::array<int, 4> chosen{};
    for (int c = 0; c < 4; ++c)
        chosen[c] = cornerNear(p, frame.points, frame.boxCorner[c], reach, options);

    std::array<int, 4> sorted = chosen;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        sorted = spreadCorners(p, chosen[0], perimeter);
    return labelCorners(p, sorted);
}

RegionCorners findTipCorners(const Region& region, const CornerOptions& options) {
    const std::vector<Vec2>& p = outerLoopOf(region);
    const int n = static_cast<int>(p.size());
    double perimeter = 0;
    std::vector<double> at(n + 1, 0);  // arc length from point 0
    for (int k = 0; k < n; ++k) at[k + 1] = perimeter += norm(p[(k + 1) % n] - p[k]);
    // Sharpness: the region's share of the disk; the sharpest convex tips first.
    std::vector<double> share(n);
    const double disk = kPi * options.radius * options.radius;
    for (int k = 0; k < n; ++k) share[k] = diskArea(p, p[k], options.radius) / disk;
    std::vector<int> order(n);
    for (int k = 0; k < n; ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return share[a] < share[b]; });
    auto apart = [&](int a, int b) {
        const double d = std::abs(at[a] - at[b]);
        return std::min(d, perimeter - d);
    };
    std::vector<int> chosen;
    for (int k : order) {
        bool ok = true;
        for (int c : chosen) ok = ok && apart(k, c) >= perimeter / 12;
        if (ok) chosen.push_back(k);
        if (chosen.size() == 4) break;
    }
    if (chosen.size() < 4) return findCorners(region, options);
    std::array<int, 4> sorted{chosen[0], chosen[1], chosen[2], chosen[3]};
    std::sort(sorted.begin(), sorted.end());
    return labelCorners(p, sorted);
}

namespace {
RegionCorners labelCorners(const std::vector<Vec2>& p, const std::array<int, 4>& sorted) {
    // sorted is in loop order, which is top-left → top-right → bottom-right → bottom-left for
    // some rotation; pick the one whose top and bottom sides point most nearly along +x.
    int bestShift = 0;
    double bestScore = -std::numeric_limits<double>::max();
    for (int s = 0; s < 4; ++s) {
        const Vec2 tl = p[sorted[s]], tr = p[sorted[(s + 1) % 4]];
        const Vec2 br = p[sorted[(s + 2) % 4]], bl = p[sorted[(s + 3) % 4]];
        const Vec2 dir = (tr - tl) + (br - bl);
        const double len = norm(dir);
        double score = len > 0 ? dir.x / len : -1;
        // Ties (a square at 45°): prefer the top-left corner nearest the image's top-left.
        score -= 1e-9 * (tl.x + tl.y);
        if (score > bestScore) bestScore = score, bestShift = s;
    }
    RegionCorners rc;
    for (int c = 0; c < 4; ++c) rc.index[c] = sorted[(bestShift + c) % 4];
    for (int c = 0; c < 4; ++c) rc.sideLength[c] = arcLength(p, rc.index[c], rc.index[(c + 1) % 4]);
    rc.px = std::max(rc.sideLength[0], rc.sideLength[2]);
    rc.py = std::max(rc.sideLength[1], rc.sideLength[3]);
    return rc;
}
}  // namespace

}  // namespace gm
