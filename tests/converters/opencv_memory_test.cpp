// OpenCV's allocation failures leave the converters as std::bad_alloc (opencv_memory.h), which
// the commands report as "out of memory"; its other errors pass unchanged.
#include <catch2/catch.hpp>

#include <new>

#include "opencv_memory.h"

using namespace gm;

TEST_CASE("an OpenCV allocation failure becomes std::bad_alloc, other OpenCV errors stay",
          "[opencv][memory]") {
    CHECK(withOpenCvOutOfMemoryAsBadAlloc([] { return 7; }) == 7);
    CHECK_THROWS_AS(withOpenCvOutOfMemoryAsBadAlloc([]() -> int {
                        cv::error(cv::Error::StsNoMem, "Failed to allocate", "test", "here", 1);
                        return 0;
                    }),
                    std::bad_alloc);
    CHECK_THROWS_AS(withOpenCvOutOfMemoryAsBadAlloc([]() -> int {
                        cv::error(cv::Error::StsBadArg, "bad argument", "test", "here", 1);
                        return 0;
                    }),
                    cv::Exception);
}
