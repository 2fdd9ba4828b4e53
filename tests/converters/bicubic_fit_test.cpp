// The bicubic colour fit's pull across patch edges shorter than a pixel (bicubic_fit.h).
#include <catch2/catch.hpp>
#include <cmath>

#include "converters/colors.h"
#include "fit_inputs.h"

using namespace gm;

namespace {

// One row of straight patches with node columns at `xs`, `height` px tall. Each node's u
// tangent is the narrower of its two columns, so that no patch folds.
GradientMesh columnsAt(const std::vector<double>& xs, double height) {
    const int C = static_cast<int>(xs.size()) - 1;
    GradientMesh m(C, 1);
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= C; ++i) {
            const double left = i > 0 ? xs[i] - xs[i - 1] : xs[1] - xs[0];
            const double right = i < C ? xs[i + 1] - xs[i] : left;
            Node& n = m.node(i, j);
            n.pos = {xs[static_cast<size_t>(i)], j * height};
            n.posU = {std::min(left, right), 0};
            n.posV = {0, height};
        }
    return m;
}

}  // namespace

TEST_CASE("a colour step inside a sub-pixel column of patches is pulled flat", "[colours]") {
    // Dark up to x = 10, bright from x = 11, the pixel between a half blend: a region's
    // anti-aliased border. The mesh's middle column, 0.4 px wide, holds that pixel's centre.
    // Fitted to the pixels alone its two node columns would take the whole step across 0.4 px,
    // which a renderer sampling a pixel off its centre draws anywhere between dark and bright.
    const int W = 21, H = 8;
    const GradientMesh geometry = columnsAt({0, 10.3, 10.7, 21}, H);
    RgbaImage img(W, H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float* p = img.at(x, y);
            p[0] = p[1] = p[2] = x < 10 ? 0.1f : x > 10 ? 0.9f : 0.5f;
            p[3] = 1;
        }
    Document doc;
    doc.width = W;
    doc.height = H;
    doc.meshes = {geometry};
    const std::vector<PixelSample> samples = fitSamples(doc);
    const Region all = wholeCanvas(W, H);
    ColorOptions co;
    co.mode = ColorMode::FitBicubic;
    auto stepAcross = [&](double pull) {
        co.subPixelEdgePull = pull;
        const GradientMesh fit = fitColorsToSamples(geometry, img, all, samples, 0, co);
        REQUIRE(fit.colorModel == ColorModel::Bicubic);
        // The far columns fit their flat sides either way.
        CHECK(fit.node(0, 0).col.r == Approx(0.1).margin(0.05));
        CHECK(fit.node(3, 0).col.r == Approx(0.9).margin(0.05));
        return std::fabs(fit.node(2, 0).col.r - fit.node(1, 0).col.r);
    };
    const double free = stepAcross(0), pulled = stepAcross(0.5);
    WARN("colour step across the 0.4 px column: " << free << " free, " << pulled << " pulled");
    CHECK(free > 0.6);
    CHECK(pulled < 0.4);
}
