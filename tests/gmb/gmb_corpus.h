// The deterministic documents behind tests/data/gmb: golden files of versions 1.0 to 2.0 and
// the malformed corpus, each with the message its reading must produce. Only IEEE-exact
// arithmetic (no libm calls but exact ones: frexp, ldexp, llround), so that the same bytes come
// out on every platform.
//
// To regenerate after a deliberate format change (then bump the version and keep the old files):
//   build-gmb/tests/gmb/test_gmb "[.generate]"
// The golden files of earlier versions are not regenerated (today's writer writes the newest
// version); the malformed cases built from a compressed 1.0 section read golden-1.0-compact.gmb,
// those built from a 1.1 NODE of encoding 2 read golden-1.1-compact.gmb, those built from CMSH
// sections read golden-1.2-compact.gmb and golden-1.2-compact-mixed.gmb, those built from CMS2
// sections golden-1.3-compact.gmb (the 1.3 writer's goldenCompact11). The 1.4 files
// (golden-1.4-compact.gmb: goldenCompact11; golden-1.4-compact-mixed.gmb: goldenMixed12) are
// today's writer's output at level 0 with CMS3 asked for (GmbStreams::Cms3) in 1.x framing
// (GmbFraming::Long); the 2.0 files (golden-2.0-*.gmb) are the same in today's default framing.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "formats/gmb.h"
#include "gmb_spec_coded.h"
#include "gmb_test_support.h"
#include "meshcore/color_rule.h"

namespace gmbtest {

// The writer's 1.x output (compact files as 1.3 or 1.4, in the 24-byte section framing that the
// tests built before version 2.0 edit byte by byte).
inline std::string encodeV1(const gm::Document& doc, bool compact, int level = 0,
                            gm::GmbStreams streams = gm::GmbStreams::Smaller) {
    return gm::encodeGmb(doc, compact, level, streams, gm::GmbFraming::Long);
}

// Two meshes on a 64x48 canvas; mesh 0 is 5x4 with a slit on row 2 (columns 1..4, two split
// nodes) and two corner tangent breaks; mesh 1 is 2x1. Values are not dyadic: lossless only.
inline gm::Document goldenLossless() {
    gm::Document d;
    d.width = 64;
    d.height = 48;
    gm::GradientMesh m(5, 4);
    m.u = {0, 0.1, 0.3, 0.35, 1, 2.5};
    m.v = {-1, 0, 1.0 / 3, 2.0 / 3, 1};
    for (int j = 0; j <= 4; ++j) {
        for (int i = 0; i <= 5; ++i) {
            gm::Node& n = m.node(i, j);
            n.pos = {10 + 10.1 * i + 0.01 * j * j, 5 + 9.7 * j - 0.3 * i};
            n.posU = {30.1 + 0.2 * j, -0.3 + 0.05 * i};
            n.posV = {0.02 * j, 29.1 - 0.1 * i};
            n.col = {0.1 * i / 5 + 0.05, 0.2 * j / 4 + 0.3, 0.9 - 0.1 * (i + j) / 9};
            n.colU = {0.02, -0.001 * j, 0.0};
            n.colV = {0.0, 0.05 / 3, -0.01 * i};
        }
    }
    gm::Slit s;
    s.row = 2;
    s.i0 = 1;
    s.i1 = 4;
    for (int i = 2; i <= 3; ++i) {
        gm::Node n = m.node(i, 2);
        n.pos.y += 2.2;
        n.posU.y = -n.posU.y;
        s.below.push_back(n);
        m.node(i, 2).pos.y -= 2.2;
    }
    s.left = {{0, -7.7}, {0.1, 0.2, 0.3}};
    s.right = {{0, 7.7}, {-0.1, -0.2, -0.3}};
    m.slits.push_back(s);
    m.tangents.push_back({0, 0, 0, 0, {1.1, 2.2}, {0.01, 0.02, 0.03}});
    m.tangents.push_back({4, 3, 1, 1, {-3.3, 4.4}, {-0.04, 0.05, -0.06}});
    d.meshes.push_back(m);

    gm::GradientMesh small(2, 1);
    small.u = {100, 100.5, 101};
    small.v = {7, 7.001};
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= 2; ++i) {
            gm::Node& n = small.node(i, j);
            n.pos = {40 + 5.5 * i, 30 + 6.25 * j};
            n.posU = {11, 0.1};
            n.posV = {0.2, 6250};
            n.col = {0.7, 0.1 * (i + j), 1.0 / 7};
        }
    d.meshes.push_back(small);
    return d;
}

// The same structure with every value on the compact grid (knots with a smallest interval of
// 0.25 and a largest of 1: derivatives in steps of 1/64 px and 1/512), so a compact round trip
// is exact.
inline gm::Document goldenCompact() {
    gm::Document d = goldenLossless();
    gm::GradientMesh& m = d.meshes[0];
    m.u = {0, 0.25, 0.5, 1, 2, 3};
    m.v = {0, 1, 2, 3, 4};
    auto dyadic = [](gm::Node& n, int i, int j) {
        n.pos = {10 + 10.125 * i + j / 32.0, 5 + 9.75 * j - 0.25 * i};
        n.posU = {30 + j / 64.0, -0.5 + i / 64.0};
        n.posV = {j / 16.0, 29 - i / 8.0};
        n.col = {(20 + 10 * i) / 256.0, (70 + 12 * j) / 256.0, (230 - 3 * (i + j)) / 256.0};
        n.colU = {10 / 512.0, -j / 512.0, 0};
        n.colV = {0, 9 / 512.0, -3.0 * i / 512.0};
    };
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 5; ++i) dyadic(m.node(i, j), i, j);
    for (size_t b = 0; b < m.slits[0].below.size(); ++b) {
        gm::Node& n = m.slits[0].below[b];
        dyadic(n, 2 + static_cast<int>(b), 2);
        n.pos.y += 2.25;
        n.posU.y = -n.posU.y;
    }
    m.slits[0].left = {{0, -7.75}, {50 / 512.0, 100 / 512.0, 150 / 512.0}};
    m.slits[0].right = {{0, 7.75}, {-50 / 512.0, -100 / 512.0, -150 / 512.0}};
    m.tangents[0] = {0, 0, 0, 0, {1.125, 2.25}, {5 / 512.0, 10 / 512.0, 15 / 512.0}};
    m.tangents[1] = {4, 3, 1, 1, {-3.25, 4.5}, {-20 / 512.0, 25 / 512.0, -30 / 512.0}};
    gm::GradientMesh& small = d.meshes[1];
    small.v = {7, 7.25};
    for (int j = 0; j <= 1; ++j)
        for (int i = 0; i <= 2; ++i) {
            gm::Node& n = small.node(i, j);
            n.posU = {11, 0.125};
            n.posV = {0.25, 25};
            n.col = {179 / 256.0, (26 * (i + j)) / 256.0, 37 / 256.0};
        }
    return d;
}

// goldenCompact with the colour rule applied to mesh 1: its colour derivatives are not stored.
inline gm::Document goldenCompactRule() {
    gm::Document d = goldenCompact();
    gm::applyColorRule(d.meshes[1]);
    return d;
}

// Moves every stored derivative of `m` onto the grid of encoding 2 (tangents in steps of 1/8 px
// and 1/128 over the span of their node, docs/formats.md), with the writer's exponents.
inline void snapToCodedGrid(gm::GradientMesh& m) {
    double minStep = m.u[1] - m.u[0];
    for (size_t i = 1; i < m.u.size(); ++i) minStep = std::min(minStep, m.u[i] - m.u[i - 1]);
    for (size_t j = 1; j < m.v.size(); ++j) minStep = std::min(minStep, m.v[j] - m.v[j - 1]);
    int p = 0;
    std::frexp(minStep, &p);
    const int eKnot = p - 22;
    std::vector<int64_t> ku, kv;
    for (double x : m.u) ku.push_back(std::llround(std::ldexp(x, -eKnot)));
    for (double x : m.v) kv.push_back(std::llround(std::ldexp(x, -eKnot)));
    const std::vector<int64_t> Du = specSpans(ku), Dv = specSpans(kv);
    auto snap = [&](double& x, int e, int64_t D) {
        const int64_t q = std::llround(std::ldexp(x * static_cast<double>(D), eKnot - e));
        x = std::ldexp(static_cast<double>(q), e - eKnot) / static_cast<double>(D);
    };
    auto node = [&](gm::Node& n, size_t i, size_t j) {
        snap(n.posU.x, -3, Du[i]);
        snap(n.posU.y, -3, Du[i]);
        snap(n.posV.x, -3, Dv[j]);
        snap(n.posV.y, -3, Dv[j]);
        for (int c = 0; c < 3; ++c) {
            snap(n.colU[c], -7, Du[i]);
            snap(n.colV[c], -7, Dv[j]);
        }
    };
    const size_t stride = m.u.size();
    for (size_t k = 0; k < m.nodes.size(); ++k) node(m.nodes[k], k % stride, k / stride);
    for (gm::Slit& s : m.slits) {
        for (size_t b = 0; b < s.below.size(); ++b)
            node(s.below[b], static_cast<size_t>(s.i0) + 1 + b, static_cast<size_t>(s.row));
        for (auto end : {std::make_pair(&s.left, s.i0), std::make_pair(&s.right, s.i1)}) {
            snap(end.first->posU.x, -3, Du[static_cast<size_t>(end.second)]);
            snap(end.first->posU.y, -3, Du[static_cast<size_t>(end.second)]);
            for (int c = 0; c < 3; ++c)
                snap(end.first->colU[c], -7, Du[static_cast<size_t>(end.second)]);
        }
    }
    for (gm::CornerTangent& t : m.tangents) {
        const size_t column = static_cast<size_t>(t.i + t.a);
        snap(t.posU.x, -3, Du[column]);
        snap(t.posU.y, -3, Du[column]);
        for (int c = 0; c < 3; ++c) snap(t.colU[c], -7, Du[column]);
    }
}

// goldenCompact with its derivatives on the grid of encoding 2, so that a compact round trip
// (version 1.1) is exact.
inline gm::Document goldenCompact11() {
    gm::Document d = goldenCompact();
    for (gm::GradientMesh& m : d.meshes) snapToCodedGrid(m);
    return d;
}

// goldenCompact11 with the colour rule applied to mesh 1: its colour derivatives are not stored.
inline gm::Document goldenCompact11Rule() {
    gm::Document d = goldenCompact11();
    gm::applyColorRule(d.meshes[1]);
    return d;
}

// For a 1.2 file that mixes: goldenCompact11Rule's two meshes (mesh 1 by the rule), a mesh the
// compact writer must keep as float64 (a coordinate beyond the quantised range), and mesh 1
// again: CMSH (2 meshes), MESH KNOT NODE, CMSH (1 mesh).
inline gm::Document goldenMixed12() {
    gm::Document d = goldenCompact11Rule();
    gm::GradientMesh far = goldenLossless().meshes[1];
    far.node(2, 1).pos.x = 1e20;
    d.meshes.push_back(far);
    d.meshes.push_back(d.meshes[1]);
    return d;
}

// A file with one section's payload replaced (sizes and CRC follow; stored, codec 0).
inline std::string withPayload(const std::string& file, const std::string& tag, int nth,
                               const std::string& payload) {
    const SectionInfo i = findSection(file, tag, nth);
    const std::string head = file.substr(i.offset, 4);
    return file.substr(0, i.offset) + section(head, payload, i.flags, 0) + file.substr(i.end());
}

// Every mesh record of every CMSH section of a file, in order (spec decoding).
inline std::vector<SpecCmshMesh> cmshRecords(const std::string& file) {
    std::vector<SpecCmshMesh> out;
    for (const SectionInfo& i : listSections(file)) {
        if (i.tag != "CMSH") continue;
        for (SpecCmshMesh& m : specDecodeCmsh(file.substr(i.payload(), static_cast<size_t>(i.stored))))
            out.push_back(std::move(m));
    }
    return out;
}

// Every mesh of every CMSH, CMS2 or CMS3 section of a file, in order (spec decoding).
inline std::vector<SpecCmshMesh> compactRecords(const std::string& file) {
    std::vector<SpecCmshMesh> out;
    for (const SectionInfo& i : listSections(file)) {
        const std::string payload = file.substr(i.payload(), static_cast<size_t>(i.stored));
        std::vector<SpecCmshMesh> meshes;
        if (i.tag == "CMSH") meshes = specDecodeCmsh(payload);
        if (i.tag == "CMS2" || i.tag == "CMS3") meshes = specDecodeCms2(payload, i.tag == "CMS3");
        for (SpecCmshMesh& m : meshes) out.push_back(std::move(m));
    }
    return out;
}

// The same file in the 1.2 layout: each CMS2 or CMS3 section as a CMSH section with the same weights,
// residuals, knots, slits and breaks (spec encoding). It holds the same document, so its size
// is what CMSH costs for the very same data.
inline std::string cms2AsCmsh(const std::string& file) {
    std::string s = fileHeader(1, 2);
    for (const SectionInfo& i : listSections(file)) {
        if (i.tag != "CMS2" && i.tag != "CMS3") {
            s += file.substr(i.offset, i.end() - i.offset);
            continue;
        }
        s += section("CMSH", specCms2AsCmsh(file.substr(i.payload(), static_cast<size_t>(i.stored)),
                                            i.tag == "CMS3"));
    }
    return s;
}

// The same file in the 1.3 layout: each CMS3 section as a CMS2 section with the same integers
// (spec encoding). It holds the same document, so its size is what CMS2 costs for the very
// same data.
inline std::string cms3AsCms2(const std::string& file) {
    std::string s = fileHeader(1, 3);
    for (const SectionInfo& i : listSections(file)) {
        if (i.tag != "CMS3") {
            s += file.substr(i.offset, i.end() - i.offset);
            continue;
        }
        s += section("CMS2", specCms3AsCms2(file.substr(i.payload(), static_cast<size_t>(i.stored))));
    }
    return s;
}

// The same file in the 1.1 layout: each CMSH mesh record as MESH, KNOT, NODE (every plane's
// weights stated, the same range-coded stream), SLIT and TANG sections, all stored. It holds the
// same document, so its size is what the 1.1 layout costs for the very same data.
inline std::string cmshAs11(const std::string& file) {
    std::string s = fileHeader(1, 1);
    for (const SectionInfo& i : listSections(file)) {
        const std::string payload = file.substr(i.payload(), static_cast<size_t>(i.stored));
        if (i.tag != "CMSH") {
            s += file.substr(i.offset, i.end() - i.offset);
            continue;
        }
        for (const SpecCmshMesh& m : specDecodeCmsh(payload)) {
            std::string mesh;
            for (int x : {m.info.C, m.info.R, m.slits, m.tangents}) putLE(mesh, static_cast<uint32_t>(x), 4);
            mesh.push_back(2);
            mesh.push_back(m.byRule ? 1 : 0);
            for (int f = 0; f < 7; ++f) putLE(mesh, static_cast<uint16_t>(m.info.e[f]), 2);
            std::string node;
            for (int o = 0; o < m.info.F; ++o) {
                const int c = kSpecOrder[o];
                putSvarint(node, m.weights.a[c]);
                if (kSpecValueOf[c] < 0) putSvarint(node, m.weights.b[c]);
                putSvarint(node, m.weights.s[c]);
            }
            node += payload.substr(m.streamAt, m.slitsAt - m.streamAt);
            s += section("MESH", mesh);
            s += section("KNOT", payload.substr(m.knotsAt, m.weightsAt - m.knotsAt));
            s += section("NODE", node);
            if (m.slits) s += section("SLIT", payload.substr(m.slitsAt, m.tangentsAt - m.slitsAt));
            if (m.tangents) s += section("TANG", payload.substr(m.tangentsAt, m.end - m.tangentsAt));
        }
    }
    return s;
}

// A newer minor (1.1) file: DOCU and MESH carry appended fields and an unknown optional
// section stands before END. A 1.0 reader must read it as goldenLossless.
inline std::string goldenNewerMinor() {
    const gm::Document d = goldenLossless();
    std::string s = fileHeader(1, 1);
    s += section("DOCU", docPayload(d) + std::string("\x01\x02\x03\x04", 4));
    s += section("XTRA", "future data the 1.0 reader skips", 0x01);
    for (const gm::GradientMesh& m : d.meshes) {
        const MeshPayloads p = specMeshPayloads(m);
        s += section("MESH", p.mesh + std::string(8, '\x7f'));
        s += section("KNOT", p.knot) + section("NODE", p.node);
        if (!m.slits.empty()) s += section("SLIT", p.slit);
        if (!m.tangents.empty()) s += section("TANG", p.tang);
        s += section("xtra", std::string(3, '\0'), 0x01, 7);  // even an unknown codec is skipped
    }
    return s + section("END ", "");
}

struct Malformed {
    std::string name;      // file name under tests/data/gmb/malformed/
    std::string bytes;
    std::string expected;  // a part of the error message
};

inline std::vector<Malformed> malformedCorpus() {
    std::vector<Malformed> out;
    const std::string good = specEncode(goldenLossless());
    // Version 1.0 compact, the compressed sections of which the compressed-* cases edit.
    const std::string compact =
        readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.0-compact.gmb");
    // Version 1.1 (encoding 2 in MESH KNOT NODE), which the writer no longer writes.
    const std::string coded =
        readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.1-compact.gmb");
    auto edit = [&](const std::string& base, const std::string& tag, int nth, size_t at,
                    uint64_t value, int width) {
        std::string s = base;
        const SectionInfo i = findSection(s, tag, nth);
        setLE(s, i.offset + at, value, width);
        fixCrc(s, i.offset);
        return s;
    };
    // A copy of goldenLossless with one mesh altered, written from the spec (no validation).
    auto withMesh = [](auto change) {
        gm::Document d = goldenLossless();
        change(d.meshes[0]);
        return specEncode(d);
    };

    out.push_back({"empty.gmb", "", "empty file"});
    out.push_back({"text.gmb", "mesh 5 4\nnode 0 0 10.0 5.0\n", "bad magic: not a .gmb file (looks like text)"});
    out.push_back({"png-signature.gmb", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), "bad magic"});
    {
        std::string s = good;
        s.erase(4, 1);  // CR LF -> LF, as a text-mode transfer does
        out.push_back({"crlf-converted.gmb", s, "line endings were converted"});
    }
    {
        std::string s = good;
        setLE(s, 8, 3, 2);
        out.push_back({"major-3.gmb", s, "unsupported .gmb major version 3 (this reader knows 1 and 2)"});
    }
    out.push_back({"header-only.gmb", fileHeader(), "truncated: the file ends before section DOCU"});
    out.push_back({"truncated-in-node.gmb", good.substr(0, findSection(good, "NODE").offset + 100),
                   "truncated in section NODE"});
    out.push_back({"missing-end.gmb", good.substr(0, findSection(good, "END ").offset),
                   "truncated: the file ends before section END"});
    out.push_back({"trailing-bytes.gmb", good + "xyz", "3 bytes after the END section"});
    {
        std::string s = good;
        s[findSection(s, "NODE").payload() + 17] ^= 0x10;
        out.push_back({"crc-mismatch.gmb", s, "CRC mismatch in section NODE"});
    }
    {
        std::string s = good;
        const size_t end = findSection(s, "END ").offset;
        s.insert(end, section("FUTR", "must be understood"));
        out.push_back({"unknown-required-section.gmb", s, "unknown required section 'FUTR'"});
    }
    {
        const SectionInfo knot = findSection(good, "KNOT");
        const SectionInfo node = findSection(good, "NODE");
        std::string s = good.substr(0, knot.offset) + good.substr(node.offset, node.end() - node.offset) +
                        good.substr(knot.offset, knot.end() - knot.offset) + good.substr(node.end());
        out.push_back({"section-out-of-order.gmb", s, "section NODE out of place: expected KNOT"});
    }
    out.push_back({"grid-100000x100000.gmb", edit(edit(good, "MESH", 0, 24, 100000, 4), "MESH", 0, 28, 100000, 4),
                   "grid 100000x100000 exceeds the limit of 65536 columns or rows"});
    out.push_back({"grid-65000x65000-nodes.gmb", edit(edit(good, "MESH", 0, 24, 65000, 4), "MESH", 0, 28, 65000, 4),
                   "nodes, over the limit of 16777216"});
    out.push_back({"meshes-4294967295.gmb", edit(good, "DOCU", 0, 32, 0xffffffffu, 4),
                   "4294967295 meshes exceed the limit"});
    out.push_back({"meshes-more-than-bytes.gmb", edit(good, "DOCU", 0, 32, 5000, 4),
                   "declares 5000 meshes but only"});
    out.push_back({"section-size-2-63.gmb", edit(good, "NODE", 0, 8, uint64_t(1) << 63, 8),
                   "truncated in section NODE"});
    out.push_back({"canvas-zero.gmb", edit(good, "DOCU", 0, 24, 0, 4), "canvas size 0x48 is not positive"});
    out.push_back({"canvas-huge.gmb", edit(good, "DOCU", 0, 28, 0xfffffff0u, 4), "exceeds the limit"});
    out.push_back({"slit-count-beyond-grid.gmb", edit(good, "MESH", 0, 32, 1000, 4), "slits cannot fit"});
    out.push_back({"slit-outside-grid.gmb",
                   withMesh([](gm::GradientMesh& m) { m.slits[0].row = 4; }),
                   "slit 0 (row 4, columns 1..4) is not inside the 5x4 grid"});
    out.push_back({"slit-columns-reversed.gmb",
                   withMesh([](gm::GradientMesh& m) { m.slits[0].i1 = 1; m.slits[0].i0 = 4; }),
                   "is not inside"});
    out.push_back({"slits-overlapping.gmb", withMesh([](gm::GradientMesh& m) {
                       gm::Slit t = m.slits[0];
                       t.i0 = 3;  // touches the first slit's columns 1..4
                       t.i1 = 4;
                       t.below.clear();
                       m.slits.push_back(t);
                   }),
                   "slit 1 touches slit 0 on row 2"});
    out.push_back({"tangent-outside-grid.gmb", withMesh([](gm::GradientMesh& m) { m.tangents[1].i = 5; }),
                   "names a corner outside the grid"});
    out.push_back({"nan-node.gmb", withMesh([](gm::GradientMesh& m) { m.node(2, 3).colV.g = std::nan(""); }),
                   "node (2,3) has a non-finite value"});
    out.push_back({"inf-knot.gmb", withMesh([](gm::GradientMesh& m) { m.v[4] = HUGE_VAL; }),
                   "v knot 4 is not finite"});
    out.push_back({"nan-slit-end.gmb", withMesh([](gm::GradientMesh& m) { m.slits[0].right.posU.x = -std::nan(""); }),
                   "non-finite end tangent"});
    out.push_back({"knots-not-increasing.gmb", withMesh([](gm::GradientMesh& m) { m.u[3] = m.u[2]; }),
                   "u knots not strictly increasing at index 3"});
    {
        // Compressed NODE of the compact file: its declared size lies in both directions.
        const SectionInfo node = findSection(compact, "NODE");
        out.push_back({"compressed-size-too-large.gmb", edit(compact, "NODE", 0, 16, node.raw + 1, 8),
                       "compressed data ends after"});
        out.push_back({"compressed-size-too-small.gmb", edit(compact, "NODE", 0, 16, node.raw - 1, 8),
                       "larger than its declared size"});
        out.push_back({"compressed-size-beyond-counts.gmb", edit(compact, "NODE", 0, 16, uint64_t(1) << 40, 8),
                       "its counts allow at most"});
        std::string s = compact;
        for (size_t k = node.payload() + 4; k < node.end() - 4; k += 3) s[k] = static_cast<char>(s[k] ^ 0x5a);
        fixCrc(s, node.offset);
        out.push_back({"compressed-data-corrupt.gmb", s, "in section NODE"});
    }
    out.push_back({"stored-size-mismatch.gmb", edit(good, "KNOT", 0, 16, 80, 8),
                   "stored uncompressed but declares 80 bytes for a 88-byte payload"});
    out.push_back({"unknown-codec.gmb", edit(good, "NODE", 0, 5, 9, 1), "unknown compression method 9"});
    out.push_back({"unknown-encoding.gmb", edit(good, "MESH", 0, 24 + 16, 7, 1), "unknown mesh encoding 7"});

    // Encoding 2 (range-coded NODE, version 1.1). Mesh 1 is the 2x1 mesh: 6 nodes, 15 planes.
    {
        std::string s = coded;
        setLE(s, 10, 0, 2);
        out.push_back({"coded-in-version-1.0.gmb", s, "mesh encoding 2 needs format version 1.1"});
    }
    out.push_back({"coded-exponent-out-of-range.gmb",
                   edit(coded, "MESH", 0, 24 + 18 + 2 * 2, 40, 2),
                   "derivative quantisation exponent 40 out of range"});
    {
        const SectionInfo node = findSection(coded, "NODE", 1);
        const std::string payload = coded.substr(node.payload(), static_cast<size_t>(node.stored));
        out.push_back({"coded-node-truncated.gmb",
                       withPayload(coded, "NODE", 1, payload.substr(0, payload.size() - 2)),
                       "truncated"});
        out.push_back({"coded-node-trailing-bytes.gmb",
                       withPayload(coded, "NODE", 1, payload + std::string("\0\0", 2)),
                       "2 unexpected bytes at the end of the NODE payload"});
        out.push_back({"coded-node-weights-only.gmb",
                       withPayload(coded, "NODE", 1, payload.substr(0, 20)), "truncated"});
        // Weights: pos.x's a of 40000, the rest 0; then a stream of zero residuals.
        std::string weights;
        putSvarint(weights, 40000);
        for (int k = 0; k < 34; ++k) putSvarint(weights, 0);
        SpecRangeEncoder zeros;
        SpecPlaneModels models[15];
        for (int p = 0; p < 15; ++p)
            for (int k = 0; k < 6; ++k) zeros.residual(models[p], 0, 0);
        const std::string stream = zeros.finish();
        out.push_back({"coded-weight-out-of-range.gmb",
                       withPayload(coded, "NODE", 1, weights + stream),
                       "plane weight 40000 out of range"});
        std::string nonZero = std::string(35, '\0') + stream;
        nonZero[35] = 1;
        out.push_back({"coded-stream-first-byte.gmb", withPayload(coded, "NODE", 1, nonZero),
                       "corrupt range-coded data"});
        // A residual of 2^60 for the first value: beyond the ±2^53 of a quantised value.
        SpecRangeEncoder huge;
        SpecPlaneModels m;
        huge.residual(m, 0, int64_t(1) << 60);
        out.push_back({"coded-value-out-of-range.gmb",
                       withPayload(coded, "NODE", 1, std::string(35, '\0') + huge.finish()),
                       "quantised value out of range"});
    }

    // CMSH sections (version 1.2). The golden document is one CMSH of two meshes: mesh 0 is 5x4
    // with a slit and two tangent breaks, mesh 1 is 2x1 (in `rule`, with colour derivatives
    // omitted: 9 planes); the payload is rebuilt around the parts the spec decoder locates.
    // The writer no longer writes CMSH: `cmsh` is the 1.2 golden file (the 1.2 writer's
    // goldenCompact11), `rule` the same file with the first CMSH payload of the 1.2 mixed golden
    // file (goldenCompact11Rule's two meshes), as the 1.2 writer wrote goldenCompact11Rule.
    auto cmshPayload = [](const std::string& file) {
        const SectionInfo i = findSection(file, "CMSH");
        return file.substr(i.payload(), static_cast<size_t>(i.stored));
    };
    const std::string cmsh = readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.2-compact.gmb");
    const std::string rule = withPayload(
        cmsh, "CMSH", 0,
        cmshPayload(readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.2-compact-mixed.gmb")));
    const std::string payload = cmshPayload(cmsh), rulePayload = cmshPayload(rule);
    const std::vector<SpecCmshMesh> records = specDecodeCmsh(payload),
                                    ruleRecords = specDecodeCmsh(rulePayload);
    auto withCmsh = [&](const std::string& base, const std::string& p) {
        return withPayload(base, "CMSH", 0, p);
    };
    auto varint = [](uint64_t x) {
        std::string v;
        while (x >= 0x80) {
            v.push_back(static_cast<char>((x & 0x7f) | 0x80));
            x >>= 7;
        }
        v.push_back(static_cast<char>(x));
        return v;
    };
    {
        std::string s = cmsh;
        setLE(s, 10, 1, 2);
        out.push_back({"cmsh-in-version-1.1.gmb", s, "section CMSH needs format version 1.2 (the file says 1.1)"});
    }
    out.push_back({"cmsh-compressed.gmb", edit(cmsh, "CMSH", 0, 5, 2, 1),
                   "section CMSH must be stored (codec 0), not codec 2"});
    out.push_back({"cmsh-no-mesh.gmb", withCmsh(cmsh, varint(0) + payload.substr(1)),
                   "a CMSH section holds no mesh"});
    out.push_back({"cmsh-more-meshes-than-declared.gmb", withCmsh(cmsh, varint(3) + payload.substr(1)),
                   "CMSH holds 3 meshes, but the document has only 2 more"});
    out.push_back({"cmsh-fewer-meshes-than-declared.gmb",
                   withCmsh(cmsh, varint(1) + payload.substr(1, records[1].start - 1)),
                   "section END  out of place: expected MESH, CMSH, CMS2 or CMS3"});
    // 25 meshes declared (DOCU too): 16 bytes each at least, more than the payload holds.
    out.push_back({"cmsh-records-beyond-payload.gmb",
                   withCmsh(edit(cmsh, "DOCU", 0, 32, 25, 4), varint(25) + payload.substr(1)),
                   "truncated: 400 bytes needed for 25 mesh records"});
    {
        std::string p = payload;
        p[2] = 80;  // e_posU (zigzag 80: 40), against e_pos -5 and e_knot
        out.push_back({"cmsh-exponent-out-of-range.gmb", withCmsh(cmsh, p),
                       "derivative quantisation exponent 40 out of range"});
    }
    {
        std::string p = payload;
        p[records[0].start + 4] = 4;
        out.push_back({"cmsh-unknown-flags.gmb", withCmsh(cmsh, p), "unknown mesh flags 4 in section CMSH (mesh 0)"});
    }
    {
        // Mesh 1 cut in the middle of a varint: after its first knot, a knot step whose every
        // byte says "more follows".
        size_t step = records[1].knotsAt;
        while (payload[step] & 0x80) ++step;
        out.push_back({"cmsh-truncated-varint.gmb",
                       withCmsh(cmsh, payload.substr(0, step + 1) + std::string(9, '\x80')),
                       "truncated: 1 bytes needed for a varint, 0 remain in section CMSH (mesh 1)"});
    }
    out.push_back({"cmsh-truncated-stream.gmb", withCmsh(cmsh, payload.substr(0, payload.size() - 2)),
                   "truncated"});
    out.push_back({"cmsh-trailing-bytes.gmb", withCmsh(cmsh, payload + std::string(3, '\0')),
                   "3 unexpected bytes at the end of the CMSH payload"});
    // Counts the remaining bytes cannot hold: 60000 columns of knots in a few bytes; eight
    // tangent breaks of mesh 1 where the payload ends.
    out.push_back({"cmsh-knots-beyond-payload.gmb",
                   withCmsh(cmsh, payload.substr(0, records[1].start) + varint(60000) +
                                      payload.substr(records[1].start + 1)),
                   "truncated: 60003 bytes needed for the knots"});
    {
        std::string p = payload;
        p[records[1].start + 3] = 8;
        out.push_back({"cmsh-tangents-beyond-payload.gmb", withCmsh(cmsh, p),
                       "truncated: 64 bytes needed for the tangent breaks, 0 remain in section CMSH (mesh 1)"});
    }
    out.push_back({"cmsh-grid-beyond-limit.gmb",
                   withCmsh(cmsh, payload.substr(0, records[1].start) + varint(100000) +
                                      payload.substr(records[1].start + 1)),
                   "grid 100000x1 exceeds the limit of 65536 columns or rows in section CMSH (mesh 1)"});
    // Weights: a mask naming a 10th plane of a mesh of 9; a stated weight out of range.
    out.push_back({"cmsh-weights-mask-beyond-planes.gmb",
                   withCmsh(rule, rulePayload.substr(0, ruleRecords[1].weightsAt) + varint(1 << 9) +
                                      rulePayload.substr(ruleRecords[1].streamAt)),
                   "weights mask 512 names planes beyond the 9 of this mesh"});
    {
        std::string weights = varint(1);  // pos.x stated: a = 256 + 40000
        putSvarint(weights, 40000);
        putSvarint(weights, 0);
        putSvarint(weights, 0);
        out.push_back({"cmsh-weight-out-of-range.gmb",
                       withCmsh(cmsh, payload.substr(0, records[1].weightsAt) + weights +
                                          payload.substr(records[1].streamAt)),
                       "plane weight 40256 out of range in section CMSH (mesh 1)"});
    }

    // CMS2 sections (version 1.3): the 1.3 writer's goldenCompact11, one CMS2 of both meshes.
    const std::string cms2 = readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.3-compact.gmb");
    const SectionInfo cms2Info = findSection(cms2, "CMS2");
    const std::string cms2Payload = cms2.substr(cms2Info.payload(), static_cast<size_t>(cms2Info.stored));
    const size_t streamAt = 7;  // M and the six exponents: one byte each here
    auto withCms2 = [&](const std::string& p) { return withPayload(cms2, "CMS2", 0, p); };
    {
        std::string s = cms2;
        setLE(s, 10, 2, 2);
        out.push_back({"cms2-in-version-1.2.gmb", s, "section CMS2 needs format version 1.3 (the file says 1.2)"});
    }
    out.push_back({"cms2-compressed.gmb", edit(cms2, "CMS2", 0, 5, 2, 1),
                   "section CMS2 must be stored (codec 0), not codec 2"});
    out.push_back({"cms2-no-mesh.gmb", withCms2(varint(0) + cms2Payload.substr(1)),
                   "a CMS2 section holds no mesh"});
    out.push_back({"cms2-more-meshes-than-declared.gmb", withCms2(varint(3) + cms2Payload.substr(1)),
                   "CMS2 holds 3 meshes, but the document has only 2 more"});
    // M says 1: the stream's bytes for mesh 1 are left over after it.
    out.push_back({"cms2-fewer-meshes-than-declared.gmb", withCms2(varint(1) + cms2Payload.substr(1)),
                   "unexpected bytes at the end of the CMS2 payload"});
    out.push_back({"cms2-trailing-bytes.gmb", withCms2(cms2Payload + std::string(3, '\0')),
                   "3 unexpected bytes at the end of the CMS2 payload"});
    out.push_back({"cms2-truncated-stream.gmb", withCms2(cms2Payload.substr(0, cms2Payload.size() - 2)),
                   "truncated"});
    out.push_back({"cms2-stream-only-start.gmb", withCms2(cms2Payload.substr(0, streamAt + 3)),
                   "truncated: 5 bytes needed for the start of the range-coded data"});
    {
        std::string p = cms2Payload;
        p[streamAt] = 1;
        out.push_back({"cms2-stream-first-byte.gmb", withCms2(p), "corrupt range-coded data"});
    }
    {
        std::string p = cms2Payload;
        p[2] = 80;  // e_posU (zigzag 80: 40), against e_pos -5 and e_knot
        out.push_back({"cms2-exponent-out-of-range.gmb", withCms2(p),
                       "derivative quantisation exponent 40 out of range (knot exponent -23, value exponent -5) "
                       "in section CMS2 (mesh 0)"});
    }
    // Streams crafted integer by integer (SpecCms2Writer), after M = 1 and the exponents.
    const std::string oneMesh = varint(1) + cms2Payload.substr(1, streamAt - 1);
    auto crafted = [&](auto write) {
        SpecCms2Writer w;
        write(w);
        return withCms2(oneMesh + w.finish());
    };
    using W = SpecCms2Writer;
    // A 2x1 mesh of 9 planes (colour by the rule) from `flags` on, all residuals 0.
    auto smallMesh = [](W& w, uint64_t flags, int64_t weightDelta) {
        w.U(W::Flags, flags);
        w.S(W::KnotExponent, -22);
        for (int count : {2, 1}) {
            w.S(W::KnotStart, 0);
            for (int k = 0; k < count; ++k) w.U(W::KnotStep, (1 << 22) - 1);
        }
        for (int o = 0; o < 9; ++o) {
            w.weighted(o, o == 0 && weightDelta != 0);
            if (o == 0 && weightDelta != 0)
                for (int64_t d : {weightDelta, int64_t(0), int64_t(0)}) w.S(W::WeightDelta, d);
        }
        for (int c : {0, 1, 7, 6, 8, 2, 3, 4, 5})
            for (int k = 0; k < 6; ++k) w.residual(c, 0, 0);
    };
    out.push_back({"cms2-grid-beyond-limit.gmb", crafted([](W& w) {
                       w.U(W::Size, 100000);
                       w.U(W::Size, 1);
                       w.U(W::Count, 0);
                       w.U(W::Count, 0);
                   }),
                   "grid 100000x1 exceeds the limit of 65536 columns or rows in section CMS2 (mesh 0)"});
    out.push_back({"cms2-unknown-flags.gmb", crafted([&](W& w) {
                       w.U(W::Size, 2);
                       w.U(W::Size, 1);
                       w.U(W::Count, 0);
                       w.U(W::Count, 0);
                       smallMesh(w, 4, 0);
                   }),
                   "unknown mesh flags 4 in section CMS2 (mesh 0)"});
    out.push_back({"cms2-weight-out-of-range.gmb", crafted([&](W& w) {
                       w.U(W::Size, 2);
                       w.U(W::Size, 1);
                       w.U(W::Count, 0);
                       w.U(W::Count, 0);
                       smallMesh(w, 1, 40000);
                   }),
                   "plane weight 40256 out of range in section CMS2 (mesh 0)"});
    // Without its flaw the crafted mesh reads (craftedSoundCms2, checked by the malformed
    // tests), so each case above fails for its own reason.
    out.push_back({"cms2-tangent-outside-grid.gmb", crafted([&](W& w) {
                       w.U(W::Size, 2);
                       w.U(W::Size, 1);
                       w.U(W::Count, 0);
                       w.U(W::Count, 1);
                       smallMesh(w, 1, 0);
                       for (uint64_t x : {2, 0, 0}) w.U(W::TangentIndex, x);
                       w.S(W::TangentValue, 1);
                       w.S(W::TangentValue, 1);
                   }),
                   "tangent break 0 names a corner outside the grid in section CMS2 (mesh 0)"});

    // CMS3 sections (version 1.4): the writer's goldenCompact11, one CMS3 of both meshes. They
    // share CMS2's parsing; these cases check that the tag gets its own checks and names.
    const std::string cms3 = encodeV1(goldenCompact11(), true, 0, gm::GmbStreams::Cms3);
    const SectionInfo cms3Info = findSection(cms3, "CMS3");
    const std::string cms3Payload = cms3.substr(cms3Info.payload(), static_cast<size_t>(cms3Info.stored));
    auto withCms3 = [&](const std::string& p) { return withPayload(cms3, "CMS3", 0, p); };
    {
        std::string s = cms3;
        setLE(s, 10, 3, 2);
        out.push_back({"cms3-in-version-1.3.gmb", s, "section CMS3 needs format version 1.4 (the file says 1.3)"});
    }
    out.push_back({"cms3-compressed.gmb", edit(cms3, "CMS3", 0, 5, 2, 1),
                   "section CMS3 must be stored (codec 0), not codec 2"});
    out.push_back({"cms3-more-meshes-than-declared.gmb", withCms3(varint(3) + cms3Payload.substr(1)),
                   "CMS3 holds 3 meshes, but the document has only 2 more"});
    out.push_back({"cms3-fewer-meshes-than-declared.gmb", withCms3(varint(1) + cms3Payload.substr(1)),
                   "unexpected bytes at the end of the CMS3 payload"});
    out.push_back({"cms3-trailing-bytes.gmb", withCms3(cms3Payload + std::string(3, '\0')),
                   "3 unexpected bytes at the end of the CMS3 payload"});
    out.push_back({"cms3-truncated-stream.gmb", withCms3(cms3Payload.substr(0, cms3Payload.size() - 2)),
                   "truncated"});
    {
        std::string p = cms3Payload;
        p[2] = 80;  // e_posU (zigzag 80: 40), against e_pos -5 and e_knot
        out.push_back({"cms3-exponent-out-of-range.gmb", withCms3(p),
                       "derivative quantisation exponent 40 out of range (knot exponent -23, value exponent -5) "
                       "in section CMS3 (mesh 0)"});
    }

    // Version 2.0: 1.4's sections in short framing (varint sizes, varint DOCU), built from the
    // spec (reframeAs20) out of the CMS3 file above.
    const std::string v2 = reframeAs20(cms3);
    const std::string v2Rest = v2.substr(listSections2(v2)[1].offset);  // the CMS3 and END sections
    auto v2Docu = [](const std::string& payload, uint8_t codec = 0, int64_t raw = -1) {
        return fileHeader(2, 0) + section2("DOCU", payload, 0, codec, raw);
    };
    auto v2Dims = [](uint64_t w, uint64_t h, uint64_t meshes) {
        std::string d;
        putVarint(d, w);
        putVarint(d, h);
        putVarint(d, meshes);
        return d;
    };
    {
        std::string s = cms3;  // a 1.4 file that claims to be 2.0
        setLE(s, 8, 2, 2);
        setLE(s, 10, 0, 2);
        out.push_back({"v2-in-1x-framing.gmb", s, "CRC mismatch in section DOCU"});
    }
    {
        std::string s = fileHeader(2, 0) + "DOCU" + std::string(2, '\0');
        putVarint(s, uint64_t(1) << 40);
        out.push_back({"v2-section-size-beyond-file.gmb", s + std::string(8, '\0'),
                       "truncated in section DOCU: its 1099511627776-byte payload and CRC need"});
    }
    out.push_back({"v2-truncated-size-varint.gmb", fileHeader(2, 0) + "DOCU" + std::string(2, '\0') + "\x80\x80",
                   "truncated: 1 bytes needed for a varint, 0 remain in section DOCU (its header)"});
    out.push_back({"v2-overlong-size-varint.gmb",
                   fileHeader(2, 0) + "DOCU" + std::string(2, '\0') + std::string(10, '\xff') + "\x01" +
                       std::string(4, '\0'),
                   "varint overflows 64 bits in section DOCU (its header)"});
    out.push_back({"v2-docu-size-beyond-counts.gmb", v2Docu(v2Dims(64, 48, 2), 2, int64_t(1) << 40) + v2Rest,
                   "section DOCU declares 1099511627776 uncompressed bytes; its counts allow at most 4096"});
    out.push_back({"v2-canvas-zero.gmb", v2Docu(v2Dims(0, 48, 2)) + v2Rest, "canvas size 0x48 is not positive"});
    out.push_back({"v2-docu-truncated.gmb", v2Docu(v2Dims(64, 48, 2).substr(0, 2)) + v2Rest,
                   "truncated: 1 bytes needed for a varint, 0 remain in section DOCU"});
    out.push_back({"v2-meshes-more-than-declared.gmb", v2Docu(v2Dims(64, 48, 1)) + v2Rest,
                   "CMS3 holds 2 meshes, but the document has only 1 more"});
    out.push_back({"v2-unknown-required-section.gmb",
                   v2Docu(v2Dims(64, 48, 2)) + section2("XTRA", "data") + v2Rest,
                   "unknown required section 'XTRA' (file version 2.0; this reader knows 1.5 and 2.1)"});
    out.push_back({"v2-crc-mismatch.gmb",
                   [&] {
                       std::string s = v2;
                       s[listSections2(v2)[1].payload + 3] ^= 0x20;
                       return s;
                   }(),
                   "CRC mismatch in section CMS3"});
    return out;
}

// The crafted CMS2 mesh of the malformed cases with nothing wrong: a 2x1 mesh, colours by the
// rule, a tangent break at patch (1, 0). It must read.
inline std::string craftedSoundCms2() {
    const std::string cms2 = readFile(std::string(GRADMESH_TEST_DATA) + "/gmb/golden-1.3-compact.gmb");
    const SectionInfo info = findSection(cms2, "CMS2");
    const std::string payload = cms2.substr(info.payload(), static_cast<size_t>(info.stored));
    using W = SpecCms2Writer;
    W w;
    w.U(W::Size, 2);
    w.U(W::Size, 1);
    w.U(W::Count, 0);
    w.U(W::Count, 1);
    w.U(W::Flags, 1);
    w.S(W::KnotExponent, -22);
    for (int count : {2, 1}) {
        w.S(W::KnotStart, 0);
        for (int k = 0; k < count; ++k) w.U(W::KnotStep, (1 << 22) - 1);
    }
    for (int o = 0; o < 9; ++o) w.weighted(o, 0);
    for (int c : {0, 1, 7, 6, 8, 2, 3, 4, 5})
        for (int k = 0; k < 6; ++k) w.residual(c, 0, 0);
    for (uint64_t x : {1, 0, 0}) w.U(W::TangentIndex, x);
    w.S(W::TangentValue, 1);
    w.S(W::TangentValue, 1);
    std::string p = payload.substr(0, 7);
    p[0] = 1;
    // DOCU: one mesh.
    std::string s = withPayload(cms2, "CMS2", 0, p + w.finish());
    const SectionInfo docu = findSection(s, "DOCU");
    setLE(s, docu.payload() + 8, 1, 4);
    fixCrc(s, docu.offset);
    return s;
}

}  // namespace gmbtest
