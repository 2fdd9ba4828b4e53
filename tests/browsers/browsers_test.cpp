// The mesh script an SVG carries (formats/svg/script/mesh_polyfill.js) in the browsers users
// open our files in: headless Chromium and Firefox ESR draw the default
// SVG of an object (the apple), of an object with holes (pic1) and of a whole image (HappyFish,
// --segment), opened directly and inline in an HTML page, as `gradmesh render` draws it, with
// no pixel of a mesh left uncovered and no paint in its holes or around it. Flat shapes painted
// with linear gradients beside a mesh: the browser draws them itself, the script leaves them.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/synthetic_meshes.h"
#include "support/browser.h"
#include "support/cli_run.h"
#include "support/compare.h"
#include "support/gradient_shapes.h"
#include "svg/svg_test_support.h"

using namespace gmtest;
namespace fs = std::filesystem;

namespace {

// The page background: a colour no sample mesh holds, so that a pixel a mesh leaves
// uncovered shows.
constexpr float kBackground[3] = {1.0f, 0.0f, 1.0f};  // #ff00ff

struct Sample {
    std::string name, convert;  // convert: the gradmesh arguments that make the mesh
    int width = 0, height = 0;
};

const std::vector<Sample>& samples() {
    const std::string S = std::string(GRADMESH_SAMPLES) + "/";
    static const std::vector<Sample> all = {
        {"apple", "convert " + q(S + "apple.jpg") + " --mask " + q(S + "apple_mask.png"), 512, 512},
        {"pic1", "convert " + q(S + "pic1.png"), 400, 300},
        {"fish", "convert " + q(S + "HappyFish.jpg") + " --segment", 259, 194},
    };
    return all;
}

void writeFile(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// Converts the samples named once per test case: NAME.gmb, NAME.svg (the default SVG) and
// NAME_ours.png (our render of the SVG), in a directory of the case's own (ctest runs the cases
// as separate processes, possibly at the same time).
fs::path preparedSamples(const std::string& testCase, const std::vector<std::string>& names) {
    static std::map<std::string, fs::path> prepared;
    if (auto it = prepared.find(testCase); it != prepared.end()) return it->second;
    const fs::path d = scratchDir("browsers_samples_", testCase);
    for (const Sample& s : samples()) {
        if (std::find(names.begin(), names.end(), s.name) == names.end()) continue;
        const fs::path gmb = d / (s.name + ".gmb"), svg = d / (s.name + ".svg");
        const Run conv = runGradmesh(s.convert + " -o " + q(gmb), d);
        INFO(conv.err);
        REQUIRE(conv.code == 0);
        REQUIRE(runGradmesh("convert " + q(gmb) + " -o " + q(svg), d).code == 0);
        REQUIRE(runGradmesh("render " + q(svg) + " -o " + q(d / (s.name + "_ours.png")), d).code == 0);
    }
    return prepared[testCase] = d;
}

// The SVG as a document of its own on the background colour (a style on the root element).
std::string directPage(std::string svg) {
    const size_t root = svg.find("<svg");
    REQUIRE(root != std::string::npos);
    svg.insert(root + 4, " style=\"background:#ff00ff\"");
    return svg;
}

// The SVGs inline in one HTML page with no margin, one under the other, on the background
// colour: each carries the script and they repeat each other's ids, as on a page that shows
// several conversions.
std::string inlinePage(const std::vector<std::string>& svgs) {
    std::string page = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>meshes</title>"
                       "<style>body{margin:0;background:#ff00ff}svg{display:block}</style></head><body>\n";
    for (const std::string& svg : svgs) {
        const size_t root = svg.find("<svg");
        REQUIRE(root != std::string::npos);
        page += svg.substr(root);
    }
    return page + "</body></html>\n";
}

// Rows [y0, y0 + height) of the image.
gm::RgbaImage rows(const gm::RgbaImage& image, int y0, int width, int height) {
    gm::RgbaImage out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int k = 0; k < 4; ++k)
                out.at(x, y)[k] = x < image.width && y0 + y < image.height ? image.at(x, y0 + y)[k] : 0.0f;
    return out;
}

struct Coverage {
    size_t uncovered = 0;    // interior pixels showing mostly background
    double worst = 0;        // the largest background fraction seen in the interior
    size_t painted = 0;      // pixels of a hole or of the outside that show paint
    double worstPaint = 0;   // the largest difference from the background seen there
    size_t notches = 0;      // outer outline pixels far more covered than in our render
    double worstNotch = 0;   // the largest excess coverage seen there
    size_t holeNotches = 0;  // the same along the outlines of holes (not checked)
};

// Pixels that are not opaque in `ours` and connect to the image's border through such pixels:
// the outside and the outer outline, not the holes and their rims.
std::vector<char> outsideOf(const gm::RgbaImage& ours) {
    const int W = ours.width, H = ours.height;
    std::vector<char> outside(static_cast<size_t>(W) * H, 0);
    std::vector<int> queue;
    auto visit = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= W || y >= H) return;
        const size_t k = static_cast<size_t>(y) * W + x;
        if (outside[k] || ours.at(x, y)[3] >= 0.98f) return;
        outside[k] = 1;
        queue.push_back(static_cast<int>(k));
    };
    for (int x = 0; x < W; ++x) visit(x, 0), visit(x, H - 1);
    for (int y = 0; y < H; ++y) visit(0, y), visit(W - 1, y);
    for (size_t head = 0; head < queue.size(); ++head) {
        const int x = queue[head] % W, y = queue[head] / W;
        visit(x - 1, y), visit(x + 1, y), visit(x, y - 1), visit(x, y + 1);
    }
    return outside;
}

// Outline pixels (partly covered in `ours`) that the screenshot covers far more than our render
// does, next to another such pixel: where the pieces of a holed mesh meet the outline, both
// paths reaching across it (or both painting its pixels) showed as a dark notch in the edge,
// several pixels long (a lone pixel is the browser's coarser anti-aliasing of a sharp bend).
// The screenshot's coverage is estimated along the line from the background to our colour.
void checkNotches(const gm::RgbaImage& ours, const gm::RgbaImage& shot, Coverage& c) {
    const std::vector<char> outside = outsideOf(ours);
    std::vector<char> over(outside.size(), 0);
    for (int y = 0; y < ours.height; ++y)
        for (int x = 0; x < ours.width; ++x) {
            const float a = ours.at(x, y)[3];
            if (a <= 0.02f || a >= 0.98f) continue;
            double along = 0, span = 0;
            for (int k = 0; k < 3; ++k) {
                const double toColour = ours.at(x, y)[k] - kBackground[k];
                along += (shot.at(x, y)[k] - kBackground[k]) * toColour;
                span += toColour * toColour;
            }
            if (span < 0.4 * 0.4) continue;
            const double excess = along / span - a;
            if (!outside[static_cast<size_t>(y) * ours.width + x]) {
                c.holeNotches += excess > 0.3;
                continue;
            }
            c.worstNotch = std::max(c.worstNotch, excess);
            over[static_cast<size_t>(y) * ours.width + x] = excess > 0.3;
        }
    auto isOver = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < ours.width && y < ours.height && over[static_cast<size_t>(y) * ours.width + x];
    };
    for (int y = 0; y < ours.height; ++y)
        for (int x = 0; x < ours.width; ++x)
            c.notches += isOver(x, y) && (isOver(x - 1, y) || isOver(x + 1, y) || isOver(x, y - 1) || isOver(x, y + 1));
}

// Pixels painted where `ours` leaves a hole or the outside: pixels with no paint in `ours` 1 px
// around (so that anti-aliasing along the outlines is left out) must show the background.
void checkEmpty(const gm::RgbaImage& ours, const gm::RgbaImage& shot, Coverage& c) {
    const int W = ours.width, H = ours.height, reach = 1;
    auto empty = [&](int x, int y) {
        return x < 0 || y < 0 || x >= W || y >= H || ours.at(x, y)[3] <= 0.001f;
    };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool outside = true;
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) outside = outside && empty(x + dx, y + dy);
            if (!outside) continue;
            double difference = 0;
            for (int k = 0; k < 3; ++k)
                difference = std::max(difference, double(std::fabs(shot.at(x, y)[k] - kBackground[k])));
            c.worstPaint = std::max(c.worstPaint, difference);
            if (difference > 0.1) ++c.painted;
        }
}

// How much of the background shows through each pixel of `ours`' interior (opaque, eroded
// 1 px) in the screenshot: the fraction f with shot = (1−f)·ours + f·background, estimated
// along the direction from our colour to the background's. Pixels whose colour is near the
// background's say nothing and are left out, and so are pixels far off that line (no mix of our
// colour and the background: a colour difference, which E counts, not a pinhole).
Coverage coverage(const gm::RgbaImage& ours, const gm::RgbaImage& shot) {
    Coverage c;
    const int W = ours.width, H = ours.height;
    auto solid = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < W && y < H && ours.at(x, y)[3] >= 0.999f;
    };
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool inside = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) inside = inside && solid(x + dx, y + dy);
            if (!inside) continue;
            double along = 0, span = 0;
            for (int k = 0; k < 3; ++k) {
                const double toBackground = kBackground[k] - ours.at(x, y)[k];
                along += (shot.at(x, y)[k] - ours.at(x, y)[k]) * toBackground;
                span += toBackground * toBackground;
            }
            if (span < 0.4 * 0.4) continue;
            const double f = along / span;
            double offLine = 0;  // the screenshot's distance from (1−f)·ours + f·background
            for (int k = 0; k < 3; ++k) {
                const double mix = (1 - f) * ours.at(x, y)[k] + f * kBackground[k];
                offLine = std::max(offLine, double(std::fabs(shot.at(x, y)[k] - mix)));
            }
            if (offLine > 0.2) continue;
            c.worst = std::max(c.worst, f);
            if (f > 0.4) ++c.uncovered;
        }
    checkEmpty(ours, shot, c);
    checkNotches(ours, shot, c);
    return c;
}

struct Drawn {
    DiffStats diff;
    Coverage cover;
};

// Our render of the sample (prepared in `dir`) against the rows [y0, y0 + its height) of a
// screenshot.
Drawn compareWithOurs(const fs::path& dir, const Sample& s, const gm::RgbaImage& shot, int y0) {
    const gm::RgbaImage ours = gm::readImage((dir / (s.name + "_ours.png")).string());
    REQUIRE(ours.width == s.width);
    REQUIRE(ours.height == s.height);
    const gm::RgbaImage theirs = rows(shot, y0, s.width, s.height);
    return {compareInterior(ours, theirs, 1), coverage(ours, theirs)};
}

// Screenshots `page` (width × height CSS px) in browser `b`; checks that the browser ran it
// cleanly and returns the picture.
gm::RgbaImage screenshot(Browser b, const fs::path& page, int width, int height, const fs::path& work) {
    const fs::path png = work / (page.stem().string() + "_" + browserName(b) + ".png");
    fs::remove(png);
    const BrowserShot shot = browserScreenshot(b, page, width, height, png, work);
    INFO(browserName(b) << " on " << page.string() << "\n" << shot.console);
    REQUIRE(shot.code == 0);
    REQUIRE(fs::exists(png));
    CHECK(shot.console.empty());  // no error, no warning: the script prints nothing
    const gm::RgbaImage image = gm::readImage(png.string());
    REQUIRE(image.width == width);
    REQUIRE(image.height == height);
    return image;
}

void checkDrawn(Browser b, const std::string& where, const Drawn& d) {
    WARN(browserName(b) << ", " << where << ": E " << d.diff.mean << ", max " << d.diff.max << " over "
                        << d.diff.count << " px; uncovered " << d.cover.uncovered
                        << " px (largest background share " << d.cover.worst << "); painted outside "
                        << d.cover.painted << " px (largest difference " << d.cover.worstPaint << "); notches "
                        << d.cover.notches << " px (largest excess coverage " << d.cover.worstNotch << "), along holes "
                        << d.cover.holeNotches << " px");
    CHECK(d.diff.count > 1000);
    CHECK(d.diff.mean <= 1.5);
    CHECK(d.cover.uncovered == 0);
    CHECK(d.cover.painted == 0);
    CHECK(d.cover.notches == 0);
}

void checkBrowser(Browser b) {
    if (!browserAvailable(b)) {
        WARN(browserName(b) << " is not installed: skipped");
        return;
    }
    const fs::path work = scratchDir("browsers_", browserName(b));
    const fs::path dir = preparedSamples(browserName(b), {"apple", "pic1", "fish"});
    std::vector<std::string> svgs;
    int pageWidth = 0, pageHeight = 0;
    for (const Sample& s : samples()) {
        svgs.push_back(slurp(dir / (s.name + ".svg")));
        REQUIRE(svgs.back().find("<script") != std::string::npos);
        const fs::path direct = work / (s.name + "_direct.svg");
        writeFile(direct, directPage(svgs.back()));
        checkDrawn(b, direct.filename().string(),
                   compareWithOurs(dir, s, screenshot(b, direct, s.width, s.height, work), 0));
        pageWidth = std::max(pageWidth, s.width);
        pageHeight += s.height;
    }
    const fs::path inlined = work / "inline.html";
    writeFile(inlined, inlinePage(svgs));
    const gm::RgbaImage page = screenshot(b, inlined, pageWidth, pageHeight, work);
    int y0 = 0;
    for (const Sample& s : samples()) {
        checkDrawn(b, s.name + " inline in " + inlined.filename().string(), compareWithOurs(dir, s, page, y0));
        y0 += s.height;
    }
}

}  // namespace

TEST_CASE("Chromium draws the meshes of our SVGs, directly and inline", "[browsers][external]") {
    checkBrowser(Browser::Chromium);
}

TEST_CASE("Firefox ESR draws the meshes of our SVGs, directly and inline", "[browsers][external]") {
    checkBrowser(Browser::Firefox);
}

TEST_CASE("the script draws meshes painted through style or the fill attribute, with prefixed tags, and Inkscape's resaved file",
          "[browsers][external]") {
    if (!browserAvailable(Browser::Chromium)) {
        WARN("chromium is not installed: skipped");
        return;
    }
    const fs::path work = scratchDir("browsers_", "style");
    const Sample& apple = samples().front();
    const fs::path dir = preparedSamples("style", {"apple"});
    const std::string svg = slurp(dir / "apple.svg");

    // gradmesh writes style="fill:url(#id) none", as Inkscape does; older gradmesh files paint
    // with the fill="url(#id)" attribute. Both must draw.
    REQUIRE(svg.find("style=\"fill:url(#") != std::string::npos);
    writeFile(work / "styled.svg", directPage(svg));
    checkDrawn(Browser::Chromium, "style=\"fill:url(#m0) none\"",
               compareWithOurs(dir, apple, screenshot(Browser::Chromium, work / "styled.svg", apple.width,
                                                 apple.height, work), 0));
    std::string attributed = svg;
    size_t replaced = 0;
    for (size_t at = attributed.find("style=\"fill:url(#"); at != std::string::npos;
         at = attributed.find("style=\"fill:url(#", at)) {
        const size_t close = attributed.find(") none\"", at);
        REQUIRE(close != std::string::npos);
        const std::string id = attributed.substr(at + 17, close - at - 17);
        attributed.replace(at, close + 7 - at, "fill=\"url(#" + id + ")\"");
        ++replaced;
    }
    REQUIRE(replaced > 0);
    REQUIRE(attributed.find("fill=\"url(#m0)\"") != std::string::npos);
    writeFile(work / "attributed.svg", directPage(attributed));
    checkDrawn(Browser::Chromium, "fill=\"url(#m0)\"",
               compareWithOurs(dir, apple, screenshot(Browser::Chromium, work / "attributed.svg",
                                                 apple.width, apple.height, work), 0));

    // Some tools write the SVG elements with a namespace prefix (<svg:meshgradient>, <svg:stop>).
    std::string prefixed = std::regex_replace(svg, std::regex("<(/?)(meshgradient|meshrow|meshpatch|stop|path)\\b"),
                                              "<$1svg:$2");
    const size_t root = prefixed.find("<svg ");
    REQUIRE(root != std::string::npos);
    prefixed.insert(root + 4, " xmlns:svg=\"http://www.w3.org/2000/svg\"");
    REQUIRE(prefixed.find("<svg:stop ") != std::string::npos);
    writeFile(work / "prefixed.svg", directPage(prefixed));
    checkDrawn(Browser::Chromium, "<svg:meshgradient>",
               compareWithOurs(dir, apple, screenshot(Browser::Chromium, work / "prefixed.svg", apple.width,
                                                 apple.height, work), 0));

    // Inkscape's own save of the file (it keeps our script and adds its own).
    if (runCommand("command -v inkscape >/dev/null 2>&1") != 0) {
        WARN("inkscape is not installed: the resaved file is not checked");
        return;
    }
    const std::string home = (work / "inkscape-home").string();
    writeFile(work / "apple.svg", svg);
    REQUIRE(runCommand("HOME=" + q(home) + " XDG_CONFIG_HOME=" + q(home) +
                       " timeout 120 inkscape --export-type=svg --export-filename=" +
                       q(work / "resaved.svg") + " " + q(work / "apple.svg") + " >/dev/null 2>&1") == 0);
    const std::string resaved = slurp(work / "resaved.svg");
    CHECK(resaved.find("<meshgradient") != std::string::npos);
    writeFile(work / "resaved_page.svg", directPage(resaved));
    checkDrawn(Browser::Chromium, "Inkscape-resaved",
               compareWithOurs(dir, apple, screenshot(Browser::Chromium, work / "resaved_page.svg",
                                                 apple.width, apple.height, work), 0));
}

TEST_CASE("the SVG ends with one well-formed script, and --svg-script none leaves it out",
          "[browsers]") {
    const fs::path d = scratchDir("browsers_", "option");
    const fs::path gmb = preparedSamples("option", {"pic1"}) / "pic1.gmb";
    REQUIRE(runGradmesh("convert " + q(gmb) + " -o " + q(d / "none.svg") + " --svg-script none", d).code == 0);
    REQUIRE(runGradmesh("convert " + q(gmb) + " -o " + q(d / "embed.svg"), d).code == 0);
    const std::string none = slurp(d / "none.svg"), embed = slurp(d / "embed.svg");
    CHECK(none.find("<script") == std::string::npos);
    CHECK(none.find("<meshgradient") != std::string::npos);
    const size_t script = embed.find("<script type=\"text/javascript\"><![CDATA[");
    REQUIRE(script != std::string::npos);
    const size_t end = embed.find("]]></script>", script);
    REQUIRE(end != std::string::npos);
    CHECK(embed.find("]]>", script) == end);  // the script holds no CDATA end of its own
    CHECK(embed.substr(end) == "]]></script>\n</svg>\n");
    WARN("the script adds " << embed.size() - none.size() << " bytes to an SVG");
    CHECK(embed.size() - none.size() <= 10240 + 64);
    // Our reader ignores the script: both files read back to the same render.
    REQUIRE(runGradmesh("render " + q(d / "none.svg") + " -o " + q(d / "none.png"), d).code == 0);
    REQUIRE(runGradmesh("render " + q(d / "embed.svg") + " -o " + q(d / "embed.png"), d).code == 0);
    CHECK(slurp(d / "none.png") == slurp(d / "embed.png"));
    const Run bad = runGradmesh("convert " + q(gmb) + " -o " + q(d / "x.svg") + " --svg-script inline", d);
    CHECK(bad.code == 2);
    CHECK(bad.err.find("--svg-script expects embed or none") != std::string::npos);
}

namespace {

// The graded test document with a mesh the script draws, the shapes after the backdrop above
// it; `reversed`: every gradient's ends swapped (other gradients on the same outlines).
gm::Document gradedDocument(bool reversed) {
    gm::Document doc = gradientTestDocument();
    doc.meshes.push_back(gm::makeCurvedMesh(2, 2, 130, 92, 62, 44, 0.5, 3));
    for (size_t k = 1; k < doc.shapes.size(); ++k) {
        gm::FlatShape& s = doc.shapes[k];
        s.layer = 1;
        if (reversed) std::swap(s.gradient.from, s.gradient.to);
    }
    return doc;
}

// E of the rows [y0, y0 + doc's height) of a screenshot against our render of the SVG read
// back (as `gradmesh render` draws it: the mesh in the colours the file gives it): over every
// pixel but the canvas's border, and 2 px or more from every outline. Screenshot and render
// are written beside the page as NAME_shot.png and NAME_ours.png.
void checkGraded(Browser b, const std::string& svg, const gm::RgbaImage& shot, int y0,
                 const fs::path& work, const std::string& name) {
    const gm::Document doc = gm::decodeSvg(svg, gm::ReadLimits{});
    const gm::RgbaImage ours = gm::renderDocument(doc).image;
    const gm::RgbaImage theirs = rows(shot, y0, doc.width, doc.height);
    gm::writeImage(ours, (work / (name + "_ours.png")).string());
    gm::writeImage(theirs, (work / (name + "_shot.png")).string());
    const DiffStats all = compareInterior(ours, theirs, 1);
    const double away = svgtest::meanAbs(ours, theirs, svgtest::awayFromOutlines(doc));
    WARN(browserName(b) << ", " << name << ": E " << all.mean << " (max " << all.max << ") over "
                        << all.count << " px, " << away << " away from outlines");
    CHECK(all.count > 20000);
    CHECK(all.mean <= 1.0);
    CHECK(away <= 1.0);
}

void checkGradedInBrowser(Browser b) {
    if (!browserAvailable(b)) {
        WARN(browserName(b) << " is not installed: skipped");
        return;
    }
    const fs::path work = scratchDir("browsers_gradients_", browserName(b));
    // A window larger than the canvases: headless Chromium's screenshot of a window 140 px
    // high shows only the page's top 52 rows.
    constexpr int kWindow = 320;
    const gm::Document doc = gradedDocument(false);
    const std::string svg = gm::encodeSvg(doc, gm::WriteOptions{});
    const std::string otherSvg = gm::encodeSvg(gradedDocument(true), gm::WriteOptions{});
    REQUIRE(svg.find("<linearGradient") != std::string::npos);
    REQUIRE(svg.find("<script") != std::string::npos);
    writeFile(work / "gradients.svg", directPage(svg));
    checkGraded(b, svg, screenshot(b, work / "gradients.svg", kWindow, kWindow, work), 0, work,
                "direct");
    // Inline, one after the other: both use the ids of their meshes (m0), but each its own
    // gradients, whose ids differ with them.
    writeFile(work / "gradients_inline.html", inlinePage({svg, otherSvg}));
    const gm::RgbaImage page =
        screenshot(b, work / "gradients_inline.html", kWindow, kWindow, work);
    checkGraded(b, svg, page, 0, work, "inline_first");
    checkGraded(b, otherSvg, page, doc.height, work, "inline_second");
}

}  // namespace

TEST_CASE("Chromium draws graded shapes beside the script's meshes", "[browsers][external]") {
    checkGradedInBrowser(Browser::Chromium);
}

TEST_CASE("Firefox ESR draws graded shapes beside the script's meshes", "[browsers][external]") {
    checkGradedInBrowser(Browser::Firefox);
}
