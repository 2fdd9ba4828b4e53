#include "command_limits.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "meshcore/error.h"

namespace gm {

const char* const kLimitOptions[3] = {"--max-memory", "--max-canvas-pixels",
                                      "--max-document-patches"};

namespace {
uint64_t wholeNumber(const std::map<std::string, std::string>& values, const std::string& key,
                     uint64_t fallback) {
    const auto it = values.find(key);
    if (it == values.end()) return fallback;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !(v >= 1 && v <= 1e15) || v != std::floor(v))
        throw std::invalid_argument(key + " expects a whole number from 1 to 1e15, got '" +
                                    it->second + "'");
    return static_cast<uint64_t>(v);
}
}  // namespace

CommandLimits commandLimits(const std::map<std::string, std::string>& values) {
    CommandLimits limits;
    if (const auto it = values.find("--max-memory"); it != values.end())
        limits.maxMemory = parseByteCount("--max-memory", it->second);
    limits.maxCanvasPixels = wholeNumber(values, "--max-canvas-pixels", limits.maxCanvasPixels);
    limits.maxDocumentPatches =
        wholeNumber(values, "--max-document-patches", limits.maxDocumentPatches);
    return limits;
}

uint64_t parseByteCount(const std::string& option, const std::string& text) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    std::string unit = end ? std::string(end) : std::string();
    for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();        // "GB" -> "G", "B" -> ""
    if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();        // "GI" -> "G"
    double scale = 1;
    if (unit == "K") scale = 1024.0;
    else if (unit == "M") scale = 1024.0 * 1024;
    else if (unit == "G") scale = 1024.0 * 1024 * 1024;
    else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
    else if (!unit.empty() && unit != "B") scale = -1;
    const double bytes = value * scale;
    if (text.empty() || end == text.c_str() || scale < 0 || !std::isfinite(bytes) || bytes < 1 ||
        bytes > 1e18)
        throw std::invalid_argument(option + " expects a size in bytes such as 4G, 512M or " +
                                    "1000000, got '" + text + "'");
    return static_cast<uint64_t>(bytes);
}

std::string byteText(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    int u = 0;
    while (bytes >= 1024 && u < 6) {
        bytes /= 1024;
        ++u;
    }
    char text[32];
    std::snprintf(text, sizeof text, u == 0 || bytes >= 100 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
    return text;
}

void requireMemoryBudget(double needed, uint64_t limit, const std::string& what,
                         const std::string& file) {
    if (needed <= static_cast<double>(limit)) return;
    throw Error(what + " is too large for the memory budget (needs ~" + byteText(needed) +
                    ", limit " + byteText(static_cast<double>(limit)) +
                    "; raise with --max-memory)",
                file);
}

void requireRenderWithinLimits(int width, int height, double scale, const CommandLimits& limits,
                               const std::string& file) {
    const double pixels = std::ceil(width * scale) * std::ceil(height * scale);
    if (pixels > static_cast<double>(limits.maxCanvasPixels)) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "the render would be %.0f x %.0f = %.0f pixels, over the limit of %llu "
                      "(lower --scale or raise --max-canvas-pixels)",
                      std::ceil(width * scale), std::ceil(height * scale), pixels,
                      static_cast<unsigned long long>(limits.maxCanvasPixels));
        throw Error(text, file);
    }
    requireMemoryBudget(pixels * kRenderBytesPerPixel, limits.maxMemory, "the render", file);
}

}  // namespace gm
