// The triangulation of one region (docs/design.md §3 step 3) and its maps onto the parameter
// rectangle (steps 4–5). Plain data between stages.
//
// Parameter domain convention, shared by every stage after corners: the rectangle
// [0, px] × [0, py] with u to the right and v DOWN, like the image, so a map that does not fold
// keeps the sign of every triangle's area. The four corners of the region's outer loop map to
// (0,0) top-left, (px,0) top-right, (px,py) bottom-right, (0,py) bottom-left. Holes map to
// horizontal slits (v constant).
#pragma once

#include <array>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

struct TriMesh {
    std::vector<Vec2> vertices;                  // image positions, pixels
    std::vector<std::array<int, 3>> triangles;   // each with positive signed area
                                                 // (x1-x0)(y2-y0) - (x2-x0)(y1-y0) > 0
    // The outer loop as vertex indices, in the orientation of Region::outer (positive signed
    // area), starting at the top-left corner; corner[k] is the position in outerLoop of corner
    // k = 0 top-left, 1 top-right, 2 bottom-right, 3 bottom-left (corner[0] == 0).
    std::vector<int> outerLoop;
    std::array<int, 4> corner{};
    std::vector<std::vector<int>> holeLoops;     // one per hole, vertex indices in loop order
};

// A map of a TriMesh's vertices into the parameter rectangle.
struct ParamMap {
    double px = 0, py = 0;     // rectangle size
    std::vector<Vec2> uv;      // one per TriMesh vertex
};

// Triangles whose parameter-space signed area is not positive (folded or degenerate).
int countFlippedTriangles(const TriMesh& mesh, const ParamMap& map);

}  // namespace gm

namespace gm {

// Red–green refinement in image space: every listed triangle is split into four at its edge
// midpoints; neighbours with two or three split edges are split into four too, those with one
// are bisected, so the result is conforming. Midpoints of loop edges join their loop (corner
// positions follow). Orientation is kept. Returns the number of vertices added.
int refineTriangles(TriMesh& mesh, const std::vector<int>& triangles);

}  // namespace gm
