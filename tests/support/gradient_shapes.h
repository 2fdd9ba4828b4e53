// Test support: filled flat shapes painted with linear gradients, for the writers' and
// consumers' tests.
#pragma once

#include <utility>
#include <vector>

#include "meshcore/gradient_mesh.h"

namespace gmtest {

inline gm::LinearGradient linearGradient(gm::Vec2 from, gm::Vec2 to,
                                         std::vector<std::pair<double, gm::Vec3>> stops) {
    gm::LinearGradient g;
    g.from = from;
    g.to = to;
    for (const auto& [offset, col] : stops) g.stops.push_back({offset, col});
    return g;
}

// The mean of the gradient's stop colours, weighted by the spans they bound: what a shape's
// `col` holds for readers that want one colour.
inline gm::Vec3 meanStopColour(const gm::LinearGradient& g) {
    gm::Vec3 sum;
    for (size_t k = 1; k < g.stops.size(); ++k)
        sum = sum + (0.5 * (g.stops[k].offset - g.stops[k - 1].offset)) *
                        (g.stops[k - 1].col + g.stops[k].col);
    return sum;
}

inline gm::FlatShape gradedShape(std::vector<std::vector<gm::Vec2>> subpaths,
                                 gm::LinearGradient g, double alpha = 1) {
    gm::FlatShape s;
    s.subpaths = std::move(subpaths);
    s.gradient = std::move(g);
    s.col = meanStopColour(s.gradient);
    s.alpha = alpha;
    return s;
}

// On a 200 × 140 canvas, all at layer 0: a flat backdrop rectangle; a square with a horizontal
// two-stop gradient; a diamond with a diagonal three-stop gradient whose axis ends inside the
// shape (both pads show); a rectangle with a hole, its gradient vertical with four stops and
// running the other way (from below to above); a translucent triangle with a two-stop
// gradient over the others.
inline std::vector<gm::FlatShape> gradientTestShapes() {
    using gm::Vec2;
    std::vector<gm::FlatShape> shapes;
    gm::FlatShape backdrop;
    backdrop.col = {0.92, 0.9, 0.85};
    backdrop.subpaths = {gm::polygonAsCubics({{0, 0}, {200, 0}, {200, 140}, {0, 140}})};
    shapes.push_back(backdrop);

    shapes.push_back(
        gradedShape({gm::polygonAsCubics({{10, 10}, {80, 10}, {80, 70}, {10, 70}})},
                    linearGradient({10, 40}, {80, 40}, {{0, {0.9, 0.1, 0.1}}, {1, {0.1, 0.2, 0.9}}})));

    shapes.push_back(gradedShape(
        {gm::polygonAsCubics({{140, 5}, {190, 45}, {140, 85}, {90, 45}})},
        linearGradient({115, 25}, {165, 65},
                       {{0, {1, 0.9, 0.2}}, {0.4, {0.2, 0.7, 0.3}}, {1, {0.05, 0.1, 0.3}}})));

    // Outer boundary clockwise on screen, the hole counter-clockwise.
    shapes.push_back(gradedShape(
        {gm::polygonAsCubics({{20, 80}, {120, 80}, {120, 132}, {20, 132}}),
         gm::polygonAsCubics({{50, 95}, {50, 118}, {90, 118}, {90, 95}})},
        linearGradient({70, 132}, {70, 80},
                       {{0, {0.1, 0.1, 0.1}},
                        {0.3, {0.8, 0.3, 0.1}},
                        {0.7, {0.95, 0.95, 0.6}},
                        {1, {0.3, 0.6, 0.9}}})));

    shapes.push_back(gradedShape(
        {gm::polygonAsCubics({{60, 30}, {180, 100}, {100, 135}})},
        linearGradient({60, 30}, {140, 118}, {{0, {0.6, 0.1, 0.7}}, {1, {0.1, 0.8, 0.8}}}), 0.6));
    return shapes;
}

inline gm::Document gradientTestDocument() {
    gm::Document d;
    d.width = 200;
    d.height = 140;
    d.shapes = gradientTestShapes();
    return d;
}

}  // namespace gmtest
