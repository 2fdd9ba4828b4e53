// The .gmb writer (layout: docs/formats.md).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "formats/gmb.h"
#include "gmb_node_planes.h"
#include "gmb_pvt.h"
#include "gmb_shapes.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

using namespace gmb;

// zstd: on quantised payloads it is never larger than deflate; the reader also accepts
// deflate, for other writers.
constexpr Codec kCompactCodec = Codec::Zstd;

class SectionSink {
public:
    // `shortFraming`: version 2 (varint sizes in section headers), else 1.x.
    explicit SectionSink(bool shortFraming) : short_(shortFraming) {}

    void header(uint16_t minor) {
        for (char c : kMagic) w_.u8(static_cast<uint8_t>(c));
        w_.u16(short_ ? kMajorShort : kMajor);
        w_.u16(short_ ? kMinorShort : minor);
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
        if (short_) {
            w_.varint(stored.size());
            if (codec != Codec::Stored) w_.varint(payload.size());
        } else {
            w_.u16(0);
            w_.u64(stored.size());
            w_.u64(payload.size());
        }
        w_.bytes(stored);
        w_.u32(crc32Of(w_.str().data() + start, w_.str().size() - start));
    }

    std::string take() { return std::move(w_.str()); }

    bool shortFraming() const { return short_; }

private:
    bool short_;
    ByteWriter w_;
};

// A mesh quantised for encoding 2, as a CMS2 or CMS3 stream codes it: everything but the
// node planes as the integers the stream holds, in their order.
struct CodedMesh {
    bool byRule = false;   // no colour derivatives stored
    bool bicubic = false;  // ColorModel::Bicubic (implies byRule)
    CodedGrid grid;  // knots, spans, exponents (all seven) and node planes
    struct SlitInts {
        uint64_t row = 0, i0 = 0, i1 = 0;
        std::vector<int64_t> ends;   // left end, then right end: posU.x posU.y [colU.rgb]
        std::vector<int64_t> below;  // below copies: record by record, q(below) - q(above)
    };
    struct TangentInts {
        uint64_t i = 0, j = 0, corner = 0;  // corner: a | b << 1
        std::vector<int64_t> values;        // posU.x posU.y [colU.rgb]
    };
    std::vector<SlitInts> slits;
    std::vector<TangentInts> tangents;
};

// One mesh as float64 sections (MESH KNOT NODE [SLIT] [TANG]), or (`coded`) quantised for a
// CMS2 or CMS3 section.
struct MeshPayloads {
    std::string mesh, knot, node, slit, tang;
    bool coded = false;
    CodedMesh quantised;  // when coded
};

// The exponents a CMS2 or CMS3 section states once for all its meshes (all but the knots').
bool sameSharedExponents(const MeshPayloads& a, const MeshPayloads& b) {
    const int* x = a.quantised.grid.exponent;
    const int* y = b.quantised.grid.exponent;
    return std::equal(x + kPos, x + kFieldCount, y + kPos);
}

// The MESH payload of a float64 mesh (flags: the colour model only; zero exponents).
std::string float64MeshHeader(const GradientMesh& m) {
    ByteWriter w;
    w.u32(static_cast<uint32_t>(m.columns()));
    w.u32(static_cast<uint32_t>(m.rows()));
    w.u32(static_cast<uint32_t>(m.slits.size()));
    w.u32(static_cast<uint32_t>(m.tangents.size()));
    w.u8(static_cast<uint8_t>(Encoding::Float64));
    w.u8(m.colorModel == ColorModel::Bicubic ? kMeshColorBicubic : 0);
    for (int f = 0; f < kFieldCount; ++f) w.i16(0);
    return std::move(w.str());
}

void writeNodeF64(ByteWriter& w, const Node& n) {
    for (int k = 0; k < kNodeComponents; ++k) w.f64(nodeComponent(n, k));
}

MeshPayloads encodeFloat64(const GradientMesh& m) {
    MeshPayloads p;
    p.mesh = float64MeshHeader(m);
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

// The exponents that meet GmbCompactBounds (gmb.h explains the bounds). Derivatives are stored
// as tangents, derivative × span of their node (docs/formats.md, encoding 2), so their grid is
// in pixels and 0–1 colour units whatever the knot scale.
void chooseExponents(const GradientMesh& m, const GmbCompactShifts& shift, int (&e)[kFieldCount]) {
    double minStep = std::numeric_limits<double>::infinity();
    for (size_t i = 1; i < m.u.size(); ++i) minStep = std::min(minStep, m.u[i] - m.u[i - 1]);
    for (size_t j = 1; j < m.v.size(); ++j) minStep = std::min(minStep, m.v[j] - m.v[j - 1]);
    // 2^(p-1) <= smallest interval, so the knot grid is at most 2^-21 of it (2^(shift.knot-21)).
    e[kKnot] = binaryExponent(minStep) - 22 + shift.knot;
    // Level 0: positions on a 1/32 px grid (error <= 1/64 px), colours on 1/256 (error <= 1/512
    // < 0.5/255), position tangents on 1/8 px (error <= 1/16 px), colour tangents on 1/128
    // (error <= 1/256); coarser levels shift each grid.
    e[kPos] = -5 + shift.position;
    e[kCol] = -8 + shift.color;
    e[kPosU] = e[kPosV] = -3 + shift.positionTangent;
    e[kColU] = e[kColV] = -7 + shift.colorTangent;
}

// The larger knot interval next to each knot (what a node's derivative is scaled by in the
// patches that use it), in the mesh's own units.
std::vector<double> neighbouringIntervals(const std::vector<double>& k) {
    std::vector<double> out(k.size(), 0.0);
    for (size_t i = 0; i < k.size(); ++i) {
        if (i > 0) out[i] = std::max(out[i], k[i] - k[i - 1]);
        if (i + 1 < k.size()) out[i] = std::max(out[i], k[i + 1] - k[i]);
    }
    return out;
}

// Quantises the values of one mesh for encoding 2 and checks every one against its bound.
class CodedQuantizer {
public:
    CodedQuantizer(const GradientMesh& m, const int (&e)[kFieldCount], const CodedGrid& g,
                   const GmbCompactShifts& shift)
        : e_(e),
          positionTangentBound_(std::ldexp(GmbCompactBounds::positionTangent, shift.positionTangent)),
          colorTangentBound_(std::ldexp(GmbCompactBounds::colorTangent, shift.colorTangent)),
          g_(g),
          intervalU_(neighbouringIntervals(m.u)),
          intervalV_(neighbouringIntervals(m.v)) {}

    // Component c (node-record order) of a node in column i, row j.
    bool component(const Node& n, int c, int i, int j, int64_t& q) const {
        const double x = nodeComponent(n, c);
        switch (fieldOfComponent(c)) {
            case kPosU:
                return derivative(x, kPosU, g_.spanU[i], intervalU_[i], q);
            case kPosV:
                return derivative(x, kPosV, g_.spanV[j], intervalV_[j], q);
            case kColU:
                return derivative(x, kColU, g_.spanU[i], intervalU_[i], q);
            case kColV:
                return derivative(x, kColV, g_.spanV[j], intervalV_[j], q);
            default:
                return quantize(x, e_[fieldOfComponent(c)], q);
        }
    }
    // A u-derivative on its own (slit end, tangent break) at column i.
    bool derivativeU(double x, Field f, int i, int64_t& q) const {
        return derivative(x, f, g_.spanU[i], intervalU_[i], q);
    }

private:
    // Rounds x · span to the tangent grid; false if that does not fit, or (a safety net: the
    // +2 of the span leaves room for the knots' own rounding) if the decoded value misses the
    // stated bound.
    bool derivative(double x, Field f, uint64_t span, double interval, int64_t& q) const {
        const double y = std::ldexp(x * static_cast<double>(span), e_[kKnot] - e_[f]);
        if (!(std::fabs(y) <= 4503599627370496.0)) return false;  // 2^52
        q = static_cast<int64_t>(std::llround(y));
        const double bound = (f == kPosU || f == kPosV) ? positionTangentBound_ : colorTangentBound_;
        const double back = codedDerivative(q, e_[f] - e_[kKnot], span);
        return std::fabs(x - back) * interval <= bound;
    }

    const int (&e_)[kFieldCount];
    double positionTangentBound_, colorTangentBound_;
    const CodedGrid& g_;
    std::vector<double> intervalU_, intervalV_;
};

// The knots of both directions on the knot grid (exponent e[kKnot]); false when one does not
// fit or two round to the same value.
bool quantizeKnots(const GradientMesh& m, const int (&e)[kFieldCount], CodedGrid& g) {
    for (const std::vector<double>* k : {&m.u, &m.v}) {
        std::vector<int64_t>& knots = k == &m.u ? g.knotU : g.knotV;
        for (size_t i = 0; i < k->size(); ++i) {
            int64_t q;
            if (!quantize((*k)[i], e[kKnot], q)) return false;
            if (i > 0 && q <= knots.back()) return false;
            knots.push_back(q);
        }
    }
    return true;
}

// Every node's components into the grid's planes (plane c holds component c of all nodes).
bool quantizeNodes(const GradientMesh& m, const CodedQuantizer& quant, CodedGrid& g) {
    const int F = g.components, C = g.columns, R = g.rows;
    const size_t n = m.nodes.size();
    g.planes.resize(static_cast<size_t>(F) * n);
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            const size_t k = static_cast<size_t>(j) * (C + 1) + i;
            for (int c = 0; c < F; ++c)
                if (!quant.component(m.nodes[k], c, i, j, g.planes[c * n + k])) return false;
        }
    return true;
}

// A u-derivative's position (and, unless colours follow the rule, colour) components at
// column `column`, appended to `out`.
bool quantizeDerivativeU(const CodedQuantizer& quant, Vec2 posU, const Vec3& colU, int column,
                         bool byRule, std::vector<int64_t>& out) {
    int64_t q;
    for (double x : {posU.x, posU.y}) {
        if (!quant.derivativeU(x, kPosU, column, q)) return false;
        out.push_back(q);
    }
    for (int c = 0; c < 3 && !byRule; ++c) {
        if (!quant.derivativeU(colU[c], kColU, column, q)) return false;
        out.push_back(q);
    }
    return true;
}

// A slit: its ends' u-derivatives, and its lower nodes as differences from the nodes above.
bool quantizeSlit(const Slit& s, const CodedQuantizer& quant, const CodedGrid& g, bool byRule,
                  CodedMesh::SlitInts& slit) {
    const int F = g.components, C = g.columns;
    const size_t n = g.planes.size() / static_cast<size_t>(F);
    slit.row = static_cast<uint64_t>(s.row);
    slit.i0 = static_cast<uint64_t>(s.i0);
    slit.i1 = static_cast<uint64_t>(s.i1);
    for (const SlitEnd* end : {&s.left, &s.right}) {
        const int column = end == &s.left ? s.i0 : s.i1;
        if (!quantizeDerivativeU(quant, end->posU, end->colU, column, byRule, slit.ends))
            return false;
    }
    for (size_t b = 0; b < s.below.size(); ++b) {
        const int column = s.i0 + 1 + static_cast<int>(b);
        const size_t above = static_cast<size_t>(s.row) * (C + 1) + column;
        for (int c = 0; c < F; ++c) {
            int64_t q;
            if (!quant.component(s.below[b], c, column, s.row, q)) return false;
            slit.below.push_back(q - g.planes[c * n + above]);
        }
    }
    return true;
}

bool quantizeTangent(const CornerTangent& t, const CodedQuantizer& quant, bool byRule,
                     CodedMesh::TangentInts& tangent) {
    tangent.i = static_cast<uint64_t>(t.i);
    tangent.j = static_cast<uint64_t>(t.j);
    tangent.corner = static_cast<uint64_t>(t.a | (t.b << 1));
    return quantizeDerivativeU(quant, t.posU, t.colU, t.i + t.a, byRule, tangent.values);
}

// Encoding 2, quantised for a CMS2 or CMS3 section. False when some value does not fit the
// quantised grid (enormous coordinates, degenerate knot spacing); the caller then writes the
// mesh as float64, always within bounds.
bool encodeCoded(const GradientMesh& m, bool byRule, const GmbCompactShifts& shift,
                 MeshPayloads& p) {
    int e[kFieldCount];
    chooseExponents(m, shift, e);
    for (int x : e)
        if (x < -kMaxExponent || x > kMaxExponent) return false;
    if (!codedExponentProblem(e).empty()) return false;

    CodedMesh out;
    out.byRule = byRule;
    out.bicubic = m.colorModel == ColorModel::Bicubic;
    CodedGrid& g = out.grid;
    g.columns = m.columns();
    g.rows = m.rows();
    g.components = byRule ? kNodeComponentsByRule : kNodeComponents;
    std::copy(std::begin(e), std::end(e), g.exponent);
    if (!quantizeKnots(m, e, g)) return false;
    g.spanU = localSpans(g.knotU);
    g.spanV = localSpans(g.knotV);
    const CodedQuantizer quant(m, e, g, shift);
    if (!quantizeNodes(m, quant, g)) return false;
    for (const Slit& s : m.slits) {
        CodedMesh::SlitInts slit;
        if (!quantizeSlit(s, quant, g, byRule, slit)) return false;
        out.slits.push_back(std::move(slit));
    }
    for (const CornerTangent& t : m.tangents) {
        CodedMesh::TangentInts tangent;
        if (!quantizeTangent(t, quant, byRule, tangent)) return false;
        out.tangents.push_back(std::move(tangent));
    }
    p.coded = true;
    p.quantised = std::move(out);
    return true;
}

// One mesh of a CMS2 or CMS3 section, into the section's stream (docs/formats.md, "CMS2").
void writeStreamMesh(CompactStreamWriter& w, const CodedMesh& m) {
    const CodedGrid& g = m.grid;
    w.putUnsigned(StreamField::Size, static_cast<uint64_t>(g.columns));
    w.putUnsigned(StreamField::Size, static_cast<uint64_t>(g.rows));
    w.putUnsigned(StreamField::Count, m.slits.size());
    w.putUnsigned(StreamField::Count, m.tangents.size());
    w.putUnsigned(StreamField::Flags, m.bicubic ? kMeshColorBicubic
                                                : (m.byRule ? kMeshColorByRule : 0));
    w.putSigned(StreamField::KnotExponent, g.exponent[kKnot]);
    for (const std::vector<int64_t>* knots : {&g.knotU, &g.knotV}) {
        w.putSigned(StreamField::KnotStart, knots->front());
        for (size_t i = 1; i < knots->size(); ++i)
            w.putUnsigned(StreamField::KnotStep, static_cast<uint64_t>((*knots)[i] - (*knots)[i - 1] - 1));
    }
    w.putNodes(g);
    for (const CodedMesh::SlitInts& s : m.slits) {
        for (uint64_t x : {s.row, s.i0, s.i1}) w.putUnsigned(StreamField::SlitIndex, x);
        for (int64_t x : s.ends) w.putSigned(StreamField::SlitEnd, x);
        for (int64_t x : s.below) w.putSigned(StreamField::SlitBelow, x);
    }
    for (const CodedMesh::TangentInts& t : m.tangents) {
        for (uint64_t x : {t.i, t.j, t.corner}) w.putUnsigned(StreamField::TangentIndex, x);
        for (int64_t x : t.values) w.putSigned(StreamField::TangentValue, x);
    }
}

}  // namespace

GmbCompactShifts gmbCompactShifts(int level) {
    switch (level) {
        case 0: return {0, 0, 0, 0, 0};
        case 1: return {1, 0, 1, 1, 12};
        case 2: return {2, 1, 3, 3, 12};
        case 3: return {3, 2, 3, 4, 12};
        case 4: return {4, 3, 4, 5, 12};
        case 5: return {5, 3, 5, 6, 17};
        case 6: return {5, 4, 5, 7, 17};
        default:
            throw Error("compact level " + std::to_string(level) + " is not one of 0 to " +
                        std::to_string(kGmbMaxCompactLevel));
    }
}

std::string encodeGmb(const Document& doc, bool compact, int compactLevel, GmbStreams streams,
                      GmbFraming framing) {
    const GmbCompactShifts shift = gmbCompactShifts(compact ? compactLevel : 0);
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error("cannot write an invalid document: " + problem);
    if (doc.meshes.size() > UINT32_MAX) throw Error("too many meshes for a .gmb file");

    std::vector<MeshPayloads> meshes(doc.meshes.size());
    bool coded = false;
    for (size_t k = 0; k < doc.meshes.size(); ++k) {
        const GradientMesh& m = doc.meshes[k];
        const bool noSlopes = m.colorModel == ColorModel::Bicubic || followsColorRule(m);
        if (!compact || !encodeCoded(m, noSlopes, shift, meshes[k]))
            meshes[k] = encodeFloat64(m);
        coded = coded || meshes[k].coded;
    }

    // Compact files are 2.0 unless asked for 1.x: the same sections in shorter framing. In 1.x,
    // the lowest version that holds the file: lossless files stay readable by 1.0 readers, a
    // file with CMS2 sections needs 1.3 and only one with a CMS3 section 1.4 (set at the end).
    SectionSink out(compact && framing == GmbFraming::Short);
    out.header(coded ? kMinorCms2 : 0);
    bool anyCms3 = false;
    ByteWriter docu;
    if (out.shortFraming()) {
        docu.varint(static_cast<uint64_t>(doc.width));
        docu.varint(static_cast<uint64_t>(doc.height));
        docu.varint(doc.meshes.size());
    } else {
        docu.u32(static_cast<uint32_t>(doc.width));
        docu.u32(static_cast<uint32_t>(doc.height));
        docu.u32(static_cast<uint32_t>(doc.meshes.size()));
    }
    out.add("DOCU", docu.str(), false);

    for (size_t k = 0; k < doc.meshes.size();) {
        const GradientMesh& m = doc.meshes[k];
        const MeshPayloads& p = meshes[k];
        if (p.coded) {
            // One CMS2 or CMS3 for the run of coded meshes that share their exponents: their
            // stream's models learn from mesh to mesh. Stored, as range-coded data does not
            // compress.
            size_t end = k + 1;
            while (end < meshes.size() && meshes[end].coded && sameSharedExponents(p, meshes[end]))
                ++end;
            ByteWriter head;
            head.varint(end - k);
            for (int f = kPos; f < kFieldCount; ++f) head.svarint(p.quantised.grid.exponent[f]);
            // The run's stream in CMS2 and in CMS3, as asked; the smaller by default (CMS3's
            // priors suit converted images, CMS2's fresh models anything; a tie goes to CMS2,
            // which 1.3 readers read too).
            auto streamOf = [&](StreamKind kind) {
                CompactStreamWriter stream(kind);
                for (size_t r = k; r < end; ++r) writeStreamMesh(stream, meshes[r].quantised);
                return stream.finish();
            };
            std::string cms2, cms3;
            if (streams != GmbStreams::Cms3) cms2 = streamOf(StreamKind::Cms2);
            if (streams != GmbStreams::Cms2) cms3 = streamOf(StreamKind::Cms3);
            const bool useCms3 = streams == GmbStreams::Cms3 ||
                                 (streams == GmbStreams::Smaller && cms3.size() < cms2.size());
            out.add(useCms3 ? "CMS3" : "CMS2", head.str() + (useCms3 ? cms3 : cms2), false);
            anyCms3 = anyCms3 || useCms3;
            k = end;
            continue;
        }
        out.add("MESH", p.mesh, false);
        out.add("KNOT", p.knot, compact);
        out.add("NODE", p.node, compact);
        if (!m.slits.empty()) out.add("SLIT", p.slit, compact);
        if (!m.tangents.empty()) out.add("TANG", p.tang, compact);
        ++k;
    }
    if (!doc.shapes.empty()) out.add("SHAP", encodeShapes(doc.shapes, compact), compact);
    out.add("END ", std::string(), false);
    std::string bytes = out.take();
    if (anyCms3 && !out.shortFraming())
        bytes[10] = static_cast<char>(kMinor);  // the minor version, little-endian
    if (!doc.shapes.empty())
        bytes[10] = static_cast<char>(out.shortFraming() ? kMinorShortShapes : kMinorShapes);
    return bytes;
}

}  // namespace gm
