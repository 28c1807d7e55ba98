#pragma once
// A reader for Stanford PLY triangle meshes (Turk 1994, "The PLY Polygon File Format"):
// ascii, binary_little_endian and binary_big_endian; vertex positions, optional normals
// and texture coordinates; polygons fan-triangulated; everything else skipped.
#include "effigi/render/mesh.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace effigi {

/// Read a PLY file. Throws effigi::Error naming the file (and the line, for the header
/// and ascii data) on anything malformed: bad magic or header, unsupported format,
/// truncated data, non-numeric tokens, vertex indices out of range. With polygonSizes,
/// the vertex count of each face kept is appended there, in order (a face of n vertices
/// is the fan of n - 2 triangles, so the polygons can be rebuilt: subdiv's cages).
TriangleMesh readPly(const std::filesystem::path& path);
TriangleMesh readPly(const std::filesystem::path& path, std::vector<std::uint32_t>* polygonSizes);

/// Same, from bytes in memory; `name` is what error messages call the source.
TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name);
TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name, std::vector<std::uint32_t>* polygonSizes);

} // namespace effigi
