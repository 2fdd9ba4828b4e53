// Flat shapes painted with linear gradients in .gmb: SHAP encodings 4 to 7.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <vector>

#include "formats/gmb.h"
#include "gmb_shape_support.h"
#include "gmb_spec_coded.h"
#include "meshcore/validate.h"
#include "support/gradient_shapes.h"
#include "support/stroke_shapes.h"

using namespace gm;
using gmbtest::decodeError;
using gmbtest::shapeEncodingOf;
using gmbtest::versionOf;
using gmbtest::withShapePayload;

namespace {

const std::string kDir = std::string(GRADMESH_TEST_DATA) + "/gmb/";

// The gradient test document with the stroke test document's strokes on top.
Document gradedAndStrokedDocument() {
    Document doc = gmtest::gradientTestDocument();
    for (const FlatShape& s : gmtest::strokeTestShapes())
        if (s.stroked()) doc.shapes.push_back(s);
    return doc;
}

Document decoded(const std::string& bytes) { return decodeGmb(bytes, ReadLimits{}, "t.gmb"); }

// A compact round trip of shape `a`: points and gradient ends within half a 1/256 px step,
// colours, offsets and widths within half a step of theirs.
void checkCompactShape(const FlatShape& a, const FlatShape& b) {
    CHECK(a.layer == b.layer);
    CHECK(a.stroked() == b.stroked());
    CHECK(std::fabs(a.strokeWidth - b.strokeWidth) <= 1.0 / 512);
    for (int c = 0; c < 3; ++c) CHECK(std::fabs(a.col[c] - b.col[c]) <= 0.5 / 65535);
    CHECK(std::fabs(a.alpha - b.alpha) <= 0.5 / 65535);
    REQUIRE(a.gradient.stops.size() == b.gradient.stops.size());
    for (size_t k = 0; k < a.gradient.stops.size(); ++k) {
        const GradientStop &p = a.gradient.stops[k], &q = b.gradient.stops[k];
        CHECK(std::fabs(p.offset - q.offset) <= 0.5 / 65535);
        for (int c = 0; c < 3; ++c) CHECK(std::fabs(p.col[c] - q.col[c]) <= 0.5 / 65535);
    }
    if (a.graded())
        for (auto [p, q] : {std::pair{a.gradient.from, b.gradient.from},
                            std::pair{a.gradient.to, b.gradient.to}}) {
            CHECK(std::fabs(p.x - q.x) <= 1.0 / 512);
            CHECK(std::fabs(p.y - q.y) <= 1.0 / 512);
        }
    REQUIRE(a.subpaths.size() == b.subpaths.size());
    for (size_t s = 0; s < a.subpaths.size(); ++s) {
        REQUIRE(a.subpaths[s].size() == b.subpaths[s].size());
        for (size_t p = 0; p < a.subpaths[s].size(); ++p) {
            CHECK(std::fabs(a.subpaths[s][p].x - b.subpaths[s][p].x) <= 1.0 / 512);
            CHECK(std::fabs(a.subpaths[s][p].y - b.subpaths[s][p].y) <= 1.0 / 512);
        }
    }
}

void checkCompactRoundTrip(const Document& doc) {
    for (GmbFraming framing : {GmbFraming::Short, GmbFraming::Long}) {
        const std::string bytes = encodeGmb(doc, true, 0, GmbStreams::Smaller, framing);
        CHECK(versionOf(bytes) == (framing == GmbFraming::Short ? 201 : 105));
        const Document back = decoded(bytes);
        REQUIRE(back.shapes.size() == doc.shapes.size());
        for (size_t k = 0; k < doc.shapes.size(); ++k) {
            INFO("shape " << k);
            checkCompactShape(doc.shapes[k], back.shapes[k]);
        }
        // Rounding is idempotent: the decoded document writes the same file.
        CHECK(encodeGmb(back, true, 0, GmbStreams::Smaller, framing) == bytes);
    }
}

void putF64s(std::string& p, std::initializer_list<double> values) {
    for (double v : values) gmbtest::putF64(p, v);
}

// A SHAP payload of one filled square in encoding 4 (float64 with gradients), or in encoding 6
// with a stroke `width` when that is above 0: its gradient runs from `from` to (10, 0) through
// stops at `offsets`, grey, of which it declares `count`.
std::string gradientPayload(const std::vector<double>& offsets, uint64_t count, double width = 0,
                            Vec2 from = {0, 0}) {
    std::string p;
    p += '\x01';                       // one shape
    p += width > 0 ? '\x06' : '\x04';  // float64 with gradients (and strokes)
    p += '\x00';                       // layer 0
    putF64s(p, {0.5, 0.5, 0.5, 1});
    if (width > 0) gmbtest::putF64(p, width);
    gmbtest::putVarint(p, count);
    putF64s(p, {from.x, from.y, 10, 0});
    for (double offset : offsets) putF64s(p, {offset, 0.5, 0.5, 0.5});
    p += '\x01';  // one subpath
    p += '\x01';  // one segment
    putF64s(p, {0, 0, 10, 0, 10, 10});
    return p;
}

}  // namespace

TEST_CASE("lossless .gmb keeps gradients bit for bit", "[roundtrip][flat][gradient]") {
    const Document doc = gmtest::gradientTestDocument();
    const std::string bytes = encodeGmb(doc, false);
    CHECK(versionOf(bytes) == 105);
    CHECK(shapeEncodingOf(bytes) == 4);
    CHECK(decoded(bytes) == doc);
    // The same shapes in their mean colours keep encoding 0.
    Document plain = doc;
    for (FlatShape& s : plain.shapes) s.gradient = {};
    CHECK(shapeEncodingOf(encodeGmb(plain, false)) == 0);
}

TEST_CASE("compact .gmb keeps gradients within a rounding step", "[roundtrip][flat][gradient]") {
    checkCompactRoundTrip(gmtest::gradientTestDocument());
}

TEST_CASE("gradients and strokes share one SHAP section", "[roundtrip][flat][gradient][stroke]") {
    const Document doc = gradedAndStrokedDocument();
    const std::string bytes = encodeGmb(doc, false);
    CHECK(shapeEncodingOf(bytes) == 6);
    CHECK(decoded(bytes) == doc);
    checkCompactRoundTrip(doc);
    // The same shapes above two meshes.
    Document meshes = makeFlatDocument();
    const size_t flat = meshes.shapes.size();
    for (FlatShape s : gradedAndStrokedDocument().shapes) {
        s.layer = 2;
        meshes.shapes.push_back(s);
    }
    CHECK(decoded(encodeGmb(meshes, false)) == meshes);
    const Document back = decoded(encodeGmb(meshes, true));
    REQUIRE(back.shapes.size() == meshes.shapes.size());
    for (size_t k = flat; k < meshes.shapes.size(); ++k)
        checkCompactShape(meshes.shapes[k], back.shapes[k]);
}

TEST_CASE("compact gradients stay valid where rounding would break them",
          "[roundtrip][flat][gradient]") {
    Document doc = gmtest::gradientTestDocument();
    // Offsets closer than 1/65535: they stay strictly increasing, each moved by a step or two.
    LinearGradient& crowded = doc.shapes[2].gradient;
    crowded.stops = {{0, {1, 0, 0}},      {1e-6, {0, 1, 0}},       {2e-6, {0, 0, 1}},
                     {0.5, {1, 1, 0}},    {0.5 + 1e-7, {0, 1, 1}}, {1 - 1e-6, {1, 0, 1}},
                     {1, {0.2, 0.2, 0.2}}};
    // An axis just over the shortest, whose ends round 0.098 px apart to the nearest points:
    // they are rounded away from each other instead.
    LinearGradient& shortAxis = doc.shapes[1].gradient;
    shortAxis.from = {10.002, 40};
    shortAxis.to = {10.1021, 40};
    REQUIRE(validateDocument(doc).empty());
    const Document back = decoded(encodeGmb(doc, true));
    const LinearGradient& c = back.shapes[2].gradient;
    REQUIRE(c.stops.size() == crowded.stops.size());
    CHECK(gradientProblem(c).empty());
    for (size_t k = 0; k < c.stops.size(); ++k) {
        INFO("stop " << k);
        CHECK(std::fabs(c.stops[k].offset - crowded.stops[k].offset) <= 2.5 / 65535);
    }
    const LinearGradient& s = back.shapes[1].gradient;
    CHECK(gradientProblem(s).empty());
    CHECK(s.from.x == 10.0);
    CHECK(s.to.x == 10.10546875);  // 2587 / 256
    CHECK(std::fabs(s.from.x - shortAxis.from.x) <= 1.0 / 256);
    CHECK(std::fabs(s.to.x - shortAxis.to.x) <= 1.0 / 256);
}

TEST_CASE("golden 1.5 and 2.1 files with gradients read", "[golden][flat][gradient]") {
    struct Golden {
        const char* name;
        Document doc;
    };
    for (const Golden& g : {Golden{"gradient", gmtest::gradientTestDocument()},
                            Golden{"gradient-stroke", gradedAndStrokedDocument()}}) {
        INFO(g.name);
        const std::string lossName = std::string("golden-1.5-") + g.name + ".gmb";
        const std::string lossless = gmbtest::readFile(kDir + lossName);
        REQUIRE_FALSE(lossless.empty());
        CHECK(decodeGmb(lossless, ReadLimits{}, lossName) == g.doc);
        CHECK(encodeGmb(g.doc, false) == lossless);
        const std::string compactName = std::string("golden-2.1-") + g.name + ".gmb";
        const std::string compact = gmbtest::readFile(kDir + compactName);
        REQUIRE_FALSE(compact.empty());
        const Document back = decodeGmb(compact, ReadLimits{}, compactName);
        REQUIRE(back.shapes.size() == g.doc.shapes.size());
        for (size_t k = 0; k < back.shapes.size(); ++k)
            checkCompactShape(g.doc.shapes[k], back.shapes[k]);
        CHECK(encodeGmb(g.doc, true) == compact);
    }
}

TEST_CASE("a file with gradients truncated at every byte is refused",
          "[malformed][flat][gradient]") {
    for (bool compact : {false, true}) {
        const std::string full = encodeGmb(gradedAndStrokedDocument(), compact);
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n << (compact ? " (compact)" : ""));
            CHECK_FALSE(decodeError(full.substr(0, n)).empty());
        }
    }
}

TEST_CASE("bad gradients are refused with what is wrong", "[malformed][flat][gradient]") {
    REQUIRE(decodeError(withShapePayload(gradientPayload({0, 0.3, 1}, 3))).empty());
    auto refused = [](const std::string& payload, const std::string& what) {
        const std::string e = decodeError(withShapePayload(payload));
        CHECK_THAT(e, Catch::StartsWith("t.gmb: ") && Catch::Contains(what) &&
                          Catch::Contains("section SHAP"));
    };
    // Stop counts outside 2-16, refused before anything is sized.
    refused(gradientPayload({0, 1}, 17), "shape 0: 17 gradient stops: must be 0 or 2 to 16");
    refused(gradientPayload({0, 1}, uint64_t(1) << 60), "gradient stops: must be 0 or 2 to 16");
    refused(gradientPayload({0, 1}, 1), "1 gradient stops");
    // Offsets.
    refused(gradientPayload({0, 0.6, 0.4, 1}, 4), "shape 0: gradient: offsets do not increase");
    refused(gradientPayload({0, 0.5, 0.5, 1}, 4), "offsets do not increase");
    refused(gradientPayload({0, double(NAN), 1}, 3), "offsets do not increase");
    refused(gradientPayload({0.1, 0.5, 1}, 3), "offsets do not run from 0 to 1");
    refused(gradientPayload({0, 0.5, 0.9}, 3), "offsets do not run from 0 to 1");
    // Ends.
    refused(gradientPayload({0, 1}, 2, 0, {10, 0}), "its ends are the same point");
    refused(gradientPayload({0, 1}, 2, 0, {double(INFINITY), 0}), "coordinate limit");
    // A gradient on a stroke.
    refused(gradientPayload({0, 1}, 2, 3), "shape 0: a stroke painted with a gradient");
    // Cut inside the stops: 96 bytes of ends and stops declared, fewer remain.
    refused(gradientPayload({0, 1}, 2).substr(0, 116), "truncated");
    // An encoding beyond the known ones.
    refused(std::string("\x01\x08") + std::string(100, '\0'), "unknown shape encoding 8");
}

TEST_CASE("bad compact gradients are refused", "[malformed][flat][gradient]") {
    // One square in encoding 5 (quantized with gradients), its stop offsets `offsets` in 1/65535.
    auto payload = [](const std::vector<uint16_t>& offsets) {
        std::string p;
        p += '\x01';                  // one shape
        p += '\x05';                  // quantized with gradients
        p += '\x00';                  // layer 0
        p += std::string(8, '\x7f');  // colour and opacity
        gmbtest::putVarint(p, offsets.size());
        for (int64_t delta : {0, 0, 2560, 0}) gmbtest::putSvarint(p, delta);  // (0, 0) to (10, 0)
        for (uint16_t q : offsets) {
            gmbtest::putLE(p, q, 2);
            p += std::string(6, '\x7f');
        }
        p += "\x01\x01";            // one subpath of one segment
        p += std::string(6, '\0');  // its three points, all at (10, 0)
        return p;
    };
    REQUIRE(decodeError(withShapePayload(payload({0, 20000, 65535}))).empty());
    CHECK_THAT(decodeError(withShapePayload(payload({0, 40000, 30000, 65535}))),
               Catch::Contains("gradient: offsets do not increase"));
    CHECK_THAT(decodeError(withShapePayload(payload({0, 65534}))),
               Catch::Contains("gradient: offsets do not run from 0 to 1"));
}

TEST_CASE("write the golden gradient files", "[.generate-gradient]") {
    for (const auto& [name, doc] : {std::pair{"gradient", gmtest::gradientTestDocument()},
                                    std::pair{"gradient-stroke", gradedAndStrokedDocument()}}) {
        std::ofstream(kDir + "golden-1.5-" + name + ".gmb", std::ios::binary)
            << encodeGmb(doc, false);
        std::ofstream(kDir + "golden-2.1-" + name + ".gmb", std::ios::binary)
            << encodeGmb(doc, true);
    }
}
