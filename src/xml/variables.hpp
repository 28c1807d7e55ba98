#pragma once
// Internal to the XML parser: scene variables. <default name value> declares $name (the
// first declaration holds), -D name=value overrides it or sets a $name the scene does
// not declare, and attribute text has its $name references replaced ("\$" is a
// literal dollar sign), all as in Mitsuba 3.
#include "values.hpp"

#include <map>
#include <set>
#include <string>

namespace effigi::xml::detail {

class Variables {
public:
    /// `defines` (the -D values) must outlive this object.
    explicit Variables(const std::map<std::string, std::string>& defines) : m_defines(defines) {}

    /// A <default> element (its attributes not substituted).
    void declare(const Element& e);
    /// Attribute `attr` of element e with its $variables replaced; an error naming the
    /// element for an undefined one.
    std::string substitute(const std::string& text, const Element& e, const std::string& attr);
    /// Error for a -D the scene `filename` neither declared nor used (most likely a
    /// typo: Mitsuba reports unused parameters as errors too).
    void checkDefinesUsed(const std::string& filename) const;

private:
    const std::map<std::string, std::string>& m_defines;
    std::map<std::string, std::string> m_vars;         // $name -> value
    std::map<std::string, SourceLocation> m_declared;  // <default> declarations
    std::set<std::string> m_used;                      // variables substituted somewhere
};

} // namespace effigi::xml::detail
