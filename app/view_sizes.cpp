#include "view_sizes.h"

#include "formats/gmb.h"
#include "image_command.h"
#include "meshcore/error.h"

namespace gm {

namespace {

// Runs one encoding; a refusal (gm::Error: over the output limit, coordinates a format cannot
// hold) becomes the size's note.
template <typename Encode>
FormatSize measure(const std::string& format, Encode encode, std::string* keep = nullptr) {
    FormatSize size;
    size.format = format;
    try {
        std::string bytes = encode();
        size.bytes = static_cast<int64_t>(bytes.size());
        if (keep) *keep = std::move(bytes);
    } catch (const Error& e) {
        size.note = e.reason();
    }
    return size;
}

}  // namespace

ViewEncodings encodeForView(const Document& doc, const WriteOptions& given) {
    // The SVG is the default one (bicubic, one SVG patch per patch): the page inlines it, and
    // the exact-colour SVG of a large mesh takes longer to encode than the conversion.
    WriteOptions options = given;
    options.svgColors = "bicubic";
    const FormatRegistry& formats = FormatRegistry::builtin();
    ViewEncodings out;
    out.sizes.push_back(measure(".gmb", [&] { return encodeGmb(doc, false); }));
    out.sizes.push_back(measure(".gmb compact", [&] { return encodeGmb(doc, true, 0); }));
    const MeshFormat& svg = *formats.forPath("page.svg");
    Document svgDoc;
    std::string refusal;
    try {
        svgDoc = documentForWriter(doc, svg, options, "page.svg");
    } catch (const Error& e) {
        refusal = e.reason();
    }
    if (refusal.empty()) {
        out.sizes.push_back(measure(".svg", [&] { return svg.encode(svgDoc, "page.svg", options); },
                                    &out.svg));
        out.sizes.push_back(
            measure(".svgz", [&] { return svg.encode(svgDoc, "page.svgz", options); }));
    } else {
        out.sizes.push_back({".svg", -1, refusal});
        out.sizes.push_back({".svgz", -1, refusal});
    }
    const uint64_t patches = documentPatches(doc);
    for (const char* ext : {".pdf", ".eps"}) {
        if (patches > kMaxPostScriptPatches) {
            out.sizes.push_back({ext, -1, "not measured above " + std::to_string(kMaxPostScriptPatches) +
                                              " patches (convert to it to know)"});
            continue;
        }
        const std::string path = std::string("page") + ext;
        const MeshFormat& writer = *formats.forPath(path);
        out.sizes.push_back(measure(ext, [&] { return writer.encode(doc, path, options); }));
    }
    return out;
}

}  // namespace gm
