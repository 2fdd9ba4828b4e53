// gradmesh-imaging: every command of `gradmesh`, with the image libraries linked. The launcher
// (gradmesh_main.cpp) hands it the commands it does not run itself, with the same arguments.
#include "cli_common.h"
#include "commands.h"
#include "imaging_commands.h"
#include "verbosity.h"

int main(int argc, char** argv) {
    if (const std::optional<int> answered = gm::cli::answerWithoutRunning(argc, argv))
        return *answered;
    gm::cli::takeVerbosityOptions(argc, argv);
    gm::cli::prepareProcess();
    return gm::cli::runCommand(argv[1], argc, argv);
}
