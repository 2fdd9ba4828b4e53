// PDF writer: one page the size of the canvas (points = pixels), one patch-mesh shading
// (type 7) per mesh as a Flate-compressed binary stream object, painted with `sh` under a y
// flip (formats/mesh_shading.h). PDF has no text form of a mesh shading, so
// WriteOptions::textShading does not apply. Write-only.
#pragma once

#include <memory>

#include "formats/registry.h"

namespace gm {

std::unique_ptr<MeshFormat> makePdfFormat();

}  // namespace gm
