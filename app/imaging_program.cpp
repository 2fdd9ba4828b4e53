#include "imaging_program.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "meshcore/printable_text.h"

// GRADMESH_IMAGING_PROGRAM (the file name) and GRADMESH_IMAGING_FROM_BINDIR (the install's
// libexec folder relative to its bin folder) come from app/CMakeLists.txt.

namespace gm::cli {

namespace {

// The folder of this program's executable ("" when the system does not say).
std::string executableFolder() {
    std::vector<char> path(4096);
    const ssize_t n = readlink("/proc/self/exe", path.data(), path.size() - 1);
    if (n <= 0) return "";
    const std::string exe(path.data(), static_cast<size_t>(n));
    const size_t slash = exe.rfind('/');
    return slash == std::string::npos ? "" : exe.substr(0, slash);
}

}  // namespace

int execImagingProgram(int argc, char** argv) {
    const std::string folder = executableFolder();
    const std::vector<std::string> candidates = {
        folder + "/" GRADMESH_IMAGING_PROGRAM,
        folder + "/" GRADMESH_IMAGING_FROM_BINDIR "/" GRADMESH_IMAGING_PROGRAM};
    std::vector<char*> args(argv, argv + argc);
    args.push_back(nullptr);
    int error = ENOENT;
    for (const std::string& program : candidates) {
        execv(program.c_str(), args.data());
        if (errno != ENOENT) error = errno;  // there but not runnable: worth naming
    }
    std::fprintf(stderr,
                 "gradmesh %s: cannot start %s, the program that runs it (%s; looked in %s and "
                 "%s): reinstall gradmesh\n",
                 printableText(argv[1]).c_str(), GRADMESH_IMAGING_PROGRAM, std::strerror(error),
                 printableText(folder).c_str(),
                 printableText(folder + "/" GRADMESH_IMAGING_FROM_BINDIR).c_str());
    return 1;
}

}  // namespace gm::cli
