// RIB text -> requests (lexer.hpp).
#include "lexer.hpp"

#include "effigi/core/input.hpp"

#include <charconv>
#include <cmath>

namespace effigi::rib {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }

} // namespace

Reader::Reader(std::string_view text, std::string file) : m_in(text), m_file(std::move(file)) { advance(); }

void Reader::skipSpaceAndComments() {
    while (m_pos < m_in.size()) {
        char c = m_in[m_pos];
        if (c == '\n') {
            ++m_line;
            ++m_pos;
        } else if (isSpace(c)) {
            ++m_pos;
        } else if (c == '#') {  // also RIB's "##" structure comments
            while (m_pos < m_in.size() && m_in[m_pos] != '\n') ++m_pos;
        } else {
            return;
        }
    }
}

void Reader::lexString() {
    const int open = m_line;
    ++m_pos;  // the opening quote
    m_text.clear();
    while (true) {
        // A string ends on its own line: a newline (or the end of the text) before the
        // closing quote means the quote is missing, and the error points at the opening.
        if (m_pos >= m_in.size() || m_in[m_pos] == '\n')
            failAt(at(open), "unterminated string (no closing '\"' on this line)");
        char c = m_in[m_pos++];
        if (c == '"') return;
        if (c != '\\') {
            m_text += c;
            continue;
        }
        if (m_pos >= m_in.size()) failAt(at(open), "unterminated string (no closing '\"' on this line)");
        char e = m_in[m_pos++];
        switch (e) {
        case 'n': m_text += '\n'; break;
        case 'r': m_text += '\r'; break;
        case 't': m_text += '\t'; break;
        case 'b': m_text += '\b'; break;
        case 'f': m_text += '\f'; break;
        case '\n': ++m_line; break;  // backslash-newline: the string goes on
        default:
            if (e >= '0' && e <= '7') {  // up to three octal digits
                int v = e - '0';
                for (int k = 0; k < 2 && m_pos < m_in.size() && m_in[m_pos] >= '0' && m_in[m_pos] <= '7'; ++k)
                    v = 8 * v + (m_in[m_pos++] - '0');
                m_text += char(v & 0xff);
            } else {
                m_text += e;  // \\, \" and any other character stand for themselves
            }
        }
    }
}

void Reader::lexNumber() {
    const std::size_t start = m_pos;
    auto digits = [&] {
        std::size_t n = 0;
        while (m_pos < m_in.size() && isDigit(m_in[m_pos])) ++m_pos, ++n;
        return n;
    };
    if (m_in[m_pos] == '+' || m_in[m_pos] == '-') ++m_pos;
    std::size_t mantissa = digits();
    if (m_pos < m_in.size() && m_in[m_pos] == '.') {
        ++m_pos;
        mantissa += digits();
    }
    bool ok = mantissa > 0;
    if (ok && m_pos < m_in.size() && (m_in[m_pos] == 'e' || m_in[m_pos] == 'E')) {
        ++m_pos;
        if (m_pos < m_in.size() && (m_in[m_pos] == '+' || m_in[m_pos] == '-')) ++m_pos;
        ok = digits() > 0;
    }
    // A number runs up to white space, a bracket, a quote or a comment.
    while (m_pos < m_in.size() && (isAlpha(m_in[m_pos]) || isDigit(m_in[m_pos]) || m_in[m_pos] == '.' ||
                                   m_in[m_pos] == '+' || m_in[m_pos] == '-'))
        ++m_pos, ok = false;
    std::string_view text = m_in.substr(start, m_pos - start);
    if (!ok) failAt(at(m_line), "malformed number '{}'", excerpt(text));
    std::string_view digitsOnly = text[0] == '+' ? text.substr(1) : text;
    double v = 0.0;
    auto [end, ec] = std::from_chars(digitsOnly.data(), digitsOnly.data() + digitsOnly.size(), v);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && !(std::abs(v) <= MaxNumber)))
        failAt(at(m_line), "number '{}' is out of range (beyond ±1e38)", excerpt(text));
    if (ec != std::errc() || end != digitsOnly.data() + digitsOnly.size())
        failAt(at(m_line), "malformed number '{}'", excerpt(text));
    m_number = v;
}

void Reader::advance() {
    skipSpaceAndComments();
    if (m_pos >= m_in.size()) {
        m_tok = Tok::End;
        return;
    }
    m_tokLine = m_lastLine = m_line;
    const char c = m_in[m_pos];
    if (c == '"') {
        lexString();
        m_tok = Tok::String;
    } else if (c == '[' || c == ']') {
        ++m_pos;
        m_tok = c == '[' ? Tok::Open : Tok::Close;
    } else if (isDigit(c) || c == '-' || c == '+' || c == '.') {
        lexNumber();
        m_tok = Tok::Number;
    } else if (isAlpha(c)) {
        const std::size_t start = m_pos;
        while (m_pos < m_in.size() && (isAlpha(m_in[m_pos]) || isDigit(m_in[m_pos]))) ++m_pos;
        m_text.assign(m_in.substr(start, m_pos - start));
        m_tok = Tok::Name;
    } else if (static_cast<unsigned char>(c) >= 0x80) {
        failAt(at(m_line), "unexpected byte 0x{:02X} (binary RIB is not supported)", static_cast<unsigned char>(c));
    } else {
        failAt(at(m_line), "unexpected character '{}'", excerpt(std::string_view(&c, 1)));
    }
}

Value Reader::value() {
    Value v;
    v.line = m_tokLine;
    switch (m_tok) {
    case Tok::Number: v.numbers.push_back(m_number); break;
    case Tok::String:
        v.isString = true;
        v.strings.push_back(m_text);
        break;
    case Tok::Close: failAt(at(m_tokLine), "']' without a matching '['");
    case Tok::Open: {
        v.bracketed = true;
        bool numbers = false;
        for (advance(); m_tok != Tok::Close; advance()) {
            if (m_tok == Tok::End || m_tok == Tok::Name)
                failAt(at(v.line), "unterminated array: this '[' has no matching ']'");
            if (m_tok == Tok::Open) failAt(at(m_tokLine), "nested arrays are not allowed");
            if (m_tok == Tok::Number) {
                numbers = true;
                v.numbers.push_back(m_number);
            } else {
                v.isString = true;
                v.strings.push_back(m_text);
            }
            if (numbers && v.isString) failAt(at(m_tokLine), "an array mixes numbers and strings");
        }
        break;
    }
    case Tok::Name:
    case Tok::End: break;  // not reached: next() stops at names and at the end
    }
    advance();
    return v;
}

bool Reader::next(Request& r) {
    if (m_tok == Tok::End) return false;
    if (m_tok != Tok::Name) failAt(at(m_tokLine), "a value before the first request (a request name must come first)");
    r.name = m_text;
    r.line = m_tokLine;
    r.values.clear();
    advance();
    while (m_tok != Tok::Name && m_tok != Tok::End) r.values.push_back(value());
    return true;
}

} // namespace effigi::rib
