#include "view_page.h"

#include <chrono>
#include <cstdio>
#include <map>

#include "meshcore/render.h"
#include "view_encoding.h"
#include "view_error_map.h"
#include "view_mesh_lines.h"
#include "view_sizes.h"

namespace gm {

extern const char* const kViewPageTemplate;  // view_page.html (view_page_template.cpp.in)

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string colorModelOf(const Document& doc) {
    bool bicubic = false, hermite = false;
    for (const GradientMesh& m : doc.meshes)
        (m.colorModel == ColorModel::Bicubic ? bicubic : hermite) = true;
    if (bicubic && hermite) return "bicubic and hermite meshes";
    return hermite ? "hermite (free colour slopes)" : "bicubic (SVG's colour rule)";
}

std::string pairsJson(const std::vector<std::pair<std::string, double>>& rows) {
    std::string s = "[";
    for (const auto& [name, value] : rows)
        s += (s.size() > 1 ? "," : "") + ("[" + jsonString(name) + "," + jsonNumber(value) + "]");
    return s + "]";
}

std::string factsJson(const std::vector<std::pair<std::string, std::string>>& rows) {
    std::string s = "[";
    for (const auto& [label, value] : rows)
        s += (s.size() > 1 ? "," : "") + ("[" + jsonString(label) + "," + jsonString(value) + "]");
    return s + "]";
}

std::string sizesJson(const std::vector<FormatSize>& sizes) {
    std::string s = "[";
    for (const FormatSize& f : sizes)
        s += (s.size() > 1 ? "," : "") +
             ("{\"format\":" + jsonString(f.format) + ",\"bytes\":" +
              (f.bytes < 0 ? "null" : std::to_string(f.bytes)) + ",\"note\":" + jsonString(f.note) + "}");
    return s + "]";
}

// The legend's colours: the heat map's scale sampled at its stops.
std::string errorScaleJson() {
    std::string s = "[";
    for (int k = 0; k <= 8; ++k) {
        float rgb[3];
        errorColor(kErrorMapScale * k / 8.0, rgb);
        char stop[64];
        std::snprintf(stop, sizeof stop, "%s[%d,%d,%d]", k ? "," : "", int(rgb[0] * 255 + 0.5f),
                      int(rgb[1] * 255 + 0.5f), int(rgb[2] * 255 + 0.5f));
        s += stop;
    }
    return s + "]";
}

int holesOf(const Document& doc) {
    int holes = 0;
    for (const GradientMesh& m : doc.meshes) holes += m.holeCount();
    return holes;
}

// The SVG as markup for an HTML page: from its <svg> element on (no XML declaration).
std::string inlineSvg(const std::string& svg) {
    const size_t start = svg.find("<svg");
    return start == std::string::npos ? std::string() : svg.substr(start);
}

// What the page holds besides the figures.
struct PageParts {
    bool svgInline = false, meshLines = false;
};

std::string figuresJson(const Document& doc, const ViewFigures& f, const ViewEncodings& encodings,
                        PageParts parts, const std::vector<std::pair<std::string, double>>& pageSeconds) {
    std::string s = "{";
    s += "\"title\":" + jsonString(f.title);
    s += ",\"source\":" + jsonString(f.sourceName);
    s += ",\"width\":" + std::to_string(doc.width) + ",\"height\":" + std::to_string(doc.height);
    s += ",\"patches\":" + std::to_string(documentPatches(doc));
    s += ",\"meshes\":" + std::to_string(doc.meshes.size());
    s += ",\"holes\":" + std::to_string(holesOf(doc));
    s += ",\"colorModel\":" + jsonString(f.colorModel.empty() ? colorModelOf(doc) : f.colorModel);
    s += ",\"error\":" + (f.haveError ? "{\"E\":" + jsonNumber(f.meanAbs) + ",\"psnr\":" +
                                            jsonNumber(f.psnr) + ",\"over\":" + jsonString(f.errorOver) + "}"
                                      : std::string("null"));
    s += ",\"errorScale\":" + jsonNumber(kErrorMapScale) + ",\"errorColors\":" + errorScaleJson();
    s += ",\"seconds\":" + pairsJson(f.seconds) + ",\"pageSeconds\":" + pairsJson(pageSeconds);
    s += ",\"bytes\":" + sizesJson(encodings.sizes);
    s += ",\"facts\":" + factsJson(f.facts);
    s += ",\"svgInline\":" + std::string(parts.svgInline ? "true" : "false");
    s += ",\"meshLines\":" + std::string(parts.meshLines ? "true" : "false");
    return s + "}";
}

// Replaces each {{name}} of the template by values[name], in one pass (a value's own text is
// never searched again).
std::string fillTemplate(const std::string& page, const std::map<std::string, std::string>& values) {
    std::string out;
    size_t at = 0;
    while (true) {
        const size_t open = page.find("{{", at);
        const size_t close = open == std::string::npos ? open : page.find("}}", open);
        if (close == std::string::npos) break;
        const auto it = values.find(page.substr(open + 2, close - open - 2));
        out.append(page, at, open - at);
        out += it == values.end() ? page.substr(open, close + 2 - open) : it->second;
        at = close + 2;
    }
    return out.append(page, at, std::string::npos);
}

}  // namespace

std::string buildViewPage(const Document& doc, const RgbaImage* source, ViewFigures figures,
                          const WriteOptions& options) {
    std::vector<std::pair<std::string, double>> pageSeconds;
    auto t0 = Clock::now();
    const RgbaImage render = renderDocument(doc).image;
    pageSeconds.emplace_back("render", since(t0));

    t0 = Clock::now();
    std::map<std::string, std::string> values;
    values["source"] = "";
    values["errormap"] = "";
    if (source) {
        const ErrorMap map = errorHeatMap(*source, render);
        if (!figures.haveError && map.pixels > 0) {
            figures.haveError = true;
            figures.meanAbs = map.meanAbs;
            figures.psnr = map.psnr;
            figures.errorOver = "the pixels both the image and the mesh paint";
        }
        values["source"] = pngDataUri(*source);
        values["errormap"] = pngDataUri(map.image);
        pageSeconds.emplace_back("image and error map", since(t0));
    }

    t0 = Clock::now();
    const ViewEncodings encodings = encodeForView(doc, options);
    pageSeconds.emplace_back("encode formats", since(t0));

    t0 = Clock::now();
    values["render"] = pngDataUri(render);
    const bool meshLines = documentPatches(doc) <= kMaxMeshLinePatches;
    values["meshpath"] = meshLines ? meshLinesPathData(doc) : "";
    const bool svgInline = !encodings.svg.empty() && encodings.svg.size() <= kMaxInlineSvgBytes;
    values["svg"] = svgInline ? inlineSvg(encodings.svg) : "";
    values["width"] = std::to_string(doc.width);
    values["height"] = std::to_string(doc.height);
    values["title"] = htmlEscape(figures.title);
    pageSeconds.emplace_back("page", since(t0));
    values["data"] = figuresJson(doc, figures, encodings, {svgInline, meshLines}, pageSeconds);
    return fillTemplate(kViewPageTemplate, values);
}

}  // namespace gm
