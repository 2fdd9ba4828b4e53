// gradmesh-help-documents man|bash-completion: prints one of the documents of
// help_documents.h. Run by the build (app/CMakeLists.txt); not installed.
#include <cstdio>
#include <string>

#include "help_documents.h"

int main(int argc, char** argv) {
    const std::string what = argc == 2 ? argv[1] : "";
    std::string text;
    if (what == "man") text = gm::cli::manPage();
    else if (what == "bash-completion") text = gm::cli::bashCompletion();
    else {
        std::fputs("usage: gradmesh-help-documents man|bash-completion\n", stderr);
        return 2;
    }
    return std::fwrite(text.data(), 1, text.size(), stdout) == text.size() && std::fflush(stdout) == 0
               ? 0
               : 1;
}
