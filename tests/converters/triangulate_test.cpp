#include <catch2/catch.hpp>

#include <chrono>
#include <map>
#include <set>
#include <sstream>

#include "converters/corners.h"
#include "converters/regions.h"
#include "converters/triangulate.h"
#include "meshcore/error.h"
#include "shapes.h"

using namespace gm;

namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Checks every property triangulateRegion promises.
void checkTriMesh(const TriMesh& m, const Region& region) {
    const int nv = static_cast<int>(m.vertices.size());
    // Positive triangles, valid indices.
    int nonPositive = 0;
    for (const auto& t : m.triangles) {
        for (int v : t) REQUIRE((v >= 0 && v < nv));
        const Vec2 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
        nonPositive += !((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0);
    }
    CHECK(nonPositive == 0);

    // Loops: every loop vertex once; outer loop starts at corner 0, corners increase.
    std::vector<int> loopCount(nv, 0);
    for (int v : m.outerLoop) ++loopCount[v];
    for (const auto& loop : m.holeLoops)
        for (int v : loop) ++loopCount[v];
    for (int c : loopCount) REQUIRE(c <= 1);
    CHECK(m.corner[0] == 0);
    CHECK(m.corner[0] < m.corner[1]);
    CHECK(m.corner[1] < m.corner[2]);
    CHECK(m.corner[2] < m.corner[3]);
    CHECK(m.corner[3] < static_cast<int>(m.outerLoop.size()));
    CHECK(m.holeLoops.size() == region.holes.size());

    // Directed edges: each loop edge bounds exactly one triangle, on the region's side, and the
    // mesh boundary is exactly the loops.
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : m.triangles)
        for (int i = 0; i < 3; ++i) ++directed[{t[i], t[(i + 1) % 3]}];
    int boundaryEdges = 0;
    for (const auto& [e, count] : directed) {
        REQUIRE(count == 1);  // manifold and consistently oriented
        boundaryEdges += directed.count({e.second, e.first}) == 0;
    }
    int loopEdges = 0;
    auto checkLoop = [&](const std::vector<int>& loop) {
        for (size_t k = 0; k < loop.size(); ++k) {
            const std::pair<int, int> e{loop[k], loop[(k + 1) % loop.size()]};
            CHECK(directed.count(e) == 1);
            CHECK(directed.count({e.second, e.first}) == 0);
            ++loopEdges;
        }
    };
    checkLoop(m.outerLoop);
    for (const auto& loop : m.holeLoops) checkLoop(loop);
    CHECK(boundaryEdges == loopEdges);

    // Euler characteristic of a disk with holes.
    const int edges = static_cast<int>(directed.size()) - (static_cast<int>(directed.size()) - boundaryEdges) / 2;
    std::set<int> used;
    for (const auto& t : m.triangles) used.insert(t.begin(), t.end());
    CHECK(static_cast<int>(used.size()) == nv);
    CHECK(nv - edges + static_cast<int>(m.triangles.size()) ==
          1 - static_cast<int>(m.holeLoops.size()));

    // Nothing that maps to zero area: no triangle on one side or one hole, no chord.
    const int n = static_cast<int>(m.outerLoop.size());
    std::vector<unsigned> sides(nv, 0);
    std::vector<int> hole(nv, -1);
    for (int c = 0; c < 4; ++c) {
        const int to = c == 3 ? n : m.corner[c + 1];
        for (int k = m.corner[c]; k <= to; ++k) sides[m.outerLoop[k % n]] |= 1u << c;
    }
    for (size_t h = 0; h < m.holeLoops.size(); ++h)
        for (int v : m.holeLoops[h]) hole[v] = static_cast<int>(h);
    int flat = 0, chords = 0;
    for (const auto& t : m.triangles) {
        const int a = t[0], b = t[1], c = t[2];
        flat += (sides[a] & sides[b] & sides[c]) != 0 ||
                (hole[a] >= 0 && hole[a] == hole[b] && hole[a] == hole[c]);
    }
    for (const auto& [e, count] : directed) {
        if (directed.count({e.second, e.first}) == 0) continue;  // a loop edge
        const int u = e.first, v = e.second;
        chords += (sides[u] & sides[v]) != 0 || (hole[u] >= 0 && hole[u] == hole[v]);
    }
    CHECK(flat == 0);
    CHECK(chords == 0);
}

}  // namespace

TEST_CASE("an annulus triangulates with intact loops and the right topology", "[triangulate]") {
    const int w = 256, h = 256;
    const auto bits = test::rasterize(w, h, [](double x, double y) {
        return test::inDisk(x, y, 128, 128, 100) && !test::inDisk(x, y, 128, 128, 40);
    });
    const Region region = extractRegions(coverageFromBits(w, h, bits)).at(0);
    const RegionCorners corners = findCorners(region);
    const RgbaImage image = test::gradientImage(w, h);
    for (double fraction : {0.02, 0.05, 0.1}) {
        INFO("sample fraction " << fraction);
        TriangulateOptions opts;
        opts.sampleFraction = fraction;
        TriangulateStats stats;
        const TriMesh m = triangulateRegion(image, region, corners, opts, &stats);
        checkTriMesh(m, region);
        const double target = fraction * region.pixelCount;
        // Samples keep off a band along the loops, so a little under the fraction.
        CHECK(stats.samplesKept == stats.samplesPlaced);
        CHECK(stats.samplesKept > 0.8 * target);
        CHECK(stats.samplesKept < 1.02 * target);
        // The outer loop is the region's loop from its top-left corner on.
        CHECK(m.vertices[m.outerLoop[0]] == region.outer.points[corners.index[0]]);
        CHECK(m.vertices[m.outerLoop[m.corner[2]]] == region.outer.points[corners.index[2]]);
    }
}

TEST_CASE("thin, pinched and holed regions triangulate without flat triangles", "[triangulate]") {
    const int w = 120, h = 120;
    const auto bits = test::rasterize(w, h, [](double x, double y) {
        const bool squares = (x > 10 && x < 40 && y > 10 && y < 40) || (x > 40 && x < 70 && y > 40 && y < 70);
        const bool bar = x > 70 && x < 110 && y > 40 && y < 43;  // 3 pixels thin
        const bool ring = test::inDisk(x, y, 85, 90, 25) && !test::inDisk(x, y, 85, 90, 4) &&
                          !test::inDisk(x, y, 95, 100, 5);
        return squares || bar || ring;
    });
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    REQUIRE(regions.size() == 1);
    const RgbaImage image = test::gradientImage(w, h);
    for (double fraction : {0.02, 0.1, 0.5}) {
        INFO("sample fraction " << fraction);
        TriangulateOptions opts;
        opts.sampleFraction = fraction;
        const TriMesh m = triangulateRegion(image, regions[0], findCorners(regions[0]), opts);
        checkTriMesh(m, regions[0]);
    }
}

TEST_CASE("a one-pixel region triangulates into a tiny valid mesh", "[triangulate]") {
    std::vector<uint8_t> bits(100, 0);
    bits[5 * 10 + 5] = 1;
    RegionOptions ropts;
    ropts.minArea = 1;
    const Region region = extractRegions(coverageFromBits(10, 10, bits), ropts).at(0);
    const TriMesh m = triangulateRegion(RgbaImage(10, 10), region, findCorners(region));
    checkTriMesh(m, region);
    CHECK(m.outerLoop.size() == 4);
}

TEST_CASE("an image of the wrong size is reported", "[triangulate]") {
    const auto bits = test::rasterize(50, 50, [](double x, double y) { return test::inDisk(x, y, 25, 25, 15); });
    const Region region = extractRegions(coverageFromBits(50, 50, bits)).at(0);
    CHECK_THROWS_AS(triangulateRegion(RgbaImage(40, 50), region, findCorners(region)), Error);
}

TEST_CASE("salient pixels get denser samples", "[triangulate]") {
    const int w = 100, h = 100;
    const auto bits = test::rasterize(w, h, [](double, double) { return true; });
    const Region region = extractRegions(coverageFromBits(w, h, bits)).at(0);
    RgbaImage image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = image.at(x, y);
            p[0] = p[1] = p[2] = (x / 2 + y / 2) % 2 && x > 50 ? 1.f : 0.f;  // texture on the right
            p[3] = 1;
        }
    const auto saliency = compassSaliency(image, region);
    TriangulateOptions opts;
    opts.sampleFraction = 0.05;
    int left = 0, right = 0;
    for (const Vec2 s : placeSamples(region, saliency, opts)) (s.x < 50 ? left : right)++;
    CHECK(right > 2 * left);
    CHECK(left > 0);
}

TEST_CASE("stage times for a 512x512 disk", "[regions][corners][triangulate][timing]") {
    const int w = 512, h = 512;
    const auto bits = test::rasterize(w, h, [](double x, double y) { return test::inDisk(x, y, 256, 256, 200); });
    const RgbaImage image = test::gradientImage(w, h);
    auto t0 = std::chrono::steady_clock::now();
    const auto regions = extractRegions(coverageFromBits(w, h, bits));
    const double regionsMs = msSince(t0);
    REQUIRE(regions.size() == 1);
    t0 = std::chrono::steady_clock::now();
    const RegionCorners corners = findCorners(regions[0]);
    const double cornersMs = msSince(t0);
    std::ostringstream out;
    out << "512x512 disk, r = 200, " << regions[0].pixelCount << " pixels, outer loop "
        << regions[0].outer.points.size() << " points: regions " << regionsMs << " ms, corners "
        << cornersMs << " ms";
    for (double fraction : {0.01, 0.02, 0.05, 0.1}) {
        TriangulateOptions opts;
        opts.sampleFraction = fraction;
        TriangulateStats stats;
        t0 = std::chrono::steady_clock::now();
        const TriMesh m = triangulateRegion(image, regions[0], corners, opts, &stats);
        const double triMs = msSince(t0);
        out << "\n  triangulate at " << fraction * 100 << "%: " << triMs << " ms, "
            << m.vertices.size() << " vertices (" << stats.samplesKept << " samples kept of "
            << stats.samplesPlaced << ", " << stats.loopVertices << " on loops, "
            << stats.steinerPoints << " Steiner), " << m.triangles.size() << " triangles";
        checkTriMesh(m, regions[0]);
    }
    WARN(out.str());
}
