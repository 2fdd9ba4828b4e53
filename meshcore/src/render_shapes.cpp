// Flat shapes in the raster re-renderer, one colour composited "over" the image, in strips of
// rows so that a canvas-sized shape needs no canvas-sized scratch buffer.
//  - A filled shape: the outline flattened as finely as a mesh outline, its exact area coverage
//    (nonzero rule) as alpha.
//  - A stroked shape: the centrelines flattened as finely, each segment widened to a capsule (the
//    union of the capsules is the stroke with round caps and joins); a pixel's alpha is the
//    largest of its capsules' coverages, each that of a straight edge through the nearest
//    point of the outline (box-filtered exactly).
#include <algorithm>
#include <cmath>

#include "render_internal.h"

namespace gm {
namespace render_detail {

namespace {

constexpr int kShapeStripRows = 64;
// Half a pixel's diagonal: every point of a pixel lies this near its centre.
constexpr double kHalfDiagonal = 0.70710678118654752;

double flatteningTolerance(const RenderOptions& options) {
    double tol = options.positionTolerance;
    if (!(tol > 0) || !std::isfinite(tol)) tol = 0.125;
    return std::max(std::min(tol, 0.125) / 32, 1e-5);
}

std::vector<std::vector<Vec2>> shapeLoops(const FlatShape& shape, double scale, double tolerance) {
    std::vector<std::vector<Vec2>> loops;
    for (const std::vector<Vec2>& path : shape.subpaths) {
        const size_t n = path.size();
        if (n < 3 || n % 3 != 0) continue;
        std::vector<Vec2> loop{scale * path[0]};
        for (size_t k = 0; k < n; k += 3)
            flattenCubic(scale * path[k], scale * path[k + 1], scale * path[k + 2],
                         scale * path[(k + 3) % n], tolerance, loop);
        loop.pop_back();  // the closing point repeats the first
        loops.push_back(std::move(loop));
    }
    return loops;
}

// The centrelines of a stroked shape as polylines (a closed one ends on its first point).
std::vector<std::vector<Vec2>> strokeLines(const FlatShape& shape, double scale, double tolerance) {
    std::vector<std::vector<Vec2>> lines;
    for (const std::vector<Vec2>& path : shape.subpaths) {
        const size_t n = path.size();
        if (n < 4 || n % 3 != 1) continue;
        std::vector<Vec2> line{scale * path[0]};
        for (size_t k = 0; k + 3 < n; k += 3)
            flattenCubic(scale * path[k], scale * path[k + 1], scale * path[k + 2],
                         scale * path[k + 3], tolerance, line);
        lines.push_back(std::move(line));
    }
    return lines;
}

// v clamped to [lo, hi] as an int (v may lie far beyond the int range; NaN gives lo).
int clampedIndex(double v, int lo, int hi) {
    return !(v > lo) ? lo : (v >= hi ? hi : static_cast<int>(v));
}

// The share of a unit pixel on the near side of a straight edge at signed distance s beyond its
// centre, the edge's normal (nx, ny) a unit vector: the distribution function of the projection
// of a uniform point of the pixel onto the normal, whose density is a trapezoid.
double edgeCoverage(double s, double nx, double ny) {
    const double a = std::max(std::fabs(nx), std::fabs(ny)),
                 b = std::min(std::fabs(nx), std::fabs(ny));
    const double outer = (a + b) / 2, inner = (a - b) / 2;
    if (s <= -outer) return 0;
    if (s >= outer) return 1;
    if (s < -inner) return (s + outer) * (s + outer) / (2 * a * b);
    if (s > inner) return 1 - (outer - s) * (outer - s) / (2 * a * b);
    return 0.5 + s / a;
}

// A piece of a stroke: a segment of its centreline and every point within `half` of it, a
// rectangle with a half disc at either end. The union of a centreline's capsules is its stroke
// with round caps and joins. Coordinates are relative to the band's origin: buffer pixel (x, y)
// has its centre at (x + 0.5, y + 0.5).
struct Capsule {
    Vec2 p, d;       // the segment from p to p + d
    double len = 0;  // |d|
    Vec2 u, n;       // unit direction and normal; (0, 1) and (1, 0) for a single point
    double half = 0;
};

Capsule capsule(Vec2 p, Vec2 q, double half) {
    Capsule k;
    k.p = p, k.d = q - p, k.len = norm(k.d), k.half = half;
    k.u = k.len > 0 ? (1 / k.len) * k.d : Vec2{0, 1};
    k.n = {-k.u.y, k.u.x};
    return k;
}

// Where the line y = cy crosses the points within `rho` of the capsule's segment: [lo, hi],
// false when it misses. That region is convex: its chord spans the chords of the rectangle and
// of the two end discs that make it up.
bool chord(const Capsule& k, double rho, double cy, double& lo, double& hi) {
    lo = INFINITY, hi = -INFINITY;
    for (Vec2 e : {k.p, k.p + k.d}) {
        const double dy = cy - e.y, h2 = rho * rho - dy * dy;
        if (h2 < 0) continue;
        const double h = std::sqrt(h2);
        lo = std::min(lo, e.x - h), hi = std::max(hi, e.x + h);
    }
    // The rectangle: X = (p.x + ex, cy) with |n·(X - p)| <= rho and 0 <= u·(X - p) <= len.
    const double ey = cy - k.p.y;
    double a = -INFINITY, b = INFINITY;
    auto slab = [&](Vec2 axis, double from, double to) {
        const double c = axis.y * ey;
        if (std::fabs(axis.x) < 1e-12) {
            if (c < from || c > to) a = INFINITY;
            return;
        }
        const double s = (from - c) / axis.x, t = (to - c) / axis.x;
        a = std::max(a, std::min(s, t)), b = std::min(b, std::max(s, t));
    };
    if (k.len > 0) {
        slab(k.n, -rho, rho);
        slab(k.u, 0, k.len);
        if (a <= b) lo = std::min(lo, k.p.x + a), hi = std::max(hi, k.p.x + b);
    }
    return lo <= hi;
}

// The capsule's coverage of the pixel centred at `centre`: that of the straight band 2·half
// wide along the normal through the nearest point of the segment (exact where the outline is
// straight; on the end discs, the tangent's coverage).
double capsuleCoverage(const Capsule& k, Vec2 centre) {
    const double t = std::clamp(dot(centre - k.p, k.u), 0.0, k.len);
    const Vec2 off = centre - (k.p + t * k.u);
    const double dist = norm(off);
    // A centre on the centreline takes the segment's own normal.
    const Vec2 n = dist > 1e-9 ? (1 / dist) * off : k.n;
    const double a = edgeCoverage(k.half - dist, n.x, n.y) - edgeCoverage(-k.half - dist, n.x, n.y);
    return a >= 1 - 1e-9 ? 1.0 : a;
}

// Covers the capsule in rows [band.y0, band.y1): pixels wholly inside it add a run to `full`
// (per row of width + 1 counts: +1 at the run's first column, -1 after its last), pixels on
// its outline raise alpha to their coverage.
void coverCapsule(const Capsule& k, const LayerRows& band, float* alpha, int* full) {
    const double reach = k.half + kHalfDiagonal;   // a pixel centred farther lies wholly outside
    const double inside = k.half - kHalfDiagonal;  // a pixel centred nearer lies wholly inside
    const double top = std::min(k.p.y, k.p.y + k.d.y), bottom = std::max(k.p.y, k.p.y + k.d.y);
    const int r0 = clampedIndex(std::ceil(top - reach - 0.5), band.y0, band.y1);
    const int r1 = clampedIndex(std::floor(bottom + reach - 0.5) + 1, band.y0, band.y1);
    for (int r = r0; r < r1; ++r) {
        const double cy = r + 0.5;
        double lo, hi;
        if (!chord(k, reach, cy, lo, hi)) continue;
        const int c0 = clampedIndex(std::ceil(lo - 0.5), 0, band.width);
        const int c1 = clampedIndex(std::floor(hi - 0.5) + 1, c0, band.width);
        int i0 = c1, i1 = c1;  // the pixels wholly inside: [i0, i1)
        if (inside > 0 && chord(k, inside, cy, lo, hi)) {
            i0 = clampedIndex(std::ceil(lo - 0.5), c0, c1);
            i1 = clampedIndex(std::floor(hi - 0.5) + 1, i0, c1);
        }
        if (i1 > i0) {
            int* runs = full + static_cast<size_t>(r) * (band.width + 1);
            ++runs[i0], --runs[i1];
        }
        float* row = alpha + static_cast<size_t>(r) * band.width;
        auto coverSpan = [&](int from, int to) {
            for (int c = from; c < to; ++c)
                if (row[c] < 1.0f)
                    row[c] = std::max(row[c], float(capsuleCoverage(k, {c + 0.5, cy})));
        };
        coverSpan(c0, i0);
        coverSpan(i1, c1);
    }
}

// The stroke's coverage of rows [band.y0, band.y1) into alpha (zeroed by the caller); `full` is
// scratch.
void strokeCoverage(const std::vector<std::vector<Vec2>>& lines, double half, const LayerRows& band,
                    std::vector<int>& full, float* alpha) {
    const size_t stride = static_cast<size_t>(band.width) + 1;
    full.assign(stride * band.y1, 0);
    const Vec2 origin{double(band.originX), double(band.originY)};
    const double top = band.y0 - half - 1, bottom = band.y1 + half + 1;
    for (const std::vector<Vec2>& line : lines)
        for (size_t k = 0; k + 1 < line.size(); ++k) {
            const Vec2 p = line[k] - origin, q = line[k + 1] - origin;
            if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(q.x) &&
                  std::isfinite(q.y)))
                continue;
            if (std::max(p.y, q.y) < top || std::min(p.y, q.y) > bottom) continue;
            coverCapsule(capsule(p, q, half), band, alpha, full.data());
        }
    for (int r = band.y0; r < band.y1; ++r) {
        const int* runs = &full[static_cast<size_t>(r) * stride];
        float* row = alpha + static_cast<size_t>(r) * band.width;
        int depth = 0;
        for (int c = 0; c < band.width; ++c)
            if ((depth += runs[c]) > 0) row[c] = 1.0f;
    }
}

void paintOver(float* out, const float col[3], float a) {
    const float d = out[3];
    if (a >= 1.0f || d <= 0.0f) {
        out[0] = col[0], out[1] = col[1], out[2] = col[2], out[3] = a;
        return;
    }
    const float under = d * (1 - a), total = a + under;
    for (int c = 0; c < 3; ++c) out[c] = (col[c] * a + out[c] * under) / total;
    out[3] = total;
}

// The image pixels [x0, x1) x [y0, y1) that the polylines, widened by `margin`, may touch.
struct PixelBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
};

PixelBox pixelBox(const std::vector<std::vector<Vec2>>& lines, double margin,
                  const RgbaImage& image) {
    double minX = INFINITY, minY = INFINITY, maxX = -INFINITY, maxY = -INFINITY;
    for (const auto& line : lines)
        for (const Vec2& p : line) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
            minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
            minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
        }
    minX -= margin, minY -= margin, maxX += margin, maxY += margin;
    const double x0 = std::max(0.0, std::floor(minX)), y0 = std::max(0.0, std::floor(minY));
    const double x1 = std::min<double>(image.width, std::ceil(maxX) + 1);
    const double y1 = std::min<double>(image.height, std::ceil(maxY) + 1);
    if (!(x1 > x0 && y1 > y0)) return {};
    return {static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(x1), static_cast<int>(y1)};
}

// Paints the band's alpha (its rows [0, band.y1)) times the shape's opacity in its colour (or
// its gradient's at the pixel's centre) over the image; pixels it covers opaquely lose their
// mesh sample.
void paintRows(const FlatShape& shape, const RenderOptions& options, const LayerRows& band,
               const float* alpha, RgbaImage& image, std::vector<PixelSample>* samples) {
    float col[3] = {static_cast<float>(shape.col.r), static_cast<float>(shape.col.g),
                    static_cast<float>(shape.col.b)};
    const float opacity = static_cast<float>(std::clamp(shape.alpha, 0.0, 1.0));
    const bool graded = shape.graded();
    for (int r = 0; r < band.y1; ++r) {
        const int y = band.originY + r;
        for (int x = 0; x < band.width; ++x) {
            float a = alpha[static_cast<size_t>(r) * band.width + x];
            if (!options.antialias) a = a >= 0.5f ? 1.0f : 0.0f;
            a *= opacity;
            if (!(a > 0)) continue;
            if (graded) {
                const Vec2 centre{(band.originX + x + 0.5) / options.scale,
                                  (y + 0.5) / options.scale};
                const Vec3 c = shape.gradient.colourAt(centre);
                for (int k = 0; k < 3; ++k) col[k] = static_cast<float>(c[k]);
            }
            paintOver(image.at(band.originX + x, y), col, a);
            if (samples && a >= 1.0f)
                (*samples)[static_cast<size_t>(y) * image.width + band.originX + x] = PixelSample{};
        }
    }
}

}  // namespace

void renderShape(const FlatShape& shape, const RenderOptions& options, RgbaImage& image,
                 std::vector<PixelSample>* samples) {
    const double tolerance = flatteningTolerance(options);
    const bool stroked = shape.stroked();
    const double half = stroked ? options.scale * shape.strokeWidth / 2 : 0.0;
    if (!std::isfinite(half)) return;
    // Closed outlines of a filled shape, the centrelines of a stroke.
    const std::vector<std::vector<Vec2>> lines = stroked
                                                     ? strokeLines(shape, options.scale, tolerance)
                                                     : shapeLoops(shape, options.scale, tolerance);
    const PixelBox box = pixelBox(lines, half, image);
    if (box.empty()) return;
    LayerRows band;  // one strip: buffer row 0 is image row box.y0 + r0
    band.originX = box.x0;
    band.width = box.x1 - box.x0;
    std::vector<double> accumulator;
    std::vector<int> runs;
    std::vector<float> alpha;
    for (int r0 = 0; r0 < box.y1 - box.y0; r0 += kShapeStripRows) {
        band.originY = box.y0 + r0;
        band.y0 = 0;
        band.y1 = std::min(box.y1 - band.originY, kShapeStripRows);
        alpha.assign(static_cast<size_t>(band.width) * band.y1, 0.0f);
        if (stroked)
            strokeCoverage(lines, half, band, runs, alpha.data());
        else
            accumulateCoverage(lines, band, accumulator, alpha.data());
        paintRows(shape, options, band, alpha.data(), image, samples);
    }
}

}  // namespace render_detail
}  // namespace gm
