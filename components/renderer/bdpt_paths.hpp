#pragma once
// bdpt's names for the types of path space (include/effigi/render/path_vertex.hpp,
// path_context.hpp; makePathContext builds the context of a scene) and the renderer's
// `pathgenerator` child (default `bsdf`).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/path_context.hpp"

namespace effigi::bdpt {

using Vertex = PathVertex;
using VertexType = PathVertexType;
using Context = PathContext;
using Escape = PathEscape;

/// The `pathgenerator` child of a bidirectional renderer, or the default `bsdf` one.
inline Ref<IPathGenerator> pathGenerator(const Properties& p) {
    Ref<IPathGenerator> g = p.get<IPathGenerator>("pathgenerator");
    if (g) return g;
    Properties d("pathgenerator", "bsdf", p.where());
    return query<IPathGenerator>(Registry::instance().create("pathgenerator", "bsdf", d));
}

} // namespace effigi::bdpt
