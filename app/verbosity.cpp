#include "verbosity.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>

namespace gm::cli {

namespace {

Verbosity level = Verbosity::Normal;

void printTo(const char* format, va_list args) {
    std::vfprintf(stderr, format, args);
    std::fflush(stderr);
}

}  // namespace

Verbosity verbosity() { return level; }

void setVerbosity(Verbosity v) { level = v; }

void takeVerbosityOptions(int& argc, char** argv) {
    int kept = 2;
    for (int k = 2; k < argc; ++k) {
        if (std::strcmp(argv[k], "--quiet") == 0 || std::strcmp(argv[k], "-q") == 0)
            level = Verbosity::Quiet;
        else if (std::strcmp(argv[k], "--verbose") == 0)
            level = Verbosity::Verbose;
        else
            argv[kept++] = argv[k];
    }
    argc = kept;
    argv[argc] = nullptr;
}

void note(const char* format, ...) {
    if (level == Verbosity::Quiet) return;
    va_list args;
    va_start(args, format);
    printTo(format, args);
    va_end(args);
}

void detail(const char* format, ...) {
    if (level != Verbosity::Verbose) return;
    va_list args;
    va_start(args, format);
    printTo(format, args);
    va_end(args);
}

}  // namespace gm::cli
