// The documents made at build time from the help text of commands.cpp, so that they never
// drift from it: the man page gradmesh(1) and the bash completion script.
#pragma once

#include <string>
#include <vector>

namespace gm::cli {

// An option as a command's help lists it: "--name" (or "-o"), and whether a value follows.
struct HelpOption {
    std::string name;
    bool valued = false;
};

// The options of a help text: every -x / --name on its option lines (lines starting with
// "  -"), with a value when one space and a word follow the name.
std::vector<HelpOption> helpOptions(const std::string& help);

// gradmesh.1 in troff (man(7) macros).
std::string manPage();

// The bash completion script: commands, each command's options, and file names with the
// extensions each command and option reads or writes.
std::string bashCompletion();

}  // namespace gm::cli
