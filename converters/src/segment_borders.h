// Segmentation borders refined at full size. The segmentation's regions are found on a
// downscaled copy of a large image; upscaled, their borders are staircases of the downscaled
// pixel's size. Each full-size pixel near a border is given, among the labels around it, the
// one whose local colour it is closest to, so that borders follow the image's edges to the
// pixel at a cost proportional to the border's length.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

namespace gm {

// `small` holds one label per pixel of `smallBgr` (negative: none); returns labels for every
// pixel of `fullBgr`: the nearest small pixel's label, except within about one small pixel of
// a border between two labels, where each pixel takes the label of the small pixels around it
// whose mean colour (over a 5×5 small-pixel window, border pixels left out where possible)
// is closest to its own. Unlabelled pixels stay unlabelled. Returns the number of pixels whose
// label differs from plain upscaling in `changed` when not null.
std::vector<int> upscaleLabelsRefined(const cv::Mat& smallBgr, const std::vector<int>& small,
                                      const cv::Mat& fullBgr, int threads, long* changed);

}  // namespace gm
