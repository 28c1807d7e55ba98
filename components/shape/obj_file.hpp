#pragma once
// Reading a Wavefront OBJ file with tinyobjloader, as `obj` and `subdiv` do: the vertex
// attributes and the faces of every group, no materials (mtllib ignored) and no
// triangulation (tinyobjloader's own indexes vertices before anyone has range-checked
// them), with one-line errors naming the file.
#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"

#include <tiny_obj_loader.h>

#include <fstream>
#include <string>
#include <vector>

namespace effigi {

struct ObjFile {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
};

/// First line of a tinyobjloader message, for a one-line error (escaped: it may quote the file).
inline std::string objFirstLine(const std::string& s) {
    std::string r = s.substr(0, s.find('\n'));
    return r.empty() ? "parse error" : excerpt(r, 200);
}

inline ObjFile readObjFile(const std::string& file) {
    regularFileSize(file, "OBJ file");  // refuses devices and FIFOs: tinyobjloader reads to the end
    std::ifstream in(file);
    if (!in) fail("{}: cannot open OBJ file", file);
    ObjFile obj;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    if (!tinyobj::LoadObj(&obj.attrib, &obj.shapes, &materials, &warn, &err, &in, nullptr, false, false))
        fail("{}: invalid OBJ file: {}", file, objFirstLine(err));
    if (!warn.empty()) log::debug("{}: {}", file, objFirstLine(warn));
    return obj;
}

} // namespace effigi
