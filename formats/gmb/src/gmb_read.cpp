// The .gmb reader (layout: docs/formats.md). Everything in the input is untrusted: each count is
// checked against the limits and the bytes that remain before it sizes an allocation, and all
// size arithmetic is 64-bit and saturating.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <initializer_list>

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

// DOCU and MESH may grow by appended fields in later minors, but never beyond this.
constexpr uint64_t kMaxHeaderPayload = 4096;
// The smallest mesh a file can hold: a CMSH mesh record of 1x1 patches (six one-byte header
// fields, four knots, the weights mask and a 5-byte range-coded stream).
constexpr uint64_t kMinMeshRecord = 16;
// What a quantised node value counts against ReadLimits::maxFileBytes once decoded: the
// binary64 it becomes (docs/formats.md, "Reading limits").
constexpr uint64_t kDecodedBytesPerValue = 8;
// A range-coded stream of V values has more than V / 11730 bytes (docs/formats.md): a reader
// refuses V values where fewer than V / 16384 bytes remain.
constexpr uint64_t kValuesPerStreamByte = 16384;
// A mesh of a CMS2 or CMS3 stream makes at least 57 binary decisions (docs/formats.md): M meshes need
// more than M / 206 bytes, and a reader refuses M where fewer than M / 256 remain.
constexpr uint64_t kStreamMeshesPerByte = 256;
// The smallest float64 or 1.1 mesh: MESH, KNOT and NODE sections.
constexpr uint64_t kMinMeshSections = 3 * kSectionOverhead;

bool isKnownTag(const std::string& t) {
    return t == "DOCU" || t == "MESH" || t == "KNOT" || t == "NODE" || t == "SLIT" ||
           t == "TANG" || t == "CMSH" || t == "CMS2" || t == "CMS3" || t == "SHAP" || t == "END ";
}

// Tags may be any bytes in a hostile file; print them readably.
std::string printableTag(const std::string& t) {
    std::string s;
    for (unsigned char c : t) {
        if (c >= 0x20 && c < 0x7f) {
            s += static_cast<char>(c);
        } else {
            static const char hex[] = "0123456789abcdef";
            s += "\\x";
            s += hex[c >> 4];
            s += hex[c & 15];
        }
    }
    return s;
}

struct Section {
    std::string tag;
    uint8_t flags = 0;
    uint8_t codec = 0;
    uint64_t start = 0;      // file offset of the section header
    uint64_t payloadAt = 0;  // file offset of the payload
    uint64_t stored = 0, raw = 0;
};

// A section's payload ready to parse: a view into the file when stored, else inflated bytes.
struct Payload {
    std::string inflated;
    ByteReader reader{nullptr, 0, {}};
};

struct MeshHeader {
    uint64_t columns = 0, rows = 0, slits = 0, tangents = 0;
    Encoding encoding = Encoding::Float64;
    bool record = false;  // a CMSH mesh record (encoding 2, masked plane weights)
    bool byRule = false;   // colour derivatives omitted (by the rule, or the Bicubic model)
    bool bicubic = false;  // ColorModel::Bicubic
    int exponent[kFieldCount] = {};
    int components() const { return byRule ? kNodeComponentsByRule : kNodeComponents; }
    uint64_t nodes() const { return satMul(columns + 1, rows + 1); }
};

// A quantisation exponent of a CMSH section or record: an svarint within ±kMaxExponent.
int readExponent(ByteReader& r) {
    const int64_t e = r.svarint();
    if (e < -kMaxExponent || e > kMaxExponent)
        r.fail("quantisation exponent " + std::to_string(e) + " out of range");
    return static_cast<int>(e);
}

// Slit k's row and end columns, which must lie inside the grid.
void placeSlit(ByteReader& r, const MeshHeader& h, size_t k, uint64_t row, uint64_t i0,
               uint64_t i1, Slit& s) {
    if (row == 0 || row >= h.rows || i0 == 0 || i0 >= i1 || i1 >= h.columns)
        r.fail("slit " + std::to_string(k) + " (row " + std::to_string(row) + ", columns " +
               std::to_string(i0) + ".." + std::to_string(i1) + ") is not inside the " +
               std::to_string(h.columns) + "x" + std::to_string(h.rows) + " grid");
    s.row = static_cast<int>(row);
    s.i0 = static_cast<int>(i0);
    s.i1 = static_cast<int>(i1);
}

// Slit s's two end tangents (left then right: posU.x, posU.y, then colU unless colours go by the
// rule), each value from value(field, column).
template <class Value>
void readSlitEnds(const MeshHeader& h, Slit& s, Value value) {
    for (SlitEnd* end : {&s.left, &s.right}) {
        const size_t column = static_cast<size_t>(end == &s.left ? s.i0 : s.i1);
        for (double* x : {&end->posU.x, &end->posU.y}) *x = value(kPosU, column);
        if (!h.byRule)
            for (int c = 0; c < 3; ++c) end->colU[c] = value(kColU, column);
    }
}

// Tangent break k's patch (i, j) and corner (a, b), which must lie inside the grid.
void placeBreak(ByteReader& r, const MeshHeader& h, size_t k, uint64_t i, uint64_t j, uint64_t a,
                uint64_t b, CornerTangent& t) {
    if (i >= h.columns || j >= h.rows || a > 1 || b > 1)
        r.fail("tangent break " + std::to_string(k) + " names a corner outside the grid");
    t.i = static_cast<int>(i);
    t.j = static_cast<int>(j);
    t.a = static_cast<int>(a);
    t.b = static_cast<int>(b);
}

class Decoder {
public:
    Decoder(const std::string& bytes, const ReadLimits& limits, const std::string& file)
        : bytes_(bytes), limits_(limits), file_(file) {}

    Document run();

private:
    [[noreturn]] void fail(const std::string& what, uint64_t at) const {
        throw Error(what, file_, "byte " + std::to_string(at));
    }
    void readFileHeader();
    // `tags`: the tags that may stand there (one or more).
    Section next(std::initializer_list<const char*> tags);
    void open(const Section& s, uint64_t maxRaw, Payload& p, uint64_t decodedAtLeast = 0);
    void finish(const Payload& p, const Section& s) const;

    MeshHeader readMeshHeader(ByteReader& r, const Section& s);
    // What is wrong with a mesh header's counts (limits, what its grid can hold), or "".
    // Checks a mesh header's counts against the limits, and adds its patches to the
    // document's (ReadLimits::maxPatches); empty when all is well.
    std::string countProblem(const MeshHeader& h);
    GradientMesh readSections(const MeshHeader& h);
    uint64_t openMeshRun(const Section& s, const char* tag, int minor, uint64_t meshesLeft,
                         Payload& p, int (&shared)[kFieldCount]);
    void readCompactMeshes(const Section& s, uint64_t meshesLeft, Document& doc);
    void readMeshRecord(ByteReader& r, const int (&shared)[kFieldCount], Document& doc);
    void readStreamMeshes(const Section& s, uint64_t meshesLeft, Document& doc);
    void readStreamMesh(CompactStreamReader& in, ByteReader& r, const int (&shared)[kFieldCount],
                        Document& doc);
    // The parts of one mesh of a CMS2/CMS3 stream, in stream order.
    MeshHeader readStreamHeader(CompactStreamReader& in, ByteReader& r,
                                const int (&shared)[kFieldCount]);
    void readStreamKnots(CompactStreamReader& in, ByteReader& r, const MeshHeader& h,
                         GradientMesh& m);
    void readStreamNodes(CompactStreamReader& in, ByteReader& r, const MeshHeader& h,
                         GradientMesh& m);
    void readStreamSlit(CompactStreamReader& in, ByteReader& r, const MeshHeader& h, size_t k,
                        Slit& s);
    void readStreamTangent(CompactStreamReader& in, ByteReader& r, const MeshHeader& h, size_t k,
                           CornerTangent& t);
    // Adds `bytes` to what the document decodes to, refusing it beyond limits.maxFileBytes.
    void charge(ByteReader& r, uint64_t bytes);
    void addMesh(GradientMesh m, const MeshHeader& h, Document& doc);
    void readKnots(ByteReader& r, const MeshHeader& h, GradientMesh& m);
    void readNodes(ByteReader& r, const MeshHeader& h, GradientMesh& m);
    void readSlits(ByteReader& r, const MeshHeader& h, GradientMesh& m);
    void readTangents(ByteReader& r, const MeshHeader& h, GradientMesh& m);

    double quantized(ByteReader& r, int64_t q, int exponent) const;
    // Component c (node-record order) of a node in the given column and row, from its q.
    double component(ByteReader& r, const MeshHeader& h, int c, int64_t q, size_t column,
                     size_t row) const;
    double derivativeU(ByteReader& r, const MeshHeader& h, Field f, int64_t q, size_t column) const;
    void readNodeRecord(ByteReader& r, const MeshHeader& h, Node& n, size_t above);

    const std::string& bytes_;
    const ReadLimits& limits_;
    const std::string& file_;
    uint64_t pos_ = 0;
    // The 1.x minor whose sections the file may hold: the file's own for 1.x, kMinor for 2.x
    // (1.4's sections in short framing).
    uint16_t minor_ = 0;
    uint16_t fileMajor_ = 1, fileMinor_ = 0;
    bool shortFraming() const { return fileMajor_ == kMajorShort; }
    std::string fileVersion() const {
        return std::to_string(fileMajor_) + "." + std::to_string(fileMinor_);
    }
    uint64_t decodedBytes_ = 0;  // sum of declared uncompressed sizes so far
    std::string meshName_;       // "mesh 3", for section names in messages
    uint64_t documentPatches_ = 0;  // of the meshes whose headers were read
    // The current mesh when quantised: its knots, spans (encoding 2) and NODE values, per
    // component (`grid_.planes`).
    CodedGrid grid_;
};

void Decoder::readFileHeader() {
    const size_t n = bytes_.size();
    if (n == 0) throw Error("empty file: not a .gmb file", file_);
    if (n > limits_.maxFileBytes)
        throw Error("file is " + std::to_string(n) + " bytes, over the limit of " +
                        std::to_string(limits_.maxFileBytes),
                    file_);
    const size_t m = std::min(n, sizeof kMagic);
    if (std::memcmp(bytes_.data(), kMagic, m) != 0) {
        // Name the usual accidents: line endings rewritten by a text-mode transfer, a text file.
        if (n >= 5 && std::memcmp(bytes_.data(), kMagic, 4) == 0 && bytes_[4] == '\n')
            throw Error("bad magic: line endings were converted (text-mode transfer?); not a valid .gmb file",
                        file_, "byte 4");
        bool text = true;
        for (size_t k = 0; k < std::min<size_t>(n, 64); ++k) {
            const auto c = static_cast<unsigned char>(bytes_[k]);
            if (c < 0x09 || (c > 0x0d && c < 0x20) || c == 0x7f) text = false;
        }
        throw Error(text ? "bad magic: not a .gmb file (looks like text)" : "bad magic: not a .gmb file",
                    file_, "byte 0");
    }
    if (n < kFileHeaderSize)
        fail("truncated in the file header (" + std::to_string(n) + " of " +
                 std::to_string(kFileHeaderSize) + " bytes)",
             n);
    ByteReader r(bytes_.data() + sizeof kMagic, 4, Origin{file_, {}, sizeof kMagic});
    fileMajor_ = r.u16();
    fileMinor_ = r.u16();
    if (fileMajor_ != kMajor && fileMajor_ != kMajorShort)
        fail("unsupported .gmb major version " + std::to_string(fileMajor_) +
                 " (this reader knows " + std::to_string(kMajor) + " and " +
                 std::to_string(kMajorShort) + ")",
             8);
    minor_ = shortFraming() ? kMinor : fileMinor_;
    pos_ = kFileHeaderSize;
}

// The next section the document structure expects, skipping optional sections this reader does
// not know. The section's CRC has been checked; pos_ is past it.
Section Decoder::next(std::initializer_list<const char*> tags) {
    std::string want;  // "A", "A or B", "A, B or C", ...
    size_t k = 0;
    for (const char* t : tags) {
        if (k > 0) want += k + 1 == tags.size() ? " or " : ", ";
        want += t;
        ++k;
    }
    for (;;) {
        const uint64_t left = bytes_.size() - pos_;
        if (left == 0) fail("truncated: the file ends before section " + want, pos_);
        const size_t headerMin = shortFraming() ? kShortSectionHeaderMin : kSectionHeaderSize;
        if (left < headerMin)
            fail("truncated in the header of the section expected to be " + want, pos_);
        Section s;
        s.start = pos_;
        // 1.x: a fixed 24-byte header; 2.x: varint sizes, raw only when compressed.
        s.tag.assign(bytes_.data() + pos_, 4);
        ByteReader r(bytes_.data() + pos_, shortFraming() ? left : kSectionHeaderSize,
                     Origin{file_, printableTag(s.tag) + " (its header)", pos_});
        r.skip(4);
        s.flags = r.u8();
        s.codec = r.u8();
        if (shortFraming()) {
            s.stored = r.varint();
            s.raw = s.codec == static_cast<uint8_t>(Codec::Stored) ? s.stored : r.varint();
        } else {
            r.u16();  // reserved
            s.stored = r.u64();
            s.raw = r.u64();
        }
        const size_t headerSize = r.position();
        s.payloadAt = s.start + headerSize;
        const std::string name = printableTag(s.tag);
        const uint64_t after = left - headerSize;
        if (s.stored > after || after - s.stored < kCrcSize)
            fail("truncated in section " + name + ": its " + std::to_string(s.stored) +
                     "-byte payload and CRC need " + std::to_string(satAdd(s.stored, kCrcSize)) +
                     " bytes, " + std::to_string(after) + " remain",
                 s.start);
        const size_t covered = headerSize + static_cast<size_t>(s.stored);
        ByteReader crcField(bytes_.data() + pos_ + covered, kCrcSize, Origin{file_, {}, pos_ + covered});
        const uint32_t storedCrc = crcField.u32();
        const uint32_t crc = crc32Of(bytes_.data() + pos_, covered);
        if (crc != storedCrc)
            fail("CRC mismatch in section " + name + " (the file is damaged)", s.start);
        pos_ += covered + kCrcSize;
        if (isKnownTag(s.tag)) {
            if (std::find(tags.begin(), tags.end(), s.tag) == tags.end())
                fail("section " + name + " out of place: expected " + want, s.start);
            return s;
        }
        if (!(s.flags & kSectionOptional))
            fail("unknown required section '" + name + "' (file version " + fileVersion() +
                     "; this reader knows 1." + std::to_string(kMinorShapes) + " and " +
                     std::to_string(kMajorShort) + "." + std::to_string(kMinorShortShapes) + ")",
                 s.start);
    }
}

// Makes the payload of a known section readable, refusing declared sizes beyond what its counts
// allow (`maxRaw`) or beyond the document's budget before inflating anything.
// `decodedAtLeast` is charged to the budget when more than the declared size: what a
// range-coded payload decodes to, however few bytes it takes.
void Decoder::open(const Section& s, uint64_t maxRaw, Payload& p, uint64_t decodedAtLeast) {
    const std::string name = meshName_.empty() || s.tag == "DOCU" || s.tag == "END "
                                 ? s.tag
                                 : s.tag + " (" + meshName_ + ")";
    if (s.raw > maxRaw)
        fail("section " + name + " declares " + std::to_string(s.raw) +
                 " uncompressed bytes; its counts allow at most " + std::to_string(maxRaw),
             s.start);
    decodedBytes_ = satAdd(decodedBytes_, std::max(s.raw, decodedAtLeast));
    if (decodedBytes_ > limits_.maxFileBytes)
        fail("decoded data would exceed the limit of " + std::to_string(limits_.maxFileBytes) +
                 " bytes (section " + name + ")",
             s.start);
    const uint64_t payloadAt = s.payloadAt;
    const char* data = bytes_.data() + payloadAt;
    const size_t size = static_cast<size_t>(s.stored);
    if (s.codec == static_cast<uint8_t>(Codec::Stored)) {
        if (s.raw != s.stored)
            fail("section " + name + " is stored uncompressed but declares " +
                     std::to_string(s.raw) + " bytes for a " + std::to_string(s.stored) +
                     "-byte payload",
                 s.start);
        p.reader = ByteReader(data, size, Origin{file_, name, payloadAt});
        return;
    }
    if (s.codec != static_cast<uint8_t>(Codec::Deflate) && s.codec != static_cast<uint8_t>(Codec::Zstd))
        fail("unknown compression method " + std::to_string(s.codec) + " in section " + name, s.start);
    const Origin origin{file_, name, 0, true, s.start};
    p.inflated = decompressPayload(static_cast<Codec>(s.codec), data, size, s.raw, origin);
    p.reader = ByteReader(p.inflated.data(), p.inflated.size(), origin);
}

void Decoder::finish(const Payload& p, const Section& s) const {
    if (p.reader.remaining() != 0)
        p.reader.fail(std::to_string(p.reader.remaining()) + " unexpected bytes at the end of the " +
                      s.tag + " payload");
}

double Decoder::quantized(ByteReader& r, int64_t q, int exponent) const {
    if (q > kMaxQuantized || q < -kMaxQuantized) r.fail("quantised value out of range");
    return std::ldexp(static_cast<double>(q), exponent);
}

double Decoder::derivativeU(ByteReader& r, const MeshHeader& h, Field f, int64_t q,
                            size_t column) const {
    if (h.encoding == Encoding::Quantized) return quantized(r, q, h.exponent[f]);
    if (q > kMaxQuantized || q < -kMaxQuantized) r.fail("quantised value out of range");
    return codedDerivative(q, h.exponent[f] - h.exponent[kKnot], grid_.spanU[column]);
}

double Decoder::component(ByteReader& r, const MeshHeader& h, int c, int64_t q, size_t column,
                          size_t row) const {
    const Field f = fieldOfComponent(c);
    if (h.encoding == Encoding::Coded && f != kPos && f != kCol) {
        if (q > kMaxQuantized || q < -kMaxQuantized) r.fail("quantised value out of range");
        const bool alongU = f == kPosU || f == kColU;
        return codedDerivative(q, h.exponent[f] - h.exponent[kKnot],
                               alongU ? grid_.spanU[column] : grid_.spanV[row]);
    }
    return quantized(r, q, h.exponent[f]);
}

std::string Decoder::countProblem(const MeshHeader& h) {
    const std::string grid = std::to_string(h.columns) + "x" + std::to_string(h.rows);
    if (h.columns == 0 || h.rows == 0) return "grid " + grid + " is empty";
    const uint64_t side = std::min<uint64_t>(limits_.maxGridSide, INT_MAX - 1);
    if (h.columns > side || h.rows > side)
        return "grid " + grid + " exceeds the limit of " + std::to_string(side) + " columns or rows";
    if (h.nodes() > limits_.maxNodesPerMesh)
        return "grid " + grid + " has " + std::to_string(h.nodes()) + " nodes, over the limit of " +
               std::to_string(limits_.maxNodesPerMesh);
    if (h.slits > limits_.maxSlitsPerMesh)
        return std::to_string(h.slits) + " slits exceed the limit of " +
               std::to_string(limits_.maxSlitsPerMesh);
    // Slits lie on interior rows and do not touch: at most C/2 per row.
    if (h.slits > satMul(h.rows - 1, h.columns / 2))
        return std::to_string(h.slits) + " slits cannot fit a " + grid + " grid";
    if (h.tangents > satMul(4, satMul(h.columns, h.rows)))
        return std::to_string(h.tangents) + " tangent breaks for only " +
               std::to_string(h.columns * h.rows) + " patches";
    const uint64_t patches = satMul(h.columns, h.rows);
    documentPatches_ = patches > UINT64_MAX - documentPatches_ ? UINT64_MAX : documentPatches_ + patches;
    if (documentPatches_ > limits_.maxPatches)
        return tooManyPatchesMessage(documentPatches_, limits_.maxPatches);
    return {};
}

MeshHeader Decoder::readMeshHeader(ByteReader& r, const Section& s) {
    MeshHeader h;
    r.need(kMeshPayloadSize, "the mesh header");
    h.columns = r.u32();
    h.rows = r.u32();
    h.slits = r.u32();
    h.tangents = r.u32();
    const uint8_t encoding = r.u8();
    const uint8_t flags = r.u8();
    for (int& e : h.exponent) e = r.i16();
    const std::string at = meshName_ + ": ";
    const std::string problem = countProblem(h);
    if (!problem.empty()) fail(at + problem, s.start);
    if (encoding > static_cast<uint8_t>(Encoding::Coded))
        fail(at + "unknown mesh encoding " + std::to_string(encoding), s.start);
    h.encoding = static_cast<Encoding>(encoding);
    if (h.encoding == Encoding::Coded && minor_ < 1)
        fail(at + "mesh encoding 2 needs format version 1.1 (the file says " + fileVersion() + ")",
             s.start);
    h.bicubic = flags & kMeshColorBicubic;
    h.byRule = h.encoding == Encoding::Coded ? (flags & kMeshFlagsKnown) != 0
                                             : (flags & kMeshColorByRule) != 0;
    for (int e : h.exponent)
        if (e < -kMaxExponent || e > kMaxExponent)
            fail(at + "quantisation exponent " + std::to_string(e) + " out of range", s.start);
    if (h.encoding == Encoding::Coded) {
        const std::string problem = codedExponentProblem(h.exponent);
        if (!problem.empty()) fail(at + problem, s.start);
    }
    // A newer minor may append fields; version 1.0 files must be exact.
    if (minor_ == 0 && r.remaining() != 0)
        r.fail(std::to_string(r.remaining()) + " unexpected bytes at the end of the MESH payload");
    r.skip(r.remaining());
    return h;
}

void Decoder::readKnots(ByteReader& r, const MeshHeader& h, GradientMesh& m) {
    const uint64_t count = h.columns + h.rows + 2;
    if (h.encoding == Encoding::Float64) {
        r.need(8 * count, "the knots");
        m.u.resize(static_cast<size_t>(h.columns + 1));
        m.v.resize(static_cast<size_t>(h.rows + 1));
        for (double& x : m.u) x = r.f64();
        for (double& x : m.v) x = r.f64();
        return;
    }
    r.need(count, "the knots");
    for (std::vector<double>* k : {&m.u, &m.v}) {
        k->resize(static_cast<size_t>((k == &m.u ? h.columns : h.rows) + 1));
        std::vector<int64_t>& knotQ = k == &m.u ? grid_.knotU : grid_.knotV;
        knotQ.resize(k->size());
        int64_t q = r.svarint();
        (*k)[0] = quantized(r, q, h.exponent[kKnot]);
        knotQ[0] = q;
        for (size_t i = 1; i < k->size(); ++i) {
            const uint64_t step = r.varint();
            if (step == 0) r.fail("knots not strictly increasing");
            if (step > uint64_t(2) * kMaxQuantized) r.fail("knot interval out of range");
            q += static_cast<int64_t>(step);  // both within 2^54: no overflow
            (*k)[i] = quantized(r, q, h.exponent[kKnot]);
            knotQ[i] = q;
        }
    }
    grid_.spanU = localSpans(grid_.knotU);
    grid_.spanV = localSpans(grid_.knotV);
}

void Decoder::readNodes(ByteReader& r, const MeshHeader& h, GradientMesh& m) {
    const int F = h.components();
    const uint64_t n = h.nodes();
    const size_t C1 = static_cast<size_t>(h.columns + 1);
    if (h.encoding == Encoding::Float64) {
        r.need(satMul(n, 8 * F), "the nodes");
        m.nodes.resize(static_cast<size_t>(n));
        for (Node& node : m.nodes)
            for (int c = 0; c < F; ++c) nodeComponent(node, c) = r.f64();
        return;
    }
    grid_.columns = static_cast<int>(h.columns);
    grid_.rows = static_cast<int>(h.rows);
    grid_.components = F;
    std::copy(std::begin(h.exponent), std::end(h.exponent), grid_.exponent);
    if (h.encoding == Encoding::Coded) {
        // Range-coded: no bytes per value to count on (the caller charged the values to the
        // budget). The weights come first (in NODE at least 2 bytes per plane, in a CMSH record
        // at least the mask), then at least 5 bytes of the stream.
        r.need(h.record ? 6 : satAdd(satMul(2, F), 5), "the nodes");
        // Nor can a stream be shorter than its values allow (docs/formats.md, "Reading limits"):
        // checked before the planes are allocated.
        r.need(satMul(F, n) / kValuesPerStreamByte, "the range-coded nodes");
        decodeCodedNodes(r, grid_, h.record ? WeightLayout::Masked : WeightLayout::Explicit);
        m.nodes.resize(static_cast<size_t>(n));
        for (int c = 0; c < F; ++c) {
            const int64_t* q = &grid_.planes[c * static_cast<size_t>(n)];
            for (size_t k = 0; k < n; ++k)
                nodeComponent(m.nodes[k], c) = component(r, h, c, q[k], k % C1, k / C1);
        }
        return;
    }
    r.need(satMul(n, F), "the nodes");  // at least one byte per value
    m.nodes.resize(static_cast<size_t>(n));
    grid_.planes.assign(static_cast<size_t>(n) * F, 0);
    for (int c = 0; c < F; ++c) {
        int64_t* q = &grid_.planes[c * static_cast<size_t>(n)];
        const int e = h.exponent[fieldOfComponent(c)];
        for (size_t k = 0; k < n; ++k) {
            const size_t i = k % C1, j = k / C1;
            int64_t pred = 0;  // decoded values are within 2^53: the sum cannot overflow
            if (i > 0 && j > 0) pred = q[k - 1] + q[k - C1] - q[k - C1 - 1];
            else if (i > 0) pred = q[k - 1];
            else if (j > 0) pred = q[k - C1];
            // Residuals are arbitrary 64-bit numbers: add in unsigned (wrapping) arithmetic and
            // let the range check reject the result.
            q[k] = static_cast<int64_t>(static_cast<uint64_t>(pred) + static_cast<uint64_t>(r.svarint()));
            nodeComponent(m.nodes[k], c) = quantized(r, q[k], e);
        }
    }
}

// One below-copy node record; `above` indexes the node over the slit in the same column.
void Decoder::readNodeRecord(ByteReader& r, const MeshHeader& h, Node& n, size_t above) {
    const int F = h.components();
    const size_t count = grid_.planes.size() / static_cast<size_t>(F);
    const size_t C1 = static_cast<size_t>(h.columns + 1);
    for (int c = 0; c < F; ++c) {
        if (h.encoding == Encoding::Float64) {
            nodeComponent(n, c) = r.f64();
        } else {
            const int64_t q =
                static_cast<int64_t>(static_cast<uint64_t>(grid_.planes[c * count + above]) +
                                     static_cast<uint64_t>(r.svarint()));
            nodeComponent(n, c) = component(r, h, c, q, above % C1, above / C1);
        }
    }
}

void Decoder::readSlits(ByteReader& r, const MeshHeader& h, GradientMesh& m) {
    const bool f64 = h.encoding == Encoding::Float64;
    const int endValues = h.byRule ? 2 : 5;
    const uint64_t minSlit = f64 ? 12 + 2 * 8 * endValues : 3 + 2 * endValues;
    const uint64_t minNode = f64 ? 8 * h.components() : h.components();
    r.need(satMul(h.slits, minSlit), "the slits");
    m.slits.resize(static_cast<size_t>(h.slits));
    for (size_t k = 0; k < m.slits.size(); ++k) {
        Slit& s = m.slits[k];
        const uint64_t row = f64 ? r.u32() : r.varint();
        const uint64_t i0 = f64 ? r.u32() : r.varint();
        const uint64_t i1 = f64 ? r.u32() : r.varint();
        placeSlit(r, h, k, row, i0, i1, s);
        readSlitEnds(h, s, [&](Field f, size_t column) {
            return f64 ? r.f64() : derivativeU(r, h, f, r.svarint(), column);
        });
        const uint64_t below = i1 - i0 - 1;
        r.need(satMul(below, minNode), "the split nodes of slit " + std::to_string(k));
        s.below.resize(static_cast<size_t>(below));
        for (size_t b = 0; b < s.below.size(); ++b)
            readNodeRecord(r, h, s.below[b], static_cast<size_t>(row * (h.columns + 1) + i0 + 1 + b));
    }
}

void Decoder::readTangents(ByteReader& r, const MeshHeader& h, GradientMesh& m) {
    const bool f64 = h.encoding == Encoding::Float64;
    const uint64_t values = h.byRule ? 2 : 5;
    r.need(satMul(h.tangents, f64 ? 10 + 8 * values : 3 + values), "the tangent breaks");
    m.tangents.resize(static_cast<size_t>(h.tangents));
    for (size_t k = 0; k < m.tangents.size(); ++k) {
        CornerTangent& t = m.tangents[k];
        const uint64_t i = f64 ? r.u32() : r.varint();
        const uint64_t j = f64 ? r.u32() : r.varint();
        uint64_t a, b;
        if (f64) {
            a = r.u8();
            b = r.u8();
        } else {
            const uint8_t ab = r.u8();
            if (ab > 3) r.fail("tangent break " + std::to_string(k) + " has a bad corner code");
            a = ab & 1;
            b = ab >> 1;
        }
        placeBreak(r, h, k, i, j, a, b, t);
        const size_t column = static_cast<size_t>(i + a);
        for (double* x : {&t.posU.x, &t.posU.y})
            *x = f64 ? r.f64() : derivativeU(r, h, kPosU, r.svarint(), column);
        for (int c = 0; c < 3 && !h.byRule; ++c)
            t.colU[c] = f64 ? r.f64() : derivativeU(r, h, kColU, r.svarint(), column);
    }
}

// The KNOT, NODE, SLIT and TANG sections of the mesh whose MESH section gave `h`.
GradientMesh Decoder::readSections(const MeshHeader& h) {
    GradientMesh m;
    const bool f64 = h.encoding == Encoding::Float64;
    const uint64_t F = static_cast<uint64_t>(h.components());
    const uint64_t perValue = f64 ? 8 : 10;  // a varint takes at most 10 bytes
    {
        const Section s = next({"KNOT"});
        Payload p;
        open(s, satMul(perValue, h.columns + h.rows + 2), p);
        readKnots(p.reader, h, m);
        finish(p, s);
    }
    {
        const Section s = next({"NODE"});
        Payload p;
        if (h.encoding == Encoding::Coded) {
            // Weights (3 varints per plane), then at most 11 bits per binary decision of a
            // 64-bit residual (docs/formats.md), under 128 bytes per value; decoded, each
            // value counts as the binary64 it becomes.
            const uint64_t values = satMul(F, h.nodes());
            open(s, satAdd(satMul(30, F), satAdd(satMul(128, values), 5)), p,
                 satMul(kDecodedBytesPerValue, values));
        } else {
            // A quantised value (a varint of a byte or more) counts as the binary64 it becomes.
            const uint64_t values = satMul(F, h.nodes());
            open(s, satMul(perValue, values), p,
                 perValue < kDecodedBytesPerValue ? satMul(kDecodedBytesPerValue, values) : 0);
        }
        readNodes(p.reader, h, m);
        finish(p, s);
    }
    if (h.slits > 0) {
        const Section s = next({"SLIT"});
        // Row and columns, two end tangents and at most C-2 split nodes per slit.
        const uint64_t perSlit = satAdd(3 * perValue + 10 * perValue,
                                        satMul(h.columns - 1, satMul(perValue, F)));
        Payload p;
        open(s, satMul(h.slits, perSlit), p);
        readSlits(p.reader, h, m);
        finish(p, s);
    }
    if (h.tangents > 0) {
        const Section s = next({"TANG"});
        Payload p;
        open(s, satMul(h.tangents, 4 * perValue + 2 + 5 * perValue), p);
        readTangents(p.reader, h, m);
        finish(p, s);
    }
    return m;
}

// A decoded mesh joins the document once its structure is valid (the colour rule may rely on it).
void Decoder::addMesh(GradientMesh m, const MeshHeader& h, Document& doc) {
    grid_ = CodedGrid();
    const std::string problem = validateMesh(m);
    if (!problem.empty()) throw Error(meshName_ + ": " + problem, file_);
    if (h.bicubic)
        m.colorModel = ColorModel::Bicubic;
    else if (h.byRule)
        applyColorRule(m);
    doc.meshes.push_back(std::move(m));
}

// The start of a CMSH, CMS2 or CMS3 section (`tag`, since 1.`minor`): the section checked, its
// payload opened, the mesh count M (returned) and the shared exponents read.
uint64_t Decoder::openMeshRun(const Section& s, const char* tag, int minor, uint64_t meshesLeft,
                              Payload& p, int (&shared)[kFieldCount]) {
    const std::string name(tag);
    if (minor_ < minor)
        fail("section " + name + " needs format version 1." + std::to_string(minor) +
                 " (the file says " + fileVersion() + ")",
             s.start);
    if (s.codec != static_cast<uint8_t>(Codec::Stored))
        fail("section " + name + " must be stored (codec 0), not codec " + std::to_string(s.codec),
             s.start);
    meshName_.clear();  // the section holds several meshes: each names its own
    open(s, s.stored, p);
    ByteReader& r = p.reader;
    const uint64_t count = r.varint();
    if (count == 0) r.fail("a " + name + " section holds no mesh");
    if (count > meshesLeft)
        r.fail(name + " holds " + std::to_string(count) + " meshes, but the document has only " +
               std::to_string(meshesLeft) + " more");
    for (int f = kPos; f < kFieldCount; ++f) shared[f] = readExponent(r);
    return count;
}

// A CMSH section: a run of meshes in encoding 2 (version 1.2).
void Decoder::readCompactMeshes(const Section& s, uint64_t meshesLeft, Document& doc) {
    Payload p;
    int shared[kFieldCount] = {};
    const uint64_t count = openMeshRun(s, "CMSH", 2, meshesLeft, p, shared);
    ByteReader& r = p.reader;
    r.need(satMul(count, kMinMeshRecord), std::to_string(count) + " mesh records");
    const uint64_t payloadAt = s.payloadAt;
    for (uint64_t k = 0; k < count; ++k) {
        meshName_ = "mesh " + std::to_string(doc.meshes.size());
        // The record's own reader names its mesh; the stored payload is a view of the file.
        ByteReader record(bytes_.data() + payloadAt + r.position(), r.remaining(),
                          Origin{file_, "CMSH (" + meshName_ + ")", payloadAt + r.position()});
        readMeshRecord(record, shared, doc);
        r.skip(record.position());
    }
    finish(p, s);
}

void Decoder::readMeshRecord(ByteReader& r, const int (&shared)[kFieldCount], Document& doc) {
    MeshHeader h;
    h.encoding = Encoding::Coded;
    h.record = true;
    h.columns = r.varint();
    h.rows = r.varint();
    h.slits = r.varint();
    h.tangents = r.varint();
    const std::string problem = countProblem(h);
    if (!problem.empty()) r.fail(problem);
    const uint8_t flags = r.u8();
    if (flags & ~kMeshFlagsKnown) r.fail("unknown mesh flags " + std::to_string(flags));
    h.byRule = flags & kMeshFlagsKnown;
    h.bicubic = flags & kMeshColorBicubic;
    const int knot = readExponent(r);
    std::copy(std::begin(shared), std::end(shared), h.exponent);
    h.exponent[kKnot] = knot;
    const std::string exponents = codedExponentProblem(h.exponent);
    if (!exponents.empty()) r.fail(exponents);
    // Range-coded values decode from a fraction of a bit each: each counts as the binary64 it
    // becomes.
    const uint64_t values = satMul(static_cast<uint64_t>(h.components()), h.nodes());
    decodedBytes_ = satAdd(decodedBytes_, satMul(kDecodedBytesPerValue, values));
    if (decodedBytes_ > limits_.maxFileBytes)
        r.fail("decoded data would exceed the limit of " + std::to_string(limits_.maxFileBytes) +
               " bytes");
    GradientMesh m;
    readKnots(r, h, m);
    readNodes(r, h, m);
    readSlits(r, h, m);
    readTangents(r, h, m);
    addMesh(std::move(m), h, doc);
}

void Decoder::charge(ByteReader& r, uint64_t bytes) {
    decodedBytes_ = satAdd(decodedBytes_, bytes);
    if (decodedBytes_ > limits_.maxFileBytes)
        r.fail("decoded data would exceed the limit of " + std::to_string(limits_.maxFileBytes) +
               " bytes");
}

// A CMS2 or CMS3 section: a run of meshes in encoding 2 in one range-coded stream (versions
// 1.3 and 1.4; they differ only in their residual models).
void Decoder::readStreamMeshes(const Section& s, uint64_t meshesLeft, Document& doc) {
    Payload p;
    int shared[kFieldCount] = {};
    const bool cms3 = s.tag == "CMS3";
    const char* tag = cms3 ? "CMS3" : "CMS2";
    const uint64_t count = openMeshRun(s, tag, cms3 ? kMinor : kMinorCms2, meshesLeft, p, shared);
    ByteReader& r = p.reader;
    r.need(count / kStreamMeshesPerByte, std::to_string(count) + " range-coded meshes");
    CompactStreamReader stream(r, cms3 ? StreamKind::Cms3 : StreamKind::Cms2);
    for (uint64_t k = 0; k < count; ++k) {
        meshName_ = "mesh " + std::to_string(doc.meshes.size());
        r.rename(std::string(tag) + " (" + meshName_ + ")");
        readStreamMesh(stream, r, shared, doc);
    }
    r.rename(tag);
    // The stream is exactly the bytes its decoder read: nothing may follow.
    finish(p, s);
}

MeshHeader Decoder::readStreamHeader(CompactStreamReader& in, ByteReader& r,
                                     const int (&shared)[kFieldCount]) {
    MeshHeader h;
    h.encoding = Encoding::Coded;
    h.record = true;
    h.columns = in.getUnsigned(StreamField::Size);
    h.rows = in.getUnsigned(StreamField::Size);
    h.slits = in.getUnsigned(StreamField::Count);
    h.tangents = in.getUnsigned(StreamField::Count);
    const std::string problem = countProblem(h);
    if (!problem.empty()) r.fail(problem);
    const uint64_t flags = in.getUnsigned(StreamField::Flags);
    if (flags & ~uint64_t(kMeshFlagsKnown)) r.fail("unknown mesh flags " + std::to_string(flags));
    h.byRule = flags & kMeshFlagsKnown;
    h.bicubic = flags & kMeshColorBicubic;
    const int64_t knot = in.getSigned(StreamField::KnotExponent);
    if (knot < -kMaxExponent || knot > kMaxExponent)
        r.fail("quantisation exponent " + std::to_string(knot) + " out of range");
    std::copy(std::begin(shared), std::end(shared), h.exponent);
    h.exponent[kKnot] = static_cast<int>(knot);
    const std::string exponents = codedExponentProblem(h.exponent);
    if (!exponents.empty()) r.fail(exponents);
    return h;
}

void Decoder::readStreamKnots(CompactStreamReader& in, ByteReader& r, const MeshHeader& h,
                              GradientMesh& m) {
    // Every value takes at least one decision: a stream cannot be shorter than its values allow
    // (docs/formats.md, "Reading limits"), checked before each allocation.
    r.need((h.columns + h.rows + 2) / kValuesPerStreamByte, "the knots");
    for (std::vector<double>* k : {&m.u, &m.v}) {
        k->resize(static_cast<size_t>((k == &m.u ? h.columns : h.rows) + 1));
        std::vector<int64_t>& knotQ = k == &m.u ? grid_.knotU : grid_.knotV;
        knotQ.resize(k->size());
        int64_t q = in.getSigned(StreamField::KnotStart);
        (*k)[0] = quantized(r, q, h.exponent[kKnot]);
        knotQ[0] = q;
        for (size_t i = 1; i < k->size(); ++i) {
            const uint64_t step = in.getUnsigned(StreamField::KnotStep);
            if (step >= uint64_t(2) * kMaxQuantized) r.fail("knot interval out of range");
            q += static_cast<int64_t>(step + 1);  // both within 2^54: no overflow
            (*k)[i] = quantized(r, q, h.exponent[kKnot]);
            knotQ[i] = q;
        }
    }
    grid_.spanU = localSpans(grid_.knotU);
    grid_.spanV = localSpans(grid_.knotV);
}

void Decoder::readStreamNodes(CompactStreamReader& in, ByteReader& r, const MeshHeader& h,
                              GradientMesh& m) {
    const uint64_t F = static_cast<uint64_t>(h.components());
    const uint64_t n = h.nodes();
    const size_t C1 = static_cast<size_t>(h.columns + 1);
    r.need(satMul(F, n) / kValuesPerStreamByte, "the range-coded nodes");
    grid_.columns = static_cast<int>(h.columns);
    grid_.rows = static_cast<int>(h.rows);
    grid_.components = static_cast<int>(F);
    std::copy(std::begin(h.exponent), std::end(h.exponent), grid_.exponent);
    in.getNodes(grid_);
    m.nodes.resize(static_cast<size_t>(n));
    for (size_t c = 0; c < F; ++c) {
        const int64_t* q = &grid_.planes[c * static_cast<size_t>(n)];
        for (size_t k = 0; k < n; ++k)
            nodeComponent(m.nodes[k], static_cast<int>(c)) =
                component(r, h, static_cast<int>(c), q[k], k % C1, k / C1);
    }
}

// Slit k: its place, its ends' u-derivatives, and its lower nodes as residuals from the nodes
// above them.
void Decoder::readStreamSlit(CompactStreamReader& in, ByteReader& r, const MeshHeader& h, size_t k,
                             Slit& s) {
    const uint64_t F = static_cast<uint64_t>(h.components());
    const uint64_t n = h.nodes();
    const size_t C1 = static_cast<size_t>(h.columns + 1);
    const uint64_t row = in.getUnsigned(StreamField::SlitIndex);
    const uint64_t i0 = in.getUnsigned(StreamField::SlitIndex);
    const uint64_t i1 = in.getUnsigned(StreamField::SlitIndex);
    placeSlit(r, h, k, row, i0, i1, s);
    readSlitEnds(h, s, [&](Field f, size_t column) {
        return derivativeU(r, h, f, in.getSigned(StreamField::SlitEnd), column);
    });
    const uint64_t below = i1 - i0 - 1;
    charge(r, satMul(kDecodedBytesPerValue, satMul(below, F)));
    r.need(satMul(below, F) / kValuesPerStreamByte, "the split nodes of slit " + std::to_string(k));
    s.below.resize(static_cast<size_t>(below));
    for (size_t b = 0; b < s.below.size(); ++b) {
        const size_t above = static_cast<size_t>(row * (h.columns + 1) + i0 + 1 + b);
        for (size_t c = 0; c < F; ++c) {
            // Residuals are arbitrary 64-bit numbers: add in unsigned (wrapping) arithmetic
            // and let the range check reject the result.
            const int64_t q = static_cast<int64_t>(
                static_cast<uint64_t>(grid_.planes[c * static_cast<size_t>(n) + above]) +
                static_cast<uint64_t>(in.getSigned(StreamField::SlitBelow)));
            nodeComponent(s.below[b], static_cast<int>(c)) =
                component(r, h, static_cast<int>(c), q, above % C1, above / C1);
        }
    }
}

void Decoder::readStreamTangent(CompactStreamReader& in, ByteReader& r, const MeshHeader& h,
                                size_t k, CornerTangent& t) {
    const uint64_t i = in.getUnsigned(StreamField::TangentIndex);
    const uint64_t j = in.getUnsigned(StreamField::TangentIndex);
    const uint64_t corner = in.getUnsigned(StreamField::TangentIndex);
    if (corner > 3) r.fail("tangent break " + std::to_string(k) + " has a bad corner code");
    placeBreak(r, h, k, i, j, corner & 1, corner >> 1, t);
    const size_t column = static_cast<size_t>(i) + static_cast<size_t>(t.a);
    for (double* x : {&t.posU.x, &t.posU.y})
        *x = derivativeU(r, h, kPosU, in.getSigned(StreamField::TangentValue), column);
    for (int c = 0; c < 3 && !h.byRule; ++c)
        t.colU[c] = derivativeU(r, h, kColU, in.getSigned(StreamField::TangentValue), column);
}

void Decoder::readStreamMesh(CompactStreamReader& in, ByteReader& r,
                             const int (&shared)[kFieldCount], Document& doc) {
    const MeshHeader h = readStreamHeader(in, r, shared);
    // What the mesh decodes to counts as the binary64 values it becomes, charged before any of
    // it is allocated: the node planes, and the fixed parts of slits and tangent breaks (their
    // below copies once their columns are known).
    const uint64_t F = static_cast<uint64_t>(h.components());
    const uint64_t endValues = h.byRule ? 2 : 5;
    uint64_t values = satMul(F, h.nodes());
    values = satAdd(values, satMul(h.slits, 3 + 2 * endValues));
    values = satAdd(values, satMul(h.tangents, 3 + endValues));
    charge(r, satMul(kDecodedBytesPerValue, values));

    GradientMesh m;
    readStreamKnots(in, r, h, m);
    readStreamNodes(in, r, h, m);
    r.need(satMul(h.slits, 3 + 2 * endValues) / kValuesPerStreamByte, "the slits");
    m.slits.resize(static_cast<size_t>(h.slits));
    for (size_t k = 0; k < m.slits.size(); ++k) readStreamSlit(in, r, h, k, m.slits[k]);
    r.need(satMul(h.tangents, 3 + endValues) / kValuesPerStreamByte, "the tangent breaks");
    m.tangents.resize(static_cast<size_t>(h.tangents));
    for (size_t k = 0; k < m.tangents.size(); ++k) readStreamTangent(in, r, h, k, m.tangents[k]);
    addMesh(std::move(m), h, doc);
}

Document Decoder::run() {
    readFileHeader();
    Document doc;
    uint64_t meshCount = 0;
    {
        const Section s = next({"DOCU"});
        Payload p;
        open(s, kMaxHeaderPayload, p);
        ByteReader& r = p.reader;
        uint64_t width, height;
        if (shortFraming()) {  // varints (a newer 2.x minor may append fields)
            width = r.varint(), height = r.varint();
            meshCount = r.varint();
        } else {
            r.need(kDocPayloadSize, "the document header");
            width = r.u32(), height = r.u32();
            meshCount = r.u32();
            if (minor_ == 0) finish(p, s);
        }
        const uint64_t side = std::min<uint64_t>(limits_.maxCanvasSide, INT_MAX);
        if (width == 0 || height == 0)
            fail("canvas size " + std::to_string(width) + "x" + std::to_string(height) + " is not positive", s.start);
        if (width > side || height > side)
            fail("canvas " + std::to_string(width) + "x" + std::to_string(height) +
                     " exceeds the limit of " + std::to_string(side) + " pixels per side",
                 s.start);
        if (meshCount > limits_.maxMeshes)
            fail(std::to_string(meshCount) + " meshes exceed the limit of " +
                     std::to_string(limits_.maxMeshes),
                 s.start);
        const uint64_t left = bytes_.size() - pos_;
        // A mesh of a CMS2 or CMS3 stream (1.3, 1.4) may take less than a byte.
        const uint64_t least = minor_ >= 3   ? meshCount / kStreamMeshesPerByte
                               : minor_ == 2 ? satMul(meshCount, kMinMeshRecord)
                                             : satMul(meshCount, kMinMeshSections);
        if (least > left)
            fail("truncated: the document declares " + std::to_string(meshCount) + " meshes but only " +
                     std::to_string(left) + " bytes remain",
                 s.start);
        doc.width = static_cast<int>(width);
        doc.height = static_cast<int>(height);
    }

    while (doc.meshes.size() < meshCount) {
        meshName_ = "mesh " + std::to_string(doc.meshes.size());
        const Section s = next({"MESH", "CMSH", "CMS2", "CMS3"});
        if (s.tag == "CMSH") {
            readCompactMeshes(s, meshCount - doc.meshes.size(), doc);
            continue;
        }
        if (s.tag == "CMS2" || s.tag == "CMS3") {
            readStreamMeshes(s, meshCount - doc.meshes.size(), doc);
            continue;
        }
        MeshHeader h;
        {
            Payload p;
            open(s, kMaxHeaderPayload, p);
            h = readMeshHeader(p.reader, s);
        }
        addMesh(readSections(h), h, doc);
    }
    meshName_.clear();

    Section end = next({"END ", "SHAP"});
    if (end.tag == "SHAP") {
        Payload p;
        open(end, limits_.maxFileBytes, p);
        doc.shapes = decodeShapes(p.reader, limits_.maxShapes,
                                  [this](ByteReader& r, uint64_t bytes) { charge(r, bytes); });
        finish(p, end);
        end = next({"END "});
    }
    if (end.stored != 0 || end.raw != 0) fail("the END section must be empty", end.start);
    if (pos_ != bytes_.size())
        fail(std::to_string(bytes_.size() - pos_) + " bytes after the END section", pos_);
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error(problem, file_);
    return doc;
}

}  // namespace

Document decodeGmb(const std::string& bytes, const ReadLimits& limits, const std::string& fileName) {
    return Decoder(bytes, limits, fileName).run();
}

}  // namespace gm
