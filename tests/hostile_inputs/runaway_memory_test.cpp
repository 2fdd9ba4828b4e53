// Work bounded on large images: GrabCut on a downscaled copy.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <string>

#include "converters/foreground.h"
#include "meshcore/image.h"
#include "support/cli_run.h"

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("GrabCut on a large image works on a downscaled copy and refines the outline",
          "[hostile][memory][grabcut]") {
    // A 2048² disc over a differently coloured background, both noisy: 4 M pixels, 16 times
    // what GrabCut works on (kGrabCutWorkPixels); the outline comes from the band refinement.
    const int n = 2048;
    const double cx = 1000.3, cy = 1050.7, radius = 700.2;
    gm::RgbaImage image(n, n);
    uint32_t noise = 1;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const bool in = std::hypot(x + 0.5 - cx, y + 0.5 - cy) < radius;
            float* p = &image.pixels[(static_cast<size_t>(y) * n + x) * 4];
            noise = noise * 1664525u + 1013904223u;
            const float jitter = ((noise >> 24) / 255.f - 0.5f) * 0.15f;
            p[0] = (in ? 0.85f : 0.25f) + jitter;
            p[1] = (in ? 0.35f : 0.55f) + jitter;
            p[2] = (in ? 0.15f : 0.30f) + jitter;
            p[3] = 1;
        }
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<uint8_t> mask = gm::grabCutForeground(image);
    const double seconds = secondsSince(t0);
    // Wrong pixels lie on the outline only: within 2 px of the circle.
    long wrong = 0, farWrong = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy) - radius;
            if ((d < 0) != (mask[static_cast<size_t>(y) * n + x] == 1)) {
                ++wrong;
                farWrong += std::fabs(d) > 2;
            }
        }
    INFO(seconds << " s, " << wrong << " wrong pixels, " << farWrong << " beyond 2 px");
    CHECK(farWrong == 0);
    CHECK(wrong < 2 * 3.1416 * radius);  // about a pixel's width along the outline at most
    CHECK(seconds < 20);
}
