// An independent reading of the NODE payload of encoding 2 (range-coded), of CMSH sections
// (version 1.2), of CMS2 sections (version 1.3) and of CMS3 sections (version 1.4), written
// from the specification in docs/formats.md
// rather than from the reader: the tests decode the writer's files with it (so the spec is
// enough to write a decoder), and build range-coded payloads that the writer never produces
// (malformed cases).
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gmbtest {

__extension__ typedef __int128 SpecInt;

inline SpecInt specFloorDiv(SpecInt n, SpecInt d) {  // d > 0
    SpecInt q = n / d;
    if (q * d > n) --q;
    return q;
}
inline SpecInt specClamp62(SpecInt x) {
    const SpecInt l = SpecInt(1) << 62;
    return x > l ? l : (x < -l ? -l : x);
}
inline SpecInt specRnd(SpecInt n) { return specFloorDiv(n + 128, 256); }
inline uint64_t specAbs(int64_t x) {
    return x < 0 ? 0 - static_cast<uint64_t>(x) : static_cast<uint64_t>(x);
}
inline int specBitLength(uint64_t m) {
    int n = 0;
    while (m) {
        ++n;
        m >>= 1;
    }
    return n;
}

struct SpecModel {
    uint32_t A = 32768, B = 32768, c = 0;
    uint32_t P() const {
        const uint32_t p = (A + B) / 2;
        return p < 32 ? 32 : (p > 65504 ? 65504 : p);
    }
    void update(int x) {
        uint32_t w = 16;
        if (c < 30) {
            w = 1 + c / 2;
            ++c;
        }
        const uint32_t a = w < 4 ? w : 4, b = w < 7 ? w : 7;
        if (x) {
            A += (65536 - A) >> a;
            B += (65536 - B) >> b;
        } else {
            A -= A >> a;
            B -= B >> b;
        }
    }
};

struct SpecPlaneModels {
    SpecModel zero[16], sign[16], length[16][24], top[64];
};

// CMS3: the model set P0..P6 of each node-record component, and the priors of each set (the
// spec's tables, units of 2^-12): zero[x], then length[d].
static const int kSpecCms3Set[15] = {0, 1, 2, 2, 2, 2, 3, 4, 3, 5, 6, 5, 5, 6, 5};
static const uint32_t kSpecCms3Zero[7][16] = {
    {2884, 1640, 2116, 2487, 3169, 3578, 3713, 3740, 3858, 3925, 3925, 3925, 4020, 4020, 4020, 4020},
    {2155, 1451, 1770, 1958, 2597, 3363, 3543, 3677, 3762, 3762, 3762, 3762, 3762, 3762, 3762, 3762},
    {776, 1010, 1724, 2355, 3044, 3450, 3635, 3766, 3919, 4000, 4000, 4000, 4000, 4000, 4000, 4000},
    {85, 535, 710, 1806, 2299, 2965, 3380, 3416, 3416, 3416, 3416, 3416, 3416, 3416, 3416, 3416},
    {1852, 1664, 2765, 2873, 3321, 3524, 3736, 3802, 3982, 3982, 3982, 3982, 3982, 3982, 3982, 3982},
    {191, 593, 894, 1621, 2223, 2660, 2910, 3120, 3296, 3521, 3521, 3521, 3521, 3521, 3521, 3521},
    {1054, 1290, 1948, 2456, 3056, 3450, 3718, 3882, 3882, 3959, 4036, 4036, 4036, 4036, 4036, 4036}};
static const uint32_t kSpecCms3Length[7][10] = {
    {3292, 1509, 1627, 1961, 2525, 3097, 3434, 3599, 3812, 3947},
    {2904, 1912, 1912, 1912, 2236, 2843, 3326, 3595, 3788, 3891},
    {2024, 1191, 1285, 1721, 2401, 3066, 3489, 3754, 3908, 3941},
    {1197, 601, 735, 807, 1407, 2310, 2836, 3439, 3789, 3893},
    {2665, 1319, 1353, 1775, 2541, 3163, 3532, 3775, 3905, 3993},
    {379, 333, 418, 655, 1361, 2176, 2992, 3542, 3799, 3941},
    {1525, 1057, 1299, 1744, 2395, 3052, 3480, 3780, 3912, 4046}};

// The 7 residual model sets of a CMS3 stream as they start.
inline std::vector<SpecPlaneModels> specCms3Start() {
    std::vector<SpecPlaneModels> sets(7);
    for (int g = 0; g < 7; ++g)
        for (int x = 0; x < 16; ++x) {
            SpecModel& z = sets[g].zero[x];
            z.A = z.B = 16 * kSpecCms3Zero[g][x];
            z.c = 4;
            for (int k = 0; k < 24; ++k) {
                const int d = x - k < 0 ? 0 : (x - k > 9 ? 9 : x - k);
                SpecModel& l = sets[g].length[x][k];
                l.A = l.B = 16 * kSpecCms3Length[g][d];
                l.c = 4;
            }
        }
    return sets;
}

class SpecRangeDecoder {
public:
    SpecRangeDecoder(const std::string& s, size_t begin) : s_(s), pos_(begin) {
        if (byte() != 0) throw std::runtime_error("first byte of the range-coded stream is not 0");
        for (int k = 0; k < 4; ++k) V_ = (V_ << 8) | byte();
    }
    int decision(SpecModel& m) {
        const uint32_t T = (R_ >> 16) * m.P();
        int x;
        if (V_ < T) {
            x = 1;
            R_ = T;
        } else {
            x = 0;
            V_ -= T;
            R_ -= T;
        }
        m.update(x);
        normalise();
        return x;
    }
    int direct() {
        R_ /= 2;
        int x = 0;
        if (V_ >= R_) {
            x = 1;
            V_ -= R_;
        }
        normalise();
        return x;
    }
    size_t position() const { return pos_; }

private:
    uint32_t byte() {
        if (pos_ >= s_.size()) throw std::runtime_error("range-coded stream ends early");
        return static_cast<unsigned char>(s_[pos_++]);
    }
    void normalise() {
        while (R_ < (1u << 24)) {
            R_ <<= 8;
            V_ = (V_ << 8) | byte();
        }
    }
    const std::string& s_;
    size_t pos_;
    uint32_t R_ = 0xffffffffu, V_ = 0;
};

// The encoder side, for crafting streams (the spec names LZMA's encoder).
class SpecRangeEncoder {
public:
    void decision(SpecModel& m, int x) {
        const uint32_t T = (R_ >> 16) * m.P();
        if (x) {
            R_ = T;
        } else {
            low_ += T;
            R_ -= T;
        }
        m.update(x);
        normalise();
    }
    void direct(int x) {
        R_ /= 2;
        if (x) low_ += R_;
        normalise();
    }
    void residual(SpecPlaneModels& m, int ctx, int64_t r) {
        decision(m.zero[ctx], r != 0);
        if (r == 0) return;
        decision(m.sign[ctx], r < 0);
        const uint64_t M = specAbs(r);
        const int n = specBitLength(M) - 1;
        for (int k = 0; k < n; ++k) decision(m.length[ctx][k < 23 ? k : 23], 1);
        if (n < 63) decision(m.length[ctx][n < 23 ? n : 23], 0);
        if (n >= 1) {
            decision(m.top[n], static_cast<int>((M >> (n - 1)) & 1));
            for (int k = n - 2; k >= 0; --k) direct(static_cast<int>((M >> k) & 1));
        }
    }
    std::string finish() {
        for (int k = 0; k < 5; ++k) shiftLow();
        return out_;
    }

private:
    void normalise() {
        while (R_ < (1u << 24)) {
            R_ <<= 8;
            shiftLow();
        }
    }
    void shiftLow() {
        if (static_cast<uint32_t>(low_) < 0xff000000u || (low_ >> 32) != 0) {
            const auto carry = static_cast<uint8_t>(low_ >> 32);
            uint8_t b = cache_;
            do {
                out_.push_back(static_cast<char>(static_cast<uint8_t>(b + carry)));
                b = 0xff;
            } while (--pending_ != 0);
            cache_ = static_cast<uint8_t>(low_ >> 24);
        }
        ++pending_;
        low_ = (low_ & 0x00ffffffu) << 8;
    }
    uint64_t low_ = 0;
    uint32_t R_ = 0xffffffffu;
    uint8_t cache_ = 0;
    uint64_t pending_ = 1;
    std::string out_;
};

inline void putSvarint(std::string& s, int64_t n) {
    uint64_t z = (static_cast<uint64_t>(n) << 1) ^ (n < 0 ? ~uint64_t(0) : 0);
    while (z >= 0x80) {
        s.push_back(static_cast<char>((z & 0x7f) | 0x80));
        z >>= 7;
    }
    s.push_back(static_cast<char>(z));
}

// What decoding one mesh's NODE needs from MESH and KNOT.
struct SpecMeshInfo {
    int C = 0, R = 0, F = 15;
    int e[7] = {};                // knot pos posU posV col colU colV
    std::vector<int64_t> ku, kv;  // quantised knots
};

// Spans of the columns (or rows) from quantised knots.
inline std::vector<int64_t> specSpans(const std::vector<int64_t>& k) {
    std::vector<int64_t> D(k.size());
    for (size_t i = 0; i < k.size(); ++i) {
        int64_t d = 0;
        if (i > 0 && k[i] - k[i - 1] > d) d = k[i] - k[i - 1];
        if (i + 1 < k.size() && k[i + 1] - k[i] > d) d = k[i + 1] - k[i];
        D[i] = d + 2;
    }
    return D;
}

// Reads varints from a byte string, throwing std::runtime_error where it ends or overflows.
struct SpecBytes {
    const std::string& s;
    size_t pos = 0;
    uint64_t varint() {
        uint64_t z = 0;
        for (int k = 0;; ++k) {
            if (pos >= s.size() || k == 10) throw std::runtime_error("bad varint");
            const auto b = static_cast<unsigned char>(s[pos++]);
            z |= uint64_t(b & 0x7f) << (7 * k);
            if (!(b & 0x80)) return z;
        }
    }
    int64_t svarint() {
        const uint64_t z = varint();
        return static_cast<int64_t>((z >> 1) ^ (0 - (z & 1)));
    }
    int u8() {
        if (pos >= s.size()) throw std::runtime_error("bad u8");
        return static_cast<unsigned char>(s[pos++]);
    }
};

// Plane weights a, b, s by node-record component.
struct SpecWeights {
    int64_t a[15] = {}, b[15] = {}, s[15] = {};
};

static const int kSpecOrder[15] = {0, 1, 7, 6, 8, 2, 3, 4, 5, 10, 9, 11, 13, 12, 14};
static const int kSpecValueOf[15] = {-1, -1, 0, 1, 0, 1, -1, -1, -1, 6, 7, 8, 6, 7, 8};

// The context of residual (i, j) of a plane from the residuals around it: `r` this plane's,
// `S` the sibling plane's residual at (i, j) (0 without one).
inline int specContext(const std::vector<int64_t>& r, int64_t S, int C, int i, int j) {
    auto mag = [&](int ii, int jj) -> uint64_t {
        if (ii < 0 || ii > C || jj < 0) return 0;
        const uint64_t x = specAbs(r[static_cast<size_t>(jj) * (C + 1) + ii]);
        return x > (uint64_t(1) << 40) ? uint64_t(1) << 40 : x;
    };
    uint64_t S40 = specAbs(S);
    if (S40 > (uint64_t(1) << 40)) S40 = uint64_t(1) << 40;
    const uint64_t msum = 2 * mag(i - 1, j) + 2 * mag(i, j - 1) + mag(i - 1, j - 1) +
                          mag(i + 1, j - 1) + mag(i - 2, j) + 3 * S40;
    const int x = specBitLength(msum);
    return x > 15 ? 15 : x;
}

static const int kSpecSibling[15] = {-1, 0, -1, 2, -1, 4, 7, -1, 7, 10, -1, 10, 13, -1, 13};

// Decodes the planes of one mesh from `dec` to q (returned) and the residuals (`res`), both
// indexed [component][node] in node-record order. `persistent`: the models that a CMS2 or CMS3
// stream keeps across meshes, component c's being persistent[setOf[c]] (setOf null: c);
// null: fresh models for every plane (NODE, CMSH).
// Throws std::runtime_error where the spec says the data is bad.
inline std::vector<std::vector<int64_t>> specDecodePlanesWith(
    SpecRangeDecoder& dec, const SpecMeshInfo& in, const SpecWeights& w,
    SpecPlaneModels* persistent, std::vector<std::vector<int64_t>>& r,
    const int* setOf = nullptr) {
    const int* order = kSpecOrder;
    const int* valueOf = kSpecValueOf;
    const int* sibling = kSpecSibling;
    static const int fieldOf[15] = {1, 1, 2, 2, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 6};
    const int C = in.C, R = in.R;
    const size_t n = static_cast<size_t>(C + 1) * (R + 1);
    const int64_t *wa = w.a, *wb = w.b, *ws = w.s;
    const std::vector<int64_t> Du = specSpans(in.ku), Dv = specSpans(in.kv);
    std::vector<std::vector<int64_t>> q(15, std::vector<int64_t>(n, 0));
    r.assign(15, std::vector<int64_t>(n, 0));
    auto at = [&](int i, int j) { return static_cast<size_t>(j) * (C + 1) + i; };
    for (int o = 0; o < in.F; ++o) {
        const int c = order[o];
        SpecPlaneModels fresh;
        SpecPlaneModels& m = persistent ? persistent[setOf ? setOf[c] : c] : fresh;
        for (int j = 0; j <= R; ++j) {
            for (int i = 0; i <= C; ++i) {
                const int64_t S = sibling[c] >= 0 ? r[sibling[c]][at(i, j)] : 0;
                const int x = specContext(r[c], S, C, i, j);
                // The residual.
                SpecInt res = 0;
                if (dec.decision(m.zero[x])) {
                    const int negative = dec.decision(m.sign[x]);
                    int len = 0;
                    while (len < 63 && dec.decision(m.length[x][len < 23 ? len : 23])) ++len;
                    uint64_t M = uint64_t(1) << len;
                    if (len >= 1) {
                        M |= uint64_t(dec.decision(m.top[len])) << (len - 1);
                        for (int k = len - 2; k >= 0; --k) M |= uint64_t(dec.direct()) << k;
                    }
                    res = negative ? -SpecInt(M) : SpecInt(M);
                }
                // The prediction.
                SpecInt p;
                if (valueOf[c] < 0) {
                    const std::vector<int64_t>& Q = q[c];
                    if (i > 0 && j > 0) {
                        const SpecInt L = Q[at(i - 1, j)], U = Q[at(i, j - 1)],
                                      G = Q[at(i - 1, j - 1)];
                        p = L + specRnd(wa[c] * (U - L) + wb[c] * (G - L) + ws[c] * SpecInt(S));
                    } else if (i > 0) {
                        p = Q[at(i - 1, 0)] + specRnd(ws[c] * SpecInt(S));
                    } else if (j > 0) {
                        p = Q[at(0, j - 1)] + specRnd(ws[c] * SpecInt(S));
                    } else {
                        p = specRnd(ws[c] * SpecInt(S));
                    }
                } else {
                    const bool alongU = c == 2 || c == 3 || (c >= 9 && c <= 11);
                    const std::vector<int64_t>& V = q[valueOf[c]];
                    const int t = in.e[fieldOf[valueOf[c]]] - in.e[fieldOf[c]];
                    SpecInt M, W;
                    if (alongU) {
                        const int i0 = i > 0 ? i - 1 : 0, i1 = i < C ? i + 1 : C;
                        M = SpecInt(V[at(i1, j)] - V[at(i0, j)]) * Du[i];
                        W = SpecInt(in.ku[i1] - in.ku[i0]);
                    } else {
                        const int j0 = j > 0 ? j - 1 : 0, j1 = j < R ? j + 1 : R;
                        M = SpecInt(V[at(i, j1)] - V[at(i, j0)]) * Dv[j];
                        W = SpecInt(in.kv[j1] - in.kv[j0]);
                    }
                    if (t > 0) M *= SpecInt(1) << t;
                    if (t < 0) W *= SpecInt(1) << -t;
                    const SpecInt cd = specClamp62(specFloorDiv(2 * M + W, 2 * W));
                    p = specRnd(wa[c] * cd + ws[c] * SpecInt(S));
                }
                p = specClamp62(p);
                const SpecInt value = p + res;
                if (value > (SpecInt(1) << 53) || value < -(SpecInt(1) << 53))
                    throw std::runtime_error("quantised value out of range");
                q[c][at(i, j)] = static_cast<int64_t>(value);
                r[c][at(i, j)] = static_cast<int64_t>(res);
            }
        }
    }
    return q;
}

// Decodes the range-coded stream at bytes.pos to the q planes, indexed [component][node] in
// node-record order, leaving bytes.pos just after the stream (fresh models in every plane).
inline std::vector<std::vector<int64_t>> specDecodePlanes(SpecBytes& bytes, const SpecMeshInfo& in,
                                                          const SpecWeights& w) {
    SpecRangeDecoder dec(bytes.s, bytes.pos);
    std::vector<std::vector<int64_t>> r;
    auto q = specDecodePlanesWith(dec, in, w, nullptr, r);
    bytes.pos = dec.position();
    return q;
}

// Decodes a NODE payload of encoding 2 (every plane's weights, then the stream to the end).
inline std::vector<std::vector<int64_t>> specDecodeCodedNodes(const std::string& payload,
                                                              const SpecMeshInfo& in) {
    SpecBytes bytes{payload};
    SpecWeights w;
    for (int o = 0; o < in.F; ++o) {
        const int c = kSpecOrder[o];
        w.a[c] = bytes.svarint();
        if (kSpecValueOf[c] < 0) w.b[c] = bytes.svarint();
        w.s[c] = bytes.svarint();
        for (int64_t x : {w.a[c], w.b[c], w.s[c]})
            if (x > 32768 || x < -32768) throw std::runtime_error("weight out of range");
    }
    auto q = specDecodePlanes(bytes, in, w);
    if (bytes.pos != payload.size()) throw std::runtime_error("bytes after the range-coded stream");
    return q;
}

// One mesh record of a CMSH section, as the spec lays it out.
struct SpecCmshMesh {
    SpecMeshInfo info;
    int slits = 0, tangents = 0;
    bool byRule = false;  // no colour derivatives stored (flags 1: by the rule, 2: Bicubic model)
    int flags = 0;
    uint64_t weightsMask = 0;
    SpecWeights weights;                  // every plane's, defaults included
    std::vector<std::vector<int64_t>> q;  // [component][node]
    std::vector<std::vector<int64_t>> r;  // the residuals, likewise (CMS2 only)
    std::string tail;                     // slits and breaks in the CMSH layout (CMS2 only)
    // Where its parts begin in the payload (`end`: the next record); CMSH only.
    size_t start = 0, knotsAt = 0, weightsAt = 0, streamAt = 0, slitsAt = 0, tangentsAt = 0,
           end = 0;
};

// The default weights of CMSH, by node-record component (the spec's table).
inline SpecWeights specCmshDefaults() {
    SpecWeights d;
    for (int c = 0; c < 15; ++c) d.a[c] = 256;
    d.b[0] = d.b[1] = -256;
    for (int c : {6, 7, 8}) d.a[c] = 128;
    d.s[6] = d.s[8] = 240;
    d.a[10] = d.a[13] = 192;
    for (int c : {9, 11, 12, 14}) {
        d.a[c] = 224;
        d.s[c] = 240;
    }
    return d;
}

// Decodes a CMSH payload: every mesh record's knots and node planes; slits and tangent breaks
// are stepped over by their layout. Throws std::runtime_error where the spec says the data is
// bad.
inline std::vector<SpecCmshMesh> specDecodeCmsh(const std::string& payload) {
    SpecBytes bytes{payload};
    const uint64_t M = bytes.varint();
    if (M == 0) throw std::runtime_error("no mesh");
    int shared[7] = {};
    for (int f = 1; f < 7; ++f) shared[f] = static_cast<int>(bytes.svarint());
    std::vector<SpecCmshMesh> out;
    for (uint64_t k = 0; k < M; ++k) {
        SpecCmshMesh m;
        m.start = bytes.pos;
        m.info.C = static_cast<int>(bytes.varint());
        m.info.R = static_cast<int>(bytes.varint());
        m.slits = static_cast<int>(bytes.varint());
        m.tangents = static_cast<int>(bytes.varint());
        const int flags = bytes.u8();
        if (flags > 3) throw std::runtime_error("unknown flags");
        m.flags = flags;
        m.byRule = flags != 0;
        m.info.F = m.byRule ? 9 : 15;
        for (int f = 1; f < 7; ++f) m.info.e[f] = shared[f];
        m.info.e[0] = static_cast<int>(bytes.svarint());
        m.knotsAt = bytes.pos;
        for (std::vector<int64_t>* knots : {&m.info.ku, &m.info.kv}) {
            const int count = (knots == &m.info.ku ? m.info.C : m.info.R) + 1;
            int64_t q = bytes.svarint();
            knots->push_back(q);
            for (int i = 1; i < count; ++i) {
                q += static_cast<int64_t>(bytes.varint());
                knots->push_back(q);
            }
        }
        m.weightsAt = bytes.pos;
        m.weightsMask = bytes.varint();
        if (m.weightsMask >> m.info.F) throw std::runtime_error("weights mask beyond the planes");
        SpecWeights w = specCmshDefaults();
        for (int o = 0; o < m.info.F; ++o) {
            if (!((m.weightsMask >> o) & 1)) continue;
            const int c = kSpecOrder[o];
            w.a[c] += bytes.svarint();
            if (kSpecValueOf[c] < 0) w.b[c] += bytes.svarint();
            w.s[c] += bytes.svarint();
            for (int64_t x : {w.a[c], w.b[c], w.s[c]})
                if (x > 32768 || x < -32768) throw std::runtime_error("weight out of range");
        }
        m.weights = w;
        m.streamAt = bytes.pos;
        m.q = specDecodePlanes(bytes, m.info, w);
        m.slitsAt = bytes.pos;
        const int endValues = m.byRule ? 2 : 5;
        for (int sl = 0; sl < m.slits; ++sl) {
            bytes.varint();  // row
            const uint64_t i0 = bytes.varint(), i1 = bytes.varint();
            for (int x = 0; x < 2 * endValues; ++x) bytes.svarint();
            for (uint64_t x = 0; x < (i1 - i0 - 1) * static_cast<uint64_t>(m.info.F); ++x)
                bytes.svarint();
        }
        m.tangentsAt = bytes.pos;
        for (int t = 0; t < m.tangents; ++t) {
            bytes.varint();  // i, j, corner
            bytes.varint();
            bytes.u8();
            for (int x = 0; x < endValues; ++x) bytes.svarint();
        }
        m.end = bytes.pos;
        out.push_back(std::move(m));
    }
    if (bytes.pos != payload.size()) throw std::runtime_error("bytes after the last mesh record");
    return out;
}


// The models of one kind of integer of a CMS2 stream.
struct SpecIntModels {
    SpecModel zero, sign, length[24], top[64];
};

// Decodes a CMS2 payload (version 1.3), or with `cms3` a CMS3 payload (1.4): every mesh's
// counts, knots, weights, node planes (q and residuals), and its slits and tangent breaks,
// which it also lays out as CMSH would (`tail`). Throws std::runtime_error where the spec says
// the data is bad.
inline std::vector<SpecCmshMesh> specDecodeCms2(const std::string& payload, bool cms3 = false) {
    SpecBytes bytes{payload};
    const uint64_t M = bytes.varint();
    if (M == 0) throw std::runtime_error("no mesh");
    int shared[7] = {};
    for (int f = 1; f < 7; ++f) shared[f] = static_cast<int>(bytes.svarint());
    SpecRangeDecoder dec(payload, bytes.pos);
    // The model sets, fresh here and kept across the meshes: Size, Count, Flags, KnotExponent,
    // KnotStart, KnotStep, WeightDelta, SlitIndex, SlitEnd, SlitBelow, TangentIndex,
    // TangentValue; the weights decisions of the 15 plane positions; the 15 planes' residuals.
    enum { Size, Count, Flags, KnotExponent, KnotStart, KnotStep, WeightDelta, SlitIndex, SlitEnd,
           SlitBelow, TangentIndex, TangentValue, Kinds };
    std::vector<SpecIntModels> kinds(Kinds);
    std::vector<SpecModel> weighted(15);
    // CMS2: the 15 planes' residual models; CMS3: the 7 sets, from their priors.
    std::vector<SpecPlaneModels> planes = cms3 ? specCms3Start() : std::vector<SpecPlaneModels>(15);
    auto magnitude = [&](SpecIntModels& m) {
        int len = 0;
        while (len < 63 && dec.decision(m.length[len < 23 ? len : 23])) ++len;
        uint64_t x = uint64_t(1) << len;
        if (len >= 1) {
            x |= uint64_t(dec.decision(m.top[len])) << (len - 1);
            for (int k = len - 2; k >= 0; --k) x |= uint64_t(dec.direct()) << k;
        }
        return x;
    };
    auto U = [&](int kind) -> uint64_t {
        SpecIntModels& m = kinds[static_cast<size_t>(kind)];
        return dec.decision(m.zero) ? magnitude(m) : 0;
    };
    auto S = [&](int kind) -> int64_t {
        SpecIntModels& m = kinds[static_cast<size_t>(kind)];
        if (!dec.decision(m.zero)) return 0;
        const int negative = dec.decision(m.sign);
        const uint64_t x = magnitude(m);
        if (x >= (uint64_t(1) << 63)) throw std::runtime_error("integer out of range");
        return negative ? -static_cast<int64_t>(x) : static_cast<int64_t>(x);
    };
    auto putVarint = [](std::string& s, uint64_t z) {
        while (z >= 0x80) {
            s.push_back(static_cast<char>((z & 0x7f) | 0x80));
            z >>= 7;
        }
        s.push_back(static_cast<char>(z));
    };
    std::vector<SpecCmshMesh> out;
    for (uint64_t k = 0; k < M; ++k) {
        SpecCmshMesh m;
        m.info.C = static_cast<int>(U(Size));
        m.info.R = static_cast<int>(U(Size));
        m.slits = static_cast<int>(U(Count));
        m.tangents = static_cast<int>(U(Count));
        const uint64_t flags = U(Flags);
        if (flags > 3) throw std::runtime_error("unknown flags");
        m.flags = static_cast<int>(flags);
        m.byRule = flags != 0;
        m.info.F = m.byRule ? 9 : 15;
        for (int f = 1; f < 7; ++f) m.info.e[f] = shared[f];
        m.info.e[0] = static_cast<int>(S(KnotExponent));
        for (std::vector<int64_t>* knots : {&m.info.ku, &m.info.kv}) {
            const int count = (knots == &m.info.ku ? m.info.C : m.info.R) + 1;
            int64_t q = S(KnotStart);
            knots->push_back(q);
            for (int i = 1; i < count; ++i) {
                q += static_cast<int64_t>(U(KnotStep)) + 1;
                knots->push_back(q);
            }
        }
        SpecWeights w = specCmshDefaults();
        for (int o = 0; o < m.info.F; ++o) {
            if (!dec.decision(weighted[static_cast<size_t>(o)])) continue;
            m.weightsMask |= uint64_t(1) << o;
            const int c = kSpecOrder[o];
            w.a[c] += S(WeightDelta);
            if (kSpecValueOf[c] < 0) w.b[c] += S(WeightDelta);
            w.s[c] += S(WeightDelta);
            for (int64_t x : {w.a[c], w.b[c], w.s[c]})
                if (x > 32768 || x < -32768) throw std::runtime_error("weight out of range");
        }
        m.weights = w;
        m.q = specDecodePlanesWith(dec, m.info, w, planes.data(), m.r, cms3 ? kSpecCms3Set : nullptr);
        const int endValues = m.byRule ? 2 : 5;
        for (int sl = 0; sl < m.slits; ++sl) {
            const uint64_t row = U(SlitIndex), i0 = U(SlitIndex), i1 = U(SlitIndex);
            if (i1 <= i0) throw std::runtime_error("bad slit");
            for (uint64_t x : {row, i0, i1}) putVarint(m.tail, x);
            for (int x = 0; x < 2 * endValues; ++x) putSvarint(m.tail, S(SlitEnd));
            for (uint64_t x = 0; x < (i1 - i0 - 1) * static_cast<uint64_t>(m.info.F); ++x)
                putSvarint(m.tail, S(SlitBelow));
        }
        for (int t = 0; t < m.tangents; ++t) {
            putVarint(m.tail, U(TangentIndex));  // i
            putVarint(m.tail, U(TangentIndex));  // j
            const uint64_t corner = U(TangentIndex);
            if (corner > 3) throw std::runtime_error("bad corner");
            m.tail.push_back(static_cast<char>(corner));
            for (int x = 0; x < endValues; ++x) putSvarint(m.tail, S(TangentValue));
        }
        out.push_back(std::move(m));
    }
    if (dec.position() != payload.size()) throw std::runtime_error("bytes after the stream");
    return out;
}

// Writes CMS2 streams integer by integer, as the spec defines them, for crafting payloads the
// writer never produces (malformed cases). Kinds are numbered as in specDecodeCms2.
class SpecCms2Writer {
public:
    enum { Size, Count, Flags, KnotExponent, KnotStart, KnotStep, WeightDelta, SlitIndex, SlitEnd,
           SlitBelow, TangentIndex, TangentValue, Kinds };
    void U(int kind, uint64_t x) {
        SpecIntModels& m = kinds_[kind];
        enc_.decision(m.zero, x != 0);
        if (x != 0) magnitude(m, x);
    }
    void S(int kind, int64_t x) {
        SpecIntModels& m = kinds_[kind];
        enc_.decision(m.zero, x != 0);
        if (x == 0) return;
        enc_.decision(m.sign, x < 0);
        magnitude(m, specAbs(x));
    }
    // Whether the o-th plane in coding order states its weights.
    void weighted(int o, int x) { enc_.decision(weighted_[o], x); }
    // A residual of component c's plane in context ctx.
    void residual(int c, int ctx, int64_t r) { enc_.residual(planes_[c], ctx, r); }
    std::string finish() { return enc_.finish(); }

private:
    void magnitude(SpecIntModels& m, uint64_t x) {
        const int n = specBitLength(x) - 1;
        for (int k = 0; k < n; ++k) enc_.decision(m.length[k < 23 ? k : 23], 1);
        if (n < 63) enc_.decision(m.length[n < 23 ? n : 23], 0);
        if (n >= 1) {
            enc_.decision(m.top[n], static_cast<int>((x >> (n - 1)) & 1));
            for (int k = n - 2; k >= 0; --k) enc_.direct(static_cast<int>((x >> k) & 1));
        }
    }
    SpecRangeEncoder enc_;
    SpecIntModels kinds_[Kinds];
    SpecModel weighted_[15];
    SpecPlaneModels planes_[15];
};

// The CMS2 payload (version 1.3) of the meshes of a CMS3 payload (1.4): the same integers (M,
// exponents, counts, knots, weights, residuals, slits, breaks) in one CMS2 stream, whose
// models start fresh and are one set per plane. Its size is what CMS2 costs for the very same
// data.
inline std::string specCms3AsCms2(const std::string& payload) {
    SpecBytes head{payload};
    head.varint();
    for (int f = 1; f < 7; ++f) head.svarint();
    using W = SpecCms2Writer;
    W w;
    for (const SpecCmshMesh& m : specDecodeCms2(payload, true)) {
        const int C = m.info.C, R = m.info.R;
        w.U(W::Size, static_cast<uint64_t>(C));
        w.U(W::Size, static_cast<uint64_t>(R));
        w.U(W::Count, static_cast<uint64_t>(m.slits));
        w.U(W::Count, static_cast<uint64_t>(m.tangents));
        w.U(W::Flags, static_cast<uint64_t>(m.flags));
        w.S(W::KnotExponent, m.info.e[0]);
        for (const std::vector<int64_t>* knots : {&m.info.ku, &m.info.kv}) {
            w.S(W::KnotStart, knots->front());
            for (size_t i = 1; i < knots->size(); ++i)
                w.U(W::KnotStep, static_cast<uint64_t>((*knots)[i] - (*knots)[i - 1] - 1));
        }
        const SpecWeights d = specCmshDefaults();
        for (int o = 0; o < m.info.F; ++o) {
            const int stated = (m.weightsMask >> o) & 1;
            w.weighted(o, stated);
            if (!stated) continue;
            const int c = kSpecOrder[o];
            w.S(W::WeightDelta, m.weights.a[c] - d.a[c]);
            if (kSpecValueOf[c] < 0) w.S(W::WeightDelta, m.weights.b[c] - d.b[c]);
            w.S(W::WeightDelta, m.weights.s[c] - d.s[c]);
        }
        for (int o = 0; o < m.info.F; ++o) {
            const int c = kSpecOrder[o];
            for (int j = 0; j <= R; ++j)
                for (int i = 0; i <= C; ++i) {
                    const size_t k = static_cast<size_t>(j) * (C + 1) + i;
                    const int64_t S = kSpecSibling[c] >= 0 ? m.r[kSpecSibling[c]][k] : 0;
                    w.residual(c, specContext(m.r[c], S, C, i, j), m.r[c][k]);
                }
        }
        // The slits and breaks, from their CMSH layout.
        SpecBytes tail{m.tail};
        const int endValues = m.byRule ? 2 : 5;
        for (int sl = 0; sl < m.slits; ++sl) {
            const uint64_t row = tail.varint(), i0 = tail.varint(), i1 = tail.varint();
            for (uint64_t x : {row, i0, i1}) w.U(W::SlitIndex, x);
            for (int x = 0; x < 2 * endValues; ++x) w.S(W::SlitEnd, tail.svarint());
            for (uint64_t x = 0; x < (i1 - i0 - 1) * static_cast<uint64_t>(m.info.F); ++x)
                w.S(W::SlitBelow, tail.svarint());
        }
        for (int t = 0; t < m.tangents; ++t) {
            w.U(W::TangentIndex, tail.varint());
            w.U(W::TangentIndex, tail.varint());
            w.U(W::TangentIndex, static_cast<uint64_t>(tail.u8()));
            for (int x = 0; x < endValues; ++x) w.S(W::TangentValue, tail.svarint());
        }
    }
    return payload.substr(0, head.pos) + w.finish();
}

// The CMSH payload (version 1.2) of the meshes of a CMS2 (or, with `cms3`, CMS3) payload: the
// same weights, residuals, knots, slits and breaks, in CMSH's layout (every plane coded with
// fresh models, one stream per mesh).
inline std::string specCms2AsCmsh(const std::string& payload, bool cms3 = false) {
    SpecBytes head{payload};
    head.varint();
    for (int f = 1; f < 7; ++f) head.svarint();
    std::string out = payload.substr(0, head.pos);
    auto putVarint = [](std::string& s, uint64_t z) {
        while (z >= 0x80) {
            s.push_back(static_cast<char>((z & 0x7f) | 0x80));
            z >>= 7;
        }
        s.push_back(static_cast<char>(z));
    };
    const SpecWeights d = specCmshDefaults();
    for (const SpecCmshMesh& m : specDecodeCms2(payload, cms3)) {
        for (int x : {m.info.C, m.info.R, m.slits, m.tangents}) putVarint(out, static_cast<uint64_t>(x));
        out.push_back(static_cast<char>(m.flags));
        putSvarint(out, m.info.e[0]);
        for (const std::vector<int64_t>* knots : {&m.info.ku, &m.info.kv}) {
            putSvarint(out, knots->front());
            for (size_t i = 1; i < knots->size(); ++i)
                putVarint(out, static_cast<uint64_t>((*knots)[i] - (*knots)[i - 1]));
        }
        putVarint(out, m.weightsMask);
        for (int o = 0; o < m.info.F; ++o) {
            if (!((m.weightsMask >> o) & 1)) continue;
            const int c = kSpecOrder[o];
            putSvarint(out, m.weights.a[c] - d.a[c]);
            if (kSpecValueOf[c] < 0) putSvarint(out, m.weights.b[c] - d.b[c]);
            putSvarint(out, m.weights.s[c] - d.s[c]);
        }
        SpecRangeEncoder enc;
        const int C = m.info.C;
        for (int o = 0; o < m.info.F; ++o) {
            const int c = kSpecOrder[o];
            SpecPlaneModels models;
            for (int j = 0; j <= m.info.R; ++j)
                for (int i = 0; i <= C; ++i) {
                    const size_t k = static_cast<size_t>(j) * (C + 1) + i;
                    const int64_t S = kSpecSibling[c] >= 0 ? m.r[kSpecSibling[c]][k] : 0;
                    enc.residual(models, specContext(m.r[c], S, C, i, j), m.r[c][k]);
                }
        }
        out += enc.finish();
        out += m.tail;
    }
    return out;
}

// Component c (node-record order) of a node.
inline double nodeValue(const gm::Node& n, int c) {
    const double v[15] = {n.pos.x, n.pos.y, n.posU.x, n.posU.y, n.posV.x, n.posV.y, n.col.r, n.col.g,
                          n.col.b, n.colU.r, n.colU.g, n.colU.b, n.colV.r, n.colV.g, n.colV.b};
    return v[c];
}

// The value of component c (node-record order) of a node in column i, row j, from its q.
inline double specCodedValue(const SpecMeshInfo& in, int c, int64_t q, int i, int j) {
    static const int fieldOf[15] = {1, 1, 2, 2, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 6};
    const int f = fieldOf[c];
    if (f == 1 || f == 4) return std::ldexp(static_cast<double>(q), in.e[f]);
    const bool alongU = f == 2 || f == 5;
    const int64_t D = alongU ? specSpans(in.ku)[static_cast<size_t>(i)]
                             : specSpans(in.kv)[static_cast<size_t>(j)];
    return std::ldexp(static_cast<double>(q), in.e[f] - in.e[0]) / static_cast<double>(D);
}

}  // namespace gmbtest
