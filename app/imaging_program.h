// Finding and starting gradmesh-imaging, the program that runs the commands needing the image
// libraries (docs/design.md, "Start-up").
#pragma once

namespace gm::cli {

// Replaces this process with gradmesh-imaging, given the same arguments: it is looked for next
// to this program (the build tree) and then in the install's libexec folder relative to it.
// Returns only when it cannot be started, with a message on standard error and exit code 1.
int execImagingProgram(int argc, char** argv);

}  // namespace gm::cli
