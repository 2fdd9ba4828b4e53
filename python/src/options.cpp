#include "options.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "converters/convert_segments.h"
#include "formats/gmb.h"
#include "meshcore/color_text.h"

namespace py = pybind11;

namespace gmpy {

namespace {

std::string valueText(const py::handle& value) { return std::string(py::repr(value)); }

}  // namespace

OptionReader::OptionReader(const py::dict& options, const std::string& function,
                           std::initializer_list<const char*> known)
    : options_(options) {
    const std::set<std::string> names(known.begin(), known.end());
    for (const auto& item : options) {
        const std::string key = py::str(item.first);
        if (!names.count(key))
            throw py::type_error(function + "() got an unexpected keyword argument '" + key + "'");
    }
}

bool OptionReader::has(const char* key) const {
    return options_.contains(key) && !options_[key].is_none();
}

double OptionReader::number(const char* key, double fallback, double lo, double hi) const {
    if (!has(key)) return fallback;
    const py::handle value = options_[key];
    double v = NAN;
    if (!py::isinstance<py::bool_>(value) && (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)))
        v = value.cast<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream s;
        s << key << " expects a number from " << lo << " to " << hi << ", got " << valueText(value);
        throw py::value_error(s.str());
    }
    return v;
}

uint64_t OptionReader::wholeNumber(const char* key, uint64_t fallback, double lo, double hi) const {
    if (!has(key)) return fallback;
    const py::handle value = options_[key];
    double v = NAN;
    if (!py::isinstance<py::bool_>(value) && (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)))
        v = value.cast<double>();
    if (!std::isfinite(v) || v < lo || v > hi || v != std::floor(v)) {
        std::ostringstream s;
        s << key << " expects a whole number from " << lo << " to " << hi << ", got " << valueText(value);
        throw py::value_error(s.str());
    }
    return static_cast<uint64_t>(v);
}

bool OptionReader::flag(const char* key) const {
    if (!has(key)) return false;
    const py::handle value = options_[key];
    if (!py::isinstance<py::bool_>(value))
        throw py::value_error(std::string(key) + " expects True or False, got " + valueText(value));
    return value.cast<bool>();
}

std::string OptionReader::choice(const char* key, const std::string& fallback,
                                 std::initializer_list<const char*> allowed, const char* expects) const {
    if (!has(key)) return fallback;
    const py::handle value = options_[key];
    if (py::isinstance<py::str>(value)) {
        const std::string text = value.cast<std::string>();
        for (const char* c : allowed)
            if (text == c) return text;
    }
    throw py::value_error(std::string(key) + " expects " + expects + ", got " + valueText(value));
}

std::array<float, 4> OptionReader::color(const char* key, std::array<float, 4> fallback) const {
    if (!has(key)) return fallback;
    const py::handle value = options_[key];
    if (py::isinstance<py::str>(value)) return parseColorText(key, value.cast<std::string>());
    if (py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) {
        const py::sequence seq = py::reinterpret_borrow<py::sequence>(value);
        std::array<float, 4> c = {0, 0, 0, 1};
        bool ok = seq.size() == 3 || seq.size() == 4;
        for (size_t k = 0; ok && k < seq.size(); ++k) {
            const py::handle v = seq[k];
            ok = !py::isinstance<py::bool_>(v) && (py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v));
            const double d = ok ? v.cast<double>() : NAN;
            ok = ok && d >= 0 && d <= 1;
            c[k] = static_cast<float>(d);
        }
        if (ok) return c;
    }
    throw py::value_error(std::string(key) + " expects #rrggbb, #rrggbbaa, white, black, none or "
                          "an (r, g, b[, a]) tuple of 0-1 floats, got " + valueText(value));
}

std::array<float, 4> parseColorText(const std::string& key, const std::string& text) {
    if (const auto color = gm::parseColorText(text)) return *color;
    throw py::value_error(key + " expects #rrggbb, #rrggbbaa, white, black or none, got '" + text + "'");
}

ImageJob parseImageJob(const py::dict& options, bool hasMask) {
    const OptionReader o(options, "convert",
                         {"max_error", "max_patches", "colors", "max_pixels", "min_area", "min_hole",
                          "samples", "segment", "segments", "min_region", "threads", "total_patches",
                          "strokes", "gradients", "residue", "max_document_patches"});
    ImageJob job;
    gm::ConvertOptions& co = job.convert;
    job.segment = o.flag("segment");
    co.maxError = o.number("max_error", co.maxError, 0.0, 255.0);
    co.maxPatches = static_cast<int>(
        o.number("max_patches", job.segment ? gm::kSegmentMaxPatches : co.maxPatches, 1, 1e6));
    co.minArea = static_cast<int>(o.number("min_area", co.minArea, 1, 1e9));
    co.minHole = static_cast<int>(o.number("min_hole", co.minHole, 0, 1e9));
    co.sampleFraction = o.number("samples", co.sampleFraction, 1e-4, 1.0);
    job.maxPixels = static_cast<uint64_t>(o.number("max_pixels", double(job.maxPixels), 1, 1e12));
    const std::string colors = o.choice("colors", "bicubic", {"bicubic", "rule", "hermite", "fit", "sampled"},
                                        "bicubic, hermite or sampled");
    co.colors = colors == "hermite" || colors == "fit" ? gm::ColorMode::Fit
                : colors == "sampled"                  ? gm::ColorMode::Sampled
                                                       : gm::ColorMode::FitBicubic;
    gm::SegmentConvertOptions& so = job.segmentOptions;
    so.segment.segments = static_cast<int>(o.number("segments", 0, 1, 100000));
    so.segment.minRegion = static_cast<int>(o.number("min_region", 0, 1, 1e9));
    so.threads = static_cast<int>(o.number("threads", 0, 1, 1024));
    so.totalPatches = static_cast<int>(o.number("total_patches", 0, 0, 1e8));
    so.flatOnly = o.has("total_patches") && so.totalPatches == 0;
    // Each on unless set False (the command line's --no-strokes, --no-gradients, --no-residue).
    so.strokes = !o.has("strokes") || o.flag("strokes");
    so.gradients = !o.has("gradients") || o.flag("gradients");
    so.residue = !o.has("residue") || o.flag("residue");
    co.threads = so.threads;
    job.maxDocumentPatches = o.wholeNumber("max_document_patches", job.maxDocumentPatches, 1, 1e15);
    if (!job.segment)
        for (const char* key :
             {"segments", "min_region", "total_patches", "strokes", "gradients", "residue"})
            if (o.has(key)) throw py::value_error(std::string(key) + " needs segment=True");
    if (job.segment && hasMask)
        throw py::value_error("segment=True converts the whole image; it takes no mask");
    if (so.totalPatches > 0 && static_cast<uint64_t>(so.totalPatches) > job.maxDocumentPatches)
        throw py::value_error("total_patches " + std::to_string(so.totalPatches) +
                              " is over max_document_patches " + std::to_string(job.maxDocumentPatches));
    return job;
}

gm::WriteOptions parseWriteOptions(const py::dict& options) {
    const OptionReader o(options, "save",
                         {"compact", "compact_level", "legacy", "svg_colors", "svg_script",
                          "color_tolerance", "min_piece", "svg_fallback", "text_shading", "scale",
                          "background", "mesh_lines", "max_output_bytes"});
    gm::WriteOptions wo;
    wo.compact = o.flag("compact");
    if (o.has("compact_level")) {
        wo.compact = true;
        const py::handle level = options["compact_level"];
        if (py::isinstance<py::str>(level) && level.cast<std::string>() == "auto")
            wo.compactLevel = gm::kCompactLevelAuto;
        else
            wo.compactLevel = static_cast<int>(o.wholeNumber("compact_level", 0, 0, gm::kGmbMaxCompactLevel));
    }
    wo.legacy = o.flag("legacy");
    wo.textShading = o.flag("text_shading");
    wo.svgColors = o.choice("svg_colors", wo.svgColors, {"exact", "bicubic", "editable"}, "bicubic or exact");
    wo.svgScript = o.choice("svg_script", wo.svgScript, {"embed", "none"}, "embed or none");
    if (o.has("color_tolerance")) wo.colorTolerance = o.number("color_tolerance", 0, 0.01, 64) / 255.0;
    wo.minPiece = o.number("min_piece", wo.minPiece, 0, 64);
    wo.svgFallback = o.choice("svg_fallback", wo.svgFallback, {"png", "webp", "none"}, "png, webp or none");
    wo.rasterScale = o.number("scale", wo.rasterScale, 0.01, 64);
    wo.background = o.color("background", wo.background);
    wo.meshLines = o.color("mesh_lines", wo.meshLines);
    if (o.has("mesh_lines") && wo.meshLines[3] <= 0)
        throw py::value_error("mesh_lines needs a visible colour, got " + valueText(options["mesh_lines"]));
    wo.maxOutputBytes = o.wholeNumber("max_output_bytes", wo.maxOutputBytes, 1, 1e15);
    return wo;
}

}  // namespace gmpy
