#include "meshcore/color_text.h"

namespace gm {

std::optional<std::array<float, 4>> parseColorText(const std::string& text) {
    if (text == "none" || text == "transparent") return std::array<float, 4>{0, 0, 0, 0};
    if (text == "white") return std::array<float, 4>{1, 1, 1, 1};
    if (text == "black") return std::array<float, 4>{0, 0, 0, 1};
    if ((text.size() == 7 || text.size() == 9) && text[0] == '#' &&
        text.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos) {
        std::array<float, 4> c = {0, 0, 0, 1};
        for (size_t k = 0; k * 2 + 1 < text.size(); ++k)
            c[k] = static_cast<float>(std::stoi(text.substr(1 + 2 * k, 2), nullptr, 16)) / 255.f;
        return c;
    }
    return std::nullopt;
}

}  // namespace gm
