// The colour fit of a Bicubic mesh (ColorModel::Bicubic): node colours only, every slope by the
// SVG 2 bicubic rule (meshcore/bicubic_colors.h).
#pragma once

#include <vector>

#include "converters/region.h"
#include "meshcore/gradient_mesh.h"
#include "meshcore/image.h"
#include "meshcore/render.h"

namespace gm {

// Nonlinear least squares over the pixels of `region` whose render sample names mesh
// `meshIndex`: Gauss–Newton, each round solving the linear problem the rule gives at its
// current branches (limiter and extremum tests per corner and channel), keeping the round with
// the lowest true cost. A Tikhonov pull of `regularization` (relative to the mean pixel weight
// of a colour) toward the start colours keeps colours without pixels in place. With
// `subPixelEdgePull` > 0 the two ends of a patch edge of length L < 1 px are pulled toward one
// colour with that weight (same unit) times 1 − L. `mesh` (Bicubic) holds the start colours on
// entry and the best found on return.
void fitBicubicColors(GradientMesh& mesh, const RgbaImage& image, const Region& region,
                      const std::vector<PixelSample>& samples, int meshIndex,
                      double regularization, double subPixelEdgePull);

}  // namespace gm
