// Pipeline stage 6, grid (docs/design.md §3, paper §4.5): a gradient mesh whose grid is a set of
// knot lines in the parameter rectangle, carried into the image through the inverse of the
// topology/feature map. Geometry only: node colours and colour derivatives are left zero
// (stage 7, colours, fills them).
//
// The mesh's parameter domain is the map's rectangle itself: global u ∈ [0, px] (right),
// v ∈ [0, py] (down), so knots are map parameters and node derivatives are pixels per unit of
// map parameter.
#pragma once

#include <memory>
#include <vector>

#include "converters/tri_mesh.h"
#include "meshcore/gradient_mesh.h"

namespace gm {

// A hole's slit in parameter space: the horizontal segment v = const from u0 to u1 onto which
// the slit map sends the hole loop (0 < u0 < u1 < px, 0 < v < py). Its row and end columns
// become knots; the grid's nodes on it are located from above and from below separately.
struct GridSlit {
    double v = 0, u0 = 0, u1 = 0;
};

struct GridOptions {
    // Patch counts of the initial grid; 0 derives them from targetPatchSize (the map's
    // rectangle is measured in pixels of the region, so px / targetPatchSize columns).
    int columns = 0, rows = 0;
    double targetPatchSize = 64;  // pixels
    // Knot values that must be present (e.g. sharp boundary corners' parameters), parameter
    // units; values outside (0, px) / (0, py) are ignored.
    std::vector<double> extraU, extraV;
    std::vector<GridSlit> slits;
    // When non-empty, the complete knot vector along u (or v): starts at 0, ends at px (py),
    // strictly increasing. Required knots (extras, slits) are merged in. Refinement passes its
    // knots here; columns/rows/targetPatchSize are then ignored for that direction.
    std::vector<double> knotsU, knotsV;
    // Points per patch edge sampled through the inverse map to fit the position derivatives.
    int samplesPerEdge = 8;
    // Each node derivative is shortened so that on every patch edge it belongs to, its tangent
    // (derivative × the edge's knot interval) is at most this many times the edge's chord
    // (0: no limit). A cubic whose end tangents stay within ~1.5 chords does not loop, and
    // patches between such edges do not fold where knot intervals are uneven.
    double tangentLimit = 1.5;
    // When ≥ 0, the curves along the rectangle's four sides are fitted one-sided: the outline
    // (as the inverse map carries it) should lie outside them by at most this many pixels, and
    // their nodes (not the corners) may move outward off the outline, along its normal, for
    // it. A least-squares curve through a jagged outline cuts the tips of its steps and leaves
    // their pixels uncovered; the one-sided one goes round them. Two limits keep it honest:
    // no side edge strays farther from the outline (Hausdorff, both ways, as fitBoundary
    // measures it) than the plain least-squares edge does or than outlineSlack, and no patch
    // along a side folds where the plain fit's does not; where either would fail, the nodes
    // are blended back toward the plain fit. Negative: plain least squares, nodes on the
    // outline. Slits (holes) are not affected.
    double outlineCover = -1;
    double outlineSlack = 0.5;  // pixels
    // Folded patches mended last (unfoldPatches: corner derivatives pulled toward their grid
    // lines' chords; positions, outline and slits untouched).
    bool unfold = true;
};

// The knot vectors buildGrid uses for these options: required knots (0, the extent, extras,
// slit rows and ends) and, between them, knots as uniform as possible up to the requested
// count. Throws gm::Error on an empty rectangle, explicit knots that are not increasing or do
// not span the rectangle, or a slit outside it.
void chooseKnots(const ParamMap& map, const GridOptions& options, std::vector<double>& u,
                 std::vector<double>& v);

// Holds the inverse map (a bucket grid over the parameter-space triangles, for O(1) point
// location) so that repeated grids of one map — refinement — share that work.
class GridBuilder {
public:
    // Throws gm::Error when the map does not match the triangulation (sizes, vertex indices)
    // or has no triangles.
    GridBuilder(const TriMesh& mesh, const ParamMap& map);
    ~GridBuilder();
    GridBuilder(GridBuilder&&) noexcept;
    GridBuilder& operator=(GridBuilder&&) noexcept;

    // The image position of parameter point (u, v) by barycentric interpolation in the
    // triangle containing it (or, for points a hair outside the domain, the nearest one).
    // side < 0 prefers triangles above v (smaller v), side > 0 below: a point on a slit has a
    // position on each side.
    Vec2 imagePosition(double u, double v, int side = 0) const;

    GradientMesh build(const GridOptions& options) const;

    const ParamMap& map() const;

private:
    struct Impl;
    friend class GridAssembly;  // build()'s steps (grid.cpp)
    std::unique_ptr<Impl> impl_;
};

// Stage entry point: GridBuilder(mesh, map).build(options). The result passes validateMesh;
// node positions on the rectangle's sides lie on the region's outer loop (unless
// options.outlineCover moves them outward), and each grid line's
// position derivatives come from a least-squares fit of the patches' edge cubics to the map's
// iso-curve sampled through the inverse map.
GradientMesh buildGrid(const TriMesh& mesh, const ParamMap& map, const GridOptions& options);

}  // namespace gm
