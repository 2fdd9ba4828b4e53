// Pipeline stage 4, topology map (docs/design.md §3, paper §4.3): a bijective map of a region's
// triangulation onto the parameter rectangle [0, px] × [0, py] (u right, v down; conventions in
// tri_mesh.h). The outer loop's corners land on the rectangle's corners and each hole becomes a
// horizontal slit.
#pragma once

#include <array>
#include <vector>

#include "converters/tri_mesh.h"
#include "meshcore/error.h"

namespace gm {

// The slit one hole maps to: the segment v = const, u0 ≤ u ≤ u1 (parameter units). The hole loop
// splits at its two extreme vertices into the arc mapped onto the slit's upper side (facing
// smaller v) and the arc on its lower side; both list TriMesh vertex indices from the u0 end to
// the u1 end (both ends included, so upperArc.front() == lowerArc.front()) with u strictly
// increasing.
struct SlitInfo {
    double v = 0, u0 = 0, u1 = 0;
    std::vector<int> upperArc, lowerArc;
};

struct TopologyMapStats {
    int clampedWeights = 0;     // slit map: edges whose cotangent weight was negative or tiny
                                // and was raised to a small positive value
    int flipsBeforeRepair = 0;  // slit map: folded triangles of the plain two-solve map
    bool repaired = false;      // slit map: arcs made monotone and u (and v) solved again
    int untangledVertices = 0;  // slit map: interior vertices moved by local untangling
    int refineRounds = 0;       // buildTopologyMapRefining: rounds of refinement around folds
    int refinedVertices = 0;    // and the vertices they added
};

struct TopologyMap {
    ParamMap map;                // never folded: countFlippedTriangles(mesh, map) == 0
    std::vector<SlitInfo> slits;  // one per TriMesh::holeLoops entry, same order
    TopologyMapStats stats;
    std::vector<int> folded;     // buildSlitMapOrFolds only: triangles the map still folds
};

// Thrown when no unfolded map was found for a valid triangulation: the region's shape is the
// problem (holes too close to each other or to the outline, thin parts), and converting it in
// parts may work.
struct MapError : Error {
    using Error::Error;
};

// A map squeezed a triangle to zero area (a long thin part whose flanks lie on one side of the
// rectangle); other corners may avoid it.
struct SqueezeError : MapError {
    using MapError::MapError;
};

// The stage entry point. Without holes: the outer loop onto the rectangle's sides by arc length
// in the image, interior vertices by Floater's mean-value weights (a convex boundary and positive
// weights make it a bijection). With holes: buildSlitMap. Throws gm::Error on a malformed mesh
// (indices, loops, corners), on px or py not positive, on an edge that no straight-edged map can
// keep unfolded (see dividingEdges), when the slit map cannot be unfolded, or when the map
// squeezes a triangle to zero area (a long thin part between two corners).
TopologyMap buildTopologyMap(const TriMesh& mesh, double px, double py);

// buildTopologyMap, except that where the slit map still folds, the triangles around the folds
// (sharing a vertex with one) are refined in image space (refineTriangles) and the map is built
// again, up to maxRounds times: folds come from too few triangles between a hole and its
// neighbours. `mesh` is modified. Throws like buildTopologyMap when folds remain.
TopologyMap buildTopologyMapRefining(TriMesh& mesh, double px, double py, int maxRounds = 2);

// The slit map with two sparse solves whatever the number of holes (docs/design.md §3 step 4), with
// cotangent weights of the image-space triangulation:
//   v: harmonic, 0 on the top side, py on the bottom side, free on the left and right sides,
//      each hole's vertices tied to one floating value (zero total flux through the hole);
//   u: harmonic, 0 on the left side, px on the right side, free elsewhere.
// Each hole then lies on its own v; its slit runs between its vertices' extreme u. When that map
// has folded triangles or a non-monotone side or arc, u is made strictly monotone along every
// arc (and along the top and bottom sides, v along the left and right sides) and solved again
// with those values fixed; folds left after that are untangled by moving the interior vertices
// around them. Throws gm::Error if folds remain. Also valid without holes.
TopologyMap buildSlitMap(const TriMesh& mesh, double px, double py);

// buildSlitMap's map even when folds remain: they are listed in `folded` instead of thrown
// (the caller may refine the triangulation there and try again). No zero-area check.
TopologyMap buildSlitMapOrFolds(const TriMesh& mesh, double px, double py);

// Edges that are not loop edges but join two vertices of one rectangle side (a corner belongs to
// both its sides) or of one hole loop. Such an edge maps into the side's line or the hole's slit,
// so the triangles on one side of it must fold; triangulate splits them.
std::vector<std::array<int, 2>> dividingEdges(const TriMesh& mesh);

}  // namespace gm
