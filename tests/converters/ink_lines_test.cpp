// Ink lines (segment_ink.h): a cartoon's outlines become labels of their own and flat shapes
// drawn over the meshes of the regions they divide; a photograph's dark creases do not.
#include <catch2/catch.hpp>

#include <sstream>
#include <string>

#include "cartoon_scene.h"
#include "converters/convert_segments.h"
#include "converters/segment.h"
#include "formats/raster.h"
#include "image_checks.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

// Of the pixels fully inside the outlines, the share that the segmentation gave an ink label.
double inkShareOfOutlines(const test::CartoonScene& scene, const Segmentation& s) {
    long inside = 0, inked = 0;
    const int firstInk = s.count - s.inkLabels;
    for (const auto& cover : scene.coverage)
        for (size_t p = 0; p < cover.size(); ++p)
            if (cover[p] >= 1) {
                ++inside;
                inked += s.labels[p] >= firstInk;
            }
    return inside > 0 ? double(inked) / double(inside) : 0;
}

struct OutlineFigures {
    int broken = 0;        // centre-line pixels with a channel off by more than 48
    double coreError = 0;  // mean channel error over the pixels fully inside, 0-255
};

OutlineFigures measureOutline(const test::CartoonScene& scene, size_t k, const RgbaImage& render) {
    OutlineFigures f;
    const RgbaImage& image = scene.image;
    std::vector<uint8_t> seen(scene.coverage[k].size(), 0);
    for (const Vec2& p : scene.outlines[k].centreLine()) {
        const int x = static_cast<int>(p.x), y = static_cast<int>(p.y);
        const size_t i = static_cast<size_t>(y) * image.width + x;
        if (seen[i]) continue;
        seen[i] = 1;
        f.broken += test::worstChannelError(image, render, x, y) > 48;
    }
    long n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (scene.coverage[k][static_cast<size_t>(y) * image.width + x] >= 1) {
                f.coreError += test::meanChannelError(image, render, x, y);
                ++n;
            }
    f.coreError /= std::max(1L, n);
    return f;
}

// The mean channel error (0-255) over the pixels no outline touches (the fills), or only over
// those of them inside the fin and the body both (the lens the two outlines enclose).
double fillError(const test::CartoonScene& scene, const RgbaImage& render, bool lensOnly) {
    double sum = 0;
    long n = 0;
    const int W = scene.image.width;
    for (int y = 0; y < scene.image.height; ++y)
        for (int x = 0; x < W; ++x) {
            bool touched = false;
            for (const auto& cover : scene.coverage)
                touched = touched || cover[static_cast<size_t>(y) * W + x] > 0;
            const bool lens = test::cartoon::inEllipse(x + 0.5, y + 0.5, 190, 52, 30, 14) &&
                              test::cartoon::inEllipse(x + 0.5, y + 0.5, 110, 95, 85, 58);
            if (touched || (lensOnly && !lens)) continue;
            sum += test::meanChannelError(scene.image, render, x, y);
            ++n;
        }
    return sum / double(std::max(1L, n));
}

}  // namespace

TEST_CASE("a cartoon's outlines become ink lines; a photograph's creases do not",
          "[segment][ink]") {
    const test::CartoonScene scene = test::cartoonScene();
    writeImage(scene.image, std::string(GRADMESH_TMP) + "/cartoon.png");
    const Segmentation s = segmentImage(scene.image);
    const double share = inkShareOfOutlines(scene, s);
    std::printf("cartoon: %d labels, %d ink lines, %.3f of the outlines' pixels inked\n", s.count,
                s.inkLabels, share);
    CHECK(s.inkLabels >= 1);
    CHECK(share >= 0.9);
    SegmentOptions off;
    off.inkLines = false;
    CHECK(segmentImage(scene.image, off).inkLabels == 0);
    // A photograph: its ink candidates lie along few of its regions' borders.
    const Segmentation photo =
        segmentImage(readImage(std::string(GRADMESH_SAMPLES) + "/astronaut.png"));
    CHECK(photo.inkLabels == 0);
}

TEST_CASE("a cartoon's outlines convert unbroken as flat shapes over the meshes",
          "[convert][segment][ink]") {
    const test::CartoonScene scene = test::cartoonScene();
    std::ostringstream text;
    double coreWithout = 0;
    for (const bool ink : {true, false}) {
        SegmentConvertOptions o;
        o.segment.inkLines = ink;
        SegmentConvertReport report;
        const Document doc = convertSegmented(scene.image, o, "cartoon", &report);
        const RgbaImage render = renderDocument(doc, RenderOptions{}).image;
        writeImage(render, std::string(GRADMESH_TMP) + (ink ? "/cartoon_ink.png" : "/cartoon_no_ink.png"));
        const double fills = fillError(scene, render, false);
        const double lens = fillError(scene, render, true);
        text << (ink ? "ink lines" : "without") << ": " << doc.meshes.size() << " meshes, "
             << report.convert.patches << " patches, " << doc.shapes.size() << " shapes, E "
             << report.convert.error.meanAbs << ", fills E " << fills << ", lens E " << lens
             << "\n";
        int broken = 0;
        double core = 0;
        for (size_t k = 0; k < scene.outlines.size(); ++k) {
            const OutlineFigures f = measureOutline(scene, k, render);
            text << "  " << scene.outlines[k].name << ": broken " << f.broken << ", core E "
                 << f.coreError << "\n";
            broken += f.broken;
            core = std::max(core, f.coreError);
        }
        if (!ink) {
            coreWithout = core;
            continue;
        }
        CHECK(broken == 0);
        CHECK(core <= 10);
        CHECK(fills <= 1);
        CHECK(lens <= 5);  // where the fin's outline crosses the body's: not ink
        CHECK(test::strayPixels(scene.image, render) == 0);
        // The outlines are flat shapes drawn over every mesh.
        REQUIRE_FALSE(doc.shapes.empty());
        CHECK(doc.shapes.back().layer == doc.meshes.size());
    }
    WARN(text.str());
    CHECK(coreWithout > 10);  // what the meshes alone make of the outlines
}
