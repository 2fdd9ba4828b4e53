// Mesh lines over a rendered image: every patch edge (grid lines, the outline, both sides of
// each slit) drawn as a 1-output-pixel anti-aliased curve — what an illustration program's mesh
// tool shows, for looking at where a conversion spent its knots.
#pragma once

#include <array>

#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"

namespace gm {

// Composites the lines of every mesh of `doc` in `color` (RGBA 0–1, straight alpha) over
// `image`, which is the document rendered at `scale` output pixels per canvas pixel. Nodes get
// a 3×3 dot. Points outside the image are skipped.
void drawMeshLines(RgbaImage& image, const Document& doc, double scale,
                   const std::array<float, 4>& color);

}  // namespace gm
