#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "formats/svg.h"
#include "meshcore/bezier_patch.h"
#include "meshcore/color_subdivision.h"
#include "meshcore/error.h"
#include "meshcore/split_legacy.h"
#include "meshcore/validate.h"
#include "svg_number.h"
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

// Exact mode: patch column i split ku[i] times, patch row j kv[j] times.
SvgPatchGrid refinedGrid(const GradientMesh& mesh, double tolerance, double minPiece, int* maxK) {
    const int C = mesh.columns(), R = mesh.rows();
    const std::vector<BezierPatch> base = meshPatches(mesh);
    std::vector<int> ku(static_cast<size_t>(C), 1), kv(static_cast<size_t>(R), 1);
    for (int j = 0; j < R; ++j) {
        for (int i = 0; i < C; ++i) {
            const auto [ks, kt] =
                exactColorPieces(base[static_cast<size_t>(j) * C + i], tolerance, minPiece);
            ku[i] = std::max(ku[i], ks);
            kv[j] = std::max(kv[j], kt);
        }
    }
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
    for (int k : ku) *maxK = std::max(*maxK, k);
    for (int k : kv) *maxK = std::max(*maxK, k);
    return gridFromPatches(fine, nu, nv);
}

void appendPair(std::string& out, Vec2 d) {
    appendSvgNumber(out, d.x);
    out += ',';
    appendSvgNumber(out, d.y);
}

Vec2 printed(Vec2 d) { return {svgPrintedValue(d.x), svgPrintedValue(d.y)}; }

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

// One <stop>: an edge from `start` (where the reader stands) through handles h1, h2 to `end`.
// Writes offsets relative to `start` as the reader will have reconstructed it, so rounding
// never accumulates along the grid; returns the end point the reader reconstructs.
Vec2 appendStop(std::string& out, Vec2 start, Vec2 h1, Vec2 h2, Vec2 end, bool closing,
                const Vec3* color) {
    out += "<stop path=\"";
    const Vec2 chord = end - start;
    const bool line = nearlyEqual(h1, start + (1.0 / 3) * chord, 1e-6) &&
                      nearlyEqual(h2, start + (2.0 / 3) * chord, 1e-6);
    Vec2 reached = end;
    if (line) {
        out += 'l';
        if (!closing) {
            out += ' ';
            const Vec2 d = end - start;
            appendPair(out, d);
            reached = start + printed(d);
        }
    } else {
        out += "c ";
        appendPair(out, h1 - start);
        out += ' ';
        appendPair(out, h2 - start);
        if (!closing) {
            out += ' ';
            const Vec2 d = end - start;
            appendPair(out, d);
            reached = start + printed(d);
        }
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

// The interior point Inkscape assumes when a patch has no `tensor` attribute (the Coons patch
// written as a tensor patch, PDF reference §4.6.3), for the corner q[ix(0)][iy(0)].
Vec2 coonsInterior(const Vec2 (&q)[4][4], bool mirrorU, bool mirrorV) {
    auto at = [&](int a, int b) -> Vec2 {
        return q[mirrorU ? 3 - a : a][mirrorV ? 3 - b : b];
    };
    return (1.0 / 9) * (-4.0 * at(0, 0) + 6.0 * (at(1, 0) + at(0, 1)) -
                        2.0 * (at(3, 0) + at(0, 3)) + 3.0 * (at(1, 3) + at(3, 1)) - at(3, 3));
}

void appendMeshGradient(std::string& out, const SvgPatchGrid& g, const std::string& id,
                        bool bicubic, bool withTensor) {
    const int nu = g.columns, nv = g.rows;
    // Corners as the reader reconstructs them.
    std::vector<Vec2> rec(static_cast<size_t>(nu + 1) * (nv + 1));
    auto R = [&](int c, int r) -> Vec2& { return rec[static_cast<size_t>(r) * (nu + 1) + c]; };
    R(0, 0) = printed(g.P(0, 0));

    out += "<meshgradient id=\"" + id + "\" gradientUnits=\"userSpaceOnUse\" x=\"";
    appendSvgNumber(out, g.P(0, 0).x, false);
    out += "\" y=\"";
    appendSvgNumber(out, g.P(0, 0).y, false);
    out += '"';
    if (bicubic) out += " type=\"bicubic\"";
    out += ">\n";
    std::string stops;
    for (int r = 0; r < nv; ++r) {
        out += "<meshrow>\n";
        for (int c = 0; c < nu; ++c) {
            stops.clear();
            if (r == 0) {  // top, from (c,0) to (c+1,0)
                const auto& h = g.H(c, 0);
                R(c + 1, 0) = appendStop(stops, R(c, 0), h[0], h[1], g.P(c + 1, 0), false,
                                         c == 0 ? &g.C(c, 0) : nullptr);
            }
            {  // right, from (c+1,r) to (c+1,r+1)
                const auto& h = g.V(c + 1, r);
                R(c + 1, r + 1) = appendStop(stops, R(c + 1, r), h[0], h[1], g.P(c + 1, r + 1),
                                             false, r == 0 ? &g.C(c + 1, r) : nullptr);
            }
            {  // bottom, from (c+1,r+1) to (c,r+1); closes the patch unless c == 0
                const auto& h = g.H(c, r + 1);
                const Vec2 e = appendStop(stops, R(c + 1, r + 1), h[1], h[0], g.P(c, r + 1),
                                          c > 0, &g.C(c + 1, r + 1));
                if (c == 0) R(0, r + 1) = e;
            }
            if (c == 0) {  // left, from (0,r+1) to (0,r): always closing
                const auto& h = g.V(0, r);
                appendStop(stops, R(0, r + 1), h[1], h[0], g.P(0, r), true, &g.C(0, r + 1));
            }
            out += "<meshpatch";
            const size_t pi = g.patchIndex(c, r);
            if (withTensor && g.tensorSet[pi]) {
                // Reconstructed control net, to compare with the Coons interior Inkscape
                // would assume: the attribute is left out when it would change nothing.
                Vec2 q[4][4];
                const Vec2 c00 = R(c, r), c30 = R(c + 1, r), c33 = R(c + 1, r + 1),
                           c03 = R(c, r + 1);
                q[0][0] = c00;
                q[3][0] = c30;
                q[3][3] = c33;
                q[0][3] = c03;
                q[1][0] = c00 + printed(g.H(c, r)[0] - c00);
                q[2][0] = c00 + printed(g.H(c, r)[1] - c00);
                q[3][1] = c30 + printed(g.V(c + 1, r)[0] - c30);
                q[3][2] = c30 + printed(g.V(c + 1, r)[1] - c30);
                q[2][3] = c33 + printed(g.H(c, r + 1)[1] - c33);
                q[1][3] = c33 + printed(g.H(c, r + 1)[0] - c33);
                q[0][2] = c03 + printed(g.V(c, r)[1] - c03);
                q[0][1] = c03 + printed(g.V(c, r)[0] - c03);
                const auto& t = g.tensor[pi];
                const Vec2 coons[4] = {coonsInterior(q, false, false), coonsInterior(q, true, false),
                                       coonsInterior(q, true, true), coonsInterior(q, false, true)};
                const Vec2 base[4] = {c00, c30, c33, c03};
                bool differs = false;
                for (int k = 0; k < 4; ++k)
                    if (!nearlyEqual(printed(t[k] - base[k]), coons[k] - base[k], 1.5e-4))
                        differs = true;
                if (differs) {
                    out += " tensor=\"";
                    for (int k = 0; k < 4; ++k) {
                        if (k) out += ' ';
                        appendPair(out, t[k] - base[k]);
                    }
                    out += '"';
                }
            }
            out += '>';
            out += stops;
            out += "</meshpatch>\n";
        }
        out += "</meshrow>\n";
    }
    out += "</meshgradient>\n";
}

void appendPoint(std::string& out, Vec2 p) {
    appendSvgNumber(out, p.x);
    out += ',';
    appendSvgNumber(out, p.y);
}

// The outline of a hole-free mesh as one closed path of its boundary curves.
void appendOutline(std::string& out, const SvgPatchGrid& g, const std::string& id) {
    const int C = g.columns, R = g.rows;
    out += "<path fill=\"url(#" + id + ")\" d=\"M";
    appendPoint(out, g.P(0, 0));
    auto curve = [&](Vec2 h1, Vec2 h2, Vec2 e) {
        out += " C";
        appendPoint(out, h1);
        out += ' ';
        appendPoint(out, h2);
        out += ' ';
        appendPoint(out, e);
    };
    for (int i = 0; i < C; ++i) curve(g.H(i, 0)[0], g.H(i, 0)[1], g.P(i + 1, 0));
    for (int j = 0; j < R; ++j) curve(g.V(C, j)[0], g.V(C, j)[1], g.P(C, j + 1));
    for (int i = C - 1; i >= 0; --i) curve(g.H(i, R)[1], g.H(i, R)[0], g.P(i, R));
    for (int j = R - 1; j >= 0; --j) curve(g.V(0, j)[1], g.V(0, j)[0], g.P(0, j));
    out += " Z\"/>\n";
}

}  // namespace

std::string encodeSvg(const Document& doc, const WriteOptions& options, SvgEncodeStats* stats) {
    const bool editable = options.svgColors == "editable";
    if (!editable && options.svgColors != "exact")
        throw Error("unknown SVG colour mode '" + options.svgColors +
                    "' (expected 'exact' or 'editable')");
    if (!(options.colorTolerance > 0) || !std::isfinite(options.colorTolerance))
        throw Error("the colour tolerance must be a positive number");
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error("cannot write an invalid document: " + problem);

    SvgEncodeStats local;
    std::string out;
    out += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out += "<!-- gradmesh: SVG 2 meshgradient; rendered by Inkscape, not by browsers -->\n";
    out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(doc.width) +
           "\" height=\"" + std::to_string(doc.height) + "\" viewBox=\"0 0 " +
           std::to_string(doc.width) + " " + std::to_string(doc.height) + "\">\n<defs>\n";
    std::string paths;
    int n = 0;
    for (const GradientMesh& mesh : doc.meshes) {
        std::vector<GradientMesh> pieces;
        if (options.legacy || !mesh.slits.empty())
            pieces = splitIntoLegacyMeshes(mesh);
        else
            pieces.push_back(mesh);
        for (const GradientMesh& piece : pieces) {
            const std::string id = "mesh" + std::to_string(n++);
            const SvgPatchGrid base = gridFromPatches(meshPatches(piece), piece.columns(),
                                                      piece.rows());
            if (editable) {
                appendMeshGradient(out, base, id, true, true);
                local.svgPatches += base.columns * int64_t(base.rows);
            } else {
                const SvgPatchGrid fine = refinedGrid(piece, options.colorTolerance, options.minPiece,
                                                      &local.maxSubdivision);
                appendMeshGradient(out, fine, id, false, true);
                local.svgPatches += fine.columns * int64_t(fine.rows);
            }
            ++local.meshGradients;
            appendOutline(paths, base, id);
        }
    }
    out += "</defs>\n";
    out += paths;
    out += "</svg>\n";
    if (stats) *stats = local;
    return out;
}

std::string encodeSvg(const Document& doc, const WriteOptions& options) {
    return encodeSvg(doc, options, nullptr);
}

}  // namespace gm
