#include "converters/refine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "meshcore/evaluate.h"

namespace gm {

namespace {

struct Candidate {
    double score = 0;  // estimated error a split removes (see rankCandidates)
    bool alongU = true;
    int interval = 0;
    double knot = 0;
};

RefineStep stepOf(const ColorResult& r, char axis, double knot, double seconds) {
    RefineStep s;
    s.columns = r.mesh.columns();
    s.rows = r.mesh.rows();
    s.patches = r.mesh.patchCount();
    s.meanAbs = r.error.meanAbs;
    s.rmse = r.error.rmse;
    s.psnr = r.error.psnr;
    s.axis = axis;
    s.knot = knot;
    s.seconds = seconds;
    return s;
}

// Every admissible split of the current mesh, best estimated first.
//
// The estimate of what a split removes: the part of each patch's residual that varies along
// the split direction. Splitting the u interval adds freedom along u only, so it helps where
// the residual, averaged over t, still varies with s (a vertical colour edge), and does little
// where it varies with t alone. Per patch the residual is binned along s (and along t); the
// energy of the bin means is the u (v) score, summed over the patch column (row).
std::vector<Candidate> rankCandidates(const ColorResult& current, const RgbaImage& image,
                                      const Region& region, const RefineOptions& options) {
    constexpr int kBins = 8;
    const GradientMesh& m = current.mesh;
    const int C = m.columns(), R = m.rows(), P = m.patchCount();
    std::vector<PatchHermite> hermite(static_cast<size_t>(P));
    for (int j = 0; j < R; ++j)
        for (int i = 0; i < C; ++i) hermite[static_cast<size_t>(j) * C + i] = patchHermite(m, i, j);
    // Per patch and bin: residual sums per channel, and counts.
    std::vector<double> sumS(static_cast<size_t>(P) * kBins * 3, 0.0), sumT(sumS.size(), 0.0);
    std::vector<int> cntS(static_cast<size_t>(P) * kBins, 0), cntT(cntS.size(), 0);
    // Per interval: absolute error and its first moment in the local parameter.
    std::vector<double> wu(static_cast<size_t>(C), 0.0), su(wu.size(), 0.0);
    std::vector<double> wv(static_cast<size_t>(R), 0.0), sv(wv.size(), 0.0);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const size_t p = static_cast<size_t>(y) * image.width + x;
            const PixelSample& ps = current.samples[p];
            if (!region.mask[p] || ps.mesh != 0 || ps.patch < 0) continue;
            double hs[4], ht[4];
            hermiteBasis(ps.s, hs);
            hermiteBasis(ps.t, ht);
            const PatchHermite& h = hermite[static_cast<size_t>(ps.patch)];
            const Vec3 c = hermiteColor(h, hs, ht);
            const float* target = image.at(x, y);
            const int bs = std::min(kBins - 1, static_cast<int>(ps.s * kBins));
            const int bt = std::min(kBins - 1, static_cast<int>(ps.t * kBins));
            const size_t is = static_cast<size_t>(ps.patch) * kBins + bs;
            const size_t it = static_cast<size_t>(ps.patch) * kBins + bt;
            double absErr = 0;
            for (int ch = 0; ch < 3; ++ch) {
                const double r = 255.0 * (std::clamp(c[ch], 0.0, 1.0) - target[ch]);
                sumS[is * 3 + ch] += r;
                sumT[it * 3 + ch] += r;
                absErr += std::abs(r);
            }
            ++cntS[is];
            ++cntT[it];
            const int i = ps.patch % C, j = ps.patch / C;
            wu[i] += absErr;
            su[i] += absErr * ps.s;
            wv[j] += absErr;
            sv[j] += absErr * ps.t;
        }
    }
    std::vector<double> colScore(static_cast<size_t>(C), 0.0),
        rowScore(static_cast<size_t>(R), 0.0);
    for (int p = 0; p < P; ++p) {
        double eu = 0, ev = 0;
        for (int b = 0; b < kBins; ++b) {
            const size_t k = static_cast<size_t>(p) * kBins + b;
            for (int ch = 0; ch < 3; ++ch) {
                if (cntS[k]) eu += sumS[k * 3 + ch] * sumS[k * 3 + ch] / cntS[k];
                if (cntT[k]) ev += sumT[k * 3 + ch] * sumT[k * 3 + ch] / cntT[k];
            }
        }
        colScore[p % C] += eu;
        rowScore[p / C] += ev;
    }
    auto place = [](double a, double b, double w, double sum) {
        const double f = w > 0 ? std::clamp(sum / w, 0.25, 0.75) : 0.5;
        return a + f * (b - a);
    };
    std::vector<Candidate> out;
    if (static_cast<long>(C + 1) * R <= options.maxPatches)
        for (int i = 0; i < C; ++i)
            if (m.u[i + 1] - m.u[i] >= 2 * options.minInterval && wu[i] > 0)
                out.push_back({colScore[i], true, i, place(m.u[i], m.u[i + 1], wu[i], su[i])});
    if (static_cast<long>(R + 1) * C <= options.maxPatches)
        for (int j = 0; j < R; ++j)
            if (m.v[j + 1] - m.v[j] >= 2 * options.minInterval && wv[j] > 0)
                out.push_back({rowScore[j], false, j, place(m.v[j], m.v[j + 1], wv[j], sv[j])});
    std::stable_sort(out.begin(), out.end(),
                     [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    return out;
}

// Knots of `gridOptions` plus the first `count` splits of `batch`.
GridOptions withSplits(GridOptions gridOptions, const std::vector<const Candidate*>& batch,
                       size_t count) {
    for (size_t k = 0; k < count; ++k)
        (batch[k]->alongU ? gridOptions.knotsU : gridOptions.knotsV).push_back(batch[k]->knot);
    std::sort(gridOptions.knotsU.begin(), gridOptions.knotsU.end());
    std::sort(gridOptions.knotsV.begin(), gridOptions.knotsV.end());
    return gridOptions;
}

// A batch whose mesh `whole` overshoots the target: the shortest prefix of it (in rank order)
// that still reaches the target, so that the last step does not add patches the target does
// not ask for. E is taken as linear in the splits' summed scores between the two nearest known
// prefixes (regula falsi: `current` is the empty prefix, `whole` the full batch); each guess costs
// a fit, so none is tried when it would save under 2 % of the patches the batch adds, and at most
// options.trimSteps are. `whole` becomes the mesh of the returned prefix length.
size_t trimBatch(const std::vector<const Candidate*>& batch, const ColorResult& current,
                 ColorResult& whole, const GridOptions& gridOptions, const GridBuilder& grid,
                 const RgbaImage& image, const Region& region, const ColorOptions& colorOptions,
                 const RefineOptions& options) {
    std::vector<double> score(batch.size() + 1, 0.0);  // summed over the first k splits
    for (size_t k = 0; k < batch.size(); ++k) score[k + 1] = score[k] + batch[k]->score;
    const long before = current.mesh.patchCount();
    auto patchesOf = [&](size_t count) {
        long nu = 0, nv = 0;
        for (size_t k = 0; k < count; ++k) (batch[k]->alongU ? nu : nv) += 1;
        return (current.mesh.columns() + nu) * (current.mesh.rows() + nv);
    };
    size_t lo = 0, hi = batch.size();
    double eLo = current.error.meanAbs, eHi = whole.error.meanAbs;
    for (int step = 0; step < options.trimSteps && hi - lo > 1 && eLo > eHi; ++step) {
        const double need = std::clamp((eLo - options.maxError) / (eLo - eHi), 0.0, 1.0);
        const double at = score[lo] + need * (score[hi] - score[lo]);
        // The first prefix whose score reaches the interpolated need (hi: none shorter does).
        const size_t k = std::max<size_t>(
            lo + 1,
            std::lower_bound(score.begin() + lo + 1, score.begin() + hi, at) - score.begin());
        if (k >= hi || patchesOf(hi) - patchesOf(k) < 0.02 * (patchesOf(batch.size()) - before))
            break;
        ColorResult r = computeColors(grid.build(withSplits(gridOptions, batch, k)), image, region,
                                      colorOptions);
        if (r.error.meanAbs <= options.maxError) {
            hi = k;
            eHi = r.error.meanAbs;
            whole = std::move(r);
        } else {
            lo = k;
            eLo = r.error.meanAbs;
        }
    }
    return hi;
}

// Greedy refinement of one grid: each lap ranks the splits, tries a batch of the best ones,
// else single splits, and keeps the first mesh that lowers E.
class Refiner {
public:
    Refiner(const GridBuilder& grid, const GridOptions& initial, const RgbaImage& image,
            const Region& region, const RefineOptions& options)
        : grid_(grid),
          image_(image),
          region_(region),
          options_(options),
          colorOptions_(options.color),
          gridOptions_(initial),
          t0_(Clock::now()) {
        colorOptions_.keepPixels = true;
    }

    RefineResult run() {
        current_ = fit(gridOptions_);
        gridOptions_.knotsU = current_.mesh.u;
        gridOptions_.knotsV = current_.mesh.v;
        result_.steps.push_back(stepOf(current_, 0, 0, lap()));
        while (current_.error.meanAbs > options_.maxError) {
            const std::vector<Candidate> ranked =
                rankCandidates(current_, image_, region_, options_);
            if (ranked.empty()) break;
            if (tryBatch(ranked)) continue;
            if (!trySingleSplits(ranked)) break;
        }
        result_.error = current_.error;
        result_.reachedTarget = current_.error.meanAbs <= options_.maxError;
        result_.mesh = std::move(current_.mesh);
        return std::move(result_);
    }

private:
    using Clock = std::chrono::steady_clock;

    // Seconds since the last lap.
    double lap() {
        const auto t = Clock::now();
        const double s = std::chrono::duration<double>(t - t0_).count();
        t0_ = t;
        return s;
    }

    ColorResult fit(const GridOptions& gridOptions) const {
        return computeColors(grid_.build(gridOptions), image_, region_, colorOptions_);
    }

    // The best-ranked splits whose scores are within batchFraction of the best, as long as the
    // grid stays within batchGrowth times its patches (and the budget).
    std::vector<const Candidate*> batchOf(const std::vector<Candidate>& ranked) const {
        const long C = current_.mesh.columns(), R = current_.mesh.rows();
        const double cap = std::min<double>(options_.maxPatches, options_.batchGrowth * C * R);
        long nu = 0, nv = 0;
        std::vector<const Candidate*> batch;
        for (const Candidate& c : ranked) {
            if (c.score < options_.batchFraction * ranked.front().score) break;
            const long patches = (C + nu + (c.alongU ? 1 : 0)) * (R + nv + (c.alongU ? 0 : 1));
            if (patches > cap) continue;
            (c.alongU ? nu : nv) += 1;
            batch.push_back(&c);
        }
        return batch;
    }

    // A batch of the best-ranked splits at once (trimmed when it overshoots the target); true
    // when it lowered E and was kept.
    bool tryBatch(const std::vector<Candidate>& ranked) {
        if (!(options_.batchGrowth > 1.0 && ranked.size() > 1)) return false;
        std::vector<const Candidate*> batch = batchOf(ranked);
        if (batch.size() <= 1) return false;
        ColorResult r = fit(withSplits(gridOptions_, batch, batch.size()));
        if (r.error.meanAbs <= options_.maxError && options_.trimSteps > 0)
            batch.resize(trimBatch(batch, current_, r, gridOptions_, grid_, image_, region_,
                                   colorOptions_, options_));
        if (!(r.error.meanAbs < current_.error.meanAbs)) return false;
        RefineStep& step =
            accept(std::move(r), batch.front()->alongU ? 'u' : 'v', batch.front()->knot);
        for (const Candidate* c : batch) step.splits.emplace_back(c->alongU ? 'u' : 'v', c->knot);
        return true;
    }

    // Batches of `candidates` single splits, best of each batch; a later batch only when the
    // earlier ones brought no improvement. True when a split was kept.
    bool trySingleSplits(const std::vector<Candidate>& ranked) {
        const int perStep = std::max(1, options_.candidates);
        const int maxTries = std::max(perStep, options_.maxTries);
        for (size_t start = 0; start < ranked.size() && static_cast<int>(start) < maxTries;
             start += static_cast<size_t>(perStep)) {
            ColorResult best;
            bool have = false;
            const Candidate* bestCandidate = nullptr;
            for (size_t k = start; k < std::min(ranked.size(), start + perStep); ++k) {
                const Candidate& c = ranked[k];
                GridOptions trial = gridOptions_;
                std::vector<double>& knots = c.alongU ? trial.knotsU : trial.knotsV;
                knots.insert(knots.begin() + c.interval + 1, c.knot);
                ColorResult r = fit(trial);
                if (!have || r.error.meanAbs < best.error.meanAbs) {
                    best = std::move(r);
                    bestCandidate = &c;
                    have = true;
                }
            }
            if (have && best.error.meanAbs < current_.error.meanAbs) {
                RefineStep& step =
                    accept(std::move(best), bestCandidate->alongU ? 'u' : 'v', bestCandidate->knot);
                step.splits.emplace_back(step.axis, step.knot);
                return true;
            }
        }
        return false;
    }

    // The new current mesh, its knots and its step (returned for its splits).
    RefineStep& accept(ColorResult next, char axis, double knot) {
        current_ = std::move(next);
        gridOptions_.knotsU = current_.mesh.u;
        gridOptions_.knotsV = current_.mesh.v;
        result_.steps.push_back(stepOf(current_, axis, knot, lap()));
        return result_.steps.back();
    }

    const GridBuilder& grid_;
    const RgbaImage& image_;
    const Region& region_;
    const RefineOptions& options_;
    ColorOptions colorOptions_;
    GridOptions gridOptions_;
    Clock::time_point t0_;
    ColorResult current_;
    RefineResult result_;
};

}  // namespace

RefineResult refineMesh(const GridBuilder& grid, const GridOptions& initial, const RgbaImage& image,
                        const Region& region, const RefineOptions& options) {
    return Refiner(grid, initial, image, region, options).run();
}

RefineResult refineMesh(const TriMesh& mesh, const ParamMap& map, const GridOptions& initial,
                        const RgbaImage& image, const Region& region,
                        const RefineOptions& options) {
    return refineMesh(GridBuilder(mesh, map), initial, image, region, options);
}

}  // namespace gm
