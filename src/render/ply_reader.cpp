// Stanford PLY reader (Turk 1994). The header declares elements, each a count of
// records made of typed scalar or list properties; the body stores them in order,
// either as whitespace-separated ascii or packed binary of either byte order. We keep
// vertex positions, normals and uvs, the faces' index lists, and per-vertex / per-face
// attributes named as Mitsuba 3's PLY loader names them (ply_attributes.cpp); the rest is
// stepped over. The header is parsed by ply_header.cpp.
#include "effigi/render/ply_reader.hpp"

#include "ply_format.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>

namespace effigi {
namespace {

using namespace ply;

class PlyParser {
public:
    PlyParser(std::string_view data, std::string name, std::vector<std::uint32_t>* polygonSizes)
        : m_data(data), m_name(std::move(name)), m_polygonSizes(polygonSizes) {}

    TriangleMesh read() {
        Header header = parseHeader(m_data, m_name);
        m_format = header.format;
        m_elements = std::move(header.elements);
        m_pos = header.bodyPos;
        m_line = header.bodyLine;
        bool bigEndianHost = std::endian::native == std::endian::big;
        m_swap = (m_format == Format::BinaryLE && bigEndianHost) || (m_format == Format::BinaryBE && !bigEndianHost);
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

    // ---- body values ---------------------------------------------------------------
    [[noreturn]] void truncated(const Element& e, std::uint64_t i) const {
        error(dataLine(), "truncated PLY data: element '{}' record {} of {} is incomplete", excerpt(e.name), i + 1,
              e.count);
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
            error(m_line, "expected a number in PLY data, got '{}'", excerpt(tok));
        return true;
    }

    /// A list length: a non-negative integer.
    std::uint64_t count(const Element& e, std::uint64_t i, const Property& p) {
        double c = 0.0;
        if (!value(p.countType, c)) truncated(e, i);
        if (!(c >= 0.0) || c != std::floor(c) || c > 1e12)
            error(dataLine(), "PLY element '{}' record {}: invalid list length {} for '{}'", excerpt(e.name), i + 1, c,
                  excerpt(p.name));
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

    // ---- attributes ----------------------------------------------------------------
    /// Where each property's value goes: (attribute, channel) or none.
    struct AttrSlots {
        std::vector<int> attr, channel;
    };
    AttrSlots addAttributes(const Element& e, const std::vector<AttrGroup>& groups, bool perFace) {
        AttrSlots s{std::vector<int>(e.props.size(), -1), std::vector<int>(e.props.size(), 0)};
        for (const AttrGroup& g : groups) {
            for (std::size_t c = 0; c < g.props.size(); ++c) {
                s.attr[g.props[c]] = int(m_mesh.attributes.size());
                s.channel[g.props[c]] = int(c);
            }
            m_mesh.attributes.push_back({g.name, int(g.props.size()), perFace, {}});
        }
        return s;
    }
    /// Store one attribute value read for property k.
    void storeAttribute(const Element& e, const AttrSlots& s, std::size_t k, double v, std::vector<float>& record) {
        if (isInteger(e.props[k].type)) v = normalizedInteger(e.props[k].type, v);
        record[std::size_t(s.attr[k]) * 4 + std::size_t(s.channel[k])] = float(v);
    }
    /// Append one record's attribute values (record holds 4 slots per attribute).
    void appendRecord(std::size_t first, const std::vector<float>& record, std::size_t times = 1) {
        for (std::size_t a = first; a < m_mesh.attributes.size(); ++a) {
            MeshAttribute& m = m_mesh.attributes[a];
            for (std::size_t t = 0; t < times; ++t)
                for (int c = 0; c < m.channels; ++c) m.data.push_back(record[a * 4 + std::size_t(c)]);
        }
    }

    // ---- elements ------------------------------------------------------------------
    void skipElement(const Element& e) {
        if (e.props.empty()) return;  // records of no bytes (see checkCounts in ply_header.cpp)
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
        std::vector<bool> taken(e.props.size());
        for (std::size_t k = 0; k < e.props.size(); ++k) taken[k] = slot[k] >= 0;
        const std::size_t firstAttr = m_mesh.attributes.size();
        AttrSlots attrs = addAttributes(e, attributeGroups(e, "vertex_", taken, m_name), false);
        std::vector<float> record(m_mesh.attributes.size() * 4, 0.f);

        // Reserve no more than the data could hold: the count is untrusted.
        std::size_t cap = std::size_t(std::min<std::uint64_t>(e.count, m_data.size() - m_pos));
        m_mesh.positions.reserve(cap);
        if (normals) m_mesh.normals.reserve(cap);
        if (uvs) m_mesh.uvs.reserve(cap);
        for (std::uint64_t i = 0; i < e.count; ++i) {
            double v[8] = {};
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                if (attrs.attr[k] >= 0) {
                    double a = 0.0;
                    if (!value(e.props[k].type, a)) truncated(e, i);
                    storeAttribute(e, attrs, k, a, record);
                } else if (slot[k] < 0) {
                    skip(e, i, e.props[k]);
                } else if (!value(e.props[k].type, v[slot[k]])) {
                    truncated(e, i);
                }
            }
            appendRecord(firstAttr, record);
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

        std::vector<bool> taken(e.props.size());
        taken[std::size_t(which)] = true;
        const std::size_t firstAttr = m_mesh.attributes.size();
        AttrSlots attrs = addAttributes(e, attributeGroups(e, "face_", taken, m_name), true);
        std::vector<float> record(m_mesh.attributes.size() * 4, 0.f);

        std::vector<std::uint32_t> poly;
        m_mesh.indices.reserve(std::size_t(std::min<std::uint64_t>(3 * e.count, m_data.size() - m_pos)));
        for (std::uint64_t i = 0; i < e.count; ++i) {
            std::size_t trianglesBefore = m_mesh.indices.size() / 3;
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const Property& p = e.props[k];
                if (attrs.attr[k] >= 0) {
                    double a = 0.0;
                    if (!value(p.type, a)) truncated(e, i);
                    storeAttribute(e, attrs, k, a, record);
                    continue;
                }
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
                if (m_polygonSizes) m_polygonSizes->push_back(std::uint32_t(poly.size()));
                // Fan triangulation: exact for the convex polygons PLY writers emit.
                for (std::size_t j = 1; j + 1 < poly.size(); ++j) {
                    m_mesh.indices.push_back(poly[0]);
                    m_mesh.indices.push_back(poly[j]);
                    m_mesh.indices.push_back(poly[j + 1]);
                }
            }
            // A face attribute belongs to every triangle of its fan (none if skipped).
            appendRecord(firstAttr, record, m_mesh.indices.size() / 3 - trianglesBefore);
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
    std::vector<std::uint32_t>* m_polygonSizes;
};

} // namespace

TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name, std::vector<std::uint32_t>* polygonSizes) {
    return PlyParser(data, name, polygonSizes).read();
}

TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name) {
    return readPlyFromMemory(data, name, nullptr);
}

TriangleMesh readPly(const std::filesystem::path& path, std::vector<std::uint32_t>* polygonSizes) {
    std::string data = readRegularFile(path, "PLY file");
    return readPlyFromMemory(data, path.string(), polygonSizes);
}

TriangleMesh readPly(const std::filesystem::path& path) { return readPly(path, nullptr); }

} // namespace effigi
