// Bitmap loading through OpenImageIO. Built into the static library effigi_image, not
// libeffigi (see the header and src/CMakeLists.txt for why).
#include "effigi/render/bitmap.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>
#include <system_error>

namespace effigi {

namespace {

/// OpenImageIO's messages may span lines; an effigi error is one line.
std::string oneLine(std::string msg) {
    for (char& c : msg)
        if (c == '\n' || c == '\r') c = ' ';
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    return msg.empty() ? std::string("unknown error") : msg;
}

[[noreturn]] void cannotRead(const std::filesystem::path& file, const std::string& cause) {
    fail("{}: {}", excerpt(file.string(), 200), excerpt(oneLine(cause), 300));
}

bool lowerEquals(std::string a, const char* b) {
    std::transform(a.begin(), a.end(), a.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return a == b;
}

/// Whether the file's values are sRGB-encoded: what the reader reports in
/// oiio:ColorSpace, else integer data is taken as sRGB (8/16-bit images are display
/// encoded by convention, as Mitsuba assumes) and float data as linear.
bool isSrgb(const OIIO::ImageSpec& spec) {
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    if (!cs.empty()) {
        if (lowerEquals(cs, "srgb")) return true;
        if (lowerEquals(cs, "linear") || lowerEquals(cs, "lin_srgb") || lowerEquals(cs, "scene_linear") ||
            lowerEquals(cs, "gammacorrected1") || lowerEquals(cs, "gammacorrected1.0"))
            return false;
        // "GammaCorrected2.2" and other display encodings: treated as sRGB.
        if (cs.rfind("GammaCorrected", 0) == 0) return true;
    }
    OIIO::TypeDesc::BASETYPE b = OIIO::TypeDesc::BASETYPE(spec.format.basetype);
    return !(b == OIIO::TypeDesc::FLOAT || b == OIIO::TypeDesc::HALF || b == OIIO::TypeDesc::DOUBLE);
}

/// CRC-32 of PNG chunks (ISO 3309, as zlib's crc32).
std::uint32_t crc32(const unsigned char* data, std::size_t n, std::uint32_t crc = 0xffffffffu) {
    static const auto table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xff] ^ (crc >> 8);
    return crc;
}

/// A damaged PNG makes libpng print its own "libpng error: ..." line to stderr before
/// OpenImageIO reports it, so an effigi error would no longer be one line. The chunk
/// structure is checked first (lengths, CRCs, a closing IEND): truncated or altered
/// files are refused here with their cause, and libpng only sees intact streams.
void checkPng(const std::filesystem::path& file, const std::string& bytes) {
    static const char sig[8] = {'\x89', 'P', 'N', 'G', '\r', '\n', '\x1a', '\n'};
    if (bytes.size() < 8 || bytes.compare(0, 8, sig, 8) != 0) return;  // not a PNG: OIIO decides
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    std::size_t pos = 8;
    while (true) {
        if (bytes.size() - pos < 12) cannotRead(file, "truncated PNG file (it ends inside a chunk header)");
        std::uint32_t len = std::uint32_t(b[pos]) << 24 | std::uint32_t(b[pos + 1]) << 16 |
                            std::uint32_t(b[pos + 2]) << 8 | std::uint32_t(b[pos + 3]);
        if (len > bytes.size() - pos - 12) cannotRead(file, "truncated PNG file (a chunk runs past the end)");
        std::uint32_t stored = std::uint32_t(b[pos + 8 + len]) << 24 | std::uint32_t(b[pos + 9 + len]) << 16 |
                               std::uint32_t(b[pos + 10 + len]) << 8 | std::uint32_t(b[pos + 11 + len]);
        if ((crc32(b + pos + 4, len + 4) ^ 0xffffffffu) != stored)
            cannotRead(file, fmt::format("corrupt PNG file (checksum mismatch in chunk '{}')",
                                         excerpt(std::string_view(bytes.data() + pos + 4, 4))));
        if (bytes.compare(pos + 4, 4, "IEND") == 0) return;
        pos += 12 + len;
    }
}

/// OpenEXR allocates every header attribute at the size the file declares before reading
/// it (an attribute of unknown type: Imf::OpaqueAttribute), so a damaged 40-byte file can
/// make it allocate 2 GiB. The header is walked first (OpenEXR file layout: magic, version
/// and flags, then per header attributes "name\0 type\0 int32 size, value", a NUL ending
/// each header, and in a multi-part file one more NUL ending the list), and an attribute
/// that claims more bytes than the file has left is refused here.
void checkExr(const std::filesystem::path& file, const std::string& bytes) {
    static const char magic[4] = {'\x76', '\x2f', '\x31', '\x01'};
    if (bytes.size() < 8 || bytes.compare(0, 4, magic, 4) != 0) return;  // not OpenEXR: OIIO decides
    const bool multipart = (static_cast<unsigned char>(bytes[5]) & 0x10) != 0;  // version flag bit 12
    std::size_t pos = 8;
    // A NUL-terminated string at pos (name or type of an attribute), pos moved past it.
    auto cstring = [&](const char* what) {
        std::size_t end = bytes.find('\0', pos);
        if (end == std::string::npos)
            cannotRead(file, fmt::format("truncated OpenEXR file (its header ends inside an attribute {})", what));
        std::string_view s(bytes.data() + pos, end - pos);
        pos = end + 1;
        return s;
    };
    while (true) {
        for (std::string_view name = cstring("name"); !name.empty(); name = cstring("name")) {
            cstring("type");
            if (bytes.size() - pos < 4) cannotRead(file, "truncated OpenEXR file (its header ends inside an attribute)");
            const auto* b = reinterpret_cast<const unsigned char*>(bytes.data() + pos);
            const std::int32_t size = std::int32_t(std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 |
                                                   std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24);
            pos += 4;
            if (size < 0 || std::uint64_t(size) > bytes.size() - pos)
                cannotRead(file, fmt::format("corrupt OpenEXR header (attribute '{}' claims {} bytes, the file has {} "
                                             "left)", excerpt(name), size, bytes.size() - pos));
            pos += std::size_t(size);
        }
        if (!multipart) return;
        if (pos >= bytes.size()) cannotRead(file, "truncated OpenEXR file (it ends inside its headers)");
        if (bytes[pos] == '\0') return;  // the empty header that ends a multi-part file's list
    }
}

} // namespace

Bitmap::Bitmap(int width, int height, int channels, std::vector<float> pixels, bool srgb)
    : m_width(width), m_height(height), m_channels(channels), m_srgb(srgb), m_pixels(std::move(pixels)) {
    if (width < 0 || height < 0 || channels < 0 ||
        m_pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels))
        fail("bitmap: {} values given for {}x{} pixels of {} channels", m_pixels.size(), width, height, channels);
    if (channels == 4) m_alpha = 3;
    if (channels == 2) m_alpha = 1;
}

Bitmap Bitmap::load(const std::filesystem::path& file) {
    // A regular file only: the checks and the image readers read to the end (/dev/zero has
    // none), and opening a FIFO would wait for a writer.
    std::uint64_t fileBytes = 0;
    {
        const std::string bytes = readRegularFile(file, "image");
        checkPng(file, bytes);
        checkExr(file, bytes);
        fileBytes = bytes.size();
    }
    auto in = OIIO::ImageInput::open(file.string());
    if (!in) cannotRead(file, OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
        in->close();
        cannotRead(file, "the image has no pixels");
    }
    if (spec.deep) {
        in->close();
        cannotRead(file, "deep images are not supported");
    }
    if (spec.depth > 1) {  // read_image would read every slice into a buffer sized for one
        in->close();
        cannotRead(file, fmt::format("volume images ({} slices) are not supported", spec.depth));
    }
    // A corrupt header may claim any size: refuse more than 2^31 values (8 GiB of floats)
    // rather than fail inside the allocator, and more than the file could hold: deflate,
    // the strongest of the EXR and PNG codecs, expands a byte to at most 1032, so 16384
    // values per byte (a floor of 2^24 values for tiny files) leaves every real image
    // alone while a 600-byte file claiming 10^9 pixels is refused at once instead of
    // decoded for minutes (fuzz finding, tests/data/regressions/image/).
    const std::uint64_t count = std::uint64_t(spec.width) * std::uint64_t(spec.height) * std::uint64_t(spec.nchannels);
    const std::uint64_t plausible = std::max<std::uint64_t>(std::uint64_t(1) << 24, fileBytes * 16384);
    if (count > (std::uint64_t(1) << 31) || count > plausible) {
        in->close();
        cannotRead(file, fmt::format("image of {}x{}x{} values is too large{}", spec.width, spec.height,
                                     spec.nchannels,
                                     count > plausible ? fmt::format(" for a file of {} bytes", fileBytes) : ""));
    }
    Bitmap bmp;
    bmp.m_width = spec.width;
    bmp.m_height = spec.height;
    bmp.m_channels = spec.nchannels;
    bmp.m_srgb = isSrgb(spec);
    bmp.m_filename = file.string();
    bmp.m_alpha = spec.alpha_channel;
    if (bmp.m_alpha < 0 && (spec.nchannels == 4 || spec.nchannels == 2)) bmp.m_alpha = spec.nchannels - 1;
    if (bmp.m_alpha >= spec.nchannels) bmp.m_alpha = -1;
    bmp.m_pixels.resize(count);
    bool ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, bmp.m_pixels.data());
    // Some readers note trouble (a truncated stream) but still return true: any pending
    // error counts as failure, so a damaged file never yields a half-read texture.
    std::string err = in->geterror();
    if (!ok || !err.empty()) {
        in->close();
        cannotRead(file, err.empty() ? std::string("cannot read the pixel data (truncated or corrupt)") : err);
    }
    in->close();
    for (float& v : bmp.m_pixels)
        if (!std::isfinite(v)) v = 0.f;  // NaN/Inf texels would poison every estimate that reads them
    return bmp;
}

float Bitmap::srgbToLinear(float v) {
    return std::copysign(srgbDecode(std::abs(v)), v);
}

void Bitmap::convertToLinear() {
    if (!m_srgb) return;
    const std::size_t n = m_pixels.size();
    for (std::size_t i = 0; i < n; ++i)
        if (int(i % std::size_t(m_channels)) != m_alpha) m_pixels[i] = srgbToLinear(m_pixels[i]);
    m_srgb = false;
}

} // namespace effigi
