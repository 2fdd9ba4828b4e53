// Whole images must not paint where the image has nothing: small saturated objects on a flat
// background, each smaller than the segmentation's minimum piece, one cut by the image border.
// If an object ends inside the background's region, that region's smooth mesh spreads the
// object's colour far across the background (a stray wedge). Checked as a viewer would see it:
// pixels far from any strong image edge that are badly off.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "converters/convert_segments.h"
#include "formats/raster.h"
#include "image_checks.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

struct Disc {
    double x, y, radius;
    float r, g, b;
};

const Disc kDiscs[] = {
    {8, 120, 15, 0.85f, 0.08f, 0.08f},    // cut by the left border: half a disc
    {80, 60, 14, 0.08f, 0.75f, 0.15f},
    {150, 150, 14, 0.10f, 0.20f, 0.90f},
    {230, 80, 14, 0.95f, 0.45f, 0.05f},
    {250, 190, 14, 0.25f, 0.10f, 0.15f},
};

// 300x240, white, with the discs above, each gently shaded towards its lower right.
RgbaImage discsOnWhite() {
    RgbaImage img(300, 240);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            float* p = img.at(x, y);
            p[0] = p[1] = p[2] = 0.97f, p[3] = 1;
            for (const Disc& d : kDiscs) {
                const double dx = x + 0.5 - d.x, dy = y + 0.5 - d.y;
                if (std::hypot(dx, dy) >= d.radius) continue;
                const float shade = static_cast<float>(0.1 * (dx + dy) / d.radius);
                p[0] = std::clamp(d.r - shade, 0.0f, 1.0f);
                p[1] = std::clamp(d.g - shade, 0.0f, 1.0f);
                p[2] = std::clamp(d.b - shade, 0.0f, 1.0f);
            }
        }
    return img;
}

}  // namespace

TEST_CASE("small objects on a flat background paint nothing beyond themselves",
          "[convert][segment]") {
    const RgbaImage image = discsOnWhite();
    SegmentConvertOptions options;
    SegmentConvertReport report;
    const Document doc = convertSegmented(image, options, "discs", &report);
    const RgbaImage render = renderDocument(doc, RenderOptions{}).image;
    writeImage(render, std::string(GRADMESH_TMP) + "/stray_paint_discs.png");
    const long stray = gm::test::strayPixels(image, render);
    double insideError = 0;
    long insidePixels = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            for (const Disc& d : kDiscs)
                if (std::hypot(x + 0.5 - d.x, y + 0.5 - d.y) < d.radius - 2) {
                    insideError += 3 * gm::test::meanChannelError(image, render, x, y);
                    insidePixels += 3;
                }
    INFO("regions " << report.convert.regions.size() << ", E " << report.convert.error.meanAbs
                    << ", stray " << stray << ", inside E " << insideError / insidePixels);
    // Every disc is a region of its own, besides the background.
    CHECK(report.convert.regions.size() >= 6);
    CHECK(stray == 0);
    CHECK(insideError / insidePixels < 10);
}

TEST_CASE("under a small budget the base paints what the regions leave bare in its own colours",
          "[convert][segment][budget]") {
    // smarties.png at 300 patches: the white table's mesh cuts across the bottom right corner,
    // and the base mesh beneath, fitted to every pixel, painted that corner cyan (1,886 stray
    // pixels). Fitted to the pixels the regions leave showing, it paints it white.
    const RgbaImage image = readImage(std::string(GRADMESH_SAMPLES) + "/smarties.png");
    SegmentConvertOptions options;
    options.convert.maxError = 2;
    options.totalPatches = 300;
    SegmentConvertReport report;
    const Document doc = convertSegmented(image, options, "smarties.png", &report);
    const RgbaImage render = renderDocument(doc, RenderOptions{}).image;
    writeImage(render, std::string(GRADMESH_TMP) + "/stray_paint_smarties_300.png");
    const long stray = gm::test::strayPixels(image, render);
    INFO("base " << report.basePatches << " patches, " << report.regionUncovered
                 << " of the pixels left to it; stray " << stray << ", PSNR "
                 << report.convert.error.psnr);
    CHECK(report.regionUncovered > 0.005);  // the corner is the base's
    CHECK(stray < 200);
    CHECK(report.convert.error.psnr > 28);
}
