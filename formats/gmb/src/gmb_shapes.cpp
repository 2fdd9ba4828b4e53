// The SHAP section (gmb_shapes.h).
#include "gmb_shapes.h"

#include <cmath>
#include <cstdio>

#include "meshcore/validate.h"

namespace gm::gmb {

namespace {

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
    return true;
}

bool anyStroked(const std::vector<FlatShape>& shapes) {
    for (const FlatShape& s : shapes)
        if (s.stroked()) return true;
    return false;
}

ShapeEncoding encodingFor(bool quantize, bool strokes) {
    if (quantize) return strokes ? ShapeEncoding::QuantizedWithStrokes : ShapeEncoding::Quantized;
    return strokes ? ShapeEncoding::Float64WithStrokes : ShapeEncoding::Float64;
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

// A shape's subpaths: per subpath its segment count n, then 3n points (filled) or 3n + 1
// (a stroke's centreline).
void readSubpaths(ByteReader& r, FlatShape& s, PointState& points,
                  const std::function<void(ByteReader&, uint64_t)>& charge) {
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
    const bool strokes = anyStroked(shapes);
    ByteWriter w;
    w.varint(shapes.size());
    w.u8(static_cast<uint8_t>(encodingFor(quantize, strokes)));
    PointState points;
    points.quantized = quantize;
    for (const FlatShape& s : shapes) {
        w.varint(s.layer);
        for (double c : {s.col.r, s.col.g, s.col.b, s.alpha}) {
            if (quantize)
                w.u16(
                    static_cast<uint16_t>(std::lround(std::fmin(1.0, std::fmax(0.0, c)) * 65535)));
            else
                w.f64(c);
        }
        if (strokes && quantize) w.varint(quantizedWidth(s));
        if (strokes && !quantize) w.f64(s.stroked() ? s.strokeWidth : 0.0);
        w.varint(s.subpaths.size());
        for (const std::vector<Vec2>& path : s.subpaths) {
            w.varint(path.size() / 3);  // segments: 3n points filled, 3n + 1 stroked
            for (const Vec2& p : path) writePoint(w, p, points);
        }
    }
    return std::move(w.str());
}

std::vector<FlatShape> decodeShapes(ByteReader& r, uint64_t maxShapes,
                                    const std::function<void(ByteReader&, uint64_t)>& charge) {
    const uint64_t count = r.varint();
    if (count == 0 || count > maxShapes)
        r.fail(std::to_string(count) + " shapes: must be 1 to " + std::to_string(maxShapes));
    const uint8_t encoding = r.u8();
    if (encoding > static_cast<uint8_t>(ShapeEncoding::QuantizedWithStrokes))
        r.fail("unknown shape encoding " + std::to_string(encoding));
    PointState points;
    points.quantized = encoding == static_cast<uint8_t>(ShapeEncoding::Quantized) ||
                       encoding == static_cast<uint8_t>(ShapeEncoding::QuantizedWithStrokes);
    const bool quantized = points.quantized;
    const bool widths = encoding >= static_cast<uint8_t>(ShapeEncoding::Float64WithStrokes);
    // The least bytes a shape takes: layer, colour, width, a subpath count and one segment's
    // count and points.
    const uint64_t widthBytes = widths ? (quantized ? 1 : 8) : 0;
    const uint64_t leastShape = (quantized ? 1 + 8 + 1 + 1 + 6 : 1 + 32 + 1 + 1 + 48) + widthBytes;
    r.need(satMul(count, leastShape), std::to_string(count) + " shapes");
    std::vector<FlatShape> shapes(static_cast<size_t>(count));
    for (FlatShape& s : shapes) {
        s.layer = static_cast<size_t>(r.varint());
        for (double* c : {&s.col.r, &s.col.g, &s.col.b, &s.alpha})
            *c = quantized ? r.u16() / 65535.0 : r.f64();
        if (widths) s.strokeWidth = readWidth(r, quantized);
        readSubpaths(r, s, points, charge);
    }
    return shapes;
}

}  // namespace gm::gmb
