// Where the object comes from (foreground.h): a mask image, the alpha channel, or GrabCut.
#include <catch2/catch.hpp>

#include <cmath>

#include "converters/foreground.h"
#include "meshcore/error.h"

using namespace gm;

namespace {

// A w×h image of a disc (centre cx, cy, radius r) in warm shades on a cool background that
// varies by `ramp` across the image; `alphaOutside` < 1 makes the background transparent.
RgbaImage discImage(int w, int h, double cx, double cy, double r, float alphaOutside = 1,
                    float ramp = 0.1f) {
    RgbaImage im(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = im.at(x, y);
            const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
            const bool in = dx * dx + dy * dy < r * r;
            const float u = static_cast<float>(x) / w, v = static_cast<float>(y) / h;
            p[0] = in ? 0.9f - 0.2f * v : 0.15f + ramp * u;
            p[1] = in ? 0.5f + 0.2f * u : 0.3f + ramp * v;
            p[2] = in ? 0.1f : 0.6f;
            p[3] = in ? 1.f : alphaOutside;
        }
    return im;
}

// Pixels where the mask and the true disc disagree.
long mismatch(const ObjectMask& m, double cx, double cy, double r) {
    long n = 0;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x) {
            const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
            const bool in = dx * dx + dy * dy < r * r;
            n += (m.mask[static_cast<size_t>(y) * m.width + x] != 0) != in;
        }
    return n;
}

}  // namespace

TEST_CASE("a transparent background makes the alpha channel the mask", "[foreground]") {
    const RgbaImage im = discImage(120, 100, 60, 50, 30, 0.f);
    const ObjectMask m = objectMask(im, nullptr, "disc.png", "");
    CHECK(m.source == MaskSource::Alpha);
    CHECK(mismatch(m, 60, 50, 30) == 0);
}

TEST_CASE("a mask image is the mask; a mask of another size or an empty one is an error",
          "[foreground]") {
    const RgbaImage im = discImage(120, 100, 60, 50, 30);
    RgbaImage mask(120, 100);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 120; ++x) {
            float* p = mask.at(x, y);
            const float white = x < 40 ? 1.f : 0.f;
            p[0] = p[1] = p[2] = white;
            p[3] = 1;
        }
    const ObjectMask m = objectMask(im, &mask, "disc.png", "left.png");
    CHECK(m.source == MaskSource::MaskImage);
    long object = 0;
    for (uint8_t v : m.mask) object += v;
    CHECK(object == 40 * 100);

    const RgbaImage small(60, 50);
    CHECK_THROWS_WITH(objectMask(im, &small, "disc.png", "small.png"), Catch::Contains("small.png"));
    RgbaImage black(120, 100);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 120; ++x) black.at(x, y)[3] = 1;
    CHECK_THROWS_WITH(objectMask(im, &black, "disc.png", "black.png"), Catch::Contains("black.png"));
}

TEST_CASE("an opaque image gets GrabCut's foreground: the disc, to a pixel or so along its rim",
          "[foreground]") {
    const double cx = 100, cy = 90, r = 55;
    const RgbaImage im = discImage(200, 180, cx, cy, r);
    const ObjectMask m = objectMask(im, nullptr, "disc.png", "");
    CHECK(m.source == MaskSource::GrabCut);
    const double rim = 2 * 3.14159265 * r;
    INFO("pixels off the disc: " << mismatch(m, cx, cy, r));
    CHECK(mismatch(m, cx, cy, r) <= rim);
}

TEST_CASE("a large opaque image is cut on a downscaled copy and its outline refined at full size",
          "[foreground]") {
    // 1024² is four times GrabCut's working size: without the band refinement the outline
    // would be a staircase of 2-pixel steps. (A flat background: on this geometry with the
    // ramp, GrabCut itself takes a block of background for object at any size.)
    const double cx = 500, cy = 530, r = 300;
    const RgbaImage im = discImage(1024, 1024, cx, cy, r, 1.f, 0.f);
    REQUIRE(1024.0 * 1024.0 > kGrabCutWorkPixels);
    const ObjectMask m = objectMask(im, nullptr, "large.png", "", 2);
    CHECK(m.source == MaskSource::GrabCut);
    const double rim = 2 * 3.14159265 * r;
    INFO("pixels off the disc: " << mismatch(m, cx, cy, r));
    CHECK(mismatch(m, cx, cy, r) <= 0.5 * rim);
}
