#include "svg_grid_outset.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace gm {

namespace {

// A corner closer than this (px) to its interior corner is not moved: its ray has no direction
// worth trusting. The reader tells such corners apart by their distance, which stays below the
// outset (a moved corner's grew by the whole outset).
constexpr double kShortestRay = 0.1;

// Per patch column of the top and bottom rows: whether that edge is held.
struct HeldColumns {
    std::vector<char> top, bottom;
};

HeldColumns heldColumns(const HeldEdges& held, int columns) {
    HeldColumns h{std::vector<char>(static_cast<size_t>(columns), 0),
                  std::vector<char>(static_cast<size_t>(columns), 0)};
    for (int i : held.top)
        if (i >= 0 && i < columns) h.top[static_cast<size_t>(i)] = 1;
    for (int i : held.bottom)
        if (i >= 0 && i < columns) h.bottom[static_cast<size_t>(i)] = 1;
    return h;
}

// Whether boundary corner (c, r) lies on a held edge.
bool cornerHeld(const SvgPatchGrid& g, const HeldColumns& h, int c, int r) {
    const std::vector<char>* row = r == 0 ? &h.top : r == g.rows ? &h.bottom : nullptr;
    if (!row) return false;
    return (c > 0 && (*row)[static_cast<size_t>(c - 1)]) || (c < g.columns && (*row)[static_cast<size_t>(c)]);
}

// Moves every corner of `g` by its `shift` and every other control point by the bilinear blend
// of its patch's corner shifts at that point's place in the control net (thirds). The patches
// move by a smooth field: an edge written as a line stays one, and a tensor point stays as far
// from the Coons interior as it was.
void shiftGrid(SvgPatchGrid& g, const std::vector<Vec2>& shift) {
    const auto d = [&](int c, int r) { return shift[static_cast<size_t>(r) * (g.columns + 1) + c]; };
    const auto blend = [](Vec2 near, Vec2 far) { return (1.0 / 3) * (2.0 * near + far); };
    for (int r = 0; r <= g.rows; ++r)
        for (int c = 0; c <= g.columns; ++c) g.P(c, r) = g.P(c, r) + d(c, r);
    for (int r = 0; r <= g.rows; ++r)
        for (int c = 0; c < g.columns; ++c) {
            auto& h = g.H(c, r);
            h[0] = h[0] + blend(d(c, r), d(c + 1, r));
            h[1] = h[1] + blend(d(c + 1, r), d(c, r));
        }
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c <= g.columns; ++c) {
            auto& h = g.V(c, r);
            h[0] = h[0] + blend(d(c, r), d(c, r + 1));
            h[1] = h[1] + blend(d(c, r + 1), d(c, r));
        }
    // Interior points in Inkscape's order: near the top-left, top-right, bottom-right,
    // bottom-left corner; each 4/9 of its own corner's shift, 2/9 of each neighbour's, 1/9 of
    // the opposite one's.
    for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.columns; ++c) {
            const Vec2 corner[4] = {d(c, r), d(c + 1, r), d(c + 1, r + 1), d(c, r + 1)};
            auto& t = g.tensor[g.patchIndex(c, r)];
            for (int k = 0; k < 4; ++k)
                t[static_cast<size_t>(k)] =
                    t[static_cast<size_t>(k)] +
                    (1.0 / 9) * (4.0 * corner[k] + 2.0 * (corner[(k + 1) % 4] + corner[(k + 3) % 4]) +
                                 corner[(k + 2) % 4]);
        }
}

// Per corner of `g`, row-major: step(ray) for every boundary corner not held, where ray runs
// from the corner's interior corner to it; zero for the others.
template <class Step>
std::vector<Vec2> boundaryShifts(const SvgPatchGrid& g, const HeldEdges& held, Step step) {
    const HeldColumns h = heldColumns(held, g.columns);
    std::vector<Vec2> shift(g.corner.size(), Vec2{});
    for (int r = 0; r <= g.rows; ++r)
        for (int c = 0; c <= g.columns; ++c) {
            const bool boundary = r == 0 || r == g.rows || c == 0 || c == g.columns;
            if (!boundary || cornerHeld(g, h, c, r)) continue;
            const Vec2 inner = g.P(std::clamp(c, 1, g.columns - 1), std::clamp(r, 1, g.rows - 1));
            shift[static_cast<size_t>(r) * (g.columns + 1) + c] = step(g.P(c, r) - inner);
        }
    return shift;
}

// Appends "a" or "a-b" for each run of consecutive columns.
void appendRuns(std::string& out, const std::vector<int>& columns) {
    for (size_t k = 0; k < columns.size();) {
        size_t e = k;
        while (e + 1 < columns.size() && columns[e + 1] == columns[e] + 1) ++e;
        out += ' ' + std::to_string(columns[k]);
        if (e > k) out += '-' + std::to_string(columns[e]);
        k = e + 1;
    }
}

// Reads a non-negative integer below `limit` at p; false if there is none.
bool readColumn(const char*& p, int limit, int& value) {
    if (!std::isdigit(static_cast<unsigned char>(*p))) return false;
    long v = 0;
    while (std::isdigit(static_cast<unsigned char>(*p))) {
        v = v * 10 + (*p++ - '0');
        if (v >= limit) return false;
    }
    value = static_cast<int>(v);
    return true;
}

}  // namespace

bool canOutsetGrid(const SvgPatchGrid& g) { return g.columns >= 2 && g.rows >= 2; }

void outsetGrid(SvgPatchGrid& g, double amount, const HeldEdges& held) {
    if (!canOutsetGrid(g)) return;
    shiftGrid(g, boundaryShifts(g, held, [&](Vec2 ray) {
                  const double length = norm(ray);
                  return length > kShortestRay ? (amount / length) * ray : Vec2{};
              }));
}

void insetGrid(SvgPatchGrid& g, double amount, const HeldEdges& held) {
    if (!canOutsetGrid(g)) return;
    shiftGrid(g, boundaryShifts(g, held, [&](Vec2 ray) {
                  const double length = norm(ray);
                  return length > amount + 0.5 * kShortestRay ? (-amount / length) * ray : Vec2{};
              }));
}

std::string heldEdgesText(const HeldEdges& held) {
    std::string out;
    if (!held.top.empty()) {
        out += "top";
        appendRuns(out, held.top);
    }
    if (!held.bottom.empty()) {
        if (!out.empty()) out += ' ';
        out += "bottom";
        appendRuns(out, held.bottom);
    }
    return out;
}

bool parseHeldEdges(const std::string& text, int columns, HeldEdges& held) {
    HeldColumns h{std::vector<char>(static_cast<size_t>(std::max(columns, 0)), 0),
                  std::vector<char>(static_cast<size_t>(std::max(columns, 0)), 0)};
    std::vector<char>* row = nullptr;
    const char* p = text.c_str();
    while (true) {
        while (*p == ' ') ++p;
        if (!*p) break;
        if (text.compare(static_cast<size_t>(p - text.c_str()), 3, "top") == 0) {
            row = &h.top, p += 3;
        } else if (text.compare(static_cast<size_t>(p - text.c_str()), 6, "bottom") == 0) {
            row = &h.bottom, p += 6;
        } else {
            int first = 0, last = 0;
            if (!row || !readColumn(p, columns, first)) return false;
            last = first;
            if (*p == '-' && !readColumn(++p, columns, last)) return false;
            if (last < first) return false;
            std::fill(row->begin() + first, row->begin() + last + 1, 1);
        }
        if (*p && *p != ' ') return false;
    }
    held = {};
    for (int i = 0; i < columns; ++i) {
        if (h.top[static_cast<size_t>(i)]) held.top.push_back(i);
        if (h.bottom[static_cast<size_t>(i)]) held.bottom.push_back(i);
    }
    return true;
}

}  // namespace gm
