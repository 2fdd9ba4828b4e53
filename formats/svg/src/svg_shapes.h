// Flat shapes (FlatShape) in SVG: written as <path fill="#rrggbb" d="..."/> (a graded shape as
// <path fill="url(#gradient id)" d="..."/> after its <linearGradient>, svg_linear_gradient.h; a
// stroked shape as <path fill="none" stroke="#rrggbb" stroke-width="W" stroke-linecap="round"
// stroke-linejoin="round" d="..."/>) with compact relative path data at 1/100 px, read back
// from such paths.
#pragma once

#include <string>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "svg_linear_gradient.h"

namespace gm {

// Appends the shape's <path> element and a newline. Points are rounded to 1/100 px once and
// written as differences of the rounded values, so rounding never accumulates; cubics whose
// handles lie at a third and two thirds of their chord are written as lines, and a closing line
// as "z" alone. A stroked shape's closed centrelines end in "z", its open ones do not; its
// width is written to 1/100 px, at least 0.01. A graded shape's gradient goes through
// `gradients`, which writes each distinct one once, before the first path it paints.
void appendShapePath(std::string& out, const FlatShape& shape, SvgGradientWriter& gradients);

// "#rrggbb", each channel clamped to 0–1 and rounded to 8 bits.
void appendHexColour(std::string& out, Vec3 col);

// Appends path data (the d attribute's text) for closed subpaths in FlatShape's layout (point,
// handle, handle, point, ..., each subpath a cycle of cubics), written as appendShapePath does.
// Subpaths of fewer than 3 points are left out.
void appendClosedPathData(std::string& out, const std::vector<std::vector<Vec2>>& subpaths);

// The subpaths of SVG path data (M m L l H h V v C c Z z, implicit repetition), each closed and
// in FlatShape's layout (lines as cubics with handles at thirds). Every number must be finite
// and within ±maxCoordinate; at most maxPoints points in all. On failure returns false with
// `problem` set.
bool parseShapePathData(const std::string& d, double maxCoordinate, size_t maxPoints,
                        std::vector<std::vector<Vec2>>& subpaths, std::string& problem);

// The same as the centrelines of a stroked shape: a subpath closed by z ends on its first point
// (a line added when it ends elsewhere), one that is not stays open.
bool parseCentrelinePathData(const std::string& d, double maxCoordinate, size_t maxPoints,
                             std::vector<std::vector<Vec2>>& subpaths, std::string& problem);

// "#rrggbb" or "#rgb" as sRGB 0–1; false for anything else (named colours, rgb(), none, url).
bool parseHexColour(const std::string& text, Vec3& colour);

}  // namespace gm
