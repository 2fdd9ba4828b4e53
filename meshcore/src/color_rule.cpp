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

// The sides of every patch edge end, line by line: u-lines along the rows, v-lines down the
// columns, each line's Inkscape slopes computed once for all the patches that see it.
class SideCollector {
public:
    SideCollector(const GradientMesh& mesh, const Layout& layout)
        : mesh_(mesh), layout_(layout), C_(mesh.columns()), R_(mesh.rows()) {}

    Sides run() {
        if (C_ < 1 || R_ < 1) return sides_;
        for (int j = 0; j <= R_; ++j)
            for (const std::vector<int>& patchRows : patchRowsSeeing(j)) uLine(j, patchRows);
        const std::vector<int> cuts = cutRows();
        for (size_t band = 0; band + 1 < cuts.size(); ++band)
            for (int i = 0; i <= C_; ++i) vLine(cuts[band], cuts[band + 1], i);
        return std::move(sides_);
    }

private:
    bool isSlitRow(int j) const {
        for (const Slit& s : mesh_.slits) {
            if (s.row == j) return true;
        }
        return false;
    }

    // The groups of patch rows that see node row j as one line: the rows on both sides, or
    // above and below separately at a row that holds slits.
    std::vector<std::vector<int>> patchRowsSeeing(int j) const {
        if (isSlitRow(j)) return {{j - 1}, {j}};
        std::vector<int> both;
        if (j > 0) both.push_back(j - 1);
        if (j < R_) both.push_back(j);
        return {both};
    }

    // The mesh's border rows and every row that holds slits: v-lines are cut there.
    std::vector<int> cutRows() const {
        std::vector<int> rows{0, R_};
        for (const Slit& s : mesh_.slits) rows.push_back(s.row);
        std::sort(rows.begin(), rows.end());
        rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
        return rows;
    }

    // The u-line along node row j as the patch rows `patchRows` see it.
    void uLine(int j, const std::vector<int>& patchRows) {
        const int pr0 = patchRows.front();
        line_.clear();
        for (int n = 0; n <= C_; ++n) {
            const int i = std::min(n, C_ - 1);
            const CornerUse use = resolveCorner(mesh_, layout_, i, pr0, n - i, pr0 == j ? 0 : 1);
            line_.push_back(&nodeCopy(mesh_, layout_, use.node));
        }
        lineSlopes(line_, slopes_, chords_);
        for (int i = 0; i < C_; ++i) {
            const double du = mesh_.u[i + 1] - mesh_.u[i];
            for (int a = 0; a < 2; ++a) {
                uses_.clear();
                for (int pr : patchRows) {
                    const CornerUse use = resolveCorner(mesh_, layout_, i, pr, a, pr == j ? 0 : 1);
                    addUnique(uses_, use.uSlot, use.uSign);
                }
                for (const auto& p : uses_) {
                    sides_.u.push_back({p.first, p.second, du, chords_[i] * slopes_[i + a]});
                }
            }
        }
    }

    // The v-line down node column i between the cut rows r0 and r1.
    void vLine(int r0, int r1, int i) {
        std::vector<int> patchCols;
        if (i > 0) patchCols.push_back(i - 1);
        if (i < C_) patchCols.push_back(i);
        const int pc0 = patchCols.front();
        line_.clear();
        for (int n = r0; n <= r1; ++n) {
            const int r = std::min(n, r1 - 1);
            const CornerUse use = resolveCorner(mesh_, layout_, pc0, r, pc0 == i ? 0 : 1, n - r);
            line_.push_back(&nodeCopy(mesh_, layout_, use.node));
        }
        lineSlopes(line_, slopes_, chords_);
        for (int r = r0; r < r1; ++r) {
            const double dv = mesh_.v[r + 1] - mesh_.v[r];
            for (int b = 0; b < 2; ++b) {
                uses_.clear();
                for (int pc : patchCols) {
                    const CornerUse use = resolveCorner(mesh_, layout_, pc, r, pc == i ? 0 : 1, b);
                    addUnique(uses_, use.node, 1.0);
                }
                const size_t k = static_cast<size_t>(r - r0);
                for (const auto& p : uses_) {
                    sides_.v.push_back({p.first, 1.0, dv, chords_[k] * slopes_[k + b]});
                }
            }
        }
    }

    const GradientMesh& mesh_;
    const Layout& layout_;
    const int C_, R_;
    Sides sides_;
    std::vector<const Node*> line_;
    std::vector<Vec3> slopes_;
    std::vector<double> chords_;
    std::vector<std::pair<size_t, double>> uses_;
};

Sides collectSides(const GradientMesh& mesh, const Layout& layout) {
    return SideCollector(mesh, layout).run();
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
