// Pipeline stage 3, triangulate (docs/design.md §3, paper §4.2): a constrained Delaunay
// triangulation of a region whose samples are denser where the image is salient. Output as in
// tri_mesh.h.
#pragma once

#include <vector>

#include "converters/corners.h"
#include "converters/region.h"
#include "converters/tri_mesh.h"
#include "meshcore/image.h"

namespace gm {

struct TriangulateOptions {
    double sampleFraction = 0.05;    // interior samples per region pixel (paper: e.g. 0.1)
    double saliencyWeight = 2.0;     // sample density ∝ 1 + saliencyWeight · min(saliency /
    double saliencyCap = 4.0;        // mean saliency, saliencyCap): edges get denser, not solid
    double boundaryClearance = 0.4;  // no samples closer to a loop than this × the mean
                                     // sample spacing 1/√sampleFraction (never under 0.5 px)
};

struct TriangulateStats {
    int samplesPlaced = 0;   // by error diffusion, over the region less a band along its loops
    int samplesKept = 0;     // of those, in the triangulation
    int loopVertices = 0;    // outer and hole loops, after splitting edges longer than the spacing
    int steinerPoints = 0;   // added to split triangles or edges that would map to zero area
};

// Compass filter with Sobel weights (Matusik et al. 2005): per pixel the largest, over the
// compass directions, colour-vector length of the Sobel response. Neighbours outside the region
// count as the centre pixel, so the region's own outline is not salient. width*height, 0 outside
// the region. Throws gm::Error if the image and region sizes differ.
std::vector<float> compassSaliency(const RgbaImage& image, const Region& region);

// Sample positions (pixel centres) by Jarvis–Judice–Ninke error diffusion (serpentine) of a
// density that sums to sampleFraction × region.pixelCount and grows with saliency.
std::vector<Vec2> placeSamples(const Region& region, const std::vector<float>& saliency,
                               const TriangulateOptions& options);

// The triangulation of the region: the outer and hole loops (edges longer than the sample
// spacing split evenly) as constraints, the samples inside, only faces inside the region.
// Nothing maps to zero area later: no triangle has all three vertices on one rectangle side
// (corners belong to both their sides) or on one hole loop, and no edge that is not a loop edge
// joins two vertices of one side or of one hole loop; Steiner points split any such triangle or
// edge. outerLoop starts at corners.index[0]. Throws gm::Error on mismatched sizes or loops
// that cross.
TriMesh triangulateRegion(const RgbaImage& image, const Region& region,
                          const RegionCorners& corners, const TriangulateOptions& options = {},
                          TriangulateStats* stats = nullptr);

}  // namespace gm
