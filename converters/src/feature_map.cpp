#include "converters/feature_map.h"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <string>

#include "meshcore/error.h"
#include "param_laplacian.h"

namespace gm {

namespace {

// Colour (premultiplied by alpha) and alpha of a window of the image, smoothed separably.
struct SmoothedWindow {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    std::vector<double> rgb;   // 3 per pixel, straight colour after normalisation
    std::vector<char> valid;   // some alpha within reach of the kernel
    const double* at(int x, int y) const { return &rgb[(static_cast<size_t>(y) * w + x) * 3]; }
    bool ok(int x, int y) const {
        return x >= 0 && y >= 0 && x < w && y < h && valid[static_cast<size_t>(y) * w + x];
    }
};

SmoothedWindow smoothWindow(const RgbaImage& image, const std::vector<uint8_t>* mask, int x0,
                            int y0, int x1, int y1, double sigma) {
    SmoothedWindow s;
    s.x0 = x0, s.y0 = y0, s.w = x1 - x0, s.h = y1 - y0;
    const size_t n = static_cast<size_t>(s.w) * s.h;
    std::vector<double> cur(n * 4);  // αr, αg, αb, α
    for (int y = 0; y < s.h; ++y)
        for (int x = 0; x < s.w; ++x) {
            const float* p = image.at(x0 + x, y0 + y);
            const bool in = !mask || (*mask)[static_cast<size_t>(y0 + y) * image.width + x0 + x];
            const double a = in ? std::clamp(static_cast<double>(p[3]), 0.0, 1.0) : 0.0;
            double* q = &cur[(static_cast<size_t>(y) * s.w + x) * 4];
            for (int c = 0; c < 3; ++c) q[c] = a * p[c];
            q[3] = a;
        }
    if (sigma > 0) {
        const int r = static_cast<int>(std::ceil(3 * sigma));
        std::vector<double> k(2 * r + 1);
        for (int i = -r; i <= r; ++i) k[i + r] = std::exp(-0.5 * i * i / (sigma * sigma));
        std::vector<double> tmp(n * 4, 0.0);
        // Samples beyond the window weigh nothing; normalising by smoothed alpha undoes that.
        for (int pass = 0; pass < 2; ++pass) {
            std::fill(tmp.begin(), tmp.end(), 0.0);
            for (int y = 0; y < s.h; ++y)
                for (int x = 0; x < s.w; ++x) {
                    double* out = &tmp[(static_cast<size_t>(y) * s.w + x) * 4];
                    for (int i = -r; i <= r; ++i) {
                        const int xx = pass == 0 ? x + i : x, yy = pass == 0 ? y : y + i;
                        if (xx < 0 || yy < 0 || xx >= s.w || yy >= s.h) continue;
                        const double* in = &cur[(static_cast<size_t>(yy) * s.w + xx) * 4];
                        for (int c = 0; c < 4; ++c) out[c] += k[i + r] * in[c];
                    }
                }
            cur.swap(tmp);
        }
    }
    s.rgb.resize(n * 3);
    s.valid.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const double a = cur[i * 4 + 3];
        s.valid[i] = a > 1e-6;
        for (int c = 0; c < 3; ++c) s.rgb[i * 3 + c] = s.valid[i] ? cur[i * 4 + c] / a : 0.0;
    }
    return s;
}

// ∂c/∂x and ∂c/∂y at pixel (x, y) of the window by central differences, one-sided where a
// neighbour is invalid. Returns false when the pixel itself is invalid.
bool pixelGradient(const SmoothedWindow& s, int x, int y, double g[6]) {
    if (!s.ok(x, y)) return false;
    for (int axis = 0; axis < 2; ++axis) {
        const int dx = axis == 0 ? 1 : 0, dy = 1 - dx;
        const bool plus = s.ok(x + dx, y + dy), minus = s.ok(x - dx, y - dy);
        const double* a = s.at(plus ? x + dx : x, plus ? y + dy : y);
        const double* b = s.at(minus ? x - dx : x, minus ? y - dy : y);
        const double span = (plus ? 1 : 0) + (minus ? 1 : 0);
        for (int c = 0; c < 3; ++c) g[axis * 3 + c] = span > 0 ? (a[c] - b[c]) / span : 0.0;
    }
    return true;
}

struct TriangleStretch {
    double area8;     // area of the triangle's feature-space image
    double l2Squared; // Sander's L2 stretch squared
    double areaUv;
};

TriangleStretch triangleStretch(const TriMesh& mesh, const std::vector<Vec2>& uv,
                                const std::vector<FeatureCoords>& f, size_t t) {
    const auto& tri = mesh.triangles[t];
    const Vec2 p1 = uv[tri[0]], p2 = uv[tri[1]], p3 = uv[tri[2]];
    const FeatureCoords &q1 = f[tri[0]], &q2 = f[tri[1]], &q3 = f[tri[2]];
    const double twiceA = (p2.x - p1.x) * (p3.y - p1.y) - (p3.x - p1.x) * (p2.y - p1.y);
    double ss = 0, tt = 0, e11 = 0, e22 = 0, e12 = 0;
    for (int k = 0; k < 8; ++k) {
        const double su = (q1[k] * (p2.y - p3.y) + q2[k] * (p3.y - p1.y) + q3[k] * (p1.y - p2.y));
        const double sv = (q1[k] * (p3.x - p2.x) + q2[k] * (p1.x - p3.x) + q3[k] * (p2.x - p1.x));
        ss += su * su;
        tt += sv * sv;
        const double a = q2[k] - q1[k], b = q3[k] - q1[k];
        e11 += a * a, e22 += b * b, e12 += a * b;
    }
    TriangleStretch s;
    s.area8 = 0.5 * std::sqrt(std::max(0.0, e11 * e22 - e12 * e12));
    s.l2Squared = 0.5 * (ss + tt) / (twiceA * twiceA);
    s.areaUv = 0.5 * twiceA;
    return s;
}

// Normalised total stretch and, when wanted, each vertex's stretch (area-weighted over its
// triangles).
double stretchOf(const TriMesh& mesh, const std::vector<Vec2>& uv,
                 const std::vector<FeatureCoords>& f, std::vector<double>* vertexStretch) {
    double sum8 = 0, sumL2 = 0, sumUv = 0;
    std::vector<double> vs, va;
    if (vertexStretch) vs.assign(uv.size(), 0.0), va.assign(uv.size(), 0.0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const TriangleStretch s = triangleStretch(mesh, uv, f, t);
        sum8 += s.area8;
        sumL2 += s.area8 * s.l2Squared;
        sumUv += s.areaUv;
        if (vertexStretch)
            for (int k : mesh.triangles[t]) vs[k] += s.area8 * s.l2Squared, va[k] += s.area8;
    }
    if (vertexStretch) {
        vertexStretch->resize(uv.size());
        for (size_t i = 0; i < uv.size(); ++i)
            (*vertexStretch)[i] = va[i] > 0 ? std::sqrt(vs[i] / va[i]) : 1.0;
    }
    return std::sqrt(sumL2 / sum8) * std::sqrt(sumUv / sum8);
}

// Freezes the vertices within `rings` edges of the seeds (walking through frozen vertices too);
// returns how many were not frozen before.
int freezeRings(const TriMesh& mesh, const detail::VertexTriangles& vt, std::vector<int> front,
                int rings, std::vector<char>& frozen) {
    std::vector<char> seen(frozen.size(), 0);
    for (int i : front) seen[i] = 1;
    int newly = 0;
    for (int r = 0; r < rings && !front.empty(); ++r) {
        std::vector<int> next;
        for (int i : front)
            for (int k = vt.start[i]; k < vt.start[i + 1]; ++k)
                for (int j : mesh.triangles[vt.tris[k]])
                    if (!seen[j]) {
                        seen[j] = 1;
                        next.push_back(j);
                        if (!frozen[j]) frozen[j] = 1, ++newly;
                    }
        front = std::move(next);
    }
    return newly;
}

}  // namespace

std::vector<FeatureCoords> featureCoordinates(const TriMesh& mesh, const RgbaImage& image, double w,
                                              double smoothing, const std::vector<uint8_t>* mask) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != static_cast<size_t>(image.width) * image.height * 4)
        throw Error("feature map: the image is empty or its pixel buffer has the wrong size");
    if (mask && mask->size() != static_cast<size_t>(image.width) * image.height)
        throw Error("feature map: the mask's size differs from the image's");
    std::vector<FeatureCoords> f(mesh.vertices.size());
    if (mesh.vertices.empty()) return f;
    double minX = INFINITY, minY = INFINITY, maxX = -INFINITY, maxY = -INFINITY;
    for (const Vec2& p : mesh.vertices) {
        minX = std::min(minX, p.x), maxX = std::max(maxX, p.x);
        minY = std::min(minY, p.y), maxY = std::max(maxY, p.y);
    }
    const int margin = static_cast<int>(std::ceil(3 * std::max(smoothing, 0.0))) + 2;
    auto clampX = [&](double x) { return static_cast<int>(std::clamp(x, 0.0, double(image.width))); };
    auto clampY = [&](double y) { return static_cast<int>(std::clamp(y, 0.0, double(image.height))); };
    const int x0 = clampX(std::floor(minX) - margin), x1 = clampX(std::ceil(maxX) + margin);
    const int y0 = clampY(std::floor(minY) - margin), y1 = clampY(std::ceil(maxY) + margin);
    if (x1 <= x0 || y1 <= y0) throw Error("feature map: the triangulation lies outside the image");
    const SmoothedWindow s = smoothWindow(image, mask, x0, y0, x1, y1, smoothing);

    for (size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vec2 p = mesh.vertices[i];
        // Bilinear weights between the four pixel centres around p.
        const double gx = std::clamp(p.x - 0.5 - x0, 0.0, double(s.w - 1));
        const double gy = std::clamp(p.y - 0.5 - y0, 0.0, double(s.h - 1));
        const int ix = std::min(static_cast<int>(gx), s.w - 1), iy = std::min(static_cast<int>(gy), s.h - 1);
        const double fx = gx - ix, fy = gy - iy;
        double grad[6] = {0, 0, 0, 0, 0, 0}, weight = 0;
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double wgt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
                double g[6];
                if (wgt <= 0 || !pixelGradient(s, ix + dx, iy + dy, g)) continue;
                for (int c = 0; c < 6; ++c) grad[c] += wgt * g[c];
                weight += wgt;
            }
        FeatureCoords& q = f[i];
        q[0] = p.x;
        q[1] = p.y;
        for (int c = 0; c < 6; ++c) q[2 + c] = weight > 0 ? w * grad[c] / weight : 0.0;
    }
    return f;
}

double totalStretch(const TriMesh& mesh, const ParamMap& map,
                    const std::vector<FeatureCoords>& features) {
    return stretchOf(mesh, map.uv, features, nullptr);
}

namespace {

void checkFeatureMapInputs(const TriMesh& mesh, const ParamMap& initial,
                           const FeatureMapOptions& options) {
    const int nv = static_cast<int>(mesh.vertices.size());
    if (static_cast<int>(initial.uv.size()) != nv)
        throw Error("feature map: the initial map has " + std::to_string(initial.uv.size()) +
                    " parameters for " + std::to_string(nv) + " vertices");
    for (const auto& t : mesh.triangles)
        for (int k : t)
            if (k < 0 || k >= nv) throw Error("feature map: triangle vertex index out of range");
    if (mesh.triangles.empty()) throw Error("feature map: the triangulation has no triangles");
    if (const int flips = countFlippedTriangles(mesh, initial); flips > 0)
        throw Error("feature map: the initial map folds " + std::to_string(flips) + " triangle(s)");
    if (!(options.w >= 0) || !(options.eta > 0) || !(options.smoothing >= 0))
        throw Error("feature map: w and smoothing must be non-negative and eta positive");
}

// Stretch minimisation: each iteration reweights the initial map's mean-value weights by the
// vertices' stretch, solves for the interior vertices and moves towards the solution while the
// stretch falls.
class FeatureMapSolver {
public:
    FeatureMapSolver(const TriMesh& mesh, const ParamMap& initial, const FeatureMapOptions& options,
                     const std::vector<FeatureCoords>& f)
        : mesh_(mesh),
          initial_(initial),
          options_(options),
          f_(f),
          nv_(static_cast<int>(mesh.vertices.size())),
          frozen_(nv_, 0),
          vt_(mesh) {
        // Loop vertices never move; interior vertices whose solve folds a triangle are frozen too.
        for (int i : mesh.outerLoop) frozen_[i] = 1;
        for (const auto& h : mesh.holeLoops)
            for (int i : h) frozen_[i] = 1;
    }

    FeatureMap run() {
        const int loopVertices = static_cast<int>(std::count(frozen_.begin(), frozen_.end(), 1));
        result_.map = initial_;
        result_.stretch.push_back(stretchOf(mesh_, initial_.uv, f_, &sigma_));
        if (loopVertices == nv_ || options_.maxIterations <= 0) return result_;
        // Mean-value weights of the initial map reproduce it exactly; every later map is a
        // convex combination map of the fixed vertices with reweighted, still positive, weights.
        W0_ = detail::meanValueWeights(mesh_, initial_.uv);
        columnScale_ = Eigen::VectorXd::Ones(nv_);
        uv_ = initial_.uv;
        unknown_.resize(nv_);
        full_.resize(nv_);
        candidate_.resize(nv_);
        while (result_.solves < options_.maxIterations) {
            ++result_.solves;
            bool folded = solveFreezingFolds(reweighted());
            const double best = result_.stretch.back();
            double e = best;
            std::vector<double> nextSigma;
            if (!stepTowardsSolution(best, folded, e, nextSigma)) {
                result_.stop = folded ? FeatureMapStop::kWouldFold : FeatureMapStop::kStretchRose;
                break;
            }
            uv_ = candidate_;
            sigma_ = std::move(nextSigma);
            result_.stretch.push_back(e);
            result_.map.uv = uv_;
            if (e > best * (1 - options_.minGain)) {
                result_.stop = FeatureMapStop::kSmallGain;
                break;
            }
        }
        if (countFlippedTriangles(mesh_, result_.map) != 0)
            throw Error("feature map: internal error, the accepted map folds");
        return result_;
    }

private:
    // The initial weights with every column scaled down by its vertex's stretch^eta (the scales
    // accumulate over the iterations).
    detail::WeightMatrix reweighted() {
        for (int j = 0; j < nv_; ++j) columnScale_[j] /= std::pow(sigma_[j], options_.eta);
        // Keeps the weights' magnitude; the solution ignores it.
        columnScale_ /= columnScale_.mean();
        return W0_ * columnScale_.asDiagonal();
    }

    // The solution into full_. With slits the fixed boundary is not convex, so a positive-weight
    // solve can fold near a slit end: freeze the free vertices of folded triangles and their
    // neighbours (foldFreezeRings) where they are and solve again, a few times at most. Returns
    // whether the last solve folded (true, too, when nothing was left to solve).
    //
    // A direct solve each time: the reweighted matrix is badly conditioned, so an iterative
    // solver (BiCGSTAB with a diagonal preconditioner, even warm-started from the current map)
    // needs thousands of iterations and is far slower than SparseLU.
    bool solveFreezingFolds(const detail::WeightMatrix& W) {
        bool folded = true;
        for (int round = 0; round < 8 && folded; ++round) {
            int count = 0;
            Eigen::MatrixXd fixedValues(nv_, 2);
            for (int i = 0; i < nv_; ++i) {
                unknown_[i] = frozen_[i] ? -1 : count++;
                fixedValues.row(i) << uv_[i].x, uv_[i].y;
            }
            if (count == 0) break;  // every vertex fixed or frozen: nothing to solve
            const detail::LaplacianSystem sys =
                detail::assembleLaplacian(W, unknown_, count, fixedValues);
            solver_.compute(sys.A);
            ++result_.factorizations;
            if (solver_.info() != Eigen::Success)
                throw Error("feature map: the stretch-weighted system could not be factorised");
            const Eigen::MatrixXd next = solver_.solve(sys.rhs);
            if (!next.allFinite())
                throw Error("feature map: the stretch-weighted system could not be solved");
            for (int i = 0; i < nv_; ++i)
                full_[i] =
                    unknown_[i] < 0 ? uv_[i] : Vec2{next(unknown_[i], 0), next(unknown_[i], 1)};
            const std::vector<int> flipped = detail::flippedTriangles(mesh_, full_);
            folded = !flipped.empty();
            if (freezeFolded(flipped) == 0) break;
        }
        return folded;
    }

    // Freezes the vertices of the flipped triangles and their rings; returns how many.
    int freezeFolded(const std::vector<int>& flipped) {
        int newlyFrozen = 0;
        std::vector<int> seeds;
        for (int t : flipped)
            for (int k : mesh_.triangles[t]) {
                seeds.push_back(k);
                if (!frozen_[k]) frozen_[k] = 1, ++newlyFrozen;
            }
        if (newlyFrozen > 0)
            newlyFrozen += freezeRings(mesh_, vt_, seeds, options_.foldFreezeRings, frozen_);
        result_.frozenVertices += newlyFrozen;
        return newlyFrozen;
    }

    // The full step into candidate_, else shorter steps towards it, until one lowers the
    // stretch below `best` (its stretch in e, its sigma in nextSigma). A step that folds sets
    // `folded`. False when none does.
    bool stepTowardsSolution(double best, bool& folded, double& e, std::vector<double>& nextSigma) {
        bool accepted = false;
        for (double step = 1; step >= 0.125 && !accepted; step *= 0.5) {
            for (int i = 0; i < nv_; ++i) candidate_[i] = uv_[i] + step * (full_[i] - uv_[i]);
            if (!detail::flippedTriangles(mesh_, candidate_).empty()) {
                folded = true;
                continue;
            }
            e = stretchOf(mesh_, candidate_, f_, &nextSigma);
            accepted = e < best;
        }
        return accepted;
    }

    const TriMesh& mesh_;
    const ParamMap& initial_;
    const FeatureMapOptions& options_;
    const std::vector<FeatureCoords>& f_;
    const int nv_;
    std::vector<char> frozen_;
    const detail::VertexTriangles vt_;
    FeatureMap result_;
    std::vector<double> sigma_;
    detail::WeightMatrix W0_;
    Eigen::VectorXd columnScale_;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver_;
    std::vector<Vec2> uv_;
    std::vector<int> unknown_;
    std::vector<Vec2> full_, candidate_;
};

}  // namespace

FeatureMap buildFeatureMap(const TriMesh& mesh, const ParamMap& initial, const RgbaImage& image,
                           const FeatureMapOptions& options) {
    checkFeatureMapInputs(mesh, initial, options);
    const std::vector<FeatureCoords> f =
        featureCoordinates(mesh, image, options.w, options.smoothing, options.mask);
    return FeatureMapSolver(mesh, initial, options, f).run();
}

}  // namespace gm
