// Linear gradients of flat shapes in SVG (svg_linear_gradient.h).
#include "svg_linear_gradient.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "svg_number.h"
#include "svg_shapes.h"

namespace gm {

namespace {

// Offsets with `decimals` decimals, trailing zeros dropped ("0", "0.4", "1"); 0 decimals asks
// for the shortest text that reads back as the same double.
std::string offsetText(double offset, int decimals) {
    char text[40];
    if (decimals == 0) {
        std::snprintf(text, sizeof text, "%.17g", offset);
        return text;
    }
    std::snprintf(text, sizeof text, "%.*f", decimals, offset);
    std::string s = text;
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s;
}

// The offsets' texts: the fewest decimals from 3 (a thousandth of the axis) that keep them
// strictly increasing as read.
std::vector<std::string> offsetTexts(const std::vector<GradientStop>& stops) {
    for (int decimals : {3, 4, 5, 6, 7, 8, 9, 0}) {
        std::vector<std::string> texts;
        double previous = -1;
        for (const GradientStop& s : stops) {
            texts.push_back(offsetText(s.offset, decimals));
            const double read = std::strtod(texts.back().c_str(), nullptr);
            if (!(read > previous)) break;
            previous = read;
        }
        if (texts.size() == stops.size() && previous > -1) return texts;
    }
    return {};  // offsets that do not increase: validateDocument refuses them before
}

void appendCoordinate(std::string& out, const char* name, double v) {
    out += ' ';
    out += name;
    out += "=\"";
    appendSvgNumber(out, v, false, kSvgDecimalsCompact);  // as the shapes' outlines
    out += '"';
}

// Everything of the element after its id.
std::string gradientBody(const LinearGradient& g) {
    std::string body = " gradientUnits=\"userSpaceOnUse\"";
    appendCoordinate(body, "x1", g.from.x);
    appendCoordinate(body, "y1", g.from.y);
    appendCoordinate(body, "x2", g.to.x);
    appendCoordinate(body, "y2", g.to.y);
    body += '>';
    const std::vector<std::string> offsets = offsetTexts(g.stops);
    for (size_t k = 0; k < offsets.size(); ++k) {
        body += "<stop offset=\"" + offsets[k] + "\" stop-color=\"";
        appendHexColour(body, g.stops[k].col);
        body += "\"/>";
    }
    return body + "</linearGradient>\n";
}

// "g" and 40 bits of the text's FNV-1a hash in hex.
std::string hashedId(const std::string& text) {
    uint64_t h = 14695981039346656037ull;
    for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
    char id[16];
    std::snprintf(id, sizeof id, "g%010llx", static_cast<unsigned long long>(h >> 24));
    return id;
}

// The greatest and least of the scalar cubic p0..p3 over [0, 1], from its ends and the roots
// of its derivative.
void cubicExtent(double p0, double p1, double p2, double p3, double& lo, double& hi) {
    auto at = [&](double t) {
        const double s = 1 - t;
        return s * s * s * p0 + 3 * s * s * t * p1 + 3 * s * t * t * p2 + t * t * t * p3;
    };
    auto see = [&](double t) {
        if (!(t > 0 && t < 1)) return;
        const double v = at(t);
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    };
    lo = std::min({lo, p0, p3});
    hi = std::max({hi, p0, p3});
    // The derivative's roots: (A - 2B + C) t² + 2 (B - A) t + A = 0.
    const double A = p1 - p0, B = p2 - p1, C = p3 - p2;
    const double qa = A - 2 * B + C, qb = 2 * (B - A), qc = A;
    if (std::fabs(qa) < 1e-12 * (std::fabs(A) + std::fabs(B) + std::fabs(C))) {
        if (qb != 0) see(-qc / qb);
        return;
    }
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) return;
    const double root = std::sqrt(disc);
    see((-qb + root) / (2 * qa));
    see((-qb - root) / (2 * qa));
}

}  // namespace

std::string SvgGradientWriter::append(std::string& out, const LinearGradient& g) {
    const std::string body = gradientBody(g);
    if (auto found = idByBody_.find(body); found != idByBody_.end()) return found->second;
    const std::string hashed = hashedId(body);
    std::string id = hashed;
    for (int k = 2; ids_.count(id); ++k) id = hashed + "-" + std::to_string(k);  // a collision
    ids_.insert(id);
    idByBody_.emplace(body, id);
    out += "<linearGradient id=\"" + id + "\"" + body;
    return id;
}

std::vector<GradientStop> modelGradientStops(const std::vector<SvgStop>& stops) {
    std::vector<GradientStop> out;
    for (size_t k = 0; k < stops.size(); ++k) {
        const bool between = k > 0 && k + 1 < stops.size() &&
                             stops[k - 1].offset == stops[k].offset &&
                             stops[k + 1].offset == stops[k].offset;
        if (!between) out.push_back({stops[k].offset, stops[k].col});
    }
    if (out.front().offset > 0) out.insert(out.begin(), {0.0, out.front().col});
    if (out.back().offset < 1) out.push_back({1.0, out.back().col});
    constexpr double kNudge = 1e-6;
    for (size_t k = 1; k < out.size(); ++k)
        out[k].offset = std::max(out[k].offset, out[k - 1].offset + kNudge);
    out.back().offset = 1;
    for (size_t k = out.size() - 1; k-- > 1;)
        out[k].offset = std::min(out[k].offset, out[k + 1].offset - kNudge);
    out.front().offset = 0;
    return out;
}

bool canvasGradientAxis(Vec2 a, Vec2 b, const SvgAffine& m, Vec2& from, Vec2& to) {
    const double det = m.determinant();
    if (!(std::fabs(det) > 0) || !std::isfinite(det)) return false;
    // t = (p - a)·d/|d|² in gradient space is (q - m(a))·n on the canvas, n = m⁻ᵀ d/|d|².
    const Vec2 d = b - a;
    const double scale = 1 / (dot(d, d) * det);
    const Vec2 n{(m.d * d.x - m.b * d.y) * scale, (-m.c * d.x + m.a * d.y) * scale};
    from = m.apply(a);
    to = from + (1 / dot(n, n)) * n;
    return std::isfinite(to.x) && std::isfinite(to.y);
}

Vec3 meanGradientColour(const LinearGradient& g) {
    Vec3 sum;
    for (size_t k = 1; k < g.stops.size(); ++k)
        sum = sum + (0.5 * (g.stops[k].offset - g.stops[k - 1].offset)) *
                        (g.stops[k - 1].col + g.stops[k].col);
    for (int c = 0; c < 3; ++c) sum[c] = std::clamp(sum[c], 0.0, 1.0);
    return sum;
}

void extentAlong(const std::vector<std::vector<Vec2>>& subpaths, Vec2 dir, double& lo, double& hi) {
    lo = INFINITY;
    hi = -INFINITY;
    for (const std::vector<Vec2>& path : subpaths) {
        const size_t n = path.size();
        for (size_t k = 0; k + 2 < n; k += 3)
            cubicExtent(dot(path[k], dir), dot(path[k + 1], dir), dot(path[k + 2], dir),
                        dot(path[(k + 3) % n], dir), lo, hi);
    }
}

}  // namespace gm
