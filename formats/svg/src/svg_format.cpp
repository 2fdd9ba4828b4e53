#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <memory>
#include <utility>

#include "formats/input_file.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

bool isGzip(const std::string& bytes) {
    return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b;
}

// .svgz: the SVG text as one gzip member (RFC 1952), at zlib's best compression.
std::string gzipBytes(const std::string& text) {
    z_stream z{};
    if (deflateInit2(&z, Z_BEST_COMPRESSION, Z_DEFLATED, 15 + 16, 9, Z_DEFAULT_STRATEGY) != Z_OK)
        throw Error("zlib could not start gzip compression");
    std::string out(deflateBound(&z, static_cast<uLong>(text.size())) + 32, '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(text.data()));
    z.avail_in = static_cast<uInt>(text.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    const int rc = deflate(&z, Z_FINISH);
    deflateEnd(&z);
    if (rc != Z_STREAM_END) throw Error("gzip compression failed (zlib code " + std::to_string(rc) + ")");
    out.resize(z.total_out);
    return out;
}

// The SVG text of a .svgz file, refused past `limit` bytes once inflated.
std::string gunzipBytes(const std::string& bytes, uint64_t limit, const std::string& path) {
    z_stream z{};
    if (inflateInit2(&z, 15 + 16) != Z_OK) throw Error("zlib could not start gzip decoding", path);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    z.avail_in = static_cast<uInt>(bytes.size());
    std::string out;
    char buffer[1 << 16];
    int rc = Z_OK;
    while (rc == Z_OK) {
        z.next_out = reinterpret_cast<Bytef*>(buffer);
        z.avail_out = sizeof buffer;
        rc = inflate(&z, Z_NO_FLUSH);
        out.append(buffer, sizeof buffer - z.avail_out);
        if (out.size() > limit) {
            inflateEnd(&z);
            throw Error("the SVG inside the .svgz file exceeds the limit of " +
                            std::to_string(limit) + " bytes",
                        path);
        }
        if (rc == Z_OK && z.avail_in == 0 && z.avail_out != 0) rc = Z_BUF_ERROR;
    }
    inflateEnd(&z);
    if (rc != Z_STREAM_END) throw Error("corrupt or truncated gzip data (.svgz)", path);
    return out;
}

class SvgFormat : public MeshFormat {
public:
    explicit SvgFormat(SvgFallbackEncoder fallback) : fallback_(std::move(fallback)) {}

    std::string name() const override { return "svg"; }
    std::vector<std::string> extensions() const override { return {".svg", ".svgz"}; }
    bool canRead() const override { return true; }
    bool canWrite() const override { return true; }

    // An XML declaration, a comment, a doctype or the <svg> element first (after a BOM).
    bool sniff(const std::string& head) const override {
        size_t p = 0;
        if (head.compare(0, 3, "\xEF\xBB\xBF") == 0) p = 3;
        while (p < head.size() && std::isspace(static_cast<unsigned char>(head[p]))) ++p;
        const std::string rest = head.substr(p);
        if (isGzip(head)) return true;
        return rest.compare(0, 5, "<?xml") == 0 || rest.compare(0, 4, "<svg") == 0 ||
               rest.compare(0, 9, "<!DOCTYPE") == 0 || rest.compare(0, 4, "<!--") == 0;
    }

    Document read(const std::string& path, const ReadOptions& options) const override {
        const uint64_t limit =
            std::min<uint64_t>(options.limits.maxFileBytes, SvgReadLimits::maxFileBytes);
        std::string bytes = readWholeFile(path, limit);
        if (isGzip(bytes)) bytes = gunzipBytes(bytes, limit, path);
        return decodeSvg(bytes, options.limits, path);
    }

    // A meshpatch of the bicubic mode takes ~130 bytes (two stops with a path and a colour);
    // exact colours split patches into more.
    uint64_t leastBytes(const Document& doc, const WriteOptions&) const override {
        return 60 * documentPatches(doc);
    }

    std::string encode(const Document& doc, const std::string& path,
                       const WriteOptions& options) const override {
        requireOutputWithinLimit(leastBytes(doc, options), options, path);
        if (const std::string e = coordinateProblem(doc); !e.empty())
            throw Error("cannot write: " + e, path);
        try {
            const std::unique_ptr<SvgFallbackImage> image = fallbackImage(doc, options);
            const std::string svg = encodeSvg(doc, options, nullptr, image.get());
            // leastBytes counts no image: the limit is checked again with it.
            if (image) requireOutputWithinLimit(svg.size(), options, path);
            return endsWith(path, ".svgz") ? gzipBytes(svg) : svg;
        } catch (const Error& e) {
            if (!e.file().empty()) throw;
            throw Error(e.reason(), path, e.where());
        }
    }

private:
    SvgFallbackEncoder fallback_;

    // The image WriteOptions::svgFallback asks for, rendered from `doc`; null for "none" (and
    // for an unknown kind, which encodeSvg refuses).
    std::unique_ptr<SvgFallbackImage> fallbackImage(const Document& doc,
                                                    const WriteOptions& options) const {
        if (options.svgFallback == "none" || !isSvgFallbackKind(options.svgFallback))
            return nullptr;
        if (!fallback_) throw Error("this build writes no SVG fallback images");
        return std::make_unique<SvgFallbackImage>(SvgFallbackImage{
            options.svgFallback, fallback_(withoutShapesOnTop(doc), options.svgFallback)});
    }

    // The document less the flat shapes painted over every mesh: a viewer that draws no meshes
    // draws those paths itself over the image (in the image too, their anti-aliased edges
    // would be painted twice).
    static Document withoutShapesOnTop(const Document& doc) {
        Document beneath = doc;
        beneath.shapes.erase(std::remove_if(beneath.shapes.begin(), beneath.shapes.end(),
                                            [&](const FlatShape& s) {
                                                return s.layer >= doc.meshes.size();
                                            }),
                             beneath.shapes.end());
        return beneath;
    }
};

}  // namespace

std::unique_ptr<MeshFormat> makeSvgFormat(SvgFallbackEncoder fallback) {
    return std::make_unique<SvgFormat>(std::move(fallback));
}

}  // namespace gm
