// --quiet and --verbose, which every command takes: what a run prints on standard error besides
// its errors. Errors are always printed; notes (warnings, the SVG refit's figures) unless
// --quiet; details (seconds per stage, figures) only with --verbose.
#pragma once

namespace gm::cli {

enum class Verbosity { Quiet, Normal, Verbose };

Verbosity verbosity();
void setVerbosity(Verbosity level);

// Removes --quiet (-q) and --verbose from argv[2...], shifting the rest down and lowering
// argc, and sets the verbosity (the last one given wins).
void takeVerbosityOptions(int& argc, char** argv);

// printf to standard error: note() unless --quiet, detail() with --verbose only.
void note(const char* format, ...) __attribute__((format(printf, 1, 2)));
void detail(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace gm::cli
