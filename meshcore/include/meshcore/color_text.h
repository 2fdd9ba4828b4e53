// Colours as users type them on a command line or in a script: #rrggbb, #rrggbbaa, white,
// black, none (transparent).
#pragma once

#include <array>
#include <optional>
#include <string>

namespace gm {

// Straight RGBA in 0-1; nullopt when `text` is none of the forms above.
std::optional<std::array<float, 4>> parseColorText(const std::string& text);

}  // namespace gm
