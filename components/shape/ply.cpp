// ply — a triangle mesh read from a Stanford PLY file (ascii or binary, either byte
// order) by effigi's own reader.
//
// Parameters: filename (relative to the scene file), face_normals (ignore the file's
// vertex normals), flip_tex_coords (v -> 1 - v; default false, as in Mitsuba),
// flip_normals, to_world, nested bsdf and emitter.
// Vertex properties x y z, optional nx ny nz and u v (or s t, texture_u texture_v);
// faces from the list vertex_indices (or vertex_index), polygons fan-triangulated;
// other elements and properties are skipped.
// Reference: G. Turk, "The PLY Polygon File Format", 1994; Mitsuba 3 documentation, "PLY (ply)".
#include "effigi/core/registry.hpp"
#include "effigi/render/ply_reader.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Ply final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "ply", "Triangle mesh from a Stanford PLY file (ascii, binary little/big endian).");
        s.cite("G. Turk, The PLY Polygon File Format, 1994");
        s.optional("filename", ParamType::String, "PLY file, relative to the scene file").isRequired();
        s.boolean("flip_tex_coords", false, "Flip the v texture coordinate (v -> 1 - v); off by default, as in Mitsuba");
        addMeshParams(s);
        // effigi-conform: a binary non-convex mesh without normals, squashed far away, and
        // an ascii square with vertex and face colours (both from tests/data).
        const std::string torus = "tests/data/shapes/torus.ply";
        s.addConformance({"torus", {{"filename", torus}}});
        s.addConformance({"torus squashed far", {{"filename", torus}, {"to_world", Transform::translate({-500.f, 200.f, 0.f}) *
                                                                                       Transform::scale({1e2f, 1e2f, 0.1f})}}});
        s.addConformance({"coloured square", {{"filename", std::string("tests/data/textures/quad.ply")}}});
        return s;
    }

    explicit Ply(const Properties& p) : MeshShape(p) {
        std::string file = p.getPath("filename").string();
        TriangleMesh mesh;
        try {
            mesh = readPly(file);
        } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        if (p.getBool("flip_tex_coords"))
            for (Point2f& uv : mesh.uvs) uv.y = 1.f - uv.y;
        setMesh(std::move(mesh), file);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Ply)
