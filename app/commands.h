// The commands of `gradmesh` (commands.cpp holds the one list, with their help).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace gm::cli {

struct Command {
    const char* name;
    const char* help;  // what `gradmesh <name> --help` prints
};

const std::vector<Command>& commands();

// What `gradmesh --help` and `gradmesh --version` print.
const char* mainHelp();
const char* versionText();

// The command called `name`, or nullptr.
const Command* findCommand(const std::string& name);

// What is answered without running a command: no command (the usage, exit 2), --help, -h,
// help, --version, an unknown command (exit 2) and `<command> ... --help`. The exit code, or
// nothing when argv[1] is a command to run.
std::optional<int> answerWithoutRunning(int argc, char** argv);

}  // namespace gm::cli
