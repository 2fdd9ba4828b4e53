#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "formats/svg.h"
#include "meshcore/error.h"
#include "meshcore/validate.h"
#include "svg_affine.h"
#include "svg_grid_outset.h"
#include "svg_linear_gradient.h"
#include "svg_patch_grid.h"
#include "svg_shapes.h"

namespace gm {

namespace {

using tinyxml2::XMLElement;

using Affine = SvgAffine;

const char* localName(const XMLElement* el) {
    const char* name = el->Name();
    const char* colon = std::strrchr(name, ':');
    return colon ? colon + 1 : name;
}

bool isNamed(const XMLElement* el, const char* name) {
    return std::strcmp(localName(el), name) == 0;
}

class Reader {
public:
    explicit Reader(const std::string& fileName) : file_(fileName) {}

    [[noreturn]] void fail(const std::string& what, const XMLElement* el) const {
        throw Error(what, file_, el ? describe(el) : std::string());
    }

    std::string describe(const XMLElement* el) const {
        std::string s = "<" + std::string(el->Name());
        if (const char* id = el->Attribute("id")) s += " id=\"" + std::string(id).substr(0, 64) + "\"";
        s += "> at line " + std::to_string(el->GetLineNum());
        return s;
    }

    static void skipSeparators(const char*& p) {
        while (*p && (std::isspace(static_cast<unsigned char>(*p)) || *p == ',')) ++p;
    }
    static void skipSpace(const char*& p) {
        while (*p && std::isspace(static_cast<unsigned char>(*p))) ++p;
    }

    // Parses one number at p (after optional separators); false when none is there.
    bool number(const char*& p, double& v, const XMLElement* el, const char* what) const {
        skipSeparators(p);
        if (!*p) return false;
        const char c0 = *p;
        if (!(std::isdigit(static_cast<unsigned char>(c0)) || c0 == '-' || c0 == '+' || c0 == '.'))
            return false;
        char* end = nullptr;
        v = std::strtod(p, &end);
        if (end == p) return false;
        // strtod accepts "nan", "inf", hex floats: none of them belongs in SVG numbers.
        for (const char* q = p; q < end; ++q)
            if (std::isalpha(static_cast<unsigned char>(*q)) && *q != 'e' && *q != 'E')
                fail(std::string("malformed number in ") + what, el);
        if (!std::isfinite(v) || std::fabs(v) > SvgReadLimits::maxCoordinate)
            fail(std::string("number out of range in ") + what + ": " +
                     std::string(p, static_cast<size_t>(std::min<long>(end - p, 40))),
                 el);
        p = end;
        return true;
    }

    double numberAttribute(const XMLElement* el, const char* name, double fallback,
                           bool allowUnitPx = false) const {
        const char* s = el->Attribute(name);
        if (!s) return fallback;
        const char* p = s;
        double v = 0;
        if (!number(p, v, el, name)) fail(std::string("attribute ") + name + " is not a number", el);
        skipSpace(p);
        if (allowUnitPx && std::strncmp(p, "px", 2) == 0) p += 2;
        skipSpace(p);
        if (*p) fail(std::string("attribute ") + name + " has unsupported text '" + s + "'", el);
        return v;
    }

    Affine transformAttribute(const XMLElement* el, const char* name) const {
        Affine t;
        const char* s = el->Attribute(name);
        if (!s) return t;
        const char* p = s;
        for (;;) {
            skipSeparators(p);
            if (!*p) break;
            const char* start = p;
            while (std::isalpha(static_cast<unsigned char>(*p))) ++p;
            const std::string fn(start, p);
            skipSpace(p);
            if (*p != '(') fail(std::string("malformed ") + name, el);
            ++p;
            double v[6];
            int n = 0;
            for (; n < 6; ++n)
                if (!number(p, v[n], el, name)) break;
            skipSpace(p);
            if (*p != ')') fail(std::string("malformed ") + name, el);
            ++p;
            Affine m;
            const double deg = 3.14159265358979323846 / 180;
            if (fn == "matrix" && n == 6) {
                m = {v[0], v[1], v[2], v[3], v[4], v[5]};
            } else if (fn == "translate" && (n == 1 || n == 2)) {
                m.e = v[0];
                m.f = n == 2 ? v[1] : 0;
            } else if (fn == "scale" && (n == 1 || n == 2)) {
                m.a = v[0];
                m.d = n == 2 ? v[1] : v[0];
            } else if (fn == "rotate" && (n == 1 || n == 3)) {
                const double c = std::cos(v[0] * deg), s2 = std::sin(v[0] * deg);
                Affine r{c, s2, -s2, c, 0, 0};
                if (n == 3) {
                    Affine to{1, 0, 0, 1, v[1], v[2]}, back{1, 0, 0, 1, -v[1], -v[2]};
                    r = compose(to, compose(r, back));
                }
                m = r;
            } else if (fn == "skewX" && n == 1) {
                m.c = std::tan(v[0] * deg);
            } else if (fn == "skewY" && n == 1) {
                m.b = std::tan(v[0] * deg);
            } else {
                fail(std::string("unsupported transform '") + fn + "' in " + name, el);
            }
            t = compose(t, m);
        }
        if (!std::isfinite(t.a) || !std::isfinite(t.b) || !std::isfinite(t.c) ||
            !std::isfinite(t.d) || !std::isfinite(t.e) || !std::isfinite(t.f))
            fail(std::string("transform out of range in ") + name, el);
        return t;
    }

    // A property from the style attribute (wins) or the presentation attribute.
    static std::string property(const XMLElement* el, const char* name) {
        std::string value;
        if (const char* a = el->Attribute(name)) value = a;
        if (const char* style = el->Attribute("style")) {
            const std::string s = style;
            size_t pos = 0;
            while (pos < s.size()) {
                size_t semi = s.find(';', pos);
                if (semi == std::string::npos) semi = s.size();
                const std::string decl = s.substr(pos, semi - pos);
                const size_t colon = decl.find(':');
                if (colon != std::string::npos && trim(decl.substr(0, colon)) == name)
                    value = trim(decl.substr(colon + 1));
                pos = semi + 1;
            }
        }
        return trim(value);
    }

    static std::string trim(const std::string& s) {
        size_t b = 0, e = s.size();
        while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
        while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
        return s.substr(b, e - b);
    }

    // "#id" of url(#id) / url('#id'); empty when the paint is not a local url.
    static std::string urlTarget(const std::string& paint) {
        if (paint.compare(0, 4, "url(") != 0) return {};
        size_t close = paint.find(')');
        if (close == std::string::npos) return {};
        std::string inner = trim(paint.substr(4, close - 4));
        if (inner.size() >= 2 && (inner[0] == '\'' || inner[0] == '"')) inner = inner.substr(1, inner.size() - 2);
        if (inner.empty() || inner[0] != '#') return {};
        return inner.substr(1);
    }

    static std::string hrefTarget(const XMLElement* el) {
        const char* h = el->Attribute("xlink:href");
        if (!h) h = el->Attribute("href");
        if (!h || h[0] != '#') return {};
        return h + 1;
    }

    Vec3 color(const XMLElement* stop) const {
        std::string s = property(stop, "stop-color");
        if (s.empty()) return {0, 0, 0};  // the SVG initial value
        // "#rrggbb icc-color(...)": the sRGB fallback is what renderers use.
        const size_t space = s.find_first_of(" \t\r\n");
        if (space != std::string::npos && s[0] == '#') s = s.substr(0, space);
        auto hexval = [](char c) -> int {
            if (c >= '0' && c <= '9') return c - '0';
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (c >= 'a' && c <= 'f') return c - 'a' + 10;
            return -1;
        };
        if (s[0] == '#') {
            int h[6];
            const size_t n = s.size() - 1;
            if (n != 3 && n != 6) fail("bad stop-color '" + s.substr(0, 40) + "'", stop);
            for (size_t k = 0; k < n; ++k)
                if ((h[k] = hexval(s[k + 1])) < 0) fail("bad stop-color '" + s.substr(0, 40) + "'", stop);
            if (n == 3) return {h[0] * 17 / 255.0, h[1] * 17 / 255.0, h[2] * 17 / 255.0};
            return {(h[0] * 16 + h[1]) / 255.0, (h[2] * 16 + h[3]) / 255.0,
                    (h[4] * 16 + h[5]) / 255.0};
        }
        if (s.compare(0, 4, "rgb(") == 0 && s.back() == ')') {
            const std::string inner = s.substr(4, s.size() - 5);
            const char* p = inner.c_str();
            Vec3 c;
            for (int k = 0; k < 3; ++k) {
                double v = 0;
                if (!number(p, v, stop, "stop-color")) fail("bad stop-color '" + s.substr(0, 40) + "'", stop);
                skipSpace(p);
                if (*p == '%') {
                    v /= 100.0;
                    ++p;
                } else {
                    v /= 255.0;
                }
                c[k] = std::min(1.0, std::max(0.0, v));
            }
            skipSpace(p);
            if (*p) fail("bad stop-color '" + s.substr(0, 40) + "'", stop);
            return c;
        }
        static const struct {
            const char* name;
            unsigned rgb;
        } named[] = {{"black", 0x000000}, {"silver", 0xc0c0c0}, {"gray", 0x808080},
                     {"grey", 0x808080},  {"white", 0xffffff},  {"maroon", 0x800000},
                     {"red", 0xff0000},   {"purple", 0x800080}, {"fuchsia", 0xff00ff},
                     {"green", 0x008000}, {"lime", 0x00ff00},   {"olive", 0x808000},
                     {"yellow", 0xffff00}, {"navy", 0x000080},  {"blue", 0x0000ff},
                     {"teal", 0x008080},  {"aqua", 0x00ffff},   {"orange", 0xffa500}};
        std::string lower = s;
        std::transform(lower.begin(), lower.end(), lower.begin(),
                       [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
        for (const auto& nc : named)
            if (lower == nc.name)
                return {((nc.rgb >> 16) & 255) / 255.0, ((nc.rgb >> 8) & 255) / 255.0,
                        (nc.rgb & 255) / 255.0};
        fail("unsupported stop-color '" + s.substr(0, 40) + "'", stop);
    }

    // One edge of a patch from `start`: handles h1, h2 and end point. A closing edge ends at a
    // corner already known, which `end` holds on entry.
    void edge(const XMLElement* stop, Vec2 start, bool closing, Vec2& h1, Vec2& h2, Vec2& end) const {
        const char* path = stop->Attribute("path");
        if (!path) fail("stop of a meshpatch has no path attribute", stop);
        const char* p = path;
        skipSpace(p);
        const char cmd = *p;
        if (cmd != 'c' && cmd != 'C' && cmd != 'l' && cmd != 'L')
            fail(std::string("stop path must be one c, C, l or L command, not '") +
                     std::string(path).substr(0, 40) + "'",
                 stop);
        ++p;
        double v[6];
        int n = 0;
        for (; n < 6; ++n)
            if (!number(p, v[n], stop, "stop path")) break;
        skipSeparators(p);
        if (*p)
            fail("stop path has more than one command or extra text: '" +
                     std::string(path).substr(0, 60) + "'",
                 stop);
        const bool cubic = cmd == 'c' || cmd == 'C';
        const bool rel = cmd == 'c' || cmd == 'l';
        const int need = cubic ? (closing ? 4 : 6) : (closing ? 0 : 2);
        const int full = cubic ? 6 : 2;
        if (n != need && n != full)
            fail("stop path '" + std::string(path).substr(0, 60) + "' has " + std::to_string(n) +
                     " numbers, expected " + std::to_string(need) +
                     (need != full ? " or " + std::to_string(full) : std::string()),
                 stop);
        auto pt = [&](int k) {
            Vec2 q{v[2 * k], v[2 * k + 1]};
            return rel ? start + q : q;
        };
        if (!closing) end = cubic ? pt(2) : pt(0);
        if (cubic) {
            h1 = pt(0);
            h2 = pt(1);
        } else {
            h1 = start + (1.0 / 3) * (end - start);
            h2 = start + (2.0 / 3) * (end - start);
        }
    }

    // The rows of `array` read into a grid whose first corner is `origin` (gradient space).
    SvgPatchGrid grid(const XMLElement* array, Vec2 origin, const ReadLimits& limits) const {
        const std::vector<std::vector<const XMLElement*>> rows = meshRows(array, limits);
        const int C = static_cast<int>(rows.front().size()), R = static_cast<int>(rows.size());
        SvgPatchGrid g;
        g.resize(C, R);
        g.P(0, 0) = origin;
        for (int r = 0; r < R; ++r)
            for (int c = 0; c < C; ++c) {
                readPatch(rows[r][c], c, r, g);
                readTensor(rows[r][c], c, r, g);
            }
        return g;
    }

    const std::string& file() const { return file_; }

private:
    // The meshpatch elements of each meshrow of `array`; every row as long as the first, the
    // grid within the reader's limits.
    std::vector<std::vector<const XMLElement*>> meshRows(const XMLElement* array,
                                                         const ReadLimits& limits) const {
        std::vector<std::vector<const XMLElement*>> rows;
        for (const XMLElement* r = array->FirstChildElement(); r; r = r->NextSiblingElement()) {
            if (!isNamed(r, "meshrow")) continue;
            rows.emplace_back();
            for (const XMLElement* p = r->FirstChildElement(); p; p = p->NextSiblingElement())
                if (isNamed(p, "meshpatch")) rows.back().push_back(p);
            if (rows.back().empty()) fail("meshrow has no meshpatch", r);
            if (rows.back().size() != rows.front().size())
                fail("meshrow has " + std::to_string(rows.back().size()) +
                         " patches, the first row has " + std::to_string(rows.front().size()),
                     r);
        }
        if (rows.empty()) fail("meshgradient has no meshrow", array);
        const uint64_t C = rows.front().size(), R = rows.size();
        if (C > limits.maxGridSide || R > limits.maxGridSide ||
            (C + 1) * (R + 1) > limits.maxNodesPerMesh)
            fail("mesh of " + std::to_string(C) + " x " + std::to_string(R) +
                     " patches is over the reader's limits",
                 array);
        return rows;
    }

    // The stops of patch (c, r): the edges it does not share with an earlier patch (top in the
    // first row, left in the first column, always right and bottom).
    std::vector<const XMLElement*> patchStops(const XMLElement* patch, int c, int r) const {
        std::vector<const XMLElement*> stops;
        for (const XMLElement* s = patch->FirstChildElement(); s; s = s->NextSiblingElement())
            if (isNamed(s, "stop")) stops.push_back(s);
        const size_t expected = (r == 0 ? 1 : 0) + (c == 0 ? 1 : 0) + 2;
        if (stops.size() != expected)
            fail("meshpatch " + std::to_string(c + 1) + " of meshrow " + std::to_string(r + 1) +
                     " has " + std::to_string(stops.size()) + " stops, expected " +
                     std::to_string(expected),
                 patch);
        return stops;
    }

    // Patch (c, r)'s new edges, corners and corner colours into the grid.
    void readPatch(const XMLElement* patch, int c, int r, SvgPatchGrid& g) const {
        const std::vector<const XMLElement*> stops = patchStops(patch, c, r);
        size_t k = 0;
        Vec2 end;
        if (r == 0) {  // top
            auto& h = g.H(c, 0);
            edge(stops[k], g.P(c, 0), false, h[0], h[1], end);
            g.P(c + 1, 0) = end;
            if (c == 0) g.C(0, 0) = color(stops[k]);
            ++k;
        }
        {  // right
            auto& h = g.V(c + 1, r);
            edge(stops[k], g.P(c + 1, r), false, h[0], h[1], end);
            g.P(c + 1, r + 1) = end;
            if (r == 0) g.C(c + 1, 0) = color(stops[k]);
            ++k;
        }
        {  // bottom, right to left
            Vec2 h1, h2;
            end = g.P(c, r + 1);
            edge(stops[k], g.P(c + 1, r + 1), c > 0, h1, h2, end);
            g.H(c, r + 1) = {h2, h1};
            if (c == 0) g.P(0, r + 1) = end;
            g.C(c + 1, r + 1) = color(stops[k]);
            ++k;
        }
        if (c == 0) {  // left, bottom to top
            Vec2 h1, h2;
            end = g.P(0, r);
            edge(stops[k], g.P(0, r + 1), true, h1, h2, end);
            g.V(0, r) = {h2, h1};
            g.C(0, r + 1) = color(stops[k]);
        }
    }

    // Patch (c, r)'s `tensor` attribute, if any: its four interior control points as offsets
    // from the corners.
    void readTensor(const XMLElement* patch, int c, int r, SvgPatchGrid& g) const {
        const char* t = patch->Attribute("tensor");
        if (!t) return;
        const Vec2 base[4] = {g.P(c, r), g.P(c + 1, r), g.P(c + 1, r + 1), g.P(c, r + 1)};
        const char* p = t;
        auto& ts = g.tensor[g.patchIndex(c, r)];
        for (int q = 0; q < 4; ++q) {
            double x = 0, y = 0;
            if (!number(p, x, patch, "tensor") || !number(p, y, patch, "tensor"))
                fail("tensor attribute needs 8 numbers", patch);
            ts[q] = base[q] + Vec2{x, y};
        }
        skipSeparators(p);
        if (*p) fail("tensor attribute has extra text", patch);
        g.tensorSet[g.patchIndex(c, r)] = 1;
    }

    std::string file_;
};

void transformGrid(SvgPatchGrid& g, const Affine& t) {
    for (Vec2& p : g.corner) p = t.apply(p);
    for (auto& h : g.hEdge) h = {t.apply(h[0]), t.apply(h[1])};
    for (auto& h : g.vEdge) h = {t.apply(h[0]), t.apply(h[1])};
    for (auto& ts : g.tensor)
        for (Vec2& p : ts) p = t.apply(p);
}

// Patches of a meshgradient's rows: rows × patches of the first row (grid() checks the rest).
uint64_t patchesOf(const XMLElement* array) {
    uint64_t rows = 0, columns = 0;
    for (const XMLElement* r = array->FirstChildElement(); r; r = r->NextSiblingElement()) {
        if (!isNamed(r, "meshrow")) continue;
        if (rows++ == 0)
            for (const XMLElement* p = r->FirstChildElement(); p; p = p->NextSiblingElement())
                columns += isNamed(p, "meshpatch");
    }
    return rows * columns;
}

// The largest |coordinate| of the grid's points; infinity when one is not a number.
double largestCoordinate(const SvgPatchGrid& g) {
    double largest = 0;
    auto see = [&](Vec2 p) {
        for (double v : {p.x, p.y}) largest = std::isnan(v) ? INFINITY : std::max(largest, std::fabs(v));
    };
    for (const Vec2& p : g.corner) see(p);
    for (const auto& h : g.hEdge) see(h[0]), see(h[1]);
    for (const auto& h : g.vEdge) see(h[0]), see(h[1]);
    for (const auto& ts : g.tensor)
        for (const Vec2& p : ts) see(p);
    return largest;
}

}  // namespace

namespace {

// Checks on the raw text, before tinyxml2 allocates a node per element.
void checkRawSvg(const std::string& bytes, const ReadLimits& limits, const std::string& fileName) {
    const uint64_t maxBytes = std::min<uint64_t>(limits.maxFileBytes, SvgReadLimits::maxFileBytes);
    if (bytes.size() > maxBytes)
        throw Error("SVG of " + std::to_string(bytes.size()) + " bytes is over the limit of " +
                        std::to_string(maxBytes),
                    fileName);
    const uint64_t tags = static_cast<uint64_t>(std::count(bytes.begin(), bytes.end(), '<'));
    if (tags > SvgReadLimits::maxElements)
        throw Error("SVG has " + std::to_string(tags) + " tags, over the limit of " +
                        std::to_string(SvgReadLimits::maxElements),
                    fileName);
    // tinyxml2 does not expand DTD entities (so "billion laughs" cannot explode), but a file
    // that declares them means something we would read differently from other parsers.
    if (bytes.find("<!ENTITY") != std::string::npos)
        throw Error("SVG declares XML entities (<!ENTITY>), which are not supported", fileName);
}

void parseXml(tinyxml2::XMLDocument& xml, const std::string& bytes, const std::string& fileName) {
    const tinyxml2::XMLError err = xml.Parse(bytes.data(), bytes.size());
    if (err == tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED)
        throw Error("XML elements nested deeper than " +
                        std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) + " levels",
                    fileName, "line " + std::to_string(xml.ErrorLineNum()));
    if (err != tinyxml2::XML_SUCCESS)
        throw Error(std::string("not well-formed XML (") + xml.ErrorName() + ")", fileName,
                    "line " + std::to_string(xml.ErrorLineNum()));
}

// Every element once, iteratively (no recursion on file-controlled depth): ids, the elements
// painted with a url(), the meshgradients (whose rows are read through the gradient).
struct ElementIndex {
    std::unordered_map<std::string, const XMLElement*> byId;
    std::vector<const XMLElement*> painted, meshes;
    // <path>s that may be flat shapes: filled or stroked with a plain colour or a url(), each
    // with the number of `painted` elements before it in document order.
    std::vector<std::pair<const XMLElement*, size_t>> flat;
};

// The element a paint's url(#id) names; null when it names none.
const XMLElement* paintServer(const std::string& paint, const ElementIndex& index) {
    const std::string id = Reader::urlTarget(paint);
    if (id.empty()) return nullptr;
    const auto it = index.byId.find(id);
    return it == index.byId.end() ? nullptr : it->second;
}

bool isGradient(const XMLElement* el) {
    return el && (isNamed(el, "linearGradient") || isNamed(el, "radialGradient"));
}

bool isMeshGradient(const XMLElement* el) { return isNamed(el, "meshgradient"); }

// The flat shapes a path paints: 0, 1 (its fill or its stroke) or 2. A fill is one when it is
// a plain colour or a gradient (a radialGradient, refused later, counts too).
int flatShapesOf(const XMLElement* el, const ElementIndex& index) {
    Vec3 colour;
    const std::string fill = Reader::property(el, "fill");
    const XMLElement* server = paintServer(fill, index);
    if (server && isMeshGradient(server)) return 0;  // a mesh's outline
    return (parseHexColour(fill, colour) || isGradient(server)) +
           parseHexColour(Reader::property(el, "stroke"), colour);
}

// Whether a path paints with a plain colour or a url() (known once every id is indexed).
bool mayBeFlat(const XMLElement* el) {
    Vec3 colour;
    const std::string fill = Reader::property(el, "fill"), stroke = Reader::property(el, "stroke");
    return parseHexColour(fill, colour) || parseHexColour(stroke, colour) ||
           !Reader::urlTarget(fill).empty() || !Reader::urlTarget(stroke).empty();
}

ElementIndex indexElements(const XMLElement* root) {
    ElementIndex index;
    std::vector<const XMLElement*> stack{root};
    while (!stack.empty()) {
        const XMLElement* el = stack.back();
        stack.pop_back();
        if (const char* id = el->Attribute("id")) index.byId.emplace(id, el);
        if (isNamed(el, "meshgradient")) {
            index.meshes.push_back(el);
            continue;
        }
        if (isNamed(el, "path") && mayBeFlat(el)) index.flat.emplace_back(el, index.painted.size());
        if (!Reader::urlTarget(Reader::property(el, "fill")).empty()) index.painted.push_back(el);
        std::vector<const XMLElement*> children;
        for (const XMLElement* c = el->FirstChildElement(); c; c = c->NextSiblingElement())
            children.push_back(c);
        for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(*it);
    }
    return index;
}

// Canvas: the viewBox (our files map it 1:1 to pixels), else width/height (-1 when absent).
struct Canvas {
    Affine viewBoxShift;
    double width = -1, height = -1;
};

Canvas readCanvas(const XMLElement* root, Reader& rd) {
    Canvas c;
    if (const char* vb = root->Attribute("viewBox")) {
        const char* p = vb;
        double v[4];
        for (double& x : v)
            if (!rd.number(p, x, root, "viewBox")) rd.fail("viewBox needs four numbers", root);
        if (!(v[2] > 0 && v[3] > 0)) rd.fail("viewBox has no area", root);
        c.viewBoxShift.e = -v[0];
        c.viewBoxShift.f = -v[1];
        c.width = v[2];
        c.height = v[3];
    } else {
        c.width = rd.numberAttribute(root, "width", -1, true);
        c.height = rd.numberAttribute(root, "height", -1, true);
    }
    return c;
}

struct MeshUse {
    const XMLElement* paint;  // the gradient named by the fill (may href the array)
    const XMLElement* shape;  // nullptr when no shape paints it
};

// A mesh per shape painted with a meshgradient; when no shape is, a mesh per meshgradient.
std::vector<MeshUse> meshUses(const ElementIndex& index, const ReadLimits& limits,
                              const std::string& fileName) {
    std::vector<MeshUse> uses;
    for (const XMLElement* el : index.painted) {
        const std::string id = Reader::urlTarget(Reader::property(el, "fill"));
        auto it = index.byId.find(id);
        if (it == index.byId.end() || !isNamed(it->second, "meshgradient")) continue;
        uses.push_back({it->second, el});
    }
    if (uses.empty())
        for (const XMLElement* m : index.meshes) uses.push_back({m, nullptr});
    if (uses.empty() && index.flat.empty())
        throw Error("SVG has no meshgradient nor flat path", fileName);
    if (uses.size() > limits.maxMeshes)
        throw Error("SVG has " + std::to_string(uses.size()) + " meshes, over the limit", fileName);
    return uses;
}

// The gradient and those it links to by href, in order (checked: each `accepts`, described as
// `kinds`; no cycle; bounded length).
std::vector<const XMLElement*> hrefChain(const XMLElement* paint, const ElementIndex& index,
                                         Reader& rd,
                                         bool (*accepts)(const XMLElement*) = isMeshGradient,
                                         const char* kinds = "a meshgradient") {
    std::vector<const XMLElement*> chain{paint};
    std::unordered_set<const XMLElement*> seen{paint};
    while (true) {
        const std::string target = Reader::hrefTarget(chain.back());
        if (target.empty()) break;
        auto it = index.byId.find(target);
        if (it == index.byId.end()) rd.fail("href to a missing element '#" + target + "'", chain.back());
        if (!accepts(it->second))
            rd.fail("href to <" + std::string(it->second->Name()) + ">, not " + kinds,
                    chain.back());
        if (!seen.insert(it->second).second) rd.fail("href chain has a cycle", chain.back());
        if (static_cast<int>(chain.size()) >= SvgReadLimits::maxHrefChain)
            rd.fail("href chain is too long", paint);
        chain.push_back(it->second);
    }
    return chain;
}

// The transform from the gradient's space to the canvas: its gradientTransform, the shape's
// own transform and its ancestors' (user space of the root), and the viewBox's shift.
// The transform of a shape's user space to the root's: its own and its ancestors' transforms.
Affine shapeTransform(const XMLElement* shape, const XMLElement* root, Reader& rd) {
    std::vector<const XMLElement*> up;
    for (const tinyxml2::XMLNode* n = shape; n && n->ToElement(); n = n->Parent())
        up.push_back(n->ToElement());
    Affine ctm;
    for (auto it = up.rbegin(); it != up.rend(); ++it)
        if (*it != root) ctm = compose(ctm, rd.transformAttribute(*it, "transform"));
    return ctm;
}

Affine gradientToCanvas(const MeshUse& use, const XMLElement* transformEl, const XMLElement* root,
                        const Affine& viewBoxShift, Reader& rd) {
    Affine t;
    if (transformEl) t = rd.transformAttribute(transformEl, "gradientTransform");
    if (use.shape) t = compose(shapeTransform(use.shape, root, rd), t);
    return compose(viewBoxShift, t);
}

// An opacity property (fill-opacity, stroke-opacity) in 0-1; 1 when absent.
double readOpacity(const XMLElement* el, const char* name, Reader& rd) {
    const std::string text = Reader::property(el, name);
    if (text.empty()) return 1;
    char* end = nullptr;
    const double a = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end || !(a >= 0 && a <= 1))
        rd.fail(std::string(name) + " is not a number in 0-1", el);
    return a;
}

// The stroke width of a path in its own user space: a plain number, "px" allowed; 1 when
// absent (SVG's default).
double readStrokeWidth(const XMLElement* el, Reader& rd) {
    const std::string text = Reader::property(el, "stroke-width");
    if (text.empty()) return 1;
    char* end = nullptr;
    const double w = std::strtod(text.c_str(), &end);
    const std::string unit = end;
    bool plain = end != text.c_str() && (unit.empty() || unit == "px");
    for (const char* q = text.c_str(); q < end; ++q)  // no "inf", "nan", hex floats
        if (std::isalpha(static_cast<unsigned char>(*q)) && *q != 'e' && *q != 'E') plain = false;
    if (!plain || !(w > 0 && w <= kMaxStrokeWidth))
        rd.fail("stroke-width '" + text.substr(0, 40) +
                    "' is not a positive number of pixels up to " +
                    std::to_string(int(kMaxStrokeWidth)),
                el);
    return w;
}

// A stroke as FlatShape paints it: round caps, round joins, no dashes; others are refused.
void requireRoundSolidStroke(const XMLElement* el, Reader& rd) {
    const std::string cap = Reader::property(el, "stroke-linecap");
    const std::string join = Reader::property(el, "stroke-linejoin");
    const std::string dashes = Reader::property(el, "stroke-dasharray");
    if (cap != "round")
        rd.fail("stroke-linecap '" + (cap.empty() ? "butt" : cap.substr(0, 40)) +
                    "' is not supported: strokes need round caps",
                el);
    if (join != "round")
        rd.fail("stroke-linejoin '" + (join.empty() ? "miter" : join.substr(0, 40)) +
                    "' is not supported: strokes need round joins",
                el);
    if (!dashes.empty() && dashes != "none") rd.fail("dashed strokes are not supported", el);
}

// How much the transform t scales lengths; refused unless it scales every direction alike (a
// stroke under it would no longer be of one width).
double strokeScale(const Affine& t, const XMLElement* el, Reader& rd) {
    const double scale = std::sqrt(std::fabs(t.a * t.d - t.b * t.c));
    const double tol = 1e-6 * (std::fabs(t.a) + std::fabs(t.b) + std::fabs(t.c) + std::fabs(t.d));
    const bool rotation = std::fabs(t.a - t.d) <= tol && std::fabs(t.b + t.c) <= tol;
    const bool mirrored = std::fabs(t.a + t.d) <= tol && std::fabs(t.b - t.c) <= tol;
    if (!(rotation || mirrored))
        rd.fail("a stroke under a transform that scales unevenly is not supported", el);
    return scale;
}

// The most points all flat paths of a file may have together (each is 16 bytes in memory).
constexpr size_t kMaxFlatPoints = size_t(1) << 24;

// Parses a path's data in either layout (filled: closed cycles; stroked: centrelines), in the
// path's own user space.
std::vector<std::vector<Vec2>> userPathData(const XMLElement* el, bool centrelines, size_t& points,
                                            Reader& rd) {
    const char* d = el->Attribute("d");
    const size_t room = kMaxFlatPoints - std::min(points, kMaxFlatPoints);
    std::vector<std::vector<Vec2>> subpaths;
    std::string problem;
    const bool parsed =
        centrelines
            ? parseCentrelinePathData(d ? d : "", SvgReadLimits::maxCoordinate, room, subpaths,
                                      problem)
            : parseShapePathData(d ? d : "", SvgReadLimits::maxCoordinate, room, subpaths, problem);
    if (!parsed) rd.fail(problem, el);
    for (const std::vector<Vec2>& path : subpaths) points += path.size();
    return subpaths;
}

// Carries a path's subpaths to the canvas by t.
void toCanvas(std::vector<std::vector<Vec2>>& subpaths, const Affine& t, const XMLElement* el,
              Reader& rd) {
    for (std::vector<Vec2>& path : subpaths)
        for (Vec2& p : path) {
            p = t.apply(p);
            if (!(std::fabs(p.x) <= SvgReadLimits::maxCoordinate &&
                  std::fabs(p.y) <= SvgReadLimits::maxCoordinate))
                rd.fail("path coordinates reach beyond the limit of 1e7 after its transforms", el);
        }
}

// Parses a path's data in either layout and carries its points to the canvas by t.
std::vector<std::vector<Vec2>> readPathData(const XMLElement* el, bool centrelines, const Affine& t,
                                            size_t& points, Reader& rd) {
    std::vector<std::vector<Vec2>> subpaths = userPathData(el, centrelines, points, rd);
    toCanvas(subpaths, t, el, rd);
    return subpaths;
}

// Fails at the gradient element `g`, naming the path `el` it fills.
[[noreturn]] void failGradient(const std::string& what, const XMLElement* g, const XMLElement* el,
                               const Reader& rd) {
    rd.fail(what + " (in the fill of " + rd.describe(el) + ")", g);
}

// The chain's first gradient that has attribute `name`, or null; x1, y1, x2 and y2 only from a
// linearGradient (a radialGradient's mean other things).
const XMLElement* chainAttribute(const std::vector<const XMLElement*>& chain, const char* name) {
    const bool axis = name[0] == 'x' || name[0] == 'y';
    for (const XMLElement* g : chain)
        if (g->Attribute(name) && (!axis || isNamed(g, "linearGradient"))) return g;
    return nullptr;
}

// The <stop>s of the chain's first gradient that has any (SVG's inheritance through href),
// counted before they are gathered: at most kMaxGradientStops.
std::vector<const XMLElement*> stopElements(const std::vector<const XMLElement*>& chain,
                                            const XMLElement* el, Reader& rd) {
    for (const XMLElement* g : chain) {
        size_t n = 0;
        for (const XMLElement* c = g->FirstChildElement(); c; c = c->NextSiblingElement())
            n += isNamed(c, "stop");
        if (n == 0) continue;
        if (n > kMaxGradientStops)
            failGradient("a gradient of " + std::to_string(n) + " stops is over the limit of " +
                             std::to_string(kMaxGradientStops),
                         g, el, rd);
        std::vector<const XMLElement*> stops;
        for (const XMLElement* c = g->FirstChildElement(); c; c = c->NextSiblingElement())
            if (isNamed(c, "stop")) stops.push_back(c);
        return stops;
    }
    return {};
}

// A stop's offset as SVG reads it: a number or a percentage, clamped to 0–1; 0 when absent.
double stopOffset(const XMLElement* stop, Reader& rd) {
    const char* text = stop->Attribute("offset");
    if (!text) return 0;
    const char* p = text;
    double v = 0;
    const bool read = rd.number(p, v, stop, "offset");
    Reader::skipSpace(p);
    if (read && *p == '%') {
        v /= 100;
        Reader::skipSpace(++p);
    }
    if (!read || *p)
        rd.fail("offset '" + std::string(text).substr(0, 40) + "' is not a number or a percentage",
                stop);
    return std::clamp(v, 0.0, 1.0);
}

// The stops as SVG reads them: each offset at least the one before it.
std::vector<SvgStop> readStops(const std::vector<const XMLElement*>& elements, Reader& rd) {
    std::vector<SvgStop> stops;
    for (const XMLElement* e : elements) {
        SvgStop s{stopOffset(e, rd), rd.color(e), readOpacity(e, "stop-opacity", rd)};
        if (!stops.empty()) s.offset = std::max(s.offset, stops.back().offset);
        stops.push_back(s);
    }
    return stops;
}

// The stops' one stop-opacity, which multiplies the shape's; refused when they differ (the
// model's gradients vary in colour only).
double commonStopOpacity(const std::vector<SvgStop>& stops, const XMLElement* g,
                         const XMLElement* el, Reader& rd) {
    for (const SvgStop& s : stops)
        if (std::fabs(s.opacity - stops.front().opacity) > 1e-9)
            failGradient("stops of different stop-opacity are not supported (a gradient varies "
                         "in colour only)",
                         g, el, rd);
    return stops.front().opacity;
}

// An axis coordinate: a number ("px" too in user space) or a percentage of `percentBase` (user
// space: the canvas's width or height; bounding-box units: 1). Absent: fallback × percentBase.
double axisCoordinate(const std::vector<const XMLElement*>& chain, const char* name,
                      double fallback, bool bbox, double percentBase, Reader& rd) {
    const XMLElement* g = chainAttribute(chain, name);
    const bool percent = !g || std::strchr(g->Attribute(name), '%');
    if (percent && !(percentBase > 0) && (g || fallback != 0))
        rd.fail(std::string(name) + " is a percentage of a canvas of unknown size", g ? g : chain[0]);
    if (!g) return fallback * percentBase;
    const std::string text = g->Attribute(name);
    const char* p = text.c_str();
    double v = 0;
    const bool read = rd.number(p, v, g, name);
    Reader::skipSpace(p);
    if (read && *p == '%') {
        v = v / 100 * percentBase;
        ++p;
    } else if (read && !bbox && std::strncmp(p, "px", 2) == 0) {
        p += 2;
    }
    Reader::skipSpace(p);
    if (!read || *p)
        rd.fail(std::string(name) + " '" + text.substr(0, 40) +
                    (bbox ? "' is not a number or a percentage"
                          : "' is not a number of pixels or a percentage"),
                g);
    return v;
}

// Whether the chain's gradientUnits are objectBoundingBox (SVG's default), not userSpaceOnUse.
bool boundingBoxUnits(const std::vector<const XMLElement*>& chain, Reader& rd) {
    const XMLElement* g = chainAttribute(chain, "gradientUnits");
    if (!g) return true;
    const std::string units = Reader::trim(g->Attribute("gradientUnits"));
    if (units != "objectBoundingBox" && units != "userSpaceOnUse")
        rd.fail("unknown gradientUnits '" + units.substr(0, 40) + "'", g);
    return units == "objectBoundingBox";
}

// The transform from the gradient's space to the path's user space: its gradientTransform,
// then, for bounding-box units, the box of the path's own geometry (`user`).
Affine gradientToUser(const std::vector<const XMLElement*>& chain, bool bbox,
                      const std::vector<std::vector<Vec2>>& user, const XMLElement* el,
                      Reader& rd) {
    Affine g;
    if (const XMLElement* e = chainAttribute(chain, "gradientTransform"))
        g = rd.transformAttribute(e, "gradientTransform");
    if (!bbox) return g;
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    extentAlong(user, {1, 0}, x0, x1);
    extentAlong(user, {0, 1}, y0, y1);
    if (!(x1 > x0 && y1 > y0))
        failGradient("a gradient in objectBoundingBox units on a path of no width or no height",
                     chain[0], el, rd);
    return compose(Affine{x1 - x0, 0, 0, y1 - y0, x0, y0}, g);
}

// The chain's axis carried to the canvas by t (the path's user space to the canvas), as
// g.from, g.to; false when it has no length (SVG then paints the last stop's colour).
bool gradientAxis(const std::vector<const XMLElement*>& chain,
                  const std::vector<std::vector<Vec2>>& user, const Affine& t,
                  const Canvas& canvas, const XMLElement* el, LinearGradient& g, Reader& rd) {
    const bool bbox = boundingBoxUnits(chain, rd);
    const double w = bbox ? 1 : canvas.width, h = bbox ? 1 : canvas.height;
    const Vec2 a{axisCoordinate(chain, "x1", 0, bbox, w, rd),
                 axisCoordinate(chain, "y1", 0, bbox, h, rd)};
    const Vec2 b{axisCoordinate(chain, "x2", 1, bbox, w, rd),
                 axisCoordinate(chain, "y2", 0, bbox, h, rd)};
    if (a == b) return false;
    if (!canvasGradientAxis(a, b, compose(t, gradientToUser(chain, bbox, user, el, rd)), g.from,
                            g.to))
        failGradient("the gradient's transform to the canvas is not invertible", chain[0], el, rd);
    for (const Vec2& p : {g.from, g.to})
        if (!(std::fabs(p.x) <= SvgReadLimits::maxCoordinate &&
              std::fabs(p.y) <= SvgReadLimits::maxCoordinate))
            failGradient("the gradient's ends reach beyond the limit of 1e7 after its transforms",
                         chain[0], el, rd);
    if (!(norm(g.to - g.from) > kMinGradientLength))
        failGradient("the gradient's colours change over less than 0.1 px on the canvas, under "
                     "what a gradient may hold",
                     chain[0], el, rd);
    return true;
}

// spreadMethod pad, or any when the shape (`canvasPaths`) lies within the axis's span, where
// the colours beyond its ends never show.
void requirePadSpread(const std::vector<const XMLElement*>& chain, const LinearGradient& g,
                      const std::vector<std::vector<Vec2>>& canvasPaths, const XMLElement* el,
                      Reader& rd) {
    const XMLElement* e = chainAttribute(chain, "spreadMethod");
    const std::string spread = e ? Reader::trim(e->Attribute("spreadMethod")) : "pad";
    if (spread == "pad") return;
    if (spread != "reflect" && spread != "repeat")
        failGradient("unknown spreadMethod '" + spread.substr(0, 40) + "'", e, el, rd);
    const double length = norm(g.to - g.from);
    const Vec2 dir = (1 / length) * (g.to - g.from);
    double lo = 0, hi = 0;
    extentAlong(canvasPaths, dir, lo, hi);
    const double at = dot(g.from, dir), slack = 0.01;  // px
    if (!(lo - at >= -slack && hi - at <= length + slack))
        failGradient("spreadMethod '" + spread +
                         "' is not supported where the shape reaches beyond the gradient's ends "
                         "(only pad is)",
                     e, el, rd);
}

// color-interpolation sRGB (SVG's default), the model's; linearRGB is refused.
void requireSrgbInterpolation(const std::vector<const XMLElement*>& chain, const XMLElement* el,
                              Reader& rd) {
    for (const XMLElement* g : chain)
        if (Reader::property(g, "color-interpolation") == "linearRGB")
            failGradient("color-interpolation linearRGB is not supported (gradients interpolate "
                         "in sRGB)",
                         g, el, rd);
}

// The fill of path `el` by the gradient `paint` as `shape`: its subpaths on the canvas, its
// gradient, mean colour and opacity. false when it paints nothing (a gradient without stops
// paints as `none`; a path of no segment encloses nothing).
bool readGradientFill(const XMLElement* el, const XMLElement* paint, const ElementIndex& index,
                      const Affine& t, const Canvas& canvas, size_t& points, FlatShape& shape,
                      Reader& rd) {
    if (!isNamed(paint, "linearGradient"))
        rd.fail("fills by <" + std::string(paint->Name()) + "> are not supported (" +
                    rd.describe(paint) + "); only linearGradient and meshgradient are",
                el);
    const std::vector<const XMLElement*> chain =
        hrefChain(paint, index, rd, isGradient, "a linearGradient or radialGradient");
    requireSrgbInterpolation(chain, el, rd);
    const std::vector<const XMLElement*> stopEls = stopElements(chain, el, rd);
    if (stopEls.empty()) return false;
    if ((points += 2 * stopEls.size()) > kMaxFlatPoints)  // a stop takes two points' memory
        rd.fail("the flat paths and their gradients hold too many points", el);
    const std::vector<SvgStop> stops = readStops(stopEls, rd);
    std::vector<std::vector<Vec2>> user = userPathData(el, false, points, rd);
    if (user.empty()) return false;  // no segment: nothing to fill, no box for its units
    shape.alpha = readOpacity(el, "fill-opacity", rd) * commonStopOpacity(stops, paint, el, rd);
    LinearGradient g;
    const bool graded = stops.size() > 1 && gradientAxis(chain, user, t, canvas, el, g, rd);
    shape.subpaths = std::move(user);
    toCanvas(shape.subpaths, t, el, rd);
    shape.col = stops.back().col;  // one stop, or an axis of no length
    if (!graded) return true;
    g.stops = modelGradientStops(stops);
    if (g.stops.size() > kMaxGradientStops)
        failGradient("a gradient of " + std::to_string(g.stops.size()) +
                         " stops with those added at 0 and 1 is over the limit of " +
                         std::to_string(kMaxGradientStops),
                     paint, el, rd);
    requirePadSpread(chain, g, shape.subpaths, el, rd);
    if (const std::string problem = gradientProblem(g); !problem.empty())
        failGradient("gradient: " + problem, paint, el, rd);
    shape.col = meanGradientColour(g);
    shape.gradient = std::move(g);
    return true;
}

// A stroke painted with a gradient: FlatShape strokes are of one colour.
void refuseGradientStroke(const XMLElement* el, const ElementIndex& index, Reader& rd) {
    const XMLElement* server = paintServer(Reader::property(el, "stroke"), index);
    if (isGradient(server) || (server && isMeshGradient(server)))
        rd.fail("strokes painted with a gradient (" + rd.describe(server) +
                    ") are not supported; only strokes of one colour are",
                el);
}

// A <path> filled with a plain colour or a linearGradient as a flat shape (nonzero rule;
// fill-opacity as its alpha), and one stroked with a plain colour as a stroked shape
// (stroke-width, carried by the transforms, as its width; stroke-opacity as its alpha), in that
// order, which is SVG's paint order; points carried to the canvas; `layer` as FlatShape::layer.
// A path filled with a meshgradient is that mesh's outline, read as the mesh.
void readFlatPath(const XMLElement* el, size_t layer, const XMLElement* root,
                  const ElementIndex& index, const Canvas& canvas, size_t& points, Reader& rd,
                  std::vector<FlatShape>& shapes) {
    const std::string fill = Reader::property(el, "fill");
    const XMLElement* server = paintServer(fill, index);
    if (server && isMeshGradient(server)) return;
    refuseGradientStroke(el, index, rd);
    const Affine t = compose(canvas.viewBoxShift, shapeTransform(el, root, rd));
    FlatShape shape;
    shape.layer = layer;
    // A fill of no segment ("M x y z") paints nothing: no shape.
    if (isGradient(server)) {
        if (readGradientFill(el, server, index, t, canvas, points, shape, rd))
            shapes.push_back(std::move(shape));
    } else if (parseHexColour(fill, shape.col)) {
        shape.alpha = readOpacity(el, "fill-opacity", rd);
        shape.subpaths = readPathData(el, false, t, points, rd);
        if (!shape.subpaths.empty()) shapes.push_back(std::move(shape));
    }
    FlatShape line;
    line.layer = layer;
    if (parseHexColour(Reader::property(el, "stroke"), line.col)) {
        requireRoundSolidStroke(el, rd);
        line.alpha = readOpacity(el, "stroke-opacity", rd);
        line.strokeWidth = readStrokeWidth(el, rd) * strokeScale(t, el, rd);
        if (!(line.strokeWidth > 0 && line.strokeWidth <= kMaxStrokeWidth))
            rd.fail("stroke-width out of range after its transforms", el);
        line.subpaths = readPathData(el, true, t, points, rd);
        shapes.push_back(std::move(line));
    }
}

// Our writer grows a mesh beyond its outline path (svg_grid_outset.h) and says so in
// data-outset; undone here, in the gradient's own space, so that the mesh read is the one
// written. `outsetEl` and `heldEl` hold the attributes, or are null.
void undoOutset(SvgPatchGrid& g, const XMLElement* outsetEl, const XMLElement* heldEl,
                const Reader& rd) {
    if (!outsetEl) return;
    const double amount = rd.numberAttribute(outsetEl, "data-outset", 0);
    if (!(amount >= 0 && amount <= kLargestOutset))
        rd.fail("data-outset must lie between 0 and " + std::to_string(int(kLargestOutset)) + " px",
                outsetEl);
    HeldEdges held;
    if (heldEl && !parseHeldEdges(heldEl->Attribute("data-outset-held"), g.columns, held))
        rd.fail("data-outset-held must read like \"top 0-3 7 bottom 2\", with columns of the "
                "mesh's " + std::to_string(g.columns),
                heldEl);
    insetGrid(g, amount, held);
}

// One use's mesh. Attributes come from the first gradient of the href chain that has them; the
// rows from the first that has rows. `patches` counts the document's patches so far (each use
// of a gradient is a copy of it).
GradientMesh readMeshUse(const MeshUse& use, const ElementIndex& index, const XMLElement* root,
                         const Canvas& canvas, const ReadLimits& limits, size_t useCount,
                         uint64_t& patches, Reader& rd, const std::string& fileName) {
    const std::vector<const XMLElement*> chain = hrefChain(use.paint, index, rd);
    auto attr = [&](const char* name) -> const XMLElement* {
        for (const XMLElement* g : chain)
            if (g->Attribute(name)) return g;
        return nullptr;
    };
    const XMLElement* array = nullptr;
    for (const XMLElement* g : chain) {
        for (const XMLElement* c = g->FirstChildElement(); c && !array; c = c->NextSiblingElement())
            if (isNamed(c, "meshrow")) array = g;
        if (array) break;
    }
    if (!array) rd.fail("meshgradient has no meshrow (nor one it links to)", use.paint);
    patches += patchesOf(array);
    if (patches > limits.maxPatches)
        rd.fail(tooManyPatchesMessage(patches, limits.maxPatches) + ", " + std::to_string(useCount) +
                    " shapes painting meshes",
                use.shape ? use.shape : use.paint);
    const XMLElement* unitsEl = attr("gradientUnits");
    if (!unitsEl || std::strcmp(unitsEl->Attribute("gradientUnits"), "userSpaceOnUse") != 0)
        rd.fail("meshgradient must have gradientUnits=\"userSpaceOnUse\" "
                "(objectBoundingBox is not supported)",
                use.paint);
    Vec2 origin;
    if (const XMLElement* e = attr("x")) origin.x = rd.numberAttribute(e, "x", 0, true);
    if (const XMLElement* e = attr("y")) origin.y = rd.numberAttribute(e, "y", 0, true);
    bool bicubic = false;
    if (const XMLElement* e = attr("type")) {
        const std::string t = e->Attribute("type");
        if (t == "bicubic")
            bicubic = true;
        else if (t != "coons" && t != "bilinear")
            rd.fail("unsupported meshgradient type '" + t.substr(0, 40) + "'", e);
    }
    SvgPatchGrid g = rd.grid(array, origin, limits);
    g.bicubic = bicubic;
    undoOutset(g, attr("data-outset"), attr("data-outset-held"), rd);
    transformGrid(g, gradientToCanvas(use, attr("gradientTransform"), root, canvas.viewBoxShift, rd));
    // Each number is within maxCoordinate, but nested transforms multiply them.
    if (const double reach = largestCoordinate(g); !(reach <= SvgReadLimits::maxCoordinate)) {
        char text[32];
        std::snprintf(text, sizeof text, "%.3g", reach);
        rd.fail(std::string("mesh coordinates reach ") + text +
                    " after its transforms, over the limit of 1e7",
                use.shape ? use.shape : use.paint);
    }
    return meshFromPatchGrid(g, fileName, rd.describe(use.paint));
}

// The document's size: the canvas's, else (no usable size) the meshes' bounds.
void setDocumentSize(Document& doc, Canvas canvas, const ReadLimits& limits,
                     const std::string& fileName) {
    if (canvas.width <= 0 || canvas.height <= 0) {
        double mx = 1, my = 1;
        for (const GradientMesh& m : doc.meshes)
            for (const Node& n : m.nodes) {
                mx = std::max(mx, n.pos.x);
                my = std::max(my, n.pos.y);
            }
        canvas.width = mx;
        canvas.height = my;
    }
    if (canvas.width > static_cast<double>(limits.maxCanvasSide) ||
        canvas.height > static_cast<double>(limits.maxCanvasSide))
        throw Error("canvas is larger than the reader's limit", fileName);
    doc.width = static_cast<int>(std::ceil(canvas.width - 1e-9));
    doc.height = static_cast<int>(std::ceil(canvas.height - 1e-9));
}

}  // namespace

Document decodeSvg(const std::string& bytes, const ReadLimits& limits, const std::string& fileName) {
    checkRawSvg(bytes, limits, fileName);
    tinyxml2::XMLDocument xml(true, tinyxml2::PRESERVE_WHITESPACE);
    parseXml(xml, bytes, fileName);
    const XMLElement* root = xml.RootElement();
    if (!root) throw Error("no root element", fileName);
    Reader rd(fileName);
    if (!isNamed(root, "svg")) rd.fail("root element is not <svg>", root);

    const ElementIndex index = indexElements(root);
    const Canvas canvas = readCanvas(root, rd);
    const std::vector<MeshUse> uses = meshUses(index, limits, fileName);
    Document doc;
    uint64_t patches = 0;
    std::vector<size_t> usesBefore(index.painted.size() + 1, 0);  // per painted-element count
    for (const MeshUse& use : uses) {
        doc.meshes.push_back(
            readMeshUse(use, index, root, canvas, limits, uses.size(), patches, rd, fileName));
        for (size_t k = 0; k < index.painted.size(); ++k)
            if (index.painted[k] == use.shape) ++usesBefore[k + 1];
    }
    for (size_t k = 0; k < index.painted.size(); ++k) usesBefore[k + 1] += usesBefore[k];
    uint64_t outlined = 0;
    for (const auto& f : index.flat)
        if (f.first->Attribute("d")) outlined += static_cast<uint64_t>(flatShapesOf(f.first, index));
    if (outlined > limits.maxShapes)
        throw Error("SVG has " + std::to_string(outlined) + " flat shapes, over the limit of " +
                        std::to_string(limits.maxShapes),
                    fileName);
    size_t points = 0;
    for (const auto& [el, painted] : index.flat)
        if (el->Attribute("d"))
            readFlatPath(el, usesBefore[painted], root, index, canvas, points, rd, doc.shapes);
    setDocumentSize(doc, canvas, limits, fileName);
    const std::string problem = validateDocument(doc);
    if (!problem.empty()) throw Error("meshes and shapes read are not valid: " + problem, fileName);
    return doc;
}

}  // namespace gm
