// The SHAP section (gmb_shapes.h).
#include "gmb_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "meshcore/validate.h"

namespace gm::gmb {

namespace {

using Charge = std::function<void(ByteReader&, uint64_t)>;

constexpr double kPointScale = double(1 << kShapePointBits);
// The widest stroke in 1/256 px.
constexpr uint64_t kMaxQuantizedWidth = uint64_t(kMaxStrokeWidth * kPointScale);

// Whether every point lies on the quantized grid's range, so that it and the deltas between
// points fit in 64 bits; a document that strays beyond is written in float64 instead.
bool quantizable(const std::vector<FlatShape>& shapes) {
    const double limit = double(kMaxQuantized) / kPointScale;
    for (const FlatShape& s : shapes)
        for (const std::vector<Vec2>& path : s.subpaths)
            for (const Vec2& p : path)
                if (!(std::fabs(p.x) <= limit && std::fabs(p.y) <= limit)) return false;
    for (const FlatShape& s : shapes) {
        if (!s.graded()) continue;
        for (const Vec2& p : {s.gradient.from, s.gradient.to})
            if (!(std::fabs(p.x) <= limit && std::fabs(p.y) <= limit)) return false;
    }
    return true;
}

bool anyStroked(const std::vector<FlatShape>& shapes) {
    for (const FlatShape& s : shapes)
        if (s.stroked()) return true;
    return false;
}

bool anyGraded(const std::vector<FlatShape>& shapes) {
    for (const FlatShape& s : shapes)
        if (s.graded()) return true;
    return false;
}

uint8_t encodingFor(bool quantize, bool strokes, bool gradients) {
    return (quantize ? kShapeQuantizedBit : 0) | (strokes ? kShapeStrokesBit : 0) |
           (gradients ? kShapeGradientsBit : 0);
}

// A colour channel, opacity or gradient offset in 1/65535.
uint16_t unit16(double c) {
    return static_cast<uint16_t>(std::lround(std::fmin(1.0, std::fmax(0.0, c)) * 65535));
}

// A stroke's width to 1/256 px; a stroked shape stays stroked, however thin.
uint64_t quantizedWidth(const FlatShape& s) {
    if (!s.stroked()) return 0;
    const double q = std::round(std::fmin(s.strokeWidth, kMaxStrokeWidth) * kPointScale);
    return q < 1 ? 1 : static_cast<uint64_t>(q);
}

// Points are deltas along the whole payload in the quantized encodings.
struct PointState {
    bool quantized = false;
    int64_t x = 0, y = 0;
};

void writePoint(ByteWriter& w, Vec2 p, PointState& state) {
    if (!state.quantized) {
        w.f64(p.x);
        w.f64(p.y);
        return;
    }
    const int64_t x = std::llround(p.x * kPointScale), y = std::llround(p.y * kPointScale);
    w.svarint(x - state.x);
    w.svarint(y - state.y);
    state.x = x, state.y = y;
}

Vec2 readPoint(ByteReader& r, PointState& state) {
    if (!state.quantized) {
        const double x = r.f64();
        return {x, r.f64()};
    }
    // Deltas between in-range points stay within twice the range; checking them first keeps
    // the sums from overflowing.
    const int64_t dx = r.svarint(), dy = r.svarint();
    if (dx > 2 * kMaxQuantized || dx < -2 * kMaxQuantized || dy > 2 * kMaxQuantized ||
        dy < -2 * kMaxQuantized)
        r.fail("shape point out of range");
    state.x += dx;
    state.y += dy;
    if (state.x > kMaxQuantized || state.x < -kMaxQuantized || state.y > kMaxQuantized ||
        state.y < -kMaxQuantized)
        r.fail("shape point out of range");
    return {double(state.x) / kPointScale, double(state.y) / kPointScale};
}

double readWidth(ByteReader& r, bool quantized) {
    if (quantized) {
        const uint64_t q = r.varint();
        if (q > kMaxQuantizedWidth)
            r.fail("stroke width " + std::to_string(q) + "/256 px beyond 10000 px");
        return double(q) / kPointScale;
    }
    const double width = r.f64();
    if (!(width >= 0 && width <= kMaxStrokeWidth)) {
        char text[32];
        std::snprintf(text, sizeof text, "%g", width);
        r.fail(std::string("stroke width ") + text + " outside 0-10000 px");
    }
    return width;
}

// A gradient's ends on the 1/256 px grid: each rounded to the nearest point or, where that
// would bring them within kMinGradientLength of each other, each coordinate rounded away from
// the other end's, which never shortens the axis along either coordinate.
std::pair<Vec2, Vec2> quantizedEnds(const LinearGradient& g) {
    auto nearest = [](double x) { return std::round(x * kPointScale) / kPointScale; };
    const Vec2 from{nearest(g.from.x), nearest(g.from.y)}, to{nearest(g.to.x), nearest(g.to.y)};
    if (norm(to - from) > kMinGradientLength) return {from, to};
    auto away = [](double x, double other) {
        return (x < other ? std::floor(x * kPointScale) : std::ceil(x * kPointScale)) / kPointScale;
    };
    return {{away(g.from.x, g.to.x), away(g.from.y, g.to.y)},
            {away(g.to.x, g.from.x), away(g.to.y, g.from.y)}};
}

// A gradient's offsets in 1/65535, the first 0 and the last 65535; offsets closer than a step
// are moved apart (up from the first, then down from the last) so that they stay strictly
// increasing.
std::vector<uint16_t> quantizedOffsets(const LinearGradient& g) {
    const size_t n = g.stops.size();
    std::vector<int> q(n);
    for (size_t k = 1; k + 1 < n; ++k)
        q[k] = std::max<int>(unit16(g.stops[k].offset), q[k - 1] + 1);
    q.back() = 65535;
    for (size_t k = n - 1; k-- > 1;) q[k] = std::min(q[k], q[k + 1] - 1);
    return std::vector<uint16_t>(q.begin(), q.end());
}

// A shape's gradient field: its stop count (0: painted in its colour), then the two ends as
// points and each stop's offset and colour.
void writeGradient(ByteWriter& w, const LinearGradient& g, PointState& points) {
    w.varint(g.stops.size());
    if (g.stops.empty()) return;
    if (!points.quantized) {
        writePoint(w, g.from, points);
        writePoint(w, g.to, points);
        for (const GradientStop& stop : g.stops)
            for (double v : {stop.offset, stop.col.r, stop.col.g, stop.col.b}) w.f64(v);
        return;
    }
    const auto [from, to] = quantizedEnds(g);
    writePoint(w, from, points);
    writePoint(w, to, points);
    const std::vector<uint16_t> offsets = quantizedOffsets(g);
    for (size_t k = 0; k < offsets.size(); ++k) {
        w.u16(offsets[k]);
        for (int c = 0; c < 3; ++c) w.u16(unit16(g.stops[k].col[c]));
    }
}

// Reads shape `index`'s gradient field; the stop count is checked before anything is sized,
// the gradient by gradientProblem once read.
void readGradient(ByteReader& r, FlatShape& s, size_t index, PointState& points,
                  const Charge& charge) {
    auto fail = [&](const std::string& what) {
        r.fail("shape " + std::to_string(index) + ": " + what);
    };
    const uint64_t count = r.varint();
    if (count == 0) return;
    if (count < 2 || count > kMaxGradientStops)
        fail(std::to_string(count) + " gradient stops: must be 0 or 2 to " +
             std::to_string(kMaxGradientStops));
    if (s.stroked()) fail("a stroke painted with a gradient");
    const uint64_t pointBytes = points.quantized ? 2 : 16, stopBytes = points.quantized ? 8 : 32;
    r.need(2 * pointBytes + count * stopBytes, std::to_string(count) + " gradient stops");
    charge(r, 2 * sizeof(Vec2) + count * sizeof(GradientStop));
    LinearGradient& g = s.gradient;
    g.from = readPoint(r, points);
    g.to = readPoint(r, points);
    g.stops.resize(static_cast<size_t>(count));
    for (GradientStop& stop : g.stops)
        for (double* v : {&stop.offset, &stop.col.r, &stop.col.g, &stop.col.b})
            *v = points.quantized ? r.u16() / 65535.0 : r.f64();
    if (const std::string e = gradientProblem(g); !e.empty()) fail("gradient: " + e);
}

// A shape's subpaths: per subpath its segment count n, then 3n points (filled) or 3n + 1
// (a stroke's centreline).
void readSubpaths(ByteReader& r, FlatShape& s, PointState& points, const Charge& charge) {
    const uint64_t pointBytes = points.quantized ? 2 : 16;  // at least, per point
    const uint64_t extra = s.stroked() ? 1 : 0;
    const uint64_t subpaths = r.varint();
    if (subpaths == 0) r.fail("a shape without subpaths");
    r.need(satMul(subpaths, 1 + (3 + extra) * pointBytes), std::to_string(subpaths) + " subpaths");
    s.subpaths.resize(static_cast<size_t>(subpaths));
    for (std::vector<Vec2>& path : s.subpaths) {
        const uint64_t segments = r.varint();
        if (segments == 0)
            r.fail(s.stroked() ? "a stroke's centreline without segments"
                               : "a subpath without segments");
        const uint64_t n = satAdd(satMul(segments, 3), extra);
        r.need(satMul(n, pointBytes), std::to_string(segments) + " segments");
        charge(r, satMul(n, sizeof(Vec2)));
        path.resize(static_cast<size_t>(n));
        for (Vec2& p : path) p = readPoint(r, points);
    }
}

}  // namespace

std::string encodeShapes(const std::vector<FlatShape>& shapes, bool quantize) {
    quantize = quantize && quantizable(shapes);
    const bool strokes = anyStroked(shapes), gradients = anyGraded(shapes);
    ByteWriter w;
    w.varint(shapes.size());
    w.u8(encodingFor(quantize, strokes, gradients));
    PointState points;
    points.quantized = quantize;
    for (const FlatShape& s : shapes) {
        w.varint(s.layer);
        for (double c : {s.col.r, s.col.g, s.col.b, s.alpha}) {
            if (quantize)
                w.u16(unit16(c));
            else
                w.f64(c);
        }
        if (strokes && quantize) w.varint(quantizedWidth(s));
        if (strokes && !quantize) w.f64(s.stroked() ? s.strokeWidth : 0.0);
        if (gradients) writeGradient(w, s.gradient, points);
        w.varint(s.subpaths.size());
        for (const std::vector<Vec2>& path : s.subpaths) {
            w.varint(path.size() / 3);  // segments: 3n points filled, 3n + 1 stroked
            for (const Vec2& p : path) writePoint(w, p, points);
        }
    }
    return std::move(w.str());
}

std::vector<FlatShape> decodeShapes(ByteReader& r, uint64_t maxShapes, const Charge& charge) {
    const uint64_t count = r.varint();
    if (count == 0 || count > maxShapes)
        r.fail(std::to_string(count) + " shapes: must be 1 to " + std::to_string(maxShapes));
    const uint8_t encoding = r.u8();
    if (encoding > static_cast<uint8_t>(ShapeEncoding::QuantizedWithStrokesAndGradients))
        r.fail("unknown shape encoding " + std::to_string(encoding));
    PointState points;
    points.quantized = (encoding & kShapeQuantizedBit) != 0;
    const bool quantized = points.quantized;
    const bool widths = (encoding & kShapeStrokesBit) != 0;
    const bool gradients = (encoding & kShapeGradientsBit) != 0;
    // The least bytes a shape takes: layer, colour, width, stop count, a subpath count and one
    // segment's count and points.
    const uint64_t widthBytes = widths ? (quantized ? 1 : 8) : 0;
    const uint64_t leastShape =
        (quantized ? 1 + 8 + 1 + 1 + 6 : 1 + 32 + 1 + 1 + 48) + widthBytes + (gradients ? 1 : 0);
    r.need(satMul(count, leastShape), std::to_string(count) + " shapes");
    std::vector<FlatShape> shapes(static_cast<size_t>(count));
    for (size_t k = 0; k < shapes.size(); ++k) {
        FlatShape& s = shapes[k];
        s.layer = static_cast<size_t>(r.varint());
        for (double* c : {&s.col.r, &s.col.g, &s.col.b, &s.alpha})
            *c = quantized ? r.u16() / 65535.0 : r.f64();
        if (widths) s.strokeWidth = readWidth(r, quantized);
        if (gradients) readGradient(r, s, k, points, charge);
        readSubpaths(r, s, points, charge);
    }
    return shapes;
}

}  // namespace gm::gmb
