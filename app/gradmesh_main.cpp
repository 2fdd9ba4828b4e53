// The `gradmesh` command, a launcher that starts without the image libraries (docs/design.md,
// "Start-up"): it answers --help, --version and `<command> --help`, and runs `info` on the
// mesh files its readers read (.gmb, SVG). Every other command, and `info` on anything else,
// runs in gradmesh-imaging (imaging_main.cpp), which has the image libraries linked and gives
// the same output, messages and exit codes for every command.
#include <optional>
#include <string>
#include <vector>

#include "cli_common.h"
#include "commands.h"
#include "formats/registry.h"
#include "imaging_program.h"
#include "info_command.h"
#include "verbosity.h"

namespace {

// `info` runs here when its one input is a file that the mesh readers read (by content or
// extension): builtin() would pick the same reader. Bad arguments and other inputs go on to
// gradmesh-imaging, which reports them.
bool infoRunsHere(int argc, char** argv, gm::cli::Args& args) {
    if (std::string(argv[1]) != "info") return false;
    try {
        args = gm::cli::parseArgs("info", argc, argv, {}, {});
    } catch (const gm::cli::UsageError&) {
        return false;
    }
    return args.positional.size() == 1 && args.positional[0] != "-" &&
           gm::FormatRegistry::meshReaders().forReading(args.positional[0]) != nullptr;
}

}  // namespace

int main(int argc, char** argv) {
    if (const std::optional<int> answered = gm::cli::answerWithoutRunning(argc, argv))
        return *answered;
    // gradmesh-imaging gets every argument; info here reads them without --quiet/--verbose.
    std::vector<char*> own(argv, argv + argc + 1);
    int ownCount = argc;
    gm::cli::takeVerbosityOptions(ownCount, own.data());
    gm::cli::Args args;
    if (infoRunsHere(ownCount, own.data(), args)) {
        gm::cli::prepareProcess();
        return gm::cli::runReportingErrors(
            "info", [&] { return gm::cli::infoCommand(args, gm::FormatRegistry::meshReaders()); });
    }
    return gm::cli::execImagingProgram(argc, argv);
}
