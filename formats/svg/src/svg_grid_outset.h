// Growing a meshgradient's grid a little beyond the outline path that paints it, and undoing
// that on read.
//
// Inkscape (cairo) paints a mesh only at the pixel centres its patches cover, while it
// anti-aliases the path the mesh fills. A pixel on the outline whose centre lies just outside
// the mesh gets the path's coverage but none of the mesh's colour, so every shaded region would
// get a fringe of whatever lies beneath it. The writer therefore moves each boundary corner of
// the grid outward, and every handle and interior point by the blend of its patch's corner
// moves; the outline path keeps the boundary as it was, so nothing is painted beyond it.
//
// A corner moves along the ray from an interior corner of the grid, which does not move. The
// reader sees the same ray and the distance along it grown by exactly the outset, so it can
// undo the move from what it reads.
#pragma once

#include <string>
#include <vector>

#include "svg_patch_grid.h"

namespace gm {

// How far (px) the writer grows a mesh beyond its outline: enough that every pixel centre the
// anti-aliased outline touches lies inside the mesh.
constexpr double kMeshOutset = 0.7;
// The largest outset a reader accepts (px).
constexpr double kLargestOutset = 10;

// The boundary edges that must not move: where two pieces of a slit mesh meet (each piece's
// path reaches over such a seam, so the grid must stay on it). Patch columns of the grid's top
// and bottom rows, ascending.
struct HeldEdges {
    std::vector<int> top, bottom;
    bool empty() const { return top.empty() && bottom.empty(); }
};

// Whether a grid can be grown: it needs an interior corner, so at least two patches each way.
bool canOutsetGrid(const SvgPatchGrid& g);

// Moves every boundary corner of `g` not on a held edge `amount` px outward, and the handles
// and interior points with them. A grid that cannot be grown is left alone.
void outsetGrid(SvgPatchGrid& g, double amount, const HeldEdges& held);

// Undoes outsetGrid on a grid as read back (to within the precision it was written at).
void insetGrid(SvgPatchGrid& g, double amount, const HeldEdges& held);

// The held edges as attribute text, "top 0-3 7 bottom 2-5"; empty when none are held.
std::string heldEdgesText(const HeldEdges& held);

// Parses heldEdgesText's form for a grid of `columns` patch columns; false when the text is
// not of that form or names a column outside the grid.
bool parseHeldEdges(const std::string& text, int columns, HeldEdges& held);

}  // namespace gm
