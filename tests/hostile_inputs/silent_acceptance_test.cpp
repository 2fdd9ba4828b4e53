// Inputs that used to convert without a word: a truncated JPEG, a GIF named .png, the extra
// pages of a TIFF.
#include <catch2/catch.hpp>

#include <string>

#include "formats/raster.h"
#include "hostile_files.h"
#include "meshcore/error.h"
#include "support/cli_run.h"

TEST_CASE("a truncated JPEG is an error, not a grey-padded image", "[hostile][raster]") {
    const auto dir = gmtest::scratchDir("hostile_", "truncated_jpeg");
    const auto whole = dir / "whole.jpg";
    hostile::writeNoiseImage(whole.string(), 256, 256);
    const std::string bytes = gmtest::slurp(whole);
    CHECK_NOTHROW(gm::readImage(whole.string()));
    for (const int percent : {25, 50, 75, 99}) {
        const auto cut = dir / ("cut" + std::to_string(percent) + ".jpg");
        hostile::writeBytes(cut, bytes.substr(0, bytes.size() * percent / 100));
        INFO(percent << "%");
        CHECK_THROWS_AS(gm::readImage(cut.string()), gm::Error);
    }
    const gmtest::Run r = gmtest::runGradmesh(
        "convert " + gmtest::q(dir / "cut50.jpg") + " -o " + gmtest::q(dir / "out.gmb"), dir);
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(r.err.find("cannot decode image") != std::string::npos);
    CHECK(!std::filesystem::exists(dir / "out.gmb"));
}

TEST_CASE("an image is read by its content: a GIF named .png is refused as a GIF",
          "[hostile][raster]") {
    const auto dir = gmtest::scratchDir("hostile_", "renamed_gif");
    const auto gif = dir / "picture.gif";
    hostile::writeNoiseImage(gif.string(), 32, 32);
    const auto png = dir / "picture.png";
    std::filesystem::rename(gif, png);
    CHECK_THROWS_WITH(gm::readImage(png.string()), Catch::Contains("holds a GIF image"));
    // A PNG named .jpg is read: the content decides.
    const auto misnamed = dir / "really_png.jpg";
    hostile::writeNoiseImage((dir / "p.png").string(), 32, 32);
    std::filesystem::rename(dir / "p.png", misnamed);
    CHECK(gm::probeImage(misnamed.string()).format == "png");
    CHECK(gm::readImage(misnamed.string()).width == 32);
    const gmtest::Run r =
        gmtest::runGradmesh("convert " + gmtest::q(png) + " -o " + gmtest::q(dir / "out.gmb"), dir);
    CHECK(r.code == 1);
    CHECK(r.err.find("GIF") != std::string::npos);
}

TEST_CASE("a multi-page TIFF converts its first page with a warning", "[hostile][raster][cli]") {
    const auto dir = gmtest::scratchDir("hostile_", "tiff_pages");
    const auto tif = dir / "pages.tif";
    hostile::writeNoiseImage(tif.string(), 64, 48, 3);
    CHECK(gm::probeImage(tif.string()).pages == 3);
    const gmtest::Run r = gmtest::runGradmesh(
        "convert " + gmtest::q(tif) + " --segment --max-patches 4 -o " + gmtest::q(dir / "out.gmb"), dir);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(r.err.find("has 3 pages; only the first is converted") != std::string::npos);
}
