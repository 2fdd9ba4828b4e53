#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"
#include "svg_patch_grid.h"

namespace gm {

namespace {

// Handle displacement (pixels) up to which the two one-sided derivatives at a node count as
// one: our compact syntax rounds every number to 1/100 px, so the two handles of a smooth node
// come back up to ~0.007 px apart; a kink (a former slit end) is far more.
constexpr double kHandleAgreement = 0.01;

double weightedMedian(std::vector<std::pair<double, double>> values) {
    std::sort(values.begin(), values.end());
    double total = 0;
    for (const auto& v : values) total += v.second;
    double acc = 0;
    for (const auto& v : values) {
        acc += v.second;
        if (acc >= 0.5 * total) return v.first;
    }
    return values.back().first;
}

// Knot intervals along one grid direction from the ratio of the handle lengths on both sides
// of each grid line. `left(line, k)` / `right(line, k)` are the handle vectors (handle − node)
// at node k of grid line `line` (k = 1..n-1), `chord(k)` a fallback length of interval k.
template <class Left, class Right, class Chord>
std::vector<double> knotIntervals(int n, int lines, Left left, Right right, Chord chord) {
    std::vector<double> logDelta(static_cast<size_t>(n), 0.0);
    for (int k = 1; k < n; ++k) {
        std::vector<std::pair<double, double>> ratios;
        for (int l = 0; l < lines; ++l) {
            const double a = norm(left(l, k)), b = norm(right(l, k));
            if (a > 1e-6 && b > 1e-6) ratios.push_back({std::log(b / a), std::min(a, b)});
        }
        double lr;
        if (!ratios.empty()) {
            lr = weightedMedian(std::move(ratios));
        } else {
            const double a = chord(k - 1), b = chord(k);
            lr = (a > 1e-9 && b > 1e-9) ? std::log(b / a) : 0.0;
        }
        lr = std::max(-std::log(64.0), std::min(std::log(64.0), lr));
        logDelta[k] = logDelta[k - 1] + lr;
    }
    // Mean interval 1, none below 1e-6 of the largest.
    const double top = *std::max_element(logDelta.begin(), logDelta.end());
    std::vector<double> delta(static_cast<size_t>(n));
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        delta[k] = std::exp(std::max(logDelta[k] - top, std::log(1e-6)));
        sum += delta[k];
    }
    for (double& d : delta) d *= n / sum;
    return delta;
}

// Derivative at the middle of three samples spaced h0, h1 with divided differences s0, s1:
// that of the parabola through them. At an end, the same parabola's end slope.
double parabolaMid(double s0, double s1, double h0, double h1) {
    return (h1 * s0 + h0 * s1) / (h0 + h1);
}
double parabolaStart(double s0, double s1, double h0, double h1) {
    return s0 - h0 * (s1 - s0) / (h0 + h1);
}
double parabolaEnd(double s0, double s1, double h0, double h1) {
    return s1 + h1 * (s1 - s0) / (h0 + h1);
}

// Colour derivative along one grid line of n+1 samples, per unit knot, at sample k; `from` /
// `to` restrict the samples used (breaks).
Vec3 lineDerivative(const std::vector<Vec3>& c, const std::vector<double>& h, int k, int from,
                    int to) {
    Vec3 d;
    if (to - from < 1) return d;
    for (int ch = 0; ch < 3; ++ch) {
        auto slope = [&](int i) { return (c[i + 1][ch] - c[i][ch]) / h[i]; };
        if (to - from == 1) {
            d[ch] = slope(from);
        } else if (k == from) {
            d[ch] = parabolaStart(slope(k), slope(k + 1), h[k], h[k + 1]);
        } else if (k == to) {
            d[ch] = parabolaEnd(slope(k - 2), slope(k - 1), h[k - 2], h[k - 1]);
        } else {
            d[ch] = parabolaMid(slope(k - 1), slope(k), h[k - 1], h[k]);
        }
    }
    return d;
}

// Builds the mesh of a patch grid step by step: knots from the handle lengths, node positions
// and derivatives from the handles (u-breaks where the two sides disagree), colour derivatives,
// then the tangent breaks.
class GridMeshBuilder {
public:
    explicit GridMeshBuilder(const SvgPatchGrid& g)
        : g_(g),
          C_(g.columns),
          R_(g.rows),
          mesh_(C_, R_),
          breakAt_(static_cast<size_t>(C_ + 1) * (R_ + 1), 0),
          leftPosU_(breakAt_.size()) {}

    GradientMesh build() {
        chooseKnots();
        for (int r = 0; r <= R_; ++r)
            for (int c = 0; c <= C_; ++c) placeNode(c, r);
        if (g_.bicubic)
            mesh_.colorModel = ColorModel::Bicubic;  // exactly what Inkscape draws from the file
        else
            colorDerivatives();
        for (int r = 0; r <= R_; ++r)
            for (int c = 1; c < C_; ++c)
                if (breakAt(c, r)) addBreak(c, r);
        return std::move(mesh_);
    }

private:
    char& breakAt(int c, int r) { return breakAt_[static_cast<size_t>(r) * (C_ + 1) + c]; }

    void chooseKnots() {
        const SvgPatchGrid& g = g_;
        const int C = C_, R = R_;
        du_ = knotIntervals(
            C, R + 1, [&](int r, int c) { return g.P(c, r) - g.H(c - 1, r)[1]; },
            [&](int r, int c) { return g.H(c, r)[0] - g.P(c, r); },
            [&](int c) {
                double s = 0;
                for (int r = 0; r <= R; ++r) s += norm(g.P(c + 1, r) - g.P(c, r));
                return s;
            });
        dv_ = knotIntervals(
            R, C + 1, [&](int c, int r) { return g.P(c, r) - g.V(c, r - 1)[1]; },
            [&](int c, int r) { return g.V(c, r)[0] - g.P(c, r); },
            [&](int r) {
                double s = 0;
                for (int c = 0; c <= C; ++c) s += norm(g.P(c, r + 1) - g.P(c, r));
                return s;
            });
        for (int i = 0; i < C; ++i) mesh_.u[i + 1] = mesh_.u[i] + du_[i];
        for (int j = 0; j < R; ++j) mesh_.v[j + 1] = mesh_.v[j] + dv_[j];
    }

    // Node (c, r): position, colour and position derivatives. Along u the two sides' handles
    // are averaged when they agree, else the node gets a break (the right side's derivative;
    // the left one kept in leftPosU_); along v they are always averaged.
    void placeNode(int c, int r) {
        const SvgPatchGrid& g = g_;
        Node& n = mesh_.node(c, r);
        n.pos = g.P(c, r);
        n.col = g.C(c, r);
        const bool hasL = c > 0, hasR = c < C_;
        const Vec2 dL = hasL ? (3.0 / du_[c - 1]) * (g.P(c, r) - g.H(c - 1, r)[1]) : Vec2{};
        const Vec2 dR = hasR ? (3.0 / du_[c]) * (g.H(c, r)[0] - g.P(c, r)) : Vec2{};
        if (hasL && hasR) {
            const Vec2 avg = 0.5 * (dL + dR);
            const double moveL = norm(avg - dL) * du_[c - 1] / 3,
                         moveR = norm(avg - dR) * du_[c] / 3;
            if (moveL <= kHandleAgreement && moveR <= kHandleAgreement) {
                n.posU = avg;
            } else {
                n.posU = dR;
                breakAt(c, r) = 1;
                leftPosU_[static_cast<size_t>(r) * (C_ + 1) + c] = dL;
            }
        } else {
            n.posU = hasL ? dL : dR;
        }
        const bool hasA = r > 0, hasB = r < R_;
        const Vec2 dA = hasA ? (3.0 / dv_[r - 1]) * (g.P(c, r) - g.V(c, r - 1)[1]) : Vec2{};
        const Vec2 dB = hasB ? (3.0 / dv_[r]) * (g.V(c, r)[0] - g.P(c, r)) : Vec2{};
        n.posV = (hasA && hasB) ? 0.5 * (dA + dB) : (hasA ? dA : dB);
    }

    // The colours along node row r.
    std::vector<Vec3> rowColors(int r) const {
        std::vector<Vec3> line(static_cast<size_t>(C_) + 1);
        for (int c = 0; c <= C_; ++c) line[c] = g_.C(c, r);
        return line;
    }

    // Hermite colour derivatives interpolated along the node rows (sections between u-breaks
    // separately) and columns.
    void colorDerivatives() {
        for (int r = 0; r <= R_; ++r) {
            const std::vector<Vec3> line = rowColors(r);
            std::vector<int> cuts{0};
            for (int c = 1; c < C_; ++c)
                if (breakAt(c, r)) cuts.push_back(c);
            cuts.push_back(C_);
            for (size_t s = 0; s + 1 < cuts.size(); ++s) {
                const int a = cuts[s], b = cuts[s + 1];
                // Left to right: at a break the right section's value is the node's.
                for (int c = a; c <= b; ++c)
                    mesh_.node(c, r).colU = lineDerivative(line, du_, c, a, b);
            }
        }
        std::vector<Vec3> column;
        for (int c = 0; c <= C_; ++c) {
            column.assign(static_cast<size_t>(R_) + 1, Vec3{});
            for (int r = 0; r <= R_; ++r) column[r] = g_.C(c, r);
            for (int r = 0; r <= R_; ++r)
                mesh_.node(c, r).colV = lineDerivative(column, dv_, r, 0, R_);
        }
    }

    // The break at node (c, r): the patches left of the node use the left-side derivative.
    void addBreak(int c, int r) {
        Vec3 colL = mesh_.node(c, r).colU;
        if (!g_.bicubic) {
            const std::vector<Vec3> line = rowColors(r);
            int a = 0;
            for (int k = c - 1; k > 0; --k)
                if (breakAt(k, r)) {
                    a = k;
                    break;
                }
            colL = lineDerivative(line, du_, c, a, c);
        }
        const Vec2 posL = leftPosU_[static_cast<size_t>(r) * (C_ + 1) + c];
        if (r > 0) mesh_.tangents.push_back({c - 1, r - 1, 1, 1, posL, colL});
        if (r < R_) mesh_.tangents.push_back({c - 1, r, 1, 0, posL, colL});
    }

    const SvgPatchGrid& g_;
    const int C_, R_;
    GradientMesh mesh_;
    std::vector<double> du_, dv_;
    std::vector<char> breakAt_;  // per node: the u-derivative differs on its two sides
    std::vector<Vec2> leftPosU_;
};

}  // namespace

GradientMesh meshFromPatchGrid(const SvgPatchGrid& g, const std::string& fileName,
                               const std::string& where) {
    GradientMesh mesh = GridMeshBuilder(g).build();
    const std::string problem = validateMesh(mesh);
    if (!problem.empty()) throw Error("meshgradient gives an invalid mesh: " + problem, fileName, where);
    return mesh;
}

}  // namespace gm
