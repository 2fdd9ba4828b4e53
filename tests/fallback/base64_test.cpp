// The data: URI text of the fallback image: RFC 4648's test vectors, and every byte value.
#include <catch2/catch.hpp>

#include <string>

#include "formats/base64.h"

TEST_CASE("base64 gives RFC 4648's test vectors", "[fallback]") {
    CHECK(gm::base64Encode("") == "");
    CHECK(gm::base64Encode("f") == "Zg==");
    CHECK(gm::base64Encode("fo") == "Zm8=");
    CHECK(gm::base64Encode("foo") == "Zm9v");
    CHECK(gm::base64Encode("foob") == "Zm9vYg==");
    CHECK(gm::base64Encode("fooba") == "Zm9vYmE=");
    CHECK(gm::base64Encode("foobar") == "Zm9vYmFy");
}

TEST_CASE("base64 encodes bytes above 127 as unsigned", "[fallback]") {
    CHECK(gm::base64Encode(std::string("\xff\xfe\x80", 3)) == "//6A");
    CHECK(gm::base64Encode(std::string("\x00\xff", 2)) == "AP8=");
}
