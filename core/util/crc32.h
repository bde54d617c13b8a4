#pragma once
/// CRC-32 as zlib, PNG and Python's zlib.crc32 compute it (reflected polynomial
/// 0xEDB88320, initial value and final xor 0xFFFFFFFF), so that a script can name
/// a mesh file by the same checksum accelviz computes (core/exchange/structure_file.h).

#include <array>
#include <cstddef>
#include <cstdint>

namespace accelviz {

class Crc32 {
public:
    void add(const void* data, size_t size) {
        static const std::array<uint32_t, 256> table = make_table();
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < size; ++i) state_ = table[(state_ ^ p[i]) & 0xFFu] ^ (state_ >> 8);
    }
    uint32_t value() const { return state_ ^ 0xFFFFFFFFu; }

private:
    static std::array<uint32_t, 256> make_table() {
        std::array<uint32_t, 256> t{};
        for (uint32_t i = 0; i < 256; ++i) {
            uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }
    uint32_t state_ = 0xFFFFFFFFu;
};

}  // namespace accelviz
