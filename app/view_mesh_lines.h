// The mesh lines of the view page as vector data: every patch edge (grid lines, the outline,
// both sides of each slit; the edges meshcore's drawMeshLines draws) as SVG path data in canvas
// pixels, so that the lines stay one screen pixel wide and sharp at any zoom.
#pragma once

#include <string>

#include "meshcore/gradient_mesh.h"

namespace gm {

// Cubic Bézier edges, joined into runs along each grid line; coordinates to 1/10 px.
std::string meshLinesPathData(const Document& doc);

}  // namespace gm
