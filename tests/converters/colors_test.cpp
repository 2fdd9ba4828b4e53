#include "converters/colors.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "converters/grid.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/evaluate.h"
#include "meshcore/render.h"
#include "fit_inputs.h"
#include "synthetic_region.h"

using namespace gm;

namespace {

const double kP = 400;

gmtest::Synthetic disk() {
    return gmtest::makeSynthetic(kP, kP, 48, 48, gmtest::diskMap(kP, 256, 256, 200), 512, 512);
}

Vec3 ramp(double x, double y) {
    return {0.1 + 0.0012 * x + 0.0004 * y, 0.9 - 0.0011 * y, 0.3 + 0.0005 * x};
}

Vec3 smooth(double x, double y) {
    return {0.5 + 0.4 * std::sin(x / 45.0) * std::cos(y / 60.0),
            0.5 + 0.35 * std::cos((x + y) / 70.0), 0.45 + 0.4 * std::sin(y / 38.0)};
}

// A 200 × 200 rectangle (image offset 28) whose lattice is cut along v = 100 from u = 50 to
// 150, both sides moved 3 px apart to open a hole; the region excludes the hole.
gmtest::Synthetic slitRectangle() {
    auto s = gmtest::makeSynthetic(
        200, 200, 20, 20,
        [](double u, double v) {
            return Vec2{28 + u, 28 + v};
        },
        256, 256);
    // Cut the lattice along v = 100 from u = 50 to 150: duplicate those vertices for the
    // lower side and move both sides apart by 3 px to open a hole.
    const int n = 20;
    std::vector<int> lower(static_cast<size_t>((n + 1) * (n + 1)));
    for (int k = 0; k < (n + 1) * (n + 1); ++k) lower[k] = k;
    for (int i = 6; i < 15; ++i) {
        const int k = 10 * (n + 1) + i;
        lower[k] = static_cast<int>(s.tri.vertices.size());
        s.tri.vertices.push_back(s.tri.vertices[k] + Vec2{0, 3});
        s.map.uv.push_back(s.map.uv[k]);
        s.tri.vertices[k] = s.tri.vertices[k] + Vec2{0, -3};
    }
    for (auto& t : s.tri.triangles) {
        // Triangles of lattice row 10 (just below the slit) take the lower copies.
        bool belowRow = false;
        for (int k : t) belowRow = belowRow || s.map.uv[k].y > 100.5;
        if (!belowRow) continue;
        for (int& k : t)
            if (k < (n + 1) * (n + 1)) k = lower[k];
    }
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            if (y + 0.5 > 128 - 3 && y + 0.5 < 128 + 3 && x + 0.5 > 78 + 10 && x + 0.5 < 178 - 10)
                s.region.mask[y * 256 + x] = 0;
    return s;
}

}  // namespace

TEST_CASE("region colour samples come from the region's side only", "[colours]") {
    Region r;
    r.width = r.height = 8;
    r.mask.assign(64, 0);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 4; ++x) r.mask[y * 8 + x] = 1;
    const RgbaImage img = gmtest::paint(8, 8, [](double x, double) {
        return x < 4 ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
    });
    const Vec3 edge = sampleRegionColor(img, r, {4.0, 3.0});  // halfway between the two sides
    CHECK(edge.r == Approx(1));
    CHECK(edge.b == Approx(0));
    const Vec3 outside = sampleRegionColor(img, r, {7.5, 7.5});  // nearest region pixel
    CHECK(outside.r == Approx(1));
    const Vec3 inside = sampleRegionColor(img, r, {2.0, 2.0});
    CHECK(inside.r == Approx(1));

    Region wrong = r;
    wrong.width = 7;
    CHECK_THROWS_AS(sampleRegionColor(img, wrong, {1, 1}), Error);
}

TEST_CASE("sampled mode samples nodes into a bicubic mesh", "[colours]") {
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, smooth);
    GridOptions go;
    go.columns = go.rows = 4;
    const GradientMesh geo = buildGrid(s.tri, s.map, go);
    ColorOptions co;
    co.mode = ColorMode::Sampled;
    const ColorResult r = computeColors(geo, img, s.region, co);
    CHECK(r.mesh.colorModel == ColorModel::Bicubic);
    const Node& n = r.mesh.node(2, 2);
    const Vec3 e = smooth(n.pos.x, n.pos.y);
    CHECK(n.col.g == Approx(e.g).margin(0.01));
    CHECK(r.error.pixels == s.region.pixelCount);
    CHECK(r.error.uncovered < 0.001);
}

TEST_CASE("a linear colour ramp is fitted by a 1x1 mesh", "[colours]") {
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, ramp);
    GridOptions go;
    go.columns = go.rows = 1;
    const GradientMesh geo = buildGrid(s.tri, s.map, go);
    REQUIRE(geo.patchCount() == 1);
    ColorOptions co;
    co.mode = ColorMode::Fit;
    const ColorResult fit = computeColors(geo, img, s.region, co);
    co.mode = ColorMode::Sampled;
    const ColorResult sampled = computeColors(geo, img, s.region, co);
    WARN("1x1 disk, linear ramp: E fit " << fit.error.meanAbs << ", E sampled "
                                         << sampled.error.meanAbs << ", uncovered "
                                         << fit.error.uncovered);
    CHECK(fit.error.meanAbs < 0.5);
    // One cubic per quarter circle misses a sliver of the disk's outline pixels.
    CHECK(fit.error.uncovered < 0.01);
    // The render's colours are the fitted mesh's: measuring again gives the same figure.
    const ColorResult again = measureColorError(fit.mesh, img, s.region);
    CHECK(again.error.meanAbs == Approx(fit.error.meanAbs).margin(1e-6));
}

TEST_CASE("fit beats sampled on a smooth non-linear image at equal patch count, the bicubic "
          "fit lies between them",
          "[colours][rule]") {
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, smooth);
    for (int cells : {3, 6, 12}) {
        GridOptions go;
        go.columns = go.rows = cells;
        const GradientMesh geo = buildGrid(s.tri, s.map, go);
        ColorOptions co;
        co.mode = ColorMode::Sampled;
        const ColorResult sampled = computeColors(geo, img, s.region, co);
        co.mode = ColorMode::Fit;
        const ColorResult fit = computeColors(geo, img, s.region, co);
        co.mode = ColorMode::FitBicubic;
        const ColorResult rule = computeColors(geo, img, s.region, co);
        WARN(cells << "x" << cells << " disk, smooth image: E fit " << fit.error.meanAbs
                   << " (PSNR " << fit.error.psnr << "), E sampled " << sampled.error.meanAbs
                   << " (PSNR " << sampled.error.psnr << "), E rule " << rule.error.meanAbs
                   << " (PSNR " << rule.error.psnr << ")");
        CHECK(fit.error.meanAbs < sampled.error.meanAbs);
        CHECK(fit.error.rmse < sampled.error.rmse);
        CHECK(rule.mesh.colorModel == ColorModel::Bicubic);
        CHECK(rule.error.rmse < sampled.error.rmse);
        CHECK(fit.error.rmse <= rule.error.rmse * 1.001);
    }
}

TEST_CASE("the fit respects slits: each side of a hole gets its own colours", "[colours]") {
    // Red above the slit row, blue below it.
    const auto s = slitRectangle();
    const RgbaImage img = gmtest::paint(256, 256, [](double, double y) {
        return y < 128 ? Vec3{0.9, 0.1, 0.1} : Vec3{0.1, 0.1, 0.9};
    });
    GridOptions go;
    go.columns = 4;
    go.rows = 2;
    go.slits = {{100, 50, 150}};
    const GradientMesh geo = buildGrid(s.tri, s.map, go);
    REQUIRE(geo.slits.size() == 1);
    const ColorResult fit = computeColors(geo, img, s.region);
    const Slit& sl = fit.mesh.slits[0];
    for (int i = sl.i0 + 1; i < sl.i1; ++i) {
        CHECK(fit.mesh.node(i, sl.row).col.r > 0.6);  // above: red
        CHECK(sl.below[i - sl.i0 - 1].col.b > 0.6);   // below: blue
    }
    WARN("slit mesh, red above / blue below: E fit " << fit.error.meanAbs);
}

TEST_CASE("colours reject mismatched inputs", "[colours]") {
    const auto s = disk();
    const RgbaImage small(100, 100);
    GridOptions go;
    go.columns = go.rows = 2;
    const GradientMesh geo = buildGrid(s.tri, s.map, go);
    CHECK_THROWS_AS(computeColors(geo, small, s.region), Error);
}

namespace {

// The slit rectangle's 4x2 grid with arbitrary colours in every slot the patches use: node
// copies on both sides of the slit, the slit ends' ±d, a tangent break at patch (0, 0).
GradientMesh paintedSlitGrid(const gmtest::Synthetic& s) {
    GridOptions go;
    go.columns = 4;
    go.rows = 2;
    go.slits = {{100, 50, 150}};
    GradientMesh truth = buildGrid(s.tri, s.map, go);
    REQUIRE(truth.slits.size() == 1);
    unsigned seed = 12345;
    auto rnd = [&seed](double lo, double hi) {
        seed = seed * 1103515245u + 12345u;
        return lo + (hi - lo) * ((seed >> 8) & 0xffff) / 65535.0;
    };
    auto colour = [&]() { return Vec3{rnd(0.2, 0.8), rnd(0.2, 0.8), rnd(0.2, 0.8)}; };
    auto slope = [&]() { return Vec3{rnd(-0.004, 0.004), rnd(-0.004, 0.004), rnd(-0.004, 0.004)}; };
    auto paintNode = [&](Node& n) {
        n.col = colour();
        n.colU = slope();
        n.colV = slope();
    };
    for (Node& n : truth.nodes) paintNode(n);
    for (Node& n : truth.slits[0].below) paintNode(n);
    truth.slits[0].left.colU = slope();
    truth.slits[0].right.colU = slope();
    CornerTangent ct;
    ct.i = 0;
    ct.j = 0;
    ct.a = 1;
    ct.b = 1;
    ct.posU = truth.node(1, 1).posU;
    ct.colU = slope();
    truth.tangents.push_back(ct);
    return truth;
}

// The image a mesh renders (no antialiasing) and the region of the pixels it paints.
std::pair<RgbaImage, Region> renderedTarget(const GradientMesh& truth, const Region& like) {
    RenderOptions ro;
    ro.antialias = false;
    RgbaImage img = renderMesh(truth, like.width, like.height, ro).image;
    Region region = like;
    for (size_t p = 0; p < region.mask.size(); ++p) region.mask[p] = img.pixels[p * 4 + 3] >= 0.5f;
    return {std::move(img), std::move(region)};
}

}  // namespace

TEST_CASE("the fit recovers a mesh's own colours through slits and tangent breaks", "[colours]") {
    // The target image is a render of the grid with arbitrary colours in every slot.
    const auto s = slitRectangle();
    const GradientMesh truth = paintedSlitGrid(s);
    const auto [img, region] = renderedTarget(truth, s.region);
    GradientMesh geometry = truth;
    for (Node& n : geometry.nodes) n.col = n.colU = n.colV = Vec3{};
    const ColorResult fit = computeColors(geometry, img, region);
    WARN("recovering a slit mesh's colours: E fit " << fit.error.meanAbs << ", max "
                                                    << fit.error.maxAbs);
    CHECK(fit.error.meanAbs < 0.05);
    CHECK(fit.error.maxAbs < 1.0);
    const Slit& sl = fit.mesh.slits[0];
    REQUIRE(!sl.below.empty());
    REQUIRE(sl.below.size() == truth.slits[0].below.size());
    for (size_t k = 0; k < sl.below.size(); ++k)
        CHECK(sl.below[k].col.g == Approx(truth.slits[0].below[k].col.g).margin(0.01));
    CHECK(fit.mesh.node(2, 1).col.g == Approx(truth.node(2, 1).col.g).margin(0.01));
}

TEST_CASE("the bicubic fit recovers a bicubic mesh's colours, through slits and breaks",
          "[colours][rule]") {
    const auto s = slitRectangle();
    GradientMesh truth = paintedSlitGrid(s);
    truth.colorModel = ColorModel::Bicubic;
    const auto [img, region] = renderedTarget(truth, s.region);
    GradientMesh geometry = truth;
    for (Node& n : geometry.nodes) n.col = n.colU = n.colV = Vec3{};
    ColorOptions co;
    co.mode = ColorMode::FitBicubic;
    const ColorResult fit = computeColors(geometry, img, region, co);
    WARN("recovering a bicubic mesh's colours with the bicubic fit: E " << fit.error.meanAbs
                                                                       << ", max " << fit.error.maxAbs);
    CHECK(fit.mesh.colorModel == ColorModel::Bicubic);
    CHECK(fit.error.meanAbs < 0.05);
    CHECK(fit.mesh.node(2, 1).col.g == Approx(truth.node(2, 1).col.g).margin(0.01));
    CHECK(fit.mesh.slits[0].below[0].col.r == Approx(truth.slits[0].below[0].col.r).margin(0.01));
}

TEST_CASE("the bicubic fit recovers a bicubic mesh's own colours on a 12x12 grid and a large "
          "slit grid",
          "[colours][rule]") {
    const auto s = disk();
    GridOptions go;
    go.columns = go.rows = 12;
    GradientMesh truth = buildGrid(s.tri, s.map, go);
    for (Node& n : truth.nodes) n.col = smooth(n.pos.x, n.pos.y);
    truth.colorModel = ColorModel::Bicubic;
    const auto [target, region] = renderedTarget(truth, s.region);
    ColorOptions co;
    co.mode = ColorMode::FitBicubic;
    const ColorResult back = computeColors(truth, target, region, co);
    CHECK(back.mesh.colorModel == ColorModel::Bicubic);
    CHECK(back.error.meanAbs < 0.05);

    // Slit meshes of any size are fitted (no dense Jacobian), and beat the sampled colours.
    const auto r = slitRectangle();
    go.columns = 30;
    go.rows = 24;
    go.slits = {{100, 50, 150}};
    const GradientMesh geo = buildGrid(r.tri, r.map, go);
    REQUIRE(geo.slits.size() == 1);
    REQUIRE(geo.nodes.size() > 600);
    const RgbaImage img = gmtest::paint(256, 256, smooth);
    const ColorResult fitted = computeColors(geo, img, r.region, co);
    co.mode = ColorMode::Sampled;
    const ColorResult sampled = computeColors(geo, img, r.region, co);
    CHECK(fitted.error.rmse < sampled.error.rmse);
}

TEST_CASE("the values fit recovers a mesh's colour values with its slopes held, through slits",
          "[colours]") {
    // The target is a render of the grid with arbitrary colours; the geometry passed in carries
    // the true slopes (and tangent-break slopes) but no values.
    const auto s = slitRectangle();
    const GradientMesh truth = paintedSlitGrid(s);
    const auto [img, region] = renderedTarget(truth, s.region);
    GradientMesh geometry = truth;
    for (Node& n : geometry.nodes) n.col = Vec3{};
    for (Node& n : geometry.slits[0].below) n.col = Vec3{};
    ColorOptions co;
    co.mode = ColorMode::FitValues;
    const ColorResult fit = computeColors(geometry, img, region, co);
    WARN("recovering a slit mesh's values with its slopes held: E " << fit.error.meanAbs << ", max "
                                                                    << fit.error.maxAbs);
    CHECK(fit.error.meanAbs < 0.05);
    CHECK(fit.error.maxAbs < 1.0);
    for (size_t k = 0; k < truth.nodes.size(); ++k) {
        // Slopes exactly as given; values recovered.
        CHECK(fit.mesh.nodes[k].colU == truth.nodes[k].colU);
        CHECK(fit.mesh.nodes[k].colV == truth.nodes[k].colV);
    }
    CHECK(fit.mesh.slits[0].left.colU == truth.slits[0].left.colU);
    CHECK(fit.mesh.tangents[0].colU == truth.tangents[0].colU);
    CHECK(fit.mesh.node(2, 1).col.g == Approx(truth.node(2, 1).col.g).margin(0.01));
    CHECK(fit.mesh.slits[0].below[0].col.r == Approx(truth.slits[0].below[0].col.r).margin(0.01));

    // With the slopes wrong (all 0), the values are the best they can be: no worse than the
    // sampled ones with those slopes, and worse than the full fit.
    GradientMesh flat = geometry;
    for (Node& n : flat.nodes) n.colU = n.colV = Vec3{};
    for (Node& n : flat.slits[0].below) n.colU = n.colV = Vec3{};
    const ColorResult flatFit = computeColors(flat, img, region, co);
    for (const Node& n : flatFit.mesh.nodes) CHECK((n.colU == Vec3{} && n.colV == Vec3{}));
    GradientMesh flatSampled = flat;
    sampleNodeColors(flatSampled, img, region);
    for (Node& n : flatSampled.nodes) n.colU = n.colV = Vec3{};
    for (Node& n : flatSampled.slits[0].below) n.colU = n.colV = Vec3{};
    flatSampled.slits[0].left.colU = flatSampled.slits[0].right.colU = Vec3{};
    flatSampled.tangents[0].colU = Vec3{};
    REQUIRE(flatFit.mesh.tangents[0].colU == truth.tangents[0].colU);  // held, not zeroed
    CHECK(flatFit.error.rmse < measureColorError(flatSampled, img, region).error.rmse + 1e-9);
    CHECK(flatFit.error.rmse > fit.error.rmse);
}

TEST_CASE("colours fitted to a document's samples use only the pixels where the mesh is on top",
          "[colours]") {
    // Two straight meshes: A over the whole 64x48 canvas, B over its right half, drawn on top.
    // The image is dark where A shows and bright under B: fitted to its visible pixels A is
    // dark there; fitted to all of its pixels it is a blend.
    const int W = 64, H = 48;
    auto rect = [](double x0, double y0, double x1, double y1) {
        GradientMesh m(1, 1);
        for (int j = 0; j <= 1; ++j)
            for (int i = 0; i <= 1; ++i) {
                Node& n = m.node(i, j);
                n.pos = {i ? x1 : x0, j ? y1 : y0};
                n.posU = {x1 - x0, 0};
                n.posV = {0, y1 - y0};
            }
        return m;
    };
    Document doc;
    doc.width = W;
    doc.height = H;
    doc.meshes = {rect(0, 0, W, H), rect(W / 2, 0, W, H)};
    RgbaImage img(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float* p = img.at(x, y);
            const float v = x < W / 2 ? 0.1f : 0.9f;
            p[0] = p[1] = p[2] = v;
            p[3] = 1;
        }
    const std::vector<PixelSample> samples = fitSamples(doc);
    const Region all = wholeCanvas(W, H);
    Region left = all;
    for (int y = 0; y < H; ++y)
        for (int x = W / 2; x < W; ++x) left.mask[static_cast<size_t>(y) * W + x] = 0;
    left.pixelCount = W / 2 * H;
    const GradientMesh a = fitColorsToSamples(doc.meshes[0], img, all, samples, 0);
    CHECK(a.node(0, 0).col.r == Approx(0.1).margin(0.01));
    CHECK(a.node(0, 1).col.r == Approx(0.1).margin(0.01));
    const double visibleE = measureColorError(a, img, left).error.meanAbs;
    CHECK(visibleE < 1.0);
    const GradientMesh b = fitColorsToSamples(doc.meshes[1], img, all, samples, 1);
    for (const Node& n : b.nodes) CHECK(n.col.r == Approx(0.9).margin(0.01));
    // Fitted to all of its region, A is off where it shows.
    const ColorResult own = computeColors(doc.meshes[0], img, all);
    const double ownE = measureColorError(own.mesh, img, left).error.meanAbs;
    WARN("a mesh half covered by another: E where it shows "
         << visibleE << " fitted there, " << ownE << " fitted to all its pixels");
    CHECK(ownE > 10 * visibleE + 5);
    CHECK_THROWS_AS(
        fitColorsToSamples(doc.meshes[0], img, all,
                           std::vector<PixelSample>(samples.begin(), samples.end() - 1), 0),
        Error);
}

TEST_CASE("a warm-started refit reaches the colours of a cold one", "[colours]") {
    // Fit mode's iterative solve from the colours given (a refit) and from the sampled ones
    // converge to the same least-squares colours.
    const auto s = disk();
    GridOptions go;
    go.columns = 6;
    go.rows = 6;
    const GradientMesh geometry = buildGrid(s.tri, s.map, go);
    RgbaImage img(512, 512);
    for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512; ++x) {
            const Vec3 c = smooth(x + 0.5, y + 0.5);
            float* p = img.at(x, y);
            p[0] = float(c.r), p[1] = float(c.g), p[2] = float(c.b), p[3] = 1;
        }
    const ColorResult cold = computeColors(geometry, img, s.region);
    RenderOptions ro;
    ro.wantSamples = true;
    ro.antialias = false;
    Document doc;
    doc.width = doc.height = 512;
    doc.meshes = {cold.mesh};
    const std::vector<PixelSample> samples = renderDocument(doc, ro).samples;
    ColorOptions warm;
    warm.warmStart = true;
    const GradientMesh again = fitColorsToSamples(cold.mesh, img, s.region, samples, 0, warm);
    GradientMesh perturbed = cold.mesh;
    for (Node& n : perturbed.nodes) n.col = n.col + Vec3{0.05, -0.05, 0.02};
    const GradientMesh fromOff = fitColorsToSamples(perturbed, img, s.region, samples, 0, warm);
    double worst = 0;
    for (size_t k = 0; k < cold.mesh.nodes.size(); ++k)
        for (const GradientMesh* m : {&again, &fromOff}) {
            const Vec3 d = m->nodes[k].col - cold.mesh.nodes[k].col;
            worst = std::max({worst, std::abs(d.r), std::abs(d.g), std::abs(d.b)});
        }
    CHECK(worst < 2e-3);
    CHECK(measureColorError(fromOff, img, s.region).error.meanAbs ==
          Approx(cold.error.meanAbs).margin(0.01));
}
