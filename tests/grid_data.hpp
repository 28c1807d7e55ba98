#pragma once
// The voxel grids of test_media_grid and of the volume and medium conformance
// configurations (tests/data/volume, written by test_media_grid's hidden
// "[.generate]" case), and their values in closed form so that tests compare against
// them without reading the file back:
//  - ramp: 6×5×4 voxels, one channel, linear in the voxel index (so trilinear
//    interpolation reproduces the linear function between the outermost centres),
//    values 0.1 – 0.96 (an albedo too), the file's box (−1, −2, 0.5) – (2, 1, 1.5);
//  - rgb: 5×4×3 voxels, three channels, every third voxel black, channels up to 2.2
//    (RGB values above 1 take the unbounded upsampling);
//  - ramp.vdb (when OpenVDB is there): a "density" float grid, voxel size 0.25, active
//    voxels over the index box (−2, 1, 0) – (3, 4, 2) linear in the index, one voxel
//    inside switched off (it reads the background, 0), and a "velocity" vector grid.
#include "effigi/render/vol_reader.hpp"

#include <filesystem>

#if __has_include("test_openvdb.hpp")  // where CMake built OpenVDB support (tests/CMakeLists.txt)
#include "test_openvdb.hpp"
#include <openvdb/openvdb.h>
#endif

namespace effigi::test {

inline float rampValue(int i, int j, int k) { return 0.1f + 0.12f * float(i) + 0.05f * float(j) + 0.02f * float(k); }

inline VolGrid rampGrid() {
    VolGrid g;
    g.size[0] = 6, g.size[1] = 5, g.size[2] = 4;
    g.channels = 1;
    g.bbox = BBox3f(Point3f(-1.f, -2.f, 0.5f), Point3f(2.f, 1.f, 1.5f));
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 6; ++i) g.data.push_back(rampValue(i, j, k));
    return g;
}

inline Vector3f rgbValue(int i, int j, int k) {
    if ((i + j + k) % 3 == 0) return Vector3f(0.f);
    return Vector3f(0.2f + 0.5f * float(i), 0.1f * float(j), std::max(0.f, 1.5f - 0.4f * float(k)));
}

inline VolGrid rgbGrid() {
    VolGrid g;
    g.size[0] = 5, g.size[1] = 4, g.size[2] = 3;
    g.channels = 3;
    g.bbox = BBox3f(Point3f(0.f), Point3f(1.f));
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 5; ++i) {
                const Vector3f c = rgbValue(i, j, k);
                g.data.insert(g.data.end(), {c.x, c.y, c.z});
            }
    return g;
}

/// ramp.vdb's value at VDB index (x, y, z) (the switched-off voxel aside).
inline float vdbValue(int x, int y, int z) { return 0.2f + 0.1f * float(x + 2) + 0.05f * float(y) + 0.03f * float(z); }
inline constexpr int VdbHole[3] = {0, 2, 1};

#ifdef EFFIGI_TEST_OPENVDB
inline void writeRampVdb(const std::filesystem::path& file) {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr density = openvdb::FloatGrid::create(0.f);
    density->setName("density");
    density->setTransform(openvdb::math::Transform::createLinearTransform(0.25));
    openvdb::FloatGrid::Accessor acc = density->getAccessor();
    for (int z = 0; z <= 2; ++z)
        for (int y = 1; y <= 4; ++y)
            for (int x = -2; x <= 3; ++x) acc.setValue(openvdb::Coord(x, y, z), vdbValue(x, y, z));
    acc.setValueOff(openvdb::Coord(VdbHole[0], VdbHole[1], VdbHole[2]), 0.f);
    openvdb::Vec3SGrid::Ptr velocity = openvdb::Vec3SGrid::create();
    velocity->setName("velocity");
    velocity->getAccessor().setValue(openvdb::Coord(0, 0, 0), openvdb::Vec3s(1.f, 0.f, 0.f));
    openvdb::io::File(file.string()).write({density, velocity});
}
#endif

} // namespace effigi::test
