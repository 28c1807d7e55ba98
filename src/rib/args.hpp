#pragma once
// The arguments of one RIB request, taken in order: positional numbers and strings first,
// then the parameter list ("name" value pairs). Every mismatch is a one-line error at the
// request's (or the parameter's) file:line naming the request: wrong arity, a string
// where a number belongs, a parameter the translation does not know.
#include "lexer.hpp"

#include "effigi/math/vector.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace effigi::rib {

/// A parameter as written: the name with any inline declaration stripped
/// ("uniform float Kd" -> "Kd").
struct Param {
    std::string name;
    Value value;
    bool used = false;
};

class Params {
public:
    Params(std::vector<Param> list, std::string file, std::string label)
        : m_list(std::move(list)), m_file(std::move(file)), m_label(std::move(label)) {}

    /// The value of `name` (marked used), or null.
    const Value* find(const std::string& name);
    /// One number (default when absent).
    double real(const std::string& name, double def);
    /// Three numbers (a colour, point or vector).
    Vector3d triple(const std::string& name, Vector3d def);
    /// `count` numbers per item (P: 3, st: 2); null when absent. Refuses strings and a
    /// length that is not a multiple of `count`.
    const std::vector<double>* numbers(const std::string& name, std::size_t count);
    /// Every parameter not asked for is an error: "parameter 'x' is not supported".
    void finish() const;

    template <typename... A>
    [[noreturn]] void fail(const Value& v, fmt::format_string<A...> f, A&&... a) const {
        failAt(SourceLocation{m_file, v.line}, "RIB request '{}': {}", m_label, fmt::format(f, std::forward<A>(a)...));
    }

private:
    std::vector<Param> m_list;
    std::string m_file, m_label;
};

class Args {
public:
    Args(const Request& r, const std::string& file) : m_req(r), m_file(file), m_label(r.name) {}

    SourceLocation where() const { return {m_file, m_req.line}; }
    const std::string& label() const { return m_label; }
    /// How errors name the request, e.g. `Surface "plastic"` once the shader is known.
    void setLabel(std::string label) { m_label = std::move(label); }

    template <typename... A> [[noreturn]] void fail(fmt::format_string<A...> f, A&&... a) const {
        failAt(where(), "RIB request '{}': {}", m_label, fmt::format(f, std::forward<A>(a)...));
    }

    /// Exactly `n` numbers, written bare or in brackets (Translate 1 2 3, Color [1 0 0]).
    std::vector<double> numbers(std::size_t n);
    double number() { return numbers(1)[0]; }
    /// One string (bare or a one-element array).
    std::string string(const char* what);
    /// A number or a string (a light handle).
    void handle();
    /// One array of numbers (a bare number is an array of one).
    std::vector<double> array(const char* what);
    /// One array of non-negative integers below 2^31 (nverts, vertex indices).
    std::vector<std::uint32_t> integers(const char* what);
    /// True when only the parameter list (or nothing) is left.
    bool atParams() const { return m_next >= m_req.values.size() || m_req.values[m_next].isString; }
    /// The rest as "name" value pairs.
    Params params();
    /// Nothing may be left.
    void end();

private:
    const Value& take(const char* what);

    const Request& m_req;
    const std::string& m_file;
    std::string m_label;
    std::size_t m_next = 0;
};

/// Integers from numbers: each must be integral, >= 0 and < 2^31.
std::vector<std::uint32_t> toIndices(const std::vector<double>& v, const char* what, const Args& args);

} // namespace effigi::rib
