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

// Step L of a derivative: the original (0), blended toward the chord (1–4), the chord
// shortened (5 on).
Vec2 stepped(Vec2 orig, Vec2 chord, int step) {
    if (step <= 0) return orig;
    if (step <= 4) return chord + (step == 4 ? 0.0 : 1.0 / (1 << step)) * (orig - chord);
    return (1.0 / (1 << (step - 4))) * chord;
}

// unfoldPatches on one mesh: which derivatives may move, their chords, and the mending of one
// folded patch at a time.
class PatchUnfolder {
public:
    PatchUnfolder(GradientMesh& mesh, const UnfoldOptions& options)
        : mesh_(mesh), options_(options), C_(mesh.columns()), R_(mesh.rows()),
          nNodes_(static_cast<size_t>(C_ + 1) * (R_ + 1)), basis_(options.samples),
          folded_(static_cast<size_t>(C_) * R_) {}

    UnfoldResult run() {
        UnfoldResult result;
        for (int j = 0; j < R_; ++j)
            for (int i = 0; i < C_; ++i) {
                folded_[patchIndex(i, j)] = patchFolds(mesh_, i, j, basis_);
                result.before += folded_[patchIndex(i, j)];
            }
        result.after = result.before;
        // Corner breaks belong to legacy pieces, which are cut from finished meshes: left alone.
        if (result.before == 0 || !mesh_.tangents.empty()) return result;
        markMovable();
        chordDerivatives();
        step_.assign(nNodes_, 0);
        for (int pass = 0; pass < options_.maxPasses && result.after > 0; ++pass) {
            bool changed = false;
            for (int j = 0; j < R_; ++j)
                for (int i = 0; i < C_; ++i) {
                    if (!folded_[patchIndex(i, j)] || besideSlit_[patchIndex(i, j)]) continue;
                    if (const int fewer = mendPatch(i, j); fewer > 0) {
                        result.after -= fewer;
                        changed = true;
                    }
                }
            if (!changed) break;
        }
        for (size_t k = 0; k < nNodes_; ++k) result.nodesChanged += step_[k] > 0;
        return result;
    }

private:
    size_t nodeIndex(int i, int j) const { return static_cast<size_t>(j) * (C_ + 1) + i; }
    size_t patchIndex(int i, int j) const { return static_cast<size_t>(j) * C_ + i; }

    // Which derivatives may move: not the ones along the rectangle's sides (the outline), and
    // nothing on a slit row's run (the hole outline, the ±d ends, the below copies). Patches
    // with a corner on a slit run are not mended: beside a slit end the Jacobian vanishes by
    // design (the hole outline turns there), and pulling the patch's other corners swings it
    // over the hole; nor are their corners moved for a neighbour's sake.
    void markMovable() {
        freeU_.assign(nNodes_, 1);
        freeV_.assign(nNodes_, 1);
        for (int j = 0; j <= R_; ++j)
            for (int i = 0; i <= C_; ++i) {
                const size_t k = nodeIndex(i, j);
                if (j == 0 || j == R_) freeU_[k] = 0;
                if (i == 0 || i == C_) freeV_[k] = 0;
            }
        besideSlit_.assign(folded_.size(), 0);
        for (const Slit& s : mesh_.slits)
            for (int i = s.i0; i <= s.i1; ++i) {
                freeU_[nodeIndex(i, s.row)] = freeV_[nodeIndex(i, s.row)] = 0;
                for (int pj = s.row - 1; pj <= s.row; ++pj)
                    for (int pi = std::max(0, i - 1); pi <= std::min(C_ - 1, i); ++pi)
                        besideSlit_[patchIndex(pi, pj)] = 1;
            }
        for (int j = 0; j < R_; ++j)
            for (int i = 0; i < C_; ++i)
                if (besideSlit_[patchIndex(i, j)])
                    for (int b = 0; b < 2; ++b)
                        for (int a = 0; a < 2; ++a) {
                            const size_t k = nodeIndex(i + a, j + b);
                            freeU_[k] = freeV_[k] = 0;
                        }
    }

    // Chord derivatives: central differences of the neighbouring nodes along each grid line.
    void chordDerivatives() {
        original_ = mesh_.nodes;
        chordU_.resize(nNodes_);
        chordV_.resize(nNodes_);
        for (int j = 0; j <= R_; ++j)
            for (int i = 0; i <= C_; ++i) {
                const int il = std::max(0, i - 1), ir = std::min(C_, i + 1);
                const int jl = std::max(0, j - 1), jr = std::min(R_, j + 1);
                chordU_[nodeIndex(i, j)] =
                    (1.0 / (mesh_.u[ir] - mesh_.u[il])) *
                    (original_[nodeIndex(ir, j)].pos - original_[nodeIndex(il, j)].pos);
                chordV_[nodeIndex(i, j)] =
                    (1.0 / (mesh_.v[jr] - mesh_.v[jl])) *
                    (original_[nodeIndex(i, jr)].pos - original_[nodeIndex(i, jl)].pos);
            }
    }

    void apply(size_t k) {
        if (freeU_[k]) mesh_.nodes[k].posU = stepped(original_[k].posU, chordU_[k], step_[k]);
        if (freeV_[k]) mesh_.nodes[k].posV = stepped(original_[k].posV, chordV_[k], step_[k]);
    }

    // Folded patch (i,j): its movable corners taken further, step by step, until the folded
    // patches around them (3×3) are fewer; kept then (returns how many fewer), else put back.
    int mendPatch(int i, int j) {
        std::vector<size_t> corners;
        for (int b = 0; b < 2; ++b)
            for (int a = 0; a < 2; ++a) {
                const size_t k = nodeIndex(i + a, j + b);
                if ((freeU_[k] || freeV_[k]) && step_[k] < options_.maxSteps) corners.push_back(k);
            }
        if (corners.empty()) return 0;
        std::vector<size_t> ps;  // the patches around
        for (int pj = std::max(0, j - 1); pj <= std::min(R_ - 1, j + 1); ++pj)
            for (int pi = std::max(0, i - 1); pi <= std::min(C_ - 1, i + 1); ++pi)
                ps.push_back(patchIndex(pi, pj));
        int was = 0;
        for (size_t p : ps) was += folded_[p];
        std::vector<int> start;
        for (size_t k : corners) start.push_back(step_[k]);
        std::vector<uint8_t> now(ps.size());
        for (int extra = 1; extra <= options_.maxSteps; ++extra) {
            bool any = false;
            for (size_t c = 0; c < corners.size(); ++c) {
                const int target = std::min(options_.maxSteps, start[c] + extra);
                if (target != step_[corners[c]]) any = true;
                step_[corners[c]] = target;
                apply(corners[c]);
            }
            if (!any) break;
            int is = 0;
            for (size_t t = 0; t < ps.size(); ++t) {
                now[t] = patchFolds(mesh_, static_cast<int>(ps[t] % C_), static_cast<int>(ps[t] / C_),
                                    basis_);
                is += now[t];
            }
            if (is < was) {
                for (size_t t = 0; t < ps.size(); ++t) folded_[ps[t]] = now[t];
                return was - is;
            }
        }
        for (size_t c = 0; c < corners.size(); ++c) {
            step_[corners[c]] = start[c];
            apply(corners[c]);
        }
        return 0;
    }

    GradientMesh& mesh_;
    const UnfoldOptions& options_;
    const int C_, R_;
    const size_t nNodes_;
    const SampleBasis basis_;
    std::vector<uint8_t> folded_, besideSlit_;  // per patch
    std::vector<uint8_t> freeU_, freeV_;        // per node: the derivative may move
    std::vector<Node> original_;
    std::vector<Vec2> chordU_, chordV_;
    std::vector<int> step_;  // per node: how far its derivatives have been taken
};

}  // namespace

UnfoldResult unfoldPatches(GradientMesh& mesh, const UnfoldOptions& options) {
    return PatchUnfolder(mesh, options).run();
}

}  // namespace gm
