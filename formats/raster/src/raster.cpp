#include "formats/raster.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>

#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "formats/private_dir.h"
#include "meshcore/error.h"
#include "meshcore/mesh_lines.h"
#include "meshcore/render.h"

namespace gm {

namespace {
float srgbEncode(float linear) {
    if (!(linear > 0.f)) return 0.f;
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
    if (!(encoded > 0.f)) return 0.f;
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

bool isLinearSpace(const OIIO::ImageSpec& spec, const std::string& formatName) {
    const std::string cs = lower(spec.get_string_attribute("oiio:ColorSpace"));
    if (cs.find("srgb") != std::string::npos && cs.find("lin") == std::string::npos) return false;
    if (cs.find("linear") != std::string::npos || cs == "lin_srgb" || cs == "scene_linear")
        return true;
    // Float data without a stated colour space in a scene-referred format is linear.
    return cs.empty() && (formatName == "openexr" || formatName == "hdr");
}

bool linearExtension(const std::string& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".exr" || ext == ".hdr";
}

// The formats readImage takes, by OpenImageIO's name of the content, and how to say them.
bool readableFormat(const std::string& format) {
    return format == "png" || format == "jpeg" || format == "tiff" || format == "openexr";
}
constexpr const char* kReadableFormats = "PNG, JPEG, TIFF or OpenEXR";

std::string upper(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
}

// Opens `path` by content (OpenImageIO tries every reader when the extension's refuses it)
// and refuses formats other than readableFormat's.
std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path) {
    requireRegularFile(path);  // OpenImageIO would block on a FIFO and read a device without end
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // keep PNG/TIFF alpha as stored
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        std::string msg = OIIO::geterror();
        if (msg.empty()) msg = "cannot open image";
        // OIIO prefixes some messages with the file name; keep one copy of it.
        throw Error("cannot read image: " + msg, path);
    }
    const std::string format = in->format_name();
    if (!readableFormat(format))
        throw Error("the file holds a " + upper(format) + " image (whatever its name says); " +
                        "images are read as " + kReadableFormats,
                    path);
    return in;
}

int countPages(OIIO::ImageInput& in) {
    constexpr int kMaxCounted = 1000;
    int pages = 1;
    while (pages < kMaxCounted && in.seek_subimage(pages, 0)) ++pages;
    in.seek_subimage(0, 0);
    return pages;
}
}  // namespace

ImageProbe probeImage(const std::string& path) {
    auto in = openImage(path);
    ImageProbe probe;
    probe.width = in->spec().width;
    probe.height = in->spec().height;
    probe.channels = in->spec().nchannels;
    probe.format = in->format_name();
    probe.pages = countPages(*in);
    return probe;
}

RgbaImage readImage(const std::string& path, uint64_t maxPixels) {
    auto in = openImage(path);
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
        throw Error("unsupported image dimensions " + std::to_string(spec.width) + "x" +
                        std::to_string(spec.height) + "x" + std::to_string(spec.depth),
                    path);
    const uint64_t pixels = uint64_t(spec.width) * uint64_t(spec.height);
    if (pixels > maxPixels)
        throw Error("image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                        " (" + std::to_string(pixels / 1000000.0).substr(0, 6) +
                        " megapixels), over the limit of " +
                        std::to_string(maxPixels / 1000000.0).substr(0, 6) +
                        " megapixels (raise it with --max-pixels)",
                    path);
    const int nch = spec.nchannels;
    if (nch < 1) throw Error("image has no channels", path);
    std::vector<float> raw(static_cast<size_t>(pixels) * nch);
    // A damaged file may still fill the buffer (libjpeg pads a truncated JPEG with grey and
    // only warns): the reader's error state says so.
    if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, raw.data()) || in->has_error()) {
        std::string msg = in->geterror();
        throw Error("cannot decode image: " + (msg.empty() ? std::string("read failed") : msg), path);
    }
    const bool linear = isLinearSpace(spec, in->format_name());
    int alpha = spec.alpha_channel;
    if (alpha < 0 && (nch == 2 || nch == 4)) alpha = nch - 1;
    const bool associated = alpha >= 0 && spec.get_int_attribute("oiio:UnassociatedAlpha", 0) == 0 &&
                            (linear || lower(in->format_name()) == "openexr");
    RgbaImage img(spec.width, spec.height);
    for (size_t p = 0; p < pixels; ++p) {
        const float* s = &raw[p * nch];
        float* d = &img.pixels[p * 4];
        float a = alpha >= 0 ? s[alpha] : 1.f;
        float rgb[3];
        if (nch < 3) {
            rgb[0] = rgb[1] = rgb[2] = s[0];
        } else {
            rgb[0] = s[0];
            rgb[1] = s[1];
            rgb[2] = s[2];
        }
        if (!std::isfinite(a)) a = 0.f;
        a = std::clamp(a, 0.f, 1.f);
        for (float& c : rgb) {
            if (!std::isfinite(c)) c = 0.f;
            if (associated) c = a > 0.f ? c / a : 0.f;
            if (linear) c = srgbEncode(c);
            c = std::clamp(c, 0.f, 1.f);
        }
        d[0] = rgb[0];
        d[1] = rgb[1];
        d[2] = rgb[2];
        d[3] = a;
    }
    return img;
}

namespace {

// Writes the image to `target` with OpenImageIO's writer for its extension, through `proxy`
// when given; errors name `path`, the output asked for.
void writeWithOiio(const OIIO::ImageSpec& spec, const std::vector<float>& data,
                   const std::string& target, const std::string& path,
                   OIIO::Filesystem::IOProxy* proxy) {
    auto file = OIIO::ImageOutput::create(target);
    if (!file) throw Error("no image writer for this extension: " + OIIO::geterror(), path);
    if (proxy && (!file->supports("ioproxy") || !file->set_ioproxy(proxy)))
        throw Error("the image writer cannot encode in memory", path);
    if (!file->open(target, spec)) throw Error("cannot write image: " + file->geterror(), path);
    if (!file->write_image(OIIO::TypeDesc::FLOAT, data.data()) || !file->close())
        throw Error("cannot write image: " + file->geterror(), path);
}

std::string encodeInMemory(const OIIO::ImageSpec& spec, const std::vector<float>& data,
                           const std::string& path) {
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput memory(encoded);
    writeWithOiio(spec, data, path, path, &memory);
    return std::string(encoded.begin(), encoded.end());
}

// OpenImageIO's TIFF writer, given an in-memory proxy, leaves the file's directory cut short
// (no reader opens the result), so TIFF is written to a file in a private directory and read
// back.
std::string encodeThroughFile(const OIIO::ImageSpec& spec, const std::vector<float>& data,
                              const std::string& extension, const std::string& path) {
    PrivateDir dir;
    const std::string scratch = dir.file("image" + extension);
    writeWithOiio(spec, data, scratch, path, nullptr);
    std::ifstream in(scratch, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.good() && !in.eof()) throw Error("cannot read back the encoded image", path);
    return bytes;
}

}  // namespace

std::string encodeImage(const RgbaImage& image, const std::string& path) {
    const std::string ext = lowerExtension(path);
    const bool noAlpha = ext == ".jpg" || ext == ".jpeg";
    const bool linear = linearExtension(path);
    const bool tiff = ext == ".tif" || ext == ".tiff";
    const int nch = noAlpha ? 3 : 4;
    OIIO::TypeDesc type = OIIO::TypeDesc::UINT8;
    if (linear) type = OIIO::TypeDesc::HALF;
    if (tiff) type = OIIO::TypeDesc::UINT16;
    OIIO::ImageSpec spec(image.width, image.height, nch, type);
    if (!noAlpha) spec.alpha_channel = 3;
    if (!linear) {
        spec.attribute("oiio:UnassociatedAlpha", 1);
        spec.attribute("oiio:ColorSpace", "sRGB");
    }
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    std::vector<float> data(pixels * nch);
    for (size_t p = 0; p < pixels; ++p) {
        const float* s = &image.pixels[p * 4];
        for (int c = 0; c < 3; ++c) {
            float v = std::clamp(s[c], 0.f, 1.f);
            if (linear) v = srgbDecode(v) * s[3];  // EXR stores associated alpha
            data[p * nch + c] = v;
        }
        if (!noAlpha) data[p * nch + 3] = std::clamp(s[3], 0.f, 1.f);
    }
    // Encoded in memory (or a private scratch file): the output itself is written by our own
    // checked I/O (atomic_file.h).
    return tiff ? encodeThroughFile(spec, data, ext, path) : encodeInMemory(spec, data, path);
}

void writeImage(const RgbaImage& image, const std::string& path) {
    writeFileAtomically(path, encodeImage(image, path));
}

void compositeOver(RgbaImage& image, const std::array<float, 4>& bg) {
    if (bg[3] <= 0.f) return;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    for (size_t p = 0; p < pixels; ++p) {
        float* d = &image.pixels[p * 4];
        const float a = d[3];
        const float outA = a + bg[3] * (1 - a);
        for (int c = 0; c < 3; ++c)
            d[c] = outA > 0 ? (d[c] * a + bg[c] * bg[3] * (1 - a)) / outA : 0.f;
        d[3] = outA;
    }
}

namespace {
class RasterFormat : public MeshFormat {
public:
    std::string name() const override { return "raster"; }
    std::vector<std::string> extensions() const override {
        return {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr"};
    }
    bool canWrite() const override { return true; }
    std::string encode(const Document& doc, const std::string& path,
                       const WriteOptions& options) const override {
        RenderOptions renderOptions;
        renderOptions.scale = options.rasterScale;
        RgbaImage img = renderDocument(doc, renderOptions).image;
        compositeOver(img, options.background);
        if (options.meshLines[3] > 0)
            drawMeshLines(img, doc, renderOptions.scale, options.meshLines);
        return encodeImage(img, path);
    }
};
}  // namespace

std::unique_ptr<MeshFormat> makeRasterFormat() { return std::make_unique<RasterFormat>(); }

}  // namespace gm
