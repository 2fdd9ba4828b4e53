// `gradmesh view` and `convert --report PAGE.html`: the page loads in headless Chromium without
// a console message and shows our render at 1x where its layout puts it; bad input is refused
// with a message and nothing written.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "formats/raster.h"
#include "support/browser.h"
#include "support/cli_run.h"

using namespace gmtest;
namespace fs = std::filesystem;

namespace {

// Where the page puts the picture's top-left corner (view_page.html: the stage is 24 px from
// the left, below the 56 px bar and a 24 px gap), and a window that holds a 512 px canvas at 1x.
constexpr int kStageLeft = 24, kStageTop = 80;
constexpr int kWindowWidth = 1280, kWindowHeight = 800;

const std::string kSamples = GRADMESH_SAMPLES;

gm::RgbaImage crop(const gm::RgbaImage& image, int left, int top, int width, int height) {
    gm::RgbaImage out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 4; ++c) out.at(x, y)[c] = image.at(left + x, top + y)[c];
    return out;
}

// Screenshots `page` in Chromium and compares its stage with `render` (our render, whose size
// is the canvas's) over the render's interior. Returns the console messages.
std::string requireStageShowsRender(const fs::path& page, const fs::path& render, const fs::path& dir) {
    const fs::path shot = dir / "shot.png";
    const BrowserShot result = browserScreenshot(Browser::Chromium, page, kWindowWidth, kWindowHeight, shot, dir / "browser");
    REQUIRE(result.code == 0);
    const gm::RgbaImage ours = gm::readImage(render.string());
    const gm::RgbaImage screen = gm::readImage(shot.string());
    REQUIRE(screen.width == kWindowWidth);
    const DiffStats d = compareInterior(ours, crop(screen, kStageLeft, kStageTop, ours.width, ours.height));
    INFO("E " << d.mean << ", max " << d.max << " over " << d.count << " pixels");
    CHECK(d.count > 1000);
    CHECK(d.mean <= 0.5);
    CHECK(d.max <= 4);
    return result.console;
}

// The browser tests run in the suite: scripts/install-deps.sh installs Debian's chromium.
void requireChromium() {
    INFO("headless Chromium is needed: scripts/install-deps.sh installs it");
    REQUIRE(browserAvailable(Browser::Chromium));
}

// The page loads nothing: no address outside it in an attribute, a style or a script.
void requireSelfContained(const std::string& page) {
    for (const char* fetch : {"src=\"http", "href=\"http", "src=\"//", "href=\"//", "url(http", "url(//",
                              "@import", "fetch(", "XMLHttpRequest", "<link rel=\"stylesheet"})
        CHECK(page.find(fetch) == std::string::npos);
}

// The number after `key` in the page's figures ("E": 1.23).
double figure(const std::string& page, const std::string& key) {
    const size_t at = page.find(key);
    REQUIRE(at != std::string::npos);
    return std::strtod(page.c_str() + at + key.size(), nullptr);
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST_CASE("view: the page of a mesh file shows our render and loads without console messages") {
    requireChromium();
    const fs::path d = scratchDir("view_", "mesh");
    REQUIRE(runGradmesh("sample " + q(d / "sample.gmb"), d).code == 0);
    REQUIRE(runGradmesh("render " + q(d / "sample.gmb") + " -o " + q(d / "render.png"), d).code == 0);
    const Run r = runGradmesh("view " + q(d / "sample.gmb") + " -o " + q(d / "page.html"), d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string page = slurp(d / "page.html");
    CHECK(page.find("\"patches\":184,") != std::string::npos);
    CHECK(page.find("\"holes\":3,") != std::string::npos);
    CHECK(page.find("<meshgradient") != std::string::npos);  // the SVG, inline, for zooming
    requireSelfContained(page);
    const std::string console = requireStageShowsRender(d / "page.html", d / "render.png", d);
    CHECK(console == "");
}

// The page with an image is screenshot in the --report test below (the same page, other figures).
TEST_CASE("view: with --image the page holds the image and the error map, and E measures them") {
    const fs::path d = scratchDir("view_", "image");
    REQUIRE(runGradmesh("sample " + q(d / "sample.gmb"), d).code == 0);
    REQUIRE(runGradmesh("render " + q(d / "sample.gmb") + " -o " + q(d / "render.png"), d).code == 0);
    // The render as "the source": the error is 0 everywhere the mesh paints.
    const Run r = runGradmesh("view " + q(d / "sample.gmb") + " --image " + q(d / "render.png") + " -o " +
                                  q(d / "page.html"), d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string page = slurp(d / "page.html");
    CHECK(count(page, "data:image/png;base64,") == 3);  // image, render, heat map
    CHECK(figure(page, "\"error\":{\"E\":") < 0.5);  // 8-bit rounding of the PNG
    requireSelfContained(page);
}

TEST_CASE("view: convert --report PAGE.html writes the page with the conversion's figures") {
    requireChromium();
    const fs::path d = scratchDir("view_", "report");
    const Run r = runGradmesh("convert " + q(kSamples + "/apple.jpg") + " --mask " + q(kSamples + "/apple_mask.png") +
                                  " --max-patches 16 -o " + q(d / "apple.gmb") + " --report " + q(d / "apple.html"),
                              d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    REQUIRE(runGradmesh("render " + q(d / "apple.gmb") + " -o " + q(d / "render.png"), d).code == 0);
    const std::string page = slurp(d / "apple.html");
    CHECK(page.find("[\"triangulate\",") != std::string::npos);  // seconds per stage
    CHECK(page.find("\"format\":\".svgz\",\"bytes\":") != std::string::npos);
    CHECK(page.find("\"source\":\"apple.jpg\"") != std::string::npos);
    requireSelfContained(page);
    CHECK(requireStageShowsRender(d / "apple.html", d / "render.png", d) == "");
}

// The SVG's mesh script defines window.gradmeshMeshes: a stand-in for it, put into the page's
// inline SVG before the real one (which then leaves drawing to the first definition, calling
// its scan()), fills the mesh shapes red when its redraw() is called, and opens the page at 2x
// (before the page's own script reads the address).
const char* const kMeshScriptStandIn =
    "<script>history.replaceState(null, '', '#zoom=2');"
    "window.gradmeshMeshes = {scan: function () {}, redraw: function () {"
    "  var shapes = document.querySelectorAll('#gv-vector path');"
    "  for (var k = 0; k != shapes.length; ++k) shapes[k].style.fill = '#ff0000';"
    "}};</script>";

TEST_CASE("view: zoomed in, the page shows the inline SVG and has the SVG's mesh script redraw it") {
    requireChromium();
    const fs::path d = scratchDir("view_", "mesh_script");
    REQUIRE(runGradmesh("sample " + q(d / "sample.gmb"), d).code == 0);
    REQUIRE(runGradmesh("view " + q(d / "sample.gmb") + " -o " + q(d / "page.html"), d).code == 0);
    std::string page = slurp(d / "page.html");
    const size_t svg = page.find("<svg xmlns=\"http://www.w3.org/2000/svg\"");
    REQUIRE(svg != std::string::npos);
    page.insert(page.find('>', svg) + 1, kMeshScriptStandIn);
    { std::ofstream(d / "scripted.html", std::ios::binary) << page; }

    const BrowserShot shot =
        browserScreenshot(Browser::Chromium, d / "scripted.html", kWindowWidth, kWindowHeight, d / "shot.png", d / "browser");
    REQUIRE(shot.code == 0);
    CHECK(shot.console == "");
    // The stage at 2x: mostly the red shapes (our render has no pure red).
    const gm::RgbaImage screen = gm::readImage((d / "shot.png").string());
    const gm::RgbaImage stage = crop(screen, kStageLeft, kStageTop, 512, 512);
    size_t red = 0;
    for (int y = 0; y < stage.height; ++y)
        for (int x = 0; x < stage.width; ++x) {
            const float* p = stage.at(x, y);
            red += p[0] > 0.99f && p[1] < 0.01f && p[2] < 0.01f;
        }
    INFO(red << " red pixels of " << 512 * 512);
    CHECK(red > 512 * 512 / 2);
}

TEST_CASE("view: reads .svg and .svgz as well as .gmb") {
    const fs::path d = scratchDir("view_", "svg");
    REQUIRE(runGradmesh("sample " + q(d / "sample.gmb"), d).code == 0);
    for (const char* name : {"sample.svg", "sample.svgz"}) {
        INFO(name);
        REQUIRE(runGradmesh("convert " + q(d / "sample.gmb") + " -o " + q(d / name), d).code == 0);
        const Run r = runGradmesh("view " + q(d / name) + " -o " + q(d / "page.html"), d);
        CHECK(r.code == 0);
        const std::string page = slurp(d / "page.html");
        CHECK(figure(page, "\"patches\":") > 0);  // holed meshes come back as hole-free pieces
        CHECK(page.find("<meshgradient") != std::string::npos);
    }
}

TEST_CASE("view: bad input is refused with a message, and nothing is written") {
    const fs::path d = scratchDir("view_", "bad");
    REQUIRE(runGradmesh("sample " + q(d / "sample.gmb"), d).code == 0);
    const fs::path page = d / "page.html";
    auto refused = [&](const std::string& args, int code, const std::string& message) {
        const Run r = runGradmesh("view " + args, d);
        INFO(args << "\n" << r.err);
        CHECK(r.code == code);
        CHECK(r.err.find(message) != std::string::npos);
        CHECK(gmtest::lineCount(r.err) == 1);
        CHECK(!fs::exists(page));
    };
    refused(q(d / "missing.gmb") + " -o " + q(page), 1, "missing.gmb");
    refused(q(kSamples + "/apple.jpg") + " -o " + q(page), 1, "is an image, not a mesh file");
    refused(q(d / "sample.gmb") + " -o " + q(d / "page.png"), 2, "-o PAGE.html");
    refused(q(d / "sample.gmb"), 2, "missing -o");
    refused(q(d / "sample.gmb") + " -o " + q(d / "no-such-dir" / "page.html"), 1, "page.html");
    refused(q(d / "sample.gmb") + " --image " + q(kSamples + "/fruits.jpg") + " -o " + q(page), 1,
            "the mesh's canvas 512x512");
    refused(q(d / "sample.gmb") + " --max-output-bytes 1000 -o " + q(page), 1, "--max-output-bytes");
    // A failed run leaves an existing page as it was, and the input is never the output.
    { std::ofstream(page) << "earlier page"; }
    CHECK(runGradmesh("view " + q(d / "sample.gmb") + " --image " + q(d / "missing.png") + " -o " + q(page), d).code == 1);
    CHECK(slurp(page) == "earlier page");
    fs::copy_file(d / "sample.gmb", d / "mesh.html");
    const Run same = runGradmesh("view " + q(d / "mesh.html") + " -o " + q(d / "mesh.html"), d);
    CHECK(same.code == 1);
    CHECK(fs::file_size(d / "mesh.html") == fs::file_size(d / "sample.gmb"));
    const Run help = runGradmesh("view --help", d);
    CHECK(help.code == 0);
    CHECK(help.out.find("usage: gradmesh view") != std::string::npos);
    CHECK(runGradmesh("--help", d).out.find("view IN -o PAGE.html") != std::string::npos);
    // No temporaries left beside the outputs.
    for (const auto& e : fs::directory_iterator(d))
        CHECK(e.path().filename().string().find("gradmesh-tmp") == std::string::npos);
}
