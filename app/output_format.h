// --to FORMAT, as convert, render and batch take it: the formats written, by name.
#pragma once

#include <string>
#include <vector>

namespace gm {

// The extension of the writable format `name` ("svg" or ".svg" give ".svg"); "" when no
// format of that name is written.
std::string writableExtension(const std::string& name);

// The extensions of a comma-separated list of formats ("gmb,svg"), each once, in order. Throws
// std::invalid_argument naming the list when one is not a format written.
std::vector<std::string> outputExtensions(const std::string& list);

// What --to takes, for messages: "gmb, svg, svgz, eps, pdf, png ...".
std::string writableFormatNames();

}  // namespace gm
