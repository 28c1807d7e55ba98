// obj — a triangle mesh read from a Wavefront OBJ file (parsed by tinyobjloader).
//
// Parameters: filename (relative to the scene file), face_normals (ignore `vn`),
// flip_tex_coords (v -> 1 - v, default true as in Mitsuba, since OBJ puts v = 0 at the
// bottom of an image), flip_normals, to_world, nested bsdf and emitter.
// All groups/objects of the file form one mesh; polygons are fan-triangulated;
// materials (mtllib) are ignored. A corner `v/vt/vn` triple becomes one vertex.
// Reference: Wavefront Technologies, "Object Files (.obj)", Advanced Visualizer manual;
// Mitsuba 3 documentation, "Wavefront OBJ mesh loader (obj)".
#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

#include "obj_file.hpp"

#include <array>
#include <filesystem>
#include <fstream>
#include <unordered_map>

namespace effigi {
namespace {

TriangleMesh loadObj(const std::string& file, bool flipTexCoords) {
    ObjFile obj = readObjFile(file);
    const tinyobj::attrib_t& attrib = obj.attrib;
    const std::vector<tinyobj::shape_t>& shapes = obj.shapes;

    const std::size_t nv = attrib.vertices.size() / 3, nn = attrib.normals.size() / 3,
                      nt = attrib.texcoords.size() / 2;
    // Use normals / uvs only if every corner has one.
    bool normals = nn > 0, uvs = nt > 0;
    std::size_t corners = 0;
    for (const auto& s : shapes) {
        for (const auto& i : s.mesh.indices) {
            normals = normals && i.normal_index >= 0;
            uvs = uvs && i.texcoord_index >= 0;
        }
        corners += s.mesh.indices.size();
    }

    TriangleMesh m;
    struct KeyHash {
        std::size_t operator()(const std::array<int, 3>& k) const {
            std::size_t h = std::size_t(k[0]) * 0x9E3779B97F4A7C15ull;
            h ^= std::size_t(k[1]) + 0x7f4a7c159e3779b9ull + (h << 6) + (h >> 2);
            h ^= std::size_t(k[2]) + 0x94d049bb133111ebull + (h << 6) + (h >> 2);
            return h;
        }
    };
    std::unordered_map<std::array<int, 3>, std::uint32_t, KeyHash> vertexOf;
    vertexOf.reserve(corners);
    std::vector<std::uint32_t> poly;
    std::size_t face = 0;
    for (const auto& s : shapes) {
        std::size_t next = 0;
        for (unsigned char count : s.mesh.num_face_vertices) {
            ++face;
            if (next + count > s.mesh.indices.size())
                fail("{}: face {} has more than 255 vertices (unsupported)", file, face);
            poly.clear();
            for (std::size_t k = 0; k < count; ++k) {
                const tinyobj::index_t& i = s.mesh.indices[next + k];
                // (tinyobjloader has already resolved relative indices, so a negative one
                // pointed before the first vertex.)
                if (i.vertex_index < 0)
                    fail("{}: face {} uses a relative vertex index before the first vertex", file, face);
                if (std::size_t(i.vertex_index) >= nv)
                    fail("{}: face {} uses vertex index {}, out of range (file has {} vertices)", file, face,
                         i.vertex_index + 1, nv);
                if (normals && std::size_t(i.normal_index) >= nn)
                    fail("{}: face {} uses normal index {}, out of range (file has {} normals)", file, face,
                         i.normal_index + 1, nn);
                if (uvs && std::size_t(i.texcoord_index) >= nt)
                    fail("{}: face {} uses texture coordinate index {}, out of range (file has {})", file, face,
                         i.texcoord_index + 1, nt);
                std::array<int, 3> key{i.vertex_index, uvs ? i.texcoord_index : -1, normals ? i.normal_index : -1};
                auto [it, inserted] = vertexOf.try_emplace(key, std::uint32_t(m.positions.size()));
                if (inserted) {
                    const float* p = &attrib.vertices[3 * std::size_t(key[0])];
                    m.positions.emplace_back(p[0], p[1], p[2]);
                    if (uvs) {
                        const float* t = &attrib.texcoords[2 * std::size_t(key[1])];
                        m.uvs.emplace_back(t[0], flipTexCoords ? 1.f - t[1] : t[1]);
                    }
                    if (normals) {
                        const float* n = &attrib.normals[3 * std::size_t(key[2])];
                        m.normals.emplace_back(n[0], n[1], n[2]);
                    }
                }
                poly.push_back(it->second);
            }
            next += count;
            for (std::size_t k = 1; k + 1 < poly.size(); ++k) {  // fan (convex polygons)
                m.indices.push_back(poly[0]);
                m.indices.push_back(poly[k]);
                m.indices.push_back(poly[k + 1]);
            }
        }
        if (next != s.mesh.indices.size()) fail("{}: a face has more than 255 vertices (unsupported)", file);
    }
    if (m.indices.empty()) fail("{}: OBJ file has no faces", file);
    return m;
}

class Obj final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "obj", "Triangle mesh from a Wavefront OBJ file (polygons triangulated).");
        s.cite("Wavefront Technologies, Object Files (.obj); Mitsuba 3 documentation, obj shape");
        s.optional("filename", ParamType::String, "OBJ file, relative to the scene file").isRequired();
        s.boolean("flip_tex_coords", true, "Flip the v texture coordinate (v -> 1 - v), as Mitsuba does");
        addMeshParams(s);
        // effigi-conform: a non-convex mesh (tests/data/shapes/make_conform_meshes.py), also
        // tiny, and with face normals turned inward.
        const std::string torus = "tests/data/shapes/torus.obj";
        s.addConformance({"torus", {{"filename", torus}}});
        s.addConformance({"torus tiny", {{"filename", torus}, {"to_world", Transform::scale(Vector3f(1e-3f))}}});
        s.addConformance({"torus face normals flipped", {{"filename", torus}, {"face_normals", true}, {"flip_normals", true}}});
        return s;
    }

    explicit Obj(const Properties& p) : MeshShape(p) {
        std::string file = p.getPath("filename").string();
        TriangleMesh mesh;
        try {
            mesh = loadObj(file, p.getBool("flip_tex_coords"));
        } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        setMesh(std::move(mesh), file);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Obj)
