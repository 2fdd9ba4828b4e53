// Test support for the command-line tests: running gradmesh with its output captured, and
// scratch directories under the build tree.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "support/compare.h"

namespace gmtest {

struct Run {
    int code;
    std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// An empty directory GRADMESH_TMP/<prefix><name>.
inline std::filesystem::path scratchDir(const std::string& prefix, const std::string& name) {
    std::filesystem::path d = std::filesystem::path(GRADMESH_TMP) / (prefix + name);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

// Runs `gradmesh ARGS` with stdout and stderr captured into dir/stdout.txt and dir/stderr.txt,
// under a time limit: a hang shows as 124, a crash as 128 + signal (or -1).
inline Run runGradmesh(const std::string& args, const std::filesystem::path& dir) {
    const std::string o = (dir / "stdout.txt").string(), e = (dir / "stderr.txt").string();
    Run r;
    r.code = runCommand("timeout -k 5 60 " + std::string(GRADMESH_EXE) + " " + args + " >" +
                        quote(o) + " 2>" + quote(e) + " </dev/null");
    r.out = slurp(o);
    r.err = slurp(e);
    return r;
}

inline size_t lineCount(const std::string& s) {
    size_t n = 0;
    for (char c : s) n += c == '\n';
    return n;
}

inline std::string q(const std::filesystem::path& p) { return quote(p.string()); }

}  // namespace gmtest
