// The topology-preserving gradient mesh (docs/design.md §2, paper §3).
//
// Conventions, stated once here:
//  - Positions are in pixels of the canvas, x to the right, y DOWN.
//  - Colours are sRGB-encoded values in 0–1 (not linear light): the renderers of SVG, PostScript
//    and PDF interpolate mesh colours in that space.
//  - The parameter domain is a rectangle [u_0,u_C] x [v_0,v_R]. Column index i runs along u,
//    row index j runs along v. Row j is the grid line v = v_j; "above" a row means smaller v
//    (patch row j-1), "below" means larger v (patch row j).
//  - Node derivatives are with respect to the GLOBAL parameters u, v. Patch (i,j) spans
//    [u_i,u_{i+1}] x [v_j,v_{j+1}] and uses them scaled by its own interval lengths, so that
//    inserting a knot never changes the meaning of neighbouring patches. Twists are zero.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace gm {

struct Vec2 {
    double x = 0, y = 0;
};
inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
inline bool operator==(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double norm(Vec2 a) { return std::sqrt(dot(a, a)); }

// A colour (r, g, b), sRGB-encoded 0–1, or a colour derivative.
struct Vec3 {
    double r = 0, g = 0, b = 0;
    double operator[](int k) const { return k == 0 ? r : (k == 1 ? g : b); }
    double& operator[](int k) { return k == 0 ? r : (k == 1 ? g : b); }
};
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.r - b.r, a.g - b.g, a.b - b.b}; }
inline Vec3 operator-(Vec3 a) { return {-a.r, -a.g, -a.b}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.r, s * a.g, s * a.b}; }
inline Vec3 operator*(Vec3 a, double s) { return {s * a.r, s * a.g, s * a.b}; }
inline bool operator==(Vec3 a, Vec3 b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// Everything stored at a grid node: value and first derivatives w.r.t. global u and v.
struct Node {
    Vec2 pos, posU, posV;  // pixels; pixels per unit of u / v
    Vec3 col, colU, colV;  // sRGB 0–1; per unit of u / v
};
inline bool operator==(const Node& a, const Node& b) {
    return a.pos == b.pos && a.posU == b.posU && a.posV == b.posV && a.col == b.col &&
           a.colU == b.colU && a.colV == b.colV;
}

// A u-derivative used at one slit end by the patch on the slit side ABOVE the row; the patch
// below the row uses its negation (the ±d rule of paper §3), so the hole outline passes
// smoothly through the slit end.
struct SlitEnd {
    Vec2 posU;
    Vec3 colU;
};

// A hole: grid row `row` is cut open from column `i0` to column `i1` (0 < i0 < i1 < C,
// 0 < row < R). Nodes strictly between i0 and i1 exist twice: the mesh's node array holds the
// copy used by the patches above the row; `below[k]` is the copy of column i0+1+k used by the
// patches below. End nodes i0 and i1 are shared, except for their u-derivative on the slit side.
struct Slit {
    int row = 0, i0 = 0, i1 = 0;
    std::vector<Node> below;  // size i1 - i0 - 1
    SlitEnd left, right;      // at column i0 and i1 (the above-side derivative)
};

// A break in the u-derivative at one corner of one patch: that patch uses posU/colU instead of
// the node's. Hole-free legacy pieces cut from a slit mesh need these where a slit ended on
// their boundary row (the kink between the outline and the former slit side); elsewhere there
// are none.
struct CornerTangent {
    int i = 0, j = 0;  // the patch
    int a = 0, b = 0;  // its corner: a = 0 at u_i, 1 at u_{i+1}; b = 0 at v_j, 1 at v_{j+1}
    Vec2 posU;
    Vec3 colU;
};

// How a mesh's colour varies inside its patches between the node colours.
//  - Hermite: free colour derivatives, the node's colU/colV (Ferguson patches, paper §3). The
//    smallest raster error per patch, but no vector format stores such slopes.
//  - Bicubic: the SVG 2 `type="bicubic"` rule exactly as Inkscape computes it
//    (meshcore/bicubic_colors.h): every patch's colour slopes follow from node colours and
//    corner positions alone; colU/colV are ignored (kept zero). One mesh patch is one SVG patch
//    that Inkscape draws in our colours.
enum class ColorModel { Hermite, Bicubic };

class GradientMesh {
public:
    GradientMesh() = default;
    // A C x R patch grid with uniform knots 0..C and 0..R and zeroed nodes.
    GradientMesh(int columns, int rows);

    int columns() const { return static_cast<int>(u.size()) - 1; }  // C: patches along u
    int rows() const { return static_cast<int>(v.size()) - 1; }     // R: patches along v
    int patchCount() const { return columns() * rows(); }
    int holeCount() const { return static_cast<int>(slits.size()); }

    // The node at column i (0..C), row j (0..R): for slit interiors, the copy above the row.
    Node& node(int i, int j) { return nodes[static_cast<size_t>(j) * (columns() + 1) + i]; }
    const Node& node(int i, int j) const {
        return nodes[static_cast<size_t>(j) * (columns() + 1) + i];
    }

    std::vector<double> u, v;            // knots, strictly increasing: C+1 and R+1 values
    std::vector<Node> nodes;             // (C+1)(R+1), row-major: index j*(C+1)+i
    std::vector<Slit> slits;             // holes
    std::vector<CornerTangent> tangents;  // u-derivative breaks (legacy pieces only)
    ColorModel colorModel = ColorModel::Hermite;
};

bool operator==(const Slit& a, const Slit& b);
bool operator==(const CornerTangent& a, const CornerTangent& b);
bool operator==(const GradientMesh& a, const GradientMesh& b);

// A colour that varies along one direction (SVG's linearGradient with its defaults: pad spread,
// interpolation in sRGB; PDF's axial shading extended at both ends). A point p lies at
// t = (p - from)·(to - from) / |to - from|², clamped to [0, 1]; its colour interpolates linearly,
// per sRGB channel, between the two stops whose offsets enclose t. Offsets run strictly
// increasing from 0 (the first stop) to 1 (the last); 2 to kMaxGradientStops stops.
struct GradientStop {
    double offset = 0;  // 0–1
    Vec3 col;           // sRGB 0–1
};
struct LinearGradient {
    Vec2 from, to;  // canvas pixels; not the same point
    std::vector<GradientStop> stops;
    // The colour at canvas point p.
    Vec3 colourAt(Vec2 p) const;
};
constexpr size_t kMaxGradientStops = 16;
bool operator==(const GradientStop& a, const GradientStop& b);
bool operator==(const LinearGradient& a, const LinearGradient& b);

// A region of one colour: closed cubic Bézier subpaths (an outer boundary and its holes), canvas
// pixels, filled with the nonzero rule; holes wind opposite to the boundary around them, so that
// the even-odd rule fills the same area. Subpath k's points are 3n, n >= 1: segment m runs from
// points[3m] via the handles points[3m+1], points[3m+2] to points[3m+3], the last one back to
// points[0] (closed implicitly).
//
// A stroked shape (strokeWidth > 0) is a line of one colour instead: each subpath is a
// centreline of 3n + 1 points, n >= 1 (segment m runs from points[3m] via points[3m+1],
// points[3m+2] to points[3m+3]), open unless its last point equals its first; it is painted
// `strokeWidth` pixels wide with round caps and round joins, and nothing is filled.
//
// A filled shape may be painted with a linear gradient instead of its one colour: see
// LinearGradient; `col` then holds a mean colour of the gradient, for readers that want one.
struct FlatShape {
    Vec3 col;          // sRGB 0–1
    double alpha = 1;  // 0–1, straight; multiplies the gradient's colours too
    std::vector<std::vector<Vec2>> subpaths;
    double strokeWidth = 0;  // pixels; 0: a filled shape
    bool stroked() const { return strokeWidth > 0; }
    LinearGradient gradient;  // no stops: painted in `col`
    bool graded() const { return !gradient.stops.empty(); }
    // Paint order: the shape is painted after the first `layer` meshes of its document and
    // before the others (0: below every mesh, meshes.size(): above all).
    size_t layer = 0;
};
bool operator==(const FlatShape& a, const FlatShape& b);

// A closed polygon as a FlatShape subpath: one cubic per side, its handles at the side's thirds.
std::vector<Vec2> polygonAsCubics(const std::vector<Vec2>& polygon);

// Several meshes on a canvas; painted in order. Flat shapes, when there are any, are painted in
// their list order, each between the meshes its `layer` names (non-decreasing along the list).
struct Document {
    int width = 0, height = 0;  // canvas, pixels
    std::vector<GradientMesh> meshes;
    std::vector<FlatShape> shapes;
};
bool operator==(const Document& a, const Document& b);

// The Hermite data of one patch in its local parameters s, t ∈ [0,1]: corner[a][b] is at
// s = a, t = b; derivatives are already scaled by the patch's Δu, Δv. This is what every
// consumer (evaluation, rendering, Bézier conversion, writers) works from.
struct HermiteCorner {
    Vec2 pos, posS, posT;
    Vec3 col, colS, colT;
};
struct PatchHermite {
    HermiteCorner corner[2][2];
};

// Resolves node copies at slits, slit-end ±d tangents and corner tangent breaks; for a Bicubic
// mesh the colour slopes are the rule's (bicubicPatchSlopes).
PatchHermite patchHermite(const GradientMesh& mesh, int i, int j);

}  // namespace gm
