// Programmatic meshes with known structure: the demo before conversion exists, tests and
// benchmarks. Positions and colours are smooth closed-form functions with exact derivatives.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// A columns×rows mesh over roughly [x0, x0+w] × [y0, y0+h], warped by sine waves (curvature 0
// gives straight grid lines; 1 gives strongly curved patches without folds) and coloured by a
// smooth field whose phases depend on seed.
GradientMesh makeCurvedMesh(int columns, int rows, double x0, double y0, double w, double h,
                            double curvature = 1.0, unsigned seed = 1);

// A mesh over [x0, x0+w] × [y0, y0+h] with `holes` slits on distinct rows, each opened into an
// elliptical hole whose outline is smooth through the slit ends (the ±d rule).
GradientMesh makeHoledMesh(int holes, double x0, double y0, double w, double h, unsigned seed = 2);

// A flat ring: a circle of radius `outer` about (cx, cy) with a hole of radius `inner` (each
// circle four cubics; the hole winds opposite to the outline), painted above `layer` meshes.
FlatShape makeFlatRing(double cx, double cy, double outer, double inner, Vec3 col,
                       size_t layer = 0);

// A canvas of 240×180: a curved mesh over all of it, a flat ring with a hole above it, then a
// second mesh over part of the ring, then a flat square with a square hole on top of all.
Document makeFlatDocument();

// A 512×512 canvas: a mesh with three holes and a curved mesh beside it.
Document makeDemoDocument();

}  // namespace gm
