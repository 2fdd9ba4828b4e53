// Every command of `gradmesh`, run in the program gradmesh-imaging (imaging_commands.cpp).
#pragma once

#include <string>

namespace gm::cli {

// Runs `command` (argv[1]) with its arguments argv[2...]; errors become a message on standard
// error and the exit code (cli_common.h).
int runCommand(const std::string& command, int argc, char** argv);

}  // namespace gm::cli
