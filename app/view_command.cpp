#include "view_command.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "command_limits.h"
#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "formats/raster.h"
#include "formats/registry.h"
#include "meshcore/error.h"
#include "meshcore/printable_text.h"
#include "meshcore/validate.h"
#include "view_page.h"

namespace gm {

const std::set<std::string> kViewValuedOptions = {"--image", "--max-output-bytes"};

namespace {

// Memory of a page per canvas pixel, an estimate: the render, the source and the heat map as
// float RGBA (16 B each), their 8-bit PNG encodings and base64 text, the renderer's buffers.
constexpr uint64_t kViewBytesPerPixel = 144;

using Clock = std::chrono::steady_clock;

bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    return std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec) &&
           std::filesystem::equivalent(a, b, ec);
}

uint64_t maxOutputBytes(const std::map<std::string, std::string>& values) {
    const auto it = values.find("--max-output-bytes");
    if (it == values.end()) return WriteOptions{}.maxOutputBytes;
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0' || !(v >= 1 && v <= 1e15))
        throw std::invalid_argument("--max-output-bytes expects a number from 1 to 1e+15, got '" +
                                    it->second + "'");
    return static_cast<uint64_t>(v);
}

Document readMeshFile(const std::string& path, const CommandLimits& limits) {
    requireRegularFile(path);
    const MeshFormat* reader = FormatRegistry::builtin().forReading(path);
    if (reader && reader->name() == "raster")
        throw Error("is an image, not a mesh file; convert it with `gradmesh convert " +
                        printableText(path) + " -o OUT.gmb --report PAGE.html`",
                    path);
    if (!reader || !reader->canRead())
        throw Error("view reads mesh files (.gmb .svg .svgz), not '" + lowerExtension(path) + "'", path);
    ReadOptions options;
    options.limits.maxPatches = limits.maxDocumentPatches;
    Document doc = reader->read(path, options);
    if (const std::string e = validateDocument(doc); !e.empty()) throw Error("invalid mesh: " + e, path);
    return doc;
}

// The source image, checked against the canvas from its header before its pixels are read.
RgbaImage readSourceImage(const std::string& path, const Document& doc) {
    requireRegularFile(path);
    const ImageProbe probe = probeImage(path);
    if (probe.width != doc.width || probe.height != doc.height)
        throw Error("the image is " + std::to_string(probe.width) + "x" + std::to_string(probe.height) +
                        ", the mesh's canvas " + std::to_string(doc.width) + "x" +
                        std::to_string(doc.height) + "; --image needs the image it was converted from",
                    path);
    return readImage(path, static_cast<uint64_t>(doc.width) * doc.height);
}

std::string fileName(const std::string& path) {
    return std::filesystem::path(path).filename().string();
}

}  // namespace

bool isHtmlPath(const std::string& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".html" || ext == ".htm";
}

void viewCommand(const std::vector<std::string>& positional,
                 const std::map<std::string, std::string>& values) {
    if (positional.size() != 1) throw std::invalid_argument("expects exactly one input file");
    const std::string in = positional[0];
    const auto outIt = values.find("--output");
    if (outIt == values.end() || outIt->second.empty()) throw std::invalid_argument("missing -o PAGE.html");
    const std::string out = outIt->second;
    if (!isHtmlPath(out))
        throw std::invalid_argument("writes an HTML page: -o PAGE.html, got '" + out + "'");
    std::string imagePath;
    if (const auto it = values.find("--image"); it != values.end()) {
        imagePath = it->second;
        if (imagePath.empty()) throw std::invalid_argument("--image needs a file name");
    }
    const CommandLimits limits = commandLimits(values);
    WriteOptions options;
    options.maxOutputBytes = maxOutputBytes(values);

    requireRegularFile(in);
    if (sameFile(in, out)) throw Error("output is the input file; refusing to overwrite it", out);
    if (!imagePath.empty() && sameFile(imagePath, out))
        throw Error("output is the --image file; refusing to overwrite it", out);
    // The page's place is claimed first: an unwritable one fails before any work.
    OutputBatch outputs;
    outputs.reserve(out);

    const auto t0 = Clock::now();
    const Document doc = readMeshFile(in, limits);
    requireRenderWithinLimits(doc.width, doc.height, 1.0, limits, out);
    requireMemoryBudget(double(doc.width) * doc.height * kViewBytesPerPixel, limits.maxMemory,
                        "the page's images", out);
    RgbaImage source;
    if (!imagePath.empty()) source = readSourceImage(imagePath, doc);
    ViewFigures figures;
    figures.title = fileName(in);
    figures.sourceName = imagePath.empty() ? "" : fileName(imagePath);
    figures.seconds.emplace_back("read", std::chrono::duration<double>(Clock::now() - t0).count());

    const std::string page =
        buildViewPage(doc, imagePath.empty() ? nullptr : &source, figures, options);
    requireOutputWithinLimit(page.size(), options, out);
    outputs.write(out, page);
    outputs.commit();
    std::printf("page: %s (%.2f MB)\n", printableText(out).c_str(), page.size() / 1e6);
}

}  // namespace gm
