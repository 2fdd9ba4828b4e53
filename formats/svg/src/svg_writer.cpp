#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "formats/svg.h"
#include "meshcore/bezier_patch.h"
#include "meshcore/color_subdivision.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"
#include "meshcore/validate.h"
#include "svg_fallback_layer.h"
#include "svg_grid_outset.h"
#include "svg_number.h"
#include "svg_shapes.h"
#include "svg_script.h"
#include "svg_tensor_effect.h"
#include "svg_patch_grid.h"

namespace gm {

namespace {

// A grid of Bézier patches (nu × nv, patch (a, b) at b*nu + a) as a meshgradient grid. Shared
// edges are taken from one of the two patches (they agree up to rounding).
SvgPatchGrid gridFromPatches(const std::vector<BezierPatch>& patches, int nu, int nv) {
    SvgPatchGrid g;
    g.resize(nu, nv);
    for (int b = 0; b < nv; ++b) {
        for (int a = 0; a < nu; ++a) {
            const BezierPatch& p = patches[static_cast<size_t>(b) * nu + a];
            if (a == 0 && b == 0) {
                g.P(0, 0) = p.p[0][0];
                g.C(0, 0) = p.c[0][0];
            }
            if (b == 0) {
                g.P(a + 1, 0) = p.p[3][0];
                g.C(a + 1, 0) = p.c[3][0];
                g.H(a, 0) = {p.p[1][0], p.p[2][0]};
            }
            if (a == 0) {
                g.P(0, b + 1) = p.p[0][3];
                g.C(0, b + 1) = p.c[0][3];
                g.V(0, b) = {p.p[0][1], p.p[0][2]};
            }
            g.P(a + 1, b + 1) = p.p[3][3];
            g.C(a + 1, b + 1) = p.c[3][3];
            g.H(a, b + 1) = {p.p[1][3], p.p[2][3]};
            g.V(a + 1, b) = {p.p[3][1], p.p[3][2]};
            g.tensor[g.patchIndex(a, b)] = {p.p[1][1], p.p[2][1], p.p[2][2], p.p[1][2]};
            g.tensorSet[g.patchIndex(a, b)] = 1;
        }
    }
    return g;
}

std::vector<BezierPatch> meshPatches(const GradientMesh& mesh) {
    std::vector<BezierPatch> out;
    out.reserve(static_cast<size_t>(mesh.patchCount()));
    for (int j = 0; j < mesh.rows(); ++j)
        for (int i = 0; i < mesh.columns(); ++i) out.push_back(toBezier(mesh, i, j));
    return out;
}

// Exact mode: how many pieces each patch column (ku) and patch row (kv) of a hole-free mesh is
// split into: the most any of its patches needs (exactColorPieces).
struct ExactSplits {
    std::vector<int> ku, kv;
    int64_t svgPatches() const {
        int64_t nu = 0, nv = 0;
        for (int k : ku) nu += k;
        for (int k : kv) nv += k;
        return nu * nv;
    }
    int largest() const {
        int m = 1;
        for (int k : ku) m = std::max(m, k);
        for (int k : kv) m = std::max(m, k);
        return m;
    }
};

ExactSplits exactSplits(const GradientMesh& mesh, double tolerance, double minPiece) {
    const int C = mesh.columns(), R = mesh.rows();
    ExactSplits sp{std::vector<int>(static_cast<size_t>(C), 1), std::vector<int>(static_cast<size_t>(R), 1)};
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < C; ++i) {
            const auto [ks, kt] = exactColorPieces(toBezier(mesh, i, j), tolerance, minPiece);
            sp.ku[i] = std::max(sp.ku[i], ks);
            sp.kv[j] = std::max(sp.kv[j], kt);
        }
    return sp;
}

// Exact mode: patch column i split ku[i] times, patch row j kv[j] times.
SvgPatchGrid refinedGrid(const std::vector<BezierPatch>& base, int C, int R,
                         const ExactSplits& sp) {
    const std::vector<int>&ku = sp.ku, &kv = sp.kv;
    std::vector<int> u0(static_cast<size_t>(C) + 1, 0), v0(static_cast<size_t>(R) + 1, 0);
    for (int i = 0; i < C; ++i) u0[i + 1] = u0[i] + ku[i];
    for (int j = 0; j < R; ++j) v0[j + 1] = v0[j] + kv[j];
    const int nu = u0[C], nv = v0[R];
    std::vector<BezierPatch> fine(static_cast<size_t>(nu) * nv);
    for (int j = 0; j < R; ++j) {
        for (int i = 0; i < C; ++i) {
            const BezierPatch& p = base[static_cast<size_t>(j) * C + i];
            for (int b = 0; b < kv[j]; ++b) {
                for (int a = 0; a < ku[i]; ++a) {
                    fine[static_cast<size_t>(v0[j] + b) * nu + u0[i] + a] =
                        subPatch(p, double(a) / ku[i], double(a + 1) / ku[i],
                                 double(b) / kv[j], double(b + 1) / kv[j]);
                }
            }
        }
    }
    return gridFromPatches(fine, nu, nv);
}

// Compact syntax: a patch's tensor (interior) points are written only when one lies further
// than this (px) from the Coons interior Inkscape assumes without them. They move the inside
// of a patch, not its edges or colours, so leaving the small ones out is invisible in
// Inkscape, and our reader does not keep them.
constexpr double kTensorTolerance = 1.0;
// ... and when, drawn with the Coons interior, the patch's colours would move by more than
// this (0–1; tensorColorEffect), or the Coons patch folds. Large patches of a whole image
// mostly carry gentle colour, where a moved inside shows no difference.
constexpr double kTensorColorTolerance = 4.0 / 255;

// How numbers are written: decimals per coordinate, and whether separators are left out where
// the grammar allows it (before a minus sign, and after a path command letter).
struct NumberSyntax {
    int decimals = kSvgDecimalsExact;
    bool compact = false;
};

// Compact syntax: an edge's handles (relative to its start) are written to 1/10 px. A handle
// moves its curve by at most 4/9 of its own displacement (the peak of 3t(1-t)^2), so by 0.023
// px at most, and shared edges are written once, so neighbours still meet exactly.
constexpr double kCompactHandleSteps = 10;
// ... and an edge inside a mesh whose handles lie within this many px of its chord's thirds is
// written as a line: its curve moves by 4/9 of that at most (0.22 px), and a line costs a third
// of the numbers. Not on a mesh's boundary, which its outline path draws with its own handles.
constexpr double kCompactInnerLineTolerance = 0.5;

// The points of one path command after its letter: " x,y x,y" (exact), or numbers separated
// only where needed, "1.5 2-.3" (compact).
void appendPoints(std::string& out, const Vec2* begin, const Vec2* end, const NumberSyntax& syntax);
void appendPoints(std::string& out, std::initializer_list<Vec2> points, const NumberSyntax& syntax) {
    appendPoints(out, points.begin(), points.end(), syntax);
}

void appendPair(std::string& out, Vec2 d) {
    appendSvgNumber(out, d.x);
    out += ',';
    appendSvgNumber(out, d.y);
}

Vec2 printed(Vec2 d, int decimals = kSvgDecimalsExact) {
    return {svgPrintedValue(d.x, decimals), svgPrintedValue(d.y, decimals)};
}

// A handle's offset from its edge's start as written (and read back).
Vec2 handleOffset(Vec2 d, const NumberSyntax& syntax) {
    if (!syntax.compact) return printed(d, syntax.decimals);
    const double q = kCompactHandleSteps;
    return printed({std::round(d.x * q) / q, std::round(d.y * q) / q}, syntax.decimals);
}

void appendPoints(std::string& out, const Vec2* begin, const Vec2* end, const NumberSyntax& syntax) {
    if (!syntax.compact) {
        for (const Vec2* p = begin; p != end; ++p) {
            out += ' ';
            appendPair(out, *p);
        }
        return;
    }
    // A number needs no separator before it when it starts with '-', or with '.' after a
    // number that already has its point ("1.5.25" is 1.5 and .25 in the path grammar).
    bool first = true, previousHasPoint = false;
    std::string text;
    for (const Vec2* p = begin; p != end; ++p)
        for (double v : {p->x, p->y}) {
            text.clear();
            appendSvgNumber(text, v, true, syntax.decimals);
            const bool joins = text[0] == '-' || (text[0] == '.' && previousHasPoint);
            if (!first && !joins) out += ' ';
            out += text;
            previousHasPoint = text.find_first_of(".eE") != std::string::npos &&
                               text.find_first_of("eE") == std::string::npos;
            first = false;
        }
}

void appendColor(std::string& out, Vec3 c) {
    static const char* hex = "0123456789abcdef";
    out += '#';
    for (int k = 0; k < 3; ++k) {
        const long v = std::lround(std::min(1.0, std::max(0.0, c[k])) * 255.0);
        out += hex[v >> 4];
        out += hex[v & 15];
    }
}

bool nearlyEqual(Vec2 a, Vec2 b, double tol) {
    return std::fabs(a.x - b.x) <= tol && std::fabs(a.y - b.y) <= tol;
}

// Whether an edge from `start` to `end` is written as a line: its handles within
// `lineTolerance` of the chord's thirds.
bool writtenAsLine(Vec2 start, Vec2 h1, Vec2 h2, Vec2 end, double lineTolerance) {
    const Vec2 chord = end - start;
    return nearlyEqual(h1, start + (1.0 / 3) * chord, lineTolerance) &&
           nearlyEqual(h2, start + (2.0 / 3) * chord, lineTolerance);
}

// One <stop>: an edge from `start` (where the reader stands) through handles h1, h2 to `end`,
// or a line. Writes offsets relative to `start` as the reader will have reconstructed it, so
// rounding never accumulates along the grid; returns the end point the reader reconstructs.
Vec2 appendStop(std::string& out, Vec2 start, Vec2 h1, Vec2 h2, Vec2 end, bool closing,
                const Vec3* color, const NumberSyntax& syntax, bool line) {
    out += "<stop path=\"";
    const Vec2 d = end - start;
    const Vec2 reached = closing ? end : start + printed(d, syntax.decimals);
    if (line) {
        out += 'l';
        if (!closing) appendPoints(out, {d}, syntax);
    } else {
        out += 'c';
        const Vec2 a = handleOffset(h1 - start, syntax), b = handleOffset(h2 - start, syntax);
        if (closing)
            appendPoints(out, {a, b}, syntax);
        else
            appendPoints(out, {a, b, d}, syntax);
    }
    out += '"';
    if (color) {
        out += " stop-color=\"";
        appendColor(out, *color);
        out += '"';
    }
    out += "/>";
    return reached;
}

// Writes one meshgradient patch by patch. Corners are tracked as the reader reconstructs them
// (each edge written relative to where the previous one ended, at the precision written).
class MeshGradientWriter {
public:
    MeshGradientWriter(std::string& out, const SvgPatchGrid& g, const NumberSyntax& syntax)
        : out_(out),
          g_(g),
          syntax_(syntax),
          dec_(syntax.decimals),
          // The tensor attribute is left out when the Coons interior Inkscape would assume is
          // the same point at the precision written (exact syntax), or within kTensorTolerance
          // px (compact syntax: the interior points move the patch's inside, not its edges).
          tensorTol_(syntax.compact ? kTensorTolerance : 1.5e-4),
          rec_(static_cast<size_t>(g.columns + 1) * (g.rows + 1)) {}

    // `attributes`: more attributes for the meshgradient element, each after a space.
    void write(const std::string& id, bool bicubic, const std::string& attributes) {
        R(0, 0) = printed(g_.P(0, 0), dec_);
        out_ += "<meshgradient id=\"" + id + "\" gradientUnits=\"userSpaceOnUse\" x=\"";
        appendSvgNumber(out_, g_.P(0, 0).x, false, dec_);
        out_ += "\" y=\"";
        appendSvgNumber(out_, g_.P(0, 0).y, false, dec_);
        out_ += '"';
        if (bicubic) out_ += " type=\"bicubic\"";
        out_ += attributes;
        out_ += ">\n";
        for (int r = 0; r < g_.rows; ++r) {
            out_ += "<meshrow>\n";
            for (int c = 0; c < g_.columns; ++c) patch(c, r);
            out_ += "</meshrow>\n";
        }
        out_ += "</meshgradient>\n";
    }

private:
    Vec2& R(int c, int r) { return rec_[static_cast<size_t>(r) * (g_.columns + 1) + c]; }

    // Whether the grid's edges are written as lines: their handles within a tolerance of their
    // chord's thirds, the rounding step alone on the mesh's boundary. Decided on the grid's
    // own points, so that the patch that writes an edge and the one that reads it agree.
    double lineTolerance(bool boundary) const {
        if (!syntax_.compact) return 1e-6;
        return boundary ? 0.5 / svgStepsPerUnit(dec_) : kCompactInnerLineTolerance;
    }
    bool hLine(int c, int r) const {  // from P(c,r) to P(c+1,r)
        return writtenAsLine(g_.P(c, r), g_.H(c, r)[0], g_.H(c, r)[1], g_.P(c + 1, r),
                             lineTolerance(r == 0 || r == g_.rows));
    }
    bool vLine(int c, int r) const {  // from P(c,r) to P(c,r+1)
        return writtenAsLine(g_.P(c, r), g_.V(c, r)[0], g_.V(c, r)[1], g_.P(c, r + 1),
                             lineTolerance(c == 0 || c == g_.columns));
    }

    void patch(int c, int r) {
        const SvgPatchGrid& g = g_;
        stops_.clear();
        if (r == 0) {  // top, from (c,0) to (c+1,0)
            const auto& h = g.H(c, 0);
            R(c + 1, 0) = appendStop(stops_, R(c, 0), h[0], h[1], g.P(c + 1, 0), false,
                                     c == 0 ? &g.C(c, 0) : nullptr, syntax_, hLine(c, 0));
        }
        {  // right, from (c+1,r) to (c+1,r+1)
            const auto& h = g.V(c + 1, r);
            R(c + 1, r + 1) =
                appendStop(stops_, R(c + 1, r), h[0], h[1], g.P(c + 1, r + 1), false,
                           r == 0 ? &g.C(c + 1, r) : nullptr, syntax_, vLine(c + 1, r));
        }
        {  // bottom, from (c+1,r+1) to (c,r+1); closes the patch unless c == 0
            const auto& h = g.H(c, r + 1);
            const Vec2 e = appendStop(stops_, R(c + 1, r + 1), h[1], h[0], g.P(c, r + 1), c > 0,
                                      &g.C(c + 1, r + 1), syntax_, hLine(c, r + 1));
            if (c == 0) R(0, r + 1) = e;
        }
        if (c == 0) {  // left, from (0,r+1) to (0,r): always closing
            const auto& h = g.V(0, r);
            appendStop(stops_, R(0, r + 1), h[1], h[0], g.P(0, r), true, &g.C(0, r + 1), syntax_,
                       vLine(0, r));
        }
        out_ += "<meshpatch";
        if (g.tensorSet[g.patchIndex(c, r)]) tensor(c, r);
        out_ += '>';
        out_ += stops_;
        out_ += syntax_.compact ? "</meshpatch>" : "</meshpatch>\n";
    }

    // Whether the patch drawn with interior points `t` differs from the Coons patch of its
    // edges `q` (as read back) by more than the tolerances: positions, and in the compact
    // syntax also colours.
    bool tensorShows(const Vec2 (&q)[4][4], const std::array<Vec2, 4>& t, int c, int r) const {
        const Vec2 coons[4] = {coonsInterior(q, false, false), coonsInterior(q, true, false),
                               coonsInterior(q, true, true), coonsInterior(q, false, true)};
        const Vec2 base[4] = {q[0][0], q[3][0], q[3][3], q[0][3]};
        bool differs = false;
        for (int k = 0; k < 4; ++k)
            if (!nearlyEqual(printed(t[k] - base[k], dec_), coons[k] - base[k], tensorTol_))
                differs = true;
        if (!differs || !syntax_.compact) return differs;
        Vec2 net[4][4];
        std::copy(&q[0][0], &q[0][0] + 16, &net[0][0]);
        net[1][1] = t[0], net[2][1] = t[1], net[2][2] = t[2], net[1][2] = t[3];
        const Vec3 colors[4] = {g_.C(c, r), g_.C(c + 1, r), g_.C(c + 1, r + 1), g_.C(c, r + 1)};
        return tensorColorEffect(net, colors) > kTensorColorTolerance;
    }

    // The patch's tensor attribute, unless it would change nothing: the reconstructed control
    // net's Coons interior (what Inkscape assumes) compared with the interior written.
    void tensor(int c, int r) {
        const SvgPatchGrid& g = g_;
        Vec2 q[4][4];
        const Vec2 c00 = R(c, r), c30 = R(c + 1, r), c33 = R(c + 1, r + 1), c03 = R(c, r + 1);
        q[0][0] = c00;
        q[3][0] = c30;
        q[3][3] = c33;
        q[0][3] = c03;
        // Each edge's handles as the reader gets them, from the corner it was written from.
        const auto asRead = [&](Vec2 start, Vec2 h1, Vec2 h2, Vec2 end, bool line, Vec2& a,
                                Vec2& b) {
            if (line) {
                a = start + (1.0 / 3) * (end - start), b = start + (2.0 / 3) * (end - start);
            } else {
                a = start + handleOffset(h1 - start, syntax_);
                b = start + handleOffset(h2 - start, syntax_);
            }
        };
        asRead(c00, g.H(c, r)[0], g.H(c, r)[1], c30, hLine(c, r), q[1][0], q[2][0]);
        asRead(c30, g.V(c + 1, r)[0], g.V(c + 1, r)[1], c33, vLine(c + 1, r), q[3][1], q[3][2]);
        asRead(c33, g.H(c, r + 1)[1], g.H(c, r + 1)[0], c03, hLine(c, r + 1), q[2][3], q[1][3]);
        asRead(c03, g.V(c, r)[1], g.V(c, r)[0], c00, vLine(c, r), q[0][2], q[0][1]);
        const auto& t = g.tensor[g.patchIndex(c, r)];
        const Vec2 base[4] = {c00, c30, c33, c03};
        if (!tensorShows(q, t, c, r)) return;
        out_ += " tensor=\"";
        const size_t at = out_.size();
        appendPoints(out_, {t[0] - base[0], t[1] - base[1], t[2] - base[2], t[3] - base[3]},
                     syntax_);
        if (!syntax_.compact) out_.erase(at, 1);  // no space before the first pair
        out_ += '"';
    }

    std::string& out_;
    const SvgPatchGrid& g_;
    const NumberSyntax& syntax_;
    const int dec_;
    const double tensorTol_;
    std::vector<Vec2> rec_;  // corners as the reader reconstructs them
    std::string stops_;
};

// Writes `g` grown by kMeshOutset beyond its outline (svg_grid_outset.h), except along the
// edges `held`, and marks the element so that readers can undo it.
void appendMeshGradient(std::string& out, SvgPatchGrid g, const std::string& id, bool bicubic,
                        const NumberSyntax& syntax, const HeldEdges& held) {
    std::string attributes;
    if (canOutsetGrid(g)) {
        outsetGrid(g, kMeshOutset, held);
        attributes += " data-outset=\"";
        appendSvgNumber(attributes, kMeshOutset, false);
        attributes += '"';
        if (!held.empty()) attributes += " data-outset-held=\"" + heldEdgesText(held) + '"';
    }
    MeshGradientWriter(out, g, syntax).write(id, bicubic, attributes);
}

// Where a piece of a slit mesh meets the piece above or below it outside the holes: the patch
// columns whose top (bottom) edge is such a seam.
struct PieceSeams {
    std::vector<int> top, bottom;
};

// A piece's seams as the edges its grid must hold: the patch columns of the base grid, or of
// the grid refined by `splits` (exact mode), where a base column becomes ku of them.
HeldEdges heldSeams(const PieceSeams& seams, const ExactSplits* splits = nullptr) {
    if (!splits) return {seams.top, seams.bottom};
    std::vector<int> first{0};
    for (int k : splits->ku) first.push_back(first.back() + k);
    auto refine = [&](const std::vector<int>& columns) {
        std::vector<int> fine;
        for (int i : columns)
            for (int f = first[static_cast<size_t>(i)]; f < first[static_cast<size_t>(i) + 1]; ++f)
                fine.push_back(f);
        return fine;
    };
    return {refine(seams.top), refine(seams.bottom)};
}

// Patch columns whose edge on grid row `row` of `mesh` lies outside every slit of that row.
std::vector<int> seamColumns(const GradientMesh& mesh, int row) {
    std::vector<int> out;
    for (int i = 0; i < mesh.columns(); ++i) {
        bool inSlit = false;
        for (const Slit& s : mesh.slits) inSlit = inSlit || (s.row == row && i >= s.i0 && i < s.i1);
        if (!inSlit) out.push_back(i);
    }
    return out;
}

// One PieceSeams per piece of splitIntoLegacyMeshes(mesh), in its order.
std::vector<PieceSeams> legacySeams(const GradientMesh& mesh) {
    std::vector<int> cuts;
    for (const Slit& s : mesh.slits) cuts.push_back(s.row);
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    std::vector<PieceSeams> out(cuts.size() + 1);
    for (size_t k = 0; k < cuts.size(); ++k) {
        out[k].bottom = seamColumns(mesh, cuts[k]);
        out[k + 1].top = out[k].bottom;
    }
    return out;
}

double signedArea(const std::vector<Vec2>& polygon) {
    double a = 0;
    for (size_t k = 0; k < polygon.size(); ++k) {
        const Vec2 p = polygon[k], q = polygon[(k + 1) % polygon.size()];
        a += p.x * q.y - q.x * p.y;
    }
    return 0.5 * a;
}

// A band around the patch edges of grid row `row` at `columns`, as extra subpaths of a piece's
// fill path, wound like its outline (`orientation`: the outline's signed area sign). Inkscape
// paints a mesh only inside its patches, without anti-aliasing there, and anti-aliases the fill
// path: two pieces whose paths both reach across their shared edge each paint the pixels whose
// centres they cover, fully, so no seam shows between them. The band reaches 1 px beyond the
// edge's control polygon on both sides.
// Runs of consecutive patch columns: [first, last] pairs.
std::vector<std::pair<int, int>> columnRuns(const std::vector<int>& columns) {
    std::vector<std::pair<int, int>> runs;
    for (int i : columns) {
        if (!runs.empty() && runs.back().second + 1 == i)
            runs.back().second = i;
        else
            runs.emplace_back(i, i);
    }
    return runs;
}

// How far the band must reach from the chord of patch edge (i, row): 1 px beyond the edge's
// control polygon; and the chord's unit normal (zero for a degenerate edge).
double edgeReach(const SvgPatchGrid& g, int i, int row, Vec2& normal) {
    const Vec2 a = g.P(i, row), d = g.P(i + 1, row) - a;
    const double len = norm(d);
    normal = len > 0 ? Vec2{-d.y / len, d.x / len} : Vec2{};
    double reach = 1.0;
    for (Vec2 h : {g.H(i, row)[0], g.H(i, row)[1]})
        reach = std::max(reach, 1.0 + std::fabs(dot(h - a, normal)));
    return reach;
}

// The unit tangent of the piece's side at its corner (k, row), k = 0 or C, row = 0 or R: along
// the side's first handle into the piece (zero when the side is degenerate).
Vec2 sideTangent(const SvgPatchGrid& g, int k, int row) {
    const Vec2 p = g.P(k, row);
    Vec2 d = row == 0 ? g.V(k, 0)[0] - p : g.V(k, row - 1)[1] - p;
    if (!(norm(d) > 0)) d = (row == 0 ? g.P(k, 1) : g.P(k, row - 1)) - p;
    return norm(d) > 0 ? (1.0 / norm(d)) * d : Vec2{};
}

std::vector<std::vector<Vec2>> seamBandPolygons(const SvgPatchGrid& g, int row,
                                                const std::vector<int>& columns,
                                                double orientation) {
    std::vector<std::vector<Vec2>> polygons;
    for (const auto& [first, last] : columnRuns(columns)) {
        // One polygon per run: the grid row's corners offset both ways along their normals.
        std::vector<Vec2> ahead, behind;
        for (int k = first; k <= last + 1; ++k) {
            Vec2 n{};
            double reach = 1.0;
            std::vector<Vec2> edgeNormals;
            for (int e : {k - 1, k}) {
                if (e < first || e > last) continue;
                Vec2 ne;
                reach = std::max(reach, edgeReach(g, e, row, ne));
                if (norm(ne) > 0) edgeNormals.push_back(ne);
                n = n + ne;
            }
            if (!(norm(n) > 0)) continue;
            n = (1.0 / norm(n)) * n;
            // At a bend the offset corner moves further, so that both edges keep their reach.
            double slack = 1.0;
            for (Vec2 ne : edgeNormals) slack = std::min(slack, std::max(0.5, dot(n, ne)));
            // Where the row meets the mesh's outline, the band ends along the outline's side
            // (its tangent), not across it: a band reaching past the outline would widen the
            // anti-aliased edge there (a notch in browsers). Into the neighbouring piece, whose
            // side this piece does not know, it reaches 1 px along this side's continuation.
            Vec2 toAhead = (reach / slack) * n, toBehind = -1.0 * toAhead;
            if (k == 0 || k == g.columns) {
                const Vec2 t = sideTangent(g, k, row);
                const double along = dot(t, n);
                if (std::fabs(along) > 0.1) {
                    const double r = reach / slack / std::max(std::fabs(along), 0.5);
                    const Vec2 own = r * t, other = -std::min(r, 1.0) * t;
                    toAhead = along > 0 ? own : other;
                    toBehind = along > 0 ? other : own;
                }
            }
            ahead.push_back(g.P(k, row) + toAhead);
            behind.push_back(g.P(k, row) + toBehind);
        }
        if (ahead.size() < 2) continue;
        std::vector<Vec2> polygon = ahead;
        polygon.insert(polygon.end(), behind.rbegin(), behind.rend());
        if (signedArea(polygon) * orientation < 0) std::reverse(polygon.begin(), polygon.end());
        polygons.push_back(std::move(polygon));
    }
    return polygons;
}

// The boundary of a grid as one cycle of its outer patch edges, in FlatShape's layout: along
// the top row, down the right side, back along the bottom row, up the left side.
std::vector<Vec2> gridBoundaryCubics(const SvgPatchGrid& g) {
    const int C = g.columns, R = g.rows;
    std::vector<Vec2> path;
    auto curve = [&](Vec2 start, Vec2 h1, Vec2 h2) { path.insert(path.end(), {start, h1, h2}); };
    for (int i = 0; i < C; ++i) curve(g.P(i, 0), g.H(i, 0)[0], g.H(i, 0)[1]);
    for (int j = 0; j < R; ++j) curve(g.P(C, j), g.V(C, j)[0], g.V(C, j)[1]);
    for (int i = C - 1; i >= 0; --i) curve(g.P(i + 1, R), g.H(i, R)[1], g.H(i, R)[0]);
    for (int j = R - 1; j >= 0; --j) curve(g.P(0, j + 1), g.V(0, j)[1], g.V(0, j)[0]);
    return path;
}

// The outline of a hole-free mesh as one closed path of its boundary curves, plus bands over
// its seams with neighbouring pieces. The compact syntax writes it relative at 1/100 px, as
// flat shapes are written; the exact syntax absolute, at its own precision.
void appendOutline(std::string& out, const SvgPatchGrid& g, const std::string& id,
                   const NumberSyntax& syntax, const PieceSeams& seams = {}) {
    const int C = g.columns, R = g.rows;
    std::vector<std::vector<Vec2>> bands;
    if (!seams.top.empty() || !seams.bottom.empty()) {
        std::vector<Vec2> corners;
        for (int i = 0; i < C; ++i) corners.push_back(g.P(i, 0));
        for (int j = 0; j < R; ++j) corners.push_back(g.P(C, j));
        for (int i = C; i > 0; --i) corners.push_back(g.P(i, R));
        for (int j = R; j > 0; --j) corners.push_back(g.P(0, j));
        const double orientation = signedArea(corners) >= 0 ? 1.0 : -1.0;
        for (int row : {0, R})
            for (std::vector<Vec2>& band :
                 seamBandPolygons(g, row, row == 0 ? seams.top : seams.bottom, orientation))
                bands.push_back(std::move(band));
    }
    // The paint in the style attribute, where mesh polyfills look for it; "none" where the
    // viewer has no meshes, so that a fallback image beneath shows through.
    out += "<path style=\"fill:url(#" + id + ") none\" d=\"";
    if (syntax.compact) {
        std::vector<std::vector<Vec2>> subpaths{gridBoundaryCubics(g)};
        for (const std::vector<Vec2>& band : bands) subpaths.push_back(polygonAsCubics(band));
        appendClosedPathData(out, subpaths);
    } else {
        const std::vector<Vec2> boundary = gridBoundaryCubics(g);
        out += 'M';
        appendPoints(out, {boundary[0]}, syntax);
        for (size_t k = 0; k < boundary.size(); k += 3) {
            out += " C";
            appendPoints(out, {boundary[k + 1], boundary[k + 2], boundary[(k + 3) % boundary.size()]},
                         syntax);
        }
        out += " Z";
        for (const std::vector<Vec2>& band : bands) {
            out += 'M';
            appendPoints(out, {band[0]}, syntax);
            out += 'L';
            appendPoints(out, band.data() + 1, band.data() + band.size(), syntax);
            out += 'Z';
        }
    }
    out += "\"/>\n";
}

// The hole-free meshes written, with their seams to each other.
struct SvgPiece {
    GradientMesh mesh;
    PieceSeams seams;
    size_t source = 0;  // the document's mesh it came from
    bool ofSlitMesh = false;  // a piece of a mesh with slits, whose seams the slits give
};

// An edge of a grid row as the positions of its two corners, to 1e-4 px, left corner first.
using EdgeKey = std::array<long long, 4>;
EdgeKey edgeKey(Vec2 a, Vec2 b) {
    const auto q = [](double v) { return std::llround(v * 1e4); };
    return {q(a.x), q(a.y), q(b.x), q(b.y)};
}

// Adds to each piece's seams the edges of its top row that are an edge of another piece's
// bottom row, and the other way round: the pieces of a slit mesh read back from an SVG are
// meshes of their own, whose seams the document no longer names. Written again, they keep
// their seams held and banded as the first file had them. Pieces of a mesh with slits are
// left out: its slits say where its pieces meet, and a slit whose sides touch is still a hole.
void addSharedSeams(std::vector<SvgPiece>& pieces) {
    struct Place {
        size_t piece;
        int column;
    };
    std::map<EdgeKey, std::vector<Place>> bottoms;  // the bottom-row edges, where they are
    std::vector<std::vector<char>> top(pieces.size()), bottom(pieces.size());  // per column
    for (size_t k = 0; k < pieces.size(); ++k) {
        const GradientMesh& m = pieces[k].mesh;
        top[k].assign(static_cast<size_t>(m.columns()), 0);
        bottom[k].assign(static_cast<size_t>(m.columns()), 0);
        if (pieces[k].ofSlitMesh) continue;
        for (int i = 0; i < m.columns(); ++i)
            bottoms[edgeKey(m.node(i, m.rows()).pos, m.node(i + 1, m.rows()).pos)].push_back({k, i});
    }
    for (size_t k = 0; k < pieces.size(); ++k) {
        if (pieces[k].ofSlitMesh) continue;
        const GradientMesh& m = pieces[k].mesh;
        for (int i = 0; i < m.columns(); ++i) {
            const auto found = bottoms.find(edgeKey(m.node(i, 0).pos, m.node(i + 1, 0).pos));
            if (found == bottoms.end()) continue;
            for (const Place& above : found->second)
                if (above.piece != k) {
                    top[k][static_cast<size_t>(i)] = 1;
                    bottom[above.piece][static_cast<size_t>(above.column)] = 1;
                }
        }
    }
    for (size_t k = 0; k < pieces.size(); ++k) {
        PieceSeams& seams = pieces[k].seams;
        for (int i = 0; i < pieces[k].mesh.columns(); ++i) {
            if (top[k][static_cast<size_t>(i)]) seams.top.push_back(i);
            if (bottom[k][static_cast<size_t>(i)]) seams.bottom.push_back(i);
        }
    }
}

std::vector<SvgPiece> svgPieces(const Document& doc, bool legacy) {
    std::vector<SvgPiece> pieces;
    for (size_t m = 0; m < doc.meshes.size(); ++m) {
        const GradientMesh& mesh = doc.meshes[m];
        if (legacy || !mesh.slits.empty()) {
            std::vector<GradientMesh> split = splitIntoLegacyMeshes(mesh);
            const std::vector<PieceSeams> seams = legacySeams(mesh);
            for (size_t k = 0; k < split.size(); ++k)
                pieces.push_back({std::move(split[k]), k < seams.size() ? seams[k] : PieceSeams{},
                                  m, !mesh.slits.empty()});
        } else {
            pieces.push_back({mesh, {}, m});
        }
    }
    addSharedSeams(pieces);
    return pieces;
}

// The fallback image must be given exactly when the options ask for one, of their kind.
void requireFallbackImage(const WriteOptions& options, const SvgFallbackImage* fallback) {
    if (!isSvgFallbackKind(options.svgFallback))
        throw Error("unknown SVG fallback '" + options.svgFallback +
                    "' (expected png, webp or none)");
    const bool wanted = options.svgFallback != "none";
    if (wanted && !fallback)
        throw Error("the SVG fallback image (" + options.svgFallback + ") was not made");
    if (!wanted && fallback)
        throw Error("an SVG fallback image was given with the fallback 'none'");
    if (fallback && fallback->kind != options.svgFallback)
        throw Error("the SVG fallback image is " + fallback->kind + ", not " + options.svgFallback);
}

}  // namespace

std::string encodeSvg(const Document& doc, const WriteOptions& options, SvgEncodeStats* stats,
                      const SvgFallbackImage* fallback) {
    const bool exact = options.svgColors == "exact";
    if (!exact && options.svgColors != "bicubic" && options.svgColors != "editable")
        throw Error("unknown SVG colour mode '" + options.svgColors +
                    "' (expected 'bicubic' or 'exact')");
    if (options.svgScript != "embed" && options.svgScript != "none")
        throw Error("unknown SVG script mode '" + options.svgScript + "' (expected 'embed' or 'none')");
    if (!(options.colorTolerance > 0) || !std::isfinite(options.colorTolerance))
        throw Error("the colour tolerance must be a positive number");
    requireFallbackImage(options, fallback);
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error("cannot write an invalid document: " + problem);

    const std::vector<SvgPiece> pieces = svgPieces(doc, options.legacy);
    // Exact mode's splits, counted against the cap before anything is written.
    std::vector<ExactSplits> splits;
    if (exact) {
        int64_t count = 0;
        for (const SvgPiece& p : pieces) {
            splits.push_back(exactSplits(p.mesh, options.colorTolerance, options.minPiece));
            count += splits.back().svgPatches();
        }
        if (count > options.maxSvgPatches)
            throw Error("exact SVG colours need " + std::to_string(count) +
                        " SVG patches, over the cap of " + std::to_string(options.maxSvgPatches) +
                        "; write the default bicubic SVG instead (--svg-colors bicubic)");
    }
    const NumberSyntax syntax =
        exact ? NumberSyntax{} : NumberSyntax{kSvgDecimalsCompact, true};
    SvgEncodeStats local;
    std::string out;
    out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    if (!pieces.empty())  // a file of flat shapes alone is plain SVG 1.1
        out += "<!-- gradmesh: SVG 2 meshgradient; drawn by Inkscape, and in browsers by the script at the end -->\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(doc.width) +
           "\" height=\"" + std::to_string(doc.height) + "\" viewBox=\"0 0 " +
           std::to_string(doc.width) + " " + std::to_string(doc.height) + "\">\n";
    if (!pieces.empty()) out += "<defs>\n";
    if (fallback) {  // the layer's namespaces, after the SVG one on the root element
        const std::string svgNamespace = "xmlns=\"http://www.w3.org/2000/svg\"";
        out.insert(out.rfind(svgNamespace) + svgNamespace.size(), svgFallbackNamespaces());
    }
    std::string paths;
    int n = 0;
    size_t nextShape = 0;  // flat shapes go between the meshes in their paint order
    SvgGradientWriter gradients;
    auto shapesUpTo = [&](size_t layer) {
        for (; nextShape < doc.shapes.size() && doc.shapes[nextShape].layer <= layer; ++nextShape)
            appendShapePath(paths, doc.shapes[nextShape], gradients);
    };
    for (size_t k = 0; k < pieces.size(); ++k) {
        const SvgPiece& p = pieces[k];
        shapesUpTo(p.source);
        const GradientMesh& piece = p.mesh;
        const std::string id = "m" + std::to_string(n++);
        const std::vector<BezierPatch> patches = meshPatches(piece);
        const SvgPatchGrid base = gridFromPatches(patches, piece.columns(), piece.rows());
        if (exact) {
            const SvgPatchGrid fine = refinedGrid(patches, piece.columns(), piece.rows(), splits[k]);
            local.maxSubdivision = std::max(local.maxSubdivision, splits[k].largest());
            appendMeshGradient(out, fine, id, false, syntax, heldSeams(p.seams, &splits[k]));
            local.svgPatches += fine.columns * int64_t(fine.rows);
        } else {
            appendMeshGradient(out, base, id, true, syntax, heldSeams(p.seams));
            local.svgPatches += base.columns * int64_t(base.rows);
        }
        ++local.meshGradients;
        appendOutline(paths, base, id, syntax, p.seams);
    }
    shapesUpTo(SIZE_MAX);
    if (!pieces.empty()) out += "</defs>\n";
    if (fallback) appendSvgFallbackLayer(out, *fallback, doc.width, doc.height);  // beneath the shapes
    out += paths;
    if (options.svgScript == "embed" && !pieces.empty()) appendMeshScript(out);
    out += "</svg>\n";
    if (stats) *stats = local;
    return out;
}

std::string encodeSvg(const Document& doc, const WriteOptions& options) {
    return encodeSvg(doc, options, nullptr);
}

}  // namespace gm
