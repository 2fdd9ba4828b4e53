// Thin flat regions as strokes (flat_strokes.h): the region's skeleton traced into centrelines,
// each centred and measured across on the region's anti-aliased coverage, fitted with cubics,
// and kept only when the strokes' rendered coverage matches the region's.
#include "converters/flat_strokes.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc.hpp>

#include "converters/flat_regions.h"
#include "converters/regions.h"
#include "meshcore/render.h"

namespace gm {

namespace {

// A window of the image: the region's bounding box with a margin.
struct Window {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    size_t imageIndex(int x, int y, int imageWidth) const {
        return static_cast<size_t>(y0 + y) * imageWidth + x0 + x;
    }
};

// A centreline in canvas pixels; closed ones do not repeat their first point.
struct Centreline {
    std::vector<Vec2> points;
    bool closed = false;
    double width = 0;
    bool freeStart = false, freeEnd = false;  // an open line's ends: a tip, not a junction
};

Vec2 unitOr(Vec2 v, Vec2 fallback) {
    const double n = norm(v);
    return n > 1e-9 ? (1 / n) * v : fallback;
}

double lengthOf(const std::vector<Vec2>& pts, bool closed) {
    double length = 0;
    for (size_t k = 1; k < pts.size(); ++k) length += norm(pts[k] - pts[k - 1]);
    if (closed && pts.size() > 1) length += norm(pts.front() - pts.back());
    return length;
}

// The skeleton as a graph on its pixels: 4-neighbours are joined, and diagonal neighbours
// unless a 4-neighbour of both is on the skeleton too (the path goes through it), so that a
// staircase is a path and not a chain of triangles.
class SkeletonGraph {
public:
    explicit SkeletonGraph(const cv::Mat& skeleton) : skel_(skeleton) {}

    bool on(int x, int y) const {
        return x >= 0 && y >= 0 && x < skel_.cols && y < skel_.rows && skel_.at<uint8_t>(y, x);
    }

    std::vector<cv::Point> links(cv::Point p) const {
        std::vector<cv::Point> out;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if ((dx == 0 && dy == 0) || !on(p.x + dx, p.y + dy)) continue;
                if (dx != 0 && dy != 0 && (on(p.x + dx, p.y) || on(p.x, p.y + dy))) continue;
                out.push_back({p.x + dx, p.y + dy});
            }
        return out;
    }

private:
    const cv::Mat& skel_;
};

// The skeleton's paths between its ends and junctions, and its loops, in pixel centres of the
// window.
std::vector<Centreline> traceSkeleton(const cv::Mat& skeleton) {
    const SkeletonGraph graph(skeleton);
    cv::Mat visited = cv::Mat::zeros(skeleton.size(), CV_8U);
    std::vector<Centreline> lines;
    auto centre = [](cv::Point p) { return Vec2{p.x + 0.5, p.y + 0.5}; };
    auto isNode = [&](cv::Point p) { return graph.links(p).size() != 2; };
    // Walks from node `from` through `next` until the next node; marks what it passes.
    auto walk = [&](cv::Point from, cv::Point next) {
        Centreline line;
        line.points.push_back(centre(from));
        cv::Point prev = from, cur = next;
        while (!isNode(cur) && !visited.at<uint8_t>(cur)) {
            visited.at<uint8_t>(cur) = 1;
            line.points.push_back(centre(cur));
            const std::vector<cv::Point> l = graph.links(cur);
            const cv::Point step = l[0] == prev ? l[1] : l[0];
            prev = cur, cur = step;
        }
        line.points.push_back(centre(cur));
        line.freeStart = graph.links(from).size() == 1;
        line.freeEnd = graph.links(cur).size() == 1;
        return line;
    };
    std::vector<std::pair<cv::Point, cv::Point>> walked;  // node-to-node steps already taken
    for (int y = 0; y < skeleton.rows; ++y)
        for (int x = 0; x < skeleton.cols; ++x) {
            const cv::Point p{x, y};
            if (!graph.on(x, y) || !isNode(p)) continue;
            visited.at<uint8_t>(p) = 1;
            for (const cv::Point& q : graph.links(p)) {
                if (visited.at<uint8_t>(q) && !isNode(q)) continue;  // walked from its other end
                if (isNode(q)) {
                    const bool seen = std::any_of(walked.begin(), walked.end(), [&](auto& e) {
                        return e.first == q && e.second == p;
                    });
                    if (seen) continue;
                    walked.push_back({p, q});
                }
                lines.push_back(walk(p, q));
            }
        }
    // What is left unvisited are loops without a node.
    for (int y = 0; y < skeleton.rows; ++y)
        for (int x = 0; x < skeleton.cols; ++x) {
            if (!graph.on(x, y) || visited.at<uint8_t>(y, x)) continue;
            Centreline loop;
            loop.closed = true;
            cv::Point prev{-1, -1}, cur{x, y};
            while (!visited.at<uint8_t>(cur)) {
                visited.at<uint8_t>(cur) = 1;
                loop.points.push_back(centre(cur));
                const std::vector<cv::Point> l = graph.links(cur);
                const cv::Point step = l[0] == prev ? l[1] : l[0];
                prev = cur, cur = step;
            }
            lines.push_back(std::move(loop));
        }
    return lines;
}

// The points smoothed along the line (a Gaussian of `sigma` points; an open line's ends stay).
std::vector<Vec2> smoothAlong(const std::vector<Vec2>& pts, bool closed, double sigma) {
    const long n = static_cast<long>(pts.size());
    if (n < 3) return pts;
    const long reach = std::min(n / 2, static_cast<long>(std::ceil(3 * sigma)));
    std::vector<Vec2> out = pts;
    for (long k = closed ? 0 : 1; k < (closed ? n : n - 1); ++k) {
        Vec2 sum = pts[static_cast<size_t>(k)];
        double weights = 1;
        for (long d = 1; d <= reach; ++d) {
            long a = k - d, b = k + d;
            if (closed) a = (a + n) % n, b = b % n;
            else if (a < 0 || b >= n) break;  // symmetric, so that the ends do not pull
            const double wgt = std::exp(-0.5 * double(d * d) / (sigma * sigma));
            sum = sum + wgt * (pts[static_cast<size_t>(a)] + pts[static_cast<size_t>(b)]);
            weights += 2 * wgt;
        }
        out[static_cast<size_t>(k)] = (1 / weights) * sum;
    }
    return out;
}

// The region's coverage in the window, bilinear between pixel centres; 0 outside.
class CoverageField {
public:
    CoverageField(std::vector<float> values, int w, int h)
        : values_(std::move(values)), w_(w), h_(h) {}

    double at(Vec2 p) const {
        const double fx = p.x - 0.5, fy = p.y - 0.5;
        const int x = static_cast<int>(std::floor(fx)), y = static_cast<int>(std::floor(fy));
        const double ax = fx - x, ay = fy - y;
        return (1 - ay) * ((1 - ax) * pixel(x, y) + ax * pixel(x + 1, y)) +
               ay * ((1 - ax) * pixel(x, y + 1) + ax * pixel(x + 1, y + 1));
    }
    double pixel(int x, int y) const {
        if (x < 0 || y < 0 || x >= w_ || y >= h_) return 0;
        return values_[static_cast<size_t>(y) * w_ + x];
    }

private:
    std::vector<float> values_;
    int w_, h_;
};

// Across the line at p along `normal`: the centre of the coverage around p (its run above a
// trace, so that a neighbouring line is not counted) and its mass, the line's width there.
std::pair<double, double> profileAcross(const CoverageField& cov, Vec2 p, Vec2 normal,
                                        double reach) {
    constexpr double kStep = 0.25, kFloor = 0.02;
    double mass = cov.at(p) * kStep, moment = 0;
    for (int side = -1; side <= 1; side += 2)
        for (double t = kStep; t <= reach; t += kStep) {
            const double c = cov.at(p + (side * t) * normal);
            if (c < kFloor) break;
            mass += c * kStep;
            moment += side * t * c * kStep;
        }
    return {mass > 0 ? moment / mass : 0.0, mass};
}

// Moves each point to the centre of the coverage across the line (at most a pixel) and sets
// the line's width to the median of the widths measured there.
void centreOnCoverage(Centreline& line, const CoverageField& cov, double reach) {
    std::vector<Vec2>& pts = line.points;
    const size_t n = pts.size();
    std::vector<Vec2> moved = pts;
    std::vector<double> widths;
    for (size_t k = 0; k < n; ++k) {
        const size_t a = line.closed ? (k + n - 2) % n : (k >= 2 ? k - 2 : 0);
        const size_t b = line.closed ? (k + 2) % n : std::min(n - 1, k + 2);
        const Vec2 t = unitOr(pts[b] - pts[a], {1, 0});
        const Vec2 normal{-t.y, t.x};
        const auto [offset, width] = profileAcross(cov, pts[k], normal, reach);
        moved[k] = pts[k] + std::clamp(offset, -1.0, 1.0) * normal;
        widths.push_back(width);
    }
    pts = moved;
    std::nth_element(widths.begin(), widths.begin() + static_cast<long>(n / 2), widths.end());
    line.width = widths[n / 2];
}

// Moves each tip of an open line along its direction to where the region ends (its pixels,
// `mask` the window's, and its coverage above one half): so that its round cap covers as much
// as a square end there would, or,
// where the colour goes on beyond them (a neighbouring region of the same colour carries the
// line on), so that the line's full width reaches there.
void placeEnds(Centreline& line, const cv::Mat& mask, const CoverageField& cov, double reach) {
    if (line.closed || line.points.size() < 2) return;
    auto inside = [&](Vec2 p) {
        const int x = static_cast<int>(std::floor(p.x)), y = static_cast<int>(std::floor(p.y));
        return x >= 0 && y >= 0 && x < mask.cols && y < mask.rows && mask.at<uint8_t>(y, x);
    };
    for (int end = 0; end < 2; ++end) {
        if (!(end == 0 ? line.freeStart : line.freeEnd)) continue;
        std::vector<Vec2>& pts = line.points;
        const size_t n = pts.size(), back = std::min<size_t>(2, n - 1);
        const Vec2 tip = end == 0 ? pts.front() : pts.back();
        const Vec2 inner = end == 0 ? pts[back] : pts[n - 1 - back];
        const Vec2 out = unitOr(tip - inner, {1, 0});
        double t = 0;
        auto on = [&](double d) { return inside(tip + d * out) && cov.at(tip + d * out) >= 0.5; };
        while (t < reach && on(t + 0.25)) t += 0.25;
        // A round cap ending at a square end's tip leaves out its corners, (4 - π)/8 · w² of
        // area: it reaches that much further.
        const double capReach = line.width / 2 - (4 - M_PI) / 8 * line.width;
        const bool goesOn = cov.at(tip + (t + 0.75) * out) >= 0.5;
        const double shift = goesOn ? t : std::max(t - capReach,
                                                   -std::min(norm(tip - inner), line.width / 2));
        (end == 0 ? pts.front() : pts.back()) = tip + shift * out;
    }
}

// The lines as stroked shapes of colour `col`, one per group of similar widths, moved to canvas
// coordinates by `origin`.
std::vector<FlatShape> strokesOf(std::vector<Centreline> lines, const Vec3& col, Vec2 origin,
                                 const StrokeOptions& options) {
    std::sort(lines.begin(), lines.end(),
              [](const Centreline& a, const Centreline& b) { return a.width < b.width; });
    std::vector<FlatShape> shapes;
    double groupLength = 0, groupWidthSum = 0;
    for (const Centreline& line : lines) {
        const double length = std::max(1.0, lengthOf(line.points, line.closed));
        const double groupWidth = groupLength > 0 ? groupWidthSum / groupLength : 0;
        if (shapes.empty() || line.width > groupWidth * (1 + options.widthTolerance)) {
            shapes.emplace_back();
            shapes.back().col = col;
            groupLength = groupWidthSum = 0;
        }
        std::vector<Vec2> pts = line.points;
        if (line.closed) pts.push_back(pts.front());
        std::vector<Vec2> path = fitOpenCubics(pts, options.curveTolerance);
        for (Vec2& p : path) p = p + origin;
        if (line.closed) path.back() = path.front();
        shapes.back().subpaths.push_back(std::move(path));
        groupLength += length;
        groupWidthSum += length * line.width;
        shapes.back().strokeWidth = groupWidthSum / groupLength;
    }
    return shapes;
}

// How the strokes' coverage differs from the region's over the window's pixels that nothing
// drawn later covers.
struct Mismatch {
    double sum = 0;    // of |coverage difference|
    long wrong = 0;    // pixels where it exceeds one half
};

Mismatch mismatch(const std::vector<FlatShape>& strokes, const CoverageField& cov,
                  const Window& win, const std::vector<uint8_t>& under, int imageWidth) {
    Document doc;
    doc.width = win.w, doc.height = win.h;
    for (FlatShape s : strokes) {
        for (auto& path : s.subpaths)
            for (Vec2& p : path) p = p - Vec2{double(win.x0), double(win.y0)};
        doc.shapes.push_back(std::move(s));
    }
    RenderOptions options;
    options.threads = 1;
    const RenderResult drawn = renderDocument(doc, options);
    Mismatch m;
    for (int y = 0; y < win.h; ++y)
        for (int x = 0; x < win.w; ++x) {
            if (under[win.imageIndex(x, y, imageWidth)]) continue;
            const double d = std::fabs(drawn.image.at(x, y)[3] - cov.pixel(x, y));
            m.sum += d;
            m.wrong += d > 0.5;
        }
    return m;
}

}  // namespace

std::vector<FlatShape> traceStrokes(const RgbaImage& image, const Region& own, const Vec3& col,
                                    const std::vector<uint8_t>& under,
                                    const StrokeOptions& options) {
    const int iw = image.width, ih = image.height;
    if (own.width != iw || own.height != ih || own.pixelCount < options.minPixels) return {};
    const PixelBox box = maskBounds(own.mask, iw, ih);
    if (box.empty()) return {};
    const int margin = static_cast<int>(std::ceil(options.maxWidth)) + 2;
    Window win;
    win.x0 = std::max(0, box.x0 - margin), win.y0 = std::max(0, box.y0 - margin);
    win.w = std::min(iw - 1, box.x1 + margin) - win.x0 + 1;
    win.h = std::min(ih - 1, box.y1 + margin) - win.y0 + 1;
    cv::Mat mask(win.h, win.w, CV_8U);
    for (int y = 0; y < win.h; ++y)
        for (int x = 0; x < win.w; ++x)
            mask.at<uint8_t>(y, x) = own.mask[win.imageIndex(x, y, iw)] ? 255 : 0;
    cv::Mat distance;
    cv::distanceTransform(mask, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    double thickest = 0;
    cv::minMaxLoc(distance, nullptr, &thickest);
    if (2 * thickest - 1 > options.maxWidth) return {};

    const Coverage share = shareCoverage(image, own.mask, own.mask, under, col, true);
    std::vector<float> windowShare(static_cast<size_t>(win.w) * win.h);
    for (int y = 0; y < win.h; ++y)
        for (int x = 0; x < win.w; ++x)
            windowShare[static_cast<size_t>(y) * win.w + x] =
                share.values[win.imageIndex(x, y, iw)];
    const CoverageField cov(std::move(windowShare), win.w, win.h);

    cv::Mat skeleton;
    cv::ximgproc::thinning(mask, skeleton, cv::ximgproc::THINNING_ZHANGSUEN);
    const double reach = options.maxWidth / 2 + 1.5;
    std::vector<Centreline> lines;
    for (Centreline& line : traceSkeleton(skeleton)) {
        if (line.points.size() < 2) continue;
        line.points = smoothAlong(line.points, line.closed, 1.0);
        centreOnCoverage(line, cov, reach);
        line.points = smoothAlong(line.points, line.closed, 1.0);
        placeEnds(line, mask, cov, reach);
        if (!(line.width > 0.5)) continue;
        lines.push_back(std::move(line));
    }
    if (lines.empty()) return {};
    // A piece shorter than a few widths lies mostly where lines meet, where the measure across
    // it takes in the other lines: it takes the width of the region's longer pieces.
    std::vector<double> widths;
    for (const Centreline& line : lines)
        if (lengthOf(line.points, line.closed) >= 3 * line.width) widths.push_back(line.width);
    if (!widths.empty()) {
        std::nth_element(widths.begin(), widths.begin() + static_cast<long>(widths.size() / 2),
                         widths.end());
        const double typical = widths[widths.size() / 2];
        for (Centreline& line : lines)
            if (lengthOf(line.points, line.closed) < 3 * line.width) line.width = typical;
    }
    std::vector<FlatShape> strokes =
        strokesOf(std::move(lines), col, Vec2{double(win.x0), double(win.y0)}, options);
    const Mismatch m = mismatch(strokes, cov, win, under, iw);
    if (m.sum > options.maxMismatch * own.pixelCount ||
        double(m.wrong) > options.maxWrongShare * own.pixelCount)
        return {};
    return strokes;
}

}  // namespace gm
