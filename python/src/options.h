// Keyword options of the Python API, checked as the CLI checks its options (same ranges and
// choices), with the keywords' own names in the messages. An unknown keyword is a TypeError
// naming it; a bad value a ValueError.
#pragma once

#include <pybind11/pybind11.h>

#include <array>
#include <initializer_list>
#include <set>
#include <string>

#include "formats/registry.h"
#include "image_conversion.h"

namespace gmpy {

class OptionReader {
public:
    // Throws TypeError for a keyword of `options` that is not in `known`.
    OptionReader(const pybind11::dict& options, const std::string& function,
                 std::initializer_list<const char*> known);
    bool has(const char* key) const;
    double number(const char* key, double fallback, double lo, double hi) const;
    uint64_t wholeNumber(const char* key, uint64_t fallback, double lo, double hi) const;
    bool flag(const char* key) const;
    // One of `allowed`, as given.
    std::string choice(const char* key, const std::string& fallback,
                       std::initializer_list<const char*> allowed, const char* expects) const;
    // "#rrggbb", "#rrggbbaa", "white", "black", "none" or a 3- or 4-tuple of floats 0–1.
    std::array<float, 4> color(const char* key, std::array<float, 4> fallback) const;

private:
    pybind11::dict options_;
};

// The keywords of gradmesh.convert: the CLI's raster-input options.
ImageJob parseImageJob(const pybind11::dict& options, bool hasMask);

// The keywords of Document.save: the CLI's write options.
gm::WriteOptions parseWriteOptions(const pybind11::dict& options);

// "#rrggbb" and the other colours --background takes; throws ValueError naming `key`.
std::array<float, 4> parseColorText(const std::string& key, const std::string& text);

}  // namespace gmpy
