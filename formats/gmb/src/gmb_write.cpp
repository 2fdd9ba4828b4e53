// The .gmb writer (layout: gmb_format.cpp).
#include <cmath>
#include <cstdint>
#include <limits>

#include "formats/gmb.h"
#include "gmb_pvt.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

using namespace gmb;

// Measured on the quantised payloads of a 32x32-patch mesh: smooth synthetic, zstd -19 1165
// bytes against deflate -9 1344; with fitting-like noise, 12106 against 12403. zstd is never
// larger; the reader also accepts deflate, for other writers.
constexpr Codec kCompactCodec = Codec::Zstd;

class SectionSink {
public:
    void header() {
        for (char c : kMagic) w_.u8(static_cast<uint8_t>(c));
        w_.u16(kMajor);
        w_.u16(kMinor);
    }

    void add(const char (&tag)[5], const std::string& payload, bool tryCompress) {
        std::string packed;
        Codec codec = Codec::Stored;
        if (tryCompress && compressPayload(kCompactCodec, payload, packed)) codec = kCompactCodec;
        const std::string& stored = codec == Codec::Stored ? payload : packed;
        const size_t start = w_.str().size();
        w_.bytes(std::string(tag, 4));
        w_.u8(0);
        w_.u8(static_cast<uint8_t>(codec));
        w_.u16(0);
        w_.u64(stored.size());
        w_.u64(payload.size());
        w_.bytes(stored);
        w_.u32(crc32Of(w_.str().data() + start, w_.str().size() - start));
    }

    std::string take() { return std::move(w_.str()); }

private:
    ByteWriter w_;
};

struct MeshPayloads {
    std::string mesh, knot, node, slit, tang;
};

std::string meshHeader(const GradientMesh& m, Encoding encoding, uint8_t flags,
                       const int (&exponent)[kFieldCount]) {
    ByteWriter w;
    w.u32(static_cast<uint32_t>(m.columns()));
    w.u32(static_cast<uint32_t>(m.rows()));
    w.u32(static_cast<uint32_t>(m.slits.size()));
    w.u32(static_cast<uint32_t>(m.tangents.size()));
    w.u8(static_cast<uint8_t>(encoding));
    w.u8(flags);
    for (int e : exponent) w.i16(static_cast<int16_t>(e));
    return std::move(w.str());
}

void writeNodeF64(ByteWriter& w, const Node& n) {
    for (int k = 0; k < kNodeComponents; ++k) w.f64(nodeComponent(n, k));
}

MeshPayloads encodeFloat64(const GradientMesh& m) {
    MeshPayloads p;
    const int zero[kFieldCount] = {};
    p.mesh = meshHeader(m, Encoding::Float64, 0, zero);
    ByteWriter knot, node, slit, tang;
    for (double x : m.u) knot.f64(x);
    for (double x : m.v) knot.f64(x);
    for (const Node& n : m.nodes) writeNodeF64(node, n);
    for (const Slit& s : m.slits) {
        slit.u32(static_cast<uint32_t>(s.row));
        slit.u32(static_cast<uint32_t>(s.i0));
        slit.u32(static_cast<uint32_t>(s.i1));
        for (const SlitEnd* e : {&s.left, &s.right}) {
            slit.f64(e->posU.x);
            slit.f64(e->posU.y);
            for (int c = 0; c < 3; ++c) slit.f64(e->colU[c]);
        }
        for (const Node& n : s.below) writeNodeF64(slit, n);
    }
    for (const CornerTangent& t : m.tangents) {
        tang.u32(static_cast<uint32_t>(t.i));
        tang.u32(static_cast<uint32_t>(t.j));
        tang.u8(static_cast<uint8_t>(t.a));
        tang.u8(static_cast<uint8_t>(t.b));
        tang.f64(t.posU.x);
        tang.f64(t.posU.y);
        for (int c = 0; c < 3; ++c) tang.f64(t.colU[c]);
    }
    p.knot = std::move(knot.str());
    p.node = std::move(node.str());
    p.slit = std::move(slit.str());
    p.tang = std::move(tang.str());
    return p;
}

// Rounds x to the grid 2^e. False when the integer would be too large for exact decoding.
bool quantize(double x, int e, int64_t& q) {
    const double y = std::ldexp(x, -e);
    if (!(std::fabs(y) <= 4503599627370496.0)) return false;  // 2^52
    q = static_cast<int64_t>(std::llround(y));
    return true;
}

int binaryExponent(double x) {
    int p = 0;
    std::frexp(x, &p);  // x = m · 2^p, 0.5 <= m < 1
    return p;
}

// The exponents that meet GmbCompactBounds for this mesh (gmb.h explains the bounds).
void chooseExponents(const GradientMesh& m, int (&e)[kFieldCount]) {
    double minStep = std::numeric_limits<double>::infinity(), maxDu = 0, maxDv = 0;
    for (size_t i = 1; i < m.u.size(); ++i) {
        minStep = std::min(minStep, m.u[i] - m.u[i - 1]);
        maxDu = std::max(maxDu, m.u[i] - m.u[i - 1]);
    }
    for (size_t j = 1; j < m.v.size(); ++j) {
        minStep = std::min(minStep, m.v[j] - m.v[j - 1]);
        maxDv = std::max(maxDv, m.v[j] - m.v[j - 1]);
    }
    // 2^(p-1) <= smallest interval, so the knot grid is at most 2^-21 of it.
    e[kKnot] = binaryExponent(minStep) - 22;
    e[kPos] = -5;  // 1/32 px grid: error <= 1/64 px
    e[kCol] = -8;  // 1/256 grid: error <= 1/512 < 0.5/255
    // Largest interval < 2^p: a derivative step of 2^(-5-p) errs by < 1/64 px once scaled by Δu.
    const int pu = binaryExponent(maxDu), pv = binaryExponent(maxDv);
    e[kPosU] = -5 - pu;
    e[kPosV] = -5 - pv;
    e[kColU] = -8 - pu;
    e[kColV] = -8 - pv;
}

// False when some value does not fit the quantised grid (enormous coordinates, degenerate knot
// spacing); the caller then writes the mesh as float64, which is always within the bounds.
bool encodeQuantized(const GradientMesh& m, bool byRule, MeshPayloads& p) {
    int e[kFieldCount];
    chooseExponents(m, e);
    for (int x : e)
        if (x < -kMaxExponent || x > kMaxExponent) return false;
    p.mesh = meshHeader(m, Encoding::Quantized, byRule ? kMeshColorByRule : 0, e);
    const int F = byRule ? kNodeComponentsByRule : kNodeComponents;
    const int C = m.columns(), R = m.rows();

    ByteWriter knot;
    for (const std::vector<double>* k : {&m.u, &m.v}) {
        int64_t prev = 0;
        for (size_t i = 0; i < k->size(); ++i) {
            int64_t q;
            if (!quantize((*k)[i], e[kKnot], q)) return false;
            if (i == 0) {
                knot.svarint(q);
            } else {
                if (q <= prev) return false;
                knot.varint(static_cast<uint64_t>(q - prev));
            }
            prev = q;
        }
    }

    const size_t n = m.nodes.size();
    std::vector<int64_t> planes(static_cast<size_t>(F) * n);
    for (int c = 0; c < F; ++c)
        for (size_t k = 0; k < n; ++k)
            if (!quantize(nodeComponent(m.nodes[k], c), e[fieldOfComponent(c)], planes[c * n + k]))
                return false;
    ByteWriter node;
    for (int c = 0; c < F; ++c) {
        const int64_t* q = &planes[c * n];
        for (int j = 0; j <= R; ++j) {
            for (int i = 0; i <= C; ++i) {
                const size_t k = static_cast<size_t>(j) * (C + 1) + i;
                int64_t pred = 0;
                if (i > 0 && j > 0) pred = q[k - 1] + q[k - (C + 1)] - q[k - C - 2];
                else if (i > 0) pred = q[k - 1];
                else if (j > 0) pred = q[k - (C + 1)];
                node.svarint(q[k] - pred);
            }
        }
    }

    ByteWriter slit;
    for (const Slit& s : m.slits) {
        slit.varint(static_cast<uint64_t>(s.row));
        slit.varint(static_cast<uint64_t>(s.i0));
        slit.varint(static_cast<uint64_t>(s.i1));
        for (const SlitEnd* end : {&s.left, &s.right}) {
            int64_t q;
            for (double x : {end->posU.x, end->posU.y}) {
                if (!quantize(x, e[kPosU], q)) return false;
                slit.svarint(q);
            }
            if (!byRule) {
                for (int c = 0; c < 3; ++c) {
                    if (!quantize(end->colU[c], e[kColU], q)) return false;
                    slit.svarint(q);
                }
            }
        }
        for (size_t b = 0; b < s.below.size(); ++b) {
            const size_t above = static_cast<size_t>(s.row) * (C + 1) + s.i0 + 1 + b;
            for (int c = 0; c < F; ++c) {
                int64_t q;
                if (!quantize(nodeComponent(s.below[b], c), e[fieldOfComponent(c)], q)) return false;
                slit.svarint(q - planes[c * n + above]);
            }
        }
    }

    ByteWriter tang;
    for (const CornerTangent& t : m.tangents) {
        tang.varint(static_cast<uint64_t>(t.i));
        tang.varint(static_cast<uint64_t>(t.j));
        tang.u8(static_cast<uint8_t>(t.a | (t.b << 1)));
        int64_t q;
        for (double x : {t.posU.x, t.posU.y}) {
            if (!quantize(x, e[kPosU], q)) return false;
            tang.svarint(q);
        }
        for (int c = 0; c < 3 && !byRule; ++c) {
            if (!quantize(t.colU[c], e[kColU], q)) return false;
            tang.svarint(q);
        }
    }
    p.knot = std::move(knot.str());
    p.node = std::move(node.str());
    p.slit = std::move(slit.str());
    p.tang = std::move(tang.str());
    return true;
}

}  // namespace

std::string encodeGmb(const Document& doc, bool compact) {
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error("cannot write an invalid document: " + problem);
    if (doc.meshes.size() > UINT32_MAX) throw Error("too many meshes for a .gmb file");

    SectionSink out;
    out.header();
    ByteWriter docu;
    docu.u32(static_cast<uint32_t>(doc.width));
    docu.u32(static_cast<uint32_t>(doc.height));
    docu.u32(static_cast<uint32_t>(doc.meshes.size()));
    out.add("DOCU", docu.str(), false);

    for (const GradientMesh& m : doc.meshes) {
        MeshPayloads p;
        if (!compact || !encodeQuantized(m, followsColorRule(m), p)) p = encodeFloat64(m);
        out.add("MESH", p.mesh, false);
        out.add("KNOT", p.knot, compact);
        out.add("NODE", p.node, compact);
        if (!m.slits.empty()) out.add("SLIT", p.slit, compact);
        if (!m.tangents.empty()) out.add("TANG", p.tang, compact);
    }
    out.add("END ", std::string(), false);
    return out.take();
}

}  // namespace gm
