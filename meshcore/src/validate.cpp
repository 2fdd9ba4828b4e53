#include "meshcore/validate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "meshcore/evaluate.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {
bool finite2(Vec2 a) { return std::isfinite(a.x) && std::isfinite(a.y); }
bool finite3(Vec3 a) { return std::isfinite(a.r) && std::isfinite(a.g) && std::isfinite(a.b); }
bool finiteNode(const Node& n) {
    return finite2(n.pos) && finite2(n.posU) && finite2(n.posV) && finite3(n.col) &&
           finite3(n.colU) && finite3(n.colV);
}

// The longer of the knot spans either side of knot i.
double spanAt(const std::vector<double>& k, int i) {
    double span = 0;
    if (i > 0) span = k[i] - k[i - 1];
    if (i + 1 < static_cast<int>(k.size())) span = std::max(span, k[i + 1] - k[i]);
    return span;
}

bool within(Vec2 p, double bound) { return std::fabs(p.x) <= bound && std::fabs(p.y) <= bound; }

// A Bézier handle sits derivative × knot span / 3 from its node.
bool boundedHandle(Vec2 derivative, double span) {
    return within(derivative * (span / 3), 2 * kMaxCoordinate);
}

// Node (i, j): its position and handles within the coordinate limit.
bool boundedNode(const GradientMesh& m, const Node& n, int i, int j) {
    return within(n.pos, kMaxCoordinate) && boundedHandle(n.posU, spanAt(m.u, i)) &&
           boundedHandle(n.posV, spanAt(m.v, j));
}

std::string checkKnots(const std::vector<double>& k, const char* name) {
    if (k.size() < 2) return std::string("fewer than two ") + name + " knots";
    for (size_t i = 0; i < k.size(); ++i) {
        if (!std::isfinite(k[i])) return std::string(name) + " knot " + std::to_string(i) + " is not finite";
        if (i > 0 && !(k[i] > k[i - 1]))
            return std::string(name) + " knots not strictly increasing at index " + std::to_string(i);
    }
    return {};
}
}  // namespace

std::string validateMesh(const GradientMesh& m) {
    if (auto e = checkKnots(m.u, "u"); !e.empty()) return e;
    if (auto e = checkKnots(m.v, "v"); !e.empty()) return e;
    const int C = m.columns(), R = m.rows();
    const size_t expected = (static_cast<size_t>(C) + 1) * (static_cast<size_t>(R) + 1);
    if (m.nodes.size() != expected)
        return "node count " + std::to_string(m.nodes.size()) + " does not match the " +
               std::to_string(C) + "x" + std::to_string(R) + " grid (" + std::to_string(expected) + ")";
    for (size_t k = 0; k < m.nodes.size(); ++k)
        if (!finiteNode(m.nodes[k]))
            return "node (" + std::to_string(k % (C + 1)) + "," + std::to_string(k / (C + 1)) +
                   ") has a non-finite value";
    for (size_t s = 0; s < m.slits.size(); ++s) {
        const Slit& sl = m.slits[s];
        const std::string name = "slit " + std::to_string(s);
        if (sl.row <= 0 || sl.row >= R)
            return name + " is on row " + std::to_string(sl.row) + ", not an interior row (1.." +
                   std::to_string(R - 1) + ")";
        if (sl.i0 <= 0 || sl.i1 >= C || sl.i0 >= sl.i1)
            return name + " spans columns " + std::to_string(sl.i0) + ".." + std::to_string(sl.i1) +
                   ", not inside 1.." + std::to_string(C - 1);
        if (sl.below.size() != static_cast<size_t>(sl.i1 - sl.i0 - 1))
            return name + " has " + std::to_string(sl.below.size()) + " split nodes, expected " +
                   std::to_string(sl.i1 - sl.i0 - 1);
        for (const Node& n : sl.below)
            if (!finiteNode(n)) return name + " has a non-finite split node";
        if (!finite2(sl.left.posU) || !finite3(sl.left.colU) || !finite2(sl.right.posU) ||
            !finite3(sl.right.colU))
            return name + " has a non-finite end tangent";
        for (size_t o = 0; o < s; ++o) {
            const Slit& t = m.slits[o];
            if (t.row == sl.row && !(t.i1 < sl.i0 || sl.i1 < t.i0))
                return name + " touches slit " + std::to_string(o) + " on row " + std::to_string(sl.row);
        }
    }
    for (size_t k = 0; k < m.tangents.size(); ++k) {
        const CornerTangent& t = m.tangents[k];
        if (t.i < 0 || t.i >= C || t.j < 0 || t.j >= R || t.a < 0 || t.a > 1 || t.b < 0 || t.b > 1)
            return "tangent break " + std::to_string(k) + " names a patch corner outside the grid";
        if (!finite2(t.posU) || !finite3(t.colU))
            return "tangent break " + std::to_string(k) + " is not finite";
    }
    return {};
}

std::string coordinateProblem(const GradientMesh& m) {
    if (!validateMesh(m).empty()) return {};  // its indices cannot be trusted
    const int C = m.columns();
    const std::string beyond = " lies beyond the coordinate limit of 1e7 pixels";
    for (size_t k = 0; k < m.nodes.size(); ++k)
        if (!boundedNode(m, m.nodes[k], static_cast<int>(k % (C + 1)), static_cast<int>(k / (C + 1))))
            return "node (" + std::to_string(k % (C + 1)) + "," + std::to_string(k / (C + 1)) + ")" +
                   beyond;
    for (size_t s = 0; s < m.slits.size(); ++s) {
        const Slit& sl = m.slits[s];
        for (size_t b = 0; b < sl.below.size(); ++b)
            if (!boundedNode(m, sl.below[b], sl.i0 + 1 + static_cast<int>(b), sl.row))
                return "a split node of slit " + std::to_string(s) + beyond;
        if (!boundedHandle(sl.left.posU, spanAt(m.u, sl.i0)) ||
            !boundedHandle(sl.right.posU, spanAt(m.u, sl.i1)))
            return "an end tangent of slit " + std::to_string(s) + beyond;
    }
    for (size_t k = 0; k < m.tangents.size(); ++k)
        if (!boundedHandle(m.tangents[k].posU, spanAt(m.u, m.tangents[k].i + m.tangents[k].a)))
            return "tangent break " + std::to_string(k) + beyond;
    return {};
}

std::string coordinateProblem(const Document& doc) {
    for (size_t k = 0; k < doc.meshes.size(); ++k)
        if (auto e = coordinateProblem(doc.meshes[k]); !e.empty())
            return "mesh " + std::to_string(k) + ": " + e;
    for (size_t k = 0; k < doc.shapes.size(); ++k)
        for (const std::vector<Vec2>& path : doc.shapes[k].subpaths)
            for (const Vec2& p : path)
                if (!(std::fabs(p.x) <= kMaxCoordinate && std::fabs(p.y) <= kMaxCoordinate))
                    return "shape " + std::to_string(k) +
                           ": a point lies beyond the coordinate limit of 1e7 pixels";
    return {};
}

std::string gradientProblem(const LinearGradient& g) {
    auto unit = [](double x) { return x >= 0 && x <= 1; };
    const size_t n = g.stops.size();
    if (n < 2 || n > kMaxGradientStops)
        return std::to_string(n) + " stops, not 2-" + std::to_string(kMaxGradientStops);
    for (const Vec2& p : {g.from, g.to})
        if (!(std::fabs(p.x) <= kMaxCoordinate && std::fabs(p.y) <= kMaxCoordinate))
            return "an end lies beyond the coordinate limit of 1e7 pixels";
    if (!(norm(g.to - g.from) > kMinGradientLength)) return "its ends are the same point";
    if (g.stops.front().offset != 0 || g.stops.back().offset != 1)
        return "offsets do not run from 0 to 1";
    for (size_t k = 0; k < n; ++k) {
        const GradientStop& s = g.stops[k];
        if (!unit(s.col.r) || !unit(s.col.g) || !unit(s.col.b))
            return "a stop's colour is outside 0-1";
        if (k > 0 && !(s.offset > g.stops[k - 1].offset)) return "offsets do not increase";
    }
    return {};
}

std::string validateShape(const FlatShape& shape, size_t meshCount) {
    auto unit = [](double x) { return x >= 0 && x <= 1; };
    if (!unit(shape.col.r) || !unit(shape.col.g) || !unit(shape.col.b) || !unit(shape.alpha))
        return "colour or opacity outside 0-1";
    if (shape.layer > meshCount) return "painted above a mesh that does not exist";
    if (shape.subpaths.empty()) return "no outline";
    if (!(shape.strokeWidth >= 0 && shape.strokeWidth <= kMaxStrokeWidth))
        return "stroke width outside 0-10000 pixels";
    if (shape.graded()) {
        if (shape.stroked()) return "a stroke painted with a gradient";
        if (auto e = gradientProblem(shape.gradient); !e.empty()) return "gradient: " + e;
    }
    for (const std::vector<Vec2>& path : shape.subpaths) {
        if (shape.stroked() && (path.size() < 4 || path.size() % 3 != 1))
            return "a centreline's point count is not 3n + 1 with n >= 1";
        if (!shape.stroked() && (path.empty() || path.size() % 3 != 0))
            return "a subpath's point count is not a positive multiple of 3";
        for (const Vec2& p : path)
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) return "a point is not finite";
    }
    return {};
}

std::string validateDocument(const Document& doc) {
    if (doc.width <= 0 || doc.height <= 0)
        return "canvas size " + std::to_string(doc.width) + "x" + std::to_string(doc.height) +
               " is not positive";
    for (size_t k = 0; k < doc.meshes.size(); ++k)
        if (auto e = validateMesh(doc.meshes[k]); !e.empty())
            return "mesh " + std::to_string(k) + ": " + e;
    for (size_t k = 0; k < doc.shapes.size(); ++k) {
        if (auto e = validateShape(doc.shapes[k], doc.meshes.size()); !e.empty())
            return "shape " + std::to_string(k) + ": " + e;
        if (k > 0 && doc.shapes[k].layer < doc.shapes[k - 1].layer)
            return "shape " + std::to_string(k) + ": painted below the shape before it";
    }
    return {};
}

int countFoldedPatches(const GradientMesh& mesh, int samples) {
    int folded = 0;
    for (int j = 0; j < mesh.rows(); ++j)
        for (int i = 0; i < mesh.columns(); ++i) {
            const PatchHermite h = patchHermite(mesh, i, j);
            bool fold = false;
            for (int a = 0; a < samples && !fold; ++a)
                for (int b = 0; b < samples && !fold; ++b) {
                    const PatchPoint p = evaluatePatch(h, (a + 0.5) / samples, (b + 0.5) / samples);
                    fold = cross(p.posS, p.posT) <= 0;
                }
            folded += fold;
        }
    return folded;
}

double foldedArea(const GradientMesh& mesh, int samples) {
    double area = 0;
    const double weight = 1.0 / (double(samples) * samples);
    for (int j = 0; j < mesh.rows(); ++j)
        for (int i = 0; i < mesh.columns(); ++i) {
            const PatchHermite h = patchHermite(mesh, i, j);
            for (int a = 0; a < samples; ++a)
                for (int b = 0; b < samples; ++b) {
                    const PatchPoint p = evaluatePatch(h, (a + 0.5) / samples, (b + 0.5) / samples);
                    const double jac = cross(p.posS, p.posT);
                    if (jac < 0) area -= jac * weight;
                }
        }
    return area;
}

}  // namespace gm
