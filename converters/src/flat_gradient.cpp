// A flat region's linear gradient (flat_gradient.h): the region's colours binned along a few
// directions, stops placed where the profile bends and coloured by least squares; kept when it
// pays for its bytes.
#include "converters/flat_gradient.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "converters/regions.h"

namespace gm {

namespace {

Vec2 pixelCentre(const RgbaImage& image, size_t k) {
    return {double(k % image.width) + 0.5, double(k / image.width) + 0.5};
}

// The unit direction in which the pixels' colour changes most: the leading right singular
// vector of the 3 × 2 slope matrix of their least-squares affine colour fit. Zero when the
// colour does not change or the pixels lie on a line.
Vec2 steepestDirection(const RgbaImage& image, const std::vector<size_t>& at, Vec2 centroid) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d rhs = Eigen::Matrix3d::Zero();  // rows: 1, x, y; columns: r, g, b
    for (size_t k : at) {
        const Vec2 d = pixelCentre(image, k) - centroid;
        const Eigen::Vector3d basis(1, d.x, d.y);
        normal += basis * basis.transpose();
        const Vec3 c = pixelColour(image, k);
        rhs += basis * Eigen::RowVector3d(c.r, c.g, c.b);
    }
    const Eigen::LDLT<Eigen::Matrix3d> solver(normal);
    if (solver.info() != Eigen::Success || solver.rcond() < 1e-12) return {};
    const Eigen::Matrix3d coef = solver.solve(rhs);
    const Eigen::Matrix<double, 3, 2> slopes = coef.bottomRows<2>().transpose();
    const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> svd(slopes, Eigen::ComputeFullV);
    if (!(svd.singularValues()(0) > 1e-9)) return {};
    return {svd.matrixV()(0, 0), svd.matrixV()(1, 0)};
}

// The pixels' colours binned along direction `dir`: bin b holds the pixels whose position
// along it, dot(p - origin, dir), lies within `width` of start + b·width.
struct Profile {
    Vec2 origin, dir;
    double start = 0, width = 1;
    std::vector<double> weight;  // pixels per bin
    std::vector<Vec3> mean;      // their mean colour, sRGB 0–1
    double within = 0;  // squared error of the pixels about their bins' means (0–255 units, mean
                        // over channels)
    double centre(size_t b) const { return start + (double(b) + 0.5) * width; }
};

constexpr int kMaxBins = 160;

Profile profileAlong(const RgbaImage& image, const std::vector<size_t>& at, Vec2 origin, Vec2 dir) {
    Profile pr;
    pr.origin = origin, pr.dir = dir;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t k : at) {
        const double t = dot(pixelCentre(image, k) - origin, dir);
        lo = std::min(lo, t), hi = std::max(hi, t);
    }
    const int bins = std::clamp(static_cast<int>(std::ceil(hi - lo)), 1, kMaxBins);
    pr.start = lo;
    pr.width = std::max(hi - lo, 1e-9) / bins;
    pr.weight.assign(bins, 0.0);
    pr.mean.assign(bins, Vec3{});
    std::vector<double> squares(bins, 0.0);
    for (size_t k : at) {
        const double t = dot(pixelCentre(image, k) - origin, dir);
        const size_t b = std::min<size_t>(bins - 1, static_cast<size_t>((t - lo) / pr.width));
        const Vec3 c = pixelColour(image, k);
        pr.weight[b] += 1;
        pr.mean[b] = pr.mean[b] + c;
        squares[b] += c.r * c.r + c.g * c.g + c.b * c.b;
    }
    for (int b = 0; b < bins; ++b) {
        if (pr.weight[b] == 0) continue;
        pr.mean[b] = (1 / pr.weight[b]) * pr.mean[b];
        const Vec3& m = pr.mean[b];
        pr.within += squares[b] - pr.weight[b] * (m.r * m.r + m.g * m.g + m.b * m.b);
    }
    pr.within = std::max(0.0, pr.within) * 255 * 255 / 3;
    return pr;
}

// Stops at positions `knots` (increasing, along the profile's direction) with the colours that
// fit its bins best, and the squared error they leave (0–255 units, mean over channels).
struct ProfileFit {
    std::vector<double> knots;
    std::vector<Vec3> cols;
    double sse = INFINITY;
};

// Where position t falls among the knots: the knot before it and its weight (1 - s) and the
// next one's s; padded beyond the ends.
void hatWeights(const std::vector<double>& knots, double t, size_t& a, double& s) {
    const size_t n = knots.size();
    if (t <= knots.front()) {
        a = 0, s = 0;
        return;
    }
    if (t >= knots.back()) {
        a = n - 2, s = 1;
        return;
    }
    a = 0;
    while (a + 2 < n && knots[a + 1] < t) ++a;
    s = (t - knots[a]) / (knots[a + 1] - knots[a]);
}

ProfileFit fitKnotColours(const Profile& pr, std::vector<double> knots) {
    const size_t n = knots.size();
    Eigen::MatrixXd normal = 1e-9 * Eigen::MatrixXd::Identity(n, n);
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    for (size_t b = 0; b < pr.weight.size(); ++b) {
        if (pr.weight[b] == 0) continue;
        size_t a;
        double s;
        hatWeights(knots, pr.centre(b), a, s);
        const double w = pr.weight[b], wa = 1 - s;
        normal(a, a) += w * wa * wa, normal(a + 1, a + 1) += w * s * s;
        normal(a, a + 1) += w * wa * s, normal(a + 1, a) += w * wa * s;
        for (int c = 0; c < 3; ++c)
            rhs(a, c) += w * wa * pr.mean[b][c], rhs(a + 1, c) += w * s * pr.mean[b][c];
    }
    const Eigen::MatrixXd sol = normal.ldlt().solve(rhs);
    ProfileFit fit;
    fit.knots = std::move(knots);
    for (size_t j = 0; j < n; ++j)
        fit.cols.push_back(Vec3{std::clamp(sol(j, 0), 0.0, 1.0), std::clamp(sol(j, 1), 0.0, 1.0),
                                std::clamp(sol(j, 2), 0.0, 1.0)});
    double sse = 0;
    for (size_t b = 0; b < pr.weight.size(); ++b) {
        if (pr.weight[b] == 0) continue;
        size_t a;
        double s;
        hatWeights(fit.knots, pr.centre(b), a, s);
        const Vec3 d = pr.mean[b] - ((1 - s) * fit.cols[a] + s * fit.cols[a + 1]);
        sse += pr.weight[b] * (d.r * d.r + d.g * d.g + d.b * d.b);
    }
    fit.sse = sse * 255 * 255 / 3 + pr.within;
    return fit;
}

// Moves each knot in turn to the bin centre between its neighbours that fits best.
ProfileFit refineKnots(const Profile& pr, ProfileFit fit) {
    const size_t bins = pr.weight.size();
    for (int pass = 0; pass < 2; ++pass)
        for (size_t j = 0; j < fit.knots.size(); ++j) {
            const double lo = j > 0 ? fit.knots[j - 1] : -INFINITY;
            const double hi = j + 1 < fit.knots.size() ? fit.knots[j + 1] : INFINITY;
            for (size_t b = 0; b < bins; ++b) {
                const double t = pr.centre(b);
                if (!(t > lo + 0.25 * pr.width && t < hi - 0.25 * pr.width)) continue;
                std::vector<double> knots = fit.knots;
                knots[j] = t;
                ProfileFit tried = fitKnotColours(pr, std::move(knots));
                if (tried.sse < fit.sse) fit = std::move(tried);
            }
        }
    return fit;
}

// The best fits along the profile with 2, 3, … maxStops stops (index K - 2): two at its ends,
// then one more where the fit errs most, each set refined.
std::vector<ProfileFit> fitProfile(const Profile& pr, int maxStops) {
    std::vector<ProfileFit> fits;
    const size_t bins = pr.weight.size();
    if (bins < 2) return fits;
    ProfileFit fit = refineKnots(pr, fitKnotColours(pr, {pr.centre(0), pr.centre(bins - 1)}));
    fits.push_back(fit);
    for (int k = 3; k <= maxStops; ++k) {
        size_t worstBin = 0;
        double worst = -1;
        for (size_t b = 0; b < bins; ++b) {
            size_t a;
            double s;
            hatWeights(fit.knots, pr.centre(b), a, s);
            const Vec3 d = pr.mean[b] - ((1 - s) * fit.cols[a] + s * fit.cols[a + 1]);
            const double e = pr.weight[b] * (d.r * d.r + d.g * d.g + d.b * d.b);
            const double t = pr.centre(b);
            const bool free = std::none_of(fit.knots.begin(), fit.knots.end(), [&](double q) {
                return std::fabs(q - t) < 0.5 * pr.width;
            });
            if (free && e > worst) worst = e, worstBin = b;
        }
        if (worst < 0) break;
        std::vector<double> knots = fit.knots;
        knots.insert(std::upper_bound(knots.begin(), knots.end(), pr.centre(worstBin)),
                     pr.centre(worstBin));
        fit = refineKnots(pr, fitKnotColours(pr, std::move(knots)));
        fits.push_back(fit);
    }
    return fits;
}

LinearGradient toGradient(const Profile& pr, const ProfileFit& fit) {
    LinearGradient g;
    const double first = fit.knots.front(), last = fit.knots.back();
    g.from = pr.origin + first * pr.dir;
    g.to = pr.origin + last * pr.dir;
    for (size_t j = 0; j < fit.knots.size(); ++j) {
        const double offset = j == 0                      ? 0.0
                              : j + 1 == fit.knots.size() ? 1.0
                                                          : (fit.knots[j] - first) / (last - first);
        g.stops.push_back({offset, fit.cols[j]});
    }
    return g;
}

// Per stop count (index K - 2, K = 2 … maxStops), the best gradient for pixels `at` among those
// along a few directions: the one their colour changes most along, the axes and the diagonals
// (a colour that rises and falls again changes along none on average). Each spans a pixel at
// least; none when the pixels span less.
std::vector<LinearGradient> candidateGradients(const RgbaImage& image,
                                               const std::vector<size_t>& at, int maxStops) {
    std::vector<LinearGradient> best;
    if (at.size() < 3) return best;
    Vec2 centroid;
    for (size_t k : at) centroid = centroid + pixelCentre(image, k);
    centroid = (1.0 / double(at.size())) * centroid;
    const double h = std::sqrt(0.5);
    std::vector<Vec2> dirs = {{1, 0}, {0, 1}, {h, h}, {h, -h}};
    if (const Vec2 d = steepestDirection(image, at, centroid); !(d == Vec2{})) dirs.push_back(d);
    std::vector<double> bestSse;
    for (const Vec2& dir : dirs) {
        const Profile pr = profileAlong(image, at, centroid, dir);
        const std::vector<ProfileFit> fits = fitProfile(pr, std::max(2, maxStops));
        for (size_t i = 0; i < fits.size(); ++i) {
            if (!(fits[i].knots.back() - fits[i].knots.front() >= 1)) continue;
            if (best.size() <= i) best.resize(i + 1), bestSse.resize(i + 1, INFINITY);
            if (fits[i].sse < bestSse[i])
                bestSse[i] = fits[i].sse, best[i] = toGradient(pr, fits[i]);
        }
    }
    return best;
}

}  // namespace

double gradientSquaredError(const RgbaImage& image, const std::vector<size_t>& at,
                            const LinearGradient& gradient, const Vec3& flat) {
    double sum = 0;
    for (size_t k : at) {
        const Vec3 want = gradient.stops.empty() ? flat : gradient.colourAt(pixelCentre(image, k));
        const Vec3 d = 255.0 * (pixelColour(image, k) - want);
        sum += (d.r * d.r + d.g * d.g + d.b * d.b) / 3;
    }
    return sum;
}

FitError gradientFitError(const RgbaImage& image, const std::vector<size_t>& at,
                          const LinearGradient& gradient) {
    return paintedError(image, at,
                        [&](size_t k) { return gradient.colourAt(pixelCentre(image, k)); });
}

LinearGradient fitPayingGradient(const RgbaImage& image, const std::vector<size_t>& at,
                                 const Vec3& flat, const GradientFitOptions& options) {
    if (static_cast<int>(at.size()) < options.minPixels) return {};
    LinearGradient best;
    double bestCost = gradientSquaredError(image, at, best, flat);
    for (LinearGradient& g : candidateGradients(image, at, options.maxStops)) {
        if (g.stops.empty()) continue;
        const double bytes =
            options.bytesPerGradient + options.bytesPerStop * double(g.stops.size());
        const double cost = gradientSquaredError(image, at, g, flat) + options.errorPerByte * bytes;
        if (cost < bestCost) bestCost = cost, best = std::move(g);
    }
    return best;
}

LinearGradient fitGradedRegion(const RgbaImage& image, const Region& own, double maxError,
                               const GradientFitOptions& options) {
    const int w = own.width, h = own.height;
    if (image.width != w || image.height != h) return {};
    std::vector<size_t> interior;
    for (size_t k = 0; k < own.mask.size(); ++k)
        if (insideMask(own.mask, w, h, k)) interior.push_back(k);
    if (static_cast<int>(interior.size()) < options.minPixels) return {};
    for (const LinearGradient& g : candidateGradients(image, interior, options.maxStops)) {
        if (g.stops.empty()) continue;
        long outliers = 0;
        const FitError e = paintedError(
            image, interior, [&](size_t k) { return g.colourAt(pixelCentre(image, k)); },
            options.outlierError * maxError, &outliers);
        if (e.meanAbs <= options.errorShare * maxError &&
            double(outliers) <= options.outlierShare * double(interior.size()))
            return g;
    }
    return {};
}

}  // namespace gm
