// volume "vdbvolume" — a float grid of an OpenVDB file (.vdb) as a dense voxel grid over
// the unit cube, with gridvolume's lookup (grid_common.hpp). `gridvolume` hands .vdb
// files to this component, so scenes written for Mitsuba's gridvolume keep working with
// a .vdb file name; it may also be named directly.
//
// The grid named `grid` (default "density", the usual name of smoke densities) is read
// and made dense over the bounding box of its active voxels: voxel (i, j, k) of the
// dense grid is the VDB voxel at index coordinate min + (i, j, k), and inactive voxels
// inside the box read the grid's background value (0 for densities). The unit cube is
// placed by `to_world` as for .vol files; `use_grid_bbox` maps onto it the world-space
// box that the VDB's own transform gives the active voxels (each voxel a unit cell about
// its integer index coordinate), which places the data where the simulation put it.
// OpenVDB is linked only into this module, loaded when a scene names a .vdb file.
//
// Parameters: filename (required), grid, and those of gridvolume (filter_type,
// wrap_mode, raw, to_world, use_grid_bbox; accel and max_value ignored).
//
// Reference: K. Museth, "VDB: High-resolution sparse volumes with dynamic topology",
// ACM Transactions on Graphics 32(3), 2013; the OpenVDB library (openvdb.org).
#include "grid_common.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"

// Modules are compiled with hidden visibility; OpenVDB's templates must keep the default,
// or this module instantiates private copies of their static data (the tree's node
// registries) that libopenvdb never initialises, and the first read crashes.
#pragma GCC visibility push(default)
#include <openvdb/openvdb.h>
#pragma GCC visibility pop

namespace effigi {
namespace {

/// Dense grids beyond this many voxels are refused: a sparse VDB can span a box far
/// larger than memory.
constexpr std::uint64_t MaxDenseVoxels = std::uint64_t(1) << 30;

class VdbVolume final : public GridVolumeBase {
public:
    static Schema schema() {
        Schema s("volume", "vdbvolume", "A float grid of an OpenVDB file, made dense over its active voxels.");
        s.cite("K. Museth, VDB: High-resolution sparse volumes with dynamic topology, ACM TOG 32(3), 2013");
        s.optional("filename", ParamType::String, "OpenVDB file, relative to the scene file").isRequired();
        s.string("grid", "density", "Name of the float grid to read");
        addGridParams(s);
        // effigi-conform: the ramp of tests/data/volume as a VDB (gen: tests/test_media_grid.cpp).
        const std::string vdb = "tests/data/volume/ramp.vdb";
        s.addConformance({"default", {{"filename", vdb}}});
        s.addConformance({"nearest grid bbox", {{"filename", vdb}, {"filter_type", std::string("nearest")},
                                                {"use_grid_bbox", true}}});
        return s;
    }

    explicit VdbVolume(const Properties& p) {
        const std::filesystem::path file = p.getPath("filename");
        const std::string name = file.string();
        regularFileSize(file, "OpenVDB file", p.whereOf("filename"));
        VolGrid g;
        try {
            g = readDense(name, p.getString("grid"));
        } catch (const Error& e) {
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        } catch (const std::exception& e) {  // OpenVDB's exceptions: multi-line text made one line
            failAt(p.whereOf("filename"), "{}: {}: not a readable OpenVDB file ({})", p.describe(), name,
                   excerpt(e.what(), 120));
        }
        setGrid(std::move(g), p, name);
    }

private:
    static VolGrid readDense(const std::string& file, const std::string& gridName) {
        openvdb::initialize();  // registers the grid types; idempotent and thread-safe
        openvdb::io::File f(file);
        f.open(false);  // no delayed loading: the file is read now, not on first access
        if (!f.hasGrid(gridName)) {
            std::string names;
            for (auto it = f.beginName(); it != f.endName(); ++it) names += (names.empty() ? "" : ", ") + it.gridName();
            fail("{}: no grid named '{}' (grids: {})", file, excerpt(gridName), excerpt(names.empty() ? "none" : names, 80));
        }
        const openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(f.readGrid(gridName));
        f.close();
        if (!grid) fail("{}: grid '{}' does not hold floats (a density grid must)", file, excerpt(gridName));
        const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
        if (box.empty()) fail("{}: grid '{}' has no active voxels", file, excerpt(gridName));
        const openvdb::Coord dim = box.dim();
        if (std::uint64_t(dim.x()) * std::uint64_t(dim.y()) * std::uint64_t(dim.z()) > MaxDenseVoxels)
            fail("{}: grid '{}' spans {}x{}x{} voxels, too many to make dense (at most 2^30)", file, excerpt(gridName),
                 dim.x(), dim.y(), dim.z());
        VolGrid g;
        g.size[0] = std::uint32_t(dim.x());
        g.size[1] = std::uint32_t(dim.y());
        g.size[2] = std::uint32_t(dim.z());
        g.channels = 1;
        g.data.resize(std::size_t(dim.x()) * std::size_t(dim.y()) * std::size_t(dim.z()));
        openvdb::FloatGrid::ConstAccessor acc = grid->getConstAccessor();
        const openvdb::Coord lo = box.min();
        for (int z = 0; z < dim.z(); ++z)
            for (int y = 0; y < dim.y(); ++y)
                for (int x = 0; x < dim.x(); ++x) g.data[g.index(x, y, z)] = acc.getValue(lo.offsetBy(x, y, z));
        // The world box of the voxels' cells [min − ½, max + ½] in index space.
        const openvdb::math::Transform& xf = grid->transform();
        for (int c = 0; c < 8; ++c) {
            const openvdb::Vec3d idx(c & 1 ? box.max().x() + 0.5 : box.min().x() - 0.5,
                                     c & 2 ? box.max().y() + 0.5 : box.min().y() - 0.5,
                                     c & 4 ? box.max().z() + 0.5 : box.min().z() - 0.5);
            const openvdb::Vec3d w = xf.indexToWorld(idx);
            g.bbox.expand(Point3f(float(w.x()), float(w.y()), float(w.z())));
        }
        return g;
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::VdbVolume)
