// `gradmesh convert IMAGE -o OUT`: the raster → mesh path of the command. Kept apart
// from gradmesh_main.cpp so the mesh-file commands do not grow with the pipeline's options.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "formats/registry.h"

namespace gm {

class ConversionProgress;

// Options of convert that only make sense for a raster input.
extern const std::set<std::string> kImageValuedOptions;
extern const std::set<std::string> kImageFlagOptions;  // passed in `values` with value "1"

// Converts the raster image `in` and writes `out` through `writer`. `values` holds the parsed
// valued options (--mask, --max-error, ...). Throws gm::Error (input/output problems) or
// std::invalid_argument (a bad option value; the message names the option).
void convertImageCommand(const std::string& in, const std::string& out, const MeshFormat& writer,
                         const WriteOptions& writeOptions,
                         const std::map<std::string, std::string>& values,
                         ConversionProgress* progress = nullptr);

// One output of an image conversion: its path and the writer of its format.
struct ImageTarget {
    std::string path;
    const MeshFormat* writer = nullptr;
};

// What an image conversion made: the document's patches and its error (E, PSNR) over the
// measured pixels.
struct ImageFigures {
    uint64_t patches = 0;
    double meanAbs = 0, psnr = 0;
};

// convertImageCommand writing one conversion to several outputs: each holds the bytes that
// `convert IN -o PATH` with the same options writes. --report describes the first. All are
// renamed into place together, after the last is written. `progress` (may be null) is told
// each stage; with --verbose, the stages' seconds and the figures go to standard error.
ImageFigures convertImageToTargets(const std::string& in, const std::vector<ImageTarget>& targets,
                                   const WriteOptions& writeOptions,
                                   const std::map<std::string, std::string>& values,
                                   ConversionProgress* progress = nullptr);

// Throws std::invalid_argument, as the conversion would, when an option value in `values` is
// bad (--max-error x, --segments without --segment, a bad limit...).
void checkImageOptions(const std::map<std::string, std::string>& values);

// The document as `writer` should receive it: for the default bicubic SVG, Hermite meshes are
// refitted in the Bicubic model (toBicubicModel), and a line on standard error says how far
// the result is from the Hermite mesh's own render (a document over the output limit for
// `path` is refused first). Any other writer gets `doc` itself.
Document documentForWriter(const Document& doc, const MeshFormat& writer,
                           const WriteOptions& options, const std::string& path,
                           int threads = 0);

}  // namespace gm
