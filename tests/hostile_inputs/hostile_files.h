// Files the hostile-input tests build: small images through OpenImageIO, and byte edits of them.
#pragma once

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "support/cli_run.h"

namespace hostile {

// A w×h RGB image of noise over a gradient (so that a JPEG of it has real scan data), written
// by OpenImageIO in the format of `path`'s extension, `pages` subimages when more than one.
inline void writeNoiseImage(const std::string& path, int w, int h, int pages = 1) {
    std::mt19937 rng(7);
    std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * 3);
    for (size_t k = 0; k < pixels.size(); ++k)
        pixels[k] = static_cast<uint8_t>((k / 3 % w) * 200 / w + rng() % 56);
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    const OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
    std::vector<OIIO::ImageSpec> specs(static_cast<size_t>(pages), spec);
    REQUIRE(out->open(path, pages, specs.data()));
    for (int p = 0; p < pages; ++p) {
        if (p > 0) REQUIRE(out->open(path, spec, OIIO::ImageOutput::AppendSubimage));
        REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    }
    REQUIRE(out->close());
}

inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

}  // namespace hostile
