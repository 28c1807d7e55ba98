#pragma once
// Control cages of the subdiv shape: polygons (not triangulated), optional face-varying
// uvs, and edge creases / vertex corners with their sharpness, read from an OBJ file (its
// `t crease 2/1/0 v0 v1 s`, `t corner 1/1/0 v s` and `t interpolateboundary 1/0/0 n` tags,
// vertex indices counted from 0 as in OpenSubdiv's example shapes), a PLY file (polygons
// rebuilt from the reader's fans) or inline parameters. Errors name the file.
// References: Wavefront OBJ; the subdivision tags of OpenSubdiv's regression shapes
// (Pixar, regression/shapes); Turk, The PLY Polygon File Format, 1994.
#include "procedural_mesh.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"
#include "effigi/render/ply_reader.hpp"

#include "obj_file.hpp"

#include <fstream>
#include <string>
#include <vector>

namespace effigi::subdiv {

struct Cage {
    std::vector<Vector3d> positions;
    std::vector<int> faceSizes, faceVerts;  ///< polygons: sizes, then all corners in order
    std::vector<Point2f> uvs;               ///< face-varying values (empty: none)
    std::vector<int> uvIndices;             ///< per corner, into uvs
    std::vector<int> creasePairs;           ///< two vertices per crease edge
    std::vector<float> creaseWeights;
    std::vector<int> corners;
    std::vector<float> cornerWeights;
    int interpolateBoundary = -1;  ///< OBJ tag: 0 none, 1 edge and corner, 2 edge only; -1 absent
};

inline Cage readObjCage(const std::string& file, bool flipTexCoords) {
    ObjFile obj = readObjFile(file);
    const tinyobj::attrib_t& attrib = obj.attrib;
    const std::vector<tinyobj::shape_t>& shapes = obj.shapes;
    Cage c;
    const std::size_t nv = attrib.vertices.size() / 3, nt = attrib.texcoords.size() / 2;
    for (std::size_t i = 0; i < nv; ++i)
        c.positions.emplace_back(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    for (std::size_t i = 0; i < nt; ++i)
        c.uvs.emplace_back(attrib.texcoords[2 * i], flipTexCoords ? 1.f - attrib.texcoords[2 * i + 1] : attrib.texcoords[2 * i + 1]);
    bool uvs = nt > 0;
    const std::vector<tinyobj::tag_t>* tags = nullptr;  // cumulative in tinyobjloader: the longest list has all
    for (const tinyobj::shape_t& s : shapes) {
        std::size_t next = 0;
        for (unsigned char n : s.mesh.num_face_vertices) {
            if (next + n > s.mesh.indices.size()) fail("{}: a face has more than 255 vertices (unsupported)", file);
            c.faceSizes.push_back(n);
            for (std::size_t k = 0; k < n; ++k) {
                const tinyobj::index_t& i = s.mesh.indices[next + k];
                c.faceVerts.push_back(i.vertex_index);
                uvs = uvs && i.texcoord_index >= 0 && std::size_t(i.texcoord_index) < nt;
                c.uvIndices.push_back(i.texcoord_index);
            }
            next += n;
        }
        if (!tags || s.mesh.tags.size() > tags->size()) tags = &s.mesh.tags;
    }
    if (!uvs) c.uvs.clear(), c.uvIndices.clear();
    for (std::size_t k = 0; tags && k < tags->size(); ++k) {
        const tinyobj::tag_t& t = (*tags)[k];
        auto need = [&](std::size_t ints, std::size_t reals) {
            if (t.intValues.size() != ints || t.floatValues.size() != reals)
                fail("{}: tag 't {}' needs {} vertex indices and {} sharpness values", file, t.name, ints, reals);
        };
        if (t.name == "crease") {
            need(2, 1);
            c.creasePairs.insert(c.creasePairs.end(), {t.intValues[0], t.intValues[1]});
            c.creaseWeights.push_back(t.floatValues[0]);
        } else if (t.name == "corner") {
            need(1, 1);
            c.corners.push_back(t.intValues[0]);
            c.cornerWeights.push_back(t.floatValues[0]);
        } else if (t.name == "interpolateboundary" && t.intValues.size() == 1) {
            c.interpolateBoundary = t.intValues[0];
        } else {
            log::warn("{}: subdivision tag 't {}' is not supported; ignored", file, excerpt(t.name));
        }
    }
    return c;
}

inline Cage readPlyCage(const std::string& file, bool flipTexCoords) {
    std::vector<std::uint32_t> sizes;
    TriangleMesh m = readPly(file, &sizes);
    Cage c;
    for (const Point3f& p : m.positions) c.positions.emplace_back(p);
    std::size_t tri = 0;
    for (std::uint32_t n : sizes) {  // the fan (v0, v_k, v_k+1), k = 1 .. n-2, back to (v0 .. v_n-1)
        c.faceSizes.push_back(int(n));
        c.faceVerts.insert(c.faceVerts.end(), {int(m.indices[3 * tri]), int(m.indices[3 * tri + 1])});
        for (std::uint32_t k = 0; k + 2 < n; ++k, ++tri) c.faceVerts.push_back(int(m.indices[3 * tri + 2]));
    }
    if (!m.uvs.empty()) {  // per vertex: one face-varying value per vertex
        c.uvs = m.uvs;
        if (flipTexCoords)
            for (Point2f& uv : c.uvs) uv.y = 1.f - uv.y;
        c.uvIndices = c.faceVerts;
    }
    return c;
}

/// The cage written in the scene: positions "x y z, ..." and faces "i j k ..., ..." (from 0).
inline Cage inlineCage(const Properties& p) {
    Cage c;
    for (const std::vector<double>& t : procedural::parseTuples(p, "positions", 3, 3)) c.positions.emplace_back(t[0], t[1], t[2]);
    for (const std::vector<double>& f : procedural::parseTuples(p, "faces", 0, 1)) {
        c.faceSizes.push_back(int(f.size()));
        for (double i : f) {
            if (i != std::floor(i) || i < 0.0 || i >= double(c.positions.size()))
                failAt(p.whereOf("faces"), "{}: parameter 'faces': face {} uses vertex {}, not an index of the {} positions",
                       p.describe(), c.faceSizes.size(), i, c.positions.size());
            c.faceVerts.push_back(int(i));
        }
    }
    return c;
}

} // namespace effigi::subdiv
