#pragma once
// Indexed triangle meshes: the geometry that obj, ply, rectangle, cube (and later
// subdiv) hand to accelerators, with area sampling and hit reconstruction.
#include "effigi/math/bbox.hpp"
#include "effigi/math/transform.hpp"
#include "effigi/render/interaction.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace effigi {

/// A named per-vertex or per-face attribute (PLY colours and extra properties), read by
/// the mesh_attribute texture as Mitsuba's "vertex_<name>" / "face_<name>".
struct MeshAttribute {
    std::string name;       ///< with its prefix: "vertex_color", "face_color", ...
    int channels = 1;       ///< 1 or 3
    bool perFace = false;
    std::vector<float> data;  ///< channels floats per vertex (or per triangle)
};

struct TriangleMesh {
    std::vector<Point3f> positions;
    std::vector<Normal3f> normals;  // per vertex, optional
    std::vector<Point2f> uvs;       // per vertex, optional
    std::vector<std::uint32_t> indices;  // 3 per triangle
    std::vector<MeshAttribute> attributes;

    /// The attribute called name, or null.
    const MeshAttribute* attribute(const std::string& name) const {
        for (const MeshAttribute& a : attributes)
            if (a.name == name) return &a;
        return nullptr;
    }

    std::size_t triangleCount() const { return indices.size() / 3; }
    std::size_t vertexCount() const { return positions.size(); }

    /// Apply to_world to positions and normals (normals renormalised). Normals use the
    /// cofactor matrix (the inverse transpose up to det), so a transform that flattens
    /// the mesh (scale 0 along an axis) still gives the right normals.
    void transform(const Transform& t);
    /// Reverse every triangle's winding (and vertex normals).
    void flip();
    /// Throws effigi::Error (prefixed by `what`) on out-of-range indices, NaN/Inf
    /// coordinates or attribute arrays of the wrong length.
    void validate(const std::string& what) const;
    BBox3f bbox() const;

    /// Corner positions of triangle i.
    void triangle(std::size_t i, Point3f& p0, Point3f& p1, Point3f& p2) const {
        p0 = positions[indices[3 * i]];
        p1 = positions[indices[3 * i + 1]];
        p2 = positions[indices[3 * i + 2]];
    }
    /// Area of triangle i.
    float triangleArea(std::size_t i) const;
};

} // namespace effigi
