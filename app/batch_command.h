// `gradmesh batch`: many images converted as `convert` converts one, on every core, resumable,
// with a JSON-lines log (docs/batch.md).
#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "formats/registry.h"

namespace gm {

// What batch takes from convert: its option names and its parsing of the writers' options, so
// that each image is converted with exactly the options convert would use.
struct ConvertSyntax {
    std::set<std::string> valued, flags;
    // Throws (the command's usage error) on a bad value.
    std::function<WriteOptions(const std::map<std::string, std::string>& values,
                               const std::set<std::string>& flags)>
        writeOptions;
};

// Runs `gradmesh batch ARGS`. Returns the exit code: 0 when every image is done, 1 when one
// failed. Throws std::invalid_argument on a usage error (before any image is converted) and
// gm::Error on an unreadable manifest or log.
int batchCommand(const std::vector<std::string>& args, const ConvertSyntax& convert);

}  // namespace gm
