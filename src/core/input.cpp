// Untrusted input (see input.hpp): quoting it in messages, and opening only regular files.
#include "effigi/core/input.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace effigi {

namespace {

/// Length of the well-formed UTF-8 sequence at the start of `s` and its code point, or 0
/// when it is not one (overlong forms, surrogates and code points past U+10FFFF are
/// ill-formed: the Unicode Standard, table 3-7).
std::size_t utf8Sequence(std::string_view s, std::uint32_t& cp) {
    auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(0);
    std::size_t n = 0;
    unsigned char lo = 0x80, hi = 0xbf;  // the range of the second byte
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        if (c == 0xe0) lo = 0xa0;  // overlong below
        if (c == 0xed) hi = 0x9f;  // surrogates above
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        if (c == 0xf0) lo = 0x90;  // overlong below
        if (c == 0xf4) hi = 0x8f;  // past U+10FFFF above
    } else {
        return 0;
    }
    if (s.size() < n || byte(1) < lo || byte(1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if (byte(k) < 0x80 || byte(k) > 0xbf) return 0;
    cp = c & (n == 2 ? 0x1fu : n == 3 ? 0x0fu : 0x07u);
    for (std::size_t k = 1; k < n; ++k) cp = cp << 6 | (byte(k) & 0x3fu);
    return n;
}

/// Paths are quoted escaped too (a file name may hold a newline), but cut much later
/// than file content: the end of a path is what tells files apart.
constexpr std::size_t kPathChars = 200;

const char* kindOf(mode_t m) {
    if (S_ISDIR(m)) return "a directory";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISFIFO(m)) return "a FIFO (named pipe)";
    if (S_ISSOCK(m)) return "a socket";
    return "a special file";
}

[[noreturn]] void refuse(const std::filesystem::path& path, std::string_view what, const SourceLocation& where,
                         const std::string& why) {
    failAt(where, "{}: cannot read {}: {}", excerpt(path.string(), kPathChars), what, why);
}

std::string systemReason(int err) { return err == ENOENT ? "no such file" : std::string(std::strerror(err)); }

void requireRegular(const struct stat& st, const std::filesystem::path& path, std::string_view what,
                    const SourceLocation& where) {
    if (!S_ISREG(st.st_mode))
        refuse(path, what, where, fmt::format("it is {}, not a regular file", kindOf(st.st_mode)));
}

} // namespace

std::string excerpt(std::string_view text, std::size_t maxChars) {
    std::string out;
    std::size_t chars = 0;
    for (std::size_t i = 0; i < text.size(); ++chars) {
        if (chars == maxChars) {
            out += "\u2026";
            break;
        }
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const char* named = c == '\\' ? "\\\\" : c == '\n' ? "\\n" : c == '\r' ? "\\r" : c == '\t' ? "\\t" : nullptr;
        if (named) {
            out += named;
            ++i;
            continue;
        }
        if (c >= 0x20 && c < 0x7f) {
            out += char(c);
            ++i;
            continue;
        }
        std::uint32_t cp = 0;
        std::size_t n = c >= 0x80 ? utf8Sequence(text.substr(i), cp) : 0;
        // C1 controls and the Unicode line separators would break a line as well.
        bool control = (cp >= 0x80 && cp < 0xa0) || cp == 0x2028 || cp == 0x2029;
        if (n > 0 && !control) {
            out.append(text.substr(i, n));
            i += n;
            continue;
        }
        for (std::size_t k = 0; k < std::max<std::size_t>(n, 1); ++k)
            out += fmt::format("\\x{:02X}", static_cast<unsigned char>(text[i + k]));
        i += std::max<std::size_t>(n, 1);
    }
    return out;
}

std::uint64_t regularFileSize(const std::filesystem::path& path, std::string_view what, const SourceLocation& where) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) refuse(path, what, where, systemReason(errno));
    requireRegular(st, path, what, where);
    return std::uint64_t(st.st_size);
}

std::string readRegularFile(const std::filesystem::path& path, std::string_view what, const SourceLocation& where) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer; it does
    // nothing to a regular file.
    int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) refuse(path, what, where, systemReason(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st;
    if (::fstat(fd, &st) != 0) refuse(path, what, where, systemReason(errno));
    requireRegular(st, path, what, where);
    std::string data(std::size_t(st.st_size), '\0');
    std::size_t got = 0;
    while (got < data.size()) {
        ssize_t n = ::read(fd, data.data() + got, data.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0)
            failAt(where, "{}: error while reading the {}: {}", excerpt(path.string(), kPathChars), what,
                   std::strerror(errno));
        if (n == 0) break;  // the file shrank since it was opened
        got += std::size_t(n);
    }
    data.resize(got);
    return data;
}

} // namespace effigi
