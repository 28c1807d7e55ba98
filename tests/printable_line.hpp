#pragma once
// The one-line property of error messages, checked by the reader tests
// (test_readers_robust) and by every fuzz target (fuzz/fuzz_common.hpp). Written
// independently of excerpt(), which it checks.
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace effigi::test {

/// True when `s` is well-formed UTF-8 holding no control character (C0, DEL, C1) and no
/// line or paragraph separator (U+2028/U+2029): what excerpt() promises a message may hold.
inline bool printableLine(std::string_view s) {
    for (std::size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            if (c < 0x20 || c == 0x7f) return false;
            ++i;
            continue;
        }
        const std::size_t n = c >= 0xf0 ? 4 : c >= 0xe0 ? 3 : 2;
        if (c < 0xc2 || c > 0xf4 || i + n > s.size()) return false;
        std::uint32_t cp = c & (n == 2 ? 0x1f : n == 3 ? 0x0f : 0x07);
        for (std::size_t k = 1; k < n; ++k) {
            const unsigned char b = static_cast<unsigned char>(s[i + k]);
            if ((b & 0xc0) != 0x80) return false;
            cp = cp << 6 | (b & 0x3f);
        }
        const std::uint32_t least = n == 2 ? 0x80 : n == 3 ? 0x800 : 0x10000;
        if (cp < least || cp > 0x10ffff || (cp >= 0xd800 && cp < 0xe000)) return false;  // overlong, surrogate
        if (cp < 0xa0 || cp == 0x2028 || cp == 0x2029) return false;                        // C1, separators
        i += n;
    }
    return true;
}

} // namespace effigi::test
