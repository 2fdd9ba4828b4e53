#include "converters/unfold.h"

#include <algorithm>
#include <array>
#include <vector>

#include "meshcore/evaluate.h"
#include "meshcore/geometry.h"

namespace gm {

namespace {

// The Hermite basis and its derivative at n sample points (k + 0.5) / n, for patchFolds.
struct SampleBasis {
    int n = 0;
    std::vector<std::array<double, 4>> h, dh;
    explicit SampleBasis(int samples) : n(samples), h(samples), dh(samples) {
        for (int k = 0; k < n; ++k) {
            hermiteBasis((k + 0.5) / n, h[k].data());
            hermiteBasisDerivative((k + 0.5) / n, dh[k].data());
        }
    }
};

// Whether the patch's Jacobian is ≤ 0 at a sample point (countFoldedPatches' test, positions
// only: this runs on every patch of every grid that refinement builds).
bool patchFolds(const GradientMesh& mesh, int i, int j, const SampleBasis& basis) {
    const PatchHermite p = patchHermite(mesh, i, j);
    auto pos = [](const HermiteCorner& c) { return c.pos; };
    auto posS = [](const HermiteCorner& c) { return c.posS; };
    auto posT = [](const HermiteCorner& c) { return c.posT; };
    for (int a = 0; a < basis.n; ++a) {
        const auto &hs = basis.h[a], &dhs = basis.dh[a];
        for (int b = 0; b < basis.n; ++b) {
            const auto &ht = basis.h[b], &dht = basis.dh[b];
            const Vec2 ds = hermiteSum<Vec2>(p, dhs.data(), ht.data(), pos, posS, posT);
            const Vec2 dt = hermiteSum<Vec2>(p, hs.data(), dht.data(), pos, posS, posT);
            if (cross(ds, dt) <= 0) return true;
        }
    }
    return false;
}

}  // namespace

UnfoldResult unfoldPatches(GradientMesh& mesh, const UnfoldOptions& options) {
    UnfoldResult result;
    const int C = mesh.columns(), R = mesh.rows();
    const size_t nNodes = static_cast<size_t>(C + 1) * (R + 1);
    auto nodeIndex = [&](int i, int j) { return static_cast<size_t>(j) * (C + 1) + i; };

    const SampleBasis basis(options.samples);
    std::vector<uint8_t> folded(static_cast<size_t>(C) * R);
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < C; ++i) {
            folded[static_cast<size_t>(j) * C + i] = patchFolds(mesh, i, j, basis);
            result.before += folded[static_cast<size_t>(j) * C + i];
        }
    result.after = result.before;
    // Corner breaks belong to legacy pieces, which are cut from finished meshes: left alone.
    if (result.before == 0 || !mesh.tangents.empty()) return result;

    // Which derivatives may move: not the ones along the rectangle's sides (the outline), and
    // nothing on a slit row's run (the hole outline, the ±d ends, the below copies).
    std::vector<uint8_t> freeU(nNodes, 1), freeV(nNodes, 1);
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            const size_t k = nodeIndex(i, j);
            if (j == 0 || j == R) freeU[k] = 0;
            if (i == 0 || i == C) freeV[k] = 0;
        }
    // Patches with a corner on a slit run are not mended: beside a slit end the Jacobian
    // vanishes by design (the hole outline turns there), and pulling the patch's other corners
    // swings it over the hole.
    std::vector<uint8_t> besideSlit(folded.size(), 0);
    for (const Slit& s : mesh.slits)
        for (int i = s.i0; i <= s.i1; ++i) {
            freeU[nodeIndex(i, s.row)] = freeV[nodeIndex(i, s.row)] = 0;
            for (int pj = s.row - 1; pj <= s.row; ++pj)
                for (int pi = std::max(0, i - 1); pi <= std::min(C - 1, i); ++pi)
                    besideSlit[static_cast<size_t>(pj) * C + pi] = 1;
        }
    // ... nor are their corners moved for a neighbour's sake.
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < C; ++i)
            if (besideSlit[static_cast<size_t>(j) * C + i])
                for (int b = 0; b < 2; ++b)
                    for (int a = 0; a < 2; ++a) {
                        const size_t k = nodeIndex(i + a, j + b);
                        freeU[k] = freeV[k] = 0;
                    }

    // Chord derivatives: central differences of the neighbouring nodes along each grid line.
    const std::vector<Node> original = mesh.nodes;
    std::vector<Vec2> chordU(nNodes), chordV(nNodes);
    for (int j = 0; j <= R; ++j)
        for (int i = 0; i <= C; ++i) {
            const int il = std::max(0, i - 1), ir = std::min(C, i + 1);
            const int jl = std::max(0, j - 1), jr = std::min(R, j + 1);
            chordU[nodeIndex(i, j)] = (1.0 / (mesh.u[ir] - mesh.u[il])) *
                                      (original[nodeIndex(ir, j)].pos - original[nodeIndex(il, j)].pos);
            chordV[nodeIndex(i, j)] = (1.0 / (mesh.v[jr] - mesh.v[jl])) *
                                      (original[nodeIndex(i, jr)].pos - original[nodeIndex(i, jl)].pos);
        }
    // Step L of a derivative: the original (0), blended toward the chord (1–4), the chord
    // shortened (5 on).
    auto stepped = [](Vec2 orig, Vec2 chord, int step) {
        if (step <= 0) return orig;
        if (step <= 4) return chord + (step == 4 ? 0.0 : 1.0 / (1 << step)) * (orig - chord);
        return (1.0 / (1 << (step - 4))) * chord;
    };
    std::vector<int> step(nNodes, 0);
    auto apply = [&](size_t k) {
        if (freeU[k]) mesh.nodes[k].posU = stepped(original[k].posU, chordU[k], step[k]);
        if (freeV[k]) mesh.nodes[k].posV = stepped(original[k].posV, chordV[k], step[k]);
    };

    // One folded patch at a time: its movable corners taken further, step by step, until the
    // folded patches around them (3×3) are fewer; kept then, else put back.
    auto around = [&](int i, int j, std::vector<size_t>& ps) {
        ps.clear();
        for (int pj = std::max(0, j - 1); pj <= std::min(R - 1, j + 1); ++pj)
            for (int pi = std::max(0, i - 1); pi <= std::min(C - 1, i + 1); ++pi)
                ps.push_back(static_cast<size_t>(pj) * C + pi);
    };
    std::vector<size_t> ps, corners;
    std::vector<uint8_t> now;
    for (int pass = 0; pass < options.maxPasses && result.after > 0; ++pass) {
        bool changed = false;
        for (int j = 0; j < R; ++j)
            for (int i = 0; i < C; ++i) {
                if (!folded[static_cast<size_t>(j) * C + i] || besideSlit[static_cast<size_t>(j) * C + i])
                    continue;
                corners.clear();
                for (int b = 0; b < 2; ++b)
                    for (int a = 0; a < 2; ++a) {
                        const size_t k = nodeIndex(i + a, j + b);
                        if ((freeU[k] || freeV[k]) && step[k] < options.maxSteps) corners.push_back(k);
                    }
                if (corners.empty()) continue;
                around(i, j, ps);
                int was = 0;
                for (size_t p : ps) was += folded[p];
                const std::vector<int> start = [&] {
                    std::vector<int> v;
                    for (size_t k : corners) v.push_back(step[k]);
                    return v;
                }();
                bool kept = false;
                for (int extra = 1; extra <= options.maxSteps && !kept; ++extra) {
                    bool any = false;
                    for (size_t c = 0; c < corners.size(); ++c) {
                        const int target = std::min(options.maxSteps, start[c] + extra);
                        if (target != step[corners[c]]) any = true;
                        step[corners[c]] = target;
                        apply(corners[c]);
                    }
                    if (!any) break;
                    now.resize(ps.size());
                    int is = 0;
                    for (size_t t = 0; t < ps.size(); ++t) {
                        now[t] = patchFolds(mesh, static_cast<int>(ps[t] % C), static_cast<int>(ps[t] / C),
                                            basis);
                        is += now[t];
                    }
                    if (is < was) {
                        for (size_t t = 0; t < ps.size(); ++t) folded[ps[t]] = now[t];
                        result.after -= was - is;
                        kept = changed = true;
                    }
                }
                if (!kept)
                    for (size_t c = 0; c < corners.size(); ++c) {
                        step[corners[c]] = start[c];
                        apply(corners[c]);
                    }
            }
        if (!changed) break;
    }
    for (size_t k = 0; k < nNodes; ++k) result.nodesChanged += step[k] > 0;
    return result;
}

}  // namespace gm
