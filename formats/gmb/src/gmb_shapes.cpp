// The SHAP section (gmb_shapes.h).
#include "gmb_shapes.h"

#include <cmath>

namespace gm::gmb {

namespace {

constexpr double kPointScale = double(1 << kShapePointBits);

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

}  // namespace

std::string encodeShapes(const std::vector<FlatShape>& shapes, bool quantize) {
    quantize = quantize && quantizable(shapes);
    ByteWriter w;
    w.varint(shapes.size());
    w.u8(static_cast<uint8_t>(quantize ? ShapeEncoding::Quantized : ShapeEncoding::Float64));
    int64_t lastX = 0, lastY = 0;  // quantized: points are deltas along the whole payload
    for (const FlatShape& s : shapes) {
        w.varint(s.layer);
        for (double c : {s.col.r, s.col.g, s.col.b, s.alpha}) {
            if (quantize)
                w.u16(
                    static_cast<uint16_t>(std::lround(std::fmin(1.0, std::fmax(0.0, c)) * 65535)));
            else
                w.f64(c);
        }
        w.varint(s.subpaths.size());
        for (const std::vector<Vec2>& path : s.subpaths) {
            w.varint(path.size() / 3);
            for (const Vec2& p : path) {
                if (!quantize) {
                    w.f64(p.x);
                    w.f64(p.y);
                    continue;
                }
                const int64_t x = std::llround(p.x * kPointScale),
                              y = std::llround(p.y * kPointScale);
                w.svarint(x - lastX);
                w.svarint(y - lastY);
                lastX = x, lastY = y;
            }
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
    if (encoding > static_cast<uint8_t>(ShapeEncoding::Quantized))
        r.fail("unknown shape encoding " + std::to_string(encoding));
    const bool quantized = encoding == static_cast<uint8_t>(ShapeEncoding::Quantized);
    // The least bytes a shape takes: layer, colour, a subpath count and one segment's count
    // and points.
    const uint64_t leastShape = quantized ? 1 + 8 + 1 + 1 + 6 : 1 + 32 + 1 + 1 + 48;
    r.need(satMul(count, leastShape), std::to_string(count) + " shapes");
    const uint64_t pointBytes = quantized ? 2 : 16;  // at least, per point
    std::vector<FlatShape> shapes(static_cast<size_t>(count));
    int64_t x = 0, y = 0;
    for (FlatShape& s : shapes) {
        s.layer = static_cast<size_t>(r.varint());
        for (double* c : {&s.col.r, &s.col.g, &s.col.b, &s.alpha})
            *c = quantized ? r.u16() / 65535.0 : r.f64();
        const uint64_t subpaths = r.varint();
        if (subpaths == 0) r.fail("a shape without subpaths");
        r.need(satMul(subpaths, 1 + 3 * pointBytes), std::to_string(subpaths) + " subpaths");
        s.subpaths.resize(static_cast<size_t>(subpaths));
        for (std::vector<Vec2>& path : s.subpaths) {
            const uint64_t segments = r.varint();
            if (segments == 0) r.fail("a subpath without segments");
            const uint64_t points = satMul(segments, 3);
            r.need(satMul(points, pointBytes), std::to_string(segments) + " segments");
            charge(r, satMul(points, sizeof(Vec2)));
            path.resize(static_cast<size_t>(points));
            for (Vec2& p : path) {
                if (!quantized) {
                    p.x = r.f64();
                    p.y = r.f64();
                    continue;
                }
                // Deltas between in-range points stay within twice the range; checking them
                // first keeps the sums from overflowing.
                const int64_t dx = r.svarint(), dy = r.svarint();
                if (dx > 2 * kMaxQuantized || dx < -2 * kMaxQuantized ||
                    dy > 2 * kMaxQuantized || dy < -2 * kMaxQuantized)
                    r.fail("shape point out of range");
                x += dx;
                y += dy;
                if (x > kMaxQuantized || x < -kMaxQuantized || y > kMaxQuantized ||
                    y < -kMaxQuantized)
                    r.fail("shape point out of range");
                p = {double(x) / kPointScale, double(y) / kPointScale};
            }
        }
    }
    return shapes;
}

}  // namespace gm::gmb
