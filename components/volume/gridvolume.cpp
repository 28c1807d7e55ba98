// volume "gridvolume" — values on a regular voxel grid filling the unit cube, read from a
// file: Mitsuba 3's `gridvolume` (its binary .vol format, 1 or 3 channels) and, when the
// file name ends in .vdb, a float grid of an OpenVDB file.
//
// The lookup (voxel centres, trilinear or nearest filtering, wrap modes, RGB upsampling,
// to_world and use_grid_bbox) is described in grid_common.hpp. A .vdb file is handed to
// the `vdbvolume` component (vdbvolume.cpp), made through the registry: OpenVDB and its
// libraries are loaded only by a scene that names such a file, and a build without
// OpenVDB refuses .vdb files with one line.
//
// Parameters:
//   filename       string (required)  .vol file (or .vdb), relative to the scene file
//   grid           string "density"   .vdb only: the name of the float grid to read
//   filter_type    string trilinear   trilinear | nearest
//   wrap_mode      string clamp       clamp | repeat | mirror (outside the unit cube)
//   raw            bool   false       3 channels as data, not colour (eval: luminance)
//   to_world       transform          places the unit cube in the world
//   use_grid_bbox  bool   false       map the file's bounding box onto the unit cube first
//   accel, max_value                  accepted as in Mitsuba, ignored
// Mitsuba's `grid` object (a VolumeGrid from Python) does not exist in XML; its 6-channel
// grids (no plugin reads them as a spectrum) are refused.
//
// Reference: Mitsuba 3 documentation, "Grid-based volume data source (gridvolume)".
#include "grid_common.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"

namespace effigi {
namespace {

class GridVolume final : public GridVolumeBase {
public:
    static Schema schema() {
        Schema s("volume", "gridvolume", "Voxel grid over the unit cube from a Mitsuba .vol (or OpenVDB .vdb) file.");
        s.cite("Mitsuba 3 gridvolume; W. Jakob & J. Hanika, Computer Graphics Forum 38(2), 2019 (RGB upsampling)");
        s.optional("filename", ParamType::String, "Grid file (.vol, or .vdb through vdbvolume), relative to the scene")
            .isRequired();
        s.string("grid", "density", "For .vdb files: the name of the float grid to read");
        addGridParams(s);
        // effigi-conform: the grids of tests/data/volume (gen: tests/test_media_grid.cpp),
        // every filter and wrap mode, RGB upsampled and raw, stretched, turned and placed
        // by the file's own box.
        const std::string ramp = "tests/data/volume/ramp.vol", rgb = "tests/data/volume/rgb.vol";
        const Transform turned = Transform::translate({0.2f, -0.3f, 0.1f}) * Transform::rotate({1.f, 2.f, 0.5f}, 35.f) *
                                 Transform::scale({2.f, 0.5f, 1.f});
        s.addConformance({"default", {{"filename", ramp}}});
        s.addConformance({"nearest repeat", {{"filename", ramp}, {"filter_type", std::string("nearest")},
                                             {"wrap_mode", std::string("repeat")}}});
        s.addConformance({"mirror turned", {{"filename", ramp}, {"wrap_mode", std::string("mirror")}, {"to_world", turned}}});
        s.addConformance({"grid bbox", {{"filename", ramp}, {"use_grid_bbox", true}}});
        s.addConformance({"rgb", {{"filename", rgb}}});
        s.addConformance({"rgb nearest raw", {{"filename", rgb}, {"filter_type", std::string("nearest")}, {"raw", true}}});
        return s;
    }

    explicit GridVolume(const Properties& p) {
        const std::filesystem::path file = p.getPath("filename");
        if (file.extension() == ".vdb") {
            m_vdb = openVdb(p);
            return;
        }
        VolGrid g;
        try {
            g = readVol(file);
        } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        setGrid(std::move(g), p, file.string());
    }

    // A .vdb file: every question goes to the vdbvolume made for it.
    SampledSpectrum eval(const Point3f& p, const SampledWavelengths& l) const override {
        return m_vdb ? m_vdb->eval(p, l) : GridVolumeBase::eval(p, l);
    }
    float evalFloat(const Point3f& p) const override { return m_vdb ? m_vdb->evalFloat(p) : GridVolumeBase::evalFloat(p); }
    float maxValue() const override { return m_vdb ? m_vdb->maxValue() : GridVolumeBase::maxValue(); }
    float maxIn(const BBox3f& b) const override { return m_vdb ? m_vdb->maxIn(b) : GridVolumeBase::maxIn(b); }
    BBox3f bbox() const override { return m_vdb ? m_vdb->bbox() : GridVolumeBase::bbox(); }
    Transform toWorld() const override { return m_vdb ? m_vdb->toWorld() : GridVolumeBase::toWorld(); }
    glm::ivec3 resolution() const override { return m_vdb ? m_vdb->resolution() : GridVolumeBase::resolution(); }

private:
    static Ref<IVolume> openVdb(const Properties& p) {
        Registry& reg = Registry::instance();
        if (!reg.knows("volume", "vdbvolume"))
            failAt(p.whereOf("filename"), "{}: {} is an OpenVDB file, and this build of effigi has no OpenVDB support "
                   "(install libopenvdb-dev and rebuild, or convert the grid to .vol)", p.describe(),
                   excerpt(p.getPath("filename").string(), 120));
        Properties q("volume", "vdbvolume", p.where());
        for (const Properties::Entry& e : p.entries())
            if (!e.fromDefault) q.set(e.name, e.value, e.where);
        return query<IVolume>(reg.create("volume", "vdbvolume", q));
    }

    Ref<IVolume> m_vdb;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::GridVolume)
