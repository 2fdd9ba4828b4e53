#include "output_format.h"

#include <algorithm>
#include <stdexcept>

#include "formats/registry.h"

namespace gm {

std::string writableExtension(const std::string& name) {
    std::string e = name;
    if (!e.empty() && e[0] == '.') e.erase(0, 1);
    if (e.empty() || e.find_first_of("/.") != std::string::npos) return "";
    const MeshFormat* f = FormatRegistry::builtin().forPath("x." + e);
    return f && f->canWrite() ? lowerExtension("x." + e) : "";
}

std::string writableFormatNames() {
    std::string names;
    for (const MeshFormat* f : FormatRegistry::builtin().all())
        if (f->canWrite())
            for (const std::string& e : f->extensions()) names += (names.empty() ? "" : ", ") + e.substr(1);
    return names;
}

std::vector<std::string> outputExtensions(const std::string& list) {
    std::vector<std::string> exts;
    size_t start = 0;
    while (start <= list.size()) {
        size_t end = list.find(',', start);
        if (end == std::string::npos) end = list.size();
        const std::string e = writableExtension(list.substr(start, end - start));
        if (e.empty())
            throw std::invalid_argument("--to expects formats to write (" + writableFormatNames() +
                                        "), got '" + list + "'");
        if (std::find(exts.begin(), exts.end(), e) == exts.end()) exts.push_back(e);
        start = end + 1;
    }
    return exts;
}

}  // namespace gm
