// Reader (and writer) for Mitsuba's .vol grid files; see vol_reader.hpp for the layout.
#include "effigi/render/vol_reader.hpp"

#include "effigi/core/input.hpp"

#include <bit>
#include <cmath>
#include <cstring>

namespace effigi {
namespace {

constexpr std::size_t HeaderBytes = 3 + 1 + 4 * 5 + 4 * 6;  // 48

/// Little-endian scalar at `pos` (the caller has checked the bounds).
template <typename T>
T load(std::string_view b, std::size_t pos) {
    static_assert(sizeof(T) == 4);
    std::uint32_t u = 0;
    for (int i = 3; i >= 0; --i) u = (u << 8) | std::uint8_t(b[pos + std::size_t(i)]);
    return std::bit_cast<T>(u);
}

template <typename T>
void store(std::string& out, T v) {
    std::uint32_t u = std::bit_cast<std::uint32_t>(v);
    for (int i = 0; i < 4; ++i) out.push_back(char((u >> (8 * i)) & 0xffu));
}

} // namespace

VolGrid readVolFromMemory(std::string_view b, const std::string& name) {
    if (b.size() < 4 || b.substr(0, 3) != "VOL")
        fail("{}: not a .vol grid file (the first bytes are not \"VOL\")", name);
    if (std::uint8_t(b[3]) != 3)
        fail("{}: unsupported .vol version {} (only version 3 is supported)", name, int(std::uint8_t(b[3])));
    if (b.size() < HeaderBytes) fail("{}: truncated .vol file: the 48-byte header is incomplete ({} bytes)", name, b.size());
    std::int32_t encoding = load<std::int32_t>(b, 4);
    if (encoding != 1)
        fail("{}: unsupported .vol encoding {} (only 1 = float32 is supported)", name, encoding);
    VolGrid g;
    std::uint64_t count = 1;
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        std::int32_t n = load<std::int32_t>(b, 8 + 4 * std::size_t(i));
        if (n <= 0) fail("{}: invalid .vol resolution: {} size is {}", name, axis[i], n);
        g.size[i] = std::uint32_t(n);
        // Checked before multiplying so that the product cannot overflow.
        if (count > (std::uint64_t(1) << 40) / std::uint64_t(n)) fail("{}: .vol grid resolution is implausibly large", name);
        count *= std::uint64_t(n);
    }
    std::int32_t ch = load<std::int32_t>(b, 20);
    if (ch <= 0 || ch > 1024) fail("{}: invalid .vol channel count {}", name, ch);
    g.channels = std::uint32_t(ch);
    Point3f lo, hi;
    for (int i = 0; i < 3; ++i) {
        lo[i] = load<float>(b, 24 + 4 * std::size_t(i));
        hi[i] = load<float>(b, 36 + 4 * std::size_t(i));
    }
    g.bbox = BBox3f(lo, hi);
    std::uint64_t values = count * g.channels;
    std::uint64_t have = (b.size() - HeaderBytes) / 4;
    if (have < values)
        fail("{}: truncated .vol file: {}x{}x{} grid with {} channel(s) needs {} values, the file holds {}", name,
             g.size[0], g.size[1], g.size[2], g.channels, values, have);
    g.data.resize(std::size_t(values));
    for (std::size_t i = 0; i < g.data.size(); ++i) {
        float v = load<float>(b, HeaderBytes + 4 * i);
        if (!std::isfinite(v)) {
            std::size_t p = i / g.channels;
            fail("{}: .vol value at grid point ({}, {}, {}) channel {} is not finite ({})", name, p % g.size[0],
                 (p / g.size[0]) % g.size[1], p / (std::size_t(g.size[0]) * g.size[1]), i % g.channels, v);
        }
        g.data[i] = v;
    }
    return g;
}

VolGrid readVol(const std::filesystem::path& path) {
    std::string bytes = readRegularFile(path, ".vol file");
    return readVolFromMemory(bytes, path.string());
}

std::string encodeVol(const VolGrid& g) {
    std::string out = "VOL";
    out.push_back(char(3));
    store<std::int32_t>(out, 1);
    for (int i = 0; i < 3; ++i) store<std::int32_t>(out, std::int32_t(g.size[i]));
    store<std::int32_t>(out, std::int32_t(g.channels));
    for (int i = 0; i < 3; ++i) store<float>(out, g.bbox.min[i]);
    for (int i = 0; i < 3; ++i) store<float>(out, g.bbox.max[i]);
    for (float v : g.data) store<float>(out, v);
    return out;
}

} // namespace effigi
