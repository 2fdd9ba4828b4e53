// Encapsulated PostScript (PostScript 3) writer: one patch-mesh shading (type 7) per mesh,
// painted with shfill (formats/mesh_shading.h). Canvas pixels become points 1:1 with a y flip;
// the bounding box is the canvas. The default DataSource is the binary stream, Flate-compressed
// and ASCII85-encoded in the file; WriteOptions::textShading writes readable number arrays
// instead (for small files). Write-only.
#pragma once

#include <memory>

#include "formats/registry.h"

namespace gm {

std::unique_ptr<MeshFormat> makeEpsFormat();

}  // namespace gm
