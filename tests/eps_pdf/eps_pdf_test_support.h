// Helpers shared by the EPS/PDF tests: decoding what the writers produce.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "meshcore/synthetic_meshes.h"

namespace epstest {

inline std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline std::string tmpPath(const std::string& name) {
    return std::string(GRADMESH_TMP) + "/" + name;
}

inline std::string inflateBytes(const std::string& in) {
    z_stream z{};
    if (inflateInit(&z) != Z_OK) throw std::runtime_error("inflateInit");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    z.avail_in = static_cast<uInt>(in.size());
    std::string out;
    char buf[65536];
    int rc;
    do {
        z.next_out = reinterpret_cast<Bytef*>(buf);
        z.avail_out = sizeof buf;
        rc = inflate(&z, Z_NO_FLUSH);
        if (rc != Z_OK && rc != Z_STREAM_END) {
            inflateEnd(&z);
            throw std::runtime_error("inflate failed");
        }
        out.append(buf, sizeof buf - z.avail_out);
    } while (rc != Z_STREAM_END);
    inflateEnd(&z);
    return out;
}

// Decodes ASCII85 up to the "~>" marker (whitespace ignored, `z` = four zero bytes).
inline std::string ascii85Decode(const std::string& text) {
    std::string out;
    uint64_t word = 0;
    int n = 0;
    for (size_t i = 0; i < text.size(); ++i) {
        const char ch = text[i];
        if (ch == '~') break;
        if (ch == ' ' || ch == '\n' || ch == '\r' || ch == '\t') continue;
        if (ch == 'z' && n == 0) {
            out.append(4, '\0');
            continue;
        }
        if (ch < '!' || ch > 'u') throw std::runtime_error("bad ASCII85 character");
        word = word * 85 + static_cast<uint64_t>(ch - '!');
        if (++n == 5) {
            for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>((word >> (8 * k)) & 0xff));
            word = 0;
            n = 0;
        }
    }
    if (n > 0) {
        const int bytes = n - 1;
        for (int k = n; k < 5; ++k) word = word * 85 + 84;
        for (int k = 0; k < bytes; ++k)
            out.push_back(static_cast<char>((word >> (8 * (3 - k))) & 0xff));
    }
    return out;
}

inline size_t countOccurrences(const std::string& hay, const std::string& needle) {
    size_t count = 0;
    for (size_t pos = hay.find(needle); pos != std::string::npos; pos = hay.find(needle, pos + 1))
        ++count;
    return count;
}

// The test meshes of the issue: ≥ 3 holes; strongly curved; ≥ 400 patches.
struct NamedDocument {
    std::string name;
    gm::Document doc;
};
inline std::vector<NamedDocument> externalTestDocuments() {
    std::vector<NamedDocument> docs;
    {
        gm::Document d;
        d.width = 300;
        d.height = 340;
        d.meshes.push_back(gm::makeHoledMesh(3, 20, 20, 260, 300, 4));
        docs.push_back({"holes3", d});
    }
    {
        gm::Document d;
        d.width = 320;
        d.height = 280;
        d.meshes.push_back(gm::makeCurvedMesh(5, 4, 30, 30, 260, 220, 1.0, 7));
        docs.push_back({"curved", d});
    }
    {
        gm::Document d;
        d.width = 460;
        d.height = 380;
        d.meshes.push_back(gm::makeCurvedMesh(24, 20, 20, 20, 420, 340, 0.6, 3));
        docs.push_back({"grid480", d});
    }
    return docs;
}

}  // namespace epstest
