// Split a topology-preserving mesh into traditional hole-free meshes (paper §3).
#pragma once

#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gm {

// Cuts along every row that holds a slit: b+1 meshes when the b slits lie on distinct rows,
// fewer when rows are shared. Nothing moves: every patch of the result has exactly the
// Hermite data it had in the whole (slit-end kinks become CornerTangent breaks), so the pieces
// render identically. A mesh without slits comes back as one piece equal to itself.
std::vector<GradientMesh> splitIntoLegacyMeshes(const GradientMesh& mesh);

// The number of pieces splitIntoLegacyMeshes would return.
int legacyPieceCount(const GradientMesh& mesh);

}  // namespace gm
