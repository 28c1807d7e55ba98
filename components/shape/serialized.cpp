// serialized — a triangle mesh read from Mitsuba's compressed ".serialized" format.
//
// Parameters: filename (relative to the scene file), shape_index (which mesh of a file
// holding several, default 0), face_normals (ignore the stored vertex normals),
// flip_normals, to_world, nested bsdf and emitter — the parameters of Mitsuba 3's plugin.
//
// Format (versions 3 and 4, little endian): every mesh is a 4-byte header (uint16 magic
// 0x041C, uint16 version) followed by one zlib stream holding uint32 flags (0x1 normals,
// 0x2 uvs, 0x8 vertex colours, 0x2000 double precision), the NUL-terminated mesh name
// (version 4 only), uint64 vertex and triangle counts, then the arrays positions,
// normals, uvs, colours (3, 3, 2, 3 reals per vertex, those present) and 3 uint32
// indices per triangle. Meshes are concatenated; the file ends with a dictionary of
// their byte offsets (uint64 in version 4, uint32 in version 3) and a uint32 count.
// Only the requested mesh is read: shape_index > 0 seeks through the dictionary, and
// the stream is inflated straight into the arrays, so a large multi-mesh file costs
// the bytes of one mesh. Colours and the face-normal flag bit are skipped, as in
// Mitsuba 3. A mesh without normals is shaded with face normals (Mitsuba would compute
// smooth vertex normals; effigi's other meshes do not either).
// Reference: Mitsuba 3 documentation, "Serialized mesh loader (serialized)";
// P. Deutsch, J.-L. Gailly, "ZLIB Compressed Data Format Specification", RFC 1950, 1996.
#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <limits>

namespace effigi {
namespace {

// The format is little endian; reading it with memcpy assumes a little-endian host.
static_assert(std::endian::native == std::endian::little, "serialized reader assumes a little-endian host");

constexpr std::uint16_t SerializedMagic = 0x041C;
constexpr std::uint32_t HasNormals = 0x0001, HasTexcoords = 0x0002, HasColors = 0x0008,
                        DoublePrecision = 0x2000;

/// Inflates one mesh's zlib stream from the file, a buffer at a time.
class Inflater {
public:
    Inflater(std::ifstream& in, const std::string& file, std::int64_t index) : m_in(in), m_file(file), m_index(index) {
        std::memset(&m_z, 0, sizeof(m_z));
        if (inflateInit(&m_z) != Z_OK) fail("{}: cannot initialise zlib", m_file);
    }
    ~Inflater() { inflateEnd(&m_z); }
    Inflater(const Inflater&) = delete;
    Inflater& operator=(const Inflater&) = delete;

    /// Exactly n bytes of the decompressed stream into dst (null: discard them).
    void read(void* dst, std::size_t n) {
        unsigned char* out = static_cast<unsigned char*>(dst);
        while (n > 0) {
            std::size_t chunk = std::min<std::size_t>(n, out ? std::numeric_limits<uInt>::max() : m_scratch.size());
            m_z.next_out = out ? out : m_scratch.data();
            m_z.avail_out = uInt(chunk);
            while (m_z.avail_out > 0) {
                if (m_z.avail_in == 0) refill();
                int r = inflate(&m_z, Z_NO_FLUSH);
                if (r == Z_STREAM_END && m_z.avail_out > 0)
                    fail("{}: mesh {} is truncated (its compressed stream ends early)", m_file, m_index);
                if (r != Z_OK && r != Z_STREAM_END)
                    fail("{}: mesh {}: corrupt compressed data (zlib: {})", m_file, m_index,
                         m_z.msg ? m_z.msg : zError(r));
            }
            if (out) out += chunk;
            n -= chunk;
        }
    }
    template <typename T> T value() {
        T v;
        read(&v, sizeof(T));
        return v;
    }
    /// n reals (float or double in the file) as floats; null dst discards them.
    void reals(float* dst, std::size_t n, bool doublePrecision) {
        if (!doublePrecision) return read(dst, n * sizeof(float));
        double buf[1024];
        for (std::size_t done = 0; done < n;) {
            std::size_t k = std::min<std::size_t>(n - done, 1024);
            read(dst ? buf : nullptr, k * sizeof(double));
            if (dst)
                for (std::size_t i = 0; i < k; ++i) dst[done + i] = float(buf[i]);
            done += k;
        }
    }

private:
    void refill() {
        m_in.read(reinterpret_cast<char*>(m_buffer.data()), std::streamsize(m_buffer.size()));
        std::streamsize got = m_in.gcount();
        if (got <= 0) fail("{}: mesh {} is truncated (the file ends inside its compressed data)", m_file, m_index);
        m_z.next_in = m_buffer.data();
        m_z.avail_in = uInt(got);
    }

    std::ifstream& m_in;
    const std::string& m_file;
    std::int64_t m_index;
    z_stream m_z;
    std::vector<unsigned char> m_buffer = std::vector<unsigned char>(1 << 16);
    std::vector<unsigned char> m_scratch = std::vector<unsigned char>(1 << 16);
};

/// Reads `n` raw bytes at the current position or fails naming what was being read.
void rawRead(std::ifstream& in, void* dst, std::size_t n, const std::string& file, const char* what) {
    in.read(static_cast<char*>(dst), std::streamsize(n));
    if (std::size_t(in.gcount()) != n) fail("{}: file is truncated (while reading {})", file, what);
}

/// Checks the 4-byte header at the current position and returns the version.
std::uint16_t readHeader(std::ifstream& in, const std::string& file) {
    std::uint16_t h[2];
    rawRead(in, h, sizeof(h), file, "the header");
    if (h[0] != SerializedMagic)
        fail("{}: not a Mitsuba serialized mesh (magic number 0x{:04X}, expected 0x041C)", file, h[0]);
    if (h[1] != 3 && h[1] != 4) fail("{}: unsupported serialized format version {} (3 and 4 are read)", file, h[1]);
    return h[1];
}

/// Seeks to the start of mesh `index` through the end-of-file dictionary.
void seekToMesh(std::ifstream& in, const std::string& file, std::uint16_t version, std::int64_t index) {
    in.seekg(0, std::ios::end);
    const std::uint64_t size = std::uint64_t(in.tellg());
    const std::uint64_t entry = version == 4 ? 8 : 4;
    if (size < 8) fail("{}: file is truncated (no room for the mesh dictionary)", file);
    std::uint32_t count = 0;
    in.seekg(std::streamoff(size - 4));
    rawRead(in, &count, 4, file, "the mesh count");
    if (std::uint64_t(index) >= count)
        fail("{}: shape_index {} is out of range (the file holds {} mesh{})", file, index, count, count == 1 ? "" : "es");
    if (entry * count + 4 > size) fail("{}: corrupt mesh dictionary ({} meshes do not fit the file)", file, count);
    in.seekg(std::streamoff(size - 4 - entry * (count - std::uint64_t(index))));
    std::uint64_t offset = 0;
    rawRead(in, &offset, entry, file, "the mesh dictionary");
    if (offset + 4 > size - 4 - entry * count)
        fail("{}: corrupt mesh dictionary (mesh {} starts at byte {}, past the data)", file, index, offset);
    in.seekg(std::streamoff(offset));
    if (readHeader(in, file) != version) fail("{}: mesh {} has a different format version than the file", file, index);
}

TriangleMesh readSerialized(const std::string& file, std::int64_t index, bool skipNormals) {
    // A regular file only: the counts below are bounded by its size, and a device or FIFO
    // has none (reading /dev/zero would inflate forever).
    const std::uint64_t fileSize = regularFileSize(file, "serialized mesh file");
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("{}: cannot open serialized mesh file", file);
    std::uint16_t version = readHeader(in, file);
    if (index > 0) seekToMesh(in, file, version, index);

    Inflater z(in, file, index);
    std::uint32_t flags = z.value<std::uint32_t>();
    if (version == 4)  // the mesh name, NUL-terminated; not used
        for (std::size_t n = 0; z.value<char>() != 0; ++n)
            if (n > 65536) fail("{}: mesh {}: unterminated mesh name", file, index);
    std::uint64_t nv = z.value<std::uint64_t>(), nf = z.value<std::uint64_t>();
    const bool dp = flags & DoublePrecision;
    const std::uint64_t real = dp ? 8 : 4;
    std::uint64_t perVertex = 3 + (flags & HasNormals ? 3 : 0) + (flags & HasTexcoords ? 2 : 0) + (flags & HasColors ? 3 : 0);
    // Indices are 32 bit; and zlib cannot expand data more than ~1032:1, so counts that
    // need more bytes than that are corrupt (and must not drive a huge allocation).
    if (nv > 0xffffffffull || nf > 0xffffffffull / 3 ||
        (nv * perVertex * real + nf * 12) / 1032 > fileSize)
        fail("{}: mesh {}: implausible vertex/triangle counts {} / {} (corrupt file?)", file, index, nv, nf);

    TriangleMesh m;
    m.positions.resize(nv);
    z.reals(reinterpret_cast<float*>(m.positions.data()), 3 * nv, dp);
    if (flags & HasNormals) {
        if (!skipNormals) m.normals.resize(nv);
        z.reals(skipNormals ? nullptr : reinterpret_cast<float*>(m.normals.data()), 3 * nv, dp);
    }
    if (flags & HasTexcoords) {
        m.uvs.resize(nv);
        z.reals(reinterpret_cast<float*>(m.uvs.data()), 2 * nv, dp);
    }
    if (flags & HasColors) z.reals(nullptr, 3 * nv, dp);
    m.indices.resize(3 * nf);
    z.read(m.indices.data(), m.indices.size() * sizeof(std::uint32_t));
    return m;
}

class Serialized final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "serialized", "Triangle mesh from a Mitsuba .serialized file (zlib-compressed, multi-mesh).");
        s.cite("Mitsuba 3 documentation, Serialized mesh loader; RFC 1950 (zlib)");
        s.optional("filename", ParamType::String, "Serialized mesh file, relative to the scene file").isRequired();
        s.integer("shape_index", 0, "Which mesh of the file to load (0 = the first)").atLeast(0.0);
        addMeshParams(s);
        // effigi-conform: both meshes of a small file (a bare square; a prism with normals
        // and uvs, tests/data/shapes/make_serialized.py), the second also flipped.
        const std::string prism = "tests/data/shapes/prism.serialized";
        s.addConformance({"square", {{"filename", prism}}});
        s.addConformance({"prism", {{"filename", prism}, {"shape_index", std::int64_t(1)}}});
        s.addConformance({"prism flipped", {{"filename", prism}, {"shape_index", std::int64_t(1)}, {"flip_normals", true}}});
        return s;
    }

    explicit Serialized(const Properties& p) : MeshShape(p) {
        std::string file = p.getPath("filename").string();
        std::int64_t index = p.getInt("shape_index");
        if (index < 0) failAt(p.whereOf("shape_index"), "{}: parameter 'shape_index' must be >= 0, got {}", p.describe(), index);
        TriangleMesh mesh;
        try {
            mesh = readSerialized(file, index, m_faceNormals);
        } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        setMesh(std::move(mesh), fmt::format("{} (mesh {})", file, index));
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Serialized)
