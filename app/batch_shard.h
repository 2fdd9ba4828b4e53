// --shard i/n: the i-th of n disjoint parts of a batch's image list, for n machines (or n
// processes) that share one manifest. Image k (counting from 0, in the list's order) belongs
// to shard k mod n: the parts are balanced, and the same list always splits the same way.
#pragma once

#include <string>

namespace gm {

struct Shard {
    int index = 0, count = 1;
    bool owns(size_t item) const { return static_cast<int>(item % static_cast<size_t>(count)) == index; }
};

// Parses "i/n" (0 <= i < n). Throws std::invalid_argument naming --shard otherwise.
Shard parseShard(const std::string& text);

}  // namespace gm
