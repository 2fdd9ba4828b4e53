// Version 2.0 of .gmb: 1.4's sections in short framing (docs/formats.md, "Version 2"). The
// writer's compact files must be exactly the 1.x file reframed by the spec (reframeAs20, written
// from the spec alone), read back to the same documents, and be refused cleanly when damaged.
#include <catch2/catch.hpp>

#include "formats/gmb.h"
#include "gmb_corpus.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace {

using Catch::Matchers::Contains;

const std::string kDir = std::string(GRADMESH_TEST_DATA) + "/gmb/";

std::string golden(const std::string& name) {
    const std::string bytes = gmbtest::readFile(kDir + name);
    REQUIRE_FALSE(bytes.empty());
    return bytes;
}

// The documents the 2.0 checks run on: the golden ones (slits, breaks, rule colours, a mesh kept
// as float64 between two runs) and random meshes of many shapes and scales.
std::vector<gm::Document> documents() {
    std::vector<gm::Document> docs = {gmbtest::goldenCompact11(), gmbtest::goldenCompact11Rule(),
                                      gmbtest::goldenMixed12(), gmbtest::goldenLossless()};
    for (unsigned seed = 1; seed <= 6; ++seed) {
        gm::Document d;
        d.width = 300 + static_cast<int>(seed) * 1000;  // varints of 2 and 3 bytes
        d.height = 200;
        for (unsigned k = 0; k < seed; ++k) d.meshes.push_back(gmbtest::randomMesh(seed * 7 + k));
        docs.push_back(d);
    }
    return docs;
}

uint16_t majorOf(const std::string& file) {
    return static_cast<uint16_t>(gmbtest::getLE(file, 8, 2));
}

}  // namespace

TEST_CASE("compact files are version 2.0: 1.x's sections reframed by the spec, byte for byte",
          "[v2][roundtrip]") {
    for (const gm::Document& d : documents())
        for (int level : {0, 2, 6})
            for (gm::GmbStreams streams :
                 {gm::GmbStreams::Smaller, gm::GmbStreams::Cms2, gm::GmbStreams::Cms3}) {
                INFO("meshes " << d.meshes.size() << ", level " << level << ", streams "
                               << static_cast<int>(streams));
                const std::string v1 = gmbtest::encodeV1(d, true, level, streams);
                const std::string v2 = gm::encodeGmb(d, true, level, streams);
                CHECK(majorOf(v1) == 1);
                CHECK(majorOf(v2) == 2);
                CHECK(gmbtest::getLE(v2, 10, 2) == 0);
                CHECK(v2 == gmbtest::reframeAs20(v1));
                CHECK(v2.size() < v1.size());
                const gm::Document a = gm::decodeGmb(v1, gm::ReadLimits{}, "v1.gmb");
                const gm::Document b = gm::decodeGmb(v2, gm::ReadLimits{}, "v2.gmb");
                CHECK(a == b);
            }
}

TEST_CASE("lossless files stay 1.0 whatever the framing asked", "[v2]") {
    const gm::Document d = gmbtest::goldenLossless();
    for (gm::GmbFraming f : {gm::GmbFraming::Short, gm::GmbFraming::Long}) {
        const std::string bytes = gm::encodeGmb(d, false, 0, gm::GmbStreams::Smaller, f);
        CHECK(majorOf(bytes) == 1);
        CHECK(gmbtest::getLE(bytes, 10, 2) == 0);
        CHECK(bytes == golden("golden-1.0-lossless.gmb"));
    }
}

TEST_CASE("2.0 saves 57 bytes on a converted whole image", "[v2]") {
    // HappyFish whole at 10 patches a region (a 1.4 file): DOCU 40 -> 16 bytes, its CMS3
    // section's framing 28 -> 12, END 28 -> 11.
    const gm::Document d = gm::decodeGmb(golden("happyfish-whole-10.gmb"), gm::ReadLimits{});
    const std::string v1 = gmbtest::encodeV1(d, true, 6);
    const std::string v2 = gm::encodeGmb(d, true, 6);
    CHECK(v1.size() - v2.size() == 57);
    CHECK(gm::decodeGmb(v2, gm::ReadLimits{}) == gm::decodeGmb(v1, gm::ReadLimits{}));
}

TEST_CASE("golden 2.0 files read to their documents and today's writer reproduces them",
          "[v2][golden]") {
    const gm::Document compact = gm::decodeGmb(golden("golden-2.0-compact.gmb"), gm::ReadLimits{});
    CHECK(compact == gm::decodeGmb(golden("golden-1.4-compact.gmb"), gm::ReadLimits{}));
    CHECK(gm::encodeGmb(gmbtest::goldenCompact11(), true, 0, gm::GmbStreams::Cms3) ==
          golden("golden-2.0-compact.gmb"));
    const gm::Document mixed =
        gm::decodeGmb(golden("golden-2.0-compact-mixed.gmb"), gm::ReadLimits{});
    CHECK(mixed == gm::decodeGmb(golden("golden-1.4-compact-mixed.gmb"), gm::ReadLimits{}));
    CHECK(gm::encodeGmb(gmbtest::goldenMixed12(), true, 0, gm::GmbStreams::Cms3) ==
          golden("golden-2.0-compact-mixed.gmb"));
    // Its sections: DOCU, a CMS3 run, the float64 mesh's MESH KNOT NODE, a CMS3 run, END.
    std::vector<std::string> tags;
    for (const gmbtest::Section2Info& i :
         gmbtest::listSections2(golden("golden-2.0-compact-mixed.gmb")))
        tags.push_back(i.tag);
    CHECK(tags == std::vector<std::string>{"DOCU", "CMS3", "MESH", "KNOT", "NODE", "CMS3", "END "});
}

TEST_CASE("a newer 2.x minor reads: appended DOCU fields and unknown optional sections are skipped",
          "[v2]") {
    const std::string v2 = gm::encodeGmb(gmbtest::goldenMixed12(), true);
    const auto sections = gmbtest::listSections2(v2);
    std::string docu = v2.substr(sections[0].payload, static_cast<size_t>(sections[0].stored));
    gmbtest::putVarint(docu, 12345);  // a field of a later minor
    std::string s = gmbtest::fileHeader(2, 7) + gmbtest::section2("DOCU", docu) +
                    gmbtest::section2("ZZZZ", "later data", 1);
    for (size_t k = 1; k < sections.size(); ++k) {
        if (k + 1 == sections.size()) s += gmbtest::section2("YYYY", "", 1);
        s += v2.substr(sections[k].offset, sections[k].end() - sections[k].offset);
    }
    CHECK(gm::decodeGmb(s, gm::ReadLimits{}) == gm::decodeGmb(v2, gm::ReadLimits{}));
}

TEST_CASE("a 2.0 file cut at every byte is refused as truncated", "[v2][malformed]") {
    for (const gm::Document& d : {gmbtest::goldenMixed12(), gmbtest::goldenCompact11()}) {
        const std::string full = gm::encodeGmb(d, true);
        REQUIRE(majorOf(full) == 2);
        for (size_t n = 0; n < full.size(); ++n) {
            INFO("cut at " << n << " of " << full.size());
            try {
                gm::decodeGmb(full.substr(0, n), gm::ReadLimits{}, "cut.gmb");
                FAIL("decoding succeeded");
            } catch (const gm::Error& e) {
                CHECK(e.file() == "cut.gmb");
                CHECK_THAT(e.what(), Contains(n == 0 ? "empty file" : "truncated"));
            }
        }
    }
}

TEST_CASE("every single-bit flip of a 2.0 file is refused or reads to a valid document",
          "[v2][malformed]") {
    const std::string good = gm::encodeGmb(gmbtest::goldenMixed12(), true);
    int refused = 0, read = 0;
    for (size_t at = 0; at < good.size(); ++at)
        for (int bit = 0; bit < 8; ++bit) {
            INFO("byte " << at << " bit " << bit);
            std::string s = good;
            s[at] = static_cast<char>(s[at] ^ (1 << bit));
            try {
                const gm::Document d = gm::decodeGmb(s, gm::ReadLimits{}, "flipped.gmb");
                CHECK(gm::validateDocument(d).empty());
                ++read;
            } catch (const gm::Error& e) {
                CHECK(e.file() == "flipped.gmb");
                CHECK_FALSE(e.where().empty());
                ++refused;
            }
        }
    // Only the flag bits of known sections (ignored by 1.x and 2.x readers but bit 0) and the
    // minor version may change without the CRC noticing.
    CHECK(read < 64);
    CHECK(refused > 8 * static_cast<int>(good.size()) - 64);
}

TEST_CASE("a section size that lies in a 2.0 file is refused before anything is allocated",
          "[v2][malformed]") {
    const std::string v2 = gm::encodeGmb(gmbtest::goldenCompact11(), true);
    const auto sections = gmbtest::listSections2(v2);
    // The run's section (CMS2: this document is one where CMS2 is smaller) again, its stored
    // size stated in a 10-byte varint (a legal encoding) and as 2^62, with the CRC made to fit.
    const gmbtest::Section2Info& run = sections[1];
    const std::string payload = v2.substr(run.payload, static_cast<size_t>(run.stored));
    const std::string before = v2.substr(0, run.offset), after = v2.substr(run.end());
    auto withSize = [&](const std::string& size) {
        std::string sec = run.tag + std::string(2, '\0') + size + payload;
        gmbtest::putLE(sec, gmbtest::crc32(sec, 0, sec.size()), 4);
        return before + sec + after;
    };
    std::string padded;  // the true size in 10 bytes
    uint64_t x = payload.size();
    for (int k = 0; k < 9; ++k, x >>= 7) padded.push_back(static_cast<char>((x & 0x7f) | 0x80));
    padded.push_back(0);
    CHECK(gm::decodeGmb(withSize(padded), gm::ReadLimits{}) == gm::decodeGmb(v2, gm::ReadLimits{}));
    std::string huge;
    gmbtest::putVarint(huge, uint64_t(1) << 62);
    try {
        gm::decodeGmb(withSize(huge), gm::ReadLimits{}, "huge.gmb");
        FAIL("decoding succeeded");
    } catch (const gm::Error& e) {
        CHECK_THAT(e.what(), Contains("truncated in section " + run.tag));
    }
}
