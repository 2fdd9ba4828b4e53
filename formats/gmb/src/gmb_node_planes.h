// Private to the .gmb reader and writer: the NODE payload of encoding 2 (quantised, predicted
// and range-coded; specified in docs/formats.md under "Encoding 2"). Prediction and
// residual coding live here once, for both directions, so that writer and reader cannot drift.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "gmb_pvt.h"

namespace gm::gmb {

// The spans D of the columns (or rows) of a mesh, from its quantised knots k_0..k_N: at index
// i, the larger of k_i - k_{i-1} and k_{i+1} - k_i (those that exist), plus 2. Needs N >= 1 and
// strictly increasing knots within ±2^53, as KNOT guarantees.
std::vector<uint64_t> localSpans(const std::vector<int64_t>& knots);

// The value of a quantised derivative q in encoding 2: q · 2^(e_field - e_knot) / span, with
// one IEEE division (exactly what a reader on any platform computes).
inline double codedDerivative(int64_t q, int exponentFromKnot, uint64_t span) {
    return std::ldexp(static_cast<double>(q), exponentFromKnot) / static_cast<double>(span);
}

// Encoding 2 needs |e_f - e_knot| <= kMaxExponent (finite values) and |e_f - e_value| <= 16
// (exact prediction arithmetic) for the four derivative fields; an empty string if they hold.
std::string codedExponentProblem(const int (&exponent)[kFieldCount]);

// One mesh's quantised nodes and what their prediction needs.
struct CodedGrid {
    int columns = 0, rows = 0;
    int components = 0;  // kNodeComponents, or kNodeComponentsByRule without colour derivatives
    int exponent[kFieldCount] = {};
    std::vector<int64_t> knotU, knotV;   // quantised knots
    std::vector<uint64_t> spanU, spanV;  // localSpans of the knots
    // Quantised values, plane by plane in node-record component order: component c of node k
    // is planes[c * nodes + k].
    std::vector<int64_t> planes;

    size_t nodes() const {
        return static_cast<size_t>(columns + 1) * static_cast<size_t>(rows + 1);
    }
};

// How the plane weights precede the range-coded residuals: every plane's weights (a NODE
// section of encoding 2, version 1.1), or a mask of the planes that state theirs as differences
// from the defaults (the nodes of a CMSH mesh record, version 1.2).
enum class WeightLayout { Explicit, Masked };

// Fills grid.planes (everything else must be set) from the weights and the range-coded stream
// in `reader`, leaving the reader just after the stream's last byte; every failure is a
// gm::Error through the reader. (The writer writes neither NODE of encoding 2 nor CMSH any
// more: only CMS2.)
void decodeCodedNodes(ByteReader& reader, CodedGrid& grid, WeightLayout layout);

// ---- CMS2 (version 1.3) and CMS3 (1.4): one range-coded stream holds every mesh of the
// section.

// The kinds of integer coded in a CMS2 or CMS3 stream outside the node planes; each has its own
// models (docs/formats.md, "CMS2").
enum class StreamField {
    Size,           // C, R
    Count,          // slit count, corner tangent break count
    Flags,          // mesh flags
    KnotExponent,   // e_knot
    KnotStart,      // q(u_0), q(v_0)
    KnotStep,       // q(u_i) - q(u_{i-1}) - 1
    WeightDelta,    // a stated plane weight minus its default
    SlitIndex,      // row, i0, i1
    SlitEnd,        // a slit-end tangent value
    SlitBelow,      // a below copy's value minus the node above it
    TangentIndex,   // i, j, a | b << 1 of a corner tangent break
    TangentValue,   // a corner tangent break's value
};
constexpr int kStreamFields = 12;

// The two kinds of range-coded mesh stream: CMS2 (version 1.3), whose models all start fresh
// and whose 15 planes each have their own residual models, and CMS3 (version 1.4), whose planes
// share 7 sets of residual models that start from fixed priors (docs/formats.md, "CMS3").
enum class StreamKind { Cms2, Cms3 };

// All the adaptive models of a CMS2 or CMS3 stream: set at the start of a section, then shared
// by all its meshes.
struct StreamModels;
class RangeEncoder;
class RangeDecoder;

class CompactStreamWriter {
public:
    explicit CompactStreamWriter(StreamKind kind);
    ~CompactStreamWriter();
    void putUnsigned(StreamField f, uint64_t x);
    void putSigned(StreamField f, int64_t x);
    // Which planes state their weights and those weights (the defaults unless stating fitted
    // ones pays), then the residuals of the planes.
    void putNodes(const CodedGrid& grid);
    // The stream's bytes; the writer is spent afterwards.
    std::string finish();

private:
    std::unique_ptr<StreamModels> models_;
    std::unique_ptr<RangeEncoder> enc_;
};

// Reads a CMS2 or CMS3 stream from `reader`, which fails (naming file, section and byte) where
// it ends early; the stream's first 5 bytes are read on construction.
class CompactStreamReader {
public:
    CompactStreamReader(ByteReader& reader, StreamKind kind);
    ~CompactStreamReader();
    uint64_t getUnsigned(StreamField f);
    // Fails for a magnitude of 2^63 or more.
    int64_t getSigned(StreamField f);
    // Fills grid.planes (everything else must be set; the caller has checked the counts
    // against the bytes that remain).
    void getNodes(CodedGrid& grid);

private:
    ByteReader& r_;
    std::unique_ptr<StreamModels> models_;
    std::unique_ptr<RangeDecoder> dec_;
};

}  // namespace gm::gmb
