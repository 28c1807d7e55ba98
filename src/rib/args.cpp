// Arguments of RIB requests (args.hpp).
#include "args.hpp"

#include "effigi/core/input.hpp"

#include <cmath>

namespace effigi::rib {

namespace {

const char* kindOf(const Value& v) {
    if (v.isString) return v.bracketed ? "an array of strings" : "a string";
    return v.bracketed ? "an array of numbers" : "a number";
}

/// "uniform float Kd" -> "Kd": RIB lets a parameter declare its type inline.
std::string stripDeclaration(const std::string& name) {
    std::size_t end = name.find_last_not_of(" \t");
    if (end == std::string::npos) return name;
    std::size_t start = name.find_last_of(" \t", end);
    start = start == std::string::npos ? 0 : start + 1;
    return name.substr(start, end + 1 - start);
}

} // namespace

const Value* Params::find(const std::string& name) {
    for (Param& p : m_list)
        if (p.name == name) {
            p.used = true;
            return &p.value;
        }
    return nullptr;
}

double Params::real(const std::string& name, double def) {
    const Value* v = find(name);
    if (!v) return def;
    if (v->isString || v->numbers.size() != 1)
        fail(*v, "parameter '{}' expects 1 number, got {} of {}", name, kindOf(*v), v->size());
    return v->numbers[0];
}

Vector3d Params::triple(const std::string& name, Vector3d def) {
    const Value* v = find(name);
    if (!v) return def;
    if (v->isString || v->numbers.size() != 3)
        fail(*v, "parameter '{}' expects 3 numbers, got {} of {}", name, kindOf(*v), v->size());
    return {v->numbers[0], v->numbers[1], v->numbers[2]};
}

const std::vector<double>* Params::numbers(const std::string& name, std::size_t count) {
    const Value* v = find(name);
    if (!v) return nullptr;
    if (v->isString) fail(*v, "parameter '{}' expects numbers, got {}", name, kindOf(*v));
    if (v->numbers.empty() || v->numbers.size() % count != 0)
        fail(*v, "parameter '{}' expects a multiple of {} numbers, got {}", name, count, v->numbers.size());
    return &v->numbers;
}

void Params::finish() const {
    for (const Param& p : m_list)
        if (!p.used) fail(p.value, "parameter '{}' is not supported", excerpt(p.name));
}

const Value& Args::take(const char* what) {
    if (m_next >= m_req.values.size()) fail("missing {}", what);
    return m_req.values[m_next++];
}

std::vector<double> Args::numbers(std::size_t n) {
    // Count every number up to the parameter list, so that too many is reported as such.
    std::size_t have = 0, last = m_next;
    while (last < m_req.values.size() && !m_req.values[last].isString) have += m_req.values[last++].numbers.size();
    if (have != n) fail("expects {} number{}, got {}", n, n == 1 ? "" : "s", have);
    std::vector<double> out;
    out.reserve(n);
    for (; m_next < last; ++m_next) out.insert(out.end(), m_req.values[m_next].numbers.begin(), m_req.values[m_next].numbers.end());
    return out;
}

std::string Args::string(const char* what) {
    const Value& v = take(what);
    if (!v.isString || v.strings.size() != 1) fail("expects {} (a string), got {}", what, kindOf(v));
    return v.strings[0];
}

void Args::handle() {
    const Value& v = take("light handle");
    if (v.size() != 1) fail("expects a light handle (a number or a string), got {}", kindOf(v));
}

std::vector<double> Args::array(const char* what) {
    const Value& v = take(what);
    if (v.isString) fail("expects {} (an array of numbers), got {}", what, kindOf(v));
    return v.numbers;
}

std::vector<std::uint32_t> Args::integers(const char* what) { return toIndices(array(what), what, *this); }

std::vector<std::uint32_t> toIndices(const std::vector<double>& v, const char* what, const Args& args) {
    std::vector<std::uint32_t> out;
    out.reserve(v.size());
    for (double x : v) {
        if (!(x >= 0.0 && x < 2147483648.0) || x != std::floor(x))
            args.fail("{} must be integers in [0, 2^31), got {}", what, x);
        out.push_back(std::uint32_t(x));
    }
    return out;
}

Params Args::params() {
    std::vector<Param> list;
    while (m_next < m_req.values.size()) {
        const Value& name = m_req.values[m_next++];
        if (!name.isString || name.strings.size() != 1)
            failAt(SourceLocation{m_file, name.line}, "RIB request '{}': expected a parameter name (a string), got {}",
                   m_label, kindOf(name));
        std::string n = stripDeclaration(name.strings[0]);
        if (m_next >= m_req.values.size())
            failAt(SourceLocation{m_file, name.line}, "RIB request '{}': parameter '{}' has no value", m_label,
                   excerpt(n));
        for (const Param& p : list)
            if (p.name == n)
                failAt(SourceLocation{m_file, name.line}, "RIB request '{}': parameter '{}' is given twice", m_label,
                       excerpt(n));
        Param p{n, m_req.values[m_next++], false};
        p.value.line = name.line;  // errors about the value point at its name
        list.push_back(std::move(p));
    }
    return Params(std::move(list), m_file, m_label);
}

void Args::end() {
    if (m_next < m_req.values.size())
        failAt(SourceLocation{m_file, m_req.values[m_next].line}, "RIB request '{}': unexpected extra value ({})", m_label,
               kindOf(m_req.values[m_next]));
}

} // namespace effigi::rib
