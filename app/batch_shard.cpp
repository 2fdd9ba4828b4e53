#include "batch_shard.h"

#include <cstdlib>
#include <stdexcept>

namespace gm {

namespace {

bool parseCount(const std::string& text, long& value) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 9)
        return false;
    value = std::strtol(text.c_str(), nullptr, 10);
    return true;
}

}  // namespace

Shard parseShard(const std::string& text) {
    const size_t slash = text.find('/');
    long i = 0, n = 0;
    if (slash == std::string::npos || !parseCount(text.substr(0, slash), i) ||
        !parseCount(text.substr(slash + 1), n) || n < 1 || i >= n)
        throw std::invalid_argument("--shard expects i/n with 0 <= i < n (the shards of n are 0/n to " +
                                    std::string("n-1/n), got '") + text + "'");
    return {static_cast<int>(i), static_cast<int>(n)};
}

}  // namespace gm
