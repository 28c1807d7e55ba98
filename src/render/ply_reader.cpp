// Stanford PLY reader (Turk 1994). The header declares elements, each a count of
// records made of typed scalar or list properties; the body stores them in order,
// either as whitespace-separated ascii or packed binary of either byte order. We keep
// vertex positions, normals and uvs and the faces' index lists, and step over the rest.
#include "effigi/render/ply_reader.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace effigi {
namespace {

enum class Type { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };
enum class Format { Ascii, BinaryLE, BinaryBE };

bool parseType(std::string_view s, Type& t) {
    struct Name { const char* name; Type type; };
    static const Name names[] = {
        {"char", Type::I8},    {"int8", Type::I8},     {"uchar", Type::U8},     {"uint8", Type::U8},
        {"short", Type::I16},  {"int16", Type::I16},   {"ushort", Type::U16},   {"uint16", Type::U16},
        {"int", Type::I32},    {"int32", Type::I32},   {"uint", Type::U32},     {"uint32", Type::U32},
        {"int64", Type::I64},  {"uint64", Type::U64},  {"float", Type::F32},    {"float32", Type::F32},
        {"double", Type::F64}, {"float64", Type::F64},
    };
    for (const Name& n : names)
        if (s == n.name) return (t = n.type, true);
    return false;
}

std::size_t typeSize(Type t) {
    switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    default: return 8;
    }
}

struct Property {
    std::string name;
    Type type = Type::F32;
    bool list = false;
    Type countType = Type::U8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> props;
    int line = 0;  // header line declaring it
};

/// Header words split on blanks.
std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> w;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
        if (j > i) w.push_back(line.substr(i, j - i));
        i = j;
    }
    return w;
}

/// A token fit for a one-line message: printable, short.
std::string printable(std::string_view s) {
    std::string r;
    for (char c : s.substr(0, 24)) r += (c >= 0x20 && c < 0x7f) ? c : '?';
    if (s.size() > 24) r += "...";
    return r;
}

class PlyParser {
public:
    PlyParser(std::string_view data, std::string name) : m_data(data), m_name(std::move(name)) {}

    TriangleMesh read() {
        parseHeader();
        for (const Element& e : m_elements) {
            if (e.name == "vertex") readVertices(e);
            else if (e.name == "face") readFaces(e);
            else skipElement(e);
        }
        if (m_skippedFaces > 0)
            log::warn("{}: skipped {} faces with fewer than 3 vertices", m_name, m_skippedFaces);
        return std::move(m_mesh);
    }

private:
    template <typename... Args>
    [[noreturn]] void error(int line, fmt::format_string<Args...> f, Args&&... a) const {
        failAt(SourceLocation{m_name, line}, f, std::forward<Args>(a)...);
    }
    /// Line for body errors: known for ascii only.
    int dataLine() const { return m_format == Format::Ascii ? m_line : 0; }

    // ---- header --------------------------------------------------------------------
    bool nextHeaderLine(std::string_view& out) {
        if (m_pos >= m_data.size()) return false;
        std::size_t nl = m_data.find('\n', m_pos);
        std::size_t end = nl == std::string_view::npos ? m_data.size() : nl;
        out = m_data.substr(m_pos, end - m_pos);
        if (!out.empty() && out.back() == '\r') out.remove_suffix(1);
        m_pos = nl == std::string_view::npos ? m_data.size() : nl + 1;
        ++m_line;
        return true;
    }

    void parseHeader() {
        std::string_view line;
        if (!nextHeaderLine(line) || words(line).size() != 1 || words(line)[0] != "ply")
            error(1, "not a PLY file (the first line must be 'ply')");
        bool haveFormat = false;
        for (;;) {
            if (!nextHeaderLine(line)) error(m_line, "PLY header ends without 'end_header'");
            auto w = words(line);
            if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
            if (w[0] == "end_header") break;
            if (w[0] == "format") {
                if (w.size() != 3) error(m_line, "malformed PLY format line '{}'", printable(line));
                if (w[1] == "ascii") m_format = Format::Ascii;
                else if (w[1] == "binary_little_endian") m_format = Format::BinaryLE;
                else if (w[1] == "binary_big_endian") m_format = Format::BinaryBE;
                else error(m_line, "unsupported PLY format '{}' (expected ascii, binary_little_endian "
                                   "or binary_big_endian)", printable(w[1]));
                if (w[2] != "1.0" && w[2] != "1") error(m_line, "unsupported PLY version '{}'", printable(w[2]));
                haveFormat = true;
            } else if (w[0] == "element") {
                Element e;
                if (w.size() != 3) error(m_line, "malformed PLY element line '{}'", printable(line));
                e.name = std::string(w[1]);
                auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
                if (ec != std::errc() || ptr != w[2].data() + w[2].size())
                    error(m_line, "PLY element '{}' has an invalid count '{}'", e.name, printable(w[2]));
                e.line = m_line;
                for (const Element& o : m_elements)
                    if (o.name == e.name) error(m_line, "PLY element '{}' declared twice", e.name);
                m_elements.push_back(std::move(e));
            } else if (w[0] == "property") {
                if (m_elements.empty()) error(m_line, "PLY property declared before any element");
                Property p;
                bool ok;
                if (w.size() >= 2 && w[1] == "list") {
                    ok = w.size() == 5 && parseType(w[2], p.countType) && parseType(w[3], p.type);
                    p.list = true;
                    if (ok && (p.countType == Type::F32 || p.countType == Type::F64))
                        error(m_line, "PLY list count type must be an integer type");
                } else {
                    ok = w.size() == 3 && parseType(w[1], p.type);
                }
                if (!ok) error(m_line, "malformed PLY property line '{}'", printable(line));
                p.name = std::string(w.back());
                m_elements.back().props.push_back(std::move(p));
            } else {
                error(m_line, "unknown PLY header keyword '{}'", printable(w[0]));
            }
        }
        if (!haveFormat) error(m_line, "PLY header has no 'format' line");
        ++m_line;  // the body starts on the line after end_header
        bool bigEndianHost = std::endian::native == std::endian::big;
        m_swap = (m_format == Format::BinaryLE && bigEndianHost) || (m_format == Format::BinaryBE && !bigEndianHost);
    }

    // ---- body values ---------------------------------------------------------------
    [[noreturn]] void truncated(const Element& e, std::uint64_t i) const {
        error(dataLine(), "truncated PLY data: element '{}' record {} of {} is incomplete", e.name, i + 1, e.count);
    }

    /// The next value of type t as a double; false at the end of the data.
    bool value(Type t, double& out) {
        if (m_format == Format::Ascii) return asciiValue(out);
        std::size_t n = typeSize(t);
        if (m_data.size() - m_pos < n) return false;
        unsigned char b[8];
        std::memcpy(b, m_data.data() + m_pos, n);
        m_pos += n;
        if (m_swap)
            for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
        switch (t) {
        case Type::I8: { std::int8_t v; std::memcpy(&v, b, 1); out = v; break; }
        case Type::U8: out = b[0]; break;
        case Type::I16: { std::int16_t v; std::memcpy(&v, b, 2); out = v; break; }
        case Type::U16: { std::uint16_t v; std::memcpy(&v, b, 2); out = v; break; }
        case Type::I32: { std::int32_t v; std::memcpy(&v, b, 4); out = v; break; }
        case Type::U32: { std::uint32_t v; std::memcpy(&v, b, 4); out = v; break; }
        case Type::I64: { std::int64_t v; std::memcpy(&v, b, 8); out = double(v); break; }
        case Type::U64: { std::uint64_t v; std::memcpy(&v, b, 8); out = double(v); break; }
        case Type::F32: { float v; std::memcpy(&v, b, 4); out = v; break; }
        case Type::F64: { double v; std::memcpy(&v, b, 8); out = v; break; }
        }
        return true;
    }

    bool asciiValue(double& out) {
        while (m_pos < m_data.size()) {
            char c = m_data[m_pos];
            if (c == '\n') ++m_line;
            else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') break;
            ++m_pos;
        }
        if (m_pos >= m_data.size()) return false;
        std::size_t end = m_pos;
        while (end < m_data.size() && !std::isspace(static_cast<unsigned char>(m_data[end]))) ++end;
        std::string_view tok = m_data.substr(m_pos, end - m_pos);
        m_pos = end;
        std::string_view num = !tok.empty() && tok[0] == '+' ? tok.substr(1) : tok;
        auto [ptr, ec] = std::from_chars(num.data(), num.data() + num.size(), out);
        if (ec != std::errc() || ptr != num.data() + num.size())
            error(m_line, "expected a number in PLY data, got '{}'", printable(tok));
        return true;
    }

    /// A list length: a non-negative integer.
    std::uint64_t count(const Element& e, std::uint64_t i, const Property& p) {
        double c = 0.0;
        if (!value(p.countType, c)) truncated(e, i);
        if (!(c >= 0.0) || c != std::floor(c) || c > 1e12)
            error(dataLine(), "PLY element '{}' record {}: invalid list length {} for '{}'", e.name, i + 1, c, p.name);
        return std::uint64_t(c);
    }

    void skip(const Element& e, std::uint64_t i, const Property& p) {
        std::uint64_t n = p.list ? count(e, i, p) : 1;
        if (m_format != Format::Ascii) {
            std::size_t size = typeSize(p.type);
            if (n > (m_data.size() - m_pos) / size) truncated(e, i);
            m_pos += std::size_t(n) * size;
            return;
        }
        double dummy = 0.0;
        for (std::uint64_t k = 0; k < n; ++k)
            if (!value(p.type, dummy)) truncated(e, i);
    }

    // ---- elements ------------------------------------------------------------------
    void skipElement(const Element& e) {
        bool fixed = m_format != Format::Ascii;
        std::size_t stride = 0;
        for (const Property& p : e.props) {
            fixed = fixed && !p.list;
            stride += typeSize(p.type);
        }
        if (fixed) {  // one bounds check for the whole block
            if (stride > 0 && e.count > (m_data.size() - m_pos) / stride)
                truncated(e, (m_data.size() - m_pos) / stride);
            m_pos += std::size_t(e.count) * stride;
            return;
        }
        for (std::uint64_t i = 0; i < e.count; ++i)
            for (const Property& p : e.props) skip(e, i, p);
    }

    void readVertices(const Element& e) {
        if (e.count > 0xffffffffull) error(e.line, "PLY file has too many vertices ({})", e.count);
        // Slots: x y z nx ny nz u v.
        std::vector<int> slot(e.props.size(), -1);
        bool have[8] = {};
        for (std::size_t k = 0; k < e.props.size(); ++k) {
            const std::string& n = e.props[k].name;
            int s = n == "x" ? 0 : n == "y" ? 1 : n == "z" ? 2 : n == "nx" ? 3 : n == "ny" ? 4 : n == "nz" ? 5
                  : (n == "u" || n == "s" || n == "texture_u" || n == "texture_s") ? 6
                  : (n == "v" || n == "t" || n == "texture_v" || n == "texture_t") ? 7 : -1;
            if (s < 0 || e.props[k].list || have[s]) continue;
            slot[k] = s;
            have[s] = true;
        }
        if (!have[0] || !have[1] || !have[2])
            error(e.line, "PLY vertex element lacks one of the properties x, y, z");
        bool normals = have[3] && have[4] && have[5], uvs = have[6] && have[7];

        // Reserve no more than the data could hold: the count is untrusted.
        std::size_t cap = std::size_t(std::min<std::uint64_t>(e.count, m_data.size() - m_pos));
        m_mesh.positions.reserve(cap);
        if (normals) m_mesh.normals.reserve(cap);
        if (uvs) m_mesh.uvs.reserve(cap);
        for (std::uint64_t i = 0; i < e.count; ++i) {
            double v[8] = {};
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                if (slot[k] < 0) {
                    skip(e, i, e.props[k]);
                } else if (!value(e.props[k].type, v[slot[k]])) {
                    truncated(e, i);
                }
            }
            m_mesh.positions.emplace_back(float(v[0]), float(v[1]), float(v[2]));
            if (normals) m_mesh.normals.emplace_back(float(v[3]), float(v[4]), float(v[5]));
            if (uvs) m_mesh.uvs.emplace_back(float(v[6]), float(v[7]));
        }
    }

    void readFaces(const Element& e) {
        int which = -1;
        for (std::size_t k = 0; k < e.props.size(); ++k)
            if (which < 0 && (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index")) {
                if (!e.props[k].list) error(e.line, "PLY face property '{}' must be a list", e.props[k].name);
                which = int(k);
            }
        if (which < 0) error(e.line, "PLY face element has no 'vertex_indices' list");
        // Indices are checked against the declared vertex count, which the header gives
        // even when faces come first in the file.
        std::uint64_t nv = 0;
        for (const Element& o : m_elements)
            if (o.name == "vertex") nv = o.count;

        std::vector<std::uint32_t> poly;
        m_mesh.indices.reserve(std::size_t(std::min<std::uint64_t>(3 * e.count, m_data.size() - m_pos)));
        for (std::uint64_t i = 0; i < e.count; ++i) {
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const Property& p = e.props[k];
                if (int(k) != which) {
                    skip(e, i, p);
                    continue;
                }
                std::uint64_t n = count(e, i, p);
                poly.clear();
                for (std::uint64_t j = 0; j < n; ++j) {
                    double idx = 0.0;
                    if (!value(p.type, idx)) truncated(e, i);
                    if (!(idx >= 0.0 && double(idx) < double(nv)) || idx != std::floor(idx))
                        error(dataLine(), "PLY face {} of {} uses vertex index {}, out of range (file has {} vertices)",
                              i + 1, e.count, idx, nv);
                    poly.push_back(std::uint32_t(idx));
                }
                if (poly.size() < 3) {
                    ++m_skippedFaces;
                    continue;
                }
                // Fan triangulation: exact for the convex polygons PLY writers emit.
                for (std::size_t j = 1; j + 1 < poly.size(); ++j) {
                    m_mesh.indices.push_back(poly[0]);
                    m_mesh.indices.push_back(poly[j]);
                    m_mesh.indices.push_back(poly[j + 1]);
                }
            }
        }
    }

    std::string_view m_data;
    std::string m_name;
    std::size_t m_pos = 0;
    int m_line = 0;
    Format m_format = Format::Ascii;
    bool m_swap = false;
    std::vector<Element> m_elements;
    std::uint64_t m_skippedFaces = 0;
    TriangleMesh m_mesh;
};

} // namespace

TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name) {
    return PlyParser(data, name).read();
}

TriangleMesh readPly(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail("{}: cannot open PLY file (no such file)", path.string());
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("{}: cannot open PLY file", path.string());
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) fail("{}: error while reading the PLY file", path.string());
    std::string data = std::move(buf).str();
    return readPlyFromMemory(data, path.string());
}

} // namespace effigi
