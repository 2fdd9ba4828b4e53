// The SHAP section of .gmb (versions 1.5 and 2.1, docs/formats.md): the document's flat shapes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gmb_pvt.h"

namespace gm::gmb {

constexpr uint16_t kMinorShapes = 5;       // a 1.x file with a SHAP section
constexpr uint16_t kMinorShortShapes = 1;  // a 2.x file with a SHAP section

// Point encodings of a SHAP payload. The "WithStrokes" ones add a stroke width to every shape;
// a writer uses them only when some shape is stroked, so that other files stay as they were.
enum class ShapeEncoding : uint8_t {
    Float64 = 0,
    Quantized = 1,
    Float64WithStrokes = 2,
    QuantizedWithStrokes = 3
};
// Quantized points and stroke widths are multiples of 2^-kShapePointBits px.
constexpr int kShapePointBits = 8;

// The payload: float64 (lossless) or, when `quantize` and every point is within the quantized
// range, points and stroke widths to 1/256 px and colours in 16 bits.
std::string encodeShapes(const std::vector<FlatShape>& shapes, bool quantize);

// Reads a SHAP payload of at most `maxShapes` shapes, checking every count against the bytes
// that remain before allocating; `charge` is told the bytes each subpath decodes to.
std::vector<FlatShape> decodeShapes(ByteReader& r, uint64_t maxShapes,
                                    const std::function<void(ByteReader&, uint64_t)>& charge);

}  // namespace gm::gmb
