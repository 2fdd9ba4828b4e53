// Input text repeated in a message cannot drive the terminal: control characters are escaped.
#include <catch2/catch.hpp>

#include "meshcore/printable_text.h"

TEST_CASE("control characters are escaped, printable text is kept", "[output_safety]") {
    using gm::printableText;
    CHECK(printableText("plain name.svg") == "plain name.svg");
    CHECK(printableText("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x99\x82") ==
          "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x99\x82");  // UTF-8 stays as it is
    CHECK(printableText("\x1b]0;title\x07\x1b[2J") == "\\x1b]0;title\\x07\\x1b[2J");
    CHECK(printableText("a\rb\nc\td\x7f") == "a\\x0db\\x0ac\\x09d\\x7f");
    CHECK(printableText("\xC2\x9B" "31m") == "\\u009b31m");  // C1 CSI as UTF-8
    CHECK(printableText("\x9B" "31m") == "\\x9b31m");         // a lone byte, not UTF-8
    CHECK(printableText("\xC3") == "\\xc3");                  // a cut sequence
    CHECK(printableText("\xED\xA0\x80") == "\\xed\\xa0\\x80");  // a surrogate
}
