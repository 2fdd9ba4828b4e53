// Flat shapes in .gmb: the SHAP section of versions 1.5 and 2.1.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "formats/gmb.h"
#include "gmb_corpus.h"
#include "gmb_shape_support.h"
#include "meshcore/error.h"
#include "meshcore/synthetic_meshes.h"

using namespace gm;

namespace {

const std::string kDir = std::string(GRADMESH_TEST_DATA) + "/gmb/";

using gmbtest::decodeError;
using gmbtest::shapeEncodingOf;
using gmbtest::versionOf;
using gmbtest::withShapePayload;

// makeFlatDocument with strokes on top: an open curve of two segments, a closed ring and a
// shape of two straight centrelines, their widths off the 1/256 px grid.
Document strokedDocument() {
    Document doc = makeFlatDocument();
    FlatShape curve;
    curve.col = {0.05, 0.6, 0.3};
    curve.alpha = 0.75;
    curve.strokeWidth = 2.5 + 1e-4;
    curve.layer = 2;
    curve.subpaths = {{{10.1, 20.2}, {40.3, 5.4}, {70.5, 35.6}, {100.7, 20.8}, {130.9, 6.01},
                       {160.3, 50.7}, {190.2, 30.3}}};
    doc.shapes.push_back(curve);
    FlatShape ring;
    ring.col = {0.9, 0.9, 0.1};
    ring.strokeWidth = M_PI;
    ring.layer = 2;
    const Vec2 c{120.3, 90.7};
    ring.subpaths = {{c + Vec2{30, 0}, c + Vec2{30, 16.5}, c + Vec2{16.5, 30}, c + Vec2{0, 30},
                      c + Vec2{-16.5, 30}, c + Vec2{-30, 16.5}, c + Vec2{-30, 0},
                      c + Vec2{-30, -16.5}, c + Vec2{-16.5, -30}, c + Vec2{0, -30},
                      c + Vec2{16.5, -30}, c + Vec2{30, -16.5}, c + Vec2{30, 0}}};
    doc.shapes.push_back(ring);
    FlatShape lines;
    lines.col = {0.2, 0.2, 0.2};
    lines.strokeWidth = 1.0 / 3;
    lines.layer = 2;
    lines.subpaths = {polygonAsCubics({{5, 170}, {235, 170}}),
                      polygonAsCubics({{5, 175}, {235, 175}})};
    for (std::vector<Vec2>& path : lines.subpaths) path.resize(4);  // one open segment each
    doc.shapes.push_back(lines);
    return doc;
}

// A SHAP payload of one shape in encoding 2 (float64 with strokes): `width`, one centreline of
// `segments` segments and `points` points.
std::string strokePayload(double width, uint64_t segments, int points) {
    std::string p;
    p += '\x01';  // one shape
    p += '\x02';  // float64 with strokes
    p += '\x00';  // layer 0
    for (int k = 0; k < 4; ++k) gmbtest::putF64(p, 0.5);
    gmbtest::putF64(p, width);
    p += '\x01';  // one subpath
    for (uint64_t v = segments;; v >>= 7) {
        p += static_cast<char>(v >= 0x80 ? (v & 0x7f) | 0x80 : v);
        if (v < 0x80) break;
    }
    for (int k = 0; k < 2 * points; ++k) gmbtest::putF64(p, 3.0 + k);
    return p;
}

}  // namespace

TEST_CASE("lossless .gmb keeps flat shapes bit for bit as version 1.5", "[roundtrip][flat]") {
    const Document doc = makeFlatDocument();
    const std::string bytes = encodeGmb(doc, false);
    CHECK(versionOf(bytes) == 105);
    CHECK(decodeGmb(bytes, ReadLimits{}, "t.gmb") == doc);
    // Without shapes, the file is the 1.0 file it always was.
    Document meshesOnly = doc;
    meshesOnly.shapes.clear();
    const std::string plain = encodeGmb(meshesOnly, false);
    CHECK(versionOf(plain) == 100);
    CHECK(plain.find("SHAP") == std::string::npos);
    CHECK(gmbtest::encodeV1(meshesOnly, false) == plain);
}

TEST_CASE("compact .gmb keeps flat shapes to 1/256 px as version 2.1", "[roundtrip][flat]") {
    const Document doc = makeFlatDocument();
    for (GmbFraming framing : {GmbFraming::Short, GmbFraming::Long}) {
        const std::string bytes = encodeGmb(doc, true, 0, GmbStreams::Smaller, framing);
        CHECK(versionOf(bytes) == (framing == GmbFraming::Short ? 201 : 105));
        const Document back = decodeGmb(bytes, ReadLimits{}, "t.gmb");
        REQUIRE(back.shapes.size() == doc.shapes.size());
        for (size_t k = 0; k < doc.shapes.size(); ++k) {
            const FlatShape &a = doc.shapes[k], &b = back.shapes[k];
            CHECK(a.layer == b.layer);
            for (int c = 0; c < 3; ++c) CHECK(std::fabs(a.col[c] - b.col[c]) <= 0.5 / 65535);
            REQUIRE(a.subpaths.size() == b.subpaths.size());
            for (size_t s = 0; s < a.subpaths.size(); ++s) {
                REQUIRE(a.subpaths[s].size() == b.subpaths[s].size());
                for (size_t p = 0; p < a.subpaths[s].size(); ++p) {
                    CHECK(std::fabs(a.subpaths[s][p].x - b.subpaths[s][p].x) <= 1.0 / 512);
                    CHECK(std::fabs(a.subpaths[s][p].y - b.subpaths[s][p].y) <= 1.0 / 512);
                }
            }
        }
    }
}

TEST_CASE("golden 1.5 and 2.1 files with flat shapes read", "[golden][flat]") {
    const Document doc = makeFlatDocument();
    const std::string lossless = gmbtest::readFile(kDir + "golden-1.5-flat.gmb");
    REQUIRE_FALSE(lossless.empty());
    CHECK(decodeGmb(lossless, ReadLimits{}, "golden-1.5-flat.gmb") == doc);
    CHECK(encodeGmb(doc, false) == lossless);
    const std::string compact = gmbtest::readFile(kDir + "golden-2.1-flat.gmb");
    REQUIRE_FALSE(compact.empty());
    CHECK(decodeGmb(compact, ReadLimits{}, "golden-2.1-flat.gmb").shapes.size() == 2);
    CHECK(encodeGmb(doc, true) == compact);
}

TEST_CASE("a file with flat shapes truncated at every byte is refused", "[malformed][flat]") {
    for (bool compact : {false, true}) {
        const std::string full = encodeGmb(makeFlatDocument(), compact);
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n << (compact ? " (compact)" : ""));
            CHECK_FALSE(decodeError(full.substr(0, n)).empty());
        }
    }
}

TEST_CASE("SHAP counts beyond the payload are refused before allocating", "[malformed][flat]") {
    auto shape = [](uint64_t subpaths, uint64_t segments) {
        std::string p;
        p += '\x01';  // one shape
        p += '\x00';  // float64
        p += '\x00';  // layer 0
        for (int k = 0; k < 4; ++k) gmbtest::putF64(p, 0.5);
        for (uint64_t v : {subpaths, segments}) {
            for (; v >= 0x80; v >>= 7) p += static_cast<char>((v & 0x7f) | 0x80);
            p += static_cast<char>(v);
        }
        return p;
    };
    CHECK_THAT(decodeError(withShapePayload(shape(uint64_t(1) << 40, 1))),
               Catch::Contains("truncated"));
    CHECK_THAT(decodeError(withShapePayload(shape(1, uint64_t(1) << 50))),
               Catch::Contains("truncated"));
    CHECK_THAT(decodeError(withShapePayload(shape(0, 1) + std::string(48, '\0'))),
               Catch::Contains("without subpaths"));
    std::string badLayer = shape(1, 1);
    badLayer[2] = '\x07';
    for (int k = 0; k < 6; ++k) gmbtest::putF64(badLayer, 1.0);
    CHECK_THAT(decodeError(withShapePayload(badLayer)),
               Catch::Contains("mesh that does not exist"));
}

TEST_CASE("compact .gmb keeps shapes beyond the quantized range in float64", "[roundtrip][flat]") {
    // A lossless file may hold any finite point; 2^60 px lies far beyond what 1/256 px steps
    // in 64 bits can reach, so the compact writer keeps that SHAP section exact instead.
    Document doc = makeFlatDocument();
    doc.shapes[0].subpaths[0][1].x = std::ldexp(1.0, 60);
    doc.shapes[0].subpaths[0][2].y = -std::ldexp(1.0, 60);
    const Document back = decodeGmb(encodeGmb(doc, true), ReadLimits{}, "t.gmb");
    CHECK(back.shapes == doc.shapes);
    // A file the fuzzer found: a lossless shape point beyond 2^63 / 256 px, whose deltas the
    // compact grid cannot hold.
    const std::string name = "shape-far-beyond-quantized-range.gmb";
    const Document fuzzed = decodeGmb(gmbtest::readFile(kDir + name), ReadLimits{}, name);
    CHECK(decodeGmb(encodeGmb(fuzzed, true), ReadLimits{}, "t.gmb").shapes == fuzzed.shapes);
}

TEST_CASE("a quantized SHAP delta that would overflow is refused", "[malformed][flat]") {
    auto svarint = [](std::string& p, int64_t v) {
        uint64_t z = (static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63);
        for (; z >= 0x80; z >>= 7) p += static_cast<char>((z & 0x7f) | 0x80);
        p += static_cast<char>(z);
    };
    std::string p;
    p += '\x01';  // one shape
    p += '\x01';  // quantized
    p += '\x00';  // layer 0
    p += std::string(8, '\x7f');  // colour and opacity
    p += '\x01';  // one subpath
    p += '\x01';  // one segment: three points
    svarint(p, 1000);
    svarint(p, 0);
    svarint(p, INT64_MAX);  // x + INT64_MAX overflows int64
    svarint(p, 0);
    svarint(p, 0);
    svarint(p, 0);
    CHECK_THAT(decodeError(withShapePayload(p)), Catch::Contains("shape point out of range"));
}

TEST_CASE("the flat-shape count has its own limit, not the mesh count's", "[malformed][flat]") {
    // Two meshes and five shapes: within a limit of two meshes, refused at four shapes.
    Document doc = makeFlatDocument();
    for (int k = 0; k < 3; ++k) doc.shapes.push_back(doc.shapes.back());
    ReadLimits limits;
    limits.maxMeshes = 2;
    for (bool compact : {false, true}) {
        const std::string bytes = encodeGmb(doc, compact);
        CHECK(decodeGmb(bytes, limits, "t.gmb").shapes.size() == 5);
        ReadLimits fewShapes = limits;
        fewShapes.maxShapes = 4;
        try {
            decodeGmb(bytes, fewShapes, "t.gmb");
            FAIL("five shapes read under a limit of four");
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains("5 shapes: must be 1 to 4"));
        }
    }
}

TEST_CASE("lossless .gmb keeps strokes bit for bit", "[roundtrip][flat][stroke]") {
    const Document doc = strokedDocument();
    const std::string bytes = encodeGmb(doc, false);
    CHECK(versionOf(bytes) == 105);
    CHECK(shapeEncodingOf(bytes) == 2);
    const Document back = decodeGmb(bytes, ReadLimits{}, "t.gmb");
    CHECK(back == doc);
    CHECK(back.shapes[3].subpaths[0].size() == 13);
    // Without strokes the payload keeps its encodings 0 and 1 (the golden files pin the bytes).
    CHECK(shapeEncodingOf(encodeGmb(makeFlatDocument(), false)) == 0);
}

TEST_CASE("compact .gmb keeps strokes to 1/256 px", "[roundtrip][flat][stroke]") {
    const Document doc = strokedDocument();
    for (GmbFraming framing : {GmbFraming::Short, GmbFraming::Long}) {
        const Document back =
            decodeGmb(encodeGmb(doc, true, 0, GmbStreams::Smaller, framing), ReadLimits{}, "t.gmb");
        REQUIRE(back.shapes.size() == doc.shapes.size());
        for (size_t k = 0; k < doc.shapes.size(); ++k) {
            const FlatShape &a = doc.shapes[k], &b = back.shapes[k];
            CHECK(a.stroked() == b.stroked());
            CHECK(std::fabs(a.strokeWidth - b.strokeWidth) <= 1.0 / 512);
            CHECK(std::fabs(a.alpha - b.alpha) <= 0.5 / 65535);
            REQUIRE(a.subpaths.size() == b.subpaths.size());
            for (size_t s = 0; s < a.subpaths.size(); ++s) {
                REQUIRE(a.subpaths[s].size() == b.subpaths[s].size());
                for (size_t p = 0; p < a.subpaths[s].size(); ++p) {
                    CHECK(std::fabs(a.subpaths[s][p].x - b.subpaths[s][p].x) <= 1.0 / 512);
                    CHECK(std::fabs(a.subpaths[s][p].y - b.subpaths[s][p].y) <= 1.0 / 512);
                }
            }
        }
    }
    // A stroke thinner than half a step stays a stroke, one step wide.
    Document thin = doc;
    thin.shapes[2].strokeWidth = 1e-3;
    CHECK(decodeGmb(encodeGmb(thin, true), ReadLimits{}, "t.gmb").shapes[2].strokeWidth ==
          1.0 / 256);
}

TEST_CASE("golden 1.5 and 2.1 files with strokes read", "[golden][flat][stroke]") {
    const Document doc = strokedDocument();
    const std::string lossless = gmbtest::readFile(kDir + "golden-1.5-stroke.gmb");
    REQUIRE_FALSE(lossless.empty());
    CHECK(decodeGmb(lossless, ReadLimits{}, "golden-1.5-stroke.gmb") == doc);
    CHECK(encodeGmb(doc, false) == lossless);
    const std::string compact = gmbtest::readFile(kDir + "golden-2.1-stroke.gmb");
    REQUIRE_FALSE(compact.empty());
    CHECK(decodeGmb(compact, ReadLimits{}, "golden-2.1-stroke.gmb").shapes.size() == 5);
    CHECK(encodeGmb(doc, true) == compact);
}

TEST_CASE("a file with strokes truncated at every byte is refused", "[malformed][flat][stroke]") {
    for (bool compact : {false, true}) {
        const std::string full = encodeGmb(strokedDocument(), compact);
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n << (compact ? " (compact)" : ""));
            CHECK_FALSE(decodeError(full.substr(0, n)).empty());
        }
    }
}

TEST_CASE("bad stroke widths and centrelines are refused", "[malformed][flat][stroke]") {
    REQUIRE(decodeError(withShapePayload(strokePayload(2.5, 1, 4))).empty());
    for (double width : {-1.0, double(NAN), 1e4 + 1, double(INFINITY)}) {
        INFO("width " << width);
        CHECK_THAT(decodeError(withShapePayload(strokePayload(width, 1, 4))),
                   Catch::Contains("stroke width"));
    }
    // A centreline of no segments, or fewer points than 3n + 1.
    CHECK_THAT(decodeError(withShapePayload(strokePayload(2, 0, 4))),
               Catch::Contains("centreline without segments"));
    CHECK_THAT(decodeError(withShapePayload(strokePayload(2, 1, 3))), Catch::Contains("truncated"));
    CHECK_THAT(decodeError(withShapePayload(strokePayload(2, uint64_t(1) << 60, 4))),
               Catch::Contains("truncated"));
    // Width 0 in a stroke encoding: a filled shape of 3n points.
    CHECK(decodeError(withShapePayload(strokePayload(0, 1, 3))).empty());
    // Quantized: a width beyond 10000 px in 1/256 px.
    std::string q;
    q += '\x01';                  // one shape
    q += '\x03';                  // quantized with strokes
    q += '\x00';                  // layer 0
    q += std::string(8, '\x7f');  // colour and opacity
    for (uint64_t v = 10000 * 256 + 1;; v >>= 7) {
        q += static_cast<char>(v >= 0x80 ? (v & 0x7f) | 0x80 : v);
        if (v < 0x80) break;
    }
    q += "\x01\x01" + std::string(8, '\x00');  // one subpath of one segment: four points
    CHECK_THAT(decodeError(withShapePayload(q)), Catch::Contains("stroke width"));
    CHECK_THAT(decodeError(withShapePayload(std::string("\x01\x08") + std::string(60, '\0'))),
               Catch::Contains("unknown shape encoding 8"));
}

TEST_CASE("write the golden flat-shape files", "[.generate-flat]") {
    const Document doc = makeFlatDocument();
    std::ofstream(kDir + "golden-1.5-flat.gmb", std::ios::binary) << encodeGmb(doc, false);
    std::ofstream(kDir + "golden-2.1-flat.gmb", std::ios::binary) << encodeGmb(doc, true);
}

TEST_CASE("write the golden stroke files", "[.generate-stroke]") {
    const Document doc = strokedDocument();
    std::ofstream(kDir + "golden-1.5-stroke.gmb", std::ios::binary) << encodeGmb(doc, false);
    std::ofstream(kDir + "golden-2.1-stroke.gmb", std::ios::binary) << encodeGmb(doc, true);
}
