// Flat shapes in the raster re-renderer: the outline flattened as finely as a mesh outline, its
// exact area coverage (nonzero rule) as alpha, one colour composited "over" the image, in strips
// of rows so that a canvas-sized shape needs no canvas-sized scratch buffer.
#include <algorithm>
#include <cmath>

#include "render_internal.h"

namespace gm {
namespace render_detail {

namespace {

constexpr int kShapeStripRows = 64;

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

}  // namespace

void renderShape(const FlatShape& shape, const RenderOptions& options, RgbaImage& image,
                 std::vector<PixelSample>* samples) {
    double tol = options.positionTolerance;
    if (!(tol > 0) || !std::isfinite(tol)) tol = 0.125;
    const std::vector<std::vector<Vec2>> loops =
        shapeLoops(shape, options.scale, std::max(std::min(tol, 0.125) / 32, 1e-5));
    double minX = INFINITY, minY = INFINITY, maxX = -INFINITY, maxY = -INFINITY;
    for (const auto& loop : loops)
        for (const Vec2& p : loop) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
            minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
            minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
        }
    const double x0 = std::max(0.0, std::floor(minX)), y0 = std::max(0.0, std::floor(minY));
    const double x1 = std::min<double>(image.width, std::ceil(maxX) + 1);
    const double y1 = std::min<double>(image.height, std::ceil(maxY) + 1);
    if (!(x1 > x0 && y1 > y0)) return;
    const int originY = static_cast<int>(y0), rows = static_cast<int>(y1) - originY;
    LayerRows band;  // one strip: buffer row 0 is image row originY + r0
    band.originX = static_cast<int>(x0);
    band.width = static_cast<int>(x1) - band.originX;
    const float col[3] = {static_cast<float>(shape.col.r), static_cast<float>(shape.col.g),
                          static_cast<float>(shape.col.b)};
    const float opacity = static_cast<float>(std::clamp(shape.alpha, 0.0, 1.0));
    std::vector<double> accumulator;
    std::vector<float> alpha;
    for (int r0 = 0; r0 < rows; r0 += kShapeStripRows) {
        band.originY = originY + r0;
        band.y0 = 0;
        band.y1 = std::min(rows - r0, kShapeStripRows);
        alpha.assign(static_cast<size_t>(band.width) * band.y1, 0.0f);
        accumulateCoverage(loops, band, accumulator, alpha.data());
        for (int r = 0; r < band.y1; ++r) {
            const int y = band.originY + r;
            for (int x = 0; x < band.width; ++x) {
                float a = alpha[static_cast<size_t>(r) * band.width + x];
                if (!options.antialias) a = a >= 0.5f ? 1.0f : 0.0f;
                a *= opacity;
                if (!(a > 0)) continue;
                paintOver(image.at(band.originX + x, y), col, a);
                if (samples && a >= 1.0f)
                    (*samples)[static_cast<size_t>(y) * image.width + band.originX + x] =
                        PixelSample{};
            }
        }
    }
}

}  // namespace render_detail
}  // namespace gm
