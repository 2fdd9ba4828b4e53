// Text encodings the view page is assembled with: base64 data URIs for its images, and
// escaping for text placed in HTML and in JSON.
#pragma once

#include <string>

#include "meshcore/image.h"

namespace gm {

std::string base64(const std::string& bytes);

// "data:image/png;base64,..." of `image` as the raster writer encodes a .png (8-bit RGBA).
std::string pngDataUri(const RgbaImage& image);

// Text for HTML content or a quoted attribute value: & < > " ' escaped.
std::string htmlEscape(const std::string& text);

// A JSON string literal, safe inside a <script> element as well: '<' is written \u003c so that
// no "</script>" can close it.
std::string jsonQuote(const std::string& text);

// A JSON number; NaN is null, infinities the largest finite values.
std::string jsonNumber(double value);

}  // namespace gm
