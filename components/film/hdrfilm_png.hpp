#pragma once
// 8-bit PNG files written with zlib alone, for hdrfilm's preview, `effigi convert`, the
// app's converge reports and the live preview page (effigi render --preview).
//
// Why not OpenImageIO: every render writes a PNG beside its EXR (hdrfilm's png = true),
// and OpenImageIO brings about 250 shared libraries, which cost ~0.2 s of start-up on
// every run. An 8-bit PNG is a few chunks around a zlib stream (W3C PNG specification,
// 2nd ed., https://www.w3.org/TR/png/), and zlib is loaded anyway (OpenEXR uses it).
// Header-only because components/<tag>/*.cpp each become a module.
//
// What is written: IHDR; sRGB, gAMA and cHRM (the values the specification recommends
// beside sRGB, for decoders that only know gAMA/cHRM); one tEXt chunk per metadata entry
// (iTXt when the value is not ASCII: tEXt is Latin-1); IDAT; IEND. Each row takes the
// filter with the smallest sum of absolute signed bytes (the heuristic the specification
// suggests); deflate level 6, as libpng's default.
#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/tonemap.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace effigi::hdrfilm_io {

namespace fs = std::filesystem;

[[noreturn]] inline void cannotWrite(const fs::path& path, std::string reason) {
    while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
    std::replace(reason.begin(), reason.end(), '\n', ' ');  // errors are one line
    fail("cannot write {}: {}", path.string(), reason.empty() ? "unknown error" : reason);
}

/// Fail early with a clear reason when the target directory is missing; everything
/// else (permissions, full disk) is reported by the writing library.
inline void checkDirectory(const fs::path& path) {
    fs::path dir = path.parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        cannotWrite(path, fmt::format("directory '{}' does not exist", dir.string()));
}

namespace png_detail {

/// A PNG keyword: 1-79 Latin-1 printable bytes, no leading, trailing or double spaces.
inline bool validKeyword(const std::string& k) {
    if (k.empty() || k.size() > 79 || k.front() == ' ' || k.back() == ' ' || k.find("  ") != std::string::npos)
        return false;
    return std::all_of(k.begin(), k.end(), [](char ch) {
        const auto c = static_cast<unsigned char>(ch);
        return (c >= 32 && c <= 126) || c >= 161;
    });
}

/// Paeth's predictor (PNG specification, 9.4): whichever of left, up, upper-left is
/// closest to left + up - upper-left.
inline int paeth(int a, int b, int c) {
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

/// Writes chunks to a file; remembers the first failure (errno) instead of throwing
/// mid-file, so the caller reports one error and removes the partial file.
class ChunkWriter {
public:
    explicit ChunkWriter(std::FILE* f) : m_file(f) {}
    void raw(const void* data, std::size_t n) {
        if (m_error == 0 && n > 0 && std::fwrite(data, 1, n, m_file) != n) m_error = errno ? errno : EIO;
    }
    void chunk(const char type[4], const std::uint8_t* data, std::size_t n) {
        std::uint8_t len[4];
        be32(len, std::uint32_t(n));
        raw(len, 4);
        raw(type, 4);
        raw(data, n);
        uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(type), 4);
        for (std::size_t done = 0; done < n;) {  // crc32 takes a uInt length
            const std::size_t step = std::min<std::size_t>(n - done, 1u << 30);
            crc = crc32(crc, data + done, uInt(step));
            done += step;
        }
        std::uint8_t c[4];
        be32(c, std::uint32_t(crc));
        raw(c, 4);
    }
    void chunk(const char type[4], const std::vector<std::uint8_t>& data) { chunk(type, data.data(), data.size()); }
    int error() const { return m_error; }

    static void be32(std::uint8_t* p, std::uint32_t v) {
        p[0] = std::uint8_t(v >> 24), p[1] = std::uint8_t(v >> 16), p[2] = std::uint8_t(v >> 8), p[3] = std::uint8_t(v);
    }
    static void append32(std::vector<std::uint8_t>& out, std::uint32_t v) {
        std::uint8_t b[4];
        be32(b, v);
        out.insert(out.end(), b, b + 4);
    }

private:
    std::FILE* m_file;
    int m_error = 0;
};

/// Filters `row` (above it `up`, zeros for the first row; `bpp` bytes per pixel) into
/// `out`, filter type byte first, choosing the filter of least absolute sum.
inline void filterRow(const std::uint8_t* row, const std::uint8_t* up, std::size_t rowBytes, std::size_t bpp,
                      std::vector<std::uint8_t>& out, std::vector<std::uint8_t>& trial) {
    std::uint64_t bestCost = ~std::uint64_t(0);
    trial.resize(rowBytes + 1);
    // One loop per filter type (the predictor inlined into it): rows are long, types few.
    const auto tryFilter = [&](std::uint8_t type, auto predict) {
        trial[0] = type;
        std::uint64_t cost = 0;
        for (std::size_t i = 0; i < rowBytes; ++i) {
            const int a = i >= bpp ? row[i - bpp] : 0, c = i >= bpp ? up[i - bpp] : 0;
            const auto v = std::uint8_t(row[i] - predict(a, int(up[i]), c));
            trial[i + 1] = v;
            cost += v < 128 ? v : 256u - v;
        }
        if (cost < bestCost) bestCost = cost, out.assign(trial.begin(), trial.end());
    };
    tryFilter(0, [](int, int, int) { return 0; });
    tryFilter(1, [](int a, int, int) { return a; });
    tryFilter(2, [](int, int b, int) { return b; });
    tryFilter(3, [](int a, int b, int) { return (a + b) / 2; });
    tryFilter(4, [](int a, int b, int c) { return paeth(a, b, c); });
}

/// No truncated PNG is left behind; a device or pipe written to is left alone.
inline void removePartial(const fs::path& path) {
    std::error_code ec;
    if (fs::is_regular_file(path, ec)) fs::remove(path, ec);
}

/// The PNG of `channels` interleaved 8-bit values per pixel (`bytes`, rows from the top)
/// into `f`: IHDR, sRGB, gAMA, cHRM, the text chunks `texts` (iTXt where `international`),
/// IDAT, IEND. Returns 0, or the errno of a failed write, or -1 when zlib failed.
inline int writeChunks(std::FILE* f, int width, int height, int channels, const std::vector<std::uint8_t>& bytes,
                       const std::vector<std::vector<std::uint8_t>>& texts, const std::vector<bool>& international) {
    std::vector<std::uint8_t> ihdr;
    ChunkWriter::append32(ihdr, std::uint32_t(width));
    ChunkWriter::append32(ihdr, std::uint32_t(height));
    static constexpr std::uint8_t ColourType[] = {0, 0, 4, 2, 6};  // by channel count
    ihdr.insert(ihdr.end(), {8, ColourType[channels], 0, 0, 0});   // depth 8, deflate, adaptive, no interlace
    std::vector<std::uint8_t> gama, chrm;
    ChunkWriter::append32(gama, 45455);  // 1/2.2 x 100000
    for (std::uint32_t v : {31270u, 32900u, 64000u, 33000u, 30000u, 60000u, 15000u, 6000u})
        ChunkWriter::append32(chrm, v);  // D65 white, then the Rec.709 primaries, x 100000

    ChunkWriter out(f);
    static constexpr std::uint8_t Signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    out.raw(Signature, 8);
    out.chunk("IHDR", ihdr);
    const std::uint8_t intent = 0;  // perceptual: the usual intent for photographs and renders
    out.chunk("sRGB", &intent, 1);
    out.chunk("gAMA", gama);
    out.chunk("cHRM", chrm);
    for (std::size_t i = 0; i < texts.size(); ++i) out.chunk(international[i] ? "iTXt" : "tEXt", texts[i]);

    // Rows are filtered and deflated one at a time; each full output buffer becomes an IDAT.
    z_stream z{};
    if (deflateInit(&z, 6) != Z_OK) return -1;
    const std::size_t rowBytes = std::size_t(width) * std::size_t(channels);
    const std::vector<std::uint8_t> zeros(rowBytes, 0);  // the row above the first
    std::vector<std::uint8_t> filtered, trial, idat(std::size_t(1) << 18);
    z.next_out = idat.data();
    z.avail_out = uInt(idat.size());
    int status = Z_OK;
    for (int y = 0; y <= height && status == Z_OK; ++y) {
        const bool last = y == height;
        if (!last) {
            const std::uint8_t* row = bytes.data() + std::size_t(y) * rowBytes;
            filterRow(row, y > 0 ? row - rowBytes : zeros.data(), rowBytes, std::size_t(channels), filtered, trial);
        }
        z.next_in = last ? nullptr : filtered.data();
        z.avail_in = last ? 0 : uInt(filtered.size());
        do {
            status = deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
            if (z.avail_out == 0) {
                out.chunk("IDAT", idat);
                z.next_out = idat.data();
                z.avail_out = uInt(idat.size());
            }
        } while (status == Z_OK && (z.avail_in > 0 || last));
    }
    if (status == Z_STREAM_END && z.avail_out < idat.size()) out.chunk("IDAT", idat.data(), idat.size() - z.avail_out);
    deflateEnd(&z);
    out.chunk("IEND", nullptr, 0);
    return status != Z_STREAM_END ? -1 : out.error();
}

inline bool validShape(int width, int height, int channels, const std::vector<std::uint8_t>& bytes) {
    return channels >= 1 && channels <= 4 && width > 0 && height > 0 &&
           bytes.size() == std::size_t(width) * std::size_t(height) * std::size_t(channels);
}

} // namespace png_detail

/// An 8-bit PNG of `channels` (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA) interleaved,
/// already sRGB-encoded bytes, rows from the top; metadata as text chunks (a key that is
/// no valid PNG keyword is skipped with a warning). Throws "cannot write <path>: ...".
inline void writePngBytes(const fs::path& path, int width, int height, int channels,
                          const std::vector<std::uint8_t>& bytes, const FilmMetadata& meta) {
    using namespace png_detail;
    checkDirectory(path);
    if (!validShape(width, height, channels, bytes))
        cannotWrite(path, fmt::format("no {}x{} image of {} channels in {} bytes", width, height, channels,
                                      bytes.size()));

    std::vector<std::vector<std::uint8_t>> texts;
    std::vector<bool> international;
    for (const auto& [key, value] : meta) {
        if (!validKeyword(key) || value.find('\0') != std::string::npos) {
            log::warn("{}: metadata key '{}' cannot be a PNG text chunk; skipped", path.string(), key);
            continue;
        }
        const bool ascii = std::all_of(value.begin(), value.end(), [](char c) { return (unsigned char)c < 128; });
        std::vector<std::uint8_t> t(key.begin(), key.end());
        t.push_back(0);
        if (!ascii) t.insert(t.end(), {0, 0, 0, 0});  // iTXt: uncompressed, no language, no translated key
        t.insert(t.end(), value.begin(), value.end());
        texts.push_back(std::move(t));
        international.push_back(!ascii);
    }

    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) cannotWrite(path, std::strerror(errno));
    const int error = writeChunks(f, width, height, channels, bytes, texts, international);
    const bool closed = std::fclose(f) == 0;
    if (error != 0 || !closed) {
        removePartial(path);
        cannotWrite(path, error < 0 ? "zlib failed to compress the image" : std::strerror(error ? error : errno));
    }
}

/// 8-bit sRGB values of 1 (grey) or 3 (linear sRGB) channels: scaled by 2^exposure, tone
/// mapped into [0, 1] (effigi/render/tonemap.hpp), sRGB-encoded.
inline std::vector<std::uint8_t> displayBytes(int channels, const std::vector<float>& linear, float exposure,
                                              ToneMap toneMap) {
    const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
    std::vector<std::uint8_t> bytes(linear.size());
    auto encode = [](float v) { return std::uint8_t(std::lround(std::clamp(srgbEncode(v), 0.f, 1.f) * 255.f)); };
    for (std::size_t i = 0; i + std::size_t(channels) <= linear.size(); i += std::size_t(channels)) {
        if (channels == 3) {
            Vector3f v = tonemap::apply(toneMap, Vector3f(linear[i], linear[i + 1], linear[i + 2]), exposure, luma);
            for (int c = 0; c < 3; ++c) bytes[i + std::size_t(c)] = encode(v[c]);
        } else {
            bytes[i] = encode(tonemap::applyGrey(toneMap, linear[i], exposure));
        }
    }
    return bytes;
}

/// The PNG writePngBytes() writes, without text chunks, in memory (the live preview's
/// images: effigi render --preview, apps/effigi/preview_server.cpp). Throws effigi::Error
/// when it cannot.
inline std::string encodePngBytes(int width, int height, int channels, const std::vector<std::uint8_t>& bytes) {
    using namespace png_detail;
    if (!validShape(width, height, channels, bytes))
        fail("cannot encode a PNG: no {}x{} image of {} channels in {} bytes", width, height, channels, bytes.size());
    char* data = nullptr;
    std::size_t size = 0;
    std::FILE* f = open_memstream(&data, &size);  // POSIX 2008: a FILE writing into a growing buffer
    if (!f) fail("cannot encode a PNG: {}", std::strerror(errno));
    const int error = writeChunks(f, width, height, channels, bytes, {}, {});
    const bool closed = std::fclose(f) == 0;  // sets data and size
    std::string png = error == 0 && closed ? std::string(data, size) : std::string();
    std::free(data);
    if (png.empty()) fail("cannot encode a PNG: {}", error < 0 ? "zlib failed" : std::strerror(error ? error : errno));
    return png;
}

} // namespace effigi::hdrfilm_io
