// The Bicubic colour model: Inkscape's bicubic slopes per patch corner as linear forms of the
// node-copy colours; see bicubic_colors.h and color_rule.h for the rule.
#include "meshcore/bicubic_colors.h"

#include <algorithm>
#include <cmath>

#include "node_copies.h"

namespace gm {
namespace {

using detail::Layout;
using detail::nodeCopy;
using detail::resolveCorner;

// A window of one line of corners: line indices lo..lo+size-1 of a line with N+1 corners.
struct LineWindow {
    int lo = 0, N = 0, size = 0;
    int copy[4] = {0, 0, 0, 0};
    Vec2 pos[4];
    Vec3 col[4];
    double chord(int n) const { return norm(pos[n + 1 - lo] - pos[n - lo]); }
    double c(int n, int ch) const { return col[n - lo][ch]; }
};

void addTerm(RuleSlope& f, int copy, double w) {
    for (int k = 0; k < f.count; ++k)
        if (f.copy[k] == copy) {
            f.weight[k] += w;
            return;
        }
    f.copy[f.count] = copy;
    f.weight[f.count] = w;
    ++f.count;
}

void addForm(RuleSlope& f, const RuleSlope& g, double scale) {
    for (int k = 0; k < g.count; ++k) addTerm(f, g.copy[k], scale * g.weight[k]);
}

// The secant (c_{n+1} − c_n) / L_n as a form; L_n > 0.
RuleSlope secant(const LineWindow& w, int n, double chord) {
    RuleSlope f;
    addTerm(f, w.copy[n - w.lo], -1.0 / chord);
    addTerm(f, w.copy[n + 1 - w.lo], 1.0 / chord);
    return f;
}

// Inkscape's slope at interior corner k (0 < k < N), per unit of length, branch chosen by the
// current colours exactly as color_rule.cpp's interiorSlope chooses it.
RuleSlope interiorForm(const LineWindow& w, int k, int ch) {
    RuleSlope f;
    const double lb = w.chord(k - 1), la = w.chord(k);
    if (!(lb > 0.0 && la > 0.0)) return f;
    const double before = w.c(k - 1, ch), at = w.c(k, ch), after = w.c(k + 1, ch);
    if ((before < at && at > after) || (before > at && at < after)) return f;
    const double sb = (at - before) / lb, sa = (after - at) / la;
    double slope = 0.5 * (sb + sa);
    int branch = 0;  // 0: mean, 1: 3·secant before, 2: 3·secant after
    if (std::fabs(slope) > std::fabs(3.0 * sb)) {
        slope = 3.0 * sb;
        branch = 1;
    }
    if (std::fabs(slope) > std::fabs(3.0 * sa)) branch = 2;
    if (branch != 2) addForm(f, secant(w, k - 1, lb), branch == 0 ? 0.5 : 3.0);
    if (branch != 1) addForm(f, secant(w, k, la), branch == 0 ? 0.5 : 3.0);
    return f;
}

// Inkscape's slope g_k at corner k of the line: interior, or parabolic at the ends (the first
// end sees the interior g_1; with a single patch the last end sees g_0 and comes out 0).
RuleSlope slopeForm(const LineWindow& w, int k, int ch) {
    const int N = w.N;
    if (k > 0 && k < N) return interiorForm(w, k, ch);
    RuleSlope f;
    const int edge = k == 0 ? 0 : N - 1;
    const double chord = w.chord(edge);
    if (!(chord > 0.0)) return f;
    addForm(f, secant(w, edge, chord), 2.0);
    if (N == 1) {
        if (k == 1) return RuleSlope{};  // 2δ_0 − g_0 with g_0 = 2δ_0
        return f;
    }
    addForm(f, interiorForm(w, k == 0 ? 1 : N - 1, ch), -1.0);
    return f;
}

// The local slopes of the patch edge between line corners e and e+1 at both ends: chord · g.
void edgeSlopes(const LineWindow& w, int e, RuleSlope (&out)[3][2]) {
    const double chord = w.chord(e);
    for (int ch = 0; ch < 3; ++ch)
        for (int a = 0; a < 2; ++a) {
            out[ch][a] = RuleSlope{};
            addForm(out[ch][a], slopeForm(w, e + a, ch), chord);
        }
}

// The window around edge e of a line of N+1 corners whose corner n is `corner(n)`.
template <class CornerAt>
LineWindow lineWindow(const GradientMesh& mesh, const Layout& layout, int N, int e,
                      CornerAt corner) {
    LineWindow w;
    w.N = N;
    w.lo = std::max(0, e - 1);
    const int hi = std::min(N, e + 2);
    w.size = hi - w.lo + 1;
    for (int n = w.lo; n <= hi; ++n) {
        const size_t copy = corner(n);
        const Node& node = nodeCopy(mesh, layout, copy);
        w.copy[n - w.lo] = static_cast<int>(copy);
        w.pos[n - w.lo] = node.pos;
        w.col[n - w.lo] = node.col;
    }
    return w;
}

// The band of patch rows between the cut rows (0, R and every slit row) around patch row j.
void bandAround(const GradientMesh& mesh, int j, int& r0, int& r1) {
    r0 = 0;
    r1 = mesh.rows();
    for (const Slit& s : mesh.slits) {
        if (s.row <= j) r0 = std::max(r0, s.row);
        if (s.row > j) r1 = std::min(r1, s.row);
    }
}

PatchColorRule patchRule(const GradientMesh& mesh, const Layout& layout, int i, int j) {
    const int C = mesh.columns();
    PatchColorRule rule;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            rule.copy[a][b] = static_cast<int>(resolveCorner(mesh, layout, i, j, a, b).node);
    for (int b = 0; b < 2; ++b) {  // u-lines: the patch's top (b = 0) and bottom row
        const LineWindow w = lineWindow(mesh, layout, C, i, [&](int n) {
            const int pc = std::min(n, C - 1);
            return resolveCorner(mesh, layout, pc, j, n - pc, b).node;
        });
        RuleSlope out[3][2];
        edgeSlopes(w, i, out);
        for (int ch = 0; ch < 3; ++ch)
            for (int a = 0; a < 2; ++a) rule.s[ch][a][b] = out[ch][a];
    }
    int r0 = 0, r1 = 0;
    bandAround(mesh, j, r0, r1);
    for (int a = 0; a < 2; ++a) {  // v-lines: the patch's left (a = 0) and right column
        const LineWindow w = lineWindow(mesh, layout, r1 - r0, j - r0, [&](int n) {
            const int r = std::min(r0 + n, r1 - 1);
            return resolveCorner(mesh, layout, i, r, a, r0 + n - r).node;
        });
        RuleSlope out[3][2];
        edgeSlopes(w, j - r0, out);
        for (int ch = 0; ch < 3; ++ch)
            for (int b = 0; b < 2; ++b) rule.t[ch][a][b] = out[ch][b];
    }
    return rule;
}

}  // namespace

void useBicubicModel(GradientMesh& mesh) {
    mesh.colorModel = ColorModel::Bicubic;
    auto clear = [](Node& n) { n.colU = n.colV = Vec3{}; };
    for (Node& n : mesh.nodes) clear(n);
    for (Slit& s : mesh.slits) {
        for (Node& n : s.below) clear(n);
        s.left.colU = s.right.colU = Vec3{};
    }
    for (CornerTangent& t : mesh.tangents) t.colU = Vec3{};
}

PatchColorRule bicubicPatchRule(const GradientMesh& mesh, int i, int j) {
    return patchRule(mesh, Layout(mesh), i, j);
}

void bicubicPatchSlopes(const GradientMesh& mesh, int i, int j, Vec3 colS[2][2],
                        Vec3 colT[2][2]) {
    const Layout layout(mesh);
    const PatchColorRule rule = patchRule(mesh, layout, i, j);
    auto value = [&](const RuleSlope& f, int ch) {
        double v = 0.0;
        for (int k = 0; k < f.count; ++k)
            v += f.weight[k] * nodeCopy(mesh, layout, static_cast<size_t>(f.copy[k])).col[ch];
        return v;
    };
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int ch = 0; ch < 3; ++ch) {
                colS[a][b][ch] = value(rule.s[ch][a][b], ch);
                colT[a][b][ch] = value(rule.t[ch][a][b], ch);
            }
}

}  // namespace gm
