// Opening inputs: regular files only. A FIFO, a device (/dev/zero) or a directory is refused
// before anything reads from it, so that it can neither hang a run nor feed it without end.
#pragma once

#include <cstdint>
#include <string>

namespace gm {

// Throws gm::Error naming `path` unless it is an existing regular file (after symlinks).
void requireRegularFile(const std::string& path);

// Reads a whole regular file, refusing others and files over maxBytes before allocating.
std::string readWholeFile(const std::string& path, uint64_t maxBytes);

// Up to `bytes` first bytes of a regular file; "" when it cannot be read or is not regular.
std::string readFileHead(const std::string& path, size_t bytes);

}  // namespace gm
