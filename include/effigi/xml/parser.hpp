#pragma once
// XML scene files in the Mitsuba 3 grammar -> a tree of elements with typed
// properties. Handles <default>/$name substitution, -D overrides, <include>, <path>
// and file names (Mitsuba's search path), and version < 3 camelCase names. Every node
// and property keeps its file and line.
#include "effigi/core/properties.hpp"

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace effigi::xml {

struct Node;

/// A nested element: either an inline object or a <ref id="..."/>.
struct Child {
    std::string name;  ///< the `name` attribute, empty if none
    std::unique_ptr<Node> node;
    std::string refId;  ///< set for <ref>
    SourceLocation where;
};

struct Node {
    std::string tag;   ///< canonical: "camera" for <sensor>
    std::string type;  ///< the `type` attribute
    std::string id;
    SourceLocation where;
    Properties props;  ///< values (float, rgb, transform, ...); nested objects are in children
    std::vector<Child> children;
};

struct ParseOptions {
    /// -D name=value: overrides a <default>, or sets a $name the scene does not declare.
    std::map<std::string, std::string> defines;
};

/// Parse a scene file; throws effigi::Error with file:line on malformed input.
std::unique_ptr<Node> parseFile(const std::filesystem::path& path, const ParseOptions& opt = {});
/// Parse XML text; `filename` names it in errors and anchors relative paths.
std::unique_ptr<Node> parseString(const std::string& text, const std::string& filename,
                                  const ParseOptions& opt = {});

/// Mitsuba 0.6 camelCase -> snake_case ("maxDepth" -> "max_depth").
std::string camelToSnake(const std::string& name);

} // namespace effigi::xml
