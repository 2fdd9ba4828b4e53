// Test support for .gmb: meshes to round-trip, and an independent lossless writer built from the
// specification in docs/formats.md (its own CRC-32 too), so that the
// tests can write files the real writer refuses to (invalid meshes, newer minors, bad sizes)
// and can check that the real writer follows the spec byte for byte.
#pragma once

#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gmbtest {

inline uint32_t crc32(const std::string& s, size_t begin, size_t end) {
    uint32_t c = 0xffffffffu;
    for (size_t k = begin; k < end; ++k) {
        c ^= static_cast<unsigned char>(s[k]);
        for (int b = 0; b < 8; ++b) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return ~c;
}

inline void putLE(std::string& s, uint64_t x, int n) {
    for (int k = 0; k < n; ++k) s.push_back(static_cast<char>((x >> (8 * k)) & 0xff));
}
inline void setLE(std::string& s, size_t at, uint64_t x, int n) {
    for (int k = 0; k < n; ++k) s[at + k] = static_cast<char>((x >> (8 * k)) & 0xff);
}
inline uint64_t getLE(const std::string& s, size_t at, int n) {
    uint64_t x = 0;
    for (int k = 0; k < n; ++k) x |= uint64_t(static_cast<unsigned char>(s[at + k])) << (8 * k);
    return x;
}
inline void putF64(std::string& s, double x) {
    uint64_t bits;
    std::memcpy(&bits, &x, 8);
    putLE(s, bits, 8);
}

inline std::string fileHeader(uint16_t major = 1, uint16_t minor = 0) {
    std::string s("\x89GMB\r\n\x1a\n", 8);
    putLE(s, major, 2);
    putLE(s, minor, 2);
    return s;
}

// One framed section. `rawSize` defaults to the payload's size (stored, codec 0).
inline std::string section(const std::string& tag, const std::string& payload, uint8_t flags = 0,
                           uint8_t codec = 0, int64_t rawSize = -1) {
    std::string s = tag.substr(0, 4);
    s.push_back(static_cast<char>(flags));
    s.push_back(static_cast<char>(codec));
    putLE(s, 0, 2);
    putLE(s, payload.size(), 8);
    putLE(s, rawSize < 0 ? payload.size() : static_cast<uint64_t>(rawSize), 8);
    s += payload;
    putLE(s, crc32(s, 0, s.size()), 4);
    return s;
}

inline void putNode(std::string& s, const gm::Node& n) {
    for (double x : {n.pos.x, n.pos.y, n.posU.x, n.posU.y, n.posV.x, n.posV.y, n.col.r, n.col.g,
                     n.col.b, n.colU.r, n.colU.g, n.colU.b, n.colV.r, n.colV.g, n.colV.b})
        putF64(s, x);
}

// The float64 payloads of one mesh, written without any validation.
struct MeshPayloads {
    std::string mesh, knot, node, slit, tang;
};
inline MeshPayloads specMeshPayloads(const gm::GradientMesh& m) {
    MeshPayloads p;
    putLE(p.mesh, static_cast<uint32_t>(m.u.size() - 1), 4);
    putLE(p.mesh, static_cast<uint32_t>(m.v.size() - 1), 4);
    putLE(p.mesh, m.slits.size(), 4);
    putLE(p.mesh, m.tangents.size(), 4);
    p.mesh.push_back('\0');  // float64 encoding
    // Flags: bit 1 for the Bicubic colour model; then zero exponents.
    p.mesh.push_back(m.colorModel == gm::ColorModel::Bicubic ? '\x02' : '\0');
    p.mesh.append(14, '\0');
    for (double x : m.u) putF64(p.knot, x);
    for (double x : m.v) putF64(p.knot, x);
    for (const gm::Node& n : m.nodes) putNode(p.node, n);
    for (const gm::Slit& sl : m.slits) {
        putLE(p.slit, static_cast<uint32_t>(sl.row), 4);
        putLE(p.slit, static_cast<uint32_t>(sl.i0), 4);
        putLE(p.slit, static_cast<uint32_t>(sl.i1), 4);
        for (const gm::SlitEnd* e : {&sl.left, &sl.right})
            for (double x : {e->posU.x, e->posU.y, e->colU.r, e->colU.g, e->colU.b}) putF64(p.slit, x);
        for (const gm::Node& n : sl.below) putNode(p.slit, n);
    }
    for (const gm::CornerTangent& t : m.tangents) {
        putLE(p.tang, static_cast<uint32_t>(t.i), 4);
        putLE(p.tang, static_cast<uint32_t>(t.j), 4);
        putLE(p.tang, static_cast<uint8_t>(t.a), 1);
        putLE(p.tang, static_cast<uint8_t>(t.b), 1);
        for (double x : {t.posU.x, t.posU.y, t.colU.r, t.colU.g, t.colU.b}) putF64(p.tang, x);
    }
    return p;
}

inline std::string docPayload(const gm::Document& d) {
    std::string s;
    putLE(s, static_cast<uint32_t>(d.width), 4);
    putLE(s, static_cast<uint32_t>(d.height), 4);
    putLE(s, d.meshes.size(), 4);
    return s;
}

// A lossless file from the spec alone.
inline std::string specEncode(const gm::Document& d) {
    std::string s = fileHeader();
    s += section("DOCU", docPayload(d));
    for (const gm::GradientMesh& m : d.meshes) {
        const MeshPayloads p = specMeshPayloads(m);
        s += section("MESH", p.mesh) + section("KNOT", p.knot) + section("NODE", p.node);
        if (!m.slits.empty()) s += section("SLIT", p.slit);
        if (!m.tangents.empty()) s += section("TANG", p.tang);
    }
    return s + section("END ", "");
}

// ---- Version 2.x framing (from the spec): varint sizes, the raw size only when compressed,
// and a varint DOCU.

inline void putVarint(std::string& s, uint64_t x) {
    while (x >= 0x80) {
        s.push_back(static_cast<char>((x & 0x7f) | 0x80));
        x >>= 7;
    }
    s.push_back(static_cast<char>(x));
}
inline uint64_t getVarint(const std::string& s, size_t& at) {
    uint64_t x = 0;
    for (int shift = 0; at < s.size(); shift += 7) {
        const auto b = static_cast<unsigned char>(s[at++]);
        x |= uint64_t(b & 0x7f) << shift;
        if (!(b & 0x80)) break;
    }
    return x;
}

// One section in 2.x framing. `rawSize` defaults to the payload's size; it is written only for
// a compressed section (codec != 0).
inline std::string section2(const std::string& tag, const std::string& payload, uint8_t flags = 0,
                            uint8_t codec = 0, int64_t rawSize = -1) {
    std::string s = tag.substr(0, 4);
    s.push_back(static_cast<char>(flags));
    s.push_back(static_cast<char>(codec));
    putVarint(s, payload.size());
    if (codec != 0) putVarint(s, rawSize < 0 ? payload.size() : static_cast<uint64_t>(rawSize));
    s += payload;
    putLE(s, crc32(s, 0, s.size()), 4);
    return s;
}

struct Section2Info {
    size_t offset = 0, payload = 0;  // of the section header, of its payload
    std::string tag;
    uint8_t flags = 0, codec = 0;
    uint64_t stored = 0, raw = 0;
    size_t end() const { return payload + static_cast<size_t>(stored) + 4; }
};

// The sections of a well-formed 2.x file.
inline std::vector<Section2Info> listSections2(const std::string& s) {
    std::vector<Section2Info> out;
    size_t pos = 12;
    while (pos + 11 <= s.size()) {
        Section2Info i;
        i.offset = pos;
        i.tag = s.substr(pos, 4);
        i.flags = static_cast<uint8_t>(s[pos + 4]);
        i.codec = static_cast<uint8_t>(s[pos + 5]);
        size_t at = pos + 6;
        i.stored = getVarint(s, at);
        i.raw = i.codec != 0 ? getVarint(s, at) : i.stored;
        i.payload = at;
        out.push_back(i);
        pos = i.end();
    }
    return out;
}

struct SectionInfo;
inline std::vector<SectionInfo> listSections(const std::string& s);

// A 1.x file (well formed) in the 2.0 framing: the same sections, payloads and flags, each
// section's sizes as varints, DOCU's three u32 as varints; version 2.0.
inline std::string reframeAs20(const std::string& v1);

struct SectionInfo {
    size_t offset = 0;  // of the section header
    std::string tag;
    uint8_t flags = 0, codec = 0;
    uint64_t stored = 0, raw = 0;
    size_t payload() const { return offset + 24; }
    size_t end() const { return offset + 28 + static_cast<size_t>(stored); }
};

// The sections of a well-formed file.
inline std::vector<SectionInfo> listSections(const std::string& s) {
    std::vector<SectionInfo> out;
    size_t pos = 12;
    while (pos + 28 <= s.size()) {
        SectionInfo i;
        i.offset = pos;
        i.tag = s.substr(pos, 4);
        i.flags = static_cast<uint8_t>(s[pos + 4]);
        i.codec = static_cast<uint8_t>(s[pos + 5]);
        i.stored = getLE(s, pos + 8, 8);
        i.raw = getLE(s, pos + 16, 8);
        out.push_back(i);
        pos = i.end();
    }
    return out;
}

inline SectionInfo findSection(const std::string& s, const std::string& tag, int nth = 0) {
    for (const SectionInfo& i : listSections(s))
        if (i.tag == tag && nth-- == 0) return i;
    return {};
}

inline std::string reframeAs20(const std::string& v1) {
    std::string s = fileHeader(2, 0);
    for (const SectionInfo& i : listSections(v1)) {
        std::string payload = v1.substr(i.payload(), static_cast<size_t>(i.stored));
        if (i.tag == "DOCU") {
            std::string docu;
            for (int k = 0; k < 3; ++k) putVarint(docu, getLE(payload, 4 * k, 4));
            payload = docu + payload.substr(12);
        }
        s += section2(i.tag, payload, i.flags, i.codec, static_cast<int64_t>(i.raw));
    }
    return s;
}

// Recomputes the CRC of the section at `offset` after a test edited it.
inline void fixCrc(std::string& s, size_t offset) {
    const uint64_t stored = getLE(s, offset + 8, 8);
    if (stored > s.size() || offset + 28 + stored > s.size()) return;  // a size edited to lie
    const size_t end = offset + 24 + static_cast<size_t>(stored);
    setLE(s, end, crc32(s, offset, end), 4);
}

// Random knots (intervals over several orders of magnitude) and random values, including
// awkward doubles that only a bit-exact writer keeps: -0.0, subnormals, huge and tiny values.
inline gm::GradientMesh randomMesh(unsigned seed, int columns = 0, int rows = 0) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    if (columns == 0) columns = 2 + static_cast<int>(rng() % 8);
    if (rows == 0) rows = 2 + static_cast<int>(rng() % 8);
    gm::GradientMesh m(columns, rows);
    for (std::vector<double>* k : {&m.u, &m.v}) {
        double x = (unit(rng) - 0.5) * 100;
        for (double& knot : *k) {
            knot = x;
            x += std::ldexp(0.5 + unit(rng), static_cast<int>(rng() % 20) - 10);
        }
    }
    auto value = [&](int k) {
        switch (rng() % 16) {
            case 0: return -0.0;
            case 1: return 4.9406564584124654e-324 * static_cast<double>(1 + rng() % 1000);
            case 2: return (unit(rng) - 0.5) * 1e300;
            case 3: return (unit(rng) - 0.5) * 1e-300;
            default: return (unit(rng) - 0.5) * (k < 6 ? 2000.0 : 3.0);
        }
    };
    for (gm::Node& n : m.nodes) {
        int k = 0;
        for (double* x : {&n.pos.x, &n.pos.y, &n.posU.x, &n.posU.y, &n.posV.x, &n.posV.y,
                          &n.col.r, &n.col.g, &n.col.b, &n.colU.r, &n.colU.g, &n.colU.b, &n.colV.r,
                          &n.colV.g, &n.colV.b})
            *x = value(k++);
    }
    return m;
}

// What fitting to a real image leaves on an otherwise smooth synthetic mesh: positions off by
// up to half a pixel, tangents by a few percent, colours by a few 1/255 steps.
inline void addFittingNoise(gm::GradientMesh& m, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> noise(-1.0, 1.0);
    auto perturb = [&](gm::Node& n) {
        n.pos = n.pos + gm::Vec2{0.5 * noise(rng), 0.5 * noise(rng)};
        n.posU = n.posU * (1 + 0.03 * noise(rng));
        n.posV = n.posV * (1 + 0.03 * noise(rng));
        for (int c = 0; c < 3; ++c) {
            n.col[c] += 3.0 / 255 * noise(rng);
            n.colU[c] = n.colU[c] * (1 + 0.1 * noise(rng)) + 0.01 * noise(rng);
            n.colV[c] = n.colV[c] * (1 + 0.1 * noise(rng)) + 0.01 * noise(rng);
        }
    };
    for (gm::Node& n : m.nodes) perturb(n);
    for (gm::Slit& s : m.slits)
        for (gm::Node& n : s.below) perturb(n);
}

inline std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline void writeFile(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace gmbtest
