// Scene variables: <default>, -D and $substitution, as in Mitsuba 3 (variables.hpp).
#include "variables.hpp"

#include "effigi/core/input.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

namespace effigi::xml::detail {
namespace {

bool isIdentifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

} // namespace

void Variables::declare(const Element& e) {
    e.allowOnly({"name", "value"});
    std::string name = e.require("name");
    const std::string& value = e.require("value");
    if (!isIdentifier(name)) e.fail("'{}' is not a valid variable name", excerpt(name));
    // As in Mitsuba, the first <default> of a name holds and later ones are skipped: an
    // included fragment may declare the defaults its includer already set.
    if (!m_declared.emplace(name, e.where).second) return;
    auto d = m_defines.find(name);
    m_vars[name] = d != m_defines.end() ? d->second : value;
}

std::string Variables::substitute(const std::string& text, const Element& e, const std::string& attr) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        char next = i + 1 < text.size() ? text[i + 1] : '\0';
        if (text[i] == '\\' && next == '$') {  // "\$" is a literal '$', as in Mitsuba
            out += '$';
            ++i;
            continue;
        }
        if (text[i] != '$' || !(std::isalpha(static_cast<unsigned char>(next)) || next == '_')) {
            out += text[i];
            continue;
        }
        std::size_t j = i + 1;
        while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_')) ++j;
        std::string var = text.substr(i + 1, j - i - 1);
        const std::string* val = nullptr;
        if (auto it = m_vars.find(var); it != m_vars.end()) val = &it->second;
        // As in Mitsuba, a -D value is a parameter of its own: the scene may use it
        // without declaring a <default>.
        if (auto it = m_defines.find(var); !val && it != m_defines.end()) val = &it->second;
        if (!val) {
            std::vector<std::string> known;
            for (const auto& kv : m_vars) known.push_back(kv.first);
            for (const auto& kv : m_defines) known.push_back(kv.first);
            std::string hint = didYouMean(var, known);
            e.fail("attribute '{}': undefined variable '${}' (declare it first with <default name=\"{}\" "
                   "value=\"...\"/> or pass -D {}=...){}",
                   excerpt(attr), var, var, var, hint.empty() ? "" : fmt::format("; did you mean '${}'?", hint));
        }
        m_used.insert(var);
        out += *val;
        i = j - 1;
    }
    return out;
}

void Variables::checkDefinesUsed(const std::string& filename) const {
    for (const auto& [name, value] : m_defines)
        if (!m_declared.count(name) && !m_used.count(name))
            fail("{}: -D {}: the scene neither declares <default name=\"{}\"> nor uses ${}", filename, name, name,
                 name);
}

} // namespace effigi::xml::detail
