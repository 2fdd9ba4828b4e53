// Blobs a flat trace's regions miss, as regions of their own (flat_residue.h).
#include "converters/flat_residue.h"

#include <algorithm>
#include <cmath>

#include "converters/colors.h"

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

}  // namespace

size_t addResidueRegions(const RgbaImage& image, std::vector<Region>& regions, size_t& firstInk,
                         const std::function<Vec3(size_t, size_t)>& paint, double maxError,
                         double errorPerByte, const ResidueOptions& options) {
    const int w = image.width, h = image.height;
    const size_t n = static_cast<size_t>(w) * h;
    std::vector<int> owner(n, -1);
    for (size_t k = 0; k < regions.size(); ++k)
        for (size_t p = 0; p < n; ++p)
            if (regions[k].mask[p]) owner[p] = k < firstInk ? static_cast<int>(k) : -1;
    // A pixel beside another region's blends with it where the border is anti-aliased: the
    // regions' outlines draw that, no blob.
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
    std::vector<Vec3> painted(n);
    for (size_t p = 0; p < n; ++p)
        if (owner[p] >= 0) painted[p] = paint(static_cast<size_t>(owner[p]), p);
    std::vector<uint8_t> taken(n, 0);
    std::vector<Region> added;
    for (double multiple : options.errorMultiples) {
        const double limit = multiple * maxError / 255;
        std::vector<uint8_t> open(n, 0);
        for (size_t p = 0; p < n; ++p) {
            if (!inside[p] || taken[p]) continue;
            const Vec3 d = pixelColour(image, p) - painted[p];
            open[p] = (std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b)) / 3 > limit;
        }
        std::vector<uint8_t> in(n, 0);
        for (size_t seed = 0; seed < n; ++seed) {
            if (!open[seed]) continue;
            const std::vector<size_t> blob = takeBlob(open, seed, w, h);
            if (static_cast<int>(blob.size()) < options.minPixels) continue;
            Vec3 mean;
            for (size_t p : blob) mean = mean + pixelColour(image, p);
            mean = (1.0 / double(blob.size())) * mean;
            double gain = 0;
            for (size_t p : blob) {
                const Vec3 v = pixelColour(image, p);
                gain += squaredError(v, painted[p]) - squaredError(v, mean);
            }
            for (size_t p : blob) in[p] = 1;
            const double bytes = options.bytesPerBlob +
                                 options.bytesPerBorderPixel * double(borderPixels(blob, in, w, h));
            for (size_t p : blob) in[p] = 0;
            if (gain < errorPerByte * bytes) continue;
            for (size_t p : blob) taken[p] = 1, painted[p] = mean;
            added.push_back(regionOf(blob, w, h));
        }
    }
    regions.insert(regions.begin() + static_cast<std::ptrdiff_t>(firstInk), added.begin(),
                   added.end());
    firstInk += added.size();
    return added.size();
}

}  // namespace gm
