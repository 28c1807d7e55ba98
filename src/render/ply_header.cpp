// The PLY header (Turk 1994): the magic line, the format, and the elements with their
// typed scalar or list properties, up to end_header. The body is read by ply_reader.cpp.
#include "ply_format.hpp"

#include "effigi/core/input.hpp"

#include <charconv>
#include <utility>

namespace effigi::ply {
namespace {

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

/// Reads the header line by line, counting lines for error messages.
class HeaderParser {
public:
    HeaderParser(std::string_view data, const std::string& name) : m_data(data), m_name(name) {}

    Header parse() {
        std::string_view line;
        if (!nextHeaderLine(line) || words(line).size() != 1 || words(line)[0] != "ply")
            error(1, "not a PLY file (the first line must be 'ply')");
        bool haveFormat = false;
        std::vector<Element>& elements = m_header.elements;
        for (;;) {
            if (!nextHeaderLine(line)) error(m_line, "PLY header ends without 'end_header'");
            auto w = words(line);
            if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
            if (w[0] == "end_header") break;
            if (w[0] == "format") {
                if (w.size() != 3) error(m_line, "malformed PLY format line '{}'", excerpt(line));
                if (w[1] == "ascii") m_header.format = Format::Ascii;
                else if (w[1] == "binary_little_endian") m_header.format = Format::BinaryLE;
                else if (w[1] == "binary_big_endian") m_header.format = Format::BinaryBE;
                else error(m_line, "unsupported PLY format '{}' (expected ascii, binary_little_endian "
                                   "or binary_big_endian)", excerpt(w[1]));
                if (w[2] != "1.0" && w[2] != "1") error(m_line, "unsupported PLY version '{}'", excerpt(w[2]));
                haveFormat = true;
            } else if (w[0] == "element") {
                Element e;
                if (w.size() != 3) error(m_line, "malformed PLY element line '{}'", excerpt(line));
                e.name = std::string(w[1]);
                auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
                if (ec != std::errc() || ptr != w[2].data() + w[2].size())
                    error(m_line, "PLY element '{}' has an invalid count '{}'", excerpt(e.name), excerpt(w[2]));
                e.line = m_line;
                for (const Element& o : elements)
                    if (o.name == e.name) error(m_line, "PLY element '{}' declared twice", excerpt(e.name));
                elements.push_back(std::move(e));
            } else if (w[0] == "property") {
                if (elements.empty()) error(m_line, "PLY property declared before any element");
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
                if (!ok) error(m_line, "malformed PLY property line '{}'", excerpt(line));
                p.name = std::string(w.back());
                elements.back().props.push_back(std::move(p));
            } else {
                error(m_line, "unknown PLY header keyword '{}'", excerpt(w[0]));
            }
        }
        if (!haveFormat) error(m_line, "PLY header has no 'format' line");
        m_header.bodyPos = m_pos;
        m_header.bodyLine = m_line + 1;  // the body starts on the line after end_header
        checkCounts();
        return std::move(m_header);
    }

private:
    template <typename... Args>
    [[noreturn]] void error(int line, fmt::format_string<Args...> f, Args&&... a) const {
        failAt(SourceLocation{m_name, line}, f, std::forward<Args>(a)...);
    }

    /// The declared counts are untrusted: every record takes some bytes of the body, so
    /// a count the rest of the file cannot hold is refused here, before any reading
    /// (or reserving) proportional to it. An element without properties has records of
    /// no bytes; it is skipped whatever its count, as Mitsuba 3 skips it in a binary file
    /// (by seeking count x 0 bytes).
    void checkCounts() const {
        const bool ascii = m_header.format == Format::Ascii;
        // An ascii value is at least one character and a blank after it (the last value
        // of the file may end without one, hence the extra byte).
        std::uint64_t budget = m_data.size() - m_pos + (ascii ? 1 : 0);
        for (const Element& e : m_header.elements) {
            std::uint64_t least = 0;  // bytes of the smallest record (a list may be empty)
            for (const Property& p : e.props) least += ascii ? 2 : typeSize(p.list ? p.countType : p.type);
            if (least == 0) continue;
            if (e.count > budget / least)
                error(e.line, "truncated PLY data: element '{}' declares {} records, more than the rest of the "
                              "file can hold ({} bytes, {} bytes per record at least)",
                      excerpt(e.name), e.count, m_data.size() - m_pos, least);
            budget -= e.count * least;
        }
    }

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

    std::string_view m_data;
    const std::string& m_name;
    std::size_t m_pos = 0;
    int m_line = 0;
    Header m_header;
};

} // namespace

std::size_t typeSize(Type t) {
    switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    default: return 8;
    }
}

Header parseHeader(std::string_view data, const std::string& name) { return HeaderParser(data, name).parse(); }

} // namespace effigi::ply
