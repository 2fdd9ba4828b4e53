// Blobs a flat trace's regions miss, as regions of their own (flat_residue.h).
#include "converters/flat_residue.h"

#include <algorithm>
#include <cmath>

#include "converters/colors.h"
#include "converters/flat_regions.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

namespace gm {

namespace {

// Squared error of colour c against pixel colour v, 0–255 units, mean over channels.
double squaredError(const Vec3& v, const Vec3& c) {
    const Vec3 d = 255.0 * (v - c);
    return (d.r * d.r + d.g * d.g + d.b * d.b) / 3;
}

// The 8-connected blob of `open` pixels around `seed` (cleared from `open` as taken).
std::vector<size_t> takeBlob(std::vector<uint8_t>& open, size_t seed, int w, int h) {
    std::vector<size_t> blob{seed};
    open[seed] = 0;
    for (size_t i = 0; i < blob.size(); ++i) {
        const int x = static_cast<int>(blob[i] % w), y = static_cast<int>(blob[i] / w);
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const size_t q = static_cast<size_t>(yy) * w + xx;
                if (open[q]) open[q] = 0, blob.push_back(q);
            }
    }
    return blob;
}

// The blob's pixels with a 4-neighbour outside it.
size_t borderPixels(const std::vector<size_t>& blob, const std::vector<uint8_t>& in, int w, int h) {
    size_t border = 0;
    for (size_t p : blob) {
        const int x = static_cast<int>(p % w), y = static_cast<int>(p / w);
        border += x == 0 || y == 0 || x + 1 == w || y + 1 == h || !in[p - 1] || !in[p + 1] ||
                  !in[p - w] || !in[p + w];
    }
    return border;
}

Region regionOf(const std::vector<size_t>& blob, int w, int h) {
    Region r;
    r.width = w, r.height = h;
    r.mask.assign(static_cast<size_t>(w) * h, 0);
    for (size_t p : blob) r.mask[p] = 1;
    r.pixelCount = static_cast<int>(blob.size());
    return r;
}

// Pixels that belong to a region before firstInk, as do their 8 neighbours: a pixel beside
// another region's blends with it where the border is anti-aliased, and the regions' outlines
// draw that, no blob. Also each pixel's region (-1: none, or an ink line).
std::vector<uint8_t> insideOneRegion(const std::vector<Region>& regions, size_t firstInk, int w,
                                     int h, std::vector<int>& owner) {
    const size_t n = static_cast<size_t>(w) * h;
    owner.assign(n, -1);
    for (size_t k = 0; k < regions.size(); ++k)
        for (size_t p = 0; p < n; ++p)
            if (regions[k].mask[p]) owner[p] = k < firstInk ? static_cast<int>(k) : -1;
    std::vector<uint8_t> inside(n, 0);
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            const size_t p = static_cast<size_t>(y) * w + x;
            bool same = owner[p] >= 0;
            for (int dy = -1; dy <= 1 && same; ++dy)
                for (int dx = -1; dx <= 1 && same; ++dx)
                    same = owner[p + static_cast<size_t>(dy * w + dx)] == owner[p];
            inside[p] = same;
        }
    return inside;
}

// E of `painted` against the image: the mean channel error, 0–255 units.
double drawnError(const RgbaImage& image, const std::vector<Vec3>& painted) {
    double sum = 0;
    for (size_t p = 0; p < painted.size(); ++p) {
        const Vec3 d = 255.0 * (pixelColour(image, p) - painted[p]);
        sum += (std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b)) / 3;
    }
    return painted.empty() ? 0 : sum / double(painted.size());
}

struct Blob {
    std::vector<size_t> pixels;
    Vec3 mean;
};

// The blobs among `inside` pixels that `painted` misses by a pass's limit, whose squared error
// falls by errorPerByte per byte of their shape when painted in their mean colour, from the
// coarsest pass to the finest; `painted` takes each blob's colour as it is kept.
std::vector<Blob> missedBlobs(const RgbaImage& image, const std::vector<uint8_t>& inside,
                              std::vector<Vec3>& painted, double maxError, double errorPerByte,
                              const ResidueOptions& options) {
    const int w = image.width, h = image.height;
    const size_t n = static_cast<size_t>(w) * h;
    std::vector<uint8_t> taken(n, 0), in(n, 0);
    std::vector<Blob> kept;
    for (double multiple : options.errorMultiples) {
        const double limit = multiple * maxError / 255;
        std::vector<uint8_t> open(n, 0);
        for (size_t p = 0; p < n; ++p) {
            if (!inside[p] || taken[p]) continue;
            const Vec3 d = pixelColour(image, p) - painted[p];
            open[p] = (std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b)) / 3 > limit;
        }
        for (size_t seed = 0; seed < n; ++seed) {
            if (!open[seed]) continue;
            Blob blob{takeBlob(open, seed, w, h), {}};
            if (static_cast<int>(blob.pixels.size()) < options.minPixels) continue;
            for (size_t p : blob.pixels) blob.mean = blob.mean + pixelColour(image, p);
            blob.mean = (1.0 / double(blob.pixels.size())) * blob.mean;
            for (size_t p : blob.pixels) in[p] = 1;
            double gain = 0;
            for (size_t p : blob.pixels) {
                const Vec3 v = pixelColour(image, p);
                gain += squaredError(v, painted[p]) - squaredError(v, blob.mean);
            }
            const double bytes =
                options.bytesPerBlob +
                options.bytesPerBorderPixel * double(borderPixels(blob.pixels, in, w, h));
            for (size_t p : blob.pixels) in[p] = 0;
            if (gain < errorPerByte * bytes) continue;
            for (size_t p : blob.pixels) taken[p] = 1, painted[p] = blob.mean;
            kept.push_back(std::move(blob));
        }
    }
    return kept;
}

}  // namespace

size_t addResidueRegions(const RgbaImage& image, std::vector<Region>& regions, size_t& firstInk,
                         const std::function<Vec3(size_t, size_t)>& paint, double maxError,
                         double errorPerByte, const ResidueOptions& options) {
    const int w = image.width, h = image.height;
    const size_t n = static_cast<size_t>(w) * h;
    std::vector<int> owner;
    const std::vector<uint8_t> inside = insideOneRegion(regions, firstInk, w, h, owner);
    std::vector<Vec3> painted(n);
    for (size_t p = 0; p < n; ++p)
        if (owner[p] >= 0) painted[p] = paint(static_cast<size_t>(owner[p]), p);
    std::vector<Region> added;
    for (const Blob& blob : missedBlobs(image, inside, painted, maxError, errorPerByte, options))
        added.push_back(regionOf(blob.pixels, w, h));
    regions.insert(regions.begin() + static_cast<std::ptrdiff_t>(firstInk), added.begin(),
                   added.end());
    firstInk += added.size();
    return added.size();
}

namespace {

// `shape` (filled, one colour) drawn over `drawn`, from our render of it alone: the pixels it
// touches with their new colours, and the squared error it wins back there.
struct DrawnOver {
    double gain = 0;
    std::vector<std::pair<size_t, Vec3>> pixels;
};
DrawnOver drawOver(const RgbaImage& image, const std::vector<Vec3>& drawn, const FlatShape& shape) {
    double x0 = image.width, y0 = image.height, x1 = 0, y1 = 0;
    for (const auto& subpath : shape.subpaths)
        for (const Vec2& p : subpath)
            x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
            y1 = std::max(y1, p.y);
    const int left = std::max(0, static_cast<int>(std::floor(x0)) - 1);
    const int top = std::max(0, static_cast<int>(std::floor(y0)) - 1);
    const int right = std::min(image.width, static_cast<int>(std::ceil(x1)) + 1);
    const int bottom = std::min(image.height, static_cast<int>(std::ceil(y1)) + 1);
    DrawnOver out;
    if (right <= left || bottom <= top) return out;
    Document alone;
    alone.width = right - left, alone.height = bottom - top;
    FlatShape moved = shape;
    for (auto& subpath : moved.subpaths)
        for (Vec2& p : subpath) p = p - Vec2{double(left), double(top)};
    alone.shapes.push_back(std::move(moved));
    RenderOptions options;
    options.threads = 1;
    const RgbaImage cover = renderDocument(alone, options).image;
    for (int y = top; y < bottom; ++y)
        for (int x = left; x < right; ++x) {
            const double a = cover.at(x - left, y - top)[3];
            if (a <= 0) continue;
            const size_t p = static_cast<size_t>(y) * image.width + x;
            const Vec3 now = a * shape.col + (1 - a) * drawn[p], v = pixelColour(image, p);
            out.gain += squaredError(v, drawn[p]) - squaredError(v, now);
            out.pixels.push_back({p, now});
        }
    return out;
}

}  // namespace

double flatShapeSvgBytes(const FlatShape& shape) {
    constexpr double kPerShape = 40, kPerSegment = 12;
    double bytes = kPerShape;
    for (const auto& subpath : shape.subpaths) bytes += kPerSegment * double(subpath.size() / 3);
    return bytes;
}

std::vector<FlatShape> residueShapes(const RgbaImage& image, const std::vector<Region>& regions,
                                     size_t firstInk, std::vector<Vec3> painted,
                                     double maxError, double errorPerByte,
                                     const FlatOptions& flat, const ResidueOptions& options) {
    const int w = image.width, h = image.height;
    std::vector<int> owner;
    const std::vector<uint8_t> inside = insideOneRegion(regions, firstInk, w, h, owner);
    const double base = std::max(maxError, drawnError(image, painted));
    const std::vector<uint8_t> nothingOnTop(static_cast<size_t>(w) * h, 0);
    std::vector<Vec3> drawn = painted;  // what the shapes kept so far draw over
    std::vector<FlatShape> shapes;
    for (const Blob& blob : missedBlobs(image, inside, painted, base, errorPerByte, options)) {
        FlatShape shape;
        try {
            shape = traceFlatShape(image, regionOf(blob.pixels, w, h), blob.mean, 0,
                                   nothingOnTop, flat);
        } catch (const Error&) {
            continue;  // its traced coverage stays below one half: it draws nothing
        }
        // The blob's gain was an estimate over its pixels; its traced, anti-aliased shape is
        // what a viewer draws, and that must pay too (a blob that mixes two colours traces to
        // a shape of neither).
        const DrawnOver over = drawOver(image, drawn, shape);
        if (over.gain < errorPerByte * flatShapeSvgBytes(shape)) continue;
        for (const auto& [p, c] : over.pixels) drawn[p] = c;
        shapes.push_back(std::move(shape));
    }
    return shapes;
}

}  // namespace gm
