// Flat regions of a whole image (flat_regions.h): the flat-colour test, the outline traced around
// the region's pixels and its fit with cubic Béziers.
#include "converters/flat_regions.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "converters/regions.h"
#include "outline_slack.h"
#include "meshcore/error.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {

// The mean colour of the pixels `at` (indices into the image).
Vec3 meanColour(const RgbaImage& image, const std::vector<size_t>& at) {
    Vec3 mean;
    double sum[3] = {0, 0, 0};
    for (size_t k : at)
        for (int c = 0; c < 3; ++c) sum[c] += image.pixels[4 * k + c];
    for (int c = 0; c < 3; ++c)
        mean[c] = std::clamp(sum[c] / double(std::max<size_t>(1, at.size())), 0.0, 1.0);
    return mean;
}

double dot3(const Vec3& a, const Vec3& b) { return a.r * b.r + a.g * b.g + a.b * b.b; }

// Sets the pixels of every hole of `mask` (a background component, 4-connected, that does not
// reach the image border) that lies wholly in `under`.
void fillHolesUnder(std::vector<uint8_t>& mask, const std::vector<uint8_t>& under, int w, int h) {
    const PixelBox b = maskBounds(mask, w, h);
    if (b.empty()) return;
    const int x0 = std::max(0, b.x0 - 1), y0 = std::max(0, b.y0 - 1);
    const int x1 = std::min(w - 1, b.x1 + 1), y1 = std::min(h - 1, b.y1 + 1);
    const int bw = x1 - x0 + 1, bh = y1 - y0 + 1;
    // 0: unvisited, 1: outside, 2: a hole component being collected.
    std::vector<uint8_t> seen(static_cast<size_t>(bw) * bh, 0);
    auto image = [&](int i, int j) { return static_cast<size_t>(y0 + j) * w + x0 + i; };
    std::deque<int> queue;
    std::vector<int> component;
    auto flood = [&](int start, uint8_t mark) {
        queue.assign(1, start);
        seen[static_cast<size_t>(start)] = mark;
        while (!queue.empty()) {
            const int p = queue.front();
            queue.pop_front();
            component.push_back(p);
            const int i = p % bw, j = p / bw;
            const int ni[4] = {i - 1, i + 1, i, i}, nj[4] = {j, j, j - 1, j + 1};
            for (int d = 0; d < 4; ++d) {
                if (ni[d] < 0 || nj[d] < 0 || ni[d] >= bw || nj[d] >= bh) continue;
                const int q = nj[d] * bw + ni[d];
                if (seen[static_cast<size_t>(q)] || mask[image(ni[d], nj[d])]) continue;
                seen[static_cast<size_t>(q)] = mark;
                queue.push_back(q);
            }
        }
    };
    for (int j = 0; j < bh; ++j)
        for (int i = 0; i < bw; ++i) {
            const bool frame = i == 0 || j == 0 || i == bw - 1 || j == bh - 1;
            const int p = j * bw + i;
            if (frame && !seen[static_cast<size_t>(p)] && !mask[image(i, j)]) flood(p, 1);
        }
    component.clear();
    for (int p = 0; p < bw * bh; ++p) {
        if (seen[static_cast<size_t>(p)] || mask[image(p % bw, p / bw)]) continue;
        component.clear();
        flood(p, 2);
        const bool covered = std::all_of(component.begin(), component.end(),
                                         [&](int q) { return under[image(q % bw, q / bw)] != 0; });
        if (covered)
            for (int q : component) mask[image(q % bw, q / bw)] = 1;
    }
}

// How far colour c lies from every blend of `col` with `other` (0–1 units, per channel mean).
double blendResidual(const Vec3& c, const Vec3& col, const Vec3& other) {
    const Vec3 axis = col - other;
    const double len2 = dot3(axis, axis);
    const double share = len2 > 0 ? std::clamp(dot3(c - other, axis) / len2, 0.0, 1.0) : 1.0;
    const Vec3 d = c - (other + share * axis);
    return (std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b)) / 3;
}

// The colour that pixel (x, y) blends with the shape's colour `col`, among the pixels within
// `reach` that the shape does not reach (`grown` 0): the one furthest from col; or, with
// `eachSide` (a line between two regions, which blends with each on its own side), of those
// at least 0.25 (0–1 units) from col the one that leaves the least residual, and of those
// that leave about as little the one furthest from col (a pixel of the same blend explains
// the pixel as well as the colour beyond it, and would read as none of col). `col` itself
// when there is no such pixel.
Vec3 blendPartner(const RgbaImage& image, const std::vector<uint8_t>& grown, int x, int y,
                  int reach, const Vec3& col, bool eachSide) {
    const int w = image.width, h = image.height;
    constexpr double kClearContrast = 0.25, kAsLittle = 0.02;
    const Vec3 c = pixelColour(image, static_cast<size_t>(y) * w + x);
    Vec3 furthest = col;
    double furthestDistance = -1;
    std::vector<std::pair<double, Vec3>> candidates;  // residual, colour
    for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
            const size_t q = static_cast<size_t>(yy) * w + xx;
            if (grown[q]) continue;
            const Vec3 v = pixelColour(image, q);
            const double d = dot3(v - col, v - col);
            if (d > furthestDistance) furthestDistance = d, furthest = v;
            if (eachSide && d >= kClearContrast * kClearContrast)
                candidates.push_back({blendResidual(c, col, v), v});
        }
    if (!eachSide || candidates.empty()) return furthest;
    double least = INFINITY;
    for (const auto& [r, v] : candidates) least = std::min(least, r);
    Vec3 best = col;
    double bestDistance = -1;
    for (const auto& [r, v] : candidates) {
        const double d = dot3(v - col, v - col);
        if (r <= least + kAsLittle && d > bestDistance) bestDistance = d, best = v;
    }
    return best;
}

}  // namespace

Coverage shareCoverage(const RgbaImage& image, const std::vector<uint8_t>& own,
                       const std::vector<uint8_t>& grown, const std::vector<uint8_t>& under,
                       const Vec3& flat, bool eachSide, const LinearGradient* gradient) {
    const int w = image.width, h = image.height;
    Coverage c;
    c.width = w, c.height = h;
    c.values.assign(static_cast<size_t>(w) * h, 0.0f);
    const PixelBox b = maskBounds(grown, w, h);
    if (b.empty()) return c;
    constexpr int kReach = 2;
    constexpr double kLeastContrast = 0.1;  // 0–1 units: closer than this, no share is told
    for (int y = std::max(0, b.y0 - kReach); y <= std::min(h - 1, b.y1 + kReach); ++y)
        for (int x = std::max(0, b.x0 - kReach); x <= std::min(w - 1, b.x1 + kReach); ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (grown[k] && (under[k] || !own[k])) {
                c.values[k] = 1;
                continue;
            }
            const Vec3 col = gradient ? gradient->colourAt({x + 0.5, y + 0.5}) : flat;
            const Vec3 other = blendPartner(image, grown, x, y, kReach, col, eachSide);
            const Vec3 axis = col - other;
            const double len2 = dot3(axis, axis);
            if (len2 < kLeastContrast * kLeastContrast) {
                c.values[k] = own[k] ? 1.0f : 0.0f;
                continue;
            }
            const double share = dot3(pixelColour(image, k) - other, axis) / len2;
            c.values[k] = static_cast<float>(std::clamp(share, 0.0, 1.0));
        }
    return c;
}

namespace {

Vec2 unit(Vec2 v) {
    const double n = norm(v);
    return n > 0 ? (1 / n) * v : Vec2{1, 0};
}

Vec2 bezierAt(const Vec2 q[4], double t) {
    const double u = 1 - t;
    return (u * u * u) * q[0] + (3 * u * u * t) * q[1] + (3 * u * t * t) * q[2] +
           (t * t * t) * q[3];
}

// Fits cubics to the points pts[a..b] of a closed point list (indices modulo its size), with unit
// tangents tA (leaving pts[a]) and tB (arriving at pts[b], pointing back along the curve), each
// point within its own tolerance; appends each cubic's first three points (start and handles)
// to `out`.
class CubicFitter {
public:
    CubicFitter(const std::vector<Vec2>& pts, double tolerance)
        : CubicFitter(pts, std::vector<double>(pts.size(), tolerance)) {}
    CubicFitter(const std::vector<Vec2>& pts, std::vector<double> tolerances)
        : pts_(pts), n_(pts.size()), tol_(std::move(tolerances)) {}

    void fit(size_t a, size_t b, Vec2 tA, Vec2 tB, std::vector<Vec2>& out, int depth = 0) {
        const size_t count = b - a;  // b may exceed n_: indices wrap
        const Vec2 pa = at(a), pb = at(b);
        if (count <= 1 || depth > 40) {
            out.insert(out.end(), {pa, pa + (1.0 / 3) * (pb - pa), pa + (2.0 / 3) * (pb - pa)});
            return;
        }
        std::vector<double> param = chordParams(a, b);
        Vec2 q[4];
        solveHandles(a, b, tA, tB, param, q);
        size_t worst = a;
        double error = maxError(a, b, q, param, worst);
        // `error`: the largest distance of a point from the curve over its tolerance.
        for (int pass = 0; pass < 4 && error > 1 && error < 4; ++pass) {
            reparametrise(a, b, q, param);
            solveHandles(a, b, tA, tB, param, q);
            error = maxError(a, b, q, param, worst);
        }
        if (error <= 1) {
            out.insert(out.end(), {q[0], q[1], q[2]});
            return;
        }
        if (worst <= a || worst >= b) worst = a + count / 2;
        const Vec2 t = unit(at(worst + 1) - at(worst - 1));
        fit(a, worst, tA, -t, out, depth + 1);
        fit(worst, b, t, tB, out, depth + 1);
    }

private:
    Vec2 at(size_t k) const { return pts_[k % n_]; }

    std::vector<double> chordParams(size_t a, size_t b) const {
        std::vector<double> u(b - a + 1, 0.0);
        for (size_t k = a + 1; k <= b; ++k) u[k - a] = u[k - a - 1] + norm(at(k) - at(k - 1));
        const double total = u.back();
        for (double& x : u) x = total > 0 ? x / total : 0;
        return u;
    }

    // Least-squares handle lengths along the fixed tangents (Schneider's normal equations);
    // a third of the chord when they degenerate.
    void solveHandles(size_t a, size_t b, Vec2 tA, Vec2 tB, const std::vector<double>& u,
                      Vec2 q[4]) const {
        const Vec2 p0 = at(a), p3 = at(b);
        double c00 = 0, c01 = 0, c11 = 0, x0 = 0, x1 = 0;
        for (size_t k = a; k <= b; ++k) {
            const double t = u[k - a], s = 1 - t;
            const double b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
            const Vec2 A1 = b1 * tA, A2 = b2 * tB;
            c00 += dot(A1, A1), c01 += dot(A1, A2), c11 += dot(A2, A2);
            const Vec2 r = at(k) - ((b0 + b1) * p0 + (b2 + b3) * p3);
            x0 += dot(A1, r), x1 += dot(A2, r);
        }
        const double det = c00 * c11 - c01 * c01;
        double la = 0, lb = 0;
        if (std::fabs(det) > 1e-12) {
            la = (x0 * c11 - c01 * x1) / det;
            lb = (c00 * x1 - c01 * x0) / det;
        }
        const double chord = norm(p3 - p0);
        if (!(la > 1e-3 * chord) || !(lb > 1e-3 * chord) || la > 2 * chord + 1 ||
            lb > 2 * chord + 1)
            la = lb = chord / 3;
        q[0] = p0, q[1] = p0 + la * tA, q[2] = p3 + lb * tB, q[3] = p3;
    }

    double maxError(size_t a, size_t b, const Vec2 q[4], const std::vector<double>& u,
                    size_t& worst) const {
        double most = 0;
        worst = a;
        for (size_t k = a + 1; k < b; ++k) {
            const double d = norm(bezierAt(q, u[k - a]) - at(k)) / tol_[k % n_];
            if (d > most) most = d, worst = k;
        }
        return most;
    }

    // One Newton step per point towards the curve's nearest parameter.
    void reparametrise(size_t a, size_t b, const Vec2 q[4], std::vector<double>& u) const {
        for (size_t k = a + 1; k < b; ++k) {
            const double t = u[k - a], s = 1 - t;
            const Vec2 d1 = (3 * s * s) * (q[1] - q[0]) + (6 * s * t) * (q[2] - q[1]) +
                            (3 * t * t) * (q[3] - q[2]);
            const Vec2 d2 = (6 * s) * (q[2] - 2 * q[1] + q[0]) + (6 * t) * (q[3] - 2 * q[2] + q[1]);
            const Vec2 r = bezierAt(q, t) - at(k);
            const double den = dot(d1, d1) + dot(r, d2);
            if (std::fabs(den) > 1e-12) u[k - a] = std::clamp(t - dot(r, d1) / den, 0.0, 1.0);
        }
    }

    const std::vector<Vec2>& pts_;
    const size_t n_;
    const std::vector<double> tol_;  // per point, > 0
};

// The polygon with extra points so that no edge is longer than one pixel; `vertexAt` gets the
// index of each original vertex.
std::vector<Vec2> densify(const std::vector<Vec2>& poly, std::vector<size_t>& vertexAt) {
    std::vector<Vec2> out;
    vertexAt.clear();
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
        vertexAt.push_back(out.size());
        const int steps = std::max(1, static_cast<int>(std::ceil(norm(q - p))));
        for (int s = 0; s < steps; ++s) out.push_back(p + (double(s) / steps) * (q - p));
    }
    return out;
}

// The closed loop `pts` (points a pixel apart or less) smoothed (OutlineSmoothing), never
// across the `held` points (indices), which stay.
std::vector<Vec2> smoothLoop(const std::vector<Vec2>& pts, const std::vector<size_t>& held,
                             const OutlineSmoothing& smoothing) {
    const double sigma = smoothing.sigma;
    const long n = static_cast<long>(pts.size());
    if (!(sigma > 0) || n < 3) return pts;
    const long reach = std::min(n / 2, static_cast<long>(std::ceil(3 * sigma)));
    std::vector<uint8_t> fixed(pts.size(), 0);
    for (size_t c : held) fixed[c % pts.size()] = 1;
    auto wrap = [n](long k) { return static_cast<size_t>((k % n + n) % n); };
    std::vector<Vec2> out = pts;
    for (long k = 0; k < n; ++k) {
        if (fixed[wrap(k)]) continue;
        Vec2 sum = pts[wrap(k)];
        double weights = 1;
        for (int side = -1; side <= 1; side += 2)
            for (long d = 1; d <= reach; ++d) {
                const size_t q = wrap(k + side * d);
                const double weight = std::exp(-0.5 * double(d * d) / (sigma * sigma));
                sum = sum + weight * pts[q];
                weights += weight;
                if (fixed[q]) break;  // a held point ends the stretch on this side
            }
        const Vec2 shift = (1.0 / weights) * sum - pts[wrap(k)];
        const double length = norm(shift);
        const double most = smoothing.maxShift;
        out[wrap(k)] = pts[wrap(k)] + (length > most ? most / length : 1.0) * shift;
    }
    return out;
}

double turnAngle(Vec2 before, Vec2 after) {
    const double c = dot(unit(before), unit(after));
    return std::acos(std::clamp(c, -1.0, 1.0));
}

// The index after k (step +1) or before it (-1) around a loop of m.
size_t nextAround(size_t k, int step, size_t m) { return step > 0 ? (k + 1) % m : (k + m - 1) % m; }

// The point `reach` pixels along the closed polygon from vertex k, forwards (step +1) or
// backwards (-1).
Vec2 pointAlong(const std::vector<Vec2>& poly, size_t k, double reach, int step) {
    const size_t m = poly.size();
    Vec2 p = poly[k];
    double left = reach;
    for (size_t walked = 0; walked < m; ++walked) {
        k = nextAround(k, step, m);
        const double d = norm(poly[k] - p);
        if (d >= left) return p + (left / d) * (poly[k] - p);
        left -= d;
        p = poly[k];
    }
    return p;
}

// How far the outline turns at each vertex of the closed polygon, between the points `reach`
// pixels before and after it.
std::vector<double> turnsWithin(const std::vector<Vec2>& poly, double reach) {
    std::vector<double> turns(poly.size());
    for (size_t k = 0; k < poly.size(); ++k)
        turns[k] = turnAngle(poly[k] - pointAlong(poly, k, reach, -1),
                             pointAlong(poly, k, reach, +1) - poly[k]);
    return turns;
}

// Whether vertex k turns most (the first so when equal) among the vertices within `reach`
// pixels of it along the polygon.
bool isSharpestNear(const std::vector<Vec2>& poly, const std::vector<double>& turns, size_t k,
                    double reach) {
    const size_t m = poly.size();
    for (int step = -1; step <= 1; step += 2) {
        double walked = 0;
        size_t q = k;
        for (size_t count = 1; count < m; ++count) {
            const size_t next = nextAround(q, step, m);
            walked += norm(poly[next] - poly[q]);
            q = next;
            if (walked > reach || q == k) break;
            if (turns[q] > turns[k] || (turns[q] == turns[k] && q < k)) return false;
        }
    }
    return true;
}



// A thin region (a line, a rim) is nearly all anti-aliased border: its colour is the mean of its
// quarter of pixels furthest from the colours around it, and each pixel is judged by how far it
// lies from a blend of that colour with one of its outside neighbours' (what the shape's
// anti-aliased outline draws there).
FlatFit fitThinFlatColour(const RgbaImage& image, const Region& own, const std::vector<size_t>& all,
                          double maxError, double errorShare, double outlierShare,
                          const FlatOptions& options) {
    const int w = own.width, h = own.height;
    auto outside = [&](size_t k, auto&& visit) {
        const int x = static_cast<int>(k % w), y = static_cast<int>(k / w);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const size_t q = static_cast<size_t>(yy) * w + xx;
                if (!own.mask[q]) visit(pixelColour(image, q));
            }
    };
    Vec3 around;
    long aroundCount = 0;
    for (size_t k : all) outside(k, [&](const Vec3& v) { around = around + v, ++aroundCount; });
    if (aroundCount > 0) around = (1.0 / double(aroundCount)) * around;
    std::vector<std::pair<double, size_t>> contrast;
    for (size_t k : all) {
        const Vec3 d = pixelColour(image, k) - around;
        contrast.push_back({-dot3(d, d), k});
    }
    const size_t purest = std::max<size_t>(1, all.size() / 4);
    std::nth_element(contrast.begin(), contrast.begin() + static_cast<long>(purest - 1),
                     contrast.end());
    std::vector<size_t> pure;
    for (size_t i = 0; i < purest; ++i) pure.push_back(contrast[i].second);
    FlatFit fit;
    fit.col = meanColour(image, pure);
    double sum = 0;
    long outliers = 0;
    for (size_t k : all) {
        const Vec3 c = pixelColour(image, k);
        double best = blendResidual(c, fit.col, fit.col);
        outside(k, [&](const Vec3& v) { best = std::min(best, blendResidual(c, fit.col, v)); });
        sum += 255 * best;
        outliers += 255 * best > options.outlierError * maxError;
    }
    const auto flat = [&](size_t) { return fit.col; };
    fit.all = paintedError(image, all, flat);
    fit.interior = fit.all;
    fit.interior.meanAbs = sum / double(all.size());
    fit.flat = fit.interior.meanAbs <= errorShare * maxError &&
               double(outliers) <= outlierShare * double(all.size());
    return fit;
}

// Whether any pixel is set in both masks.
bool holdsAny(const std::vector<uint8_t>& mask, const std::vector<uint8_t>& own) {
    for (size_t k = 0; k < mask.size(); ++k)
        if (mask[k] && own[k]) return true;
    return false;
}

}  // namespace

FlatFit fitFlatColour(const RgbaImage& image, const Region& own, double maxError, bool inkLine,
                      const FlatOptions& options) {
    FlatFit fit;
    const int w = own.width, h = own.height;
    if (image.width != w || image.height != h) return fit;
    std::vector<size_t> interior, all;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (!own.mask[k]) continue;
            all.push_back(k);
            if (insideMask(own.mask, w, h, k)) interior.push_back(k);
        }
    if (all.empty()) return fit;
    // A thin region (a line, a frame) has little interior, and what it has says nothing of it.
    const bool fewInterior =
        static_cast<int>(interior.size()) < options.minInterior ||
        double(interior.size()) < options.minInteriorShare * double(all.size());
    if (inkLine) {
        // Flat whatever its error: what else would draw it, a mesh strip a few pixels wide,
        // draws it less cleanly in every consumer (and, under a patch budget, hardly at all).
        FlatFit fit = fitThinFlatColour(image, own, all, maxError, 0, 0, options);
        fit.flat = true;
        return fit;
    }
    if (fewInterior)
        return fitThinFlatColour(image, own, all, maxError, options.errorShare,
                                 options.outlierShare, options);
    fit.col = meanColour(image, interior);
    long outliers = 0;
    const auto flat = [&](size_t) { return fit.col; };
    fit.interior = paintedError(image, interior, flat, options.outlierError * maxError, &outliers);
    fit.all = paintedError(image, all, flat);
    fit.flat = fit.interior.meanAbs <= options.errorShare * maxError &&
               double(outliers) <= options.outlierShare * double(fit.interior.pixels);
    return fit;
}

namespace {

// fitClosedCubics, each point's tolerance raised to the room `slack` gives it there (none
// without a map); where it has room, its turns are neither corners nor held.
std::vector<Vec2> fitClosedCubicsWithin(const std::vector<Vec2>& polygon, double tolerance,
                                        const OutlineSmoothing& smoothing,
                                        const OutlineSlack* slack) {
    std::vector<Vec2> out;
    const size_t m = polygon.size();
    if (m < 3) {
        for (const Vec2& p : polygon) out.insert(out.end(), {p, p, p});
        return out;
    }
    std::vector<size_t> vertexAt;
    const std::vector<Vec2> pts = densify(polygon, vertexAt);
    const size_t n = pts.size();
    // Corners: vertices where the outline turns more than 50 degrees within a pixel either
    // side (so that a corner the trace cut off in two half turns is one), the sharpest of
    // those near each other. Without any, the vertex that turns most starts the loop and the
    // curves meet there smoothly too.
    constexpr double kCornerAngle = 50 * M_PI / 180;
    const std::vector<double> turns = turnsWithin(polygon, 1.0);
    std::vector<size_t> corners, turning;
    size_t sharpest = 0;
    double sharpestAngle = -1;
    auto roomAt = [&](Vec2 p) { return slack ? slack->at(p) : 0.0; };
    for (size_t k = 0; k < m; ++k) {
        const double a = turns[k];
        if (roomAt(polygon[k]) > tolerance) continue;
        if (a > smoothing.holdTurn * M_PI / 180) turning.push_back(vertexAt[k]);
        if (a > kCornerAngle && isSharpestNear(polygon, turns, k, 1.0))
            corners.push_back(vertexAt[k]);
        if (a > sharpestAngle) sharpestAngle = a, sharpest = vertexAt[k];
    }
    const std::vector<Vec2> smoothed = smoothLoop(pts, turning, smoothing);
    std::vector<double> tolerances(n);
    for (size_t k = 0; k < n; ++k) tolerances[k] = std::max(tolerance, roomAt(pts[k]));
    CubicFitter fitter(smoothed, std::move(tolerances));
    auto at = [&](size_t k) { return smoothed[k % n]; };
    if (corners.empty()) {
        const Vec2 t = unit(at(sharpest + 1) - at(sharpest + n - 1));
        fitter.fit(sharpest, sharpest + n, t, -t, out);
        return out;
    }
    for (size_t c = 0; c < corners.size(); ++c) {
        const size_t a = corners[c];
        const size_t b = c + 1 < corners.size() ? corners[c + 1] : corners.front() + n;
        fitter.fit(a, b, unit(at(a + 1) - at(a)), unit(at(b + n - 1) - at(b)), out);
    }
    return out;
}

}  // namespace

std::vector<Vec2> fitClosedCubics(const std::vector<Vec2>& polygon, double tolerance,
                                  const OutlineSmoothing& smoothing) {
    return fitClosedCubicsWithin(polygon, tolerance, smoothing, nullptr);
}

namespace {

// The chord direction from pts[k] to the point `reach` pixels along the polyline (step +1) or
// back along it (-1), stopping at index `limit`.
Vec2 chordFrom(const std::vector<Vec2>& pts, size_t k, int step, size_t limit, double reach) {
    size_t q = k;
    while (q != limit && norm(pts[q] - pts[k]) < reach) q = step > 0 ? q + 1 : q - 1;
    return unit(pts[q] - pts[k]);
}

// The corners of an open polyline (points a pixel apart or less): where it turns more than
// `cornerAngle` between the chords reaching `reach` pixels before and after, the sharpest within
// `reach` of each other; each moved to where the chords' lines meet, so that the corner stays
// sharp where the trace rounded it.
std::vector<size_t> openCorners(std::vector<Vec2>& pts, double cornerAngle, double reach) {
    const size_t last = pts.size() - 1;
    std::vector<double> turn(pts.size(), 0);
    for (size_t k = 1; k < last; ++k)
        turn[k] = std::acos(std::clamp(
            -dot(chordFrom(pts, k, -1, 0, reach), chordFrom(pts, k, +1, last, reach)), -1.0,
            1.0));
    std::vector<size_t> corners;
    for (size_t k = 1; k < last; ++k) {
        if (turn[k] < cornerAngle) continue;
        bool sharpest = true;
        for (size_t q = k > 3 * reach ? k - static_cast<size_t>(3 * reach) : 1;
             q < std::min(last, k + static_cast<size_t>(3 * reach) + 1) && sharpest; ++q)
            if (norm(pts[q] - pts[k]) <= reach && q != k &&
                (turn[q] > turn[k] || (turn[q] == turn[k] && q < k)))
                sharpest = false;
        if (sharpest) corners.push_back(k);
    }
    // Each corner where its arms' lines meet (from the points reach to 3·reach pixels either
    // side), and the rounded points around it dropped.
    std::vector<uint8_t> drop(pts.size(), 0);
    for (size_t c : corners) {
        const size_t a = c > 3 * reach ? c - static_cast<size_t>(3 * reach) : 0;
        const size_t b = std::min(last, c + static_cast<size_t>(3 * reach));
        const Vec2 pa = pts[a], da = chordFrom(pts, a, +1, c, reach);
        const Vec2 pb = pts[b], db = chordFrom(pts, b, -1, c, reach);
        const double den = cross(da, db);
        if (std::fabs(den) < 1e-6) continue;
        const Vec2 meet = pa + (cross(pb - pa, db) / den) * da;
        if (norm(meet - pts[c]) > reach) continue;
        pts[c] = meet;
        for (size_t q = a + 1; q < b; ++q)
            if (q != c && norm(pts[q] - meet) < reach) drop[q] = 1;
    }
    std::vector<Vec2> kept;
    std::vector<size_t> keptCorners;
    for (size_t k = 0, next = 0; k < pts.size(); ++k) {
        if (drop[k]) continue;
        if (next < corners.size() && corners[next] == k) keptCorners.push_back(kept.size()), ++next;
        while (next < corners.size() && corners[next] < k) ++next;
        kept.push_back(pts[k]);
    }
    pts = std::move(kept);
    return keptCorners;
}

}  // namespace

std::vector<Vec2> fitOpenCubics(const std::vector<Vec2>& polyline, double tolerance) {
    std::vector<Vec2> out;
    if (polyline.size() < 2) return out;
    std::vector<size_t> vertexAt;
    std::vector<Vec2> pts = densify(polyline, vertexAt);
    pts.resize(vertexAt.back() + 1);  // densify closes the polygon; an open line ends here
    const size_t last = pts.size() - 1;
    if (last == 0) {
        out.insert(out.end(), {pts[0], pts[0], pts[0], pts[0]});
        return out;
    }
    // Each piece's end tangents along the chord to the point a few pixels in: the first step
    // alone turns with every tenth of a pixel the end point is off.
    constexpr double kTangentReach = 3, kCornerReach = 3;
    constexpr double kCornerAngle = 45 * M_PI / 180;
    std::vector<Vec2> cornered = pts;
    const std::vector<size_t> corners = openCorners(cornered, kCornerAngle, kCornerReach);
    pts = densify(cornered, vertexAt);  // the points a pixel apart again where some dropped
    pts.resize(vertexAt.back() + 1);
    std::vector<size_t> ends{0};
    for (size_t c : corners) ends.push_back(vertexAt[c]);
    const size_t end = pts.size() - 1;
    ends.push_back(end);
    CubicFitter fitter(pts, tolerance);
    for (size_t e = 0; e + 1 < ends.size(); ++e) {
        const size_t a = ends[e], b = ends[e + 1];
        fitter.fit(a, b, chordFrom(pts, a, +1, b, kTangentReach),
                   chordFrom(pts, b, -1, a, kTangentReach), out);
    }
    out.push_back(pts[end]);
    return out;
}

FlatShape traceFlatShape(const RgbaImage& image, const Region& own, const Vec3& col, int overlap,
                         const std::vector<uint8_t>& under, const FlatOptions& options,
                         const LinearGradient& gradient) {
    const int w = own.width, h = own.height;
    std::vector<uint8_t> grown = own.mask;
    const bool sameSize = image.width == w && image.height == h;
    const int reach = std::max(overlap, static_cast<int>(std::ceil(options.hiddenReach)));
    if (reach > 0) {
        const std::vector<uint8_t> d = dilateMask(own.mask, w, h, reach);
        for (size_t k = 0; k < grown.size(); ++k) grown[k] = grown[k] || (d[k] && under[k]);
    }
    const OutlineSlack slack = options.hiddenReach > 0 && sameSize
                                   ? hiddenOutlineSlack(own.mask, under, w, h, options.hiddenReach)
                                   : OutlineSlack{};
    fillHolesUnder(grown, under, w, h);
    RegionOptions regionOptions;
    regionOptions.minArea = 1;
    regionOptions.minHole = options.minHole;
    regionOptions.simplifyTolerance = 0.1;
    regionOptions.maxSegment = 1e6;
    regionOptions.smoothing = options.coverageSmoothing;
    const std::vector<Region> traced = extractRegions(
        sameSize ? shareCoverage(image, own.mask, grown, under, col, options.blendEachSide,
                                 gradient.stops.empty() ? nullptr : &gradient)
                 : coverageFromBits(w, h, grown),
        regionOptions);
    if (traced.empty()) throw Error("the flat region vanished");
    FlatShape shape;
    shape.col = col;
    shape.gradient = gradient;
    // Every piece the outline traces around some of the region's pixels: a line whose coverage
    // dips below one half somewhere traces as several.
    for (const Region& piece : traced) {
        if (!holdsAny(piece.mask, own.mask)) continue;  // another region's border, not ours
        shape.subpaths.push_back(fitClosedCubicsWithin(piece.outer.points, options.curveTolerance,
                                                       options.outlineSmoothing, &slack));
        for (const Polygon& hole : piece.holes)
            shape.subpaths.push_back(fitClosedCubicsWithin(hole.points, options.curveTolerance,
                                                           options.outlineSmoothing, &slack));
    }
    return shape;
}

FlatShape canvasRectangle(int width, int height, const Vec3& col) {
    const double w = width, h = height;
    FlatShape rectangle;
    rectangle.col = col;
    rectangle.subpaths = {polygonAsCubics({{0, 0}, {w, 0}, {w, h}, {0, h}})};
    return rectangle;
}

}  // namespace gm
