#pragma once
// Errors that reach the user: one line naming where (file:line) and what.
#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace effigi {

/// A place in a scene file (or any input file). Empty file = no location known.
struct SourceLocation {
    std::string file;
    int line = 0;

    bool known() const { return !file.empty(); }
    std::string str() const { return line > 0 ? fmt::format("{}:{}", file, line) : file; }
};

/// The one exception type effigi throws for bad input. what() is the whole
/// one-line message, location first when there is one.
class Error : public std::runtime_error {
public:
    explicit Error(const std::string& msg) : std::runtime_error(msg) {}
    Error(const SourceLocation& where, const std::string& msg)
        : std::runtime_error(where.known() ? where.str() + ": " + msg : msg), m_where(where) {}

    const SourceLocation& where() const { return m_where; }

private:
    SourceLocation m_where;
};

template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) {
    throw Error(fmt::format(f, std::forward<Args>(args)...));
}

template <typename... Args>
[[noreturn]] void failAt(const SourceLocation& where, fmt::format_string<Args...> f, Args&&... args) {
    throw Error(where, fmt::format(f, std::forward<Args>(args)...));
}

/// Closest candidate by edit distance, for "did you mean" hints; empty if nothing is close.
std::string didYouMean(const std::string& word, const std::vector<std::string>& candidates);

} // namespace effigi
