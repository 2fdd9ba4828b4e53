// Raster I/O through OpenImageIO: every bit depth and channel layout into float RGBA, sRGB.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "formats/raster.h"
#include "meshcore/error.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {
std::string tmp(const std::string& name) {
    fs::create_directories(fs::path(GRADMESH_TMP) / "raster");
    return (fs::path(GRADMESH_TMP) / "raster" / name).string();
}

// Writes a w×h image with `nch` channels of `type` whose value at (x,y,c) is f(x,y,c).
template <class F>
void writeRaw(const std::string& path, int w, int h, int nch, OIIO::TypeDesc type, F f,
              const char* colorSpace = nullptr) {
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, nch, type);
    if (nch == 2 || nch == 4) spec.alpha_channel = nch - 1;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (colorSpace) spec.attribute("oiio:ColorSpace", colorSpace);
    std::vector<float> data(static_cast<size_t>(w) * h * nch);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < nch; ++c) data[(static_cast<size_t>(y) * w + x) * nch + c] = f(x, y, c);
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, data.data()));
    REQUIRE(out->close());
}

float ramp(int x, int, int c) { return std::fmod(0.1f * (x + 1) + 0.25f * c, 1.0f); }
}  // namespace

TEST_CASE("8 and 16-bit PNG, grey, grey+alpha, RGB and RGBA read as float RGBA", "[raster]") {
    struct Case {
        const char* name;
        int nch;
        OIIO::TypeDesc type;
        double tol;
    };
    for (const Case& k : {Case{"g8.png", 1, OIIO::TypeDesc::UINT8, 0.51 / 255},
                          Case{"ga8.png", 2, OIIO::TypeDesc::UINT8, 0.51 / 255},
                          Case{"rgb16.png", 3, OIIO::TypeDesc::UINT16, 0.51 / 65535},
                          Case{"rgba8.png", 4, OIIO::TypeDesc::UINT8, 0.51 / 255},
                          Case{"rgba16.tif", 4, OIIO::TypeDesc::UINT16, 0.51 / 65535},
                          Case{"rgbf.tif", 3, OIIO::TypeDesc::FLOAT, 1e-6}}) {
        INFO(k.name);
        const std::string p = tmp(k.name);
        // Alpha 0.5 in the alpha channel; colour kept unassociated.
        writeRaw(p, 7, 3, k.nch, k.type, [&](int x, int y, int c) {
            if ((k.nch == 2 && c == 1) || (k.nch == 4 && c == 3)) return 0.5f;
            return ramp(x, y, c);
        }, k.type == OIIO::TypeDesc::FLOAT ? "sRGB" : nullptr);
        const gm::RgbaImage img = gm::readImage(p);
        REQUIRE(img.width == 7);
        REQUIRE(img.height == 3);
        const float* px = img.at(4, 2);
        const bool grey = k.nch < 3;
        for (int c = 0; c < 3; ++c) CHECK(px[c] == Approx(ramp(4, 2, grey ? 0 : c)).margin(k.tol));
        CHECK(px[3] == Approx((k.nch == 2 || k.nch == 4) ? 0.5 : 1.0).margin(k.tol));
    }
}

TEST_CASE("JPEG reads and writes", "[raster]") {
    gm::RgbaImage img(16, 8);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            float* p = img.at(x, y);
            p[0] = 0.6f;
            p[1] = 0.3f;
            p[2] = 0.1f;
            p[3] = 1;
        }
    gm::writeImage(img, tmp("flat.jpg"));
    const gm::RgbaImage back = gm::readImage(tmp("flat.jpg"));
    CHECK(back.width == 16);
    CHECK(back.at(5, 5)[0] == Approx(0.6).margin(3.0 / 255));
    CHECK(back.at(5, 5)[3] == 1.0f);
}

TEST_CASE("EXR is linear: encoded to sRGB on read, decoded on write", "[raster]") {
    // Linear 0.214 is sRGB 0.5 (to 3 decimals).
    writeRaw(tmp("lin.exr"), 4, 4, 4, OIIO::TypeDesc::FLOAT,
             [](int, int, int c) { return c == 3 ? 1.0f : 0.21404f; });
    const gm::RgbaImage img = gm::readImage(tmp("lin.exr"));
    CHECK(img.at(1, 1)[0] == Approx(0.5).margin(1e-3));
    gm::writeImage(img, tmp("back.exr"));
    auto in = OIIO::ImageInput::open(tmp("back.exr"));
    REQUIRE(in);
    std::vector<float> px(4 * 16);
    REQUIRE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, px.data()));
    CHECK(px[0] == Approx(0.21404).margin(1e-3));
}

TEST_CASE("PNG round trip keeps straight alpha", "[raster]") {
    gm::RgbaImage img(3, 1);
    float vals[3][4] = {{1, 0, 0, 1}, {0.2f, 0.8f, 0.4f, 0.25f}, {0, 0, 0, 0}};
    for (int x = 0; x < 3; ++x)
        for (int c = 0; c < 4; ++c) img.at(x, 0)[c] = vals[x][c];
    gm::writeImage(img, tmp("alpha.png"));
    const gm::RgbaImage back = gm::readImage(tmp("alpha.png"));
    for (int c = 0; c < 4; ++c) CHECK(back.at(1, 0)[c] == Approx(vals[1][c]).margin(0.51 / 255));
}

TEST_CASE("TIFF written at 16 bits reads back, and in any reader", "[raster]") {
    // OpenImageIO's TIFF writer cuts the file's directory short when it encodes in memory, so
    // TIFF goes through a scratch file: the result must open in OpenImageIO's reader and ours.
    gm::RgbaImage img(64, 48);
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            float* p = img.at(x, y);
            p[0] = x / 63.f, p[1] = y / 47.f, p[2] = 0.3f, p[3] = (x + y) % 5 ? 1.f : 0.5f;
        }
    for (const char* name : {"rgba16.tif", "rgba16.tiff"}) {
        gm::writeImage(img, tmp(name));
        auto in = OIIO::ImageInput::open(tmp(name));
        REQUIRE(in);
        CHECK(in->spec().format == OIIO::TypeDesc::UINT16);
        const gm::RgbaImage back = gm::readImage(tmp(name));
        REQUIRE(back.width == 64);
        REQUIRE(back.height == 48);
        double worst = 0;
        for (size_t k = 0; k < img.pixels.size(); ++k)
            worst = std::max(worst, double(std::fabs(back.pixels[k] - img.pixels[k])));
        CHECK(worst <= 1.0 / 65535);
    }
}

TEST_CASE("an image over the pixel limit is refused before its pixels are read", "[raster][malformed]") {
    writeRaw(tmp("big.png"), 300, 200, 3, OIIO::TypeDesc::UINT8, ramp);
    CHECK_THROWS_WITH(gm::readImage(tmp("big.png"), 50000), Contains("over the limit") && Contains("big.png"));
    CHECK_NOTHROW(gm::readImage(tmp("big.png"), 60000));
}

TEST_CASE("a PNG header claiming 100000x100000 pixels is refused without allocating", "[raster][malformed]") {
    // A valid signature and IHDR for 100000×100000 RGB, then an empty IDAT: no pixel data.
    const unsigned char png[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                 0, 1, 0x86, 0xa0, 0, 1, 0x86, 0xa0, 8, 2, 0, 0, 0, 0x27, 0x30, 0x9c, 0x9f,
                                 0, 0, 0, 0, 'I', 'D', 'A', 'T', 0x35, 0xaf, 0x06, 0x1e,
                                 0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    std::ofstream(tmp("huge.png"), std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
    CHECK_THROWS_WITH(gm::readImage(tmp("huge.png")), Contains("over the limit") && Contains("huge.png"));
}

TEST_CASE("corrupt and missing images are clear errors", "[raster][malformed]") {
    std::ofstream(tmp("corrupt.png"), std::ios::binary) << "\x89PNG\r\n\x1a\n garbage garbage";
    CHECK_THROWS_WITH(gm::readImage(tmp("corrupt.png")), Contains("corrupt.png"));
    std::ofstream(tmp("empty.png"), std::ios::binary).flush();
    CHECK_THROWS_AS(gm::readImage(tmp("empty.png")), gm::Error);
    CHECK_THROWS_WITH(gm::readImage(tmp("none.png")), Contains("none.png"));
    // Writing into a missing directory fails and leaves nothing behind.
    gm::RgbaImage img(2, 2);
    CHECK_THROWS_WITH(gm::writeImage(img, tmp("nodir/x.png")), Contains("does not exist"));
}

TEST_CASE("compositing over a background", "[raster]") {
    gm::RgbaImage img(1, 1);
    float* p = img.at(0, 0);
    p[0] = 1;
    p[1] = 0;
    p[2] = 0;
    p[3] = 0.25f;
    gm::compositeOver(img, {0, 0, 1, 1});
    CHECK(p[0] == Approx(0.25));
    CHECK(p[2] == Approx(0.75));
    CHECK(p[3] == Approx(1.0));
}
