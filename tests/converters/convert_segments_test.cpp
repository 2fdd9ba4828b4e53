// Whole images (--segment): a synthetic scene of smoothly shaded areas, one of them a ring
// around another, converted region by region over the base mesh; the render checked for
// coverage, seams, holes and error.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "converters/convert_segments.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/render.h"

using namespace gm;

namespace {

// 240x200: a vertical blue gradient background, an orange ring (a hole holding a green disc),
// and a pink rounded box, all gently shaded.
RgbaImage scene() {
    const int W = 240, H = 200;
    RgbaImage img(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            float r = 0.15f + 0.1f * float(py / H), g = 0.25f + 0.15f * float(py / H), b = 0.75f;
            const double d = std::hypot(px - 90, py - 100);
            if (d < 60 && d >= 28) {  // ring
                r = 0.95f - 0.2f * float(d / 60), g = 0.55f + 0.1f * float(px / W), b = 0.1f;
            } else if (d < 28) {      // disc in the ring's hole
                r = 0.2f, g = 0.7f + 0.2f * float(py / H), b = 0.25f;
            } else if (px > 165 && px < 225 && py > 40 && py < 170) {  // box
                r = 0.9f, g = 0.45f + 0.2f * float(py / H), b = 0.6f;
            }
            float* p = img.at(x, y);
            p[0] = r, p[1] = g, p[2] = b, p[3] = 1;
        }
    return img;
}

}  // namespace

TEST_CASE("a segmented scene converts with every pixel painted and its ring keeps its hole",
          "[convert][segment]") {
    const RgbaImage image = scene();
    SegmentConvertOptions o;
    SegmentConvertReport rep;
    const Document doc = convertSegmented(image, o, "scene", &rep);
    INFO("regions " << rep.convert.regions.size() << ", failed " << rep.failedRegions
                    << ", holes filled " << rep.filledRegions << ", E " << rep.convert.error.meanAbs
                    << ", border E " << rep.border.meanAbs << ", interior E "
                    << rep.interior.meanAbs << ", region-uncovered " << rep.regionUncovered);
    for (size_t k = 0; k < rep.fallbacks.size(); ++k)
        if (!rep.fallbacks[k].empty())
            WARN("region " << k << " (" << rep.convert.regions[k].pixels << " px): " << rep.fallbacks[k]);
    // Background, ring, disc, box (the segmentation may split the background's gradient).
    CHECK(rep.convert.regions.size() >= 4);
    CHECK(rep.convert.regions.size() <= 8);
    CHECK(rep.failedRegions == 0);
    CHECK(rep.filledRegions == 0);
    // A mesh or a flat shape per region, + the base mesh.
    REQUIRE(doc.meshes.size() + doc.shapes.size() == rep.convert.regions.size() + 1);
    CHECK(doc.shapes.size() == static_cast<size_t>(rep.flatRegions));
    // Every pixel painted; the regions alone paint all but a few (where the base shows).
    CHECK(rep.convert.error.uncovered == 0);
    CHECK(rep.regionUncovered < 0.002);
    CHECK(rep.convert.error.meanAbs < 3.0);
    CHECK(rep.interior.meanAbs < 2.0);
    // Borders are where segments meet: worse than the inside, but no background line. (The
    // background is one region with two holes, so its mesh wraps both the ring and the box.)
    CHECK(rep.border.meanAbs < 14.0);
    // The ring is one mesh with one slit.
    int slitted = 0;
    for (const GradientMesh& m : doc.meshes) slitted += m.holeCount() == 1;
    CHECK(slitted >= 1);
    RgbaImage render = renderDocument(doc, RenderOptions{}).image;
    writeImage(render, std::string(GRADMESH_TMP) + "/segment_scene.png");
}

TEST_CASE("a region's budget is at most one patch per pixelsPerPatch pixels",
          "[convert][segment]") {
    // The scene with a finely striped box: out of reach for a low target, so the budget is
    // what stops its refinement.
    RgbaImage image = scene();
    for (int y = 41; y < 170; ++y)
        for (int x = 166; x < 225; ++x) {
            float* p = image.at(x, y);
            p[1] = 0.45f + 0.25f * float(std::sin(x / 1.7) * std::sin(y / 2.3));
        }
    SegmentConvertOptions o;
    o.convert.maxError = 0.3;
    o.convert.maxPatches = 1500;
    // Hermite colours: their refinement runs on into the stripes, which the cap must stop
    // (bicubic refinement stalls on them before the cap).
    o.convert.colors = ColorMode::Fit;
    long capped = 0, uncapped = 0;
    for (double ppp : {0.0, 8.0}) {
        o.pixelsPerPatch = ppp;
        SegmentConvertReport rep;
        convertSegmented(image, o, "striped scene", &rep);
        REQUIRE(rep.failedRegions == 0);
        int over = 0;
        for (const RegionReport& r : rep.convert.regions) {
            const long cap = std::max<long>(o.minRegionPatches, r.pixels / 8);
            if (r.patches > cap) ++over;
            if (ppp > 0) {
                INFO("region of " << r.pixels << " px: " << r.patches << " patches");
                CHECK(r.patches <= cap);
            }
        }
        (ppp > 0 ? capped : uncapped) = rep.convert.patches;
        if (ppp == 0) CHECK(over >= 1);  // the stripes would take more without the cap
        CHECK(rep.convert.error.uncovered == 0);
    }
    WARN("striped scene: " << uncapped << " patches without the per-pixel cap, " << capped
                           << " with one patch per 8 pixels");
    CHECK(capped < uncapped);
}

TEST_CASE("an image too small to segment into anything still converts", "[convert][segment]") {
    RgbaImage image(24, 20);
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 24; ++x) {
            float* p = image.at(x, y);
            p[0] = float(x) / 24, p[1] = float(y) / 20, p[2] = 0.5f, p[3] = 1;
        }
    SegmentConvertReport rep;
    const Document doc = convertSegmented(image, SegmentConvertOptions{}, "tiny", &rep);
    CHECK(rep.convert.error.uncovered == 0);
    CHECK(rep.convert.error.meanAbs < 3.0);
    CHECK(!doc.meshes.empty());
}

TEST_CASE("an empty image is refused", "[convert][segment]") {
    CHECK_THROWS_AS(convertSegmented(RgbaImage(), SegmentConvertOptions{}, "empty"), Error);
}

TEST_CASE("converting the same image twice gives the same meshes", "[convert][segment]") {
    // The triangulation once chose which edges to split by face address (allocation order):
    // HappyFish's regions got 446 or 448 triangles from one call to the next.
    const RgbaImage image = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
    SegmentConvertOptions o;
    o.threads = 2;
    const Document a = convertSegmented(image, o, "HappyFish.jpg");
    const Document b = convertSegmented(image, o, "HappyFish.jpg");
    REQUIRE(a.meshes.size() == b.meshes.size());
    for (size_t k = 0; k < a.meshes.size(); ++k) {
        INFO("mesh " << k);
        CHECK(a.meshes[k] == b.meshes[k]);
    }
}

TEST_CASE("a region with parts too thin for its map gets them as meshes of their own",
          "[convert][segment]") {
    // The scene's pink box with a comb of 2 px strokes above it in the same pink (a rail and
    // nine teeth on a stem): no one map of box and comb works, so the box is converted without
    // the comb and the comb's pieces on their own (in parts or tiles). Before, the comb was
    // left to the base mesh. (A ladder with loops does not do: the segmentation merges the
    // loops' insides into the box's region.)
    RgbaImage image = scene();
    std::vector<uint8_t> comb(static_cast<size_t>(image.width) * image.height, 0);
    auto stroke = [&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                float* p = image.at(x, y);
                p[0] = 0.9f, p[1] = 0.45f + 0.2f * float(y) / image.height, p[2] = 0.6f;
                comb[static_cast<size_t>(y) * image.width + x] = 1;
            }
    };
    stroke(194, 30, 196, 41);                                  // stem up from the box
    stroke(150, 28, 238, 30);                                  // a rail, 2 px
    for (int x = 150; x < 238; x += 11) stroke(x, 4, x + 2, 28);  // teeth up from it
    // neckSplits 0: the core and its thin parts; by default the region, whose one map fails,
    // is first cut at a neck (the comb off the box), each side converted on its own.
    for (const int splits : {0, 2}) {
        DYNAMIC_SECTION("neckSplits " << splits) {
            SegmentConvertOptions o;
            o.neckSplits = splits;
            o.segment.inkLines = false;  // else the comb is lifted as ink lines, flat shapes
            o.gradients = false;  // else the box and comb, a vertical ramp, are one gradient
            SegmentConvertReport rep;
            const Document doc = convertSegmented(image, o, "box with comb", &rep);
            for (size_t k = 0; k < rep.fallbacks.size(); ++k)
                if (!rep.fallbacks[k].empty())
                    WARN("region " << k << " (" << rep.convert.regions[k].pixels
                                   << " px): " << rep.fallbacks[k]);
            CHECK(rep.failedRegions == 0);
            CHECK((splits == 0 ? rep.trimmedRegions : rep.splitRegions) >= 1);
            CHECK(rep.convert.error.uncovered == 0);
            // The comb is painted in its own colours by region meshes: not by the base mesh,
            // nor by the blue background's mesh reaching under it (a pixel from each side
            // covers a 2 px stroke).
            Document regionsOnly = doc;
            regionsOnly.meshes.erase(regionsOnly.meshes.begin());
            const RgbaImage r = renderDocument(regionsOnly, RenderOptions{}).image;
            long inComb = 0, painted = 0;
            double err = 0;
            for (int y = 0; y < image.height; ++y)
                for (int x = 0; x < image.width; ++x)
                    if (comb[static_cast<size_t>(y) * image.width + x]) {
                        ++inComb;
                        const float* q = r.at(x, y);
                        if (q[3] < 0.5f) continue;
                        ++painted;
                        for (int c = 0; c < 3; ++c)
                            err += std::fabs(q[c] - image.at(x, y)[c]) * 255 / 3;
                    }
            const double combE = painted ? err / painted : 0;
            INFO(painted << " of " << inComb << " comb pixels painted by region meshes, E there "
                         << combE << ", E " << rep.convert.error.meanAbs);
            CHECK(painted >= 0.98 * inComb);
            CHECK(combE < 12.0);  // pink on blue would be about 90
            CHECK(rep.convert.error.meanAbs < 3.0);
            writeImage(renderDocument(doc, RenderOptions{}).image,
                       std::string(GRADMESH_TMP) + "/segment_comb_" + std::to_string(splits) + ".png");
        }
    }
}

TEST_CASE("a region with a lobe behind a narrow neck is cut there when that lowers its error",
          "[convert][segment][neck]") {
    // A pink box and a pink disc joined by a 10 px neck, both finely shaded: one map crowds the
    // disc into a sliver of its rectangle (grid lines fan out from the neck), so the mesh of
    // the whole misses the target; cut at the neck, each side maps well (fruits.jpg's orange
    // wedge: E 5.2 as one mesh, 3.45 cut, same budget).
    const int W = 260, H = 200;
    RgbaImage image(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const double px = x + 0.5, py = y + 0.5;
            float* p = image.at(x, y);
            p[0] = 0.15f, p[1] = 0.25f + 0.15f * float(py / H), p[2] = 0.75f, p[3] = 1;
            const bool box = px > 20 && px < 120 && py > 40 && py < 160;
            const bool neck = px >= 120 && px < 150 && std::abs(py - 100) < 5;
            const bool disc = std::hypot(px - 195, py - 100) < 50;
            if (box || neck || disc) {
                p[0] = 0.9f;
                p[1] = 0.5f + 0.25f * float(std::sin(px / 2.5) * std::cos(py / 3.0));
                p[2] = 0.55f + 0.15f * float(std::cos((px + py) / 7.0));
            }
        }
    SegmentConvertOptions o;
    o.convert.maxError = 1.0;
    o.convert.colors = ColorMode::Fit;  // the figures below were measured with Hermite colours
    auto run = [&](int splits, SegmentConvertReport& rep) {
        o.neckSplits = splits;
        return convertSegmented(image, o, "box, neck and disc", &rep);
    };
    SegmentConvertReport whole, cut;
    run(0, whole);
    const Document doc = run(2, cut);
    for (size_t k = 0; k < cut.fallbacks.size(); ++k)
        if (!cut.fallbacks[k].empty())
            WARN("region " << k << " (" << cut.convert.regions[k].pixels << " px): " << cut.fallbacks[k]);
    INFO("E " << whole.convert.error.meanAbs << " as one mesh, " << cut.convert.error.meanAbs
              << " cut; patches " << whole.convert.patches << ", " << cut.convert.patches);
    CHECK(whole.splitRegions == 0);
    CHECK(cut.splitRegions >= 1);
    CHECK(cut.convert.error.uncovered == 0);
    CHECK(cut.convert.error.meanAbs < 0.9 * whole.convert.error.meanAbs);
    writeImage(renderDocument(doc, RenderOptions{}).image,
               std::string(GRADMESH_TMP) + "/segment_neck.png");
}

TEST_CASE("a region's meshes worth their patches: fewer patches or less error than the others",
          "[convert][segment][budget]") {
    // (patches, squared error, job): 80 does not lower the error below 60's; of the two meshes
    // of 10 patches the better is kept; 30 stays (nothing smaller beats it).
    const std::vector<RdPoint> front = paretoFront({{60, 200, 0},
                                                    {10, 1000, 1},
                                                    {30, 700, 2},
                                                    {10, 900, 3},
                                                    {80, 200, 4},
                                                    {120, 150, 5}});
    REQUIRE(front.size() == 4);
    CHECK(front[0].job == 3);
    CHECK(front[1].job == 2);
    CHECK(front[2].job == 0);
    CHECK(front[3].job == 5);
    REQUIRE(paretoFront({{5, 10, 7}}).size() == 1);
}

TEST_CASE("a whole-image budget goes where it lowers the summed error most",
          "[convert][segment][budget]") {
    // Region 0 falls by 100 per patch up to 20 patches, then by 2; region 1 by 10 per patch,
    // then 5.
    const std::vector<std::vector<RdPoint>> fronts = {
        {{10, 5000, 0}, {20, 4000, 1}, {120, 3800, 2}},
        {{10, 5000, 3}, {40, 4700, 4}, {60, 4600, 5}}};
    CHECK(allotPatches(fronts, 20) == std::vector<size_t>{0, 0});   // only the start
    CHECK(allotPatches(fronts, 30) == std::vector<size_t>{1, 0});
    CHECK(allotPatches(fronts, 59) == std::vector<size_t>{1, 0});
    CHECK(allotPatches(fronts, 60) == std::vector<size_t>{1, 1});
    CHECK(allotPatches(fronts, 80) == std::vector<size_t>{1, 2});
    // 160: region 0's last step and region 1's first (8500), not 20 + 60 patches (8600).
    CHECK(allotPatches(fronts, 160) == std::vector<size_t>{2, 1});
    CHECK(allotPatches(fronts, 179) == std::vector<size_t>{2, 1});
    CHECK(allotPatches(fronts, 180) == std::vector<size_t>{2, 2});
    CHECK(allotPatches(fronts, 1000) == std::vector<size_t>{2, 2});
    // The first points alone over the total: they are kept (nothing smaller was measured).
    CHECK(allotPatches(fronts, 5) == std::vector<size_t>{0, 0});

    // Where the steepest step first is not best: region 0's step saves 30 per patch over 10
    // patches, region 1's 28 over 25; with 25 to spare, region 1's alone (700 saved) beats
    // region 0's (300 saved, and then region 1's no longer fits).
    const std::vector<std::vector<RdPoint>> tight = {{{10, 1000, 0}, {20, 700, 1}},
                                                     {{10, 1000, 2}, {35, 300, 3}}};
    CHECK(allotPatches(tight, 45) == std::vector<size_t>{0, 1});
    CHECK(allotPatches(tight, 54) == std::vector<size_t>{0, 1});
    CHECK(allotPatches(tight, 55) == std::vector<size_t>{1, 1});

    // Many regions and a total past kAllotCells: coarser units, the total still holds.
    std::vector<std::vector<RdPoint>> many;
    for (int k = 0; k < 300; ++k)
        many.push_back({{4, 1e6, 0}, {40000, 5e5 + k, 1}, {80000, 1e5, 2}});
    const std::vector<size_t> pick = allotPatches(many, 4'000'000);
    double patches = 0;
    for (size_t k = 0; k < many.size(); ++k) patches += many[k][pick[k]].patches;
    CHECK(patches <= 4'000'000);
    CHECK(patches >= 3'000'000);
}

namespace {
// The scene with a finely striped box: its error falls with every patch, the smooth regions'
// hardly at all.
RgbaImage stripedScene() {
    RgbaImage image = scene();
    for (int y = 41; y < 170; ++y)
        for (int x = 166; x < 225; ++x) {
            float* p = image.at(x, y);
            p[1] = 0.45f + 0.25f * float(std::sin(x / 5.0) * std::sin(y / 6.0));
        }
    return image;
}

// What --total-patches minimises: the regions' squared errors summed over their covered pixels,
// and their meshes' spill over the regions drawn before them.
double summedRegionError(const SegmentConvertReport& rep) {
    double sse = 0;
    for (const RegionReport& r : rep.convert.regions)
        sse += r.error.rmse * r.error.rmse * double(r.error.pixels) * (1 - r.error.uncovered);
    for (double spill : rep.keptSpill) sse += spill;
    return sse;
}
}  // namespace

TEST_CASE("with a whole-image patch budget the busy region gets the patches and the total holds",
          "[convert][segment][budget]") {
    const RgbaImage image = stripedScene();
    SegmentConvertOptions o;
    o.convert.maxError = 0.5;
    o.totalPatches = 160;
    SegmentConvertReport rep;
    const Document doc = convertSegmented(image, o, "striped scene", &rep);
    REQUIRE(rep.failedRegions == 0);
    REQUIRE(rep.keptBudget.size() == rep.convert.regions.size());
    CHECK(rep.conversions > static_cast<int>(rep.convert.regions.size()));
    int regionPatches = 0, most = 0;
    double calmest = 1e9;  // patches per 1000 pixels
    size_t busiest = 0;
    for (size_t k = 0; k < rep.convert.regions.size(); ++k) {
        const RegionReport& r = rep.convert.regions[k];
        regionPatches += r.patches;
        UNSCOPED_INFO("region " << k << ": " << r.pixels << " px, " << r.patches << " patches, E "
                                << r.error.meanAbs << ", budget " << rep.keptBudget[k]);
        if (r.patches > most) most = r.patches, busiest = k;
        calmest = std::min(calmest, 1000.0 * r.patches / r.pixels);
    }
    WARN("striped scene, 160 patches for the whole image: regions got "
         << regionPatches << ", E " << rep.convert.error.meanAbs << ", " << rep.conversions
         << " conversions");
    CHECK(regionPatches <= o.totalPatches);
    CHECK(rep.convert.error.uncovered == 0);
    // The striped box (the region whose pixels lie in it) has the most patches, and more than
    // 4x the patches per pixel of the calmest region.
    const RegionReport& box = rep.convert.regions[busiest];
    CHECK(box.pixels > 5000);
    CHECK(box.pixels < 9000);
    CHECK(1000.0 * box.patches / box.pixels > 4 * calmest);
    // Every region drawn, as a mesh or (the ladder's first rung) a flat shape, over the base.
    CHECK(doc.meshes.size() + doc.shapes.size() >= rep.convert.regions.size() + 1);
}

TEST_CASE("a larger whole-image patch budget never raises the regions' summed error and spill",
          "[convert][segment][budget]") {
    const RgbaImage image = stripedScene();
    double last = std::numeric_limits<double>::infinity();
    int lastPatches = 0;
    for (const int total : {60, 90, 120, 160}) {
        SegmentConvertOptions o;
        o.convert.maxError = 0.5;
        o.totalPatches = total;
        SegmentConvertReport rep;
        convertSegmented(image, o, "striped scene", &rep);
        REQUIRE(rep.failedRegions == 0);
        const double sse = summedRegionError(rep);
        int patches = 0;
        for (const RegionReport& r : rep.convert.regions) patches += r.patches;
        INFO("total " << total << ": " << patches << " patches, summed squared error " << sse
                      << " (before: " << lastPatches << ", " << last << ")");
        CHECK(patches <= total);
        CHECK(sse <= last);
        last = sse;
        lastPatches = patches;
    }
}

TEST_CASE("a larger whole-image patch budget does not make the image worse where meshes overlap",
          "[convert][segment][budget]") {
    // HappyFish.jpg: at 80 patches in all, the white background's 22-patch mesh was best on its
    // own pixels but its outline strayed over the fish, 0.6 dB worse over the image than at 70,
    // until the allotment counted what a mesh paints over the regions beneath it.
    const RgbaImage image = readImage(std::string(GRADMESH_SAMPLES) + "/HappyFish.jpg");
    double last = 0;
    for (const int total : {50, 60, 70, 80}) {
        SegmentConvertOptions o;
        o.convert.maxError = 2;
        o.convert.colors = ColorMode::Fit;  // the 20.5 dB below is Hermite colours'
        o.totalPatches = total;
        SegmentConvertReport rep;
        convertSegmented(image, o, "HappyFish.jpg", &rep);
        REQUIRE(rep.keptSpill.size() == rep.convert.regions.size());
        double spill = 0;
        for (double s : rep.keptSpill) spill += s;
        UNSCOPED_INFO("total " << total << ": PSNR " << rep.convert.error.psnr << " dB, spill "
                               << spill);
        CHECK(rep.convert.error.psnr > last - 0.05);
        last = rep.convert.error.psnr;
    }
    CHECK(last > 20.5);
}

TEST_CASE("a photograph is segmented finer where the budget allows; drawings are not",
          "[convert][segment][finer]") {
    // A mesh refines whole rows and columns of its grid: in smarties.png's few large regions
    // the patches that draw one sweet run across the table. Segmented again towards
    // shadedSegments regions, the same total budget draws the photograph better.
    const RgbaImage photo = readImage(std::string(GRADMESH_SAMPLES) + "/smarties.png");
    SegmentConvertOptions o;
    o.totalPatches = 1000;
    SegmentConvertReport finer, coarse;
    convertSegmented(photo, o, "smarties.png", &finer);
    o.shadedSegments = 0;
    convertSegmented(photo, o, "smarties.png", &coarse);
    CHECK(finer.finerSegments == 100);
    CHECK(coarse.finerSegments == 0);
    CHECK(finer.convert.regions.size() > 2 * coarse.convert.regions.size());
    CHECK(finer.convert.patches <= 1000 + int(finer.convert.regions.size()));
    UNSCOPED_INFO("PSNR finer " << finer.convert.error.psnr << " dB, coarse "
                                << coarse.convert.error.psnr << " dB");
    CHECK(finer.convert.error.psnr > coarse.convert.error.psnr + 0.3);

    // Under a budget of fewer than finerPatchesPerSegment patches per region it is not.
    o = SegmentConvertOptions{};
    o.totalPatches = 500;
    SegmentConvertReport small;
    convertSegmented(photo, o, "smarties.png", &small);
    CHECK(small.finerSegments == 0);

    // A drawing of flat colours, and a cartoon drawn between ink lines, keep their regions.
    for (const char* name : {"opencv-logo.png", "HappyFish.jpg"}) {
        INFO(name);
        SegmentConvertReport drawing;
        convertSegmented(readImage(std::string(GRADMESH_SAMPLES) + "/" + name),
                         SegmentConvertOptions{}, name, &drawing);
        CHECK(drawing.finerSegments == 0);
    }
}

TEST_CASE("under a small whole-image budget, the regions a mesh helps least are drawn flat",
          "[convert][segment][budget]") {
    // smarties.png at 100 patches: each of its sweets' meshes starts at 4 patches, so the
    // ladders' first rungs alone used to exceed the total (263 patches). Drawn flat, the
    // sweets that gain least from a mesh leave the patches to the others: the total holds, at
    // about the PSNR of the 263 patches and well under half their bytes.
    const RgbaImage photo = readImage(std::string(GRADMESH_SAMPLES) + "/smarties.png");
    SegmentConvertOptions o;
    o.convert.maxError = 2;
    o.totalPatches = 100;
    o.residue = false;  // the flat shapes on top would blur what the rungs alone do
    SegmentConvertReport rungs, meshesOnly;
    const Document withRungs = convertSegmented(photo, o, "smarties.png", &rungs);
    o.flatRungs = false;
    const Document without = convertSegmented(photo, o, "smarties.png", &meshesOnly);
    WriteOptions write;
    write.svgScript = "none";
    const size_t bytes = encodeSvg(withRungs, write).size();
    const size_t bytesWithout = encodeSvg(without, write).size();
    WARN("smarties at 100 patches: " << rungs.convert.patches << " patches, "
         << rungs.flatRegions << " flat, " << bytes << " B, PSNR " << rungs.convert.error.psnr
         << " dB; meshes only " << meshesOnly.convert.patches << " patches, " << bytesWithout
         << " B, " << meshesOnly.convert.error.psnr << " dB");
    CHECK(meshesOnly.flatRegions == 0);
    CHECK(meshesOnly.convert.patches - meshesOnly.basePatches > 200);
    CHECK(rungs.flatRegions > 0);
    CHECK(rungs.convert.patches - rungs.basePatches <= 100);
    CHECK(rungs.convert.error.psnr > meshesOnly.convert.error.psnr - 0.3);
    CHECK(bytes * 2 < bytesWithout);
}

TEST_CASE("with no patches at all, every region is a flat shape and the file holds no mesh",
          "[convert][segment][budget]") {
    // --total-patches 0, the low end of the curve: smarties.png posterized into its regions'
    // colours, a few kilobytes of paths (the 100-patch file is eight times larger).
    const RgbaImage photo = readImage(std::string(GRADMESH_SAMPLES) + "/smarties.png");
    SegmentConvertOptions o;
    o.flatOnly = true;
    SegmentConvertReport report;
    const Document doc = convertSegmented(photo, o, "smarties.png", &report);
    const size_t bytes = encodeSvg(doc, WriteOptions{}).size();
    WARN("smarties flat: " << report.flatRegions << " regions, " << bytes << " B, PSNR "
         << report.convert.error.psnr << " dB");
    CHECK(doc.meshes.empty());
    CHECK(report.flatBackdrop);
    CHECK(report.flatRegions == static_cast<int>(doc.shapes.size()));
    CHECK(report.convert.error.psnr > 24.5);
    CHECK(bytes < 8000);
}
