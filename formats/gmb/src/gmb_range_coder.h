// Private to the .gmb reader and writer: the adaptive binary range coder of the coded node
// planes (encoding 2). Its arithmetic is specified in docs/formats.md ("Range
// coding"); encoder and decoder here are the two halves of that one definition.
#pragma once

#include <cstdint>
#include <string>

#include "gmb_pvt.h"

namespace gm::gmb {

// The probability that a binary decision is 1, in units of 2^-16, learnt from the decisions
// coded with it: the mean of a fast and a slow estimate, both fast while the model is young.
struct BitModel {
    uint16_t fast = 32768;
    uint16_t slow = 32768;
    uint8_t seen = 0;

    uint32_t probability() const {
        const uint32_t p = (uint32_t(fast) + uint32_t(slow)) >> 1;
        return p < 32 ? 32 : (p > 65504 ? 65504 : p);
    }
    void update(int bit) {
        int shiftFast = 4, shiftSlow = 7;
        if (seen < 30) {
            const int w = 1 + seen / 2;
            if (w < shiftFast) shiftFast = w;
            if (w < shiftSlow) shiftSlow = w;
            ++seen;
        }
        if (bit) {
            fast = static_cast<uint16_t>(fast + ((65536u - fast) >> shiftFast));
            slow = static_cast<uint16_t>(slow + ((65536u - slow) >> shiftSlow));
        } else {
            fast = static_cast<uint16_t>(fast - (fast >> shiftFast));
            slow = static_cast<uint16_t>(slow - (slow >> shiftSlow));
        }
    }
};

class RangeEncoder {
public:
    void encode(BitModel& m, int bit) {
        const uint32_t bound = (range_ >> 16) * m.probability();
        if (bit) {
            range_ = bound;
        } else {
            low_ += bound;
            range_ -= bound;
        }
        m.update(bit);
        normalize();
    }
    void direct(int bit) {
        range_ >>= 1;
        if (bit) low_ += range_;
        normalize();
    }
    // Flushes the state; the encoder is spent afterwards.
    std::string finish() {
        for (int k = 0; k < 5; ++k) shiftLow();
        return std::move(out_);
    }

private:
    void normalize() {
        while (range_ < (1u << 24)) {
            range_ <<= 8;
            shiftLow();
        }
    }
    // Bytes leave once no carry can reach them: a run of 0xff bytes waits in `pending_`.
    void shiftLow() {
        if (static_cast<uint32_t>(low_) < 0xff000000u || (low_ >> 32) != 0) {
            const auto carry = static_cast<uint8_t>(low_ >> 32);
            uint8_t byte = cache_;
            do {
                out_.push_back(static_cast<char>(static_cast<uint8_t>(byte + carry)));
                byte = 0xff;
            } while (--pending_ != 0);
            cache_ = static_cast<uint8_t>(low_ >> 24);
        }
        ++pending_;
        low_ = (low_ & 0x00ffffffu) << 8;
    }

    uint64_t low_ = 0;
    uint32_t range_ = 0xffffffffu;
    uint8_t cache_ = 0;
    uint64_t pending_ = 1;
    std::string out_;
};

// Reads the stream from `reader`, which fails (naming file, section and byte) if it ends early.
class RangeDecoder {
public:
    explicit RangeDecoder(ByteReader& reader) : r_(reader) {
        r_.need(5, "the start of the range-coded data");
        if (r_.u8() != 0) r_.fail("corrupt range-coded data (its first byte is not 0)");
        for (int k = 0; k < 4; ++k) code_ = (code_ << 8) | r_.u8();
    }
    int decode(BitModel& m) {
        const uint32_t bound = (range_ >> 16) * m.probability();
        int bit;
        if (code_ < bound) {
            range_ = bound;
            bit = 1;
        } else {
            code_ -= bound;
            range_ -= bound;
            bit = 0;
        }
        m.update(bit);
        normalize();
        return bit;
    }
    int direct() {
        range_ >>= 1;
        int bit = 0;
        if (code_ >= range_) {
            code_ -= range_;
            bit = 1;
        }
        normalize();
        return bit;
    }

private:
    void normalize() {
        while (range_ < (1u << 24)) {
            range_ <<= 8;
            code_ = (code_ << 8) | r_.u8();
        }
    }

    ByteReader& r_;
    uint32_t range_ = 0xffffffffu;
    uint32_t code_ = 0;
};

}  // namespace gm::gmb
