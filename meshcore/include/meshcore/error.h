// The one exception type for failures that depend on a file, a user or another library.
// A broken invariant is a bug and is asserted instead.
#pragma once

#include <stdexcept>
#include <string>

namespace gm {

class Error : public std::runtime_error {
public:
    // `file` names the file involved (may be empty); `where` says where in it (may be empty,
    // e.g. "byte 1234" or "<meshpatch> 3 of row 2").
    Error(const std::string& what, std::string file = {}, std::string where = {})
        : std::runtime_error(compose(what, file, where)), file_(std::move(file)),
          where_(std::move(where)), what_(what) {}
    const std::string& file() const { return file_; }
    const std::string& where() const { return where_; }
    const std::string& reason() const { return what_; }

private:
    static std::string compose(const std::string& what, const std::string& file,
                               const std::string& where) {
        std::string s;
        if (!file.empty()) s += file + ": ";
        if (!where.empty()) s += where + ": ";
        return s + what;
    }
    std::string file_, where_, what_;
};

}  // namespace gm
