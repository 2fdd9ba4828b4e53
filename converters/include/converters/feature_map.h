// Pipeline stage 5, feature map (docs/design.md §3, paper §4.4): reparameterises a region's
// triangulation so that parts of the image whose colour gradient changes fast take more of the
// parameter rectangle (and so more patches of a uniform grid). Stretch minimisation after
// Yoshizawa, Belyaev and Seidel 2004, under the 8-D metric of feature coordinates
//   f = (x, y, w·∂c/∂x, w·∂c/∂y)
// x, y in pixels (y down), c = (r, g, b) sRGB 0–1 of a lightly smoothed image, so ∂c/∂x per pixel.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "converters/tri_mesh.h"
#include "meshcore/image.h"

namespace gm {

using FeatureCoords = std::array<double, 8>;

struct FeatureMapOptions {
    double w = 300;          // weight of the colour gradient in the metric (paper: 300)
    int maxIterations = 12;  // linear solves at most
    double eta = 1.0;        // weights are divided by vertex stretch to this power
    double smoothing = 1.0;  // Gaussian sigma, pixels, applied before taking image gradients
    double minGain = 1e-3;   // stop once an iteration lowers stretch by less than this fraction
    // Image-sized, 1 inside the region: pixels outside are left out of the smoothing and the
    // gradients as if transparent, so the region's own outline (object against background) is
    // not a colour feature. Without it the image's alpha alone decides.
    const std::vector<uint8_t>* mask = nullptr;
    // With slits the fixed boundary is not convex: around a slit end (an angle of 360° in the
    // parameter rectangle) a positive-weight solve can fold; the vertices of folded triangles
    // are then frozen and the system solved again, each time a new factorisation. A fold also
    // freezes their neighbours within foldFreezeRings edges, so that the next solve is less
    // likely to fold one ring further out: fewer factorisations, and lower stretch.
    int foldFreezeRings = 2;
};

enum class FeatureMapStop {
    kStretchRose,     // the last iteration did not lower stretch, even with a shortened step
                      // (discarded)
    kSmallGain,       // the last iteration lowered stretch by less than minGain (kept)
    kWouldFold,       // the last iteration folded a triangle at every step length tried
                      // (discarded)
    kMaxIterations,
};

struct FeatureMap {
    ParamMap map;                 // the accepted map with the lowest stretch; never folded
    std::vector<double> stretch;  // total L2 stretch of the input map, then of each accepted
                                  // iteration: strictly decreasing
    int solves = 0;               // iterations run, the discarded last one included
    int factorizations = 0;       // sparse factorisations (an iteration that folds needs more)
    int frozenVertices = 0;       // interior vertices held in place because moving them folded
                                  // (or a neighbour of such a vertex)
    FeatureMapStop stop = FeatureMapStop::kMaxIterations;
};

// Feature coordinates of every TriMesh vertex. The image is smoothed with a Gaussian of the given
// sigma by normalised convolution with alpha (times `mask`, when given) as the weight, so pixels
// of alpha 0 or outside the mask (the background, neighbouring regions) never enter; the
// gradient is sampled bilinearly at each vertex from central differences at pixel centres
// (pixel (x, y) has its centre at (x + .5, y + .5)). Throws gm::Error on an empty image.
std::vector<FeatureCoords> featureCoordinates(const TriMesh& mesh, const RgbaImage& image, double w,
                                              double smoothing,
                                              const std::vector<uint8_t>* mask = nullptr);

// Sander et al.'s normalised total L2 stretch of the map from parameter space onto the feature
// coordinates (1 when the map is a uniform scaling of the metric, larger otherwise). Every
// triangle of `map` must have positive area.
double totalStretch(const TriMesh& mesh, const ParamMap& map,
                    const std::vector<FeatureCoords>& features);

// The stage entry point. `initial` is the topology map (unfolded); the outer loop (so its corners)
// and every hole loop (so the slits) keep their parameters. The first solve uses mean-value
// weights of `initial` itself, which reproduce it; each iteration divides every weight w_ij by
// σ(v_j)^eta, σ the vertex stretch of the current map, and solves again. Where a solve folds triangles (near slit ends: the boundary is then not convex)
// their interior vertices are frozen at their current place and the solve repeated; an iteration
// whose step raises stretch is retried at 1/2, 1/4, 1/8 of its length. Stops when stretch stops
// falling; returns the best map, which is never folded. Throws gm::Error when `initial` does not match the mesh or is folded.
FeatureMap buildFeatureMap(const TriMesh& mesh, const ParamMap& initial, const RgbaImage& image,
                           const FeatureMapOptions& options = {});

}  // namespace gm
