// The raster fallback in the viewers that draw no meshes (librsvg, a browser's <img>), and
// Inkscape, which must keep drawing the meshes over it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <regex>
#include <vector>

#include "fallback_support.h"
#include "formats/svg.h"
#include "support/browser.h"

using namespace fallbacktest;
using gmtest::Run;

namespace {

// Our render of `svg` (the file as written, read back), the reference for every viewer.
fs::path ourRender(const fs::path& svg, const fs::path& dir) {
    const fs::path png = dir / (svg.stem().string() + "_ours.png");
    checkSuccess(gmtest::runGradmesh("render " + q(svg) + " -o " + q(png), dir));
    return png;
}

// One fallback SVG as the viewers are asked to show it.
struct Shown {
    std::string label;
    fs::path svg, ours, embedded;  // the file; gradmesh render of it; the render it embeds
    int width = 0, height = 0, left = 0;  // its place on the shared page
};

Shown writeFallbackSvg(const Sample& s, const std::string& kind, const fs::path& dir) {
    Shown v;
    v.label = s.name + " " + kind;
    v.svg = dir / (s.name + "_" + kind + ".svg");
    checkSuccess(gmtest::runGradmesh(
        "convert " + q(sampleGmb(s)) + " --svg-fallback " + kind + " -o " + q(v.svg), dir));
    v.ours = ourRender(v.svg, dir);
    v.embedded = dir / (s.name + "_embedded.png");
    checkSuccess(gmtest::runGradmesh("render " + q(sampleGmb(s)) + " -o " + q(v.embedded), dir));
    const gm::RgbaImage image = gm::readImage(v.ours.string());
    v.width = image.width;
    v.height = image.height;
    return v;
}

// Every file through <img> on one page (body margin 0), side by side at their own size: one
// browser start for all of them.
fs::path imgPage(std::vector<Shown>& shown, const fs::path& dir, int& width, int& height) {
    const fs::path page = dir / "img.html";
    std::ofstream html(page);
    html << "<!DOCTYPE html><html><body style=\"margin:0\">";
    width = height = 0;
    for (Shown& v : shown) {
        v.left = width;
        html << "<img style=\"position:absolute;top:0;left:" << v.left << "px\" src=\""
             << v.svg.filename().string() << "\">";
        width += v.width;
        height = std::max(height, v.height);
    }
    html << "</body></html>\n";
    return page;
}

// The part of a screenshot where `v` was shown, as a PNG beside the file.
fs::path cropped(const gm::RgbaImage& shot, const Shown& v) {
    gm::RgbaImage part(v.width, v.height);
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x)
            for (int c = 0; c < 4; ++c) part.at(x, y)[c] = shot.at(v.left + x, y)[c];
    const fs::path png = v.svg.parent_path() / (v.svg.stem().string() + "_img.png");
    gm::writeImage(part, png.string());
    return png;
}

}  // namespace

TEST_CASE("rsvg-convert and Chromium's <img> show the fallback as gradmesh renders it",
          "[fallback][external]") {
    REQUIRE(gmtest::runCommand("command -v rsvg-convert >/dev/null") == 0);
    REQUIRE(gmtest::browserAvailable(gmtest::Browser::Chromium));
    const fs::path d = tmpDir("viewers");
    std::vector<Shown> shown;
    for (const Sample& s : kSamples) shown.push_back(writeFallbackSvg(s, "png", d));
    shown.push_back(writeFallbackSvg(kSamples[2], "webp", d));  // browsers only

    int width = 0, height = 0;
    const fs::path page = imgPage(shown, d, width, height), shotPng = d / "img.png";
    REQUIRE(gmtest::browserScreenshot(gmtest::Browser::Chromium, page, width, height, shotPng, d)
                .code == 0);
    const gm::RgbaImage shot = gm::readImage(shotPng.string());
    REQUIRE(shot.width == width);

    for (const Shown& v : shown) {
        INFO(v.label);
        const fs::path img = cropped(shot, v);
        const gmtest::DiffStats byImg = interiorError(v.ours, img);
        // The embedded pixels are the render of the document written (the .gmb's): the
        // viewers show them as they are. Flat shapes painted over every mesh (the fish's ink
        // lines) are left out of the image and drawn by the viewer itself, over it.
        const bool shapesOnTop = gmtest::slurp(v.svg).find("<path fill=") != std::string::npos;
        const double imgExact = interiorError(v.embedded, img).mean;
        CHECK(byImg.count > 1000);
        CHECK(byImg.mean <= 1.0);
        if (!shapesOnTop) CHECK(imgExact <= 0.1);
        if (v.label.find("webp") != std::string::npos) {
            WARN(v.label << ": Chromium <img> E " << byImg.mean << " (max " << byImg.max
                         << ") from the render of the SVG, " << imgExact << " from the embedded");
            continue;  // librsvg decodes no WebP here (docs/browsers.md)
        }
        const fs::path rsvg = d / (v.svg.stem().string() + "_rsvg.png");
        REQUIRE(gmtest::runCommand("rsvg-convert " + q(v.svg) + " -o " + q(rsvg)) == 0);
        const gmtest::DiffStats byRsvg = interiorError(v.ours, rsvg);
        const double rsvgExact = interiorError(v.embedded, rsvg).mean;
        WARN(v.label << ": rsvg-convert E " << byRsvg.mean << " (max " << byRsvg.max
                     << "), Chromium <img> E " << byImg.mean << " (max " << byImg.max
                     << ") from the render of the SVG; " << rsvgExact << " and " << imgExact
                     << " from the embedded");
        CHECK(byRsvg.mean <= 1.0);
        if (!shapesOnTop) CHECK(rsvgExact <= 0.1);
    }

    // .svgz carries the fallback as well.
    const fs::path svgz = d / "fish_png.svgz", rsvg = d / "fish_svgz_rsvg.png";
    checkSuccess(gmtest::runGradmesh(
        "convert " + q(sampleGmb(kSamples[2])) + " --svg-fallback png -o " + q(svgz), d));
    REQUIRE(gmtest::runCommand("rsvg-convert " + q(svgz) + " -o " + q(rsvg)) == 0);
    CHECK(interiorError(shown[2].ours, rsvg).mean <= 1.0);
}

namespace {

// Inkscape's PNG export of `svg`, with a private profile.
fs::path inkscapePng(const fs::path& svg, const fs::path& dir) {
    const fs::path png = dir / (svg.stem().string() + "_ink.png");
    const std::string home = (dir / "inkscape-home").string();
    REQUIRE(gmtest::runCommand("HOME=" + q(home) + " XDG_CONFIG_HOME=" + q(home) +
                               " inkscape --export-type=png --export-filename=" + q(png) + " " +
                               q(svg) + " >/dev/null 2>&1") == 0);
    return png;
}

// A PNG of one colour over the whole canvas: a fallback that must not show in Inkscape.
std::string magentaPng(int width, int height) {
    gm::RgbaImage image(width, height);
    for (size_t p = 0; p < image.pixels.size(); p += 4) {
        image.pixels[p] = image.pixels[p + 2] = image.pixels[p + 3] = 1.f;
        image.pixels[p + 1] = 0.f;
    }
    return gm::encodeImage(image, "magenta.png");
}

}  // namespace

TEST_CASE("Inkscape draws the meshes over the fallback layer, not the image",
          "[fallback][external][bicubic]") {
    const fs::path d = tmpDir("inkscape");
    const gm::MeshFormat* gmb = gm::FormatRegistry::builtin().byName("gmb");
    {  // pic1: 14 hole-free pieces, whose seams would show the image
        const Sample& s = kSamples[1];
        const gm::Document doc = gmb->read(sampleGmb(s).string(), gm::ReadOptions{});
        gm::WriteOptions options;
        options.svgFallback = "png";
        const gm::SvgFallbackImage wrong{"png", magentaPng(doc.width, doc.height)};
        const fs::path svg = d / (s.name + ".svg");
        std::ofstream(svg, std::ios::binary) << gm::encodeSvg(doc, options, nullptr, &wrong);
        const fs::path ours = ourRender(svg, d), ink = inkscapePng(svg, d);
        const gmtest::DiffStats byInkscape = interiorError(ours, ink);
        WARN(s.name << ": Inkscape over a magenta fallback against our render: E "
                    << byInkscape.mean << " (max " << byInkscape.max << ")");
        CHECK(byInkscape.mean <= 0.5);  // as without a fallback (cli_convert [bicubic])
    }

    // The paint in style draws what the fill attribute drew, pixel for pixel.
    const fs::path styled = d / "styled.svg", attribute = d / "attribute.svg";
    checkSuccess(
        gmtest::runGradmesh("convert " + q(sampleGmb(kSamples[1])) + " -o " + q(styled), d));
    const std::string text = gmtest::slurp(styled);
    const std::string old = std::regex_replace(
        text, std::regex("style=\"fill:url\\(#(m[0-9]+)\\) none\""), "fill=\"url(#$1)\"");
    REQUIRE(old != text);
    std::ofstream(attribute, std::ios::binary) << old;
    const gm::RgbaImage a = gm::readImage(inkscapePng(styled, d).string());
    const gm::RgbaImage b = gm::readImage(inkscapePng(attribute, d).string());
    CHECK(a.pixels == b.pixels);
}
