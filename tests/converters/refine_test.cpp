#include "converters/refine.h"

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <ctime>
#include <sstream>

#include "converters/colors.h"
#include "converters/grid.h"
#include "meshcore/validate.h"
#include "synthetic_region.h"

using namespace gm;

namespace {

const double kP = 400;

gmtest::Synthetic disk() {
    return gmtest::makeSynthetic(kP, kP, 48, 48, gmtest::diskMap(kP, 256, 256, 200), 512, 512);
}

Vec3 smooth(double x, double y) {
    return {0.5 + 0.4 * std::sin(x / 45.0) * std::cos(y / 60.0),
            0.5 + 0.35 * std::cos((x + y) / 70.0), 0.45 + 0.4 * std::sin(y / 38.0)};
}

void checkSequence(const RefineResult& r, const RefineOptions& o) {
    REQUIRE(!r.steps.empty());
    CHECK(r.steps.front().axis == 0);
    for (size_t k = 1; k < r.steps.size(); ++k) {
        CHECK(r.steps[k].meanAbs <= r.steps[k - 1].meanAbs);
        CHECK(r.steps[k].patches > r.steps[k - 1].patches);
        CHECK((r.steps[k].axis == 'u' || r.steps[k].axis == 'v'));
    }
    CHECK(r.steps.back().patches == r.mesh.patchCount());
    CHECK(r.steps.back().meanAbs == r.error.meanAbs);
    CHECK(r.mesh.patchCount() <= o.maxPatches);
    CHECK(validateMesh(r.mesh).empty());
}

}  // namespace

TEST_CASE("refinement never increases E and records the sequence", "[refine]") {
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, smooth);
    GridOptions go;
    go.columns = go.rows = 2;
    for (ColorMode mode : {ColorMode::Sampled, ColorMode::Fit}) {
        RefineOptions ro;
        ro.maxError = 0.1;  // out of reach: the budget ends it
        ro.maxPatches = 30;
        ro.color.mode = mode;
        ro.candidates = mode == ColorMode::Fit ? 2 : 1;
        const RefineResult r = refineMesh(s.tri, s.map, go, img, s.region, ro);
        checkSequence(r, ro);
        CHECK(r.steps.size() >= 3);
        CHECK(!r.reachedTarget);
        WARN((mode == ColorMode::Fit ? "fit" : "sampled")
             << ": E " << r.steps.front().meanAbs << " at " << r.steps.front().patches
             << " patches -> " << r.error.meanAbs << " at " << r.mesh.patchCount() << " in "
             << r.steps.size() - 1 << " splits");
    }
}

TEST_CASE("refinement stops at the target error when the budget allows", "[refine]") {
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, smooth);
    GridOptions go;
    go.columns = go.rows = 2;
    RefineOptions ro;
    ro.maxError = 1.0;
    ro.maxPatches = 400;
    const RefineResult r = refineMesh(s.tri, s.map, go, img, s.region, ro);
    checkSequence(r, ro);
    CHECK(r.reachedTarget);
    CHECK(r.error.meanAbs <= 1.0);
    // It stopped as soon as it got there.
    REQUIRE(r.steps.size() >= 2);
    CHECK(r.steps[r.steps.size() - 2].meanAbs > 1.0);
    WARN("target E 1.0: reached " << r.error.meanAbs << " with " << r.mesh.columns() << "x"
                                  << r.mesh.rows() << " patches");
}

TEST_CASE("a batch that overshoots the target is cut to what the target needs", "[refine]") {
    // Busier colours than `smooth`: late batches add tens of knots at once.
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, [](double x, double y) {
        return Vec3{0.5 + 0.4 * std::sin(x / 17.0) * std::cos(y / 23.0),
                    0.5 + 0.35 * std::cos((x + 2 * y) / 29.0), 0.45 + 0.4 * std::sin(y / 13.0)};
    });
    GridOptions go;
    go.columns = go.rows = 2;
    int fewer = 0;
    for (double target : {1.0, 2.0, 3.0, 5.0}) {
        RefineOptions ro;
        ro.maxError = target;
        ro.maxPatches = 2000;
        ro.trimSteps = 0;
        const RefineResult whole = refineMesh(s.tri, s.map, go, img, s.region, ro);
        ro.trimSteps = 4;
        const RefineResult cut = refineMesh(s.tri, s.map, go, img, s.region, ro);
        checkSequence(cut, ro);
        REQUIRE(whole.reachedTarget);
        CHECK(cut.reachedTarget);
        CHECK(cut.mesh.patchCount() <= whole.mesh.patchCount());
        if (cut.mesh.patchCount() < whole.mesh.patchCount()) ++fewer;
        WARN("target " << target << ": whole batches " << whole.mesh.patchCount()
                       << " patches (E " << whole.error.meanAbs << "), cut "
                       << cut.mesh.patchCount() << " (E " << cut.error.meanAbs << ")");
    }
    CHECK(fewer >= 2);
}

TEST_CASE("a colour step inside the region is refined near the step", "[refine]") {
    // Identity map on a 240 x 120 rectangle: u = x - 8, v = y - 4. A vertical colour edge
    // (blurred over about a pixel) at x = 151.3, i.e. u = 143.3.
    const double stepU = 143.3;
    const auto s = gmtest::makeSynthetic(
        240, 120, 24, 12,
        [](double u, double v) {
            return Vec2{8 + u, 4 + v};
        },
        256, 128);
    const RgbaImage img = gmtest::paint(256, 128, [&](double x, double y) {
        const double a = 1 / (1 + std::exp(-(x - 8 - stepU) / 0.5));
        return Vec3{0.2 + 0.6 * a, 0.7 - 0.5 * a, 0.3 + 0.001 * y};
    });
    GridOptions go;
    go.columns = 2;
    go.rows = 1;
    RefineOptions ro;
    ro.maxError = 0.2;
    ro.maxPatches = 12;
    const RefineResult r = refineMesh(s.tri, s.map, go, img, s.region, ro);
    checkSequence(r, ro);
    int nearStep = 0, along = 0;
    double closest = 1e9;
    std::ostringstream knots;
    for (const RefineStep& st : r.steps)
        for (const auto& [axis, knot] : st.splits) {
            knots << axis << "=" << knot << " ";
            if (axis != 'u') continue;
            ++along;
            closest = std::min(closest, std::abs(knot - stepU));
            if (std::abs(knot - stepU) < 30) ++nearStep;
        }
    WARN("step at u = " << stepU << ": inserted " << knots.str() << "; E " << r.error.meanAbs);
    CHECK(along >= 3);
    CHECK(nearStep * 2 > along);  // most splits go to the step
    CHECK(closest < 3);
}

TEST_CASE("stage timings on a 512x512 disk", "[refine][timing][.]") {
    using Clock = std::chrono::steady_clock;
    auto ms = [](Clock::time_point a) {
        return std::chrono::duration<double, std::milli>(Clock::now() - a).count();
    };
    const auto s = disk();
    const RgbaImage img = gmtest::paint(512, 512, smooth);
    auto t = Clock::now();
    const GridBuilder builder(s.tri, s.map);
    const double tLocator = ms(t);
    GridOptions go;
    go.columns = go.rows = 18;
    t = Clock::now();
    const GradientMesh geo = builder.build(go);
    const double tGrid = ms(t);
    ColorOptions co;
    co.mode = ColorMode::Sampled;
    t = Clock::now();
    const ColorResult sampled = computeColors(geo, img, s.region, co);
    const double tSampled = ms(t);
    co.mode = ColorMode::Fit;
    t = Clock::now();
    const ColorResult fit = computeColors(geo, img, s.region, co);
    const double tFit = ms(t);
    t = Clock::now();
    const ColorResult measured = measureColorError(fit.mesh, img, s.region);
    const double tMeasure = ms(t);
    RefineOptions ro;
    ro.maxError = 0.0;
    ro.maxPatches = 300;
    GridOptions start;
    start.columns = start.rows = 4;
    t = Clock::now();
    const std::clock_t cpu0 = std::clock();
    const RefineResult r = refineMesh(builder, start, img, s.region, ro);
    const double tRefine = ms(t);
    const double cpuRefine = 1000.0 * (std::clock() - cpu0) / CLOCKS_PER_SEC;
    WARN("512x512 disk, " << geo.patchCount() << " patches, " << s.tri.triangles.size()
                          << " triangles: locator " << tLocator << " ms, grid " << tGrid
                          << " ms, colours sampled " << tSampled << " ms (E "
                          << sampled.error.meanAbs << "), fit " << tFit << " ms (E "
                          << fit.error.meanAbs << "), measure " << tMeasure << " ms");
    WARN("refine 4x4 -> " << r.mesh.columns() << "x" << r.mesh.rows() << " (" << r.mesh.patchCount()
                          << " patches) in " << r.steps.size() - 1 << " splits: " << tRefine
                          << " ms (CPU " << cpuRefine << " ms), E " << r.steps.front().meanAbs
                          << " -> " << r.error.meanAbs);
    CHECK(measured.error.meanAbs == Approx(fit.error.meanAbs).margin(1e-6));
}
