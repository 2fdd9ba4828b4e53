// convert's and render's inputs and outputs as the tools users script take them (potrace,
// ImageMagick, Inkscape): `-` for standard input and for standard output, --to FORMAT where the
// output's name does not say it, and several inputs into --output-dir.
#pragma once

#include <functional>
#include <string>

#include "cli_common.h"
#include "formats/registry.h"

namespace gm::cli {

// Converts the file `in` into the file `out` through `writer` (out's extension is the format's).
using ConvertFile = std::function<void(const std::string& in, const std::string& out,
                                       const MeshFormat& writer)>;

// Runs `convertFile` for `command` ("convert" or "render") as its arguments say: IN -o OUT, or
// IN... --output-dir DIR (each input to DIR/<stem>.<ext>; one failing does not stop the others,
// each failure is reported and the exit code is 1). Either may be `-`, spooled through private
// temporary files (std_streams.h); messages name them <stdin> and <stdout>. Returns the exit
// code; throws UsageError before any work on a bad command line.
int runConversions(const std::string& command, const Args& args, const ConvertFile& convertFile);

}  // namespace gm::cli
