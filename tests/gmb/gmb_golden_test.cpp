// Golden .gmb files of version 1.0 (tests/data/gmb): a later reader must still read them to the
// same documents. gmb_corpus.h says how they were made.
#include <catch2/catch.hpp>

#include "formats/gmb.h"
#include "gmb_corpus.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"

namespace {

const std::string kDir = std::string(GRADMESH_TEST_DATA) + "/gmb/";

std::string golden(const std::string& name) {
    const std::string bytes = gmbtest::readFile(kDir + name);
    REQUIRE_FALSE(bytes.empty());
    return bytes;
}

}  // namespace

TEST_CASE("golden 1.0 lossless file reads to its document", "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.0-lossless.gmb");
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.0-lossless.gmb");
    // Known values, independent of the generator.
    REQUIRE(d.width == 64);
    REQUIRE(d.height == 48);
    REQUIRE(d.meshes.size() == 2);
    const gm::GradientMesh& m = d.meshes[0];
    REQUIRE(m.columns() == 5);
    REQUIRE(m.rows() == 4);
    CHECK(m.u[2] == 0.3);
    CHECK(m.v[2] == 1.0 / 3);
    CHECK(m.node(3, 4).pos.x == Approx(40.46).epsilon(1e-15));
    CHECK(m.node(3, 4).pos.y == Approx(42.9).epsilon(1e-15));
    REQUIRE(m.slits.size() == 1);
    CHECK(m.slits[0].row == 2);
    CHECK(m.slits[0].i0 == 1);
    CHECK(m.slits[0].i1 == 4);
    REQUIRE(m.slits[0].below.size() == 2);
    CHECK(m.slits[0].left.posU.y == -7.7);
    CHECK(m.slits[0].right.colU.b == -0.3);
    REQUIRE(m.tangents.size() == 2);
    CHECK(m.tangents[1].i == 4);
    CHECK(m.tangents[1].posU.y == 4.4);
    CHECK(d.meshes[1].v[1] == 7.001);
    CHECK(d.meshes[1].node(2, 1).posV.y == 6250);
    // All of it, bit for bit.
    REQUIRE(d == gmbtest::goldenLossless());
    // Today's writer still produces these very bytes.
    CHECK(gm::encodeGmb(d, false) == bytes);
}

TEST_CASE("golden 1.0 compact file reads to its document exactly", "[golden][roundtrip]") {
    const gm::Document d =
        gm::decodeGmb(golden("golden-1.0-compact.gmb"), gm::ReadLimits{}, "golden-1.0-compact.gmb");
    CHECK(d.meshes[0].node(5, 4).pos.x == 10 + 10.125 * 5 + 4 / 32.0);
    CHECK(d.meshes[0].slits[0].left.colU.b == 150 / 512.0);
    REQUIRE(d == gmbtest::goldenCompact());
}

TEST_CASE("golden 1.0 compact file with rule colour derivatives recomputes them",
          "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.0-compact-rule.gmb");
    // Mesh 1's MESH section has the colour-by-rule flag (payload byte 17, bit 0).
    const gmbtest::SectionInfo mesh1 = gmbtest::findSection(bytes, "MESH", 1);
    REQUIRE(mesh1.codec == 0);
    CHECK((bytes[mesh1.payload() + 17] & 1) == 1);
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.0-compact-rule.gmb");
    const gm::Document expected = gmbtest::goldenCompactRule();
    REQUIRE(d.meshes[0] == expected.meshes[0]);
    REQUIRE(d.meshes[1].u == expected.meshes[1].u);
    for (size_t k = 0; k < d.meshes[1].nodes.size(); ++k) {
        CHECK(d.meshes[1].nodes[k].pos == expected.meshes[1].nodes[k].pos);
        CHECK(d.meshes[1].nodes[k].col == expected.meshes[1].nodes[k].col);
    }
    CHECK(gm::followsColorRule(d.meshes[1]));
}

TEST_CASE("a 1.1 file with appended fields and unknown optional sections reads", "[golden][malformed]") {
    const std::string bytes = golden("golden-1.1-optional-sections.gmb");
    CHECK(bytes == gmbtest::goldenNewerMinor());
    REQUIRE(gm::decodeGmb(bytes, gm::ReadLimits{}) == gmbtest::goldenLossless());
}

// Writes the golden files and the malformed corpus; run by hand only (see gmb_corpus.h).
TEST_CASE("generate the golden files and the malformed corpus", "[.generate]") {
    gmbtest::writeFile(kDir + "golden-1.0-lossless.gmb", gm::encodeGmb(gmbtest::goldenLossless(), false));
    gmbtest::writeFile(kDir + "golden-1.0-compact.gmb", gm::encodeGmb(gmbtest::goldenCompact(), true));
    gmbtest::writeFile(kDir + "golden-1.0-compact-rule.gmb",
                       gm::encodeGmb(gmbtest::goldenCompactRule(), true));
    gmbtest::writeFile(kDir + "golden-1.1-optional-sections.gmb", gmbtest::goldenNewerMinor());
    for (const gmbtest::Malformed& m : gmbtest::malformedCorpus())
        gmbtest::writeFile(kDir + "malformed/" + m.name, m.bytes);
}
