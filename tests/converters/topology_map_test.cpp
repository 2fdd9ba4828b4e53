#include <catch2/catch.hpp>

#include <chrono>
#include <map>
#include <set>

#include "converters/topology_map.h"
#include "meshcore/error.h"
#include "converters/plot_uv.h"
#include "converters/test_meshes.h"

using namespace gm;
using namespace gm::test;

namespace {

std::vector<double> uniformRadii(int rings, double r0, double r1) {
    std::vector<double> r;
    for (int k = 0; k < rings; ++k) r.push_back(r0 + (r1 - r0) * k / (rings - 1));
    return r;
}

// Radii r0·e^(k·step·√3/2): rings as far apart as their points, so the zipped triangles are
// close to equilateral (Delaunay) at every radius.
std::vector<double> logRadii(int rings, int count, double r0) {
    std::vector<double> r;
    for (int k = 0; k < rings; ++k) r.push_back(r0 * std::exp(2 * kPi / count * std::sqrt(3.0) / 2 * k));
    return r;
}

TriMesh disk(int rings, int count, double radius = 100) {
    return ringMesh({128, 128}, uniformRadii(rings, radius / rings, radius), count, false);
}

void requireOnRectangle(const TriMesh& mesh, const ParamMap& map) {
    const Vec2 corners[4] = {{0, 0}, {map.px, 0}, {map.px, map.py}, {0, map.py}};
    for (int k = 0; k < 4; ++k) {
        const Vec2 p = map.uv[mesh.outerLoop[mesh.corner[k]]];
        REQUIRE(p.x == Approx(corners[k].x).margin(1e-12));
        REQUIRE(p.y == Approx(corners[k].y).margin(1e-12));
    }
    for (int i : mesh.outerLoop) {
        const Vec2 p = map.uv[i];
        const bool onSide = std::abs(p.x) < 1e-9 || std::abs(p.y) < 1e-9 ||
                            std::abs(p.x - map.px) < 1e-9 || std::abs(p.y - map.py) < 1e-9;
        REQUIRE(onSide);
    }
}

// Each slit's arcs cover its hole loop, run from u0 to u1 with u increasing, lie on v, and the
// triangles along the upper arc lie above it (smaller v), those along the lower arc below.
void requireSlitConsistent(const TriMesh& mesh, const ParamMap& map, const SlitInfo& s,
                           const std::vector<int>& loop) {
    REQUIRE(s.u0 > 0);
    REQUIRE(s.u1 < map.px);
    REQUIRE(s.u0 < s.u1);
    REQUIRE(s.v > 0);
    REQUIRE(s.v < map.py);
    for (int i : loop) REQUIRE(map.uv[i].y == s.v);
    REQUIRE(s.upperArc.front() == s.lowerArc.front());
    REQUIRE(s.upperArc.back() == s.lowerArc.back());
    REQUIRE(s.upperArc.size() + s.lowerArc.size() == loop.size() + 2);
    std::set<int> covered(s.upperArc.begin(), s.upperArc.end());
    covered.insert(s.lowerArc.begin(), s.lowerArc.end());
    REQUIRE(covered == std::set<int>(loop.begin(), loop.end()));
    for (const auto* arc : {&s.upperArc, &s.lowerArc}) {
        REQUIRE(map.uv[arc->front()].x == s.u0);
        REQUIRE(map.uv[arc->back()].x == s.u1);
        for (size_t k = 1; k < arc->size(); ++k) REQUIRE(map.uv[(*arc)[k]].x > map.uv[(*arc)[k - 1]].x);
    }
    std::set<std::pair<int, int>> upper, lower;
    for (size_t k = 1; k < s.upperArc.size(); ++k) upper.insert(std::minmax(s.upperArc[k - 1], s.upperArc[k]));
    for (size_t k = 1; k < s.lowerArc.size(); ++k) lower.insert(std::minmax(s.lowerArc[k - 1], s.lowerArc[k]));
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const auto e = std::minmax(t[k], t[(k + 1) % 3]);
            const double third = map.uv[t[(k + 2) % 3]].y;
            if (upper.count(e)) REQUIRE(third < s.v);
            if (lower.count(e)) REQUIRE(third > s.v);
        }
}

}  // namespace

TEST_CASE("a disk maps without flips, corners on the rectangle's corners", "[topology_map]") {
    const TriMesh mesh = disk(12, 64);
    const TopologyMap tm = buildTopologyMap(mesh, 300, 200);
    plotUv(mesh, tm.map, "disk_mean_value");
    CHECK(tm.slits.empty());
    REQUIRE(tm.map.uv.size() == mesh.vertices.size());
    REQUIRE(countFlippedTriangles(mesh, tm.map) == 0);
    requireOnRectangle(mesh, tm.map);
    for (const Vec2& p : tm.map.uv) {
        REQUIRE(p.x >= 0);
        REQUIRE(p.x <= 300);
        REQUIRE(p.y >= 0);
        REQUIRE(p.y <= 200);
    }
}

TEST_CASE("a non-convex blob maps without flips", "[topology_map]") {
    const TriMesh mesh = ringMesh({128, 128}, uniformRadii(16, 6, 100), 96, false,
                                  [](double a) { return 1 + 0.4 * std::cos(3 * a + 0.3); });
    const TopologyMap mv = buildTopologyMap(mesh, 250, 180);
    plotUv(mesh, mv.map, "blob_mean_value");
    REQUIRE(countFlippedTriangles(mesh, mv.map) == 0);
    requireOnRectangle(mesh, mv.map);
}

TEST_CASE("the boundary lies on the rectangle's sides by arc length", "[topology_map]") {
    // A star-shaped outline, so sides are curved and their vertices unevenly spaced.
    const TriMesh mesh = ringMesh({128, 128}, uniformRadii(8, 10, 90), 80, false,
                                  [](double a) { return 1 + 0.25 * std::sin(2 * a); });
    const double px = 170, py = 90;
    const ParamMap map = buildTopologyMap(mesh, px, py).map;
    const int n = static_cast<int>(mesh.outerLoop.size());
    for (int s = 0; s < 4; ++s) {
        const int begin = mesh.corner[s], end = s == 3 ? n : mesh.corner[s + 1];
        double total = 0;
        for (int k = begin; k < end; ++k)
            total += norm(mesh.vertices[mesh.outerLoop[(k + 1) % n]] - mesh.vertices[mesh.outerLoop[k]]);
        double run = 0;
        for (int k = begin; k <= end; ++k) {
            if (k > begin)
                run += norm(mesh.vertices[mesh.outerLoop[k % n]] - mesh.vertices[mesh.outerLoop[k - 1]]);
            const double f = run / total;
            const Vec2 expected = s == 0 ? Vec2{px * f, 0}
                                  : s == 1 ? Vec2{px, py * f}
                                  : s == 2 ? Vec2{px * (1 - f), py}
                                           : Vec2{0, py * (1 - f)};
            const Vec2 got = map.uv[mesh.outerLoop[k % n]];
            REQUIRE(got.x == Approx(expected.x).margin(1e-9));
            REQUIRE(got.y == Approx(expected.y).margin(1e-9));
        }
    }
}

TEST_CASE("mean-value and slit maps reproduce an affine map of a square", "[topology_map]") {
    const double px = 230, py = 40;
    for (const bool slitMap : {false, true}) {
        CAPTURE(slitMap);
        // Jitter would make some cotangent weights negative, and clamping them breaks the
        // reproduction; mean-value weights reproduce affine maps of any triangulation.
        const TriMesh mesh = squareGrid(21, 100, slitMap ? 0.0 : 0.25);
        const TopologyMap tm = slitMap ? buildSlitMap(mesh, px, py) : buildTopologyMap(mesh, px, py);
        CHECK_FALSE(tm.stats.repaired);
        for (size_t i = 0; i < mesh.vertices.size(); ++i) {
            REQUIRE(tm.map.uv[i].x == Approx(mesh.vertices[i].x * px / 100).margin(1e-9));
            REQUIRE(tm.map.uv[i].y == Approx(mesh.vertices[i].y * py / 100).margin(1e-9));
        }
    }
}

TEST_CASE("an annulus maps to a rectangle with one slit", "[topology_map]") {
    const int count = 96;
    const TriMesh mesh = ringMesh({128, 128}, logRadii(14, count, 25), count, true);
    const TopologyMap tm = buildTopologyMap(mesh, 200, 150);
    plotUv(mesh, tm.map, "annulus_slit");
    INFO("clamped " << tm.stats.clampedWeights << ", flips before repair "
                    << tm.stats.flipsBeforeRepair << ", untangled " << tm.stats.untangledVertices);
    REQUIRE(countFlippedTriangles(mesh, tm.map) == 0);
    requireOnRectangle(mesh, tm.map);
    REQUIRE(tm.slits.size() == 1);
    requireSlitConsistent(mesh, tm.map, tm.slits[0], mesh.holeLoops[0]);
    // A centred round hole in a symmetric region: its slit is centred too.
    CHECK(tm.slits[0].v == Approx(75).margin(1.5));
    CHECK(tm.slits[0].u0 + tm.slits[0].u1 == Approx(200).margin(3));
}

TEST_CASE("an off-centre hole maps to a slit without flips", "[topology_map]") {
    const TriMesh mesh = holedDisk({{100, 100}, 80}, {{{130, 80}, 20}}, 5);
    const TopologyMap tm = buildTopologyMap(mesh, 160, 160);
    plotUv(mesh, tm.map, "offcentre_slit");
    INFO("clamped " << tm.stats.clampedWeights << ", flips before repair "
                    << tm.stats.flipsBeforeRepair << ", untangled " << tm.stats.untangledVertices);
    REQUIRE(countFlippedTriangles(mesh, tm.map) == 0);
    requireOnRectangle(mesh, tm.map);
    REQUIRE(tm.slits.size() == 1);
    requireSlitConsistent(mesh, tm.map, tm.slits[0], mesh.holeLoops[0]);
}

TEST_CASE("a disk with three holes maps to three disjoint slits", "[topology_map]") {
    const TriMesh mesh =
        holedDisk({{128, 128}, 100}, {{{88, 108}, 15}, {{163, 98}, 12}, {{128, 173}, 18}}, 4.5);
    INFO("3 holes: " << mesh.vertices.size() << " vertices, " << mesh.triangles.size()
                     << " triangles");
    const TopologyMap tm = buildTopologyMap(mesh, 200, 200);
    plotUv(mesh, tm.map, "three_holes");
    INFO("3 holes: clamped weights " << tm.stats.clampedWeights << ", flips before repair "
                                     << tm.stats.flipsBeforeRepair << ", untangled vertices "
                                     << tm.stats.untangledVertices);
    REQUIRE(countFlippedTriangles(mesh, tm.map) == 0);
    requireOnRectangle(mesh, tm.map);
    REQUIRE(tm.slits.size() == 3);
    for (int h = 0; h < 3; ++h) requireSlitConsistent(mesh, tm.map, tm.slits[h], mesh.holeLoops[h]);
    for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) {
            const SlitInfo &s = tm.slits[a], &t = tm.slits[b];
            REQUIRE((s.v != t.v || s.u1 < t.u0 || t.u1 < s.u0));
        }
    // The holes' vertical order survives: hole 1 (highest) above hole 0 above hole 2.
    CHECK(tm.slits[1].v < tm.slits[0].v);
    CHECK(tm.slits[0].v < tm.slits[2].v);
}

TEST_CASE("an edge joining two vertices of one side is rejected", "[topology_map]") {
    TriMesh mesh;
    // Top side TL, M, TR bulging upwards; the triangle TL–M–TR lies on the top side alone and its
    // edge TL–TR joins two non-adjacent vertices of that side.
    mesh.vertices = {{0, 0}, {10, -3}, {20, 0}, {20, 20}, {0, 20}, {10, 12}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 5}, {2, 3, 5}, {3, 4, 5}, {4, 0, 5}};
    mesh.outerLoop = {0, 1, 2, 3, 4};
    mesh.corner = {0, 2, 3, 4};
    REQUIRE(dividingEdges(mesh).size() == 1);
    REQUIRE_THROWS_AS(buildTopologyMap(mesh, 10, 10), Error);
    REQUIRE_THROWS_AS(buildSlitMap(mesh, 10, 10), Error);
}

TEST_CASE("malformed input is reported", "[topology_map]") {
    TriMesh mesh = disk(4, 16);
    REQUIRE_THROWS_AS(buildTopologyMap(mesh, 0, 10), Error);
    TriMesh badCorners = mesh;
    badCorners.corner = {0, 5, 3, 12};
    REQUIRE_THROWS_AS(buildTopologyMap(badCorners, 10, 10), Error);
    TriMesh badIndex = mesh;
    badIndex.triangles[0][1] = static_cast<int>(mesh.vertices.size());
    REQUIRE_THROWS_AS(buildTopologyMap(badIndex, 10, 10), Error);
}

TEST_CASE("topology map timings", "[.][timing][topology_map]") {
    using Clock = std::chrono::steady_clock;
    for (const int target : {20000, 100000}) {
        const int count = static_cast<int>(std::sqrt(target * 2.0));
        const TriMesh d = disk(target / count, count, 300);
        auto t0 = Clock::now();
        const TopologyMap mv = buildTopologyMap(d, 600, 600);
        const double msMv = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        REQUIRE(countFlippedTriangles(d, mv.map) == 0);
        WARN("mean-value map, " << d.vertices.size() << " vertices: " << msMv << " ms");

        const int ac = static_cast<int>(std::sqrt(target * 8.0));
        const TriMesh a = ringMesh({600, 600}, logRadii(target / ac, ac, 100), ac, true);
        t0 = Clock::now();
        const TopologyMap sm = buildTopologyMap(a, 600, 600);
        const double msSlit = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        REQUIRE(countFlippedTriangles(a, sm.map) == 0);
        WARN("slit map (annulus), " << a.vertices.size() << " vertices: " << msSlit
                                    << " ms; flips before repair " << sm.stats.flipsBeforeRepair
                                    << ", clamped " << sm.stats.clampedWeights);
    }
}

namespace {
// Every edge in one or two triangles, loop edges in exactly one; every triangle positive.
void requireConforming(const TriMesh& mesh) {
    std::map<std::pair<int, int>, int> directed;
    for (const auto& t : mesh.triangles) {
        const Vec2 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        REQUIRE((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) > 0);
        for (int k = 0; k < 3; ++k) REQUIRE(++directed[{t[k], t[(k + 1) % 3]}] == 1);
    }
    int unpaired = 0;
    for (const auto& [e, n] : directed) unpaired += directed.count({e.second, e.first}) ? 0 : 1;
    auto loopEdges = [&](const std::vector<int>& loop) {
        for (size_t k = 0; k < loop.size(); ++k) {
            const int a = loop[k], b = loop[(k + 1) % loop.size()];
            REQUIRE((directed.count({a, b}) + directed.count({b, a})) == 1);
        }
        return static_cast<int>(loop.size());
    };
    int boundary = loopEdges(mesh.outerLoop);
    for (const auto& h : mesh.holeLoops) boundary += loopEdges(h);
    REQUIRE(unpaired == boundary);  // no hanging vertex: only loop edges lack a twin
}

double totalArea(const TriMesh& mesh) {
    double s = 0;
    for (const auto& t : mesh.triangles) {
        const Vec2 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        s += 0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    }
    return s;
}
}  // namespace

TEST_CASE("red-green refinement stays conforming and keeps loops, corners and area", "[topology_map][refine]") {
    TriMesh mesh = holedDisk({{100, 100}, 80}, {{{110, 90}, 20}}, 8);
    requireConforming(mesh);
    const double area = totalArea(mesh);
    std::array<int, 4> cornerVertex{};
    for (int k = 0; k < 4; ++k) cornerVertex[k] = mesh.outerLoop[mesh.corner[k]];
    const size_t outer = mesh.outerLoop.size(), hole = mesh.holeLoops[0].size();
    // Every triangle touching a loop, and one in the middle: closure spreads from them.
    std::vector<int> chosen;
    std::vector<char> onLoop(mesh.vertices.size(), 0);
    for (int i : mesh.outerLoop) onLoop[i] = 1;
    for (int i : mesh.holeLoops[0]) onLoop[i] = 1;
    for (size_t t = 0; t < mesh.triangles.size(); t += 3)
        chosen.push_back(static_cast<int>(t));
    const size_t before = mesh.vertices.size();
    const int added = refineTriangles(mesh, chosen);
    CHECK(added > 0);
    CHECK(mesh.vertices.size() == before + static_cast<size_t>(added));
    requireConforming(mesh);
    CHECK(totalArea(mesh) == Approx(area).epsilon(1e-12));
    CHECK(mesh.outerLoop.size() > outer);
    CHECK(mesh.holeLoops[0].size() > hole);
    for (int k = 0; k < 4; ++k) CHECK(mesh.outerLoop[mesh.corner[k]] == cornerVertex[k]);
    // Refining nothing changes nothing.
    const TriMesh copy = mesh;
    CHECK(refineTriangles(mesh, {}) == 0);
    CHECK(mesh.triangles == copy.triangles);
}

TEST_CASE("folds between a hole and a close outline go away with refinement", "[topology_map][refine]") {
    // Holes r 15 within 0.7-1.5 px of the outline, coarsely triangulated: one layer of
    // triangles between them, and the plain slit map folds (measured: one triangle each).
    struct Case { double angle, gap, spacing; };
    const std::vector<Case> cases = {{180, 1.5, 6}, {45, 0.7, 6}, {105, 1.5, 9}, {225, 0.7, 9}, {300, 1.5, 6}};
    for (const Case& c : cases) {
        const double a = c.angle * 3.14159265358979323846 / 180, r = 80 - 15 - c.gap;
        const TriMesh mesh = holedDisk({{100, 100}, 80},
                                       {{{100 + r * std::cos(a), 100 + r * std::sin(a)}, 15}}, c.spacing);
        INFO("hole at " << c.angle << " degrees, " << c.gap << " px from the outline, spacing "
                        << c.spacing);
        const TopologyMap plain = buildSlitMapOrFolds(mesh, 160, 160);
        REQUIRE(!plain.folded.empty());  // the case this test is about
        CHECK_THROWS_AS(buildTopologyMap(mesh, 160, 160), Error);
        TriMesh refined = mesh;
        const TopologyMap tm = buildTopologyMapRefining(refined, 160, 160, 3);
        INFO("refinement: " << tm.stats.refineRounds << " rounds, " << tm.stats.refinedVertices
                            << " vertices");
        REQUIRE(countFlippedTriangles(refined, tm.map) == 0);
        requireOnRectangle(refined, tm.map);
        REQUIRE(tm.slits.size() == 1);
        requireSlitConsistent(refined, tm.map, tm.slits[0], refined.holeLoops[0]);
        CHECK(tm.stats.refineRounds >= 1);
        CHECK(tm.stats.refinedVertices ==
              static_cast<int>(refined.vertices.size() - mesh.vertices.size()));
    }
}
