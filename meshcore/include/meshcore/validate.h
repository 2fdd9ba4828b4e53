// Invariants of a GradientMesh / Document, checked on data that came from outside.
#pragma once

#include <string>

#include "meshcore/gradient_mesh.h"

namespace gm {

// The largest |coordinate|, in canvas pixels, of a node the SVG, EPS and PDF writers take; each Bézier handle a node's derivative makes (derivative × knot span / 3)
// lies at most 2 × kMaxCoordinate from its node. Their number formats stay exact within it,
// and no real canvas comes near it. (.gmb keeps any finite double.)
constexpr double kMaxCoordinate = 1e7;
// The widest stroke a flat shape may have, pixels.
constexpr double kMaxStrokeWidth = 1e4;
// The shortest a linear gradient's axis may be, pixels: writers round its ends to 1/100 px.
constexpr double kMinGradientLength = 0.1;

// Returns an empty string when the mesh is valid, else a one-line description of the first
// problem found: knots not strictly increasing, node count mismatch, slit outside the grid or
// not interior, slits touching on a row, wrong number of split nodes, tangent break on a
// patch that does not exist, a non-finite number anywhere.
std::string validateMesh(const GradientMesh& mesh);

// A flat shape of a document of `meshCount` meshes: colour and opacity within 0-1, a layer that
// exists, at least one subpath, each of 3n points (n >= 1), every point finite; a gradient
// only on a filled shape, and a valid one.
std::string validateShape(const FlatShape& shape, size_t meshCount);

// Empty when the gradient is valid (2 to kMaxGradientStops stops, offsets strictly increasing
// from 0 to 1, colours within 0-1, ends within kMaxCoordinate and at least kMinGradientLength
// apart), else what is wrong.
std::string gradientProblem(const LinearGradient& gradient);

// As above for every mesh and shape (shapes in non-decreasing layers), plus a positive canvas
// size; the message names the mesh or shape.
std::string validateDocument(const Document& doc);

// Empty when every position of a valid mesh is within kMaxCoordinate and every handle within
// 2 × kMaxCoordinate of its node; else the first one beyond (the document's names the mesh).
std::string coordinateProblem(const GradientMesh& mesh);
std::string coordinateProblem(const Document& doc);

// Patches that fold: the Jacobian of position (d pos/ds × d pos/dt) is ≤ 0 at one of
// `samples`² points strictly inside the patch (a fold shows as grid lines crossing and the
// patch painting over itself or its neighbours). A valid mesh may fold; a good one does not.
int countFoldedPatches(const GradientMesh& mesh, int samples = 6);

// The area, in pixels, of the mesh's inverted sheets: the integral of the negative part of the
// Jacobian (d pos/ds × d pos/dt) over every patch, by the midpoint rule on samples² points per
// patch. A fold's hairline sliver at a patch corner is a fraction of a pixel; a grid fanned
// across a notch of the outline inverts tens to hundreds of pixels, painted over whatever is
// beneath.
double foldedArea(const GradientMesh& mesh, int samples = 8);

}  // namespace gm
