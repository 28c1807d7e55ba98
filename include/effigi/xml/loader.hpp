#pragma once
// Property tree -> components: each element becomes Registry::create(tag, type, props)
// (the module loads on first use), references resolve to earlier ids, and the top-level
// children are assembled into a Scene.
#include "effigi/core/registry.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/parser.hpp"

#include <memory>

namespace effigi {

/// Build a scene from a parsed <scene> element.
std::unique_ptr<Scene> loadScene(const xml::Node& root, Registry& registry = Registry::instance());
/// Parse and build in one go.
std::unique_ptr<Scene> loadSceneFile(const std::filesystem::path& path, const xml::ParseOptions& opt = {},
                                     Registry& registry = Registry::instance());
/// Instantiate one element (and its children) on its own; `named` resolves <ref>s.
Ref<IComponent> instantiate(const xml::Node& node, Registry& registry,
                            const std::map<std::string, Ref<IComponent>>& named = {});

} // namespace effigi
