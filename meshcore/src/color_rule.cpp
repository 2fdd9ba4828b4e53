// The Inkscape `bicubic` colour-derivative rule in global parameters; see color_rule.h for the
// rule, its derivation and when the editable SVG export is exact.
#include "meshcore/color_rule.h"

#include "node_copies.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace gm {
namespace {

using detail::CornerUse;
using detail::Layout;
using detail::nodeCopy;
using detail::resolveCorner;
using detail::setSlotU;
using detail::slotU;

// Inkscape's slope at an interior corner of a line, per unit of user-space length, from the
// colours before, at and after it and the two chords.
double interiorSlope(double before, double at, double after, double chordBefore,
                     double chordAfter) {
    if (!(chordBefore > 0.0 && chordAfter > 0.0)) return 0.0;
    const bool peak = before < at && at > after;
    const bool trough = before > at && at < after;
    if (peak || trough) return 0.0;
    const double secantBefore = (at - before) / chordBefore;
    const double secantAfter = (after - at) / chordAfter;
    double slope = 0.5 * (secantBefore + secantAfter);
    if (std::fabs(slope) > std::fabs(3.0 * secantBefore)) slope = 3.0 * secantBefore;
    if (std::fabs(slope) > std::fabs(3.0 * secantAfter)) slope = 3.0 * secantAfter;
    return slope;
}

// Inkscape's slopes g_0..g_N (per unit length) along one line of corners, and its chords.
void lineSlopes(const std::vector<const Node*>& line, std::vector<Vec3>& slopes,
                std::vector<double>& chords) {
    const size_t n = line.size();
    chords.assign(n - 1, 0.0);
    for (size_t k = 0; k + 1 < n; ++k) chords[k] = norm(line[k + 1]->pos - line[k]->pos);
    slopes.assign(n, Vec3{});
    for (int c = 0; c < 3; ++c) {
        for (size_t k = 1; k + 1 < n; ++k) {
            slopes[k][c] = interiorSlope(line[k - 1]->col[c], line[k]->col[c], line[k + 1]->col[c],
                                         chords[k - 1], chords[k]);
        }
        // The ends, first then last: with a single patch the last sees the first's value.
        const double first = chords[0];
        slopes[0][c] =
            first > 0.0 ? 2.0 * (line[1]->col[c] - line[0]->col[c]) / first - slopes[1][c] : 0.0;
        const double last = chords[n - 2];
        slopes[n - 1][c] =
            last > 0.0 ? 2.0 * (line[n - 1]->col[c] - line[n - 2]->col[c]) / last - slopes[n - 2][c]
                       : 0.0;
    }
}

// One patch edge end served by a slot: the slot's value x should satisfy sign·delta·x = target.
struct Side {
    size_t slot = 0;
    double sign = 1.0;
    double delta = 0.0;  // the patch's parameter interval along the slot's direction
    Vec3 target;         // Inkscape's local slope g·L
};

struct Sides {
    std::vector<Side> u, v;
};

void addUnique(std::vector<std::pair<size_t, double>>& uses, size_t slot, double sign) {
    for (const auto& p : uses) {
        if (p.first == slot && p.second == sign) return;
    }
    uses.emplace_back(slot, sign);
}

Sides collectSides(const GradientMesh& mesh, const Layout& layout) {
    Sides sides;
    const int C = mesh.columns(), R = mesh.rows();
    if (C < 1 || R < 1) return sides;

    std::vector<int> cutRows{0, R};
    for (const Slit& s : mesh.slits) cutRows.push_back(s.row);
    std::sort(cutRows.begin(), cutRows.end());
    cutRows.erase(std::unique(cutRows.begin(), cutRows.end()), cutRows.end());
    auto isSlitRow = [&](int j) {
        for (const Slit& s : mesh.slits) {
            if (s.row == j) return true;
        }
        return false;
    };

    std::vector<const Node*> line;
    std::vector<Vec3> g;
    std::vector<double> chords;
    std::vector<std::pair<size_t, double>> uses;

    // u-lines: along each row, once for the patches on both sides, or separately above and below
    // a row that holds slits.
    for (int j = 0; j <= R; ++j) {
        std::vector<std::vector<int>> groups;  // patch rows that see one line
        if (isSlitRow(j)) {
            groups = {{j - 1}, {j}};
        } else {
            std::vector<int> both;
            if (j > 0) both.push_back(j - 1);
            if (j < R) both.push_back(j);
            groups.push_back(both);
        }
        for (const std::vector<int>& patchRows : groups) {
            const int pr0 = patchRows.front();
            line.clear();
            for (int n = 0; n <= C; ++n) {
                const int i = std::min(n, C - 1);
                const CornerUse use = resolveCorner(mesh, layout, i, pr0, n - i, pr0 == j ? 0 : 1);
                line.push_back(&nodeCopy(mesh, layout, use.node));
            }
            lineSlopes(line, g, chords);
            for (int i = 0; i < C; ++i) {
                const double du = mesh.u[i + 1] - mesh.u[i];
                for (int a = 0; a < 2; ++a) {
                    uses.clear();
                    for (int pr : patchRows) {
                        const CornerUse use =
                            resolveCorner(mesh, layout, i, pr, a, pr == j ? 0 : 1);
                        addUnique(uses, use.uSlot, use.uSign);
                    }
                    for (const auto& p : uses) {
                        sides.u.push_back({p.first, p.second, du, chords[i] * g[i + a]});
                    }
                }
            }
        }
    }

    // v-lines: each column, cut at every row that holds slits.
    for (size_t band = 0; band + 1 < cutRows.size(); ++band) {
        const int r0 = cutRows[band], r1 = cutRows[band + 1];
        for (int i = 0; i <= C; ++i) {
            std::vector<int> patchCols;
            if (i > 0) patchCols.push_back(i - 1);
            if (i < C) patchCols.push_back(i);
            const int pc0 = patchCols.front();
            line.clear();
            for (int n = r0; n <= r1; ++n) {
                const int r = std::min(n, r1 - 1);
                const CornerUse use = resolveCorner(mesh, layout, pc0, r, pc0 == i ? 0 : 1, n - r);
                line.push_back(&nodeCopy(mesh, layout, use.node));
            }
            lineSlopes(line, g, chords);
            for (int r = r0; r < r1; ++r) {
                const double dv = mesh.v[r + 1] - mesh.v[r];
                for (int b = 0; b < 2; ++b) {
                    uses.clear();
                    for (int pc : patchCols) {
                        const CornerUse use =
                            resolveCorner(mesh, layout, pc, r, pc == i ? 0 : 1, b);
                        addUnique(uses, use.node, 1.0);
                    }
                    const size_t k = static_cast<size_t>(r - r0);
                    for (const auto& p : uses) {
                        sides.v.push_back({p.first, 1.0, dv, chords[k] * g[k + b]});
                    }
                }
            }
        }
    }
    return sides;
}

// x = Σ σ·t / Σ Δ per slot; 0 for a slot that serves nothing.
std::vector<Vec3> solveSlots(const std::vector<Side>& sides, size_t slots) {
    std::vector<Vec3> num(slots);
    std::vector<double> den(slots, 0.0);
    for (const Side& s : sides) {
        num[s.slot] = num[s.slot] + s.sign * s.target;
        den[s.slot] += s.delta;
    }
    std::vector<Vec3> value(slots);
    for (size_t k = 0; k < slots; ++k) {
        if (den[k] > 0.0) value[k] = (1.0 / den[k]) * num[k];
    }
    return value;
}

struct RuleValues {
    std::vector<Vec3> u, v;
};

RuleValues computeRule(const GradientMesh& mesh, const Layout& layout) {
    const Sides sides = collectSides(mesh, layout);
    return {solveSlots(sides.u, layout.uSlots), solveSlots(sides.v, layout.nodeCopies)};
}

double maxAbsDiff(Vec3 a, Vec3 b) {
    double m = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double d = std::fabs(a[c] - b[c]);
        if (std::isnan(d)) return d;
        m = std::max(m, d);
    }
    return m;
}

// worst = max(worst, d), keeping a NaN once seen.
void raiseTo(double& worst, double d) {
    if (std::isnan(worst)) return;
    if (std::isnan(d) || d > worst) worst = d;
}

}  // namespace

void applyColorRule(GradientMesh& mesh) {
    const Layout layout(mesh);
    const RuleValues rule = computeRule(mesh, layout);
    for (size_t k = 0; k < layout.uSlots; ++k) setSlotU(mesh, layout, k, rule.u[k]);
    for (size_t k = 0; k < layout.nodeCopies; ++k) nodeCopy(mesh, layout, k).colV = rule.v[k];
}

double colorRuleDeviation(const GradientMesh& mesh) {
    const Layout layout(mesh);
    const RuleValues rule = computeRule(mesh, layout);
    double worst = 0.0;
    for (size_t k = 0; k < layout.uSlots; ++k) {
        raiseTo(worst, maxAbsDiff(slotU(mesh, layout, k), rule.u[k]));
    }
    for (size_t k = 0; k < layout.nodeCopies; ++k) {
        raiseTo(worst, maxAbsDiff(nodeCopy(mesh, layout, k).colV, rule.v[k]));
    }
    return worst;
}

bool followsColorRule(const GradientMesh& mesh, double tolerance) {
    return colorRuleDeviation(mesh) <= tolerance;
}

double bicubicExportDeviation(const GradientMesh& mesh) {
    const Layout layout(mesh);
    const Sides sides = collectSides(mesh, layout);
    double worst = 0.0;
    for (const Side& s : sides.u) {
        const Vec3 local = (s.sign * s.delta) * slotU(mesh, layout, s.slot);
        raiseTo(worst, maxAbsDiff(local, s.target));
    }
    for (const Side& s : sides.v) {
        const Vec3 local = s.delta * nodeCopy(mesh, layout, s.slot).colV;
        raiseTo(worst, maxAbsDiff(local, s.target));
    }
    return worst;
}

}  // namespace gm
