// What every command of `gradmesh` shares, in both of its programs (docs/design.md, "Start-up"):
// argument parsing, reading a mesh file, and the one place that turns errors into messages and
// exit codes: 0 success, 1 a failure with the input or output, 2 a usage error.
#pragma once

#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/registry.h"

namespace gm::cli {

// A bad command line: reported with a pointer to the command's --help, exit code 2.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> values;
    std::set<std::string> flags;
};

// argv[2...] of `command`: -o is --output; --name=value or --name value for `valued` options;
// `flagNames` take no value. Throws UsageError on anything else.
Args parseArgs(const std::string& command, int argc, char** argv,
               const std::set<std::string>& valued, const std::set<std::string>& flagNames);

// `text` as a number from lo to hi; UsageError naming `option` otherwise.
double parseNumber(const std::string& option, const std::string& text, double lo, double hi);

// Refuses a missing input and anything but a regular file (a FIFO would hang the run, a device
// feed it without end) before anything opens it.
void requireInputFile(const std::string& path);

// The format of `registry` that reads `path` (gm::Error naming the file when none does).
const MeshFormat* readerFor(const FormatRegistry& registry, const std::string& path);

// The document in `path`, read and validated (gm::Error naming the file on any problem).
Document readDocument(const FormatRegistry& registry, const std::string& path,
                      const ReadOptions& options = {});

// The process set-up every run of a command needs (allocator thresholds, signals).
void prepareProcess();

// Runs `command` and turns what it throws into one line on standard error and an exit code.
int runReportingErrors(const std::string& command, const std::function<int()>& run);

}  // namespace gm::cli
