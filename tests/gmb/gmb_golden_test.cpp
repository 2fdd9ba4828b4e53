// Golden .gmb files of versions 1.0 to 1.4 (tests/data/gmb): a later reader must still read
// them to the same documents. gmb_corpus.h says how they were made.
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
    CHECK(gmbtest::encodeV1(d, false) == bytes);
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
    // Files from before the colour models read as Hermite, their slopes recomputed.
    for (const gm::GradientMesh& m : d.meshes) CHECK(m.colorModel == gm::ColorModel::Hermite);
}

TEST_CASE("golden 1.1 compact file reads to its document exactly", "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.1-compact.gmb");
    CHECK(gmbtest::getLE(bytes, 10, 2) == 1);  // minor version
    for (int k = 0; k < 2; ++k) {
        const gmbtest::SectionInfo mesh = gmbtest::findSection(bytes, "MESH", k);
        CHECK(bytes[mesh.payload() + 16] == 2);  // encoding 2
        CHECK(gmbtest::findSection(bytes, "NODE", k).codec == 0);
    }
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.1-compact.gmb");
    // Known values, independent of the generator: positions and colours as in 1.0; a
    // derivative is its tangent q · 2^-3 (or 2^-7 for colour) over the node's span in knot
    // quanta of 2^-23: column 0 of mesh 0 spans 0.25 (2^21 quanta, + 2).
    CHECK(d.meshes[0].node(5, 4).pos.x == 10 + 10.125 * 5 + 4 / 32.0);
    // posU.x = 30 + 1/64 at (0,1): 30.015625 · 0.25 · 8 = 60.03 -> 60 over 2^21 + 2 quanta
    CHECK(d.meshes[0].node(0, 1).posU.x == 60 * 1048576.0 / 2097154.0);
    // colU.r = 10/512 in column 4 (span 1): 2.5 · (1 + 2^-22) · ... -> 3 over 2^23 + 2 quanta
    CHECK(d.meshes[0].node(4, 0).colU.r == 3 * 65536.0 / 8388610.0);
    // the left slit end (column 1, span 0.25): -7.75 · 0.25 · 8 = -15.5 (and a little) -> -16
    CHECK(d.meshes[0].slits[0].left.posU.y == -16 * 1048576.0 / 2097154.0);
    REQUIRE(d == gmbtest::goldenCompact11());
    // Compact is stable on its own grid: the writer gives back what it read.
    CHECK(gm::decodeGmb(gmbtest::encodeV1(d, true), gm::ReadLimits{}) == d);
}

TEST_CASE("golden 1.1 compact file with rule colour derivatives recomputes them",
          "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.1-compact-rule.gmb");
    const gmbtest::SectionInfo mesh1 = gmbtest::findSection(bytes, "MESH", 1);
    CHECK((bytes[mesh1.payload() + 17] & 1) == 1);
    CHECK(bytes[mesh1.payload() + 16] == 2);
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.1-compact-rule.gmb");
    REQUIRE(d == gmbtest::goldenCompact11Rule());
    CHECK(gm::followsColorRule(d.meshes[1]));
}

TEST_CASE("a 1.1 file with appended fields and unknown optional sections reads", "[golden][malformed]") {
    const std::string bytes = golden("golden-1.1-optional-sections.gmb");
    CHECK(bytes == gmbtest::goldenNewerMinor());
    REQUIRE(gm::decodeGmb(bytes, gm::ReadLimits{}) == gmbtest::goldenLossless());
}

TEST_CASE("golden 1.2 compact file reads to its document exactly", "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.2-compact.gmb");
    CHECK(gmbtest::getLE(bytes, 10, 2) == 2);  // minor version
    // DOCU, one CMSH holding both meshes, END.
    const auto sections = gmbtest::listSections(bytes);
    REQUIRE(sections.size() == 3);
    CHECK(sections[1].tag == "CMSH");
    CHECK(sections[1].codec == 0);
    CHECK(bytes[sections[1].payload()] == 2);  // M
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.2-compact.gmb");
    // The same values as the 1.1 file (same quantisation), known independently of the writer.
    CHECK(d.meshes[0].node(5, 4).pos.x == 10 + 10.125 * 5 + 4 / 32.0);
    CHECK(d.meshes[0].node(0, 1).posU.x == 60 * 1048576.0 / 2097154.0);
    CHECK(d.meshes[0].slits[0].left.posU.y == -16 * 1048576.0 / 2097154.0);
    REQUIRE(d == gmbtest::goldenCompact11());
    REQUIRE(d == gm::decodeGmb(golden("golden-1.1-compact.gmb"), gm::ReadLimits{}));
    CHECK(gm::decodeGmb(gmbtest::encodeV1(d, true), gm::ReadLimits{}) == d);
}

TEST_CASE("golden 1.2 file mixing CMSH runs, a float64 mesh and rule colours reads", "[golden][roundtrip]") {
    const std::string bytes = golden("golden-1.2-compact-mixed.gmb");
    std::vector<std::string> tags;
    for (const gmbtest::SectionInfo& i : gmbtest::listSections(bytes)) tags.push_back(i.tag);
    CHECK(tags == std::vector<std::string>{"DOCU", "CMSH", "MESH", "KNOT", "NODE", "CMSH", "END "});
    const auto records = gmbtest::cmshRecords(bytes);
    REQUIRE(records.size() == 3);
    CHECK_FALSE(records[0].byRule);
    CHECK(records[1].byRule);
    CHECK(records[2].byRule);
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, "golden-1.2-compact-mixed.gmb");
    REQUIRE(d == gmbtest::goldenMixed12());
    CHECK(gm::followsColorRule(d.meshes[1]));
}

namespace {

// A golden file of goldenCompact11 in one range-coded run (`tag`: CMS2 or CMS3, file version
// 1.`minor`): its layout, the spec decoder's reading, and values known independently of the
// writer (the same quantisation as the 1.1 and 1.2 files). Returns the document.
gm::Document checkStreamGolden(const std::string& name, const char* tag, int minor) {
    const std::string bytes = golden(name);
    CHECK(gmbtest::getLE(bytes, 10, 2) == static_cast<uint64_t>(minor));
    // DOCU, one run holding both meshes in one stream, END.
    const auto sections = gmbtest::listSections(bytes);
    REQUIRE(sections.size() == 3);
    CHECK(sections[1].tag == tag);
    CHECK(sections[1].codec == 0);
    CHECK(bytes[sections[1].payload()] == 2);  // M
    const auto meshes = gmbtest::compactRecords(bytes);  // the spec decoder
    REQUIRE(meshes.size() == 2);
    CHECK(meshes[0].slits == 1);
    CHECK(meshes[0].tangents == 2);
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, name);
    CHECK(d.meshes[0].node(5, 4).pos.x == 10 + 10.125 * 5 + 4 / 32.0);
    CHECK(d.meshes[0].node(0, 1).posU.x == 60 * 1048576.0 / 2097154.0);
    CHECK(d.meshes[0].node(4, 0).colU.r == 3 * 65536.0 / 8388610.0);
    CHECK(d.meshes[0].slits[0].left.posU.y == -16 * 1048576.0 / 2097154.0);
    REQUIRE(d == gmbtest::goldenCompact11());
    REQUIRE(d == gm::decodeGmb(golden("golden-1.2-compact.gmb"), gm::ReadLimits{}));
    // In the 1.2 layout, the same data is larger.
    CHECK(gmbtest::cms2AsCmsh(bytes).size() > bytes.size());
    return d;
}

// A golden file of goldenMixed12: two runs of `tag` around a float64 mesh.
void checkMixedStreamGolden(const std::string& name, const char* tag) {
    const std::string bytes = golden(name);
    std::vector<std::string> tags;
    for (const gmbtest::SectionInfo& i : gmbtest::listSections(bytes)) tags.push_back(i.tag);
    CHECK(tags == std::vector<std::string>{"DOCU", tag, "MESH", "KNOT", "NODE", tag, "END "});
    const auto meshes = gmbtest::compactRecords(bytes);
    REQUIRE(meshes.size() == 3);
    CHECK_FALSE(meshes[0].byRule);
    CHECK(meshes[1].byRule);
    CHECK(meshes[2].byRule);
    const gm::Document d = gm::decodeGmb(bytes, gm::ReadLimits{}, name);
    REQUIRE(d == gmbtest::goldenMixed12());
    REQUIRE(d == gm::decodeGmb(golden("golden-1.2-compact-mixed.gmb"), gm::ReadLimits{}));
    CHECK(gm::followsColorRule(d.meshes[1]));
}

}  // namespace

TEST_CASE("golden 1.3 compact file reads to its document exactly", "[golden][roundtrip]") {
    const gm::Document d = checkStreamGolden("golden-1.3-compact.gmb", "CMS2", 3);
    CHECK(gm::decodeGmb(gmbtest::encodeV1(d, true), gm::ReadLimits{}) == d);
}

TEST_CASE("golden 1.3 file mixing CMS2 runs, a float64 mesh and rule colours reads", "[golden][roundtrip]") {
    checkMixedStreamGolden("golden-1.3-compact-mixed.gmb", "CMS2");
}

TEST_CASE("golden 1.4 compact file reads to its document exactly", "[golden][roundtrip]") {
    const gm::Document d = checkStreamGolden("golden-1.4-compact.gmb", "CMS3", 4);
    CHECK(gmbtest::encodeV1(d, true, 0, gm::GmbStreams::Cms3) == golden("golden-1.4-compact.gmb"));
    // This synthetic document is one where CMS2 is smaller (CMS3's priors suit converted
    // images): by default the writer keeps that.
    CHECK(gmbtest::listSections(gmbtest::encodeV1(d, true))[1].tag == "CMS2");
}

TEST_CASE("golden 1.4 file mixing CMS3 runs, a float64 mesh and rule colours reads", "[golden][roundtrip]") {
    checkMixedStreamGolden("golden-1.4-compact-mixed.gmb", "CMS3");
}

// Writes the golden files and the malformed corpus; run by hand only (see gmb_corpus.h). The
// 1.0 to 1.3 compact files came from the writers of their versions and stay as they are;
// lossless files are still 1.0.
TEST_CASE("generate the golden files and the malformed corpus", "[.generate]") {
    gmbtest::writeFile(kDir + "golden-1.0-lossless.gmb",
                       gmbtest::encodeV1(gmbtest::goldenLossless(), false));
    gmbtest::writeFile(kDir + "golden-1.1-optional-sections.gmb", gmbtest::goldenNewerMinor());
    gmbtest::writeFile(kDir + "golden-1.4-compact.gmb",
                       gmbtest::encodeV1(gmbtest::goldenCompact11(), true, 0, gm::GmbStreams::Cms3));
    gmbtest::writeFile(kDir + "golden-1.4-compact-mixed.gmb",
                       gmbtest::encodeV1(gmbtest::goldenMixed12(), true, 0, gm::GmbStreams::Cms3));
    gmbtest::writeFile(kDir + "golden-2.0-compact.gmb",
                       gm::encodeGmb(gmbtest::goldenCompact11(), true, 0, gm::GmbStreams::Cms3));
    gmbtest::writeFile(kDir + "golden-2.0-compact-mixed.gmb",
                       gm::encodeGmb(gmbtest::goldenMixed12(), true, 0, gm::GmbStreams::Cms3));
    for (const gmbtest::Malformed& m : gmbtest::malformedCorpus())
        gmbtest::writeFile(kDir + "malformed/" + m.name, m.bytes);
}
