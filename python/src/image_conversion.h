// What `gradmesh.convert` does once its inputs are images and its options parsed: the same steps
// as `gradmesh convert IMAGE` (app/image_command.cpp), without files: the object's mask, one
// conversion (an object, or the whole image with segment=True), the document's patch limit;
// then, on demand, the JSON report and the files `Document.save` writes (compact .gmb refitted
// against the image, Hermite meshes refitted for the bicubic SVG).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "converters/convert_segments.h"
#include "formats/registry.h"
#include "meshcore/image.h"

namespace gmpy {

// A conversion as its options ask for it (the CLI's ImageJob).
struct ImageJob {
    bool segment = false;
    gm::ConvertOptions convert;
    gm::SegmentConvertOptions segmentOptions;
    uint64_t maxPixels = uint64_t(64) << 20;
    uint64_t maxDocumentPatches = gm::ReadLimits{}.maxPatches;
};

// An image to convert: its pixels and the name errors and the report give it (the file's path,
// or "<array>").
struct NamedImage {
    gm::RgbaImage image;
    std::string name;
    double readSeconds = 0;
};

// A finished conversion: what the report and a compact .gmb are measured against.
struct Conversion {
    ImageJob job;
    std::string inputName;
    gm::RgbaImage image;
    std::vector<uint8_t> measured;  // the pixels its error is over: the object's, or all
    gm::SegmentConvertReport report;
    double readSeconds = 0, maskSeconds = 0, convertSeconds = 0;
};

// Throws gm::Error naming the image (or the mask) as the CLI does, std::invalid_argument for
// options that do not go together.
gm::Document convertImages(NamedImage image, const NamedImage* mask, const ImageJob& job,
                           std::shared_ptr<Conversion>& conversion);

// The JSON report of `convert --report R.json`, without an output ("output" empty, its bytes 0).
std::string conversionReport(const gm::Document& doc, const Conversion& conversion);

// The bytes `gradmesh convert` writes to `path` through `writer` for this document: a compact
// .gmb refitted against the image when the document comes from a conversion, Hermite meshes
// refitted for the default bicubic SVG. `conversion` may be null (a loaded document).
std::string encodeForWriter(const gm::Document& doc, const Conversion* conversion,
                            const gm::MeshFormat& writer, const std::string& path,
                            gm::WriteOptions options);

// The writer for `path`'s extension, or gm::Error naming it and the known extensions.
const gm::MeshFormat& writerFor(const std::string& path);

// A mesh file read and validated as `gradmesh convert MESHFILE` reads it.
gm::Document readDocument(const std::string& path, uint64_t maxPatches);

// An image file read as `gradmesh convert IMAGE` reads it (within maxPixels).
NamedImage readImageFile(const std::string& path, uint64_t maxPixels);

// Refuses an output that is `input` (same file, whatever the spelling), like the CLI.
void requireDistinct(const std::string& input, const std::string& output);

// The CLI's error line: one line, repeated parts dropped, control characters escaped.
std::string messageLine(const std::string& message);

}  // namespace gmpy
