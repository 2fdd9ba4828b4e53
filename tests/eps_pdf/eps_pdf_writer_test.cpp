#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <regex>

#include "eps_pdf_test_support.h"
#include "formats/eps.h"
#include "formats/mesh_shading.h"
#include "formats/pdf.h"
#include "formats/registry.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"

using namespace gm;
using namespace epstest;

namespace {

Document holedDocument() {
    Document d;
    d.width = 300;
    d.height = 340;
    d.meshes.push_back(makeHoledMesh(3, 20, 20, 260, 300, 4));
    return d;
}

uint64_t bigEndian(const std::string& s, size_t at, int bytes) {
    uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) v = (v << 8) | static_cast<unsigned char>(s[at + k]);
    return v;
}

// The binary payload of the n-th PostScript shading (between `exec` and `~>`).
std::string epsBinaryPayload(const std::string& eps, size_t n) {
    size_t pos = 0;
    for (size_t k = 0; k <= n; ++k) {
        pos = eps.find("} exec\n", pos);
        REQUIRE(pos != std::string::npos);
        pos += 7;
    }
    const size_t end = eps.find("~>", pos);
    REQUIRE(end != std::string::npos);
    return inflateBytes(ascii85Decode(eps.substr(pos, end - pos + 2)));
}

}  // namespace

TEST_CASE("registry finds the EPS and PDF writers by extension", "[eps][pdf]") {
    const FormatRegistry& r = FormatRegistry::builtin();
    REQUIRE(r.forPath("a.eps") != nullptr);
    CHECK(r.forPath("a.EPS")->name() == "eps");
    REQUIRE(r.forPath("a.pdf") != nullptr);
    CHECK(r.forPath("a.pdf")->name() == "pdf");
    CHECK(r.forPath("a.pdf")->canWrite());
    CHECK_FALSE(r.forPath("a.eps")->canRead());
}

TEST_CASE("ASCII85 encoding decodes back and keeps DSC-safe lines", "[eps]") {
    std::string bytes;
    for (int i = 0; i < 3000; ++i) bytes.push_back(static_cast<char>((i * 7919) % 251));
    bytes.append(8, '\0');  // zero groups become 'z'
    for (int tail = 0; tail < 4; ++tail) {
        const std::string data = bytes.substr(0, bytes.size() - static_cast<size_t>(tail));
        const std::string text = ascii85Encode(data, 76);
        CHECK(ascii85Decode(text) == data);
        std::istringstream lines(text);
        for (std::string line; std::getline(lines, line);) {
            CHECK(line.size() <= 77);
            CHECK((line.empty() || line[0] != '%'));
        }
        CHECK(text.find("~>") != std::string::npos);
    }
}

TEST_CASE("formatDecimal is short, exact and locale-free", "[eps][pdf]") {
    CHECK(formatDecimal(12.5, 4) == "12.5");
    CHECK(formatDecimal(-0.00001, 4) == "0");
    CHECK(formatDecimal(3.0, 4) == "3");
    CHECK(formatDecimal(0.1234567, 6) == "0.123457");
    CHECK(formatDecimal(-250, 0) == "-250");
}

TEST_CASE(
    "binary shading data round-trips points and colours in Table 4.36 order, in 16, 24 or "
    "32-bit coordinates",
    "[eps][pdf]") {
    // Pages of 40, 400 and 20000 px: the fewest coordinate bytes that keep a step of 1/1024 px.
    std::vector<std::pair<Document, int>> cases;
    for (const auto& [size, bytes] : {std::pair{40, 2}, {400, 3}, {20000, 4}}) {
        Document doc;
        doc.width = size;
        doc.height = size * 3 / 4;
        doc.meshes.push_back(
            makeCurvedMesh(3, 2, size * 0.1, size * 0.1, size * 0.75, size * 0.5, 1.0, 2));
        cases.emplace_back(doc, bytes);
    }
    cases.emplace_back(holedDocument(), 3);
    const int order[16][2] = {{0, 0}, {0, 1}, {0, 2}, {0, 3}, {1, 3}, {2, 3}, {3, 3}, {3, 2},
                              {3, 1}, {3, 0}, {2, 0}, {1, 0}, {1, 1}, {1, 2}, {2, 2}, {2, 1}};
    const int corners[4][2] = {{0, 0}, {0, 3}, {3, 3}, {3, 0}};
    for (const auto& [doc, bytes] : cases) {
        for (const MeshShading& sh : buildMeshShadings(doc, WriteOptions{})) {
            const BinaryShading bin = encodeShadingBinary(sh);
            INFO(doc.width << " px page, " << sh.patches.size() << " patches");
            REQUIRE(bin.coordinateBytes == bytes);
            CHECK(binaryShadingEntries(bin).find("/BitsPerCoordinate " + std::to_string(8 * bytes) +
                                                 " ") != std::string::npos);
            const size_t perPatch = 1 + 16 * 2 * bytes + 4 * 3 * 2;
            REQUIRE(bin.data.size() == sh.patches.size() * perPatch);
            const double maxCode = std::ldexp(1.0, 8 * bytes) - 1;
            const double xr = bin.decode[1] - bin.decode[0], yr = bin.decode[3] - bin.decode[2];
            double worstPos = 0, worstCol = 0;
            for (size_t n = 0; n < sh.patches.size(); ++n) {
                const BezierPatch& p = sh.patches[n];
                size_t at = n * perPatch;
                REQUIRE(bin.data[at] == '\0');
                ++at;
                for (const auto& ab : order) {
                    const double x =
                        bin.decode[0] + xr * double(bigEndian(bin.data, at, bytes)) / maxCode;
                    const double y = bin.decode[2] +
                                     yr * double(bigEndian(bin.data, at + bytes, bytes)) / maxCode;
                    worstPos = std::max(worstPos, std::fabs(x - p.p[ab[0]][ab[1]].x));
                    worstPos = std::max(worstPos, std::fabs(y - p.p[ab[0]][ab[1]].y));
                    at += 2 * bytes;
                }
                for (const auto& ab : corners) {
                    for (int ch = 0; ch < 3; ++ch) {
                        const double c = double(bigEndian(bin.data, at, 2)) / 65535.0;
                        const double want = std::min(1.0, std::max(0.0, p.c[ab[0]][ab[1]][ch]));
                        worstCol = std::max(worstCol, std::fabs(c - want));
                        at += 2;
                    }
                }
            }
            CHECK(worstPos <= 0.5 / 1024 + 1e-9);  // half a step, a step ≤ 1/1024 px
            CHECK(worstCol <= 0.5 / 65535 + 1e-12);
        }
    }
}

TEST_CASE("binary shading coordinates keep a step of 1/1024 px at the width boundaries",
          "[eps][pdf]") {
    // One flat patch from (0, 0) to (w, w/2): the decode box is [0, w] x [0, w/2].
    for (const auto& [w, bytes] : {std::pair{63, 2}, {64, 3}, {16383, 3}, {16384, 4}}) {
        MeshShading sh;
        BezierPatch patch{};
        for (int a = 0; a < 4; ++a)
            for (int b = 0; b < 4; ++b) patch.p[a][b] = {w * a / 3.0, w * b / 6.0};
        sh.patches.push_back(patch);
        const BinaryShading bin = encodeShadingBinary(sh);
        INFO(w << " px");
        CHECK(bin.decode[1] - bin.decode[0] == w);
        CHECK(bin.coordinateBytes == bytes);
        CHECK((std::ldexp(1.0, 8 * bin.coordinateBytes) - 1) >= 1024.0 * w);
    }
}

TEST_CASE("EPS has the DSC header, one binary shading per mesh, y flipped", "[eps]") {
    Document doc = holedDocument();
    doc.meshes.push_back(makeCurvedMesh(3, 2, 40, 40, 100, 80, 1.0, 2));
    const std::string path = tmpPath("structure.eps");
    FormatRegistry::builtin().forPath(path)->write(doc, path, WriteOptions{});
    const std::string eps = readFile(path);
    CHECK(eps.rfind("%!PS-Adobe-3.0 EPSF-3.0\n", 0) == 0);
    CHECK(eps.find("\n%%BoundingBox: 0 0 300 340\n") != std::string::npos);
    CHECK(eps.find("\n%%HiResBoundingBox: 0 0 300 340\n") != std::string::npos);
    CHECK(eps.find("\n%%LanguageLevel: 3\n") != std::string::npos);
    CHECK(eps.find("0 340 translate 1 -1 scale") != std::string::npos);
    CHECK(countOccurrences(eps, "shfill") == 2);
    CHECK(countOccurrences(eps, "/BitsPerCoordinate 24 /BitsPerComponent 16 /BitsPerFlag 8") == 2);
    CHECK(countOccurrences(eps, "currentfile /ASCII85Decode filter") == 2);
    CHECK(eps.find("/FlateDecode filter") != std::string::npos);
    CHECK(eps.find("%%EOF") != std::string::npos);

    const std::vector<MeshShading> shadings = buildMeshShadings(doc, WriteOptions{});
    REQUIRE(shadings.size() == 2);
    for (size_t n = 0; n < 2; ++n)
        CHECK(epsBinaryPayload(eps, n) == encodeShadingBinary(shadings[n]).data);
}

TEST_CASE("EPS text DataSource holds every patch as flag, 32 coordinates, 12 components", "[eps]") {
    const Document doc = holedDocument();
    WriteOptions text;
    text.textShading = true;
    const std::string path = tmpPath("text.eps");
    FormatRegistry::builtin().forPath(path)->write(doc, path, text);
    const std::string eps = readFile(path);
    CHECK(eps.find("ASCII85Decode") == std::string::npos);
    // Arrays hold at most 1000 patches (PostScript's array limit is 65535 elements).
    size_t count = 0, arrays = 0;
    for (size_t open = eps.find("/DataSource ["); open != std::string::npos;
         open = eps.find("/DataSource [", open + 1)) {
        const size_t close = eps.find(']', open);
        REQUIRE(close != std::string::npos);
        std::istringstream numbers(eps.substr(open + 13, close - open - 13));
        size_t inArray = 0;
        for (double v; numbers >> v;) ++inArray;
        CHECK(inArray <= 45000);
        CHECK(inArray % 45 == 0);
        count += inArray;
        ++arrays;
    }
    CHECK(countOccurrences(eps, "shfill") == arrays);
    const std::vector<MeshShading> shadings = buildMeshShadings(doc, text);
    REQUIRE(shadings.size() == 1);
    CHECK(count == 45 * shadings[0].patches.size());
}

TEST_CASE("PDF is well formed: xref offsets, stream lengths, one shading per mesh", "[pdf]") {
    Document doc = holedDocument();
    doc.meshes.push_back(makeCurvedMesh(3, 2, 40, 40, 100, 80, 1.0, 2));
    const std::string path = tmpPath("structure.pdf");
    FormatRegistry::builtin().forPath(path)->write(doc, path, WriteOptions{});
    const std::string pdf = readFile(path);
    REQUIRE(pdf.rfind("%PDF-1.7\n%", 0) == 0);
    CHECK(static_cast<unsigned char>(pdf[10]) >= 128);  // binary comment line
    CHECK(pdf.find("/MediaBox [0 0 300 340]") != std::string::npos);
    CHECK(pdf.find("q 1 0 0 -1 0 340 cm\n/Sh0 sh\n/Sh1 sh\nQ") != std::string::npos);

    // startxref points at the table; every entry points at its object.
    const size_t sx = pdf.rfind("startxref\n");
    REQUIRE(sx != std::string::npos);
    const size_t xref = std::stoul(pdf.substr(sx + 10));
    REQUIRE(pdf.compare(xref, 5, "xref\n") == 0);
    std::istringstream table(pdf.substr(xref + 5));
    int first = -1, count = 0;
    table >> first >> count;
    CHECK(first == 0);
    REQUIRE(count == 7);  // free entry, catalog, pages, page, contents, two shadings
    const size_t entries = pdf.find('\n', xref + 5) + 1;
    CHECK(pdf.compare(entries, 20, "0000000000 65535 f\r\n") == 0);
    for (int n = 1; n < count; ++n) {
        const std::string entry = pdf.substr(entries + 20 * static_cast<size_t>(n), 20);
        CHECK(entry.substr(10, 10) == " 00000 n\r\n");
        const size_t offset = std::stoul(entry.substr(0, 10));
        CHECK(pdf.compare(offset, std::to_string(n).size() + 6, std::to_string(n) + " 0 obj") == 0);
    }
    CHECK(pdf.find("/Size 7 /Root 1 0 R") != std::string::npos);
    CHECK(pdf.substr(pdf.size() - 6) == "%%EOF\n");

    // Each shading stream: declared length, inflates to the binary data of its mesh.
    const std::vector<MeshShading> shadings = buildMeshShadings(doc, WriteOptions{});
    std::regex shadingHeader(
        "/ShadingType 7 [^>]*/Filter /FlateDecode /Length ([0-9]+) >>\nstream\n");
    size_t found = 0;
    for (auto it = std::sregex_iterator(pdf.begin(), pdf.end(), shadingHeader);
         it != std::sregex_iterator(); ++it) {
        const size_t length = std::stoul((*it)[1].str());
        const size_t start = static_cast<size_t>(it->position() + it->length());
        CHECK(pdf.compare(start + length, 10, "\nendstream") == 0);
        REQUIRE(found < shadings.size());
        CHECK(inflateBytes(pdf.substr(start, length)) == encodeShadingBinary(shadings[found]).data);
        ++found;
    }
    CHECK(found == 2);
}

TEST_CASE("legacy option writes b+1 shadings for b slits on distinct rows", "[eps][pdf]") {
    const Document doc = holedDocument();
    REQUIRE(doc.meshes[0].holeCount() == 3);
    WriteOptions legacy;
    legacy.legacy = true;
    const std::string eps = tmpPath("legacy.eps"), pdf = tmpPath("legacy.pdf");
    FormatRegistry::builtin().forPath(eps)->write(doc, eps, legacy);
    FormatRegistry::builtin().forPath(pdf)->write(doc, pdf, legacy);
    CHECK(countOccurrences(readFile(eps), "shfill") == 4);
    CHECK(countOccurrences(readFile(pdf), " sh\n") == 4);
    CHECK(countOccurrences(readFile(pdf), "/ShadingType 7") == 4);
    // Same patches either way: pieces keep the exact geometry and colours.
    size_t whole = buildMeshShadings(doc, WriteOptions{})[0].patches.size(), pieces = 0;
    for (const MeshShading& s : buildMeshShadings(doc, legacy)) pieces += s.patches.size();
    CHECK(pieces == whole);
}

TEST_CASE("writers refuse invalid documents and leave no file", "[eps][pdf]") {
    Document doc = holedDocument();
    doc.meshes[0].nodes[5].pos.x = std::nan("");
    for (const char* name : {"invalid.eps", "invalid.pdf"}) {
        const std::string path = tmpPath(name);
        std::remove(path.c_str());
        CHECK_THROWS_AS(FormatRegistry::builtin().forPath(path)->write(doc, path, WriteOptions{}),
                        gm::Error);
        CHECK(readFile(path).empty());
        std::ifstream probe(path);
        CHECK_FALSE(probe.good());
    }
}

TEST_CASE("an empty document still gives valid files", "[eps][pdf]") {
    Document doc;
    doc.width = 10;
    doc.height = 20;
    const std::string eps = tmpPath("empty.eps"), pdf = tmpPath("empty.pdf");
    FormatRegistry::builtin().forPath(eps)->write(doc, eps, WriteOptions{});
    FormatRegistry::builtin().forPath(pdf)->write(doc, pdf, WriteOptions{});
    CHECK(countOccurrences(readFile(eps), "shfill") == 0);
    CHECK(readFile(pdf).find("/MediaBox [0 0 10 20]") != std::string::npos);
}
