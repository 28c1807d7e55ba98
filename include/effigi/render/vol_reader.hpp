#pragma once
// Mitsuba's binary grid-volume format (.vol, version 3), used by the sdfgrid shape and by
// grid-based volume data. Layout, all little endian:
//   bytes 0-2   "VOL"            magic
//   byte  3     3                version
//   int32       1                encoding (1 = float32, the only one Mitsuba reads)
//   int32 ×3    xres yres zres   grid size
//   int32       channels
//   float32 ×6  xmin ymin zmin xmax ymax zmax   bounding box (informative)
//   float32 ×(xres·yres·zres·channels)  values, x fastest, then y, then z; the channels
//                                        of one grid point are adjacent.
// Reference: Mitsuba 3, src/render/volumegrid.cpp (format read by VolumeGrid::read).
#include "effigi/math/bbox.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace effigi {

struct VolGrid {
    std::uint32_t size[3] = {0, 0, 0};  ///< x, y, z resolution
    std::uint32_t channels = 0;
    BBox3f bbox;                        ///< as stored in the file
    std::vector<float> data;            ///< size[0]·size[1]·size[2]·channels values

    std::size_t index(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t c = 0) const {
        return ((std::size_t(z) * size[1] + y) * size[0] + x) * channels + c;
    }
    float at(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t c = 0) const {
        return data[index(x, y, z, c)];
    }
};

/// Read a .vol file. Throws effigi::Error with one line naming the file and the cause on
/// a missing file, wrong magic, version or encoding, non-positive sizes, truncated data
/// or a non-finite value. Bytes after the data are ignored, as Mitsuba does.
VolGrid readVol(const std::filesystem::path& path);

/// Same, from bytes in memory; `name` is what error messages call the source.
VolGrid readVolFromMemory(std::string_view bytes, const std::string& name);

/// The bytes of a .vol file holding `grid` (tests, tools, converters).
std::string encodeVol(const VolGrid& grid);

} // namespace effigi
