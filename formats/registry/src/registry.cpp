#include "formats/registry.h"

#include <algorithm>
#include <cctype>

#include "formats/atomic_file.h"
#include "formats/input_file.h"
#include "meshcore/error.h"

namespace gm {

Document MeshFormat::read(const std::string& path, const ReadOptions&) const {
    throw Error("the " + name() + " format cannot be read", path);
}

std::string MeshFormat::encode(const Document&, const std::string& path,
                               const WriteOptions&) const {
    throw Error("the " + name() + " format cannot be written", path);
}

void MeshFormat::write(const Document& doc, const std::string& path,
                       const WriteOptions& options) const {
    writeFileAtomically(path, encode(doc, path, options));
}

std::string lowerExtension(const std::string& path) {
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    return ext;
}

void FormatRegistry::add(std::unique_ptr<MeshFormat> format) {
    formats_.push_back(std::move(format));
}

const MeshFormat* FormatRegistry::byName(const std::string& name) const {
    for (const auto& f : formats_)
        if (f->name() == name) return f.get();
    return nullptr;
}

const MeshFormat* FormatRegistry::forPath(const std::string& path) const {
    const std::string ext = lowerExtension(path);
    if (ext.empty()) return nullptr;
    for (const auto& f : formats_) {
        const auto exts = f->extensions();
        if (std::find(exts.begin(), exts.end(), ext) != exts.end()) return f.get();
    }
    return nullptr;
}

const MeshFormat* FormatRegistry::forReading(const std::string& path) const {
    // Only a regular file is read: a FIFO or a device gives "" and is refused by its reader.
    const std::string head = readFileHead(path, 64);
    // A file whose content says what it is wins over a misleading extension.
    if (!head.empty())
        for (const auto& f : formats_)
            if (f->canRead() && f->sniff(head)) return f.get();
    return forPath(path);
}

const MeshFormat& FormatRegistry::writerFor(const std::string& path) const {
    const MeshFormat* format = forPath(path);
    if (format && format->canWrite()) return *format;
    std::string known;
    for (const auto& f : formats_)
        if (f->canWrite())
            for (const std::string& e : f->extensions()) known += (known.empty() ? "" : " ") + e;
    throw Error("cannot write '" + lowerExtension(path) + "' files (known: " + known + ")", path);
}

std::vector<const MeshFormat*> FormatRegistry::all() const {
    std::vector<const MeshFormat*> out;
    for (const auto& f : formats_) out.push_back(f.get());
    return out;
}

}  // namespace gm
