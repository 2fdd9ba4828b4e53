// .gmb round trips: lossless is bit-exact, compact stays within GmbCompactBounds.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

#include "formats/gmb.h"
#include "gmb_corpus.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"
#include "meshcore/validate.h"
#include "meshcore/synthetic_meshes.h"

using gm::Document;
using gm::GradientMesh;

namespace {

GradientMesh slitMeshWithBreaks() {
    GradientMesh m = gm::makeHoledMesh(3, 20, 30, 400, 300, 7);
    REQUIRE(m.slits.size() == 3);
    m.tangents.push_back({0, 0, 0, 0, {1.25, -3.5}, {0.1, -0.2, 0.3}});
    m.tangents.push_back({3, 2, 1, 0, {-7.0, 0.125}, {0.0, 0.5, -0.25}});
    m.tangents.push_back({m.columns() - 1, m.rows() - 1, 1, 1, {2.0, 2.0}, {0.01, 0.02, 0.03}});
    return m;
}

Document singleMeshDocument(GradientMesh m, int width = 512, int height = 512) {
    Document d;
    d.width = width;
    d.height = height;
    d.meshes.push_back(std::move(m));
    return d;
}

// Lossless: equal as a document, and re-encoding the decoded document gives the same bytes
// (which compares every double bit for bit, -0.0 and NaN payloads included).
void requireLosslessRoundTrip(const Document& doc) {
    const std::string bytes = gmbtest::encodeV1(doc, false);
    const Document back = gm::decodeGmb(bytes, gm::ReadLimits{}, "roundtrip.gmb");
    REQUIRE(back == doc);
    REQUIRE(gmbtest::encodeV1(back, false) == bytes);
    // The writer follows the written spec byte for byte.
    REQUIRE(gmbtest::specEncode(doc) == bytes);
}

// The larger knot interval next to each knot: what GmbCompactBounds scales the derivatives of
// that column (or row) by.
std::vector<double> neighbouringIntervals(const std::vector<double>& k) {
    std::vector<double> out(k.size(), 0.0);
    for (size_t i = 0; i < k.size(); ++i) {
        if (i > 0) out[i] = std::max(out[i], k[i] - k[i - 1]);
        if (i + 1 < k.size()) out[i] = std::max(out[i], k[i + 1] - k[i]);
    }
    return out;
}
double minInterval(const std::vector<double>& k) {
    double m = INFINITY;
    for (size_t i = 1; i < k.size(); ++i) m = std::min(m, k[i] - k[i - 1]);
    return m;
}

struct Deviation {
    double pos = 0, col = 0, posTangent = 0, colTangent = 0, knot = 0;
};

void track(double& worst, double a, double b, double scale = 1.0) {
    worst = std::max(worst, std::fabs(a - b) * scale);
}

// The largest errors of `b` against `a` in the units of GmbCompactBounds; structure must match.
Deviation compactDeviation(const GradientMesh& a, const GradientMesh& b, bool colorDerivatives) {
    Deviation d;
    REQUIRE(a.u.size() == b.u.size());
    REQUIRE(a.v.size() == b.v.size());
    REQUIRE(a.nodes.size() == b.nodes.size());
    REQUIRE(a.slits.size() == b.slits.size());
    REQUIRE(a.tangents.size() == b.tangents.size());
    const std::vector<double> intervalU = neighbouringIntervals(a.u),
                              intervalV = neighbouringIntervals(a.v);
    const double minStep = std::min(minInterval(a.u), minInterval(a.v));
    for (size_t i = 0; i < a.u.size(); ++i) track(d.knot, a.u[i], b.u[i], 1 / minStep);
    for (size_t j = 0; j < a.v.size(); ++j) track(d.knot, a.v[j], b.v[j], 1 / minStep);
    const size_t stride = a.u.size();
    // A node in column i, row j.
    auto node = [&](const gm::Node& x, const gm::Node& y, size_t i, size_t j) {
        const double du = intervalU[i], dv = intervalV[j];
        track(d.pos, x.pos.x, y.pos.x);
        track(d.pos, x.pos.y, y.pos.y);
        track(d.posTangent, x.posU.x, y.posU.x, du);
        track(d.posTangent, x.posU.y, y.posU.y, du);
        track(d.posTangent, x.posV.x, y.posV.x, dv);
        track(d.posTangent, x.posV.y, y.posV.y, dv);
        for (int c = 0; c < 3; ++c) {
            track(d.col, x.col[c], y.col[c]);
            if (colorDerivatives) {
                track(d.colTangent, x.colU[c], y.colU[c], du);
                track(d.colTangent, x.colV[c], y.colV[c], dv);
            }
        }
    };
    for (size_t k = 0; k < a.nodes.size(); ++k)
        node(a.nodes[k], b.nodes[k], k % stride, k / stride);
    for (size_t s = 0; s < a.slits.size(); ++s) {
        const gm::Slit &x = a.slits[s], &y = b.slits[s];
        REQUIRE(x.row == y.row);
        REQUIRE(x.i0 == y.i0);
        REQUIRE(x.i1 == y.i1);
        REQUIRE(x.below.size() == y.below.size());
        for (size_t k = 0; k < x.below.size(); ++k)
            node(x.below[k], y.below[k], static_cast<size_t>(x.i0) + 1 + k,
                 static_cast<size_t>(x.row));
        for (auto ends : {std::make_pair(&x.left, &y.left), std::make_pair(&x.right, &y.right)}) {
            const double du = intervalU[static_cast<size_t>(ends.first == &x.left ? x.i0 : x.i1)];
            track(d.posTangent, ends.first->posU.x, ends.second->posU.x, du);
            track(d.posTangent, ends.first->posU.y, ends.second->posU.y, du);
            for (int c = 0; c < 3 && colorDerivatives; ++c)
                track(d.colTangent, ends.first->colU[c], ends.second->colU[c], du);
        }
    }
    for (size_t k = 0; k < a.tangents.size(); ++k) {
        const gm::CornerTangent &x = a.tangents[k], &y = b.tangents[k];
        REQUIRE((x.i == y.i && x.j == y.j && x.a == y.a && x.b == y.b));
        const double du = intervalU[static_cast<size_t>(x.i + x.a)];
        track(d.posTangent, x.posU.x, y.posU.x, du);
        track(d.posTangent, x.posU.y, y.posU.y, du);
        for (int c = 0; c < 3 && colorDerivatives; ++c) track(d.colTangent, x.colU[c], y.colU[c], du);
    }
    return d;
}

// Within the bounds of compact level `level` (level 0: GmbCompactBounds as stated).
void requireWithinBounds(const Deviation& d, int level = 0) {
    const gm::GmbCompactShifts k = gm::gmbCompactShifts(level);
    INFO("level " << level << ": position " << d.pos << ", colour " << d.col
                  << ", position tangent " << d.posTangent << ", colour tangent " << d.colTangent
                  << ", knot " << d.knot);
    CHECK(d.pos <= std::ldexp(gm::GmbCompactBounds::position, k.position));
    CHECK(d.col <= std::ldexp(gm::GmbCompactBounds::color, k.color));
    CHECK(d.posTangent <= std::ldexp(gm::GmbCompactBounds::positionTangent, k.positionTangent));
    CHECK(d.colTangent <= std::ldexp(gm::GmbCompactBounds::colorTangent, k.colorTangent));
    CHECK(d.knot <= std::ldexp(gm::GmbCompactBounds::knotRelative, k.knot));
}

}  // namespace

TEST_CASE("lossless round trip is bit-exact on random meshes", "[roundtrip]") {
    for (unsigned seed = 1; seed <= 20; ++seed) {
        INFO("seed " << seed);
        requireLosslessRoundTrip(singleMeshDocument(gmbtest::randomMesh(seed)));
    }
}

TEST_CASE("lossless round trip keeps slits, below copies, end tangents and tangent breaks",
          "[roundtrip]") {
    GradientMesh m = slitMeshWithBreaks();
    // Rows 2, 4 and 6: three slits on three rows.
    CHECK(m.slits[0].row != m.slits[1].row);
    CHECK(m.slits[1].row != m.slits[2].row);
    requireLosslessRoundTrip(singleMeshDocument(m, 640, 480));
}

TEST_CASE("lossless round trip keeps a multi-mesh document and its order", "[roundtrip]") {
    Document d = gm::makeDemoDocument();
    d.meshes.push_back(gmbtest::randomMesh(99));
    d.meshes.push_back(slitMeshWithBreaks());
    d.meshes.push_back(gmbtest::randomMesh(100, 1, 1));
    requireLosslessRoundTrip(d);
    std::swap(d.meshes.front(), d.meshes.back());
    const Document back = gm::decodeGmb(gmbtest::encodeV1(d, false), gm::ReadLimits{});
    REQUIRE(back.meshes.front() == d.meshes.front());
    REQUIRE(back == d);
}

TEST_CASE("compact round trip stays within the stated bounds on a smooth mesh", "[roundtrip]") {
    GradientMesh m = gm::makeCurvedMesh(32, 32, 16, 16, 480, 480, 1.0, 3);
    gmbtest::addFittingNoise(m, 11);
    const Document doc = singleMeshDocument(m);
    REQUIRE_FALSE(gm::followsColorRule(doc.meshes[0]));
    const std::string lossless = gmbtest::encodeV1(doc, false);
    const std::string compact = gmbtest::encodeV1(doc, true);
    const Document back = gm::decodeGmb(compact, gm::ReadLimits{}, "compact.gmb");
    REQUIRE(back.width == doc.width);
    REQUIRE(back.height == doc.height);
    requireWithinBounds(compactDeviation(doc.meshes[0], back.meshes[0], true));
    const double patches = doc.meshes[0].patchCount();
    WARN("32x32 smooth mesh: lossless " << lossless.size() << " bytes ("
                                        << lossless.size() / patches << " per patch), compact "
                                        << compact.size() << " bytes (" << compact.size() / patches
                                        << " per patch)");
    CHECK(compact.size() * 4 < lossless.size());
    // Compact is stable: a second pass changes nothing.
    REQUIRE(gm::decodeGmb(gmbtest::encodeV1(back, true), gm::ReadLimits{}) == back);
}

TEST_CASE("compact round trip stays within the bounds with slits, breaks and odd knots",
          "[roundtrip]") {
    GradientMesh m = slitMeshWithBreaks();
    // Non-uniform knots at another scale: derivative bounds scale with the intervals.
    for (size_t i = 0; i < m.u.size(); ++i) m.u[i] = 0.001 * i * i + 0.37 * i + 5;
    for (size_t j = 0; j < m.v.size(); ++j) m.v[j] = 40.0 * j + 0.1 * std::sin(double(j));
    const Document doc = singleMeshDocument(m, 640, 480);
    const Document back = gm::decodeGmb(gmbtest::encodeV1(doc, true), gm::ReadLimits{});
    requireWithinBounds(compactDeviation(doc.meshes[0], back.meshes[0], true));
}

TEST_CASE("compact mode omits colour derivatives that follow the rule", "[roundtrip]") {
    GradientMesh m = gm::makeCurvedMesh(32, 32, 16, 16, 480, 480, 1.0, 5);
    gmbtest::addFittingNoise(m, 12);
    const std::string explicitDerivatives = gmbtest::encodeV1(singleMeshDocument(m), true);
    gm::applyColorRule(m);
    REQUIRE(gm::followsColorRule(m));
    const Document doc = singleMeshDocument(m);
    const std::string byRule = gmbtest::encodeV1(doc, true);
    WARN("compact with colour derivatives " << explicitDerivatives.size()
                                            << " bytes, by rule " << byRule.size());
    CHECK(byRule.size() < explicitDerivatives.size());
    const Document back = gm::decodeGmb(byRule, gm::ReadLimits{});
    requireWithinBounds(compactDeviation(m, back.meshes[0], false));
    CHECK(gm::followsColorRule(back.meshes[0]));
    CHECK(gm::colorRuleDeviation(back.meshes[0]) == 0.0);
}

TEST_CASE("compact writes a mesh it cannot quantise as float64", "[roundtrip]") {
    // Coordinates far beyond the quantised range: the mesh must come back exactly.
    const Document doc = singleMeshDocument(gmbtest::randomMesh(4));
    const std::string bytes = gmbtest::encodeV1(doc, true);
    CHECK(bytes[gmbtest::findSection(bytes, "MESH").payload() + 16] == 0);  // float64
    CHECK(gmbtest::getLE(bytes, 10, 2) == 0);  // nothing of 1.1 in it: a 1.0 file
    const Document back = gm::decodeGmb(bytes, gm::ReadLimits{});
    REQUIRE(back == doc);
    // Next to a mesh that can be quantised, each mesh is written its own way.
    Document both = doc;
    GradientMesh smooth = gm::makeCurvedMesh(6, 5, 16, 16, 200, 160, 1.0, 8);
    both.meshes.insert(both.meshes.begin(), smooth);
    const std::string mixed = gmbtest::encodeV1(both, true);
    // A CMS2 section (version 1.3) or a CMS3 section (1.4), whichever is smaller.
    const std::string runTag = gmbtest::listSections(mixed)[1].tag;
    CHECK(gmbtest::getLE(mixed, 10, 2) == (runTag == "CMS3" ? 4u : 3u));
    CHECK((runTag == "CMS2" || runTag == "CMS3"));
    CHECK(gmbtest::compactRecords(mixed).size() == 1);
    CHECK(mixed[gmbtest::findSection(mixed, "MESH", 0).payload() + 16] == 0);  // float64
    CHECK(gmbtest::findSection(mixed, "MESH", 1).tag.empty());
    const Document mixedBack = gm::decodeGmb(mixed, gm::ReadLimits{});
    REQUIRE(mixedBack.meshes[1] == doc.meshes[0]);
    requireWithinBounds(compactDeviation(smooth, mixedBack.meshes[0], true));
}

namespace {

// Meshes of many shapes, knot scales and values, with slits, tangent breaks and rule colours.
std::vector<GradientMesh> compactTestMeshes() {
    std::vector<GradientMesh> out;
    for (unsigned seed = 1; seed <= 3; ++seed) {
        GradientMesh m =
            gm::makeCurvedMesh(3 + 7 * seed, 2 + 5 * seed, 8, 8, 300, 200, 0.5 * seed, seed);
        gmbtest::addFittingNoise(m, 40 + seed);
        out.push_back(m);
    }
    out.push_back(gm::makeCurvedMesh(1, 1, 10, 10, 30, 30, 0.0, 4));    // one patch
    out.push_back(gm::makeCurvedMesh(12, 1, 10, 10, 300, 20, 1.0, 5));  // one row
    out.push_back(gm::makeCurvedMesh(1, 9, 10, 10, 20, 300, 1.0, 6));   // one column
    {
        // Knots on very different scales, and uneven: derivatives in pixels per 1/1000 unit
        // next to pixels per 1000 units.
        GradientMesh m = gm::makeCurvedMesh(10, 8, 8, 8, 400, 300, 1.0, 7);
        gmbtest::addFittingNoise(m, 47);
        for (size_t i = 0; i < m.u.size(); ++i) m.u[i] = 1e-3 * (i * i + i);
        for (size_t j = 0; j < m.v.size(); ++j) m.v[j] = 1e3 * j + (j % 2 ? 400 : 0);
        for (gm::Node& n : m.nodes) {
            n.posU = n.posU * 1e3;
            n.colU = n.colU * 1e3;
            n.posV = n.posV * 1e-3;
            n.colV = n.colV * 1e-3;
        }
        out.push_back(m);
    }
    {
        // Colours far outside 0-1 and large, jumpy derivatives.
        GradientMesh m = gm::makeCurvedMesh(9, 9, -500, -300, 2000, 1500, 1.0, 8);
        std::mt19937_64 rng(9);
        std::uniform_real_distribution<double> u(-1, 1);
        for (gm::Node& n : m.nodes) {
            for (int c = 0; c < 3; ++c) {
                n.col[c] = 40 * u(rng);
                n.colU[c] = 300 * u(rng);
                n.colV[c] = 300 * u(rng);
            }
            n.posU = {5000 * u(rng), 5000 * u(rng)};
        }
        out.push_back(m);
    }
    GradientMesh holed = slitMeshWithBreaks();
    gmbtest::addFittingNoise(holed, 48);
    out.push_back(holed);
    for (GradientMesh& piece : gm::splitIntoLegacyMeshes(gm::makeHoledMesh(2, 10, 10, 300, 200, 9)))
        out.push_back(piece);  // hole-free pieces with corner tangent breaks
    GradientMesh rule = gm::makeCurvedMesh(14, 11, 10, 10, 300, 240, 1.0, 10);
    gmbtest::addFittingNoise(rule, 49);
    gm::applyColorRule(rule);
    out.push_back(rule);
    GradientMesh holedRule = gm::makeHoledMesh(2, 10, 10, 300, 200, 11);
    gm::applyColorRule(holedRule);
    out.push_back(holedRule);
    return out;
}

// The quantised knots of a mesh read from encoding 2, from its exponent: decoded knots are
// q · 2^e exactly.
std::vector<int64_t> knotIntegers(const std::vector<double>& k, int e) {
    std::vector<int64_t> out;
    for (double x : k) {
        const double q = std::ldexp(x, -e);
        REQUIRE(q == std::round(q));
        out.push_back(static_cast<int64_t>(q));
    }
    return out;
}

}  // namespace

TEST_CASE("compact round trip stays within the bounds on meshes of many shapes and scales",
          "[roundtrip]") {
    const std::vector<GradientMesh> meshes = compactTestMeshes();
    Document doc = singleMeshDocument(meshes[0], 800, 600);
    doc.meshes = meshes;
    const std::string bytes = gmbtest::encodeV1(doc, true);
    CHECK(gmbtest::getLE(bytes, 10, 2) >= 3);  // version 1.3 or 1.4
    const Document back = gm::decodeGmb(bytes, gm::ReadLimits{}, "compact.gmb");
    REQUIRE(back.meshes.size() == doc.meshes.size());
    // Every one range-coded, in one CMS2 or CMS3 section.
    const auto records = gmbtest::compactRecords(bytes);
    REQUIRE(records.size() == doc.meshes.size());
    CHECK(gmbtest::listSections(bytes).size() == 3);
    for (size_t k = 0; k < doc.meshes.size(); ++k) {
        INFO("mesh " << k);
        const bool rule = records[k].byRule;
        CHECK(rule == gm::followsColorRule(doc.meshes[k]));
        requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k], !rule));
    }
    // Stable: the decoded document is on the grid, and comes back bit for bit.
    REQUIRE(gm::decodeGmb(gmbtest::encodeV1(back, true), gm::ReadLimits{}) == back);
    // Lossless files are still 1.0 files.
    CHECK(gmbtest::getLE(gmbtest::encodeV1(doc, false), 10, 2) == 0);
}

TEST_CASE("coarser compact levels stay within their scaled bounds and shrink the file",
          "[roundtrip]") {
    const std::vector<GradientMesh> meshes = compactTestMeshes();
    Document doc = singleMeshDocument(meshes[0], 800, 600);
    doc.meshes = meshes;
    size_t previous = gmbtest::encodeV1(doc, true).size();
    CHECK(gmbtest::encodeV1(doc, true, 0) == gmbtest::encodeV1(doc, true));
    for (int level = 1; level <= gm::kGmbMaxCompactLevel; ++level) {
        INFO("level " << level);
        const std::string bytes = gmbtest::encodeV1(doc, true, level);
        const Document back = gm::decodeGmb(bytes, gm::ReadLimits{}, "coarse.gmb");
        REQUIRE(back.meshes.size() == doc.meshes.size());
        const auto records = gmbtest::compactRecords(bytes);
        REQUIRE(records.size() == doc.meshes.size());  // still range-coded, not float64
        for (size_t k = 0; k < doc.meshes.size(); ++k) {
            INFO("mesh " << k);
            const bool rule = records[k].byRule;
            requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k], !rule), level);
            // The slit structure is exact at every level.
            CHECK(back.meshes[k].slits.size() == doc.meshes[k].slits.size());
        }
        CHECK(bytes.size() < previous);
        previous = bytes.size();
        // Stable at its own level.
        CHECK(gm::decodeGmb(gmbtest::encodeV1(back, true, level), gm::ReadLimits{}) == back);
    }
    // A lossless file ignores the level; a level outside 0..kGmbMaxCompactLevel is refused.
    CHECK(gmbtest::encodeV1(doc, false, 3) == gmbtest::encodeV1(doc, false));
    CHECK_THROWS_WITH(gmbtest::encodeV1(doc, true, gm::kGmbMaxCompactLevel + 1),
                      Catch::Contains("compact level " + std::to_string(gm::kGmbMaxCompactLevel + 1)));
    CHECK_THROWS_WITH(gmbtest::encodeV1(doc, true, -1), Catch::Contains("compact level -1"));
}

TEST_CASE("compact meshes decode by the written specification alone", "[roundtrip]") {
    // An independent decoder written from the spec (gmb_spec_coded.h) reads every mesh of the
    // CMS2 and CMS3 sections the writer produces, knots and nodes, to the same numbers as the
    // reader, at every level.
    const std::vector<GradientMesh> meshes = compactTestMeshes();
    Document doc = singleMeshDocument(meshes[0], 800, 600);
    doc.meshes = meshes;
    for (gm::GmbStreams streams : {gm::GmbStreams::Cms2, gm::GmbStreams::Cms3})
    for (int level = 0; level <= gm::kGmbMaxCompactLevel; ++level) {
        INFO("level " << level << (streams == gm::GmbStreams::Cms3 ? ", CMS3" : ", CMS2"));
        const std::string bytes = gmbtest::encodeV1(doc, true, level, streams);
        CHECK(gmbtest::listSections(bytes)[1].tag == (streams == gm::GmbStreams::Cms3 ? "CMS3" : "CMS2"));
        const Document back = gm::decodeGmb(bytes, gm::ReadLimits{});
        const auto records = gmbtest::compactRecords(bytes);
        REQUIRE(records.size() == doc.meshes.size());
        for (size_t k = 0; k < doc.meshes.size(); ++k) {
            INFO("mesh " << k);
            const gmbtest::SpecCmshMesh& r = records[k];
            const gmbtest::SpecMeshInfo& info = r.info;
            const GradientMesh& m = back.meshes[k];
            REQUIRE(info.C == m.columns());
            REQUIRE(info.R == m.rows());
            CHECK(r.slits == static_cast<int>(m.slits.size()));
            CHECK(r.tangents == static_cast<int>(m.tangents.size()));
            // Knots: q · 2^e_knot.
            CHECK(knotIntegers(m.u, info.e[0]) == info.ku);
            CHECK(knotIntegers(m.v, info.e[0]) == info.kv);
            bool same = true;
            for (int j = 0; j <= info.R; ++j)
                for (int i = 0; i <= info.C; ++i)
                    for (int c = 0; c < info.F; ++c) {
                        const size_t at = static_cast<size_t>(j) * (info.C + 1) + i;
                        if (gmbtest::specCodedValue(info, c, r.q[c][at], i, j) !=
                            gmbtest::nodeValue(m.node(i, j), c))
                            same = false;
                    }
            CHECK(same);
        }
    }
}

TEST_CASE("1.1 range-coded nodes still decode by the written specification alone", "[roundtrip]") {
    // The NODE sections of the 1.1 golden files (encoding 2, every plane's weights stated).
    for (const char* name : {"golden-1.1-compact.gmb", "golden-1.1-compact-rule.gmb"}) {
        INFO(name);
        const std::string bytes = gmbtest::readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/" + name);
        const Document back = gm::decodeGmb(bytes, gm::ReadLimits{});
        for (size_t k = 0; k < back.meshes.size(); ++k) {
            const int nth = static_cast<int>(k);
            const gmbtest::SectionInfo mesh = gmbtest::findSection(bytes, "MESH", nth);
            const gmbtest::SectionInfo node = gmbtest::findSection(bytes, "NODE", nth);
            gmbtest::SpecMeshInfo info;
            info.C = static_cast<int>(gmbtest::getLE(bytes, mesh.payload(), 4));
            info.R = static_cast<int>(gmbtest::getLE(bytes, mesh.payload() + 4, 4));
            info.F = (bytes[mesh.payload() + 17] & 1) ? 9 : 15;
            for (int f = 0; f < 7; ++f)
                info.e[f] = static_cast<int16_t>(gmbtest::getLE(bytes, mesh.payload() + 18 + 2 * f, 2));
            const GradientMesh& m = back.meshes[k];
            info.ku = knotIntegers(m.u, info.e[0]);
            info.kv = knotIntegers(m.v, info.e[0]);
            const auto q = gmbtest::specDecodeCodedNodes(
                bytes.substr(node.payload(), static_cast<size_t>(node.stored)), info);
            for (int c = 0; c < info.F; ++c)
                for (size_t at = 0; at < m.nodes.size(); ++at) {
                    const int i = static_cast<int>(at % (info.C + 1)), j = static_cast<int>(at / (info.C + 1));
                    CHECK(gmbtest::specCodedValue(info, c, q[c][at], i, j) ==
                          gmbtest::nodeValue(m.nodes[at], c));
                }
        }
    }
}

TEST_CASE("CMSH and CMS2 and CMS3 hold what the 1.1 sections held in far fewer bytes for small meshes",
          "[roundtrip]") {
    // 15 meshes of 2x3 patches (a whole image cut into small regions): per-mesh overhead is most
    // of a 1.1 file.
    Document doc;
    doc.width = 600;
    doc.height = 400;
    for (unsigned k = 0; k < 15; ++k) {
        GradientMesh m = gm::makeCurvedMesh(2, 3, 40.0 * (k % 5), 100.0 * (k / 5), 100, 90, 0.5,
                                            20 + k);
        gmbtest::addFittingNoise(m, 60 + k);
        if (k % 3 == 0) gm::applyColorRule(m);
        doc.meshes.push_back(m);
    }
    for (int level = 0; level <= gm::kGmbMaxCompactLevel; ++level) {
        INFO("level " << level);
        // A CMS3 file, the same data in CMS2 (1.3) and CMSH (1.2), and CMSH's very streams in
        // the 1.1 layout.
        const std::string v14 = gmbtest::encodeV1(doc, true, level, gm::GmbStreams::Cms3);
        const std::string v13 = gmbtest::cms3AsCms2(v14);
        const std::string v12 = gmbtest::cms2AsCmsh(v13);
        const std::string v11 = gmbtest::cmshAs11(v12);
        CHECK(gmbtest::getLE(v13, 10, 2) == 3);
        CHECK(gmbtest::listSections(v13)[1].tag == "CMS2");
        CHECK(gmbtest::getLE(v12, 10, 2) == 2);
        CHECK(gmbtest::listSections(v12)[1].tag == "CMSH");
        const Document back = gm::decodeGmb(v14, gm::ReadLimits{});
        REQUIRE(gm::decodeGmb(v13, gm::ReadLimits{}) == back);
        REQUIRE(gm::decodeGmb(v12, gm::ReadLimits{}) == back);
        REQUIRE(gm::decodeGmb(v11, gm::ReadLimits{}) == back);
        for (size_t k = 0; k < doc.meshes.size(); ++k)
            requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k], k % 3 != 0), level);
        const double perMesh12 = (v12.size() - 12 - 40 - 28) / 15.0;
        WARN("15 meshes of 2x3 patches, level " << level << ": 1.1 layout " << v11.size()
                                                << " B, 1.2 (CMSH) " << v12.size() << " B ("
                                                << 100.0 * v12.size() / v11.size() << " %), "
                                                << perMesh12 << " B per mesh");
        CHECK(v12.size() * 10 < v11.size() * 7);  // at least 30 % smaller
        WARN("  1.3 (CMS2) " << v13.size() << " B (" << 100.0 * v13.size() / v12.size()
                             << " % of CMSH)");
        CHECK(v13.size() * 100 < v12.size() * 95);  // at least 5 % smaller again
        // These synthetic meshes are unlike converted images: CMS3's priors cost a little here,
        // and the writer's default keeps CMS2.
        const std::string chosen = gmbtest::encodeV1(doc, true, level);
        WARN("  1.4 (CMS3) " << v14.size() << " B (" << 100.0 * v14.size() / v13.size()
                             << " % of CMS2); the default writes " << chosen.size() << " B");
        CHECK(v14.size() * 100 < v13.size() * 110);
        CHECK(chosen.size() ==
              std::min(v14.size(), gmbtest::encodeV1(doc, true, level, gm::GmbStreams::Cms2).size()));
    }
}

TEST_CASE("multi-mesh compact documents with slits and breaks round-trip at every level",
          "[roundtrip]") {
    // Slits, tangent breaks, rule colours and a float64 fallback, mesh after mesh: CMS3 runs
    // broken by a MESH section (and CMS2 runs, with the 1.3 layout asked for).
    Document doc = singleMeshDocument(slitMeshWithBreaks(), 640, 480);
    GradientMesh rule = gm::makeHoledMesh(2, 10, 10, 300, 200, 11);
    gm::applyColorRule(rule);
    doc.meshes.push_back(rule);
    doc.meshes.push_back(gmbtest::randomMesh(4));  // beyond the quantised range: float64
    for (GradientMesh& piece : gm::splitIntoLegacyMeshes(gm::makeHoledMesh(2, 10, 10, 300, 200, 9)))
        doc.meshes.push_back(piece);
    for (const char* run : {"CMS2", "CMS3"})
    for (int level = 0; level <= gm::kGmbMaxCompactLevel; ++level) {
        INFO("level " << level << ", " << run);
        const std::string bytes = gmbtest::encodeV1(
            doc, true, level, run == std::string("CMS3") ? gm::GmbStreams::Cms3 : gm::GmbStreams::Cms2);
        std::vector<std::string> tags;
        for (const gmbtest::SectionInfo& i : gmbtest::listSections(bytes)) tags.push_back(i.tag);
        CHECK(tags == std::vector<std::string>{"DOCU", run, "MESH", "KNOT", "NODE", run, "END "});
        const Document back = gm::decodeGmb(bytes, gm::ReadLimits{});
        REQUIRE(back.meshes.size() == doc.meshes.size());
        REQUIRE(back.meshes[2] == doc.meshes[2]);
        for (size_t k = 0; k < doc.meshes.size(); ++k) {
            if (k == 2) continue;
            INFO("mesh " << k);
            requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k], k != 1), level);
        }
        CHECK(back.meshes[1].slits.size() == 2);
        CHECK_FALSE(back.meshes[3].tangents.empty());
        CHECK(gm::decodeGmb(gmbtest::encodeV1(back, true, level), gm::ReadLimits{}) == back);
    }
}

namespace {

// A whole image as small regions: 12 meshes of 2x2 to 5x2 patches; mesh 3 (4x2) has a slit on
// row 1, mesh 5 a corner tangent break, mesh 7 colours by the rule, and mesh 6 has a coordinate
// beyond the quantised range, so it stays float64 and splits the CMS3 run in two.
Document smallRegions() {
    Document doc;
    doc.width = 640;
    doc.height = 480;
    for (unsigned k = 0; k < 12; ++k) {
        const int C = 2 + static_cast<int>(k % 4), R = 2;
        GradientMesh m = gm::makeCurvedMesh(C, R, 50.0 * (k % 4), 120.0 * (k / 4), 30.0 * C,
                                            90, 0.5, 70 + k);
        gmbtest::addFittingNoise(m, 80 + k);
        if (k == 3) {
            gm::Slit s;
            s.row = 1;
            s.i0 = 1;
            s.i1 = 3;
            gm::Node below = m.node(2, 1);
            below.pos.y += 1.5;
            m.node(2, 1).pos.y -= 1.5;
            s.below.push_back(below);
            s.left = {{0, -3}, {0.01, 0.02, 0.03}};
            s.right = {{0, 3}, {-0.01, -0.02, -0.03}};
            m.slits.push_back(s);
        }
        if (k == 5) m.tangents.push_back({1, 0, 1, 1, {12.5, -3.25}, {0.05, -0.1, 0.02}});
        if (k == 6) m.node(1, 1).pos.x = 1e20;
        if (k == 7) gm::applyColorRule(m);
        doc.meshes.push_back(m);
    }
    return doc;
}

}  // namespace

TEST_CASE("CMS3 runs of small meshes round-trip within the bounds and beat CMSH", "[roundtrip]") {
    const Document doc = smallRegions();
    REQUIRE(gm::validateDocument(doc).empty());
    REQUIRE(gm::followsColorRule(doc.meshes[7]));
    for (int level : {0, 2, 4, 5}) {
        INFO("level " << level);
        const std::string v14 = gmbtest::encodeV1(doc, true, level, gm::GmbStreams::Cms3);
        CHECK(gmbtest::getLE(v14, 10, 2) == 4);
        std::vector<std::string> tags;
        for (const gmbtest::SectionInfo& i : gmbtest::listSections(v14)) tags.push_back(i.tag);
        CHECK(tags == std::vector<std::string>{"DOCU", "CMS3", "MESH", "KNOT", "NODE", "CMS3", "END "});
        const auto records = gmbtest::compactRecords(v14);
        REQUIRE(records.size() == 11);
        CHECK(records[3].slits == 1);
        CHECK(records[5].tangents == 1);
        CHECK(records[6].byRule);  // mesh 7: mesh 6 (float64) has no record
        const Document back = gm::decodeGmb(v14, gm::ReadLimits{}, "regions.gmb");
        REQUIRE(back.meshes.size() == doc.meshes.size());
        REQUIRE(back.meshes[6] == doc.meshes[6]);  // float64, exactly
        for (size_t k = 0; k < doc.meshes.size(); ++k) {
            if (k == 6) continue;
            INFO("mesh " << k);
            requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k], k != 7), level);
        }
        CHECK(back.meshes[3].slits.size() == 1);
        CHECK(back.meshes[5].tangents.size() == 1);
        CHECK(gm::followsColorRule(back.meshes[7]));
        // Stable on its own grid.
        CHECK(gm::decodeGmb(gmbtest::encodeV1(back, true, level), gm::ReadLimits{}) == back);
        // The very same data in CMS2 (1.3) and CMSH sections (1.2) reads to the same document
        // and is larger.
        const std::string v13 = gmbtest::cms3AsCms2(v14);
        const std::string v12 = gmbtest::cms2AsCmsh(v14);
        REQUIRE(gm::decodeGmb(v13, gm::ReadLimits{}) == back);
        REQUIRE(gm::decodeGmb(v12, gm::ReadLimits{}) == back);
        WARN("12 small meshes, level " << level << ": CMSH " << v12.size() << " B, CMS2 "
                                       << v13.size() << " B (" << 100.0 * v13.size() / v12.size()
                                       << " %), CMS3 " << v14.size() << " B ("
                                       << 100.0 * v14.size() / v13.size() << " % of CMS2)");
        CHECK(v13.size() * 100 < v12.size() * 92);  // at least 8 % smaller
        CHECK(v14.size() * 100 < v13.size() * 102);  // synthetic meshes: about CMS2's size
    }
}

TEST_CASE("a single big mesh is no larger in CMS3 than in CMS2 or CMSH", "[roundtrip]") {
    for (int level : {0, 5}) {
        INFO("level " << level);
        GradientMesh m = gm::makeCurvedMesh(32, 24, 16, 16, 480, 400, 1.0, 21);
        gmbtest::addFittingNoise(m, 22);
        const std::string v14 = gmbtest::encodeV1(singleMeshDocument(m), true, level, gm::GmbStreams::Cms3);
        const std::string v13 = gmbtest::cms3AsCms2(v14);
        const std::string v12 = gmbtest::cms2AsCmsh(v13);
        const Document back = gm::decodeGmb(v14, gm::ReadLimits{});
        REQUIRE(gm::decodeGmb(v13, gm::ReadLimits{}) == back);
        REQUIRE(gm::decodeGmb(v12, gm::ReadLimits{}) == back);
        WARN("32x24 mesh, level " << level << ": CMSH " << v12.size() << " B, CMS2 " << v13.size()
                                  << " B, CMS3 " << v14.size() << " B");
        CHECK(v13.size() <= v12.size() + 4);
        CHECK(v14.size() <= v13.size() + 4);
    }
}

TEST_CASE("the format object writes atomically and reads back", "[roundtrip]") {
    const auto format = gm::makeGmbFormat();
    CHECK(format->name() == "gmb");
    CHECK(format->extensions() == std::vector<std::string>{".gmb"});
    CHECK(format->sniff(gmbtest::encodeV1(singleMeshDocument(gmbtest::randomMesh(1)), false)));
    CHECK_FALSE(format->sniff("<svg"));
    CHECK_FALSE(format->sniff("\x89GMB"));
    const std::string path = std::string(GRADMESH_TMP) + "/gmb_format_roundtrip.gmb";
    Document doc = gm::makeDemoDocument();
    gm::WriteOptions options;
    format->write(doc, path, options);
    CHECK(format->read(path, gm::ReadOptions{}) == doc);
    options.compact = true;
    format->write(doc, path, options);
    CHECK(format->read(path, gm::ReadOptions{}).meshes.size() == doc.meshes.size());
    options.compact = false;
    options.legacy = true;  // slits become hole-free pieces
    format->write(doc, path, options);
    for (const GradientMesh& m : format->read(path, gm::ReadOptions{}).meshes) CHECK(m.slits.empty());
    std::remove(path.c_str());
    // An invalid document is refused and leaves no file behind.
    doc.meshes[0].u[1] = doc.meshes[0].u[0];
    REQUIRE_THROWS_AS(format->write(doc, path, gm::WriteOptions{}), gm::Error);
    CHECK(gmbtest::readFile(path).empty());
}


TEST_CASE("a converted whole image is smaller in CMS3 than in CMS2", "[roundtrip]") {
    // happyfish-whole-10.gmb: HappyFish.jpg converted whole at 10 patches a region (13 meshes,
    // 108 patches), lossless. CMS3's priors were measured on such files.
    const Document doc = gm::decodeGmb(
        gmbtest::readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/happyfish-whole-10.gmb"),
        gm::ReadLimits{});
    REQUIRE(doc.meshes.size() == 13);
    for (int level : {0, 2, 4, 6}) {
        INFO("level " << level);
        const std::string cms2 = gmbtest::encodeV1(doc, true, level, gm::GmbStreams::Cms2);
        const std::string cms3 = gmbtest::encodeV1(doc, true, level, gm::GmbStreams::Cms3);
        const std::string chosen = gmbtest::encodeV1(doc, true, level);
        WARN("HappyFish whole, level " << level << ": CMS2 " << cms2.size() << " B, CMS3 "
                                       << cms3.size() << " B (" << 100.0 * cms3.size() / cms2.size()
                                       << " %)");
        CHECK(cms3.size() * 100 < cms2.size() * 97);  // measured: 4-5 % smaller
        CHECK(chosen == cms3);
        CHECK(gmbtest::getLE(chosen, 10, 2) == 4);
        // The same document either way, and the spec decoder reads the CMS3 stream to the
        // reader's numbers.
        const Document back = gm::decodeGmb(cms3, gm::ReadLimits{});
        REQUIRE(gm::decodeGmb(cms2, gm::ReadLimits{}) == back);
        const auto records = gmbtest::compactRecords(cms3);
        REQUIRE(records.size() == back.meshes.size());
        bool same = true;
        for (size_t k = 0; k < records.size(); ++k) {
            const gmbtest::SpecMeshInfo& info = records[k].info;
            const GradientMesh& m = back.meshes[k];
            REQUIRE((info.C == m.columns() && info.R == m.rows()));
            for (int j = 0; j <= info.R; ++j)
                for (int i = 0; i <= info.C; ++i)
                    for (int c = 0; c < info.F; ++c) {
                        const size_t at = static_cast<size_t>(j) * (info.C + 1) + i;
                        if (gmbtest::specCodedValue(info, c, records[k].q[c][at], i, j) !=
                            gmbtest::nodeValue(m.node(i, j), c))
                            same = false;
                    }
        }
        CHECK(same);
        for (size_t k = 0; k < doc.meshes.size(); ++k)
            requireWithinBounds(compactDeviation(doc.meshes[k], back.meshes[k],
                                                 !gm::followsColorRule(doc.meshes[k])),
                                level);
    }
}

TEST_CASE("the colour model round-trips: a bicubic mesh is read back bicubic, without slopes",
          "[roundtrip][bicubic]") {
    GradientMesh m = slitMeshWithBreaks();
    m.colorModel = gm::ColorModel::Bicubic;
    // The model ignores stored slopes: zero them, as the converter leaves them.
    for (gm::Node& n : m.nodes) n.colU = n.colV = gm::Vec3{};
    for (gm::Slit& s : m.slits) {
        for (gm::Node& n : s.below) n.colU = n.colV = gm::Vec3{};
        s.left.colU = s.right.colU = gm::Vec3{};
    }
    for (gm::CornerTangent& t : m.tangents) t.colU = gm::Vec3{};
    Document doc = singleMeshDocument(m, 640, 480);
    doc.meshes.push_back(gmbtest::randomMesh(7));  // a hermite mesh beside it
    requireLosslessRoundTrip(doc);
    for (const std::string& bytes : {gm::encodeGmb(doc, true), gmbtest::encodeV1(doc, true)}) {
        const Document back = gm::decodeGmb(bytes, gm::ReadLimits{});
        REQUIRE(back.meshes.size() == 2);
        CHECK(back.meshes[0].colorModel == gm::ColorModel::Bicubic);
        CHECK(back.meshes[1].colorModel == gm::ColorModel::Hermite);
    }
    // Without slopes the compact bicubic mesh is smaller than the same mesh as hermite.
    Document hermite = doc;
    hermite.meshes[0].colorModel = gm::ColorModel::Hermite;
    gmbtest::addFittingNoise(hermite.meshes[0], 5);
    CHECK(gm::encodeGmb(doc, true).size() < gm::encodeGmb(hermite, true).size());
}
