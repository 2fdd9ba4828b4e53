// Hermite meshes for consumers that only have the bicubic rule (SVG 2 type="bicubic",
// Inkscape): the node colours refitted in ColorModel::Bicubic so that the rule's colours come
// closest to what the Hermite mesh shows, one patch per patch, geometry unchanged.
#pragma once

#include "converters/colors.h"
#include "meshcore/gradient_mesh.h"

namespace gm {

struct BicubicConversion {
    Document doc;        // every mesh Bicubic
    int refitted = 0;    // meshes that were Hermite
    FitError error;      // the result's render against the input's, over the input's coverage
};

// True when some mesh of `doc` is Hermite.
bool hasHermiteMeshes(const Document& doc);

// `doc` with every Hermite mesh refitted (FitBicubic) to our render of `doc`, over the pixels
// where that mesh is on top; Bicubic meshes are kept as they are. Two renders and one fit per
// Hermite mesh (threads 0: all hardware threads).
BicubicConversion toBicubicModel(const Document& doc, int threads = 0);

}  // namespace gm
