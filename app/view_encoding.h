// Text encodings the view page is assembled with: base64 data URIs for its images, and
// escaping for text placed in HTML and in JSON.
#pragma once

#include "converters/conversion_report.h"  // jsonString, jsonNumber

#include <string>

#include "meshcore/image.h"

namespace gm {

// "data:image/png;base64,..." of `image` as the raster writer encodes a .png (8-bit RGBA).
std::string pngDataUri(const RgbaImage& image);

// Text for HTML content or a quoted attribute value: & < > " ' escaped.
std::string htmlEscape(const std::string& text);

}  // namespace gm
