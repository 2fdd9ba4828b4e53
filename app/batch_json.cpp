#include "batch_json.h"

#include <cctype>
#include <stdexcept>

namespace gm {

namespace {

class JsonLineParser {
public:
    explicit JsonLineParser(const std::string& s) : s_(s) {}

    std::map<std::string, JsonValue> object() {
        std::map<std::string, JsonValue> out;
        expect('{');
        if (peek() == '}') return ++pos_, finish(out);
        for (;;) {
            const std::string key = string();
            expect(':');
            out[key] = value();
            if (peek() == ',') {
                ++pos_;
                continue;
            }
            expect('}');
            return finish(out);
        }
    }

private:
    std::map<std::string, JsonValue> finish(std::map<std::string, JsonValue>& out) {
        if (peek() != '\0') fail("text after the object");
        return out;
    }

    [[noreturn]] void fail(const std::string& what) const {
        throw std::invalid_argument("bad JSON at column " + std::to_string(pos_ + 1) + ": " + what);
    }

    char peek() {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
        return pos_ < s_.size() ? s_[pos_] : '\0';
    }

    void expect(char c) {
        if (peek() != c) fail(std::string("expected '") + c + "'");
        ++pos_;
    }

    JsonValue value() {
        JsonValue v;
        const char c = peek();
        if (c == '"') {
            v.kind = JsonValue::String;
            v.text = string();
        } else if (c == '[') {
            v.kind = JsonValue::Array;
            ++pos_;
            if (peek() == ']') return ++pos_, v;
            for (;;) {
                JsonValue item = value();
                if (item.kind == JsonValue::Array) fail("nested array");
                v.items.push_back(item.text);
                if (peek() == ',') {
                    ++pos_;
                    continue;
                }
                expect(']');
                return v;
            }
        } else if (c == '{') {
            fail("nested object");
        } else {
            const size_t start = pos_;
            while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) ||
                                        s_[pos_] == '-' || s_[pos_] == '+' || s_[pos_] == '.'))
                ++pos_;
            v.text = s_.substr(start, pos_ - start);
            if (v.text == "null") v.kind = JsonValue::Null;
            else if (v.text == "true" || v.text == "false") v.kind = JsonValue::Bool;
            else if (!v.text.empty() && (std::isdigit(static_cast<unsigned char>(v.text[0])) || v.text[0] == '-'))
                v.kind = JsonValue::Number;
            else fail("expected a value");
        }
        return v;
    }

    std::string string() {
        expect('"');
        std::string out;
        while (pos_ < s_.size() && s_[pos_] != '"') {
            const char c = s_[pos_++];
            if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (pos_ >= s_.size()) break;
            const char e = s_[pos_++];
            switch (e) {
                case 'n': out += '\n'; break;
                case 't': out += '\t'; break;
                case 'r': out += '\r'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'u': out += codePoint(); break;
                case '"': case '\\': case '/': out += e; break;
                default: fail("bad escape");
            }
        }
        if (pos_ >= s_.size()) fail("unterminated string");
        ++pos_;
        return out;
    }

    // \uXXXX (and a surrogate pair) as UTF-8.
    std::string codePoint() {
        unsigned cp = hex4();
        if (cp >= 0xD800 && cp < 0xDC00 && s_.compare(pos_, 2, "\\u") == 0) {
            pos_ += 2;
            cp = 0x10000 + ((cp - 0xD800) << 10) + (hex4() - 0xDC00);
        }
        std::string out;
        if (cp < 0x80) out += static_cast<char>(cp);
        else if (cp < 0x800) out += {static_cast<char>(0xC0 | cp >> 6), static_cast<char>(0x80 | (cp & 0x3F))};
        else if (cp < 0x10000)
            out += {static_cast<char>(0xE0 | cp >> 12), static_cast<char>(0x80 | ((cp >> 6) & 0x3F)),
                    static_cast<char>(0x80 | (cp & 0x3F))};
        else
            out += {static_cast<char>(0xF0 | cp >> 18), static_cast<char>(0x80 | ((cp >> 12) & 0x3F)),
                    static_cast<char>(0x80 | ((cp >> 6) & 0x3F)), static_cast<char>(0x80 | (cp & 0x3F))};
        return out;
    }

    unsigned hex4() {
        if (pos_ + 4 > s_.size()) fail("short \\u escape");
        unsigned v = 0;
        for (int k = 0; k < 4; ++k) {
            const char c = s_[pos_++];
            if (!std::isxdigit(static_cast<unsigned char>(c))) fail("bad \\u escape");
            v = v * 16 + static_cast<unsigned>(std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : (std::tolower(c) - 'a' + 10));
        }
        return v;
    }

    const std::string& s_;
    size_t pos_ = 0;
};

}  // namespace

std::map<std::string, JsonValue> parseJsonObjectLine(const std::string& line) {
    return JsonLineParser(line).object();
}

}  // namespace gm
