// What a patch's `tensor` attribute changes in what a reader draws: its colours' movement on
// the canvas when the interior control points are replaced by the Coons interior a reader
// assumes without the attribute.
#pragma once

#include "meshcore/gradient_mesh.h"

namespace gm {

// The interior point a reader assumes when a patch has no `tensor` attribute (the Coons patch
// written as a tensor patch, PDF reference §4.6.3), for the corner q[0][0] of the net seen with
// its u and/or v direction mirrored.
Vec2 coonsInterior(const Vec2 (&q)[4][4], bool mirrorU, bool mirrorV);

// The largest colour change (0–1, any channel) at an interior grid of samples when the net
// `withTensor` is drawn with its Coons interior instead: each sample's displacement times the
// colour's gradient on the canvas there. Colour is interpolated bilinearly from the corner
// colours (q[0][0], q[3][0], q[3][3], q[0][3]), which stands in for the bicubic rule's slopes.
// Infinity where the Coons patch folds (its Jacobian vanishes or flips sign).
double tensorColorEffect(const Vec2 (&withTensor)[4][4], const Vec3 (&cornerColor)[4]);

}  // namespace gm
