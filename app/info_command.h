// `gradmesh info IN`: the canvas, and per mesh its grid, patches, holes and legacy pieces.
#pragma once

#include <string>

#include "cli_common.h"
#include "formats/registry.h"

namespace gm::cli {

// Prints the figures of the mesh file a.positional[0], read through `registry`; its `file:`
// line says `shownName` when given (<stdin> for a spooled standard input).
int infoCommand(const Args& a, const FormatRegistry& registry, const std::string& shownName = "");

}  // namespace gm::cli
