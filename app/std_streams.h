// `-` for standard input and standard output, as the tools users script take it (potrace,
// ImageMagick). Standard input is spooled whole into a private temporary file: every reader
// (the mesh readers, OpenImageIO's) decides a file's format by content and reads a file. An
// output for standard output is written to a private temporary file and copied out once it is
// complete, so a failed run writes nothing there. Both files go when the run ends, however it
// ends (signals included, temp_registry.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "formats/private_dir.h"
#include "formats/registry.h"
#include "meshcore/error.h"

namespace gm::cli {

// How messages name them.
extern const char* const kStdinName;   // "<stdin>"
extern const char* const kStdoutName;  // "<stdout>"

inline bool isStdStream(const std::string& path) { return path == "-"; }

// Copies standard input into a file of `dir` whose extension says its content: a mesh file
// `registry` sniffs (.gmb, SVG), PNG, JPEG, TIFF or OpenEXR. Returns its path. Throws gm::Error
// naming <stdin> when standard input is a terminal, empty, over 4 GiB or none of these.
std::string spoolStandardInput(PrivateDir& dir, const FormatRegistry& registry);

// Writes the file at `path` to standard output; gm::Error naming <stdout> when a write fails
// (a closed pipe included).
void copyToStandardOutput(const std::string& path);

// Runs `work`; a gm::Error naming the file `from` is thrown again naming `to` instead.
template <class Work>
auto withFileNamed(const std::string& from, const std::string& to, Work&& work) {
    try {
        return work();
    } catch (const Error& e) {
        if (from.empty() || e.file() != from) throw;
        throw Error(e.reason(), to, e.where());
    }
}

}  // namespace gm::cli
