#include <catch2/catch.hpp>

#include <chrono>

#include "converters/feature_map.h"
#include "converters/topology_map.h"
#include "meshcore/error.h"
#include "converters/plot_uv.h"
#include "converters/test_meshes.h"

using namespace gm;
using namespace gm::test;

namespace {

// Red rises from 0 to 1 (blue falls) over `width` pixels from x = x0; green is flat.
RgbaImage rampImage(int w, int h, double x0, double width) {
    RgbaImage img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double t = std::clamp((x + 0.5 - x0) / width, 0.0, 1.0);
            float* p = img.at(x, y);
            p[0] = static_cast<float>(t);
            p[1] = 0.3f;
            p[2] = static_cast<float>(1 - t);
            p[3] = 1;
        }
    return img;
}

std::vector<double> radii(int rings, double r0, double r1) {
    std::vector<double> r;
    for (int k = 0; k < rings; ++k) r.push_back(r0 + (r1 - r0) * k / (rings - 1));
    return r;
}

// Parameter area of the triangles whose image centroid has x in [lo, hi].
double uvAreaInBand(const TriMesh& mesh, const ParamMap& map, double lo, double hi) {
    double sum = 0;
    for (const auto& t : mesh.triangles) {
        const double cx = (mesh.vertices[t[0]].x + mesh.vertices[t[1]].x + mesh.vertices[t[2]].x) / 3;
        if (cx < lo || cx > hi) continue;
        sum += 0.5 * twiceArea(map.uv[t[0]], map.uv[t[1]], map.uv[t[2]]);
    }
    return sum;
}

void requireLoopsFixed(const TriMesh& mesh, const ParamMap& before, const ParamMap& after) {
    for (int i : mesh.outerLoop) {
        REQUIRE(after.uv[i].x == before.uv[i].x);
        REQUIRE(after.uv[i].y == before.uv[i].y);
    }
    for (const auto& h : mesh.holeLoops)
        for (int i : h) {
            REQUIRE(after.uv[i].x == before.uv[i].x);
            REQUIRE(after.uv[i].y == before.uv[i].y);
        }
}

void requireDecreasing(const std::vector<double>& s) {
    for (size_t k = 1; k < s.size(); ++k) REQUIRE(s[k] < s[k - 1]);
}

}  // namespace

TEST_CASE("feature map gives a sharp colour ramp more parameter area", "[feature_map]") {
    const TriMesh mesh = ringMesh({128, 128}, radii(30, 3.5, 100), 180, false);
    const RgbaImage img = rampImage(256, 256, 124, 8);
    const ParamMap start = buildTopologyMap(mesh, 200, 200).map;
    const FeatureMap fm = buildFeatureMap(mesh, start, img);
    plotUv(mesh, start, "ramp_start");
    plotUv(mesh, fm.map, "ramp_feature");
    std::string seq;
    for (double s : fm.stretch) seq += std::to_string(s) + " ";
    INFO("ramp: stretch " << seq << "solves " << fm.solves << " stop " << static_cast<int>(fm.stop));
    REQUIRE(fm.stretch.size() >= 2);
    requireDecreasing(fm.stretch);
    REQUIRE(countFlippedTriangles(mesh, fm.map) == 0);
    requireLoopsFixed(mesh, start, fm.map);
    const double before = uvAreaInBand(mesh, start, 118, 138);
    const double after = uvAreaInBand(mesh, fm.map, 118, 138);
    INFO("ramp band parameter area " << before << " -> " << after);
    REQUIRE(after > 1.5 * before);
    // Flat colour far from the ramp gives up area.
    REQUIRE(uvAreaInBand(mesh, fm.map, 28, 90) < uvAreaInBand(mesh, start, 28, 90));
}

TEST_CASE("feature map keeps slits fixed and never folds", "[feature_map]") {
    const TriMesh mesh =
        holedDisk({{128, 128}, 100}, {{{88, 108}, 15}, {{163, 98}, 12}, {{128, 173}, 18}}, 5);
    const RgbaImage img = rampImage(256, 256, 140, 6);
    const TopologyMap tm = buildTopologyMap(mesh, 200, 200);
    const FeatureMap fm = buildFeatureMap(mesh, tm.map, img);
    plotUv(mesh, fm.map, "three_holes_feature");
    std::string seq;
    for (double s : fm.stretch) seq += std::to_string(s) + " ";
    INFO("3 holes: stretch " << seq << "solves " << fm.solves << " stop " << static_cast<int>(fm.stop));
    requireDecreasing(fm.stretch);
    REQUIRE(countFlippedTriangles(mesh, fm.map) == 0);
    requireLoopsFixed(mesh, tm.map, fm.map);
}

TEST_CASE("feature map with 21 holes: a fold freezes its neighbours too, fewer solves", "[feature_map]") {
    // Like the amulet: around each slit end (a 360° angle of the parameter domain) a
    // positive-weight solve can fold; each fold costs another factorisation. Freezing the
    // neighbours of folded triangles with them halves the count here (the amulet: 10
    // factorisations for 3 iterations before).
    std::vector<Circle> holes{{{128, 128}, 14}};
    for (int k = 0; k < 8; ++k)
        holes.push_back({{128 + 45 * std::cos(k * M_PI / 4), 128 + 45 * std::sin(k * M_PI / 4)}, 8});
    for (int k = 0; k < 12; ++k)
        holes.push_back({{128 + 85 * std::cos((k + 0.5) * M_PI / 6), 128 + 85 * std::sin((k + 0.5) * M_PI / 6)}, 6});
    const TriMesh mesh = holedDisk({{128, 128}, 110}, holes, 4);
    REQUIRE(mesh.holeLoops.size() == 21);
    const RgbaImage img = rampImage(256, 256, 140, 6);
    const TopologyMap tm = buildTopologyMap(mesh, 220, 220);
    FeatureMapOptions plain;
    plain.foldFreezeRings = 0;
    const FeatureMap before = buildFeatureMap(mesh, tm.map, img, plain);
    const FeatureMap fm = buildFeatureMap(mesh, tm.map, img);
    INFO("factorisations " << before.factorizations << " for " << before.solves
                           << " iterations freezing folds only, " << fm.factorizations << " for "
                           << fm.solves << " with; stretch " << before.stretch.back() << ", "
                           << fm.stretch.back() << " (start " << fm.stretch.front() << ")");
    REQUIRE(countFlippedTriangles(mesh, fm.map) == 0);
    requireLoopsFixed(mesh, tm.map, fm.map);
    requireDecreasing(fm.stretch);
    CHECK(fm.factorizations <= 2 * fm.solves + 1);
    CHECK(fm.factorizations < before.factorizations);
    CHECK(fm.stretch.back() < 0.95 * fm.stretch.front());
}

TEST_CASE("feature map of a flat image changes little", "[feature_map]") {
    const TriMesh mesh = squareGrid(15, 100, 0.2);
    RgbaImage img(128, 128);
    for (size_t k = 0; k < img.pixels.size(); ++k) img.pixels[k] = 0.5f;
    const ParamMap start = buildTopologyMap(mesh, 100, 100).map;
    const FeatureMap fm = buildFeatureMap(mesh, start, img);
    // The map is already the image (up to scale): stretch is 1 and nothing improves on it.
    REQUIRE(fm.stretch.front() == Approx(1).epsilon(1e-9));
    REQUIRE(fm.stretch.back() == Approx(1).epsilon(1e-9));
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        REQUIRE(fm.map.uv[i].x == Approx(start.uv[i].x).margin(1e-6));
        REQUIRE(fm.map.uv[i].y == Approx(start.uv[i].y).margin(1e-6));
    }
}

TEST_CASE("feature coordinates carry the weighted image gradient", "[feature_map]") {
    TriMesh mesh = squareGrid(5, 200, 0);
    for (Vec2& v : mesh.vertices) v = v + Vec2{20, 20};  // away from the image border
    const RgbaImage img = rampImage(256, 256, 0, 256);  // red gradient 1/256 per pixel everywhere
    const auto f = featureCoordinates(mesh, img, 300, 1.0);
    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        REQUIRE(f[i][0] == mesh.vertices[i].x);
        REQUIRE(f[i][1] == mesh.vertices[i].y);
        REQUIRE(f[i][2] == Approx(300.0 / 256).epsilon(1e-6));   // w·∂r/∂x
        REQUIRE(f[i][4] == Approx(-300.0 / 256).epsilon(1e-6));  // w·∂b/∂x
        REQUIRE(f[i][5] == Approx(0).margin(1e-9));              // w·∂r/∂y
    }
}

TEST_CASE("with a mask, the region's outline against the background is no feature", "[feature_map]") {
    // A grey square on white: without the mask the vertices along its edge see the step to the
    // background; with the square as the mask they see none.
    TriMesh mesh = squareGrid(4, 100, 0);
    for (Vec2& v : mesh.vertices) v = v + Vec2{30, 30};
    RgbaImage img(160, 160);
    std::vector<uint8_t> mask(160 * 160, 0);
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x) {
            const bool in = x >= 30 && x < 130 && y >= 30 && y < 130;
            float* p = img.at(x, y);
            p[0] = p[1] = p[2] = in ? 0.3f : 1.0f;
            p[3] = 1;
            mask[static_cast<size_t>(y) * 160 + x] = in;
        }
    const auto plain = featureCoordinates(mesh, img, 300, 1.0);
    const auto masked = featureCoordinates(mesh, img, 300, 1.0, &mask);
    double plainMax = 0, maskedMax = 0;
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int c = 2; c < 8; ++c) {
            plainMax = std::max(plainMax, std::abs(plain[i][c]));
            maskedMax = std::max(maskedMax, std::abs(masked[i][c]));
        }
    INFO("largest feature coordinate without the mask " << plainMax << ", with " << maskedMax);
    CHECK(plainMax > 10);
    CHECK(maskedMax < 1e-6);
    const std::vector<uint8_t> wrong(10, 1);
    CHECK_THROWS_AS(featureCoordinates(mesh, img, 300, 1.0, &wrong), Error);
}

TEST_CASE("feature map rejects a folded or mismatched initial map", "[feature_map]") {
    const TriMesh mesh = squareGrid(6, 50, 0.1);
    const RgbaImage img = rampImage(64, 64, 20, 5);
    ParamMap map = buildTopologyMap(mesh, 50, 50).map;
    ParamMap shorter = map;
    shorter.uv.pop_back();
    REQUIRE_THROWS_AS(buildFeatureMap(mesh, shorter, img), Error);
    std::swap(map.uv[7], map.uv[8]);  // two interior neighbours exchanged: folds
    REQUIRE_THROWS_AS(buildFeatureMap(mesh, map, img), Error);
}

TEST_CASE("feature map timings", "[.][timing][feature_map]") {
    using Clock = std::chrono::steady_clock;
    for (const int target : {20000, 100000}) {
        const int count = static_cast<int>(std::sqrt(target * 2.0));
        const double radius = std::sqrt(target * 10 / kPi);  // 10 % of the region's pixels
        const TriMesh mesh = ringMesh({radius + 8, radius + 8}, radii(target / count, radius / (target / count), radius), count, false);
        const int size = static_cast<int>(2 * radius + 16);
        RgbaImage img = rampImage(size, size, radius, 10);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x)
                img.at(x, y)[1] = static_cast<float>(0.5 + 0.5 * std::sin(x * 0.02) * std::cos(y * 0.03));
        const ParamMap start = buildTopologyMap(mesh, 2 * radius, 2 * radius).map;
        const auto t0 = Clock::now();
        const FeatureMap fm = buildFeatureMap(mesh, start, img);
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        REQUIRE(countFlippedTriangles(mesh, fm.map) == 0);
        WARN("feature map, " << mesh.vertices.size() << " vertices: " << ms << " ms, "
                             << fm.solves << " solves, stretch " << fm.stretch.front() << " -> "
                             << fm.stretch.back());
    }
}
