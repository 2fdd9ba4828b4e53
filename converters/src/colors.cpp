#include "converters/colors.h"

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "bicubic_fit.h"
#include "meshcore/bicubic_colors.h"
#include "meshcore/color_rule.h"
#include "meshcore/error.h"
#include "meshcore/evaluate.h"
#include "meshcore/validate.h"

namespace gm {

namespace {

void checkSizes(const RgbaImage& image, const Region& region) {
    if (region.width != image.width || region.height != image.height)
        throw Error("colours: the region's size differs from the image's");
    if (region.mask.size() != static_cast<size_t>(image.width) * image.height)
        throw Error("colours: the region's mask does not match its size");
}

Vec3 pixelColor(const RgbaImage& image, int x, int y) {
    const float* p = image.at(x, y);
    return {p[0], p[1], p[2]};
}

// Where each unknown of the colour fit lives. Values: node copies (nodes, then slit `below`
// copies). u-slopes: node copies, slit ends (left, right per slit), corner tangents.
// v-slopes: node copies.
struct SlotLayout {
    int nNodes = 0, nCopies = 0;  // copies = nodes + below copies
    std::vector<int> belowBase;   // first copy index of each slit's below copies
    int endBase = 0, tangentBase = 0, nU = 0;
    int valueOffset() const { return 0; }
    int uOffset() const { return nCopies; }
    int vOffset() const { return nCopies + nU; }
    int total() const { return nCopies + nU + nCopies; }

    explicit SlotLayout(const GradientMesh& mesh) {
        nNodes = static_cast<int>(mesh.nodes.size());
        nCopies = nNodes;
        for (const Slit& s : mesh.slits) {
            belowBase.push_back(nCopies);
            nCopies += static_cast<int>(s.below.size());
        }
        endBase = nCopies;
        tangentBase = endBase + 2 * static_cast<int>(mesh.slits.size());
        nU = tangentBase + static_cast<int>(mesh.tangents.size());
    }
};

// The unknowns one patch uses, resolved exactly as patchHermite resolves them: per corner
// (a,b) the value copy, the u-slope slot with its sign, the v-slope copy.
struct PatchSlots {
    int value[2][2], uSlot[2][2], vSlot[2][2];
    double uSign[2][2];
};

PatchSlots patchSlots(const GradientMesh& mesh, const SlotLayout& L, int i, int j) {
    PatchSlots ps;
    const int C = mesh.columns();
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            const int col = i + a, row = j + b;
            int copy = row * (C + 1) + col;
            int uSlot = copy;
            double sign = 1;
            for (size_t k = 0; k < mesh.slits.size(); ++k) {
                const Slit& s = mesh.slits[k];
                if (s.row != row) continue;
                const bool below = (b == 0);
                if (col > s.i0 && col < s.i1 && below) {
                    copy = L.belowBase[k] + (col - s.i0 - 1);
                    uSlot = copy;
                    sign = 1;
                } else if (col == s.i0 && a == 0) {
                    uSlot = L.endBase + 2 * static_cast<int>(k);
                    sign = below ? -1 : 1;
                } else if (col == s.i1 && a == 1) {
                    uSlot = L.endBase + 2 * static_cast<int>(k) + 1;
                    sign = below ? -1 : 1;
                }
            }
            for (size_t k = 0; k < mesh.tangents.size(); ++k) {
                const CornerTangent& t = mesh.tangents[k];
                if (t.i == i && t.j == j && t.a == a && t.b == b) {
                    uSlot = L.tangentBase + static_cast<int>(k);
                    sign = 1;
                }
            }
            ps.value[a][b] = L.valueOffset() + copy;
            ps.uSlot[a][b] = L.uOffset() + uSlot;
            ps.uSign[a][b] = sign;
            ps.vSlot[a][b] = L.vOffset() + copy;
        }
    }
    return ps;
}

// The mesh's colour unknowns as one vector per channel, and back.
void gatherColors(const GradientMesh& mesh, const SlotLayout& L, Eigen::MatrixXd& x) {
    x.resize(L.total(), 3);
    auto put = [&](int row, Vec3 c) {
        for (int k = 0; k < 3; ++k) x(row, k) = c[k];
    };
    for (int n = 0; n < L.nNodes; ++n) {
        put(L.valueOffset() + n, mesh.nodes[n].col);
        put(L.uOffset() + n, mesh.nodes[n].colU);
        put(L.vOffset() + n, mesh.nodes[n].colV);
    }
    for (size_t s = 0; s < mesh.slits.size(); ++s) {
        const Slit& sl = mesh.slits[s];
        for (size_t k = 0; k < sl.below.size(); ++k) {
            const int c = L.belowBase[s] + static_cast<int>(k);
            put(L.valueOffset() + c, sl.below[k].col);
            put(L.uOffset() + c, sl.below[k].colU);
            put(L.vOffset() + c, sl.below[k].colV);
        }
        put(L.uOffset() + L.endBase + 2 * static_cast<int>(s), sl.left.colU);
        put(L.uOffset() + L.endBase + 2 * static_cast<int>(s) + 1, sl.right.colU);
    }
    for (size_t t = 0; t < mesh.tangents.size(); ++t)
        put(L.uOffset() + L.tangentBase + static_cast<int>(t), mesh.tangents[t].colU);
}

void scatterColors(GradientMesh& mesh, const SlotLayout& L, const Eigen::MatrixXd& x) {
    auto get = [&](int row) { return Vec3{x(row, 0), x(row, 1), x(row, 2)}; };
    for (int n = 0; n < L.nNodes; ++n) {
        mesh.nodes[n].col = get(L.valueOffset() + n);
        mesh.nodes[n].colU = get(L.uOffset() + n);
        mesh.nodes[n].colV = get(L.vOffset() + n);
    }
    for (size_t s = 0; s < mesh.slits.size(); ++s) {
        Slit& sl = mesh.slits[s];
        for (size_t k = 0; k < sl.below.size(); ++k) {
            const int c = L.belowBase[s] + static_cast<int>(k);
            sl.below[k].col = get(L.valueOffset() + c);
            sl.below[k].colU = get(L.uOffset() + c);
            sl.below[k].colV = get(L.vOffset() + c);
        }
        sl.left.colU = get(L.uOffset() + L.endBase + 2 * static_cast<int>(s));
        sl.right.colU = get(L.uOffset() + L.endBase + 2 * static_cast<int>(s) + 1);
    }
    for (size_t t = 0; t < mesh.tangents.size(); ++t)
        mesh.tangents[t].colU = get(L.uOffset() + L.tangentBase + static_cast<int>(t));
}

// The 12 Hermite coefficients of a pixel at (s,t) of a patch of size du × dv, in the order
// value[a][b], u-slope[a][b], v-slope[a][b] (a-major).
void pixelCoefficients(double s, double t, double du, double dv, const PatchSlots& ps,
                       double c[12]) {
    double hs[4], ht[4];
    hermiteBasis(s, hs);
    hermiteBasis(t, ht);
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            const int k = 2 * a + b;
            c[k] = hs[a] * ht[b];
            c[4 + k] = hs[2 + a] * ht[b] * du * ps.uSign[a][b];
            c[8 + k] = hs[a] * ht[2 + b] * dv;
        }
    }
}

void slotIndices(const PatchSlots& ps, int idx[12]) {
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
            const int k = 2 * a + b;
            idx[k] = ps.value[a][b];
            idx[4 + k] = ps.uSlot[a][b];
            idx[8 + k] = ps.vSlot[a][b];
        }
    }
}

RenderResult renderForSamples(const GradientMesh& mesh, const RgbaImage& image,
                              const ColorOptions& options) {
    RenderOptions renderOptions;
    renderOptions.wantSamples = true;
    renderOptions.antialias = false;
    renderOptions.threads = options.threads;
    return renderMesh(mesh, image.width, image.height, renderOptions);
}

// Error figures of `mesh` (coloured) against the image over the region, from render samples.
void measure(const GradientMesh& mesh, const RgbaImage& image, const Region& region,
             const std::vector<PixelSample>& samples, bool keepPixels, ColorResult& out) {
    const int C = mesh.columns();
    std::vector<PatchHermite> hermite(static_cast<size_t>(mesh.patchCount()));
    for (int j = 0; j < mesh.rows(); ++j)
        for (int i = 0; i < C; ++i)
            hermite[static_cast<size_t>(j) * C + i] = patchHermite(mesh, i, j);
    out.patchError.assign(hermite.size(), 0.0);
    if (keepPixels) out.pixelError.assign(region.mask.size(), -1.0f);
    double sumAbs = 0, sumSq = 0, maxAbs = 0;
    long covered = 0, total = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const size_t p = static_cast<size_t>(y) * image.width + x;
            if (!region.mask[p]) continue;
            ++total;
            const PixelSample& ps = samples[p];
            if (ps.mesh != 0 || ps.patch < 0) continue;
            ++covered;
            double hs[4], ht[4];
            hermiteBasis(ps.s, hs);
            hermiteBasis(ps.t, ht);
            const PatchHermite& h = hermite[static_cast<size_t>(ps.patch)];
            const Vec3 c = hermiteColor(h, hs, ht);
            const Vec3 target = pixelColor(image, x, y);
            double pixelSum = 0;
            for (int ch = 0; ch < 3; ++ch) {
                const double e = 255.0 * std::abs(std::clamp(c[ch], 0.0, 1.0) - target[ch]);
                pixelSum += e;
                sumSq += e * e;
                maxAbs = std::max(maxAbs, e);
            }
            sumAbs += pixelSum;
            out.patchError[static_cast<size_t>(ps.patch)] += pixelSum / 3;
            if (keepPixels) out.pixelError[p] = static_cast<float>(pixelSum / 3);
        }
    }
    FitError& e = out.error;
    e.pixels = total;
    e.uncovered = total > 0 ? static_cast<double>(total - covered) / total : 0.0;
    e.meanAbs = covered > 0 ? sumAbs / (3.0 * covered) : 0.0;
    e.rmse = covered > 0 ? std::sqrt(sumSq / (3.0 * covered)) : 0.0;
    e.psnr =
        e.rmse > 0 ? 20.0 * std::log10(255.0 / e.rmse) : std::numeric_limits<double>::infinity();
    e.maxAbs = maxAbs;
}

// The least-squares node colours with every colour slope held at its value in `mesh`: the
// normal equations' value rows, the slopes' part moved to the right-hand side.
void fitValues(GradientMesh& mesh, const SlotLayout& L, const Eigen::SparseMatrix<double>& A,
               const Eigen::MatrixXd& rhs) {
    Eigen::MatrixXd x;
    gatherColors(mesh, L, x);
    const int nv = L.nCopies, n = L.total();
    const Eigen::SparseMatrix<double> Avv = A.topLeftCorner(nv, nv);
    const Eigen::SparseMatrix<double> Avs = A.topRightCorner(nv, n - nv);
    const Eigen::MatrixXd b = rhs.topRows(nv) - Avs * x.bottomRows(n - nv);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Avv);
    if (ldlt.info() != Eigen::Success) return;
    const Eigen::MatrixXd c = ldlt.solve(b);
    if (ldlt.info() != Eigen::Success || !c.allFinite()) return;
    x.topRows(nv) = c;
    scatterColors(mesh, L, x);
}

// Region pixels grouped by patch (a counting sort): the pixels of patch k are
// order[start[k] .. start[k+1]).
struct PixelsByPatch {
    std::vector<int> start, order;
    int count(int patch) const { return start[patch + 1] - start[patch]; }
};

PixelsByPatch groupPixelsByPatch(const RgbaImage& image, const Region& region,
                                 const std::vector<PixelSample>& samples, int meshIndex,
                                 int patches) {
    PixelsByPatch g;
    g.start.assign(static_cast<size_t>(patches) + 1, 0);
    const size_t nPix = static_cast<size_t>(image.width) * image.height;
    auto usable = [&](size_t p) {
        return region.mask[p] && samples[p].mesh == meshIndex && samples[p].patch >= 0;
    };
    for (size_t p = 0; p < nPix; ++p)
        if (usable(p)) ++g.start[static_cast<size_t>(samples[p].patch) + 1];
    for (int p = 0; p < patches; ++p) g.start[p + 1] += g.start[p];
    g.order.resize(static_cast<size_t>(g.start[patches]));
    std::vector<int> fill(g.start.begin(), g.start.end() - 1);
    for (size_t p = 0; p < nPix; ++p)
        if (usable(p)) g.order[fill[samples[p].patch]++] = static_cast<int>(p);
    return g;
}

// The normal equations A·x = rhs of the colour fit (one right-hand side per channel), with
// A's sparsity fixed before any value is added.
struct NormalEquations {
    Eigen::SparseMatrix<double> A;
    Eigen::MatrixXd rhs;

    // The entry (row, col) of A, which the pattern holds.
    double& entry(int row, int col) {
        const int* b = A.innerIndexPtr() + A.outerIndexPtr()[col];
        const int* e = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
        return A.valuePtr()[std::lower_bound(b, e, row) - A.innerIndexPtr()];
    }
};

// The n×n pattern in which two unknowns interact when a patch with pixels uses both (the 12
// unknowns of patch k are patchIdx[12k .. 12k+12)); every unknown also has its diagonal (the
// regularisation's pull). Built as compressed columns directly (the matrix is symmetric, so a
// column lists its row's neighbours too): one pass for the column sizes, one to fill, a sort
// per column; no triplet list. Values are zero.
Eigen::SparseMatrix<double> normalPattern(int n, const std::vector<int>& patchIdx,
                                          const PixelsByPatch& pixels) {
    const int P = static_cast<int>(patchIdx.size() / 12);
    std::vector<int> colStart(static_cast<size_t>(n) + 1, 0);
    for (int patch = 0; patch < P; ++patch) {
        if (pixels.count(patch) == 0) continue;
        for (int r = 0; r < 12; ++r) colStart[static_cast<size_t>(patchIdx[12 * patch + r]) + 1] += 12;
    }
    for (int k = 0; k < n; ++k) colStart[k + 1] += colStart[k] + 1;
    std::vector<int> rowsOf(static_cast<size_t>(colStart[n]));
    std::vector<int> fill(colStart.begin(), colStart.end() - 1);
    for (int k = 0; k < n; ++k) rowsOf[fill[k]++] = k;
    for (int patch = 0; patch < P; ++patch) {
        if (pixels.count(patch) == 0) continue;
        const int* idx = &patchIdx[static_cast<size_t>(patch) * 12];
        for (int r = 0; r < 12; ++r)
            for (int q = 0; q < 12; ++q) rowsOf[fill[idx[r]]++] = idx[q];
    }
    std::vector<int> length(static_cast<size_t>(n));
    size_t nnz = 0;
    for (int k = 0; k < n; ++k) {
        auto b = rowsOf.begin() + colStart[k], e = rowsOf.begin() + colStart[k + 1];
        std::sort(b, e);
        length[k] = static_cast<int>(std::unique(b, e) - b);
        nnz += static_cast<size_t>(length[k]);
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.resizeNonZeros(static_cast<Eigen::Index>(nnz));
    int* outer = A.outerIndexPtr();
    int* inner = A.innerIndexPtr();
    outer[0] = 0;
    for (int k = 0; k < n; ++k) {
        inner = std::copy_n(rowsOf.begin() + colStart[k], length[k], inner);
        outer[k + 1] = outer[k] + length[k];
    }
    std::fill(A.valuePtr(), A.valuePtr() + nnz, 0.0);
    return A;
}

// Adds each patch's pixels to the normal equations: per patch one dense 12×12 product (shared
// by the three channels) and one 12×3.
void addPatchPixels(NormalEquations& eq, const GradientMesh& mesh, const RgbaImage& image,
                    const std::vector<PixelSample>& samples, const PixelsByPatch& pixels,
                    const std::vector<PatchSlots>& slots, const std::vector<int>& patchIdx) {
    const int C = mesh.columns(), P = mesh.patchCount();
    Eigen::Matrix<double, Eigen::Dynamic, 12> Ap;
    Eigen::Matrix<double, Eigen::Dynamic, 3> Bp;
    Eigen::Matrix<double, 12, 12> M;
    Eigen::Matrix<double, 12, 3> B;
    for (int patch = 0; patch < P; ++patch) {
        const int count = pixels.count(patch);
        if (count == 0) continue;
        const int pi = patch % C, pj = patch / C;
        const double du = mesh.u[pi + 1] - mesh.u[pi], dv = mesh.v[pj + 1] - mesh.v[pj];
        const PatchSlots& ps = slots[static_cast<size_t>(patch)];
        Ap.resize(count, 12);
        Bp.resize(count, 3);
        for (int k = 0; k < count; ++k) {
            const int p = pixels.order[static_cast<size_t>(pixels.start[patch] + k)];
            const PixelSample& sample = samples[static_cast<size_t>(p)];
            double c[12];
            pixelCoefficients(sample.s, sample.t, du, dv, ps, c);
            for (int q = 0; q < 12; ++q) Ap(k, q) = c[q];
            const float* col = image.at(p % image.width, p / image.width);
            for (int ch = 0; ch < 3; ++ch) Bp(k, ch) = col[ch];
        }
        M.noalias() = Ap.transpose() * Ap;
        B.noalias() = Ap.transpose() * Bp;
        const int* idx = &patchIdx[static_cast<size_t>(patch) * 12];
        for (int r = 0; r < 12; ++r) {
            for (int q = 0; q < 12; ++q) eq.entry(idx[r], idx[q]) += M(r, q);
            for (int ch = 0; ch < 3; ++ch) eq.rhs(idx[r], ch) += B(r, ch);
        }
    }
}

// Tikhonov toward x0 (the sampled solution), scaled per kind of unknown (values, u-slopes,
// v-slopes) by its mean pixel weight.
void regularizeTowards(NormalEquations& eq, const SlotLayout& L, const Eigen::MatrixXd& x0,
                       double regularization) {
    const int kindStart[4] = {0, L.uOffset(), L.vOffset(), L.total()};
    for (int kind = 0; kind < 3; ++kind) {
        double sum = 0;
        int used = 0;
        for (int k = kindStart[kind]; k < kindStart[kind + 1]; ++k)
            if (const double d = eq.entry(k, k); d > 0) {
                sum += d;
                ++used;
            }
        const double lambda = std::max(regularization, 1e-12) * (used > 0 ? sum / used : 1.0);
        for (int k = kindStart[kind]; k < kindStart[kind + 1]; ++k) {
            eq.entry(k, k) += lambda;
            for (int ch = 0; ch < 3; ++ch) eq.rhs(k, ch) += lambda * x0(k, ch);
        }
    }
}

// Solves the equations by conjugate gradients started at `from` (a relative residual of 1e-5
// is far below what moves E), falling back on a direct factorisation, which fills in and is
// slower on large meshes. False when neither gives a finite solution.
bool solveNormalEquations(const NormalEquations& eq, const Eigen::MatrixXd& from,
                          Eigen::MatrixXd& x) {
    const Eigen::Index n = eq.A.rows();
    x.resize(n, 3);
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg(eq.A);
    cg.setTolerance(1e-5);
    cg.setMaxIterations(std::max<Eigen::Index>(1000, n));
    bool converged = cg.info() == Eigen::Success;
    for (int ch = 0; ch < 3 && converged; ++ch) {
        x.col(ch) = cg.solveWithGuess(eq.rhs.col(ch), from.col(ch));
        converged = cg.info() == Eigen::Success;
    }
    if (!converged) {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(eq.A);
        if (ldlt.info() != Eigen::Success) return false;
        x = ldlt.solve(eq.rhs);
    }
    return x.allFinite();
}

// The least-squares colours of `mesh` (geometry fixed) given the render samples; `mesh` holds
// the sampled solution on entry and the fitted one on return (kept when the solve fails).
void fitColors(GradientMesh& mesh, const RgbaImage& image, const Region& region,
               const std::vector<PixelSample>& samples, int meshIndex, const ColorOptions& options,
               const GradientMesh* guess = nullptr) {
    const double regularization = options.regularization;
    const ColorMode mode = options.mode;
    if (mesh.colorModel == ColorModel::Bicubic) {
        fitBicubicColors(mesh, image, region, samples, meshIndex, regularization,
                         options.subPixelEdgePull);
        return;
    }
    const SlotLayout L(mesh);
    const int C = mesh.columns(), P = mesh.patchCount();
    std::vector<PatchSlots> slots(static_cast<size_t>(P));
    std::vector<int> patchIdx(static_cast<size_t>(P) * 12);
    for (int patch = 0; patch < P; ++patch) {
        slots[static_cast<size_t>(patch)] = patchSlots(mesh, L, patch % C, patch / C);
        slotIndices(slots[static_cast<size_t>(patch)], &patchIdx[static_cast<size_t>(patch) * 12]);
    }
    const PixelsByPatch pixels = groupPixelsByPatch(image, region, samples, meshIndex, P);
    NormalEquations eq{normalPattern(L.total(), patchIdx, pixels),
                       Eigen::MatrixXd::Zero(L.total(), 3)};
    addPatchPixels(eq, mesh, image, samples, pixels, slots, patchIdx);
    Eigen::MatrixXd x0;
    gatherColors(mesh, L, x0);
    regularizeTowards(eq, L, x0, regularization);
    if (mode == ColorMode::FitValues) {
        fitValues(mesh, L, eq.A, eq.rhs);
        return;
    }
    // From the guess when there is one (a refit: its colours are near the answer), else from
    // the sampled solution.
    Eigen::MatrixXd from = x0;
    if (guess) {
        gatherColors(*guess, L, from);
        if (!from.allFinite()) from = x0;
    }
    Eigen::MatrixXd x;
    if (solveNormalEquations(eq, from, x)) scatterColors(mesh, L, x);
}

}  // namespace

Vec3 sampleRegionColor(const RgbaImage& image, const Region& region, Vec2 p) {
    checkSizes(image, region);
    const int W = image.width, H = image.height;
    auto inside = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < W && y < H && region.mask[static_cast<size_t>(y) * W + x];
    };
    const double fx = p.x - 0.5, fy = p.y - 0.5;
    const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
    const double wx = fx - x0, wy = fy - y0;
    Vec3 acc, plain;
    double wsum = 0;
    int count = 0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            if (!inside(x0 + dx, y0 + dy)) continue;
            const double w = (dx ? wx : 1 - wx) * (dy ? wy : 1 - wy);
            const Vec3 c = pixelColor(image, x0 + dx, y0 + dy);
            acc = acc + w * c;
            plain = plain + c;
            wsum += w;
            ++count;
        }
    if (wsum > 1e-9) return (1.0 / wsum) * acc;
    if (count > 0) return (1.0 / count) * plain;
    // Outside the region: the nearest region pixel, ring by ring.
    const int cx = std::clamp(static_cast<int>(std::floor(p.x)), 0, W - 1);
    const int cy = std::clamp(static_cast<int>(std::floor(p.y)), 0, H - 1);
    const int maxR = std::max(W, H);
    double best = std::numeric_limits<double>::infinity();
    Vec3 found;
    for (int r = 0; r <= maxR; ++r) {
        if (r > 1 && static_cast<double>(r - 1) * (r - 1) > best) break;
        for (int y = cy - r; y <= cy + r; ++y) {
            if (y < 0 || y >= H) continue;
            const bool edgeRow = (y == cy - r || y == cy + r);
            for (int x = cx - r; x <= cx + r; x += (edgeRow ? 1 : 2 * r)) {
                if (inside(x, y)) {
                    const double d2 =
                        (x + 0.5 - p.x) * (x + 0.5 - p.x) + (y + 0.5 - p.y) * (y + 0.5 - p.y);
                    if (d2 < best) {
                        best = d2;
                        found = pixelColor(image, x, y);
                    }
                }
                if (r == 0) break;
            }
        }
    }
    return found;
}

void sampleNodeColors(GradientMesh& mesh, const RgbaImage& image, const Region& region) {
    checkSizes(image, region);
    for (Node& n : mesh.nodes) n.col = sampleRegionColor(image, region, n.pos);
    for (Slit& s : mesh.slits)
        for (Node& n : s.below) n.col = sampleRegionColor(image, region, n.pos);
    applyColorRule(mesh);
}

namespace {

// The sampled solution computeColors starts from: every node colour sampled; the slopes by the
// rule (a Hermite mesh), the Bicubic model (Sampled, FitBicubic, and FitValues of a Bicubic
// mesh), or in FitValues mode the geometry's own.
GradientMesh sampledStart(const GradientMesh& geometry, const RgbaImage& image,
                          const Region& region, ColorMode mode) {
    const std::string problem = validateMesh(geometry);
    if (!problem.empty()) throw Error("colours: invalid mesh: " + problem);
    GradientMesh mesh = geometry;
    mesh.colorModel = ColorModel::Hermite;
    sampleNodeColors(mesh, image, region);
    const bool bicubic = mode == ColorMode::Sampled || mode == ColorMode::FitBicubic ||
                         (mode == ColorMode::FitValues && geometry.colorModel == ColorModel::Bicubic);
    if (bicubic) {
        useBicubicModel(mesh);
        return mesh;
    }
    if (mode != ColorMode::FitValues) return mesh;
    GradientMesh withSlopes = geometry;
    for (size_t k = 0; k < withSlopes.nodes.size(); ++k)
        withSlopes.nodes[k].col = mesh.nodes[k].col;
    for (size_t s = 0; s < withSlopes.slits.size(); ++s)
        for (size_t k = 0; k < withSlopes.slits[s].below.size(); ++k)
            withSlopes.slits[s].below[k].col = mesh.slits[s].below[k].col;
    return withSlopes;
}

}  // namespace

ColorResult computeColors(const GradientMesh& geometry, const RgbaImage& image,
                          const Region& region, const ColorOptions& options) {
    checkSizes(image, region);
    ColorResult out;
    out.mesh = sampledStart(geometry, image, region, options.mode);
    // Colours do not move the outline, so one render of the geometry serves fit and measure.
    RenderResult r = renderForSamples(out.mesh, image, options);
    if (options.mode != ColorMode::Sampled)
        fitColors(out.mesh, image, region, r.samples, 0, options);
    measure(out.mesh, image, region, r.samples, options.keepPixels, out);
    if (options.keepPixels) out.samples = std::move(r.samples);
    return out;
}

GradientMesh fitColorsToSamples(const GradientMesh& geometry, const RgbaImage& image,
                                const Region& region, const std::vector<PixelSample>& samples,
                                int meshIndex, const ColorOptions& options) {
    checkSizes(image, region);
    if (samples.size() != region.mask.size())
        throw Error("colours: " + std::to_string(samples.size()) + " render samples for " +
                    std::to_string(region.mask.size()) + " pixels");
    GradientMesh mesh = sampledStart(geometry, image, region, options.mode);
    if (options.mode != ColorMode::Sampled)
        fitColors(mesh, image, region, samples, meshIndex, options,
                  options.warmStart ? &geometry : nullptr);
    return mesh;
}

ColorResult measureColorError(const GradientMesh& mesh, const RgbaImage& image,
                              const Region& region, const ColorOptions& options) {
    checkSizes(image, region);
    const std::string problem = validateMesh(mesh);
    if (!problem.empty()) throw Error("colours: invalid mesh: " + problem);
    ColorResult out;
    out.mesh = mesh;
    RenderResult r = renderForSamples(mesh, image, options);
    measure(mesh, image, region, r.samples, options.keepPixels, out);
    if (options.keepPixels) out.samples = std::move(r.samples);
    return out;
}

}  // namespace gm
