// The JSON that batch reads: one object per line (a manifest line, a log record), whose values
// are strings, numbers, booleans, null or arrays of those. Nested objects are refused.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace gm {

struct JsonValue {
    enum Kind { Null, Bool, Number, String, Array } kind = Null;
    std::string text;               // a string's value; a number's or boolean's spelling
    std::vector<std::string> items;  // an array's items, as text
};

// Parses one JSON object. Throws std::invalid_argument saying what is wrong and where.
std::map<std::string, JsonValue> parseJsonObjectLine(const std::string& line);

}  // namespace gm
