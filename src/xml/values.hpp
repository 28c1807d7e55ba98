#pragma once
// Internal to the XML parser: typed values from attribute text (numbers, triples,
// spectra, transform operations). The parser hands each element over as an
// `Element`: its attributes after $substitution and where it was written, so every
// error here can name file:line and the element.
#include "effigi/core/properties.hpp"

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace effigi::xml::detail {

struct Element {
    std::string tag;
    std::string name;  ///< the `name` attribute (after version mapping), may be empty
    std::string context;  ///< enclosing element for errors ("<transform name=\"to_world\">")
    SourceLocation where;
    std::vector<std::pair<std::string, std::string>> attrs;  ///< after $substitution

    /// How errors name it: "<float name=\"fov\">", "<rotate> in <transform name=\"to_world\">".
    std::string describe() const;
    const std::string* find(std::string_view attr) const;
    /// The attribute's text; error naming the element when it is missing.
    const std::string& require(std::string_view attr) const;
    /// Error (with a did-you-mean) on any attribute not in `allowed`.
    void allowOnly(std::initializer_list<std::string_view> allowed) const;
    template <typename... Args>
    [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
        failAt(where, "{}: {}", describe(), fmt::format(f, std::forward<Args>(args)...));
    }
};

/// A finite number that fits a float; the whole text must parse.
double parseNumber(const Element& e, std::string_view attr, std::string_view text);
std::int64_t parseInteger(const Element& e, std::string_view attr, std::string_view text);
bool parseBool(const Element& e, std::string_view attr, std::string_view text);
/// Numbers separated by commas and/or white space.
std::vector<double> parseList(const Element& e, std::string_view attr, std::string_view text);
/// value="x, y, z" (or a single number when `allowScalar`), or x=/y=/z= attributes
/// with `missing` for absent ones.
Vector3f parseXYZ(const Element& e, float missing, bool allowScalar);

/// The value of a property element other than <transform>; `baseDir` anchors file names.
PropertyValue parseProperty(const Element& e, const std::filesystem::path& baseDir);
/// Multiply one operation of a <transform> onto `m` from the left (M = op * M), as in
/// Mitsuba: operations written later apply later. Degenerate operations are errors.
void applyTransformOp(const Element& op, Transform& m);

} // namespace effigi::xml::detail
