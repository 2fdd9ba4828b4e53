// Linear gradients of flat shapes (FlatShape::gradient) in SVG: the <linearGradient> elements the
// writer emits, and the steps that turn what a reader finds in an SVG gradient (stops as
// written, an axis in the gradient's own space, a transform to the canvas) into the model.
#pragma once

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "meshcore/gradient_mesh.h"
#include "svg_affine.h"

namespace gm {

// Writes each distinct gradient of a document once, as
//   <linearGradient id="gXXXXXXXXXX" gradientUnits="userSpaceOnUse" x1 y1 x2 y2>
//   <stop offset="0" stop-color="#rrggbb"/>...</linearGradient>
// with its ends to 1e-4 px and its offsets with the fewest decimals (4 to 9) that keep them
// strictly increasing. The id is a hash of the element's text: two files inlined in one HTML
// page share an id only for the same gradient (a browser resolves url(#id) to the page's first
// element of that id), and it never takes the form of the mesh ids (mN) or the mesh script's.
class SvgGradientWriter {
public:
    // The id of `g`'s element, appended to `out` first unless the document has it already.
    std::string append(std::string& out, const LinearGradient& g);

private:
    std::unordered_map<std::string, std::string> idByBody_;
    std::unordered_set<std::string> ids_;
};

// A <stop> as SVG reads it: offset clamped to 0–1 and never below the stop before it.
struct SvgStop {
    double offset = 0;
    Vec3 col;
    double opacity = 1;  // stop-opacity, 0–1
};

// Two or more SVG stops as the model's: stops at 0 and at 1 added with the end colours where
// missing (SVG pads with them), of a run of stops at one offset only the first and the last
// kept (those between are never seen), and equal offsets then moved apart by 1e-6 (SVG's hard
// step, the later stop's colour from that offset on). The result may hold up to two stops more
// than kMaxGradientStops; the caller checks.
std::vector<GradientStop> modelGradientStops(const std::vector<SvgStop>& stops);

// The canvas gradient of the SVG axis a→b (gradient space) under `m` (gradient space to canvas),
// exactly. An affine map keeps lines of one colour parallel but may turn them against the axis
// (a non-uniform scale, a skew), so `to` is where the colour ramp ends along the normal of those
// lines, which is m(b) only for a uniform scale with rotation. false when m is not invertible.
bool canvasGradientAxis(Vec2 a, Vec2 b, const SvgAffine& m, Vec2& from, Vec2& to);

// The mean of the gradient's colour over its parameter 0–1: stop colours weighted by the spans
// they bound. What a graded shape's `col` holds.
Vec3 meanGradientColour(const LinearGradient& g);

// The least and greatest dot(p, dir) over closed cubic subpaths in FlatShape's layout: the
// curves' own extent (derivative roots), not their control points'.
void extentAlong(const std::vector<std::vector<Vec2>>& subpaths, Vec2 dir, double& lo, double& hi);

}  // namespace gm
