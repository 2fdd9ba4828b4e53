// The SHAP section of .gmb (versions 1.5 and 2.1, docs/formats.md): the document's flat shapes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gmb_pvt.h"

namespace gm::gmb {

constexpr uint16_t kMinorShapes = 5;       // a 1.x file with a SHAP section
constexpr uint16_t kMinorShortShapes = 1;  // a 2.x file with a SHAP section

// Point encodings of a SHAP payload: bit 0 quantized, bit 1 a stroke width on every shape,
// bit 2 a gradient field on every shape. A writer sets bit 1 only when some shape is stroked and
// bit 2 only when some shape is graded, so that other files stay as they were.
enum class ShapeEncoding : uint8_t {
    Float64 = 0,
    Quantized = 1,
    Float64WithStrokes = 2,
    QuantizedWithStrokes = 3,
    Float64WithGradients = 4,
    QuantizedWithGradients = 5,
    Float64WithStrokesAndGradients = 6,
    QuantizedWithStrokesAndGradients = 7
};
constexpr uint8_t kShapeQuantizedBit = 1, kShapeStrokesBit = 2, kShapeGradientsBit = 4;
// Quantized points, stroke widths and gradient ends are multiples of 2^-kShapePointBits px.
constexpr int kShapePointBits = 8;

// The payload: float64 (lossless) or, when `quantize` and every point is within the quantized
// range, points, stroke widths and gradient ends to 1/256 px, colours and gradient offsets in
// 16 bits, rounded so that every gradient stays valid.
std::string encodeShapes(const std::vector<FlatShape>& shapes, bool quantize);

// Reads a SHAP payload of at most `maxShapes` shapes, checking every count against the bytes
// that remain before allocating; `charge` is told the bytes each subpath and gradient decodes to.
std::vector<FlatShape> decodeShapes(ByteReader& r, uint64_t maxShapes,
                                    const std::function<void(ByteReader&, uint64_t)>& charge);

}  // namespace gm::gmb
