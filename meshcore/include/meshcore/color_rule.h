// The colour-derivative rule that can be recomputed from node colours alone (DESIGN §2):
// monotone cubic, the SVG 2 / Inkscape `bicubic` rule, expressed in our global parameters.
// A mesh whose colour derivatives follow it may be stored without them, and opens in Inkscape
// as an editable bicubic mesh with our colours.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// Overwrites colU/colV of every node (slit copies and slit ends included) with the rule's
// values computed from the node colours (and, where the rule needs it, positions and knots).
void applyColorRule(GradientMesh& mesh);

// The largest absolute difference (0–1 colour units per unit parameter, max over nodes and
// channels) between the mesh's colour derivatives and the rule's.
double colorRuleDeviation(const GradientMesh& mesh);

// True when the mesh's colour derivatives are the rule's to within `tolerance`.
bool followsColorRule(const GradientMesh& mesh, double tolerance = 1e-12);

}  // namespace gm
