// The command-line tests' shared pieces: gradmesh run in the foreground, the apple sample
// converted quickly, and what a clean failure looks like.
#pragma once

#include <catch2/catch.hpp>

#include "output_safety_support.h"

namespace safetytest {

inline gmtest::Run gradmesh(const std::string& args, const fs::path& dir) {
    return gmtest::runGradmesh(args, dir);
}

inline const std::string kApple = std::string(GRADMESH_SAMPLES) + "/apple.jpg";
inline const std::string kAppleMask = std::string(GRADMESH_SAMPLES) + "/apple_mask.png";

// A quick image conversion writing `out` (and the report when given).
inline std::string convertApple(const fs::path& out, const std::string& report = {}) {
    return "convert " + gmtest::q(kApple) + " --mask " + gmtest::q(kAppleMask) +
           " --max-patches 16 -o " + gmtest::q(out) +
           (report.empty() ? std::string() : " --report " + gmtest::q(report));
}

// Exit 1, one line on stderr, naming `named`.
inline void checkFailedCleanly(const gmtest::Run& r, const std::string& named) {
    INFO("exit " << r.code << ", stderr: " << r.err);
    CHECK(r.code == 1);
    CHECK(gmtest::lineCount(r.err) == 1);
    CHECK_THAT(r.err, Catch::Matchers::Contains(named));
}

}  // namespace safetytest
