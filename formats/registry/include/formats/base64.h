// Base64 (RFC 4648, with padding, no line breaks): the text of a data: URI.
#pragma once

#include <string>

namespace gm {

std::string base64Encode(const std::string& bytes);

}  // namespace gm
