// Checkpoint files: serialisation, the atomic write (temporary file, fsync, rename, fsync
// of the directory: POSIX rename(2) replaces the name atomically) and the checked read.
#include "effigi/render/checkpoint.hpp"

#include "effigi/core/error.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <iterator>
#include <span>

namespace effigi {

namespace {

constexpr char Magic[8] = {'E', 'F', 'F', 'I', 'G', 'I', 'C', 'K'};
constexpr std::uint32_t FormatVersion = 1;
constexpr std::size_t HeaderBytes = 8 + 4 + 4 + 8 + 8;

/// FNV-1a taken over 64-bit words (then the tail bytes): one multiply per 8 bytes keeps a
/// 100 MB film's checksum well under a second.
std::uint64_t checksum(std::string_view bytes) {
    std::uint64_t h = 1469598103934665603ull;
    std::size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
        std::uint64_t w;
        std::memcpy(&w, bytes.data() + i, 8);
        h = (h ^ w) * 1099511628211ull;
    }
    for (; i < bytes.size(); ++i) h = (h ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
    return h;
}

class Writer {
public:
    template <typename T> void put(T v) { m_out.append(reinterpret_cast<const char*>(&v), sizeof(T)); }
    void put(const std::string& s) {
        put<std::uint64_t>(s.size());
        m_out += s;
    }
    template <typename T> void put(const std::vector<T>& v) {
        put<std::uint64_t>(v.size());
        m_out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
    void put(const AccumulatorSums& s) { put(s.layout), put(s.floats), put(s.doubles); }
    std::string& bytes() { return m_out; }

private:
    std::string m_out;
};

class Reader {
public:
    Reader(std::string_view bytes, const std::filesystem::path& file) : m_in(bytes), m_file(file) {}
    template <typename T> T get() {
        T v;
        std::memcpy(&v, take(sizeof(T)), sizeof(T));
        return v;
    }
    void get(std::string& s) {
        const std::uint64_t n = get<std::uint64_t>();
        s.assign(take(n), n);
    }
    template <typename T> void get(std::vector<T>& v) {
        const std::uint64_t n = get<std::uint64_t>();
        if (n > m_in.size() / sizeof(T)) bad("an array longer than the file");
        v.resize(n);
        const char* bytes = take(n * sizeof(T));
        if (n != 0) std::memcpy(v.data(), bytes, n * sizeof(T));  // an empty vector's data() may be null
    }
    void get(AccumulatorSums& s) { get(s.layout), get(s.floats), get(s.doubles); }
    bool done() const { return m_in.empty(); }
    [[noreturn]] void bad(const char* what) const {
        fail("{}: not a valid effigi checkpoint ({})", m_file.string(), what);
    }

private:
    const char* take(std::uint64_t n) {
        if (n > m_in.size()) bad("its fields run past its end");
        const char* p = m_in.data();
        m_in.remove_prefix(n);
        return p;
    }
    std::string_view m_in;
    const std::filesystem::path& m_file;
};

[[noreturn]] void writeFailed(const std::filesystem::path& file, const char* step) {
    fail("cannot write checkpoint {}: {} failed: {}", file.string(), step, std::strerror(errno));
}

/// Write everything to fd, retrying short writes and EINTR.
void writeAll(int fd, std::string_view bytes, const std::filesystem::path& file) {
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) writeFailed(file, "write");
        bytes.remove_prefix(std::size_t(n));
    }
}

} // namespace

std::uint64_t checkpointIdentity(const std::filesystem::path& scene, const std::map<std::string, std::string>& defines,
                                 std::uint64_t seed) {
    std::ifstream in(scene, std::ios::binary);
    if (!in) fail("cannot read scene {}", scene.string());
    std::ostringstream file;
    file << in.rdbuf();
    // Not text.append(istreambuf_iterator ...): GCC 12 warns falsely (-Warray-bounds) there.
    std::string text = "effigi checkpoint identity\n" + file.str();
    for (const auto& [k, v] : defines) text += fmt::format("\n-D {}={}", k, v);  // a std::map: sorted
    text += fmt::format("\n--seed {}", seed);
    return fnv1a(text);
}

std::filesystem::path checkpointFile(const std::filesystem::path& dir) { return dir / "checkpoint.effigi"; }

std::uint64_t writeCheckpoint(const std::filesystem::path& dir, const Checkpoint& c) {
    const std::filesystem::path file = checkpointFile(dir);
    Writer w;
    w.put(c.identity), w.put(c.scene);
    w.put(c.spp), w.put(c.timeBudget), w.put(c.targetRelMSE);
    w.put(c.report.spp), w.put(c.report.seconds), w.put(c.report.stats.samples), w.put(c.report.stats.rejectedSamples);
    w.put(c.processSpp);
    w.put(c.film), w.put(c.renderer);
    const std::string& payload = w.bytes();
    const std::string header = checkpointHeader(payload);  // written apart: a film's payload can be large

    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) fail("cannot write checkpoint {}: cannot create the directory: {}", file.string(), ec.message());
    const std::filesystem::path tmp = dir / fmt::format(".checkpoint.effigi.{}.tmp", ::getpid());
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) writeFailed(tmp, "open");
    try {
        writeAll(fd, header, tmp);
        writeAll(fd, payload, tmp);
        if (::fsync(fd) != 0) writeFailed(tmp, "fsync");
    } catch (...) {
        ::close(fd);
        ::unlink(tmp.c_str());
        throw;
    }
    if (::close(fd) != 0) writeFailed(tmp, "close");
    if (::rename(tmp.c_str(), file.c_str()) != 0) {
        const int err = errno;
        ::unlink(tmp.c_str());
        errno = err;
        writeFailed(file, "rename");
    }
    // The rename itself reaches the disk with the directory.
    const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) ::fsync(dfd), ::close(dfd);
    return header.size() + payload.size();
}

std::string checkpointHeader(std::string_view payload) {
    std::string header(Magic, sizeof Magic);
    auto append = [&](auto v) { header.append(reinterpret_cast<const char*>(&v), sizeof v); };
    append(FormatVersion), append(std::uint32_t(0)), append(std::uint64_t(payload.size())), append(checksum(payload));
    return header;
}

Checkpoint readCheckpoint(const std::filesystem::path& dir) {
    const std::filesystem::path file = checkpointFile(dir);
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("cannot resume from {}: no checkpoint there ({} cannot be read)", dir.string(), file.string());
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Reader header(bytes, file);
    if (bytes.size() < HeaderBytes || std::memcmp(bytes.data(), Magic, sizeof Magic) != 0)
        header.bad("no checkpoint header");
    std::uint64_t size, sum;
    std::uint32_t version;
    std::memcpy(&version, bytes.data() + 8, 4);
    std::memcpy(&size, bytes.data() + 16, 8);
    std::memcpy(&sum, bytes.data() + 24, 8);
    if (version != FormatVersion)
        fail("{}: checkpoint format version {}, this effigi reads version {}", file.string(), version, FormatVersion);
    if (bytes.size() - HeaderBytes != size)
        fail("{}: checkpoint of {} bytes, its header says {}: truncated or damaged", file.string(), bytes.size(),
             HeaderBytes + size);
    const std::string_view payload = std::string_view(bytes).substr(HeaderBytes);
    if (checksum(payload) != sum) fail("{}: checkpoint checksum mismatch: the file is damaged", file.string());

    Reader r(payload, file);
    Checkpoint c;
    c.identity = r.get<std::uint64_t>();
    r.get(c.scene);
    c.spp = r.get<std::uint64_t>();
    c.timeBudget = r.get<double>(), c.targetRelMSE = r.get<double>();
    c.report.spp = r.get<std::uint64_t>();
    c.report.seconds = r.get<double>();
    c.report.stats.samples = r.get<std::uint64_t>(), c.report.stats.rejectedSamples = r.get<std::uint64_t>();
    c.report.stats.seconds = c.report.seconds;
    r.get(c.processSpp);
    r.get(c.film), r.get(c.renderer);
    if (!r.done()) r.bad("bytes after its last field");
    // A render writes finite, non-negative times and finite sums: anything else was made
    // by hand (the checksum passed), and would reach the progress and the image.
    for (double v : {c.timeBudget, c.targetRelMSE, c.report.seconds})
        if (!(v >= 0.0 && std::isfinite(v))) r.bad("a time or budget that is negative or not finite");
    for (const AccumulatorSums* s : {&c.film, &c.renderer}) {
        for (float v : s->floats)
            if (!std::isfinite(v)) r.bad("a sum that is not finite");
        for (double v : s->doubles)
            if (!std::isfinite(v)) r.bad("a sum that is not finite");
    }
    return c;
}

} // namespace effigi
