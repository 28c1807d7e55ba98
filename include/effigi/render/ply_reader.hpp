#pragma once
// A reader for Stanford PLY triangle meshes (Turk 1994, "The PLY Polygon File Format"):
// ascii, binary_little_endian and binary_big_endian; vertex positions, optional normals
// and texture coordinates; polygons fan-triangulated; everything else skipped.
#include "effigi/render/mesh.hpp"

#include <filesystem>
#include <string>
#include <string_view>

namespace effigi {

/// Read a PLY file. Throws effigi::Error naming the file (and the line, for the header
/// and ascii data) on anything malformed: bad magic or header, unsupported format,
/// truncated data, non-numeric tokens, vertex indices out of range.
TriangleMesh readPly(const std::filesystem::path& path);

/// Same, from bytes in memory; `name` is what error messages call the source.
TriangleMesh readPlyFromMemory(std::string_view data, const std::string& name);

} // namespace effigi
