#include "formats/private_dir.h"

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "formats/temp_registry.h"
#include "meshcore/error.h"

namespace gm {

PrivateDir::PrivateDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/gradmesh-XXXXXX";
    if (!::mkdtemp(pattern.data()))
        throw Error(std::string("cannot make a temporary directory: ") + std::strerror(errno),
                    pattern.substr(0, pattern.size() - 16));
    path_ = pattern;
    slot_ = registerTemporary(path_);
}

PrivateDir::~PrivateDir() {
    for (const auto& [file, slot] : files_) {
        ::unlink(file.c_str());
        unregisterTemporary(slot);
    }
    ::rmdir(path_.c_str());
    unregisterTemporary(slot_);
}

std::string PrivateDir::file(const std::string& name) {
    const std::string path = path_ + "/" + name;
    files_.emplace_back(path, registerTemporary(path));
    return path;
}

}  // namespace gm
