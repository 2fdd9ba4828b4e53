// Malformed .gmb input: every problem is a gm::Error naming the file and saying what is wrong;
// nothing crashes or allocates by a count it has not checked.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <map>
#include <random>

#include "formats/gmb.h"
#include "gmb_corpus.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

using Catch::Matchers::Contains;

namespace {

const std::string kDir = std::string(GRADMESH_TEST_DATA) + "/gmb/";

std::string decodeError(const std::string& bytes, const gm::ReadLimits& limits = {},
                        const std::string& name = "bad.gmb") {
    try {
        gm::decodeGmb(bytes, limits, name);
    } catch (const gm::Error& e) {
        CHECK(e.file() == name);
        return e.what();
    }
    FAIL("decoding succeeded");
    return {};
}

std::vector<std::string> filesIn(const std::string& dir) {
    std::vector<std::string> out;
    if (!std::filesystem::is_directory(dir)) return out;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.is_regular_file()) out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST_CASE("each malformed case gives its own clear error", "[malformed]") {
    for (const gmbtest::Malformed& m : gmbtest::malformedCorpus()) {
        INFO(m.name);
        CHECK_THAT(decodeError(m.bytes, {}, m.name), Contains(m.expected));
    }
}

TEST_CASE("the malformed corpus on disk is refused with the expected messages", "[malformed]") {
    std::map<std::string, std::string> expected;
    for (const gmbtest::Malformed& m : gmbtest::malformedCorpus()) expected[m.name] = m.expected;
    const auto files = filesIn(kDir + "malformed");
    REQUIRE(files.size() >= expected.size());
    for (const std::string& path : files) {
        const std::string name = std::filesystem::path(path).filename().string();
        INFO(name);
        const std::string message = decodeError(gmbtest::readFile(path), {}, path);
        if (expected.count(name)) CHECK_THAT(message, Contains(expected[name]));
    }
}

TEST_CASE("inputs that once crashed the reader are refused or read cleanly", "[malformed]") {
    // Files found by gmb_fuzzer (tests/fuzz); each must give a gm::Error or a valid document.
    for (const std::string& path : filesIn(kDir + "crash")) {
        INFO(path);
        try {
            const gm::Document d = gm::decodeGmb(gmbtest::readFile(path), gm::ReadLimits{}, path);
            CHECK(gm::decodeGmb(gmbtest::encodeV1(d, false), gm::ReadLimits{}) == d);
        } catch (const gm::Error& e) {
            CHECK_THAT(e.what(), Contains(path));
        }
    }
}

TEST_CASE("a file truncated at every byte is refused as truncated", "[malformed]") {
    for (bool compact : {false, true}) {
        const std::string full = gmbtest::encodeV1(gmbtest::goldenCompact(), compact);
        if (compact) CHECK(gmbtest::listSections(full)[1].tag.substr(0, 3) == "CMS");
        INFO((compact ? "compact, " : "lossless, ") << full.size() << " bytes");
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n);
            const std::string message = decodeError(full.substr(0, n));
            CHECK_THAT(message, Contains(n == 0 ? "empty file" : "truncated"));
        }
    }
}

namespace {

// Two runs of range-coded meshes around a float64 mesh (goldenMixed12), with their tag: the 1.3
// file (CMS2) and today's writer's (CMS3).
std::vector<std::pair<std::string, std::string>> streamFiles() {
    return {{"CMS2", gmbtest::readFile(kDir + "golden-1.3-compact-mixed.gmb")},
            {"CMS3", gmbtest::encodeV1(gmbtest::goldenMixed12(), true, 0, gm::GmbStreams::Cms3)}};
}

}  // namespace

TEST_CASE("a CMS2 or CMS3 file truncated at every byte is refused", "[malformed]") {
    // Cut anywhere, and also with the cut section's sizes and CRC made to fit (so that the
    // stream itself ends early).
    for (const auto& [tag, full] : streamFiles()) {
        INFO(tag);
        REQUIRE(gmbtest::listSections(full)[1].tag == tag);
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n);
            CHECK_THAT(decodeError(full.substr(0, n)), Contains(n == 0 ? "empty file" : "truncated"));
        }
        for (int nth : {0, 1}) {
            const gmbtest::SectionInfo run = gmbtest::findSection(full, tag, nth);
            const std::string payload = full.substr(run.payload(), static_cast<size_t>(run.stored));
            for (size_t n = 0; n < payload.size(); ++n) {
                INFO(tag << " " << nth << " payload cut at " << n);
                CHECK_THAT(decodeError(gmbtest::withPayload(full, tag, nth, payload.substr(0, n))),
                           Contains(tag) && Contains("truncated"));
            }
        }
    }
}

TEST_CASE("every single-bit flip of a CMS2 or CMS3 section is refused or reads to a valid document",
          "[malformed]") {
    int refused = 0, read = 0;
    for (const auto& [tag, good] : streamFiles()) {
        for (int nth : {0, 1}) {
            const gmbtest::SectionInfo cms2 = gmbtest::findSection(good, tag, nth);
            for (size_t at = cms2.offset; at < cms2.end(); ++at)
                for (int bit = 0; bit < 8; ++bit) {
                    INFO("byte " << at << " bit " << bit);
                    std::string s = good;
                    s[at] = static_cast<char>(s[at] ^ (1 << bit));
                    // As damaged (the CRC catches it), and behind a recomputed CRC when the framing
                    // still holds.
                    CHECK_THAT(decodeError(s), Contains("bad.gmb"));
                    if (at >= cms2.payload() && at < cms2.end() - 4) {
                        gmbtest::fixCrc(s, cms2.offset);
                        try {
                            const gm::Document d = gm::decodeGmb(s, gm::ReadLimits{}, "flipped.gmb");
                            CHECK(gm::validateDocument(d).empty());
                            CHECK(gm::decodeGmb(gmbtest::encodeV1(d, false), gm::ReadLimits{}) == d);
                            ++read;
                        } catch (const gm::Error& e) {
                            CHECK(e.file() == "flipped.gmb");
                            CHECK_THAT(e.what(), Contains(tag) || Contains("mesh "));
                            CHECK_FALSE(e.where().empty());
                            ++refused;
                        }
                    }
                }
        }
    }
    WARN("single-bit flips of CMS2 and CMS3 payloads: " << refused << " refused, " << read << " read");
    CHECK(refused > 0);
}

TEST_CASE("a crafted CMS2 stream without a flaw reads", "[malformed]") {
    // The malformed cms2-* cases built with SpecCms2Writer differ from this file by their flaw.
    const gm::Document d = gm::decodeGmb(gmbtest::craftedSoundCms2(), gm::ReadLimits{}, "crafted.gmb");
    REQUIRE(d.meshes.size() == 1);
    CHECK(d.meshes[0].columns() == 2);
    CHECK(d.meshes[0].tangents.size() == 1);
}

namespace {

// Bytes [begin, end) of the section at `sectionOffset` changed at random behind a recomputed CRC,
// 300 times: whatever they decode to, the reader ends in a gm::Error naming the file (and, in the
// message, one of `expected`) or in a document that passes validation. Returns the errors.
int damageRandomly(const std::string& good, size_t sectionOffset, size_t begin, size_t end,
                   const std::vector<std::string>& expected) {
    std::mt19937 rng(5);
    int errors = 0;
    for (int round = 0; round < 300; ++round) {
        std::string s = good;
        const int changes = 1 + round % 4;
        for (int k = 0; k < changes; ++k) {
            const size_t at = begin + rng() % (end - begin);
            s[at] = static_cast<char>(s[at] ^ (1 + rng() % 255));
        }
        gmbtest::fixCrc(s, sectionOffset);
        try {
            const gm::Document d = gm::decodeGmb(s, gm::ReadLimits{}, "damaged.gmb");
            CHECK(gm::decodeGmb(gmbtest::encodeV1(d, false), gm::ReadLimits{}) == d);
        } catch (const gm::Error& e) {
            CHECK(e.file() == "damaged.gmb");
            const std::string what = e.what();
            INFO(what);
            CHECK(std::any_of(expected.begin(), expected.end(),
                              [&](const std::string& x) { return what.find(x) != std::string::npos; }));
            ++errors;
        }
    }
    return errors;
}

}  // namespace

TEST_CASE("damaged range-coded nodes give an error or a valid document", "[malformed]") {
    // A NODE of encoding 2 (version 1.1).
    const std::string v11 = gmbtest::readFile(kDir + "golden-1.1-compact.gmb");
    const gmbtest::SectionInfo node = gmbtest::findSection(v11, "NODE");
    CHECK(damageRandomly(v11, node.offset, node.payload(), node.end() - 4, {"NODE"}) > 0);
    // The mesh records of a CMSH section (version 1.2), from mesh 0's plane weights on: a
    // damaged stream of mesh 0 also moves where its slit and mesh 1 begin, so the error may
    // come from a check of the decoded mesh ("mesh 0: ...").
    const std::string v12 = gmbtest::readFile(kDir + "golden-1.2-compact.gmb");
    const gmbtest::SectionInfo cmsh = gmbtest::findSection(v12, "CMSH");
    const auto records =
        gmbtest::specDecodeCmsh(v12.substr(cmsh.payload(), static_cast<size_t>(cmsh.stored)));
    CHECK(damageRandomly(v12, cmsh.offset, cmsh.payload() + records[0].weightsAt, cmsh.end() - 4,
                         {"CMSH", "mesh 0: ", "mesh 1: "}) > 0);
    // A CMS2 section (version 1.3) and a CMS3 section (1.4), from the stream's first byte on.
    const std::string v13 = gmbtest::readFile(kDir + "golden-1.3-compact.gmb");
    const gmbtest::SectionInfo cms2 = gmbtest::findSection(v13, "CMS2");
    CHECK(damageRandomly(v13, cms2.offset, cms2.payload() + 7, cms2.end() - 4,
                         {"CMS2", "mesh 0: ", "mesh 1: "}) > 0);
    const std::string v14 = gmbtest::encodeV1(gmbtest::goldenCompact11(), true, 0, gm::GmbStreams::Cms3);
    const gmbtest::SectionInfo cms3 = gmbtest::findSection(v14, "CMS3");
    CHECK(damageRandomly(v14, cms3.offset, cms3.payload() + 7, cms3.end() - 4,
                         {"CMS3", "mesh 0: ", "mesh 1: "}) > 0);
}

TEST_CASE("counts that would need terabytes are refused before allocating", "[malformed]") {
    // Limits raised far beyond the defaults: only the bytes that remain can stop the reader.
    gm::ReadLimits huge;
    huge.maxGridSide = uint64_t(1) << 30;
    huge.maxNodesPerMesh = uint64_t(1) << 62;
    huge.maxSlitsPerMesh = uint64_t(1) << 40;
    huge.maxMeshes = uint64_t(1) << 40;
    huge.maxFileBytes = uint64_t(1) << 62;
    huge.maxPatches = uint64_t(1) << 62;
    const std::string good = gmbtest::specEncode(gmbtest::goldenLossless());
    auto edit = [&](const std::string& tag, size_t at, uint64_t value, int width) {
        std::string s = good;
        const gmbtest::SectionInfo i = gmbtest::findSection(s, tag);
        gmbtest::setLE(s, i.offset + at, value, width);
        gmbtest::fixCrc(s, i.offset);
        return s;
    };
    // 2^30 x 2^30 nodes: 2^60 nodes of 120 bytes, but the NODE section holds 3600.
    std::string both = edit("MESH", 24, uint64_t(1) << 30, 4);
    {
        const gmbtest::SectionInfo i = gmbtest::findSection(both, "MESH");
        gmbtest::setLE(both, i.offset + 28, uint64_t(1) << 30, 4);
        gmbtest::fixCrc(both, i.offset);
    }
    CHECK_THAT(decodeError(both, huge), Contains("counts allow") || Contains("truncated"));
    // A compressed NODE declaring a terabyte is refused before inflating (a 1.0 compact file:
    // the writer's range-coded NODE is stored).
    std::string compact = gmbtest::readFile(kDir + "golden-1.0-compact.gmb");
    {
        const gmbtest::SectionInfo i = gmbtest::findSection(compact, "NODE");
        REQUIRE(i.codec != 0);
        gmbtest::setLE(compact, i.offset + 16, uint64_t(1) << 40, 8);
        gmbtest::fixCrc(compact, i.offset);
    }
    CHECK_THAT(decodeError(compact), Contains("its counts allow at most"));
    // A small file that inflates to a large document: the budget (maxFileBytes) refuses it.
    gm::ReadLimits budget;
    budget.maxFileBytes = 100000;
    gm::Document big;
    big.width = big.height = 100;
    big.meshes.push_back(gm::GradientMesh(300, 300));
    for (size_t k = 0; k < big.meshes[0].nodes.size(); ++k)
        big.meshes[0].nodes[k].pos = {double(k % 301) / 3, double(k / 301) / 3};
    const std::string bomb = gmbtest::encodeV1(big, true);
    CHECK(bomb.size() < 20000);
    REQUIRE(gmbtest::listSections(bomb)[1].tag.substr(0, 3) == "CMS");
    CHECK_THAT(decodeError(bomb, budget), Contains("decoded data would exceed the limit of 100000 bytes"));
    // A CMSH record of 4000x4000 patches (9 planes: 144 M values) with its 8002 knots but a
    // 5-byte stream: such a stream cannot hold that many values (each costs a fraction of a
    // bit, never less than 1/11730 byte), so the 1.2 GB of planes are never allocated.
    std::string payload("\x01\x09\x05\x05\x0f\x0d\x0d", 7);  // M, shared exponents
    payload += std::string("\xa0\x1f\xa0\x1f\x00\x00\x01\x2b", 8);  // C, R, 0, 0, rule, e_knot -22
    for (int k = 0; k < 2; ++k) payload += std::string(1, '\0') + std::string(4000, '\x01');
    payload += std::string(6, '\0');  // weights mask, stream
    std::string huge4000 = gmbtest::fileHeader(1, 2) + gmbtest::section("DOCU", std::string("\x64\0\0\0\x64\0\0\0\x01\0\0\0", 12)) +
                           gmbtest::section("CMSH", payload) + gmbtest::section("END ", "");
    // Under the default limits its 16 M patches are over the document's limit; past that, its
    // values alone (8 bytes each once decoded) are over budget; with a budget raised past that,
    // the stream's length refuses it.
    CHECK_THAT(decodeError(huge4000), Contains("16000000 patches, over the limit of 1048576") &&
                                          Contains("CMSH (mesh 0)"));
    gm::ReadLimits manyPatches;
    manyPatches.maxPatches = uint64_t(1) << 30;
    CHECK_THAT(decodeError(huge4000, manyPatches),
               Contains("decoded data would exceed the limit of 1073741824 bytes") &&
                   Contains("CMSH (mesh 0)"));
    gm::ReadLimits roomy = manyPatches;
    roomy.maxFileBytes = uint64_t(4) << 30;
    CHECK_THAT(decodeError(huge4000, roomy), Contains("truncated: 8793 bytes needed for the range-coded nodes") &&
                                                 Contains("CMSH (mesh 0)"));
    // The same in a CMS2 stream: a 4000x4000 mesh (colours by the rule) and its knots, then the
    // stream ends. Under the default limits its values are over budget; with a budget raised
    // past that, the bytes that remain refuse the planes before they are allocated.
    {
        using W = gmbtest::SpecCms2Writer;
        W w;
        w.U(W::Size, 4000);
        w.U(W::Size, 4000);
        w.U(W::Count, 0);
        w.U(W::Count, 0);
        w.U(W::Flags, 1);
        w.S(W::KnotExponent, -22);
        for (int k = 0; k < 2; ++k) {
            w.S(W::KnotStart, 0);
            for (int i = 0; i < 4000; ++i) w.U(W::KnotStep, 0);
        }
        std::string payload("\x01\x09\x05\x05\x0f\x0d\x0d", 7);  // M, shared exponents
        payload += w.finish();
        const std::string file =
            gmbtest::fileHeader(1, 3) +
            gmbtest::section("DOCU", std::string("\x64\0\0\0\x64\0\0\0\x01\0\0\0", 12)) +
            gmbtest::section("CMS2", payload) + gmbtest::section("END ", "");
        CHECK_THAT(decodeError(file), Contains("16000000 patches, over the limit of 1048576") &&
                                          Contains("CMS2 (mesh 0)"));
        CHECK_THAT(decodeError(file, manyPatches),
                   Contains("decoded data would exceed the limit of 1073741824 bytes") &&
                       Contains("CMS2 (mesh 0)"));
        gm::ReadLimits roomy = manyPatches;
        roomy.maxFileBytes = uint64_t(4) << 30;
        CHECK_THAT(decodeError(file, roomy), Contains("bytes needed for the range-coded nodes") &&
                                                 Contains("CMS2 (mesh 0)"));
        // Huge counts in the stream itself: refused by the limits before anything is sized.
        W big;
        big.U(W::Size, uint64_t(1) << 62);
        big.U(W::Size, uint64_t(1) << 62);
        big.U(W::Count, 0);
        big.U(W::Count, 0);
        std::string p2("\x01\x09\x05\x05\x0f\x0d\x0d", 7);
        p2 += big.finish();
        const std::string bigFile =
            gmbtest::fileHeader(1, 3) +
            gmbtest::section("DOCU", std::string("\x64\0\0\0\x64\0\0\0\x01\0\0\0", 12)) +
            gmbtest::section("CMS2", p2) + gmbtest::section("END ", "");
        CHECK_THAT(decodeError(bigFile, huge), Contains("exceeds the limit") && Contains("CMS2 (mesh 0)"));
    }
    CHECK_THAT(decodeError(edit("DOCU", 32, 0xffffffffu, 4), huge), Contains("meshes but only"));
}

TEST_CASE("limits a caller lowers are enforced", "[malformed]") {
    const std::string good = gmbtest::encodeV1(gmbtest::goldenLossless(), false);
    gm::ReadLimits l;
    l.maxGridSide = 4;
    CHECK_THAT(decodeError(good, l), Contains("grid 5x4 exceeds the limit of 4 columns or rows"));
    l = {};
    l.maxNodesPerMesh = 29;
    CHECK_THAT(decodeError(good, l), Contains("30 nodes, over the limit of 29"));
    l = {};
    l.maxSlitsPerMesh = 0;
    CHECK_THAT(decodeError(good, l), Contains("1 slits exceed the limit of 0"));
    l = {};
    l.maxMeshes = 1;
    CHECK_THAT(decodeError(good, l), Contains("2 meshes exceed the limit of 1"));
    l = {};
    l.maxCanvasSide = 50;
    CHECK_THAT(decodeError(good, l), Contains("canvas 64x48 exceeds the limit of 50"));
    l = {};
    l.maxFileBytes = 1000;
    CHECK_THAT(decodeError(good, l), Contains("file is 5248 bytes, over the limit of 1000"));
}

TEST_CASE("errors name the byte where the problem is", "[malformed]") {
    const std::string good = gmbtest::encodeV1(gmbtest::goldenLossless(), false);
    const gmbtest::SectionInfo node = gmbtest::findSection(good, "NODE");
    try {
        gm::decodeGmb(good.substr(0, node.offset + 50), {}, "cut.gmb");
        FAIL("no error");
    } catch (const gm::Error& e) {
        CHECK(e.file() == "cut.gmb");
        CHECK(e.where() == "byte " + std::to_string(node.offset));
        CHECK_THAT(e.what(), Contains("cut.gmb: byte") && Contains("truncated in section NODE"));
    }
}

TEST_CASE("reading through the format object names the file", "[malformed]") {
    const auto format = gm::makeGmbFormat();
    const std::string path = kDir + "malformed/crc-mismatch.gmb";
    REQUIRE_THROWS_WITH(format->read(path, gm::ReadOptions{}),
                        Contains(path) && Contains("CRC mismatch"));
    gm::ReadOptions small;
    small.limits.maxFileBytes = 10;
    REQUIRE_THROWS_WITH(format->read(kDir + "golden-1.0-lossless.gmb", small), Contains("over the limit"));
}
