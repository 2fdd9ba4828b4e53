// `gradmesh convert IMAGE -o OUT`: the raster → mesh path of the command. Kept apart
// from gradmesh_main.cpp so the mesh-file commands do not grow with the pipeline's options.
#pragma once

#include <map>
#include <set>
#include <string>

#include "formats/registry.h"

namespace gm {

// Options of convert that only make sense for a raster input.
extern const std::set<std::string> kImageValuedOptions;
extern const std::set<std::string> kImageFlagOptions;  // passed in `values` with value "1"

// Converts the raster image `in` and writes `out` through `writer`. `values` holds the parsed
// valued options (--mask, --max-error, ...). Throws gm::Error (input/output problems) or
// std::invalid_argument (a bad option value; the message names the option).
void convertImageCommand(const std::string& in, const std::string& out, const MeshFormat& writer,
                         const WriteOptions& writeOptions,
                         const std::map<std::string, std::string>& values);

// The document as `writer` should receive it: for the default bicubic SVG, Hermite meshes are
// refitted in the Bicubic model (toBicubicModel), and a line on standard error says how far
// the result is from the Hermite mesh's own render (a document over the output limit for
// `path` is refused first). Any other writer gets `doc` itself.
Document documentForWriter(const Document& doc, const MeshFormat& writer,
                           const WriteOptions& options, const std::string& path,
                           int threads = 0);

}  // namespace gm
