#include "image_conversion.h"

#include <chrono>
#include <filesystem>
#include <optional>
#include <system_error>

#include "converters/bicubic_model.h"
#include "converters/compact_file.h"
#include "converters/conversion_report.h"
#include "converters/foreground.h"
#include "formats/atomic_file.h"
#include "formats/gmb.h"
#include "formats/input_file.h"
#include "formats/raster.h"
#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/printable_text.h"
#include "meshcore/validate.h"

namespace gmpy {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// An error of a stage that does not know the file, named as the CLI names it: the mask for an
// error about the mask (when there is one), else the image.
gm::Error namedError(const gm::Error& e, const std::string& imageName, const std::string& maskName) {
    const bool aboutMask = e.reason().find("mask") != std::string::npos;
    return gm::Error(e.reason(), aboutMask && !maskName.empty() ? maskName : imageName, e.where());
}

const gm::CompactCodec kGmbCodec{
    [](const gm::Document& d, int level) { return gm::encodeGmb(d, true, level); },
    [](const std::string& bytes) { return gm::decodeGmb(bytes, gm::ReadLimits{}); }};

gm::CompactTarget compactTarget(const Conversion& c) {
    return {c.image, c.measured, c.job.convert.colors, c.job.convert.threads, c.report.convert.error};
}

// Above this many patches the report leaves out the exact SVG's size, as the CLI's does.
constexpr int kReportSvgMaxPatches = 2000;

// For the default bicubic SVG, Hermite meshes are refitted to the bicubic rule (the CLI's
// documentForWriter, without its line on standard error).
gm::Document documentForWriter(const gm::Document& doc, const gm::MeshFormat& writer,
                               const gm::WriteOptions& options, const std::string& path,
                               int threads) {
    if (writer.name() != "svg" || options.svgColors == "exact" || !gm::hasHermiteMeshes(doc))
        return doc;
    gm::requireOutputWithinLimit(writer.leastBytes(doc, options), options, path);
    return gm::toBicubicModel(doc, threads).doc;
}

// The output's directory must exist and the output must not be a directory (the CLI's checks
// before any work).
void requireWritablePlace(const std::string& path) {
    const std::filesystem::path p(path);
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw gm::Error("the output's directory does not exist", path);
    if (std::filesystem::is_directory(p, ec)) throw gm::Error("is a directory, not a file", path);
}

}  // namespace

gm::Document convertImages(NamedImage input, const NamedImage* mask, const ImageJob& job,
                           std::shared_ptr<Conversion>& conversion) {
    auto c = std::make_shared<Conversion>();
    c->job = job;
    c->inputName = input.name;
    c->readSeconds = input.readSeconds + (mask ? mask->readSeconds : 0);
    const std::string maskName = mask ? mask->name : std::string();
    gm::Document doc;
    gm::ObjectMask objectMask;
    try {
        auto t0 = Clock::now();
        if (!job.segment)
            objectMask = gm::objectMask(input.image, mask ? &mask->image : nullptr, input.name,
                                        maskName, job.convert.threads);
        c->maskSeconds = since(t0);
        t0 = Clock::now();
        if (job.segment) {
            gm::SegmentConvertOptions options = job.segmentOptions;
            options.convert = job.convert;
            doc = gm::convertSegmented(input.image, options, input.name, &c->report);
        } else {
            doc = gm::convertImage(input.image, objectMask, job.convert, input.name, &c->report.convert);
        }
        c->convertSeconds = since(t0);
    } catch (const gm::Error& e) {
        if (!e.file().empty()) throw;
        throw namedError(e, input.name, maskName);
    }
    if (const uint64_t patches = gm::documentPatches(doc); patches > job.maxDocumentPatches)
        throw gm::Error("the conversion made " + std::to_string(patches) +
                            " patches, over the limit of " + std::to_string(job.maxDocumentPatches) +
                            " (raise it with max_document_patches, or lower max_patches)",
                        input.name);
    c->measured = job.segment ? std::vector<uint8_t>(
                                    static_cast<size_t>(input.image.width) * input.image.height, 1)
                              : std::move(objectMask.mask);
    c->image = std::move(input.image);
    conversion = std::move(c);
    return doc;
}

std::string conversionReport(const gm::Document& doc, const Conversion& c) {
    gm::ReportFacts f;
    f.input = c.inputName;
    f.width = c.image.width;
    f.height = c.image.height;
    f.segment = c.job.segment;
    f.colors = c.job.convert.colors;
    f.maxError = c.job.convert.maxError;
    f.maxPatches = c.job.convert.maxPatches;
    f.totalPatches = c.job.segmentOptions.totalPatches;
    f.readSeconds = c.readSeconds;
    f.maskSeconds = c.maskSeconds;
    f.endToEndSeconds = c.readSeconds + c.maskSeconds + c.convertSeconds;
    f.meshes = doc.meshes.size();
    f.gmbLosslessBytes = gm::encodeGmb(doc, false).size();
    if (!c.job.segment && c.report.convert.patches <= kReportSvgMaxPatches) {
        gm::WriteOptions exact;
        exact.svgColors = "exact";
        f.exactSvgBytes = gm::encodeSvg(doc, exact).size();
    }
    const gm::CompactFile compact = gm::compactFileAt(doc, 0, compactTarget(c), kGmbCodec);
    return gm::conversionReportJson(f, c.report, compact);
}

std::string encodeForWriter(const gm::Document& doc, const Conversion* conversion,
                            const gm::MeshFormat& writer, const std::string& path,
                            gm::WriteOptions options) {
    requireWritablePlace(path);
    const bool autoLevel = options.compact && options.compactLevel == gm::kCompactLevelAuto;
    if (autoLevel && !conversion)
        throw std::invalid_argument("compact_level='auto' applies to converted images only (it "
                                    "measures each level's file against the image)");
    const int threads = conversion ? conversion->job.convert.threads : 0;
    if (options.compact && writer.name() == "gmb" && conversion) {
        const gm::CompactFile compact =
            autoLevel ? gm::coarsestCompactFile(doc, gm::kGmbMaxCompactLevel, compactTarget(*conversion), kGmbCodec)
                      : gm::compactFileAt(doc, options.compactLevel, compactTarget(*conversion), kGmbCodec);
        options.compactLevel = compact.level;
        return writer.encode(compact.doc, path, options);
    }
    return writer.encode(documentForWriter(doc, writer, options, path, threads), path, options);
}

const gm::MeshFormat& writerFor(const std::string& path) {
    return gm::FormatRegistry::builtin().writerFor(path);
}

gm::Document readDocument(const std::string& path, uint64_t maxPatches) {
    gm::requireRegularFile(path);
    const gm::MeshFormat* f = gm::FormatRegistry::builtin().forReading(path);
    if (!f || !f->canRead())
        throw gm::Error(f ? "cannot read meshes from " + f->name() + " files"
                          : "unknown file type '" + gm::lowerExtension(path) + "'",
                        path);
    gm::ReadOptions options;
    options.limits.maxPatches = maxPatches;
    gm::Document doc = f->read(path, options);
    if (std::string e = gm::validateDocument(doc); !e.empty()) throw gm::Error("invalid mesh: " + e, path);
    return doc;
}

NamedImage readImageFile(const std::string& path, uint64_t maxPixels) {
    const auto t0 = Clock::now();
    gm::requireRegularFile(path);
    std::error_code ec;
    if (std::filesystem::file_size(path, ec) == 0 && !ec) throw gm::Error("file is empty (0 bytes)", path);
    NamedImage named{gm::readImage(path, maxPixels), path, 0};
    named.readSeconds = since(t0);
    return named;
}

void requireDistinct(const std::string& input, const std::string& output) {
    gm::refuseOverwritingInput(input, output);
}

std::string messageLine(const std::string& message) {
    return gm::printableText(gm::oneLine(message));
}

}  // namespace gmpy
