// .gmb — the native binary format of gradmesh, version 1.0. This comment is the specification.
//
// Conventions. Integers are little-endian and fixed-width unless called varint. f64 is an
// IEEE 754 binary64 stored as its 8 bytes, little-endian. varint: unsigned LEB128, at most 10
// bytes. svarint: a varint holding the zigzag code (n << 1) ^ (n >> 63) of a signed 64-bit n.
//
// File = header, sections, and nothing after the END section.
//
// Header, 12 bytes
//    0   8  magic 89 47 4D 42 0D 0A 1A 0A ("\x89GMB\r\n\x1a\n")
//    8   2  major version, 1. A reader refuses a major it does not know.
//   10   2  minor version, 0. A newer minor may only add optional sections and append fields to
//           the DOCU and MESH payloads; a reader of an older minor skips both.
//
// Section, 28 + S bytes
//    0   4  tag, four ASCII characters
//    4   1  flags: bit 0 = optional (a reader that does not know the tag skips the section;
//           a required section it does not know is an error). Other bits are 0 in 1.0 and
//           ignored by a 1.0 reader.
//    5   1  codec of the payload: 0 stored, 1 deflate (zlib stream, RFC 1950), 2 zstd frame(s)
//    6   2  reserved, 0
//    8   8  S: payload bytes stored in the file
//   16   8  N: payload bytes after decompression (N = S when stored)
//   24   S  payload
//  24+S  4  CRC-32 (zlib's crc32) of the section's bytes 0 .. 24+S-1
//
// Section order (unknown optional sections may stand between any two):
//   DOCU                  once, first
//   per mesh, in painting order:
//     MESH KNOT NODE      always
//     SLIT                if and only if the mesh has slits
//     TANG                if and only if the mesh has corner tangent breaks
//   END                   once, last, empty payload
// Every section defined by 1.0 is required (flags bit 0 clear).
//
// DOCU payload, 12 bytes: u32 canvas width, u32 canvas height (pixels), u32 mesh count.
// MESH payload, 32 bytes: u32 C (patch columns), u32 R (patch rows), u32 slit count,
//   u32 corner tangent break count, u8 encoding (0 float64 = lossless, 1 quantised = compact),
//   u8 flags (bit 0: colour derivatives omitted; the reader recomputes them with applyColorRule
//   from the decoded mesh; other bits 0, ignored by a 1.0 reader), 7 × i16 exponents e for the quantised fields knot, pos, posU, posV,
//   col, colU, colV (0 for float64). A quantised value q of field f stands for q · 2^e_f.
//
// A node record has 15 components: pos.x pos.y posU.x posU.y posV.x posV.y col.r col.g col.b
// colU.r colU.g colU.b colV.r colV.g colV.b; the last six are absent when colour derivatives are
// omitted. Slit-end tangents and corner tangent breaks use the posU and colU fields.
//
// Float64 encoding (every value an f64)
//   KNOT  u_0 .. u_C, then v_0 .. v_R
//   NODE  (C+1)(R+1) node records, row-major (index j(C+1)+i)
//   SLIT  per slit: u32 row, u32 i0, u32 i1; left end posU.x posU.y [colU.r colU.g colU.b];
//         right end likewise; then i1-i0-1 node records: the copies used below the row of
//         columns i0+1 .. i1-1. The end colU is absent when colour derivatives are omitted.
//   TANG  per break: u32 i, u32 j (the patch), u8 a, u8 b (its corner), posU.x posU.y
//         [colU.r colU.g colU.b], the colU absent when colour derivatives are omitted
//
// Quantised encoding (every value q an svarint unless said otherwise; |q| <= 2^53)
//   KNOT  q(u_0), then C varints q(u_i) - q(u_{i-1}), each >= 1; then the same for v
//   NODE  one plane per node-record component, in record order; a plane holds (C+1)(R+1)
//         residuals q(i,j) - p(i,j), row-major, with the parallelogram prediction
//         p = q(i-1,j) + q(i,j-1) - q(i-1,j-1); on row 0 p = q(i-1,0), in column 0
//         p = q(0,j-1), and p(0,0) = 0
//   SLIT  per slit: varints row, i0, i1; the two end tangents as for float64 but as q values;
//         then the below copies as node records of residuals q(below) - q(node above the row in
//         the same column)
//   TANG  per break: varints i, j, u8 (a | b << 1), then posU.x posU.y [colU.rgb]
//
// Reading limits. Every count is checked against ReadLimits and against the bytes that remain
// before anything is allocated. A section's declared N must fit its counts, and the sum of the
// N of all sections may not exceed ReadLimits::maxFileBytes: a decoded document is never larger
// than the largest file the caller accepts, whatever the compression ratio.
#include <algorithm>

#include "formats/atomic_file.h"
#include "formats/gmb.h"
#include "gmb_pvt.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"

namespace gm {

namespace {

class GmbFormat : public MeshFormat {
public:
    std::string name() const override { return "gmb"; }
    std::vector<std::string> extensions() const override { return {".gmb"}; }
    bool canRead() const override { return true; }
    bool canWrite() const override { return true; }

    bool sniff(const std::string& head) const override {
        return head.size() >= sizeof gmb::kMagic &&
               std::equal(head.begin(), head.begin() + sizeof gmb::kMagic, gmb::kMagic);
    }

    Document read(const std::string& path, const ReadOptions& options) const override {
        const std::string bytes = readWholeFile(path, options.limits.maxFileBytes);
        return decodeGmb(bytes, options.limits, path);
    }

    void write(const Document& doc, const std::string& path,
               const WriteOptions& options) const override {
        std::string bytes;
        try {
            if (options.legacy) {
                Document pieces{doc.width, doc.height, {}};
                for (const GradientMesh& m : doc.meshes)
                    for (GradientMesh& piece : splitIntoLegacyMeshes(m))
                        pieces.meshes.push_back(std::move(piece));
                bytes = encodeGmb(pieces, options.compact);
            } else {
                bytes = encodeGmb(doc, options.compact);
            }
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error(e.reason(), path, e.where());
        }
        writeFileAtomically(path, bytes);
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeGmbFormat() { return std::make_unique<GmbFormat>(); }

}  // namespace gm
