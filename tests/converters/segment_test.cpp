#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "converters/segment.h"
#include "formats/raster.h"
#include "label_checks.h"
#include "meshcore/error.h"

using namespace gm;
using gm::test::defaultMinRegion;
using gm::test::labelMapProblem;
using gm::test::paint;
using gm::test::twoRegionMismatch;

namespace {

const char* const kSamples[] = {"fruits.jpg", "HappyFish.jpg", "astronaut.png", "chelsea.png",
                                "apple.jpg",  "horse.png",     "pic1.png",      "plant.jpg"};

RgbaImage sample(const std::string& name) {
    return readImage(std::string(GRADMESH_SAMPLES) + "/" + name);
}

void printStats(const std::string& what, const Segmentation& s) {
    const SegmentStats& t = s.stats;
    std::printf(
        "segment %-22s %4dx%-4d %6.3f s (FH %.3f s x%d k=%.0f on %dx%d, GrabCut %.3f s on %d "
        "segments/%ld px, grow %.3f s, merge %.3f s)  FH %d regions, %d cleaned -> %d  (GrabCut "
        "changed %ld, "
        "grown %ld, %d components, merged %ld)\n",
        what.c_str(), s.width, s.height, t.seconds, t.fhSeconds, t.fhTrials, t.threshold,
        t.workWidth, t.workHeight, t.grabCutSeconds, t.grabCutSegments, t.grabCutPixels,
        t.growSeconds, t.mergeSeconds, t.fhRegions, t.fhCleanRegions, t.regions, t.grabCutChanged, t.grown,
        t.components, t.merged);
}

}  // namespace

TEST_CASE("two flat colours split by a straight line give the two halves", "[segment]") {
    const int w = 240, h = 180;
    auto below = [](double x, double y) { return y > 0.4 * x + 50; };
    const auto image = paint(w, h, [&](double x, double y, float* p) {
        const bool b = below(x, y);
        p[0] = b ? 0.85f : 0.15f;
        p[1] = b ? 0.55f : 0.35f;
        p[2] = b ? 0.20f : 0.70f;
    });
    for (bool grabCut : {true, false}) {
        SegmentOptions o;
        o.grabCut = grabCut;
        const auto s = segmentImage(image, o);
        printStats(grabCut ? "line" : "line (no GrabCut)", s);
        CHECK(labelMapProblem(s, defaultMinRegion(w, h), 64) == "");
        REQUIRE(s.count == 2);
        std::printf("  %ld pixels off the true halves\n", twoRegionMismatch(s, below));
        // A few pixels along the 260-pixel boundary at most.
        CHECK(twoRegionMismatch(s, below) <= 2 * 260);
        if (grabCut) CHECK(twoRegionMismatch(s, below) <= 60);
    }
}

TEST_CASE("a smooth gradient disc on a flat background gives two regions", "[segment]") {
    const int w = 256, h = 256;
    const double cx = 120, cy = 136, r = 80;
    auto inDisc = [&](double x, double y) {
        return (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
    };
    const auto image = paint(w, h, [&](double x, double y, float* p) {
        if (inDisc(x, y)) {
            // Orange to yellow left to right, darker towards the bottom.
            const double u = (x - (cx - r)) / (2 * r), v = (y - (cy - r)) / (2 * r);
            p[0] = static_cast<float>(0.95 - 0.25 * v);
            p[1] = static_cast<float>(0.35 + 0.5 * u - 0.2 * v);
            p[2] = static_cast<float>(0.1 + 0.1 * u);
        } else {
            p[0] = 0.25f;
            p[1] = 0.4f;
            p[2] = 0.55f;
        }
    });
    const auto s = segmentImage(image);
    printStats("gradient disc", s);
    CHECK(labelMapProblem(s, defaultMinRegion(w, h), 64) == "");
    REQUIRE(s.count == 2);
    std::printf("  %ld pixels off the true disc\n", twoRegionMismatch(s, inDisc));
    // The disc's circumference is ~500 pixels.
    CHECK(twoRegionMismatch(s, inDisc) <= 250);
}

TEST_CASE("every sample image gets a valid label map", "[segment][samples]") {
    for (const char* name : kSamples) {
        SECTION(name) {
            const auto image = sample(name);
            const auto s = segmentImage(image);
            printStats(name, s);
            CHECK(labelMapProblem(s, defaultMinRegion(image.width, image.height), 64) == "");
            CHECK(s.count >= 2);
            CHECK(s.count <= 60);
        }
    }
}

TEST_CASE("a given minRegion is honoured on a sample", "[segment][samples]") {
    const auto image = sample("chelsea.png");
    SegmentOptions o;
    o.minRegion = 2000;
    o.segments = 40;
    const auto s = segmentImage(image, o);
    printStats("chelsea minRegion 2000", s);
    CHECK(labelMapProblem(s, 2000) == "");
}

TEST_CASE("a large image is refined at GrabCut's resolution cap", "[segment][samples]") {
    const auto image = sample("chelsea.png");
    SegmentOptions o;
    o.grabCutPixels = 40000;
    const auto s = segmentImage(image, o);
    printStats("chelsea, GrabCut at 40k px", s);
    CHECK(s.stats.grabCutWidth * s.stats.grabCutHeight <= 40000);
    CHECK(s.stats.grabCutWidth < image.width);
    CHECK(s.stats.grabCutSegments > 0);
    CHECK(labelMapProblem(s, defaultMinRegion(image.width, image.height), 64) == "");
}

TEST_CASE("GrabCut refinement gives the same labels on one thread and on several",
          "[segment][samples]") {
    const auto image = sample("fruits.jpg");
    SegmentOptions one, many;
    one.threads = 1;
    many.threads = 3;  // more threads than cores: batches and merge order still fixed
    const auto a = segmentImage(image, one), b = segmentImage(image, many);
    CHECK(a.stats.grabCutSegments > 1);
    CHECK(a.stats.grabCutSegments == b.stats.grabCutSegments);
    CHECK(a.stats.grabCutChanged == b.stats.grabCutChanged);
    CHECK(a.count == b.count);
    CHECK(a.labels == b.labels);
}

TEST_CASE("more segments asked for give more regions", "[segment][samples]") {
    const auto image = sample("fruits.jpg");
    SegmentOptions few, many;
    few.segments = 4;
    many.segments = 40;
    const auto a = segmentImage(image, few), b = segmentImage(image, many);
    printStats("fruits segments=4", a);
    printStats("fruits segments=40", b);
    CHECK(labelMapProblem(a, defaultMinRegion(image.width, image.height), 64) == "");
    CHECK(labelMapProblem(b, defaultMinRegion(image.width, image.height), 64) == "");
    CHECK(a.count < b.count);
    CHECK(a.count <= 10);
    CHECK(b.count >= 20);
}

TEST_CASE("a given threshold is used as k in one FH run", "[segment]") {
    const auto image = sample("HappyFish.jpg");
    SegmentOptions lowK, highK;
    lowK.threshold = 100;
    highK.threshold = 3000;
    const auto a = segmentImage(image, lowK), b = segmentImage(image, highK);
    CHECK(a.stats.fhTrials == 1);
    CHECK(a.stats.threshold == 100);
    CHECK(labelMapProblem(a, defaultMinRegion(image.width, image.height), 64) == "");
    CHECK(labelMapProblem(b, defaultMinRegion(image.width, image.height), 64) == "");
    CHECK(a.count > b.count);
}

TEST_CASE("regions split along weak borders are joined again", "[segment]") {
    // A gentle ramp that a tiny k cuts into bands; no band border is a real edge.
    const int w = 240, h = 100;
    const auto image = paint(w, h, [&](double x, double, float* p) {
        p[0] = static_cast<float>(0.1 + 0.8 * x / w);
        p[1] = 0.5f;
        p[2] = static_cast<float>(0.9 - 0.6 * x / w);
    });
    SegmentOptions o;
    o.threshold = 1;
    o.fhMinSize = 200;
    o.weakEdge = 0;
    const auto split = segmentImage(image, o);
    o.weakEdge = 12;
    const auto joined = segmentImage(image, o);
    printStats("ramp, weakEdge 0", split);
    printStats("ramp, weakEdge 12", joined);
    CHECK(labelMapProblem(split, defaultMinRegion(w, h), 64) == "");
    CHECK(labelMapProblem(joined, defaultMinRegion(w, h), 64) == "");
    CHECK(split.count > 3);
    CHECK(joined.count == 1);
}

TEST_CASE("a 1x1 image is one region and an empty image is an error", "[segment]") {
    const auto one = paint(1, 1, [](double, double, float* p) { p[0] = p[1] = p[2] = 0.5f; });
    const auto s = segmentImage(one);
    CHECK(s.count == 1);
    REQUIRE(s.labels.size() == 1);
    CHECK(s.labels[0] == 0);
    CHECK_THROWS_AS(segmentImage(RgbaImage()), Error);
    CHECK_THROWS_AS(segmentImage(RgbaImage(0, 5)), Error);
}

TEST_CASE("thin and tiny images are handled", "[segment]") {
    for (auto [w, h] : {std::pair{1, 50}, std::pair{50, 1}, std::pair{2, 2}, std::pair{7, 9},
                        std::pair{300, 3}}) {
        const auto image = paint(w, h, [](double x, double y, float* p) {
            p[0] = x < 3 ? 0.9f : 0.1f;
            p[1] = y < 4 ? 0.2f : 0.7f;
            p[2] = 0.5f;
        });
        const auto s = segmentImage(image);
        INFO(w << "x" << h);
        CHECK(labelMapProblem(s, defaultMinRegion(w, h), 64) == "");
    }
}

TEST_CASE("a noise image ends in regions of at least minRegion pixels", "[segment]") {
    const int w = 200, h = 160;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0, 1);
    RgbaImage image(w, h);
    for (size_t k = 0; k < image.pixels.size(); k += 4) {
        image.pixels[k] = u(rng);
        image.pixels[k + 1] = u(rng);
        image.pixels[k + 2] = u(rng);
        image.pixels[k + 3] = 1;
    }
    for (int minRegion : {1, 50, 500}) {
        for (bool raw : {false, true}) {
            SegmentOptions o;
            o.minRegion = minRegion;
            if (raw) {  // FH leaves thousands of pixel-sized regions for the last merge
                o.threshold = 5;
                o.fhMinSize = 1;
                o.sliverWidth = 0;
            }
            const auto s = segmentImage(image, o);
            INFO("minRegion " << minRegion << (raw ? ", raw FH" : ""));
            printStats("noise", s);
            CHECK(labelMapProblem(s, minRegion) == "");
            if (raw && minRegion > 1) CHECK(s.stats.merged > 1000);
        }
    }
}

TEST_CASE("random blocky images under random options keep the contract", "[segment]") {
    std::mt19937 rng(11);
    for (int round = 0; round < 12; ++round) {
        const int w = 20 + static_cast<int>(rng() % 120), h = 20 + static_cast<int>(rng() % 100);
        // Random rectangles of random colours, plus a little noise.
        RgbaImage image(w, h);
        for (int r = 0; r < 12; ++r) {
            const int x0 = static_cast<int>(rng() % w), y0 = static_cast<int>(rng() % h);
            const int x1 = std::min(w, x0 + 1 + static_cast<int>(rng() % w));
            const int y1 = std::min(h, y0 + 1 + static_cast<int>(rng() % h));
            const float c[3] = {(rng() % 256) / 255.f, (rng() % 256) / 255.f, (rng() % 256) / 255.f};
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    for (int k = 0; k < 3; ++k) image.at(x, y)[k] = c[k];
        }
        for (size_t k = 0; k < image.pixels.size(); ++k)
            image.pixels[k] = k % 4 == 3 ? 1.f
                                         : std::clamp(image.pixels[k] + ((rng() % 21) - 10.f) / 255.f,
                                                      0.f, 1.f);
        SegmentOptions o;
        o.minRegion = 1 + static_cast<int>(rng() % 80);
        o.segments = static_cast<int>(rng() % 30);
        o.grabCut = rng() % 4 != 0;
        o.sliverWidth = static_cast<int>(rng() % 6);
        if (rng() % 3 == 0) o.fhMinSize = 1 + static_cast<int>(rng() % 20);
        if (rng() % 3 == 0) o.threshold = 5 + rng() % 2000;
        if (rng() % 2 == 0) o.workPixels = 500 + static_cast<int>(rng() % 5000);
        if (rng() % 2 == 0) o.grabCutPixels = 300 + static_cast<int>(rng() % 5000);
        const auto s = segmentImage(image, o);
        INFO("round " << round << ": " << w << "x" << h << " minRegion " << o.minRegion
                      << " segments " << o.segments << " grabCut " << o.grabCut << " sliver "
                      << o.sliverWidth << " fhMinSize " << o.fhMinSize << " k " << o.threshold
                      << " workPixels " << o.workPixels << " grabCutPixels "
                      << o.grabCutPixels);
        CHECK(labelMapProblem(s, o.minRegion) == "");
    }
}

TEST_CASE("segmentation is reproducible", "[segment][samples]") {
    const auto image = sample("fruits.jpg");
    const auto a = segmentImage(image), b = segmentImage(image);
    CHECK(a.count == b.count);
    CHECK(a.labels == b.labels);
}

TEST_CASE("transparent pixels count as black", "[segment]") {
    const int w = 120, h = 100;
    auto inBox = [](double x, double y) { return x > 30 && x < 90 && y > 20 && y < 80; };
    auto image = paint(w, h, [&](double x, double y, float* p) {
        // Outside the box: random colours, but fully transparent.
        const unsigned hsh = static_cast<unsigned>(x * 7919 + y * 104729) * 2654435761u;
        p[0] = (hsh & 255) / 255.f;
        p[1] = ((hsh >> 8) & 255) / 255.f;
        p[2] = ((hsh >> 16) & 255) / 255.f;
        if (inBox(x, y)) p[0] = p[1] = p[2] = 0.8f;
    });
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) image.at(x, y)[3] = inBox(x + .5, y + .5) ? 1.f : 0.f;
    const auto s = segmentImage(image);
    CHECK(labelMapProblem(s, defaultMinRegion(w, h), 64) == "");
    REQUIRE(s.count == 2);
    CHECK(twoRegionMismatch(s, inBox) <= 20);
}

// Writes each sample's label map to /tmp/seg/: <name>.labels.png in arbitrary colours and
// <name>.mean.png in each region's mean colour with its boundary drawn black.
TEST_CASE("dump sample label maps", "[.][dump]") {
    namespace fs = std::filesystem;
    fs::create_directories("/tmp/seg");
    for (const char* name : kSamples) {
        const auto image = sample(name);
        const auto s = segmentImage(image);
        printStats(name, s);
        const int W = s.width, H = s.height;
        std::vector<double> sum(static_cast<size_t>(s.count) * 3, 0);
        std::vector<long> n(s.count, 0);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int l = s.labels[static_cast<size_t>(y) * W + x];
                ++n[l];
                for (int c = 0; c < 3; ++c) sum[l * 3 + c] += image.at(x, y)[c];
            }
        RgbaImage labels(W, H), mean(W, H);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const int l = s.labels[static_cast<size_t>(y) * W + x];
                const unsigned hsh = (static_cast<unsigned>(l) + 1) * 2654435761u;
                float* a = labels.at(x, y);
                a[0] = 0.2f + 0.8f * ((hsh >> 8) & 255) / 255.f;
                a[1] = 0.2f + 0.8f * ((hsh >> 16) & 255) / 255.f;
                a[2] = 0.2f + 0.8f * ((hsh >> 24) & 255) / 255.f;
                a[3] = 1;
                const bool edge = (x + 1 < W && s.labels[static_cast<size_t>(y) * W + x + 1] != l) ||
                                  (y + 1 < H && s.labels[static_cast<size_t>(y + 1) * W + x] != l);
                float* m = mean.at(x, y);
                for (int c = 0; c < 3; ++c)
                    m[c] = edge ? 0.f : static_cast<float>(sum[l * 3 + c] / n[l]);
                m[3] = 1;
            }
        const std::string stem = fs::path(name).stem().string();
        writeImage(labels, "/tmp/seg/" + stem + ".labels.png");
        writeImage(mean, "/tmp/seg/" + stem + ".mean.png");
    }
}

TEST_CASE("regions found on a downscaled copy keep full-size borders", "[segment]") {
    // 1536² is over GrabCut's 512² cap: GrabCut works at a third of the size, and the
    // upscaled border is a staircase of 3-pixel steps unless refined at full size.
    const int w = 1536, h = 1536;
    const double cx = 720, cy = 816, r = 480;
    auto inDisc = [&](double x, double y) {
        return (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r;
    };
    const auto image = paint(w, h, [&](double x, double y, float* p) {
        const double u = x / w, v = y / h;
        if (inDisc(x, y)) {
            p[0] = static_cast<float>(0.95 - 0.25 * v);
            p[1] = static_cast<float>(0.35 + 0.5 * u - 0.2 * v);
            p[2] = static_cast<float>(0.1 + 0.1 * u);
        } else {
            p[0] = static_cast<float>(0.2 + 0.1 * u);
            p[1] = 0.4f;
            p[2] = static_cast<float>(0.5 + 0.1 * v);
        }
    });
    long mismatch[2] = {0, 0};
    for (const bool refine : {false, true}) {
        SegmentOptions o;
        o.refineBorders = refine;
        const auto s = segmentImage(image, o);
        printStats(refine ? "large disc, borders refined" : "large disc, upscaled", s);
        CHECK(s.stats.grabCutWidth < w);
        CHECK(labelMapProblem(s, defaultMinRegion(w, h), 64) == "");
        REQUIRE(s.count == 2);
        mismatch[refine] = twoRegionMismatch(s, inDisc);
        std::printf("  %ld pixels off the true disc (%ld refined)\n", mismatch[refine],
                    s.stats.borderRefined);
        if (refine) CHECK(s.stats.borderRefined > 0);
    }
    // The circumference is ~3000 pixels: refined, well under one pixel off per border pixel,
    // and far better than the staircase.
    CHECK(mismatch[1] <= 600);
    CHECK(mismatch[1] * 3 <= mismatch[0]);
}
