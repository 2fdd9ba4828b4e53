// A private directory (mode 0700) under $TMPDIR, else /tmp, for files a run needs only while it
// lasts: standard input spooled to a file, an output bound for standard output, an image an
// encoder can only write to a file. It and its files are removed when it is destroyed, and on
// SIGINT, SIGTERM or SIGHUP (temp_registry.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace gm {

class PrivateDir {
public:
    // Throws gm::Error when the directory cannot be made.
    PrivateDir();
    ~PrivateDir();
    PrivateDir(const PrivateDir&) = delete;
    PrivateDir& operator=(const PrivateDir&) = delete;

    // The path of the file `name` in the directory (made by its user), removed with it.
    std::string file(const std::string& name);

private:
    std::string path_;
    int slot_ = -1;
    std::vector<std::pair<std::string, int>> files_;  // path, temp_registry slot
};

}  // namespace gm
