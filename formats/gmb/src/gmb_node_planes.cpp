// The coded node planes of encoding 2 (layout: docs/formats.md, "Encoding 2"). All prediction
// arithmetic is on exact integers (128-bit where products need it), so that every reader
// reproduces the writer's predictions bit for bit.
#include "gmb_node_planes.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "gmb_range_coder.h"

namespace gm::gmb {

namespace {

__extension__ typedef __int128 int128;  // GCC and Clang; exact products of 64-bit values

constexpr int64_t kPredictionLimit = int64_t(1) << 62;  // predictions are clamped to ±this
constexpr uint64_t kContextTermLimit = uint64_t(1) << 40;
constexpr int kContexts = 16;
constexpr int kLengthModels = 24;
constexpr int32_t kMaxWeight = 32768;
constexpr int kWeightShift = 8;
constexpr int kWeightOne = 1 << kWeightShift;  // weights are in units of 1/256
constexpr int kMaxShift = 16;                  // |e_derivative - e_value|

// Node-record components in coding order, and each one's role: the sibling whose residual at
// the same node it may use, the value plane a derivative is the derivative of (-1 for value
// planes), and the direction of a derivative.
constexpr int kCodingOrder[kNodeComponents] = {0, 1, 7, 6, 8, 2, 3, 4, 5, 10, 9, 11, 13, 12, 14};
constexpr int kSibling[kNodeComponents] = {-1, 0, -1, 2, -1, 4, 7, -1, 7, 10, -1, 10, 13, -1, 13};
constexpr int kValuePlane[kNodeComponents] = {-1, -1, 0, 1, 0, 1, -1, -1, -1, 6, 7, 8, 6, 7, 8};
constexpr bool kAlongU[kNodeComponents] = {false, false, true, true, false, false, false, false,
                                           false, true,  true, true, false, false, false};

// The weights a, b, s of each plane (node-record order) in a CMSH mesh record unless stated
// (docs/formats.md, "CMSH"), in units of 1/256; b is unused for derivative planes. Fitted on
// whole photos: positions follow the parallelogram and the central difference; a colour is
// nearer the mean of its left and upper neighbours, and red and blue move with green.
constexpr int32_t kDefaultWeights[kNodeComponents][3] = {
    {256, -256, 0}, {256, -256, 0},                 // pos.x, pos.y
    {256, 0, 0},    {256, 0, 0},                    // posU.x, posU.y
    {256, 0, 0},    {256, 0, 0},                    // posV.x, posV.y
    {128, 0, 240},  {128, 0, 0},    {128, 0, 240},  // col.r, col.g, col.b
    {224, 0, 240},  {192, 0, 0},    {224, 0, 240},  // colU.r, colU.g, colU.b
    {224, 0, 240},  {192, 0, 0},    {224, 0, 240}}; // colV.r, colV.g, colV.b

bool isDerivative(int c) { return kValuePlane[c] >= 0; }

int128 floorDiv(int128 n, int128 d) {  // d > 0
    // Nearly always both fit in 64 bits, where division is far cheaper.
    constexpr int128 fast = int128(1) << 62;
    if (n < fast && n > -fast && d < fast) {
        const auto n64 = static_cast<int64_t>(n), d64 = static_cast<int64_t>(d);
        int64_t q = n64 / d64;
        if (n64 % d64 != 0 && n64 < 0) --q;
        return q;
    }
    int128 q = n / d;
    if (n % d != 0 && n < 0) --q;
    return q;
}

int64_t clampPrediction(int128 x) {
    if (x > kPredictionLimit) return kPredictionLimit;
    if (x < -kPredictionLimit) return -kPredictionLimit;
    return static_cast<int64_t>(x);
}

struct Weights {
    int32_t a = 0, b = 0, s = 0;
    bool operator==(const Weights& o) const { return a == o.a && b == o.b && s == o.s; }
};

Weights defaultWeights(int c) {
    Weights w;
    w.a = kDefaultWeights[c][0];
    w.b = kDefaultWeights[c][1];
    w.s = kDefaultWeights[c][2];
    return w;
}

// What the prediction of one node combines: p = base + round((a·f1 + b·f2 + s·f3) / 256).
struct Features {
    int64_t base = 0, f1 = 0, f2 = 0, f3 = 0;
};

int64_t predictFrom(const Features& f, const Weights& w) {
    const int128 sum = int128(w.a) * f.f1 + int128(w.b) * f.f2 + int128(w.s) * f.f3;
    // floor((sum + 128) / 256): GCC and Clang shift signed integers arithmetically.
    return clampPrediction(int128(f.base) + ((sum + kWeightOne / 2) >> kWeightShift));
}

// The features of one plane at any node, from what a decoder has at that point: this plane up
// to the node (row-major), whole earlier planes (values, sibling residuals).
class PlaneFeatures {
public:
    // `sibling`: the residuals of the sibling plane, if the plane has one.
    PlaneFeatures(const CodedGrid& g, int c, const int64_t* sibling)
        : g_(g), c_(c), stride_(static_cast<size_t>(g.columns) + 1), sibling_(sibling) {
        const size_t n = g.nodes();
        q_ = g.planes.data() + static_cast<size_t>(c) * n;
        if (isDerivative(c)) {
            value_ = g.planes.data() + static_cast<size_t>(kValuePlane[c]) * n;
            const Field f = fieldOfComponent(c), v = fieldOfComponent(kValuePlane[c]);
            shift_ = g.exponent[v] - g.exponent[f];
        }
    }

    Features at(int i, int j, size_t k) const {
        Features f;
        if (sibling_) f.f3 = sibling_[k];
        if (value_) {
            f.f1 = kAlongU[c_] ? centralDifference(g_.knotU, g_.spanU, i, g_.columns, k, 1)
                               : centralDifference(g_.knotV, g_.spanV, j, g_.rows, k, stride_);
        } else if (i > 0 && j > 0) {
            const int64_t left = q_[k - 1];
            f.base = left;
            f.f1 = q_[k - stride_] - left;
            f.f2 = q_[k - stride_ - 1] - left;
        } else if (i > 0) {
            f.base = q_[k - 1];
        } else if (j > 0) {
            f.base = q_[k - stride_];
        }
        return f;
    }

private:
    // The derivative the value plane implies at the node, in the derivative's quantisation
    // units: (V(t1) - V(t0)) / (k_t1 - k_t0) · span · 2^shift, rounded, halves up.
    int64_t centralDifference(const std::vector<int64_t>& knots, const std::vector<uint64_t>& spans,
                              int t, int last, size_t k, size_t step) const {
        const int t0 = std::max(t - 1, 0), t1 = std::min(t + 1, last);
        const int64_t v0 = value_[k - static_cast<size_t>(t - t0) * step];
        const int64_t v1 = value_[k + static_cast<size_t>(t1 - t) * step];
        int128 num = int128(v1 - v0) * int128(spans[static_cast<size_t>(t)]);
        int128 den = int128(knots[static_cast<size_t>(t1)] - knots[static_cast<size_t>(t0)]);
        if (shift_ >= 0)
            num *= int128(1) << shift_;
        else
            den *= int128(1) << -shift_;
        return clampPrediction(floorDiv(2 * num + den, 2 * den));
    }

    const CodedGrid& g_;
    int c_;
    size_t stride_;
    const int64_t* sibling_;
    const int64_t* q_ = nullptr;
    const int64_t* value_ = nullptr;
    int shift_ = 0;
};

uint64_t magnitude(int64_t e) {
    const uint64_t m = e < 0 ? 0 - static_cast<uint64_t>(e) : static_cast<uint64_t>(e);
    return std::min(m, kContextTermLimit);
}

// The coding context of a residual: how large the residuals around it were.
int contextOf(const int64_t* e, const int64_t* sibling, int i, int j, int columns, size_t k,
              size_t stride) {
    uint64_t m = 0;
    if (i > 0) m += 2 * magnitude(e[k - 1]);
    if (i > 1) m += magnitude(e[k - 2]);
    if (j > 0) {
        m += 2 * magnitude(e[k - stride]);
        if (i > 0) m += magnitude(e[k - stride - 1]);
        if (i < columns) m += magnitude(e[k - stride + 1]);
    }
    if (sibling) m += 3 * magnitude(sibling[k]);
    const int bits = m == 0 ? 0 : 64 - __builtin_clzll(m);
    return std::min(bits, kContexts - 1);
}

struct ResidualModels {
    BitModel zero[kContexts], sign[kContexts], length[kContexts][kLengthModels], top[64];
};

// A magnitude m >= 1, with n = (bit length of m) - 1: n decisions 1 and a decision 0 (left out
// when n = 63), the k-th with length[min(k, 23)]; if n >= 1, the bit below the leading 1 with
// top[n], then the n - 1 lower bits as direct bits. Residuals and stream integers alike.
void encodeMagnitude(RangeEncoder& enc, BitModel* length, BitModel* top, uint64_t mag) {
    const int n = 63 - __builtin_clzll(mag);
    for (int k = 0; k < n; ++k) enc.encode(length[std::min(k, kLengthModels - 1)], 1);
    if (n < 63) enc.encode(length[std::min(n, kLengthModels - 1)], 0);
    if (n >= 1) {
        enc.encode(top[n], static_cast<int>((mag >> (n - 1)) & 1));
        for (int k = n - 2; k >= 0; --k) enc.direct(static_cast<int>((mag >> k) & 1));
    }
}

uint64_t decodeMagnitude(RangeDecoder& dec, BitModel* length, BitModel* top) {
    int n = 0;
    while (n < 63 && dec.decode(length[std::min(n, kLengthModels - 1)])) ++n;
    uint64_t mag = uint64_t(1) << n;
    if (n >= 1) {
        mag |= static_cast<uint64_t>(dec.decode(top[n])) << (n - 1);
        for (int k = n - 2; k >= 0; --k) mag |= static_cast<uint64_t>(dec.direct()) << k;
    }
    return mag;
}

uint64_t absolute(int64_t e) {
    return e < 0 ? 0 - static_cast<uint64_t>(e) : static_cast<uint64_t>(e);
}

void encodeResidual(RangeEncoder& enc, ResidualModels& m, int x, int64_t e) {
    enc.encode(m.zero[x], e != 0);
    if (e == 0) return;
    enc.encode(m.sign[x], e < 0);
    encodeMagnitude(enc, m.length[x], m.top, absolute(e));
}

int128 decodeResidual(RangeDecoder& dec, ResidualModels& m, int x) {
    if (!dec.decode(m.zero[x])) return 0;
    const bool negative = dec.decode(m.sign[x]);
    const uint64_t mag = decodeMagnitude(dec, m.length[x], m.top);
    return negative ? -int128(mag) : int128(mag);
}

// The models of one kind of integer in a CMS2 stream: a residual's with a single context.
struct IntegerModels {
    BitModel zero, sign, length[kLengthModels], top[64];
};

// ---- Writer side: choosing the weights (any choice decodes; these are the cheapest we find).

// Solves the (at most 3x3) normal equations A w = b; false if singular.
bool solve(double (&A)[3][3], double (&b)[3], int m, double (&w)[3]) {
    for (int p = 0; p < m; ++p) {
        int best = p;
        for (int r = p + 1; r < m; ++r)
            if (std::fabs(A[r][p]) > std::fabs(A[best][p])) best = r;
        std::swap(A[p], A[best]);
        std::swap(b[p], b[best]);
        if (!(std::fabs(A[p][p]) > 1e-300)) return false;
        for (int r = 0; r < m; ++r) {
            if (r == p) continue;
            const double f = A[r][p] / A[p][p];
            for (int c = 0; c < m; ++c) A[r][c] -= f * A[p][c];
            b[r] -= f * b[p];
        }
    }
    for (int p = 0; p < m; ++p) w[p] = b[p] / A[p][p];
    return true;
}

// Fits the plane's weights by least squares, reweighted a few times towards least absolute
// residuals (the coder's cost grows like log |e|: outliers should not steer the fit). False when
// the fit is singular or out of range.
bool fitWeights(const std::vector<Features>& f, const int64_t* q, bool derivative, bool sibling,
                Weights& fit) {
    // Features used: derivative planes f1 (and f3), value planes f1, f2 (and f3).
    int used[3], m = 0;
    used[m++] = 1;
    if (!derivative) used[m++] = 2;
    if (sibling) used[m++] = 3;
    auto feature = [&](const Features& x, int which) {
        return static_cast<double>(which == 1 ? x.f1 : which == 2 ? x.f2 : x.f3);
    };
    double w[3] = {};
    for (int pass = 0; pass < 4; ++pass) {
        double A[3][3] = {}, b[3] = {};
        for (size_t k = 0; k < f.size(); ++k) {
            const double y = static_cast<double>(q[k] - f[k].base);
            double x[3];
            for (int a = 0; a < m; ++a) x[a] = feature(f[k], used[a]);
            double weight = 1;
            if (pass > 0) {
                double r = y;
                for (int a = 0; a < m; ++a) r -= w[a] * x[a];
                weight = 1 / (std::fabs(r) + 1);
            }
            for (int a = 0; a < m; ++a) {
                b[a] += weight * x[a] * y;
                for (int c = 0; c < m; ++c) A[a][c] += weight * x[a] * x[c];
            }
        }
        for (int a = 0; a < m; ++a) A[a][a] += 1e-9 * A[a][a] + 1e-9;
        if (!solve(A, b, m, w)) return false;
    }
    fit = Weights();
    for (int a = 0; a < m; ++a) {
        const double x = std::round(w[a] * kWeightOne);
        if (!(std::fabs(x) <= kMaxWeight)) return false;
        (used[a] == 1 ? fit.a : used[a] == 2 ? fit.b : fit.s) = static_cast<int32_t>(x);
    }
    return true;
}

// The bits a decision costs with model m, without coding it (then m learns it, as when coding).
double decisionBits(BitModel& m, int bit) {
    const double p = m.probability() / 65536.0;
    m.update(bit);
    return -std::log2(bit ? p : 1 - p);
}

// What encodeMagnitude takes, in bits (the models learn, as when coding).
double magnitudeBits(BitModel* length, BitModel* top, uint64_t mag) {
    const int n = 63 - __builtin_clzll(mag);
    double bits = 0;
    for (int k = 0; k < n; ++k) bits += decisionBits(length[std::min(k, kLengthModels - 1)], 1);
    if (n < 63) bits += decisionBits(length[std::min(n, kLengthModels - 1)], 0);
    if (n >= 1)  // the bit below the leading 1, then n - 1 direct bits
        bits += decisionBits(top[n], static_cast<int>((mag >> (n - 1)) & 1)) + (n - 1);
    return bits;
}

// What coding one plane's residuals `e` takes, in bits, exactly as encodeResidual codes them
// (the contexts of the plane and its sibling's residuals), from the models `start` on;
// `scratch` does the learning.
double planeBits(const CodedGrid& g, const int64_t* e, const int64_t* sibling,
                 const ResidualModels& start, ResidualModels& scratch) {
    scratch = start;
    const size_t stride = static_cast<size_t>(g.columns) + 1;
    double bits = 0;
    for (int j = 0; j <= g.rows; ++j)
        for (int i = 0; i <= g.columns; ++i) {
            const size_t k = static_cast<size_t>(j) * stride + static_cast<size_t>(i);
            const int x = contextOf(e, sibling, i, j, g.columns, k, stride);
            const int64_t r = e[k];
            bits += decisionBits(scratch.zero[x], r != 0);
            if (r == 0) continue;
            bits += decisionBits(scratch.sign[x], r < 0);
            bits += magnitudeBits(scratch.length[x], scratch.top, absolute(r));
        }
    return bits;
}

// What a signed stream integer takes with models `m`, in bits (m learns it).
double signedBits(IntegerModels& m, int64_t x) {
    double bits = decisionBits(m.zero, x != 0);
    if (x == 0) return bits;
    bits += decisionBits(m.sign, x < 0);
    return bits + magnitudeBits(m.length, m.top, absolute(x));
}

// CMS3 (docs/formats.md, "CMS3"): the residual models each plane (node-record component) codes
// with, named by the first component that uses them; 7 sets in all.
constexpr int kCms3Models[kNodeComponents] = {0, 1, 2, 2, 2, 2, 6, 7, 6, 9, 10, 9, 9, 10, 9};

// The priors of CMS3's residual models, per set, in units of 2^-12 (a model starts with A = B =
// 16 times its prior and c = kPriorCount): `zero[x]` for the decision r != 0 in context x, and
// `length[d]` for the length decisions length[x][k], with d = min(max(x - k, 0), 9). Measured on
// the bench's images converted whole at levels 0 to 6 and at budgets from 4 patches a region to
// the defaults (38 files, each weighted alike): the rate of each decision, made monotone.
struct ResidualPrior {
    uint16_t zero[kContexts];
    uint16_t length[10];
};
constexpr int kPriorCount = 4;
constexpr struct {
    int model;  // the first component of the set (kCms3Models)
    ResidualPrior prior;
} kCms3Priors[7] = {
    {0,  // pos.x
     {{2884, 1640, 2116, 2487, 3169, 3578, 3713, 3740, 3858, 3925, 3925, 3925, 4020, 4020, 4020, 4020},
      {3292, 1509, 1627, 1961, 2525, 3097, 3434, 3599, 3812, 3947}}},
    {1,  // pos.y
     {{2155, 1451, 1770, 1958, 2597, 3363, 3543, 3677, 3762, 3762, 3762, 3762, 3762, 3762, 3762, 3762},
      {2904, 1912, 1912, 1912, 2236, 2843, 3326, 3595, 3788, 3891}}},
    {2,  // posU.x, posU.y, posV.x, posV.y
     {{776, 1010, 1724, 2355, 3044, 3450, 3635, 3766, 3919, 4000, 4000, 4000, 4000, 4000, 4000, 4000},
      {2024, 1191, 1285, 1721, 2401, 3066, 3489, 3754, 3908, 3941}}},
    {6,  // col.r, col.b
     {{85, 535, 710, 1806, 2299, 2965, 3380, 3416, 3416, 3416, 3416, 3416, 3416, 3416, 3416, 3416},
      {1197, 601, 735, 807, 1407, 2310, 2836, 3439, 3789, 3893}}},
    {7,  // col.g
     {{1852, 1664, 2765, 2873, 3321, 3524, 3736, 3802, 3982, 3982, 3982, 3982, 3982, 3982, 3982, 3982},
      {2665, 1319, 1353, 1775, 2541, 3163, 3532, 3775, 3905, 3993}}},
    {9,  // colU.r, colU.b, colV.r, colV.b
     {{191, 593, 894, 1621, 2223, 2660, 2910, 3120, 3296, 3521, 3521, 3521, 3521, 3521, 3521, 3521},
      {379, 333, 418, 655, 1361, 2176, 2992, 3542, 3799, 3941}}},
    {10,  // colU.g, colV.g
     {{1054, 1290, 1948, 2456, 3056, 3450, 3718, 3882, 3882, 3959, 4036, 4036, 4036, 4036, 4036, 4036},
      {1525, 1057, 1299, 1744, 2395, 3052, 3480, 3780, 3912, 4046}}},
};

void startFrom(BitModel& m, uint16_t prior) {
    m.fast = m.slow = static_cast<uint16_t>(prior * 16);
    m.seen = kPriorCount;
}

}  // namespace

// All the models of a CMS2 or CMS3 stream (docs/formats.md, "CMS2", "CMS3"): set at the start of
// a section, shared by its meshes.
struct StreamModels {
    IntegerModels fields[kStreamFields];
    BitModel weighted[kNodeComponents];      // by position in the coding order
    ResidualModels planes[kNodeComponents];  // CMS2: by component; CMS3: the sets of kCms3Models
    int modelOf[kNodeComponents];            // the set of planes[] a component codes with

    explicit StreamModels(StreamKind kind) {
        for (int c = 0; c < kNodeComponents; ++c)
            modelOf[c] = kind == StreamKind::Cms3 ? kCms3Models[c] : c;
        if (kind != StreamKind::Cms3) return;
        for (const auto& set : kCms3Priors) {
            ResidualModels& m = planes[set.model];
            for (int x = 0; x < kContexts; ++x) {
                startFrom(m.zero[x], set.prior.zero[x]);
                for (int k = 0; k < kLengthModels; ++k)
                    startFrom(m.length[x][k], set.prior.length[std::min(std::max(x - k, 0), 9)]);
            }
        }
    }
    ResidualModels& plane(int c) { return planes[modelOf[c]]; }
    const ResidualModels& plane(int c) const { return planes[modelOf[c]]; }
};

namespace {

// The weights of the planes of a CMS2 or CMS3 mesh (the defaults, or fitted weights where they
// save more than they cost to state, estimated with the stream's models as they are when the
// mesh begins) and the residuals they leave, plane by plane in node-record component order.
void chooseWeights(const CodedGrid& g, const StreamModels& models,
                   Weights (&weights)[kNodeComponents], uint64_t& mask,
                   std::vector<int64_t>& residuals) {
    const size_t n = g.nodes(), stride = static_cast<size_t>(g.columns) + 1;
    const int F = g.components;
    residuals.assign(static_cast<size_t>(F) * n, 0);
    std::vector<int64_t> trial(n);
    std::vector<Features> features(n);
    auto scratch = std::make_unique<ResidualModels>();
    IntegerModels deltas = models.fields[static_cast<int>(StreamField::WeightDelta)];
    mask = 0;
    for (int o = 0; o < F; ++o) {
        const int c = kCodingOrder[o];
        const int64_t* sibling =
            kSibling[c] >= 0 ? &residuals[static_cast<size_t>(kSibling[c]) * n] : nullptr;
        const PlaneFeatures plane(g, c, sibling);
        for (int j = 0; j <= g.rows; ++j)
            for (int i = 0; i <= g.columns; ++i) {
                const size_t k = static_cast<size_t>(j) * stride + static_cast<size_t>(i);
                features[k] = plane.at(i, j, k);
            }
        const int64_t* q = &g.planes[static_cast<size_t>(c) * n];
        int64_t* e = &residuals[static_cast<size_t>(c) * n];
        const Weights defaults = defaultWeights(c);
        weights[c] = defaults;
        for (size_t k = 0; k < n; ++k) e[k] = q[k] - predictFrom(features[k], defaults);
        Weights fit;
        if (!fitWeights(features, q, isDerivative(c), kSibling[c] >= 0, fit) || fit == defaults)
            continue;
        for (size_t k = 0; k < n; ++k) trial[k] = q[k] - predictFrom(features[k], fit);
        const double saved = planeBits(g, e, sibling, models.plane(c), *scratch) -
                             planeBits(g, trial.data(), sibling, models.plane(c), *scratch);
        BitModel yes = models.weighted[o], no = models.weighted[o];
        IntegerModels stated = deltas;
        double cost = decisionBits(yes, 1) - decisionBits(no, 0);
        cost += signedBits(stated, int64_t(fit.a) - defaults.a);
        if (!isDerivative(c)) cost += signedBits(stated, int64_t(fit.b) - defaults.b);
        cost += signedBits(stated, int64_t(fit.s) - defaults.s);
        if (saved > cost) {
            weights[c] = fit;
            mask |= uint64_t(1) << o;
            deltas = stated;
            std::copy(trial.begin(), trial.end(), e);
        }
    }
}

// The residuals of the planes, in coding order, with the stream's models.
void encodePlanes(RangeEncoder& enc, const CodedGrid& g, const std::vector<int64_t>& residuals,
                  StreamModels& models) {
    const size_t n = g.nodes(), stride = static_cast<size_t>(g.columns) + 1;
    for (int o = 0; o < g.components; ++o) {
        const int c = kCodingOrder[o];
        const int64_t* e = &residuals[static_cast<size_t>(c) * n];
        const int64_t* sibling =
            kSibling[c] >= 0 ? &residuals[static_cast<size_t>(kSibling[c]) * n] : nullptr;
        for (int j = 0; j <= g.rows; ++j)
            for (int i = 0; i <= g.columns; ++i) {
                const size_t k = static_cast<size_t>(j) * stride + static_cast<size_t>(i);
                encodeResidual(enc, models.plane(c),
                               contextOf(e, sibling, i, j, g.columns, k, stride), e[k]);
            }
    }
}

// Fills g.planes from the residuals in `dec`, predicted with `weights`. `models`: the stream's
// models, which persist (CMS2, CMS3), or null for fresh models in every plane (NODE and CMSH).
void decodePlanes(RangeDecoder& dec, ByteReader& r, CodedGrid& g,
                  const Weights (&weights)[kNodeComponents], StreamModels* models) {
    const size_t n = g.nodes(), stride = static_cast<size_t>(g.columns) + 1;
    const int F = g.components;
    g.planes.assign(static_cast<size_t>(F) * n, 0);
    // Residuals are kept for the plane being decoded and for the head of its group (the
    // sibling of the others): each sibling is the first plane of a run in the coding order.
    std::vector<int64_t> head(n), current(n);
    std::unique_ptr<ResidualModels> fresh;
    if (!models) fresh = std::make_unique<ResidualModels>();
    for (int o = 0; o < F; ++o) {
        const int c = kCodingOrder[o];
        ResidualModels& m = models ? models->plane(c) : *fresh;
        if (!models) m = ResidualModels();
        const int64_t* sibling = kSibling[c] >= 0 ? head.data() : nullptr;
        const PlaneFeatures plane(g, c, sibling);
        int64_t* q = &g.planes[static_cast<size_t>(c) * n];
        int64_t* e = kSibling[c] >= 0 ? current.data() : head.data();
        for (int j = 0; j <= g.rows; ++j)
            for (int i = 0; i <= g.columns; ++i) {
                const size_t k = static_cast<size_t>(j) * stride + static_cast<size_t>(i);
                const int128 residual =
                    decodeResidual(dec, m, contextOf(e, sibling, i, j, g.columns, k, stride));
                const int64_t p = predictFrom(plane.at(i, j, k), weights[c]);
                const int128 value = int128(p) + residual;
                if (value > kMaxQuantized || value < -kMaxQuantized)
                    r.fail("quantised value out of range");
                q[k] = static_cast<int64_t>(value);
                e[k] = static_cast<int64_t>(residual);  // |e| <= |q| + |p| < 2^63
            }
    }
}

}  // namespace

std::vector<uint64_t> localSpans(const std::vector<int64_t>& knots) {
    const size_t n = knots.size();
    std::vector<uint64_t> spans(n);
    for (size_t i = 0; i < n; ++i) {
        uint64_t d = 0;
        if (i > 0) d = std::max(d, static_cast<uint64_t>(knots[i] - knots[i - 1]));
        if (i + 1 < n) d = std::max(d, static_cast<uint64_t>(knots[i + 1] - knots[i]));
        spans[i] = d + 2;
    }
    return spans;
}

std::string codedExponentProblem(const int (&e)[kFieldCount]) {
    for (Field f : {kPosU, kPosV, kColU, kColV}) {
        const Field value = (f == kPosU || f == kPosV) ? kPos : kCol;
        if (std::abs(e[f] - e[kKnot]) > kMaxExponent || std::abs(e[f] - e[value]) > kMaxShift)
            return "derivative quantisation exponent " + std::to_string(e[f]) +
                   " out of range (knot exponent " + std::to_string(e[kKnot]) +
                   ", value exponent " + std::to_string(e[value]) + ")";
    }
    return {};
}


void decodeCodedNodes(ByteReader& r, CodedGrid& g, WeightLayout layout) {
    const int F = g.components;
    Weights weights[kNodeComponents];
    uint64_t mask = (uint64_t(1) << F) - 1;  // NODE: every plane states its weights
    if (layout == WeightLayout::Masked) {
        mask = r.varint();
        if (mask >> F)
            r.fail("weights mask " + std::to_string(mask) + " names planes beyond the " +
                   std::to_string(F) + " of this mesh");
    }
    for (int o = 0; o < F; ++o) {
        const int c = kCodingOrder[o];
        Weights& w = weights[c];
        const Weights d = layout == WeightLayout::Masked ? defaultWeights(c) : Weights();
        w = d;
        if (!(mask >> o & 1)) continue;
        for (int32_t* x : {&w.a, &w.b, &w.s}) {
            if (x == &w.b && isDerivative(c)) continue;
            // Differences from the defaults are read in 64 bits: a wild one fails the range check.
            const int64_t v = static_cast<int64_t>(static_cast<uint64_t>(r.svarint()) +
                                                   static_cast<uint64_t>(int64_t(*x)));
            if (v > kMaxWeight || v < -kMaxWeight)
                r.fail("plane weight " + std::to_string(v) + " out of range");
            *x = static_cast<int32_t>(v);
        }
    }
    RangeDecoder dec(r);
    decodePlanes(dec, r, g, weights, nullptr);
}

// ---- CMS2 and CMS3 streams.

CompactStreamWriter::CompactStreamWriter(StreamKind kind)
    : models_(std::make_unique<StreamModels>(kind)), enc_(std::make_unique<RangeEncoder>()) {}
CompactStreamWriter::~CompactStreamWriter() = default;

void CompactStreamWriter::putUnsigned(StreamField f, uint64_t x) {
    IntegerModels& m = models_->fields[static_cast<int>(f)];
    enc_->encode(m.zero, x != 0);
    if (x != 0) encodeMagnitude(*enc_, m.length, m.top, x);
}

void CompactStreamWriter::putSigned(StreamField f, int64_t x) {
    IntegerModels& m = models_->fields[static_cast<int>(f)];
    enc_->encode(m.zero, x != 0);
    if (x == 0) return;
    enc_->encode(m.sign, x < 0);
    encodeMagnitude(*enc_, m.length, m.top, absolute(x));
}

void CompactStreamWriter::putNodes(const CodedGrid& g) {
    Weights weights[kNodeComponents];
    uint64_t mask = 0;
    std::vector<int64_t> residuals;
    chooseWeights(g, *models_, weights, mask, residuals);
    for (int o = 0; o < g.components; ++o) {
        const bool stated = mask >> o & 1;
        enc_->encode(models_->weighted[o], stated);
        if (!stated) continue;
        const int c = kCodingOrder[o];
        const Weights d = defaultWeights(c);
        putSigned(StreamField::WeightDelta, int64_t(weights[c].a) - d.a);
        if (!isDerivative(c)) putSigned(StreamField::WeightDelta, int64_t(weights[c].b) - d.b);
        putSigned(StreamField::WeightDelta, int64_t(weights[c].s) - d.s);
    }
    encodePlanes(*enc_, g, residuals, *models_);
}

std::string CompactStreamWriter::finish() { return enc_->finish(); }

CompactStreamReader::CompactStreamReader(ByteReader& reader, StreamKind kind)
    : r_(reader),
      models_(std::make_unique<StreamModels>(kind)),
      dec_(std::make_unique<RangeDecoder>(reader)) {}
CompactStreamReader::~CompactStreamReader() = default;

uint64_t CompactStreamReader::getUnsigned(StreamField f) {
    IntegerModels& m = models_->fields[static_cast<int>(f)];
    if (!dec_->decode(m.zero)) return 0;
    return decodeMagnitude(*dec_, m.length, m.top);
}

int64_t CompactStreamReader::getSigned(StreamField f) {
    IntegerModels& m = models_->fields[static_cast<int>(f)];
    if (!dec_->decode(m.zero)) return 0;
    const bool negative = dec_->decode(m.sign);
    const uint64_t mag = decodeMagnitude(*dec_, m.length, m.top);
    if (mag > static_cast<uint64_t>(INT64_MAX)) r_.fail("coded integer out of range");
    return negative ? -static_cast<int64_t>(mag) : static_cast<int64_t>(mag);
}

void CompactStreamReader::getNodes(CodedGrid& g) {
    Weights weights[kNodeComponents];
    for (int o = 0; o < g.components; ++o) {
        const int c = kCodingOrder[o];
        Weights& w = weights[c];
        w = defaultWeights(c);
        if (!dec_->decode(models_->weighted[o])) continue;
        for (int32_t* x : {&w.a, &w.b, &w.s}) {
            if (x == &w.b && isDerivative(c)) continue;
            const int128 v = int128(getSigned(StreamField::WeightDelta)) + *x;
            if (v > kMaxWeight || v < -kMaxWeight)
                r_.fail("plane weight " + std::to_string(static_cast<long long>(
                                              v > INT64_MAX ? INT64_MAX : (v < INT64_MIN ? INT64_MIN : v))) +
                        " out of range");
            *x = static_cast<int32_t>(v);
        }
    }
    decodePlanes(*dec_, r_, g, weights, models_.get());
}

}  // namespace gm::gmb
