#pragma once
// RIB (the RenderMan Interface Bytestream), ASCII form: text -> requests. A request is a
// name followed by its values up to the next name, across any number of lines: numbers,
// "strings" (C escapes, backslash-newline continues a string) and [ arrays ] of either;
// '#' starts a comment that runs to the end of the line. Binary RIB (bytes >= 0x80) is
// refused. Every request and value keeps the line it starts on, for file:line errors.
// Reference: Pixar, The RenderMan Interface, version 3.2 (2000), appendix C.
#include "effigi/core/error.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace effigi::rib {

/// One argument as written: a number, a string, or a bracketed array of either (an
/// empty array counts as numbers).
struct Value {
    bool isString = false;
    bool bracketed = false;
    std::vector<double> numbers;
    std::vector<std::string> strings;
    int line = 0;

    std::size_t size() const { return isString ? strings.size() : numbers.size(); }
};

struct Request {
    std::string name;  ///< as written (requests are matched without regard to case)
    int line = 0;
    std::vector<Value> values;
};

/// Numbers beyond this magnitude are refused (RenderMan's RI_INFINITY is 1e38; a float
/// holds up to 3.4e38).
constexpr double MaxNumber = 1e38;

class Reader {
public:
    Reader(std::string_view text, std::string file);

    /// The next request; false at the end of the text. Throws Error (file:line) on
    /// malformed text: an unterminated string or array, a malformed or huge number, a
    /// value before the first request, a byte that belongs to no token.
    bool next(Request& r);
    /// The line of the last token read (1 for a text without any): where errors about
    /// the end of the text point.
    int line() const { return m_lastLine; }
    const std::string& file() const { return m_file; }

private:
    enum class Tok { Name, Number, String, Open, Close, End };
    void advance();  // reads the next token into m_tok, m_text, m_number, m_tokLine
    void skipSpaceAndComments();
    void lexString();
    void lexNumber();
    Value value();
    SourceLocation at(int line) const { return {m_file, line}; }

    std::string_view m_in;
    std::string m_file;
    std::size_t m_pos = 0;
    int m_line = 1;
    Tok m_tok = Tok::End;
    int m_tokLine = 1;
    int m_lastLine = 1;
    std::string m_text;
    double m_number = 0.0;
};

} // namespace effigi::rib
