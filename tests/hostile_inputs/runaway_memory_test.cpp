// Work bounded by the image's real content and by a memory budget checked before the large
// allocations: a JPEG header claiming 8000x8000, GrabCut on a large image.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <string>

#include "converters/foreground.h"
#include "hostile_files.h"
#include "meshcore/image.h"
#include "support/cli_run.h"

namespace {

// The JPEG's SOF0 marker says the image is w×h (its scan data stays that of the small one).
std::string claimSize(std::string jpeg, int w, int h) {
    const size_t sof = jpeg.find("\xFF\xC0");
    REQUIRE(sof != std::string::npos);
    jpeg[sof + 5] = static_cast<char>(h >> 8);
    jpeg[sof + 6] = static_cast<char>(h & 255);
    jpeg[sof + 7] = static_cast<char>(w >> 8);
    jpeg[sof + 8] = static_cast<char>(w & 255);
    return jpeg;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

TEST_CASE("a small JPEG claiming 8000x8000 is refused by the memory budget before decoding",
          "[hostile][memory][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "jpeg_claims_8000");
    const auto small = dir / "small.jpg";
    hostile::writeNoiseImage(small.string(), 64, 64);
    const auto big = dir / "big.jpg";
    hostile::writeBytes(big, claimSize(gmtest::slurp(small), 8000, 8000));
    REQUIRE(std::filesystem::file_size(big) < 8000);
    const auto t0 = std::chrono::steady_clock::now();
    const gmtest::Run r =
        gmtest::runGradmesh("convert " + gmtest::q(big) + " -o " + gmtest::q(dir / "out.gmb"), dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("8000x8000 image is too large for the memory budget") != std::string::npos);
    CHECK(r.err.find("raise with --max-memory") != std::string::npos);
    CHECK(secondsSince(t0) < 10);
    CHECK(!std::filesystem::exists(dir / "out.gmb"));
}

TEST_CASE("the conversion is checked against the memory budget of --max-memory", "[hostile][memory][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "max_memory");
    const std::string in = gmtest::quote(std::string(GRADMESH_SAMPLES) + "/fruits.jpg");
    const auto out = dir / "out.gmb";
    gmtest::Run r = gmtest::runGradmesh("convert " + in + " --max-memory 10M -o " + gmtest::q(out), dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("512x480 image is too large for the memory budget (needs ~") != std::string::npos);
    CHECK(r.err.find("limit 10.0 MiB; raise with --max-memory)") != std::string::npos);
    r = gmtest::runGradmesh("convert " + in + " --max-memory 12X -o " + gmtest::q(out), dir);
    CHECK(r.code == 2);  // a usage error
    CHECK(r.err.find("--max-memory expects a size") != std::string::npos);
}

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
